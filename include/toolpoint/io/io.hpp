// toolpoint: files. Whole-file reads, atomic writes, and the FRF CSV format every command uses.
//
// FRF CSV as toolpoint writes it (frequency in Hz; H in m/N, L in 1/N, N in rad/N, P in rad/(N·m)):
//   # comment lines start with '#'; blank lines are ignored
//   frequency_hz,H_re,H_im,L_re,L_im,N_re,N_im,P_re,P_im      <- a 2×2 receptance block
//   frequency_hz,re,im[,coherence]                             <- a single FRF
// Numbers are written in shortest round-trip form, so write-then-read gives back the same data.
//
// FRF CSV as measurement software and scripts export it, read as well (parse_frf_csv):
//   * a UTF-8 byte order mark; CRLF line ends; comment lines starting with '#' or '%';
//   * ',' ';' or tab between columns (the header line decides), quoted cells;
//   * a decimal comma (1,5e-6) when the columns are separated by ';' or tab;
//   * header synonyms with units in brackets, after '_', '/' or a blank: frequency (Freq,
//     Frequency, f; Hz, kHz, rad/s), real and imaginary part (Re, Real, Im, Imag, Imaginary),
//     magnitude (Mag, Magnitude, Abs, Amplitude, |H|; linear, or dB for 20·log10 |H| in the
//     units after "re"), phase (Phase, Angle, Arg; deg or rad), coherence (Coherence, Coh, γ²);
//   * a 0 Hz line is dropped with a warning; other columns are reported and not used.
// The values' units in the header (e.g. "Real [mm/N]") are returned as text for frf_file.hpp to
// interpret. Whatever the header cannot say (no header, a phase without its unit, unknown column
// names) is an error naming the column and the option that settles it (FrfCsvOptions) — never a
// guess.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/model/receptance.hpp"

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
  std::string copy_;  // a pipe or device read whole instead
};

// Output written whole or not at all: a hidden temporary file beside `target` (same file
// system, so the final rename is atomic). Fill it through write() or by its path (e.g. from
// another program), then commit() flushes it to the disk (fsync, every error checked), and
// renames it over the target; destroyed uncommitted, it is removed and the target is untouched.
// Missing parent folders are created. A target that exists and is not a regular file (a device
// such as /dev/full or /dev/stdout, a fifo, a folder) is refused: renaming over it would replace
// the device, so toolpoint writes regular files only. A symbolic link to a regular file is
// written through (the file it names is replaced). While an OutputSet is open on this thread,
// commit() stages the file in it instead of renaming. Throws IoError naming the target.
class AtomicOutput {
 public:
  explicit AtomicOutput(std::string target);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::string& path() const { return path_; }  // the temporary file
  const std::string& target() const { return target_; }
  void write(const std::string& content);  // replaces the temporary file's content
  void commit();                           // mode 0644, fsync, renamed over the target

 private:
  std::string target_, path_;
  std::vector<std::string> created_;  // folders made for the target, deepest first: removed (if empty) when discarded
};

// Writes `content` whole or not at all (AtomicOutput). Throws IoError naming the path.
void write_text_file(const std::string& path, const std::string& content);

// The files of one run, written all or none. While a set is open (from construction to
// destruction) on a thread, every AtomicOutput committed on that thread — write_text_file, the
// FRF, table, joint and UFF writers, plot::render — is staged in it: its temporary file is
// complete and on disk, the target untouched. commit() then renames every staged file over its
// target; if one rename fails, the targets already replaced get their old content back (or are
// removed if they did not exist) and IoError names the file at fault. A set destroyed without
// commit() removes its temporary files: nothing of the run is written. Sets nest (the innermost
// is the open one). A set may commit several times (what was staged since the last commit).
//
// The set also guards the inputs: a file read on this thread while the set is open
// (read_text_file, MappedFile) cannot be staged as an output, nor can one target be staged
// twice (InvalidArgument naming both). check_output_paths says the same before any work.
class OutputSet {
 public:
  OutputSet();
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Renames every staged file over its target, all or none. Returns the targets written.
  std::vector<std::string> commit();
  // The targets staged and not yet committed.
  std::vector<std::string> staged() const;
  // The set open on this thread (nullptr: none).
  static OutputSet* active();

  struct Staged {
    std::string target, temporary;
    std::vector<std::string> created;  // folders made for it, deepest first
  };
  struct Input {
    std::string path;
    unsigned long long device = 0, inode = 0;
  };

 private:
  friend class AtomicOutput;
  friend void note_input_read(const std::string& path);
  void stage(const std::string& target, std::string temporary, std::vector<std::string> created);
  void discard();  // removes every staged temporary file and the folders made for them
  std::vector<Staged> staged_;
  std::vector<Input> inputs_;
  std::vector<std::string> committed_;  // canonical targets already written by this set
  OutputSet* previous_ = nullptr;
};

// Records that `path` was read as an input of the open OutputSet (if any); read_text_file and
// MappedFile call it.
void note_input_read(const std::string& path);

