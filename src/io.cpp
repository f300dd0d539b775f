// toolpoint: whole-file I/O, atomic writes, FRF CSV.
#include "toolpoint/io/io.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "text.hpp"

namespace toolpoint {

namespace fs = std::filesystem;

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(fmt::format("{}: is a folder, not a file", path));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw IoError(fmt::format("{}: cannot open for reading ({})", path, std::strerror(errno)),
                  "check the path and the file's permissions");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError(fmt::format("{}: read failed", path));
  note_input_read(path);
  return ss.str();
}

MappedFile::MappedFile(const std::string& path) {
  note_input_read(path);
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(fmt::format("{}: is a folder, not a file", path));
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0)
    throw IoError(fmt::format("{}: cannot open for reading ({})", path, std::strerror(errno)),
                  "check the path and the file's permissions");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    throw IoError(fmt::format("{}: cannot read its size ({})", path, why));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    copy_ = read_text_file(path);
    return;
  }
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw IoError(fmt::format("{}: cannot map for reading ({})", path, why));
    }
    data_ = static_cast<const char*>(p);
  }
  ::close(fd);  // the mapping keeps the file
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<char*>(data_), size_);
}

namespace {

// What a non-regular file is, for messages.
const char* kind_of(const struct stat& st) {
  if (S_ISDIR(st.st_mode)) return "a folder";
  if (S_ISCHR(st.st_mode)) return "a character device";
  if (S_ISBLK(st.st_mode)) return "a block device";
  if (S_ISFIFO(st.st_mode)) return "a fifo (named pipe)";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return "not a regular file";
}

// Refuses a target that exists and is not a regular file (following symbolic links).
void check_regular_target(const std::string& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) != 0) return;  // does not exist (yet): a new file
  if (S_ISREG(st.st_mode)) return;
  throw IoError(fmt::format("{}: is {}, not a regular file; toolpoint writes regular files only (a temporary file renamed "
                            "over the target, which would replace {}); nothing was written",
                            target, kind_of(st), kind_of(st)),
                S_ISDIR(st.st_mode) ? "name a file (e.g. inside that folder)"
                                    : "name a regular file; to see the output, write it to a file and print that (cat FILE)");
}

// fsync of a file or folder by path; errors thrown as IoError naming `target`.
void sync_path(const std::string& path, const std::string& target, bool folder) {
  const int fd = ::open(path.c_str(), folder ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) {
    if (folder) return;  // a folder that cannot be opened for sync is no reason to fail the write
    throw IoError(
        fmt::format("{}: cannot reopen its temporary file to flush it ({}); nothing was written", target, std::strerror(errno)));
  }
  const int rc = ::fsync(fd);
  const int why = errno;
  const int closed = ::close(fd);
  if (!folder && (rc != 0 || closed != 0))
    throw IoError(fmt::format("{}: flushing to the disk failed ({}); nothing was written", target,
                              std::strerror(rc != 0 ? why : errno)),
                  "check the free space and the device");
}

std::string parent_of(const std::string& path) {
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

// The name a target is compared by: its weakly canonical absolute path.
std::string canonical_name(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? path : p.string();
}

thread_local OutputSet* open_set = nullptr;

}  // namespace

AtomicOutput::AtomicOutput(std::string target) : target_(std::move(target)) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(target_, ec))) {  // write through to the file the link names
    const fs::path real = fs::weakly_canonical(target_, ec);
    if (!ec) target_ = real.string();
  }
  check_regular_target(target_);
  const fs::path t(target_);
  const fs::path dir = t.has_parent_path() ? t.parent_path() : fs::path(".");
  for (fs::path d = dir; !d.empty() && !fs::exists(d, ec); d = d.parent_path()) {
    created_.push_back(d.string());
    if (d == d.parent_path()) break;
  }
  fs::create_directories(dir, ec);
  if (ec)
    throw IoError(fmt::format("{}: cannot create folder {} ({}); nothing was written", target_, dir.string(), ec.message()),
                  "check that the folder path is not a file and is writable");
  std::string leaf(".");  // hidden, beside the target, so rename() stays on one file system
  leaf += t.filename().string();
  leaf += ".tmp.XXXXXX";
  std::string tmpl = (dir / leaf).string();
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0)
    throw IoError(fmt::format("{}: cannot create a temporary file in {} ({}); nothing was written", target_, dir.string(),
                              std::strerror(errno)),
                  "check that the folder exists and is writable");
  ::close(fd);
  path_ = std::move(tmpl);
}

namespace {

void remove_empty_folders(const std::vector<std::string>& folders) {
  std::error_code ec;
  for (const std::string& d : folders)
    if (fs::is_empty(d, ec) && !ec) fs::remove(d, ec);
}

}  // namespace

