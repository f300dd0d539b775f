// toolpoint: measured FRF files. One entry point reads any supported file into a receptance
// series, one writes a series in any supported format.
//
// Formats (chosen by file extension, or named explicitly):
//   csv    .csv              FRF CSV (io.hpp): a single FRF or a 2×2 receptance block; Hz, m/N
//   uff    .uff .unv .uf     universal file dataset 58 (uff.hpp); reading also takes binary 58b;
//                            writing gives ASCII 58, complex double, function type 4 (FRF),
//                            record 8 code 18 (frequency, Hz), record 9 code 8 (displacement, m),
//                            record 10 code 13 (excitation force, N)
//   uffb   (by name only)    the same, written as binary 58b (little-endian IEEE 754 doubles)
//   frf    .frf              CutPro text: one line per frequency, "frequency<TAB>real<TAB>
//                            imaginary", frequency in Hz, receptance in m/N. CutPro's own files
//                            carry the labels "Freq Hz Real m/N Imag m/N" (or "… Imag Real", as
//                            MATLAB scripts write them), on the first line after its numbers or on
//                            a line of their own; a file without labels is read as the format
//                            defines it. Any other header (a magnitude/phase table renamed .frf)
//                            is refused, never read as real and imaginary parts. Tabs, blanks,
//                            commas or semicolons between the numbers, comment lines (# % ! ; //)
//                            and CRLF are read; written strictly (tabs, shortest round-trip
//                            numbers, LF, no labels).
//
// Ordinates (sign convention: e^{iωt} time dependence, x = H·f):
//   receptance   H = X/F      [m/N]
//   mobility     Y = V/F      [(m/s)/N]     V = iωX   →   H = Y/(iω)
//   accelerance  A = Ẍ/F     [(m/s²)/N]    Ẍ = −ω²X  →   H = A/(−ω²)
// with ω = 2πf [rad/s] and f in Hz. A UFF dataset states its ordinate in record 9 (numerator:
// 8 displacement, 11 velocity, 12 acceleration) over record 10 (denominator: 13 excitation force);
// an explicit ordinate overrides the codes (and is the only way for files whose codes say
// "general" and whose units labels say nothing). CSV and .frf files hold receptance unless their
// header's units or an option say otherwise. Points at f = 0 cannot be converted (ω = 0) and a
// receptance series needs f > 0: they are dropped with a warning.
//
// Units of the values (FrfUnits; SI value = file value × to_si): what the user gives
// (FrfReadOptions::units) wins, with a warning where the file says otherwise; else a UFF dataset
// 164 with non-SI factors; else the units the file states (a CSV header's "Real [mm/N]", a UFF
// record 9/10 units label "g" over "N"); else SI. g is the standard gravity, 9.80665 m/s²; lbf is
// 4.4482216152605 N. A UFF units label that contradicts its record's data type code (acceleration
// in "mm") is an error unless the user says which is right.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/io/io.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/io/uff.hpp"

namespace toolpoint {

enum class FrfFormat { Auto, Csv, Uff, UffBinary, Frf };

// "auto", "csv", "uff", "uffb", "frf".
std::string frf_format_name(FrfFormat format);
// By extension: .csv, .uff/.unv/.uf, .frf (case-insensitive). Throws InvalidArgument for others.
FrfFormat frf_format_of_path(const std::string& path);

enum class FrfOrdinate { Receptance, Mobility, Accelerance };

std::string frf_ordinate_name(FrfOrdinate ordinate);   // "mobility"
std::string frf_ordinate_units(FrfOrdinate ordinate);  // "(m/s)/N"

// The units of FRF values.
struct FrfUnits {
  FrfOrdinate ordinate = FrfOrdinate::Receptance;
  double to_si = 1.0;  // SI value = value in these units × to_si
  std::string label;   // as written, e.g. "g/N"