// A file of a run and what names it in messages ("--output", "the assembly file", …).
struct RunPath {
  std::string path;
  std::string role;
};

// Before any work: throws InvalidArgument when an output is one of the inputs (the same file
// by std::filesystem::equivalent when both exist, so ./a.csv, a.csv and a hard link match; the
// same std::filesystem::weakly_canonical path otherwise) or two outputs name the same file.
// Empty paths are skipped. The message names both roles and paths. An output that exists and is
// not a regular file (a device, a fifo, a folder) is an IoError, as AtomicOutput would throw.
void check_output_paths(const std::vector<RunPath>& inputs, const std::vector<RunPath>& outputs);

// What the two value columns of a single-FRF CSV hold: real and imaginary part, magnitude and
// phase (degrees or radians), or magnitude in dB (20·log10 of |H| in the value units) and phase.
enum class FrfValueFormat { ReIm, MagPhaseDeg, MagPhaseRad, DbPhaseDeg, DbPhaseRad };

// "re-im", "mag-phase-deg", "mag-phase-rad", "db-phase" (dB and degrees), "db-phase-rad".
std::string frf_value_format_name(FrfValueFormat format);

// What the header of a CSV cannot say.
struct FrfCsvOptions {
  std::optional<FrfValueFormat> format;  // the value columns' meaning (default: from the header)
  // The frequency column, the two value columns and optionally the coherence column, each a
  // 1-based column number or a header cell's text (default: found by the header's names).
  std::vector<std::string> columns;
  void check() const;  // 3 or 4 distinct entries; throws InvalidArgument naming FrfCsvOptions::columns
};

// What an FRF CSV file holds: a block series or a single FRF.
struct FrfTable {
  bool is_block = false;
  BlockSeries block;  // when is_block: SI (a block file's units, if its header gives any, must be SI)
  FrfSeries single;   // otherwise: frequency in Hz, values as complex numbers in value_units
  // Coherence per frequency (0…1) when the file has a coherence column, else empty. Kept for
  // callers that use it as a noise estimate (with γ², Var|H|/|H|² ≈ (1 − γ²)/(2 n_avg γ²)).
  std::vector<double> coherence;
  std::string value_units;                       // the values' units as the header gives them ("mm/N"); empty: not given
  std::string value_units_column;                // the header cell that gave them, for messages
  FrfValueFormat format = FrfValueFormat::ReIm;  // how the file stored the values
  std::vector<std::string> warnings;             // dropped 0 Hz lines, unused columns, …
};

// Parses FRF CSV text; `source` (a file name) appears in every error with the line number (and
// column). Throws InputError on a header that cannot be understood, a malformed number, a wrong
// column count, NaN/Inf, a negative or non-increasing frequency, a negative linear magnitude or a
// coherence outside [0, 1]; InvalidArgument for options that do not fit the file.
FrfTable parse_frf_csv(const std::string& text, const std::string& source, const FrfCsvOptions& options = {});
FrfTable read_frf_csv(const std::string& path, const FrfCsvOptions& options = {});

// Reads a file that must hold a 2×2 block series (or a single FRF in SI units, for
// read_single_csv).
BlockSeries read_block_csv(const std::string& path);
FrfSeries read_single_csv(const std::string& path);

// Formats FRF CSV text. `comments` become '#' lines after the standard units line; a coherence
// (one value per frequency, or empty) becomes a last column `coherence`.
std::string format_frf_csv(const BlockSeries& series, const std::vector<std::string>& comments = {},
                           const std::vector<double>& coherence = {});
std::string format_frf_csv(const FrfSeries& series, const std::vector<std::string>& comments = {},
                           const std::vector<double>& coherence = {});

// A series about to be written must be finite: NumericalError naming `path`, the entry and the
// frequency otherwise (an overflow or an undefined result, not bad input data). The FRF writers
// (write_frf_csv, write_frf_file) call it, so no file holds inf or NaN values.
void require_finite_output(const BlockSeries& series, const std::string& path);
void require_finite_output(const FrfSeries& series, const std::string& path);

void write_frf_csv(const std::string& path, const BlockSeries& series, const std::vector<std::string>& comments = {},
                   const std::vector<double>& coherence = {});
void write_frf_csv(const std::string& path, const FrfSeries& series, const std::vector<std::string>& comments = {},
                   const std::vector<double>& coherence = {});

// A generic numeric table writer for other results (k(ω), lobes, …): header names carry units.
// A NaN in a column named in `may_be_empty` means "no value" (a mode not found at an overhang) and
// is written as an empty cell; any other non-finite value is an error (NumericalError naming the
// file, column and row), so no table holds inf or NaN.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<std::string> may_be_empty;
};
void require_finite_output(const Table& table, const std::string& path);
std::string format_table_csv(const Table& table, const std::vector<std::string>& comments = {});
void write_table_csv(const std::string& path, const Table& table, const std::vector<std::string>& comments = {});

}  // namespace toolpoint