AtomicOutput::~AtomicOutput() {
  if (path_.empty()) return;
  ::unlink(path_.c_str());
  remove_empty_folders(created_);
}

void AtomicOutput::write(const std::string& content) {
  const int fd = ::open(path_.c_str(), O_WRONLY | O_TRUNC);
  if (fd < 0)
    throw IoError(fmt::format("{}: cannot write its temporary file ({}); nothing was written", target_, std::strerror(errno)));
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw IoError(fmt::format("{}: write failed after {} of {} bytes ({}); nothing was written", target_, written,
                                content.size(), why),
                    "check the free space and the folder's permissions");
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    throw IoError(fmt::format("{}: flushing to the disk failed ({}); nothing was written", target_, why),
                  "check the free space and the device");
  }
  if (::close(fd) != 0)
    throw IoError(fmt::format("{}: write failed on close ({}); nothing was written", target_, std::strerror(errno)),
                  "check the free space and the device");
}

void AtomicOutput::commit() {
  ::chmod(path_.c_str(), 0644);
  sync_path(path_, target_, false);  // also what another program (gnuplot) wrote by path
  if (OutputSet* set = OutputSet::active()) {
    std::string tmp = path_;
    path_.clear();
    set->stage(target_, std::move(tmp), std::move(created_));
    return;
  }
  check_regular_target(target_);
  if (std::rename(path_.c_str(), target_.c_str()) != 0)
    throw IoError(fmt::format("{}: cannot replace the file ({}); nothing was written", target_, std::strerror(errno)));
  path_.clear();
  sync_path(parent_of(target_), target_, true);
}

void write_text_file(const std::string& path, const std::string& content) {
  AtomicOutput out(path);
  out.write(content);
  out.commit();
}

// ---- OutputSet ---------------------------------------------------------------------------------

OutputSet::OutputSet() : previous_(open_set) {
  if (previous_) {  // an inner set guards the same inputs and knows what the outer one wrote
    inputs_ = previous_->inputs_;
    committed_ = previous_->committed_;
    for (const Staged& s : previous_->staged_) committed_.push_back(canonical_name(s.target));
  }
  open_set = this;
}

OutputSet::~OutputSet() {
  discard();
  open_set = previous_;
}

void OutputSet::discard() {
  for (const Staged& s : staged_) ::unlink(s.temporary.c_str());
  for (const Staged& s : staged_) remove_empty_folders(s.created);
  staged_.clear();
}

OutputSet* OutputSet::active() { return open_set; }

std::vector<std::string> OutputSet::staged() const {
  std::vector<std::string> v;
  for (const Staged& s : staged_) v.push_back(s.target);
  return v;
}

void note_input_read(const std::string& path) {
  OutputSet* set = OutputSet::active();
  if (!set) return;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;
  set->inputs_.push_back({path, static_cast<unsigned long long>(st.st_dev), static_cast<unsigned long long>(st.st_ino)});
}

void OutputSet::stage(const std::string& target, std::string temporary, std::vector<std::string> created) {
  const auto refuse = [&](const std::string& why) {
    ::unlink(temporary.c_str());
    remove_empty_folders(created);
    throw InvalidArgument(fmt::format("the output {} {}: it would be overwritten; nothing was written", target, why),
                          "write the results to another file");
  };
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0)
    for (const Input& in : inputs_)
      if (in.device == static_cast<unsigned long long>(st.st_dev) && in.inode == static_cast<unsigned long long>(st.st_ino))
        refuse(fmt::format("is the input {} of this run", in.path));
  const std::string name = canonical_name(target);
  for (const Staged& s : staged_)
    if (canonical_name(s.target) == name) refuse(fmt::format("is written twice in this run (also as {})", s.target));
  for (const std::string& c : committed_)
    if (c == name) refuse("was already written in this run");
  staged_.push_back({target, std::move(temporary), std::move(created)});
}

