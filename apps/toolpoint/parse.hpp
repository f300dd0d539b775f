// toolpoint CLI: text parsers for option values (the library takes numbers and value types, never
// option text). Errors name the option as the user typed it.
// Units: frequencies in Hz.
#pragma once

#include <string>
#include <utility>

#include "toolpoint/conventions.hpp"

namespace toolpoint::cli {

// Parses "START:STOP:STEP" (Hz) into a checked FrequencyGrid. Throws InvalidArgument naming
// `option` on malformed text or an invalid grid (FrequencyGrid::check's message after it).
FrequencyGrid parse_frequency_grid(const std::string& text, const std::string& option);

// Parses "A:B" into two numbers. Throws InvalidArgument naming `option`.
std::pair<double, double> parse_range(const std::string& text, const std::string& option);

// Parses "I/N" (shard I of N, 0 ≤ I < N ≤ 100000) into (I, N). Throws InvalidArgument naming `option`.
std::pair<int, int> parse_shard(const std::string& text, const std::string& option);

}  // namespace toolpoint::cli
