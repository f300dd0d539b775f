// toolpoint: Universal File Format (UFF) dataset 58, "function at nodal DOF", in its ASCII (58)
// and binary (58b) forms: reading, selecting and writing. This is how measurement software
// exports tap-test FRFs and time records.
//
// File layout (SDRC/I-DEAS universal file specification, dataset 58; docs/reference.md §8):
//       -1                      a dataset starts only on the line after a `    -1` delimiter line
//       58     (or 58b + binary fields: byte order 1 little / 2 big endian, float format 2 IEEE 754,
//               ASCII header line count 11, byte count of the binary data)
//   records 1–5   ID lines (80 characters)
//   record 6      function type, response/reference entity, node and direction
//   record 7      ordinate data type (2 real single, 4 real double, 5 complex single, 6 complex
//                 double), point count, spacing (1 even, 0 uneven), abscissa minimum, increment, z
//   records 8–11  data characteristics of abscissa, ordinate numerator, ordinate denominator and
//                 z axis: specific data type (8 displacement, 11 velocity, 12 acceleration,
//                 13 excitation force, 17 time, 18 frequency, …), units exponents, labels
//   record 12     the data: ASCII 6E13.5 (single) or 4E20.12 (double), even spacing ordinates
//                 only, uneven spacing x,y pairs (x,re,im triples for complex; 2(E13.5,E20.12) and
//                 E13.5,2E20.12 for double); 58b: the same sequence as raw IEEE 754 values
//       -1
// Units: the values are taken as written. A dataset 164 (units) before a dataset 58 is recorded
// with it (factors that convert SI to file units: SI value = file value / factor); frf_file.hpp
// applies it when turning a dataset into a receptance in m/N. The abscissa of an FRF is in Hz.
//
// Reading is liberal and never trusts a count it cannot check: files in the wild carry wrong
// byte counts, headers that declare more points than the file holds, line breaks after binary
// data, CRLF line ends, Latin-1 labels and numbers run together in full fixed-width fields. What
// can be read safely is read and every departure from the specification is reported in the
// warnings (with line or byte offset, record and field); a dataset 58 that cannot be read at all
// is skipped and reported, and other dataset types are skipped. Only IoError (the file) leaves
// read_uff; parse_uff does not throw on any content. Writing is strict.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

// Records 8–11: data characteristics of one axis.
struct UffAxis {
  int data_type = 0;  // specific data type (see uff_data_type_name)
  int length_exponent = 0, force_exponent = 0, temperature_exponent = 0;
  std::string label = "NONE";  // axis label, at most 20 characters when written
  std::string units = "NONE";  // axis units label, at most 20 characters when written
};

// Dataset 164: the units of the datasets that follow it. SI value = file value / factor.
struct UffUnits {
  int code = 1;  // 1 SI, 2 BG, 3 MG, 4 BA, 5 mm/mN, 6 cm/cN, 7 in/lbf, 8 mm/kgf, 9 user, 10 mm/N
  std::string description;
  double length_factor = 1.0, force_factor = 1.0, temperature_factor = 1.0;
  std::size_t line = 0;  // where the dataset 164 starts in its file
};

// One dataset 58 (function at nodal DOF). The same struct is read and written.
struct UffDataset58 {
  std::array<std::string, 5> id{"NONE", "NONE", "NONE", "NONE", "NONE"};  // records 1–5
  // Record 6.
  int function_type = 4;  // 1 time response, 4 FRF, … (see uff_function_type_name)
  int function_id = 0, version = 0, load_case = 0;
  std::string response_entity = "NONE";
  int response_node = 0, response_direction = 0;  // direction: 0 scalar, ±1..±3 ±X..±Z, ±4..±6 rotations
  std::string reference_entity = "NONE";
  int reference_node = 0, reference_direction = 0;
  // Record 7. The writer takes the point count from `y` and, with even spacing, the abscissa from
  // abscissa_min and abscissa_increment (x must agree with them).
  int ordinate_data_type = 6;     // 2 real single, 4 real double, 5 complex single, 6 complex double
  long long declared_points = 0;  // reading: the point count record 7 declares (may differ from y.size())
  bool even = true;               // abscissa spacing: true even (1), false uneven (0)
  double abscissa_min = 0.0, abscissa_increment = 0.0, z_value = 0.0;
  // Records 8–11.
  UffAxis abscissa, ordinate, denominator, z_axis;
  // Record 12: one abscissa and one ordinate per point (real types have zero imaginary parts).
  std::vector<double> x;
  std::vector<Complex> y;

  // Where it came from (reading only; ignored by the writer).
  std::size_t index = 0;              // position among the datasets 58 of its file, from 0 (skipped ones count)
  std::size_t line = 0;               // line of its opening `    -1`
  bool binary = false;                // read from a 58b dataset
  int byte_order = 1;                 // 58b: 1 little endian, 2 big endian
  std::optional<UffUnits> units;      // the dataset 164 in force, if any
  std::vector<std::string> warnings;  // what was wrong with it (also in UffFile::warnings)
  bool headers_only = false;          // read with UffReadOptions::headers_only: x, y empty
  // The first and last abscissa of record 12 (also when read headers only; 0 without points).
  double abscissa_first = 0.0, abscissa_last = 0.0;