std::vector<std::string> OutputSet::commit() {
  // The old content of each existing target, kept as a hard link until every rename succeeded.
  struct Step {
    const Staged* file;
    std::string backup;  // empty: the target did not exist
    bool renamed = false;
  };
  std::vector<Step> steps;
  const auto undo = [&](const std::string& what, const std::string& hint) {
    for (Step& s : steps) {
      if (s.renamed) {
        if (!s.backup.empty()) ::rename(s.backup.c_str(), s.file->target.c_str());
        else ::unlink(s.file->target.c_str());
      } else if (!s.backup.empty()) {
        ::unlink(s.backup.c_str());
      }
    }
    std::vector<std::string> targets = staged();
    discard();
    std::string list;
    for (const auto& t : targets) list += (list.empty() ? "" : ", ") + t;
    throw IoError(fmt::format("{}; none of the {} files of this run was written ({})", what, targets.size(), list), hint);
  };
  for (const Staged& f : staged_) {
    steps.push_back({&f, {}, false});
    struct stat st {};
    if (::stat(f.target.c_str(), &st) != 0) continue;
    if (!S_ISREG(st.st_mode)) undo(fmt::format("{}: is {}, not a regular file", f.target, kind_of(st)), "name a regular file");
    std::string backup =
        (fs::path(parent_of(f.target)) / fmt::format(".{}.old.XXXXXX", fs::path(f.target).filename().string())).string();
    const int fd = ::mkstemp(backup.data());
    if (fd < 0) continue;  // no backup possible: the rename is still atomic for this file
    ::close(fd);
    ::unlink(backup.c_str());
    if (::link(f.target.c_str(), backup.c_str()) == 0) steps.back().backup = backup;
  }
  for (Step& s : steps) {
    if (std::rename(s.file->temporary.c_str(), s.file->target.c_str()) != 0)
      undo(fmt::format("{}: cannot replace the file ({})", s.file->target, std::strerror(errno)),
           "check the path and the folder's permissions");
    s.renamed = true;
  }
  std::vector<std::string> written;
  for (const Step& s : steps) {
    if (!s.backup.empty()) ::unlink(s.backup.c_str());
    sync_path(parent_of(s.file->target), s.file->target, true);
    written.push_back(s.file->target);
    committed_.push_back(canonical_name(s.file->target));
  }
  staged_.clear();
  return written;
}

void check_output_paths(const std::vector<RunPath>& inputs, const std::vector<RunPath>& outputs) {
  const auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) {
      const bool eq = fs::equivalent(a, b, ec);
      if (!ec) return eq;
    }
    return canonical_name(a) == canonical_name(b);
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const RunPath& out = outputs[i];
    if (out.path.empty()) continue;
    try {
      check_regular_target(out.path);
    } catch (const IoError& e) {
      throw IoError(fmt::format("{} {}", out.role, e.what()), e.hint());
    }
    for (const RunPath& in : inputs)
      if (!in.path.empty() && same(out.path, in.path))
        throw InvalidArgument(fmt::format("{} {} is the {} {}: it would be overwritten", out.role, out.path, in.role, in.path),
                              fmt::format("write the results to another file ({})", out.role));
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() && same(out.path, outputs[j].path))
        throw InvalidArgument(fmt::format("{} {} and {} {} are the same file: one would overwrite the other", outputs[j].role,
                                          outputs[j].path, out.role, out.path),
                              "give each output its own file name");
  }
}

namespace {

const std::vector<std::string> kBlockHeader = {"frequency_hz", "H_re", "H_im", "L_re", "L_im", "N_re", "N_im", "P_re", "P_im"};
const std::vector<std::string> kSingleHeader = {"frequency_hz", "re", "im"};

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
  return s;
}

}  // namespace

FrfTable read_frf_csv(const std::string& path, const FrfCsvOptions& options) {
  return parse_frf_csv(read_text_file(path), path, options);
}

BlockSeries read_block_csv(const std::string& path) {
  FrfTable t = read_frf_csv(path);
  if (!t.is_block)
    throw InputError(fmt::format("{}: holds a single FRF where a 2×2 block is needed", path),
                     fmt::format("give a file with columns {} (e.g. the block of rotational_frfs)", join(kBlockHeader)));
  return std::move(t.block);
}

FrfSeries read_single_csv(const std::string& path) {
  FrfTable t = read_frf_csv(path);
  if (t.is_block) throw InputError(fmt::format("{}: holds a 2×2 block where a single FRF (frequency_hz,re,im) is needed", path));
  if ((!t.value_units.empty() && t.value_units != "m/N") || t.format != FrfValueFormat::ReIm)
    throw InputError(fmt::format("{}: values in '{}' ({}), where a receptance in m/N as real and imaginary part is "
                                 "needed here",
                                 path, t.value_units, frf_value_format_name(t.format)),
                     "read it with read_frf_file, which converts units and formats");
  return std::move(t.single);
}

namespace {

std::string comment_lines(const std::string& units, const std::vector<std::string>& comments) {
  std::string s = "# " + units + "\n";
  for (const auto& c : comments) s += "# " + c + "\n";
  return s;
}

// A coherence column must match the series point for point.
void check_coherence(const std::vector<double>& coherence, std::size_t points) {
  if (!coherence.empty() && coherence.size() != points)
    throw InvalidArgument(fmt::format("coherence has {} values for {} frequencies", coherence.size(), points),
                          "give one coherence value per frequency, or none");
}

}  // namespace

