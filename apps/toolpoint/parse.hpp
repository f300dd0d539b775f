// toolpoint CLI: text parsers for option values (the library takes numbers and value types, never
// option text). Errors name the option as the user typed it.
// Units: frequencies in Hz.
#pragma once

#include <string>
#include <string_view>
#include <utility>

#include "toolpoint/conventions.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/measured/resample.hpp"

namespace toolpoint::cli {

// Option text as the parsers compare it: surrounding blanks (space, tab, CR, FF, VT) removed and
// ASCII letters in lower case (other bytes unchanged: values may hold UTF-8). The CLI's own, so it
// needs none of the library's private headers.
std::string option_word(std::string_view text);

// Parses "START:STOP:STEP" (Hz) into a checked FrequencyGrid. Throws InvalidArgument naming
// `option` on malformed text or an invalid grid (FrequencyGrid::check's message after it).
FrequencyGrid parse_frequency_grid(const std::string& text, const std::string& option);

// Parses one number. Throws InvalidArgument naming `option`.
double parse_value(const std::string& text, const std::string& option);

// Parses "A:B" into two numbers. Throws InvalidArgument naming `option`.
std::pair<double, double> parse_range(const std::string& text, const std::string& option);

// Parses a fraction written as a percentage ("2%", "2 %") or as a number ("0.02"). Throws
// InvalidArgument naming `option` on malformed text or a negative or non-finite value.
double parse_fraction(const std::string& text, const std::string& option);

// Parses "I/N" (shard I of N, 0 ≤ I < N ≤ 100000) into (I, N). Throws InvalidArgument naming `option`.
std::pair<int, int> parse_shard(const std::string& text, const std::string& option);

// "auto", "csv", "uff" (also "unv", "uf"), "uffb" (also "uff-binary", "58b"), "frf" (also
// "cutpro"); case-insensitive. Throws InvalidArgument naming `option`.
FrfFormat parse_frf_format(const std::string& text, const std::string& option);

// FRF units as parse_frf_units reads them ("m/N", "g/N", "in/lbf", …). Throws InvalidArgument
// naming `option` and listing the accepted forms.
FrfUnits parse_frf_units_option(const std::string& text, const std::string& option);

// "receptance" (also "compliance"), "mobility", "accelerance" (also "inertance");
// case-insensitive. Throws InvalidArgument naming `option`.
FrfOrdinate parse_frf_ordinate(const std::string& text, const std::string& option);

// "re-im" (also "reim"), "mag-phase-deg", "mag-phase-rad", "db-phase" (also "db-phase-deg"),
// "db-phase-rad"; case-insensitive. Throws InvalidArgument naming `option`.
FrfValueFormat parse_frf_value_format(const std::string& text, const std::string& option);

// "linear" or "cubic" (also "spline"); case-insensitive. Throws InvalidArgument naming `option`.
Interpolation parse_interpolation(const std::string& text, const std::string& option);

// "+X", "x", "Y-", "-Z", "+RX", "-ry", "scalar" or an integer −6..6 → the UFF record 6 direction
// code (uff_direction_name is the inverse). Throws InvalidArgument naming `option`.
int parse_uff_direction(const std::string& text, const std::string& option);

}  // namespace toolpoint::cli
