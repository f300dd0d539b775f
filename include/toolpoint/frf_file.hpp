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
//   frf    .frf              CutPro-style text: one line per frequency, "frequency<TAB>real<TAB>
//                            imaginary", frequency in Hz, receptance in m/N, no header. Read
//                            liberally (tabs, blanks, commas or semicolons between the three
//                            numbers; leading header lines; comment lines starting with # % ! ; or
//                            //; CRLF), written strictly (tabs, shortest round-trip numbers, LF).
//
// Ordinates (sign convention: e^{iωt} time dependence, x = H·f):
//   receptance   H = X/F      [m/N]
//   mobility     Y = V/F      [(m/s)/N]     V = iωX   →   H = Y/(iω)
//   accelerance  A = Ẍ/F     [(m/s²)/N]    Ẍ = −ω²X  →   H = A/(−ω²)
// with ω = 2πf [rad/s] and f in Hz. A UFF dataset states its ordinate in record 9 (numerator:
// 8 displacement, 11 velocity, 12 acceleration) over record 10 (denominator: 13 excitation force);
// an explicit ordinate overrides the codes (and is the only way for files whose codes say
// "general"). CSV and .frf files hold receptance unless an ordinate is given. Points at f = 0
// cannot be converted (ω = 0) and a receptance series needs f > 0: they are dropped with a warning.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/receptance.hpp"
#include "toolpoint/uff.hpp"

namespace toolpoint {

enum class FrfFormat { Auto, Csv, Uff, UffBinary, Frf };

// "auto", "csv", "uff", "uffb", "frf" (case-insensitive). Throws InvalidArgument naming `option`.
FrfFormat parse_frf_format(const std::string& text, const std::string& option);
std::string frf_format_name(FrfFormat format);
// By extension: .csv, .uff/.unv/.uf, .frf (case-insensitive). Throws InvalidArgument for others.
FrfFormat frf_format_of_path(const std::string& path);

enum class FrfOrdinate { Receptance, Mobility, Accelerance };

// "receptance", "mobility", "accelerance" (case-insensitive). Throws InvalidArgument naming `option`.
FrfOrdinate parse_frf_ordinate(const std::string& text, const std::string& option);
std::string frf_ordinate_name(FrfOrdinate ordinate);   // "mobility"
std::string frf_ordinate_units(FrfOrdinate ordinate);  // "(m/s)/N"

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
// warning). Applies the dataset 164 units in force (SI = file value × force factor / length
// factor). Throws InputError naming `source`, the dataset and the record when the dataset is not
// an FRF, its ordinate is unknown and no override is given, or the result is not a valid series.
struct UffReceptance {
  FrfSeries receptance;
  FrfOrdinate ordinate = FrfOrdinate::Receptance;  // what the dataset held (after any override)
  std::vector<std::string> warnings;
};
UffReceptance uff_receptance(const UffDataset58& dataset, std::optional<FrfOrdinate> ordinate,
                             const std::string& source);

// Record 6 labels of a written dataset.
struct UffDof {
  int response_node = 0, response_direction = 0, reference_node = 0, reference_direction = 0;
};

// A receptance series as a UFF dataset 58 (see the format list above). Even spacing when
// record 7's 13-column fields hold the start and step exactly and start + i·step gives every
// frequency bit for bit; otherwise uneven. `description` becomes ID line 1 (cut to 80 characters).
UffDataset58 uff_from_receptance(const FrfSeries& receptance, const UffDof& dof, const std::string& description);

// CutPro-style .frf text (see above). parse throws InputError naming `source`, the line and what
// was expected; f = 0 lines are dropped with a warning.
struct FrfText {
  FrfSeries series;
  std::vector<std::string> warnings;
};
FrfText parse_cutpro_frf(std::string_view text, const std::string& source);
std::string format_cutpro_frf(const FrfSeries& series);

// Reading any supported file.
struct FrfReadOptions {
  FrfFormat format = FrfFormat::Auto;     // Auto: by extension
  UffSelection uff;                       // which dataset 58 (UFF only; empty: the only one)
  std::optional<FrfOrdinate> ordinate;    // what the values are; default: from the UFF codes, else receptance
  void check() const;                     // throws InvalidArgument
};

struct FrfFileData {
  FrfFormat format = FrfFormat::Csv;       // the format read
  bool is_block = false;                   // a 2×2 block CSV
  FrfSeries single;                        // receptance [m/N] vs frequency [Hz] (when !is_block)
  BlockSeries block;                       // when is_block
  FrfOrdinate ordinate = FrfOrdinate::Receptance;  // what the file held, before conversion
  std::string description;                 // where the data came from (UFF: dataset, DOFs, ID line 1)
  UffDof dof;                              // UFF: record 6 labels of the dataset read
  std::vector<std::string> warnings;       // everything questionable about the file and the conversion
};

// Reads `path` (validated: f > 0 strictly increasing, finite values). Throws InputError (content,
// naming file, line or dataset), InvalidArgument (unknown extension, options), IoError.
FrfFileData read_frf_file(const std::string& path, const FrfReadOptions& options = {});

// Writing.
struct FrfWriteOptions {
  FrfFormat format = FrfFormat::Auto;   // Auto: by extension (.uff/.unv/.uf → ASCII UFF)
  UffDof dof;                           // UFF record 6 labels
  std::string description;              // UFF ID line 1; CSV comment line
  std::vector<std::string> comments;    // CSV comment lines
};

// Writes a receptance series (validated first). Returns what the format lost (ASCII UFF rounds
// uneven frequencies to 7 significant digits). Throws InputError for an invalid series,
// InvalidArgument for an unknown extension, IoError.
std::vector<std::string> write_frf_file(const std::string& path, const FrfSeries& receptance,
                                        const FrfWriteOptions& options = {});
// A 2×2 block series: FRF CSV only (InvalidArgument for other formats).
std::vector<std::string> write_frf_file(const std::string& path, const BlockSeries& receptance,
                                        const FrfWriteOptions& options = {});

}  // namespace toolpoint