std::string format_frf_csv(const BlockSeries& series, const std::vector<std::string>& comments,
                           const std::vector<double>& coherence) {
  check_coherence(coherence, series.size());
  std::string s = comment_lines(
      "toolpoint FRF block [[H, L], [N, P]]; units: frequency Hz, H m/N, L 1/N (m/(N m)), N rad/N, P rad/(N m)", comments);
  s += join(kBlockHeader) + (coherence.empty() ? "\n" : ",coherence\n");
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Block& b = series.blocks[i];
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{}", series.frequency_hz[i], b(0, 0).real(), b(0, 0).imag(),
                   b(0, 1).real(), b(0, 1).imag(), b(1, 0).real(), b(1, 0).imag(), b(1, 1).real(), b(1, 1).imag());
    if (!coherence.empty()) fmt::format_to(std::back_inserter(s), ",{}", coherence[i]);
    s += '\n';
  }
  return s;
}

std::string format_frf_csv(const FrfSeries& series, const std::vector<std::string>& comments,
                           const std::vector<double>& coherence) {
  check_coherence(coherence, series.size());
  std::string s = comment_lines("toolpoint FRF; units: frequency Hz, value in the FRF's own units (receptance m/N)", comments);
  s += join(kSingleHeader) + (coherence.empty() ? "\n" : ",coherence\n");
  for (std::size_t i = 0; i < series.size(); ++i) {
    fmt::format_to(std::back_inserter(s), "{},{},{}", series.frequency_hz[i], series.values[i].real(), series.values[i].imag());
    if (!coherence.empty()) fmt::format_to(std::back_inserter(s), ",{}", coherence[i]);
    s += '\n';
  }
  return s;
}

void require_finite_output(const BlockSeries& series, const std::string& path) {
  static const char* names[4] = {"H", "L", "N", "P"};
  for (std::size_t i = 0; i < series.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      const Complex z = series.blocks[i](k / 2, k % 2);
      if (!std::isfinite(z.real()) || !std::isfinite(z.imag()))
        throw NumericalError(fmt::format("{}: {} at {} Hz is {}: a result out of the range of double precision (beyond "
                                         "±1.8e308, or undefined); nothing was written",
                                         path, names[k], series.frequency_hz[i], format_complex(z)),
                             "check the input's magnitudes and units: values near 1e308 overflow in arithmetic");
    }
}

void require_finite_output(const FrfSeries& series, const std::string& path) {
  for (std::size_t i = 0; i < series.size(); ++i)
    if (!std::isfinite(series.values[i].real()) || !std::isfinite(series.values[i].imag()))
      throw NumericalError(fmt::format("{}: the value at {} Hz is {}: a result out of the range of double precision (beyond "
                                       "±1.8e308, or undefined); nothing was written",
                                       path, series.frequency_hz[i], format_complex(series.values[i])),
                           "check the input's magnitudes and units: values near 1e308 overflow in arithmetic");
}

void write_frf_csv(const std::string& path, const BlockSeries& series, const std::vector<std::string>& comments,
                   const std::vector<double>& coherence) {
  require_finite_output(series, path);
  write_text_file(path, format_frf_csv(series, comments, coherence));
}

void write_frf_csv(const std::string& path, const FrfSeries& series, const std::vector<std::string>& comments,
                   const std::vector<double>& coherence) {
  require_finite_output(series, path);
  write_text_file(path, format_frf_csv(series, comments, coherence));
}

void require_finite_output(const Table& table, const std::string& path) {
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    for (std::size_t c = 0; c < table.rows[r].size(); ++c) {
      const double v = table.rows[r][c];
      if (std::isfinite(v)) continue;
      const std::string column = c < table.columns.size() ? table.columns[c] : fmt::format("#{}", c + 1);
      const bool optional = std::find(table.may_be_empty.begin(), table.may_be_empty.end(), column) != table.may_be_empty.end();
      if (std::isnan(v) && optional) continue;
      throw NumericalError(fmt::format("{}: the value of '{}' in data row {} is {}: a result out of the range of double "
                                       "precision or undefined; nothing was written",
                                       path, column, r + 1, v),
                           "check the inputs' magnitudes and units");
    }
}

std::string format_table_csv(const Table& table, const std::vector<std::string>& comments) {
  std::string s;
  for (const auto& c : comments) s += "# " + c + "\n";
  s += join(table.columns) + "\n";
  for (const auto& row : table.rows) {
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c) s += ',';
      if (!std::isnan(row[c])) fmt::format_to(std::back_inserter(s), "{}", row[c]);  // NaN: no value, an empty cell
    }
    s += '\n';
  }
  return s;
}

void write_table_csv(const std::string& path, const Table& table, const std::vector<std::string>& comments) {
  require_finite_output(table, path);
  write_text_file(path, format_table_csv(table, comments));
}

}  // namespace toolpoint