  bool operator==(const FrfUnits& o) const { return ordinate == o.ordinate && to_si == o.to_si; }
};

// "m/N", "mm/N", "µm/N" (or "um/N"), "nm/N", "in/lbf"; "m/s/N", "(m/s)/N", "mm/s/N", "in/s/lbf";
// "m/s^2/N" ("m/s²/N", "m/s2/N", "(m/s^2)/N"), "mm/s^2/N", "g/N", "g/lbf"; force in N, kN, mN or
// lbf; blanks, brackets and "·"/"*" ignored. nullopt for anything else.
std::optional<FrfUnits> parse_frf_units(std::string_view text);
// The units two UFF labels state: record 9's (the response, or the whole FRF "g/N") over record
// 10's (the force; blank or NONE read as N). nullopt when they state nothing recognisable.
std::optional<FrfUnits> uff_label_units(const std::string& numerator, const std::string& denominator);

// What records 9 and 10 of a dataset state: 8/11/12 over 13 (or over 0, "not given"). nullopt
// when the codes say anything else (general, pressure, …).
std::optional<FrfOrdinate> uff_ordinate_kind(const UffDataset58& dataset);

// Converts `series` of the given ordinate to receptance: H = Y/(iω) or H = A/(−ω²), ω = 2πf.
// Drops f = 0 points (with a warning naming `what`). Other frequencies are left as they are:
// validate() the result.
FrfSeries to_receptance(const FrfSeries& series, FrfOrdinate ordinate, std::vector<std::string>& warnings,
                        const std::string& what);

// A UFF dataset 58 as a receptance in m/N against frequency in Hz. Requires an FRF (function
// type 4, or 0 "general" with a warning) with a frequency abscissa (record 8 code 18, or 0 with a
// warning). Units as above: `units` (the user's) wins, else the dataset 164 units in force (SI =
// file value × force factor / length factor), else the units labels, else SI. Throws InputError
// naming `source`, the dataset and the record when the dataset is not an FRF, its ordinate is
// unknown and no override is given, its labels contradict its codes, or the result is not a
// valid series.
struct UffReceptance {
  FrfSeries receptance;
  FrfOrdinate ordinate = FrfOrdinate::Receptance;  // what the dataset held (after any override)
  FrfUnits units;                                  // the units its values were read in
  std::vector<std::string> warnings;
};
UffReceptance uff_receptance(const UffDataset58& dataset, std::optional<FrfOrdinate> ordinate, const std::string& source,
                             const std::optional<FrfUnits>& units = std::nullopt);

// Record 6 labels of a written dataset.
struct UffDof {
  int response_node = 0, response_direction = 0, reference_node = 0, reference_direction = 0;
};

// A receptance series as a UFF dataset 58 (see the format list above). Even spacing when
// record 7's 13-column fields hold the start and step exactly and start + i·step gives every
// frequency bit for bit; otherwise uneven. `description` becomes ID line 1 (cut to 80 characters).
UffDataset58 uff_from_receptance(const FrfSeries& receptance, const UffDof& dof, const std::string& description);

// A coherence γ² (0…1) per frequency as a UFF dataset 58 of function type 6 (coherence), real
// double, dimensionless, on the same abscissa rule. Throws InvalidArgument for values outside
// [0, 1] or sizes that differ.
UffDataset58 uff_coherence(const std::vector<double>& frequency_hz, const std::vector<double>& coherence, const UffDof& dof,
                           const std::string& description);

// The coherence of a dataset 58 of function type 6 as values in [0, 1] (real part of each ordinate).
// Throws InputError naming `source` and the dataset for another function type or values outside
// [0, 1] (a coherence in per cent, or γ rather than γ², is refused rather than guessed).
std::vector<double> uff_coherence_values(const UffDataset58& dataset, const std::string& source);

// CutPro-style .frf text (see above). parse throws InputError naming `source`, the line and what
// was expected; f = 0 lines are dropped with a warning.
struct FrfText {
  FrfSeries series;
  std::vector<std::string> warnings;
  std::string labels;  // CutPro's label line as found ("Freq Hz Real m/N Imag m/N"), or empty
};
FrfText parse_cutpro_frf(std::string_view text, const std::string& source);
std::string format_cutpro_frf(const FrfSeries& series);

// Reading any supported file. The same options for every format: one reader for every command.
struct FrfReadOptions {
  FrfFormat format = FrfFormat::Auto;   // Auto: by extension
  UffSelection uff;                     // which dataset 58 (UFF only; empty: the only one)
  std::optional<FrfOrdinate> ordinate;  // what the values are; default: the file's units or codes, else receptance
  std::optional<FrfUnits> units;        // the values' units (they imply the ordinate); default: the file's, else SI
  FrfCsvOptions csv;                    // CSV only: columns and value format where the header cannot say
  // Throws InvalidArgument: a units/ordinate contradiction (g/N as receptance), CSV options for
  // another format is checked by read_frf_file.
  void check() const;
};

struct FrfFileData {
  FrfFormat format = FrfFormat::Csv;  // the format read
  bool is_block = false;              // a 2×2 block CSV
  FrfSeries single;                   // receptance [m/N] vs frequency [Hz] (when !is_block)
  BlockSeries block;                  // when is_block
  // Coherence γ² (0…1) per frequency of `single` or `block`, when the file has a coherence column
  // (CSV), else empty. Read, kept and written (CSV) but not used by the reader: identification
  // can take it as a noise estimate, since the relative random error of |H| from n averages is
  // about sqrt((1 − γ²) / (2 n γ²)) (Bendat & Piersol).
  std::vector<double> coherence;
  FrfOrdinate ordinate = FrfOrdinate::Receptance;  // what the file held, before conversion
  FrfUnits units;                                  // the units the values were read in (converted to SI)
  std::string description;                         // where the data came from (UFF: dataset, DOFs, ID line 1)
  UffDof dof;                                      // UFF: record 6 labels of the dataset read
  std::vector<std::string> warnings;               // everything questionable about the file and the conversion
};

// Reads `path` (validated: f > 0 strictly increasing, finite values). Throws InputError (content,
// naming file, line or dataset; an end point more than 100 median steps from its neighbour — a
// stray line —, a top frequency or a largest |H| so far outside the plausible range that it cannot
// be meant), InvalidArgument (unknown extension, options), IoError.
FrfFileData read_frf_file(const std::string& path, const FrfReadOptions& options = {});

/// \brief The magnitude checks read_frf_file makes on a file, for a receptance given as data (arrays
/// from Python): the same plausible ranges (plausibility.hpp) and the same verdicts.
///
/// An end frequency more than 100 median steps from its neighbour (a stray point), a top frequency
/// that cannot be meant in Hz (rad/s given as Hz) or a largest |H| from 5 Hz up that cannot be
/// meant in m/N (µm/N given as m/N) throw InputError naming `what`; merely unusual ones (a top
/// frequency in rad/s, a peak in mm/N) are returned as warnings. For a block series |H| is its H entry.
/// \param receptance the data [m/N] against frequency [Hz] (not validated here: the caller's checks)
/// \param what the data's name in the messages (an argument's name)
/// \return the warnings, each naming `what`
std::vector<std::string> judge_receptance_data(const FrfSeries& receptance, const std::string& what);
/// \copydoc judge_receptance_data(const FrfSeries&, const std::string&)
std::vector<std::string> judge_receptance_data(const BlockSeries& receptance, const std::string& what);

// Writing.
struct FrfWriteOptions {
  FrfFormat format = FrfFormat::Auto;  // Auto: by extension (.uff/.unv/.uf → ASCII UFF)
  UffDof dof;                          // UFF record 6 labels
  std::string description;             // UFF ID line 1; CSV comment line
  std::vector<std::string> comments;   // CSV comment lines
  std::vector<double> coherence;       // per frequency, or empty: a CSV column; UFF and .frf cannot hold it
  // Throws InvalidArgument naming the field: a description or comment of more than one line (it
  // would end the CSV comment and corrupt the file), a coherence value outside [0, 1] or not finite.
  // (The coherence's length is checked against the series by write_frf_file.)
  void check() const;
};

// Writes a receptance series (validated first). Returns what the format lost (ASCII UFF rounds
// uneven frequencies to 7 significant digits; a coherence has no place in UFF or .frf). Throws
// InputError for an invalid series, InvalidArgument for an unknown extension, IoError.
std::vector<std::string> write_frf_file(const std::string& path, const FrfSeries& receptance,
                                        const FrfWriteOptions& options = {});
// A 2×2 block series: FRF CSV only (InvalidArgument for other formats).
std::vector<std::string> write_frf_file(const std::string& path, const BlockSeries& receptance,
                                        const FrfWriteOptions& options = {});

}  // namespace toolpoint