  bool is_complex() const { return ordinate_data_type == 5 || ordinate_data_type == 6; }
  bool is_double() const { return ordinate_data_type == 4 || ordinate_data_type == 6; }
  std::size_t size() const { return y.size(); }

  // For writing: the types and codes are valid, x and y agree in length (and x with the even
  // spacing), real types have no imaginary parts, text is one line of UTF-8, numbers fit their
  // columns. Throws InvalidArgument. (Text longer than its field — ID lines 80, entity names 10,
  // labels 20 characters — is cut by the writer, with a warning.)
  void check() const;
};

// One dataset of any type, as listed in the file.
struct UffDatasetEntry {
  int type = 0;            // 58, 151, 164, 2411, …
  bool binary = false;     // written as e.g. `58b`
  std::size_t line = 0;    // line of its opening `    -1`
  std::size_t offset = 0;  // byte offset of its opening `    -1`
};

// A parsed universal file.
struct UffFile {
  std::string source;                      // file name, for messages
  std::vector<UffDatasetEntry> datasets;   // every dataset in file order, whatever its type
  std::vector<UffDataset58> functions;     // the readable datasets 58/58b, in file order
  std::vector<std::string> warnings;       // every problem found, with file, line/byte, record, field
  std::vector<std::string> skipped;        // the datasets 58 that could not be read, and why
  std::vector<std::string> file_warnings;  // the problems not about one dataset 58 (stray text, other datasets)

  // What a caller using `sets` should report: file_warnings, the warnings of each of `sets`, and
  // how many datasets 58 were skipped.
  std::vector<std::string> warnings_for(const std::vector<const UffDataset58*>& sets) const;
};

// How to read. headers_only: records 1–11 of every dataset 58 and where its data end, but not the
// data themselves (x and y stay empty; abscissa_first/last and the checks on binary sizes still
// hold). That is what a listing needs: the time is that of finding the line ends, and binary data
// are skipped by their size without being looked at.
struct UffReadOptions {
  bool headers_only = false;
};

// Parses the bytes of a universal file. Never throws on content: problems go to warnings, and a
// dataset 58 that cannot be read at all goes to `skipped`. `source` names the file in messages.
UffFile parse_uff(std::string_view bytes, const std::string& source, const UffReadOptions& options = {});
// Reads (maps) and parses a file. Throws IoError if it cannot be read.
UffFile read_uff(const std::string& path, const UffReadOptions& options = {});

// Which dataset 58 to use: by index (position among the file's datasets 58, from 0) and/or by
// response/reference node and direction. Every criterion given must match.
struct UffSelection {
  std::optional<std::size_t> index;
  std::optional<int> response_node, response_direction, reference_node, reference_direction;

  bool empty() const;
  std::string describe() const;  // "dataset 2, response node 1 direction +Z", for messages
};

// The one dataset 58 the selection picks. An empty selection picks the only dataset 58 of the
// file. Throws InputError if none or several match (listing the candidates), or if the file has
// no readable dataset 58 (saying why each was skipped).
const UffDataset58& select_dataset58(const UffFile& file, const UffSelection& selection);

// How to write: ASCII dataset 58 or binary 58b (little or big endian IEEE 754).
struct UffWriteOptions {
  bool binary = false;
  int byte_order = 1;  // 1 little endian, 2 big endian (binary only)
  void check() const;  // throws InvalidArgument naming `UffWriteOptions::byte_order` (uff_write_fields())
};

/// \brief UffWriteOptions' fields defined once (option_fields.hpp): check(), `toolpoint taptest
/// --binary` and the keywords of Python's write_uff derive from this table.
/// \return the table, in the order of the fields
const std::vector<OptionField<UffWriteOptions>>& uff_write_fields();

// Text (or bytes, for 58b) of a universal file holding `sets`, and what the writing lost.
// ASCII numbers are right-aligned in the specification's field widths (13 for single precision
// and uneven abscissae, 20 for double precision) with as many significant digits as fit after a
// leading blank: at least 6 (E13.5) and 13 (E20.12). Binary data are exact. Warnings say when the
// ASCII abscissa (record 7 minimum and increment, or uneven values in 13-character fields) does
// not reproduce the given x exactly, with the largest change.
struct UffText {
  std::string bytes;
  std::vector<std::string> warnings;
};
UffText format_uff(const std::vector<UffDataset58>& sets, const UffWriteOptions& options = {});
// Writes atomically (write_text_file). Returns the warnings of format_uff.
std::vector<std::string> write_uff(const std::string& path, const std::vector<UffDataset58>& sets,
                                   const UffWriteOptions& options = {});

// What a reader gets back from `v` written in a 13-column E field (record 7's abscissa minimum and
// increment, uneven ASCII abscissae): 7 significant digits for positive values, 6 for negative.
double uff_field13_roundtrip(double v);

// The record 6 direction code as text: 0 → "scalar", 3 → "+Z", −4 → "-RX"; codes outside −6..6 → "code N".
std::string uff_direction_name(int direction);

// Names for messages and listings.
std::string uff_function_type_name(int function_type);       // 4 → "frequency response function"
std::string uff_data_type_name(int specific_data_type);      // 12 → "acceleration"
std::string uff_ordinate_type_name(int ordinate_data_type);  // 6 → "complex double"

}  // namespace toolpoint
