// toolpoint: files. Whole-file reads, atomic writes, and the FRF CSV format every command uses.
//
// FRF CSV (units: frequency in Hz; H in m/N, L in 1/N, N in rad/N, P in rad/(N·m)):
//   # comment lines start with '#'; blank lines are ignored
//   frequency_hz,H_re,H_im,L_re,L_im,N_re,N_im,P_re,P_im      <- a 2×2 receptance block
//   frequency_hz,re,im                                         <- a single FRF
// The first non-comment line is the header and decides the form. Numbers are read exactly as
// written and written in shortest round-trip form, so write-then-read gives back the same data.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/receptance.hpp"

namespace toolpoint {

// Reads a whole file. Throws IoError naming the path.
std::string read_text_file(const std::string& path);

// A whole file as read-only bytes, mapped into memory (no copy: a 1 GB universal file is listed
// without reading what is not looked at; a pipe or device is read whole instead). Empty files
// give an empty view. Throws IoError naming
// the path. The bytes stay valid while the object lives.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  std::string_view bytes() const { return data_ ? std::string_view(data_, size_) : std::string_view(copy_); }

 private:
  const char* data_ = nullptr;  // the mapping, for a regular file
  std::size_t size_ = 0;
  std::string copy_;            // a pipe or device read whole instead
};

// Output written whole or not at all: a hidden temporary file beside `target` (same file
// system, so the final rename is atomic). Fill it through write() or by its path (e.g. from
// another program), then commit() renames it over the target; destroyed uncommitted, it is
// removed and the target is untouched. Missing parent folders are created. Throws IoError naming
// the target.
class AtomicOutput {
 public:
  explicit AtomicOutput(std::string target);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::string& path() const { return path_; }  // the temporary file
  void write(const std::string& content);            // replaces the temporary file's content
  void commit();                                     // mode 0644, renamed over the target

 private:
  std::string target_, path_;
};

// Writes `content` whole or not at all (AtomicOutput). Throws IoError naming the path.
void write_text_file(const std::string& path, const std::string& content);

// What an FRF CSV file holds: a block series or a single FRF.
struct FrfTable {
  bool is_block = false;
  BlockSeries block;  // when is_block
  FrfSeries single;   // otherwise
};

// Parses FRF CSV text; `source` (a file name) appears in every error with the line number.
// Throws InputError on a bad header, a malformed number, a wrong column count, NaN/Inf, a
// non-increasing or non-positive frequency.
FrfTable parse_frf_csv(const std::string& text, const std::string& source);
FrfTable read_frf_csv(const std::string& path);

// Reads a file that must hold a 2×2 block series (or a single FRF, for read_single_csv).
BlockSeries read_block_csv(const std::string& path);
FrfSeries read_single_csv(const std::string& path);

// Formats FRF CSV text. `comments` become '#' lines after the standard units line.
std::string format_frf_csv(const BlockSeries& series, const std::vector<std::string>& comments = {});
std::string format_frf_csv(const FrfSeries& series, const std::vector<std::string>& comments = {});

void write_frf_csv(const std::string& path, const BlockSeries& series, const std::vector<std::string>& comments = {});
void write_frf_csv(const std::string& path, const FrfSeries& series, const std::vector<std::string>& comments = {});

// A generic numeric table writer for other results (k(ω), lobes, …): header names carry units.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};
std::string format_table_csv(const Table& table, const std::vector<std::string>& comments = {});
void write_table_csv(const std::string& path, const Table& table, const std::vector<std::string>& comments = {});

}  // namespace toolpoint
