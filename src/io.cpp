// toolpoint: whole-file I/O, atomic writes, FRF CSV.
#include "toolpoint/io.hpp"

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
  if (!in) throw IoError(fmt::format("{}: cannot open for reading ({})", path, std::strerror(errno)),
                         "check the path and the file's permissions");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError(fmt::format("{}: read failed", path));
  return ss.str();
}

MappedFile::MappedFile(const std::string& path) {
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

AtomicOutput::AtomicOutput(std::string target) : target_(std::move(target)) {
  const fs::path t(target_);
  const fs::path dir = t.has_parent_path() ? t.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(fmt::format("{}: cannot create folder {} ({})", target_, dir.string(), ec.message()));
  std::string leaf(".");  // hidden, beside the target, so rename() stays on one file system
  leaf += t.filename().string();
  leaf += ".tmp.XXXXXX";
  std::string tmpl = (dir / leaf).string();
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0)
    throw IoError(fmt::format("{}: cannot create a temporary file in {} ({})", target_, dir.string(), std::strerror(errno)),
                  "check that the folder exists and is writable");
  ::close(fd);
  path_ = std::move(tmpl);
}

AtomicOutput::~AtomicOutput() {
  if (!path_.empty()) ::unlink(path_.c_str());
}

void AtomicOutput::write(const std::string& content) {
  const int fd = ::open(path_.c_str(), O_WRONLY | O_TRUNC);
  if (fd < 0) throw IoError(fmt::format("{}: cannot write its temporary file ({})", target_, std::strerror(errno)));
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw IoError(fmt::format("{}: write failed ({}); nothing was written", target_, why));
    }
    written += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) throw IoError(fmt::format("{}: write failed on close; nothing was written", target_));
}

void AtomicOutput::commit() {
  ::chmod(path_.c_str(), 0644);
  if (std::rename(path_.c_str(), target_.c_str()) != 0)
    throw IoError(fmt::format("{}: cannot replace the file ({}); nothing was written", target_, std::strerror(errno)));
  path_.clear();
}

void write_text_file(const std::string& path, const std::string& content) {
  AtomicOutput out(path);
  out.write(content);
  out.commit();
}

namespace {

const std::vector<std::string> kBlockHeader = {"frequency_hz", "H_re", "H_im", "L_re", "L_im",
                                               "N_re",         "N_im", "P_re", "P_im"};
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
                     fmt::format("give a file with columns {} (e.g. from `toolpoint rotational`)", join(kBlockHeader)));
  return std::move(t.block);
}

FrfSeries read_single_csv(const std::string& path) {
  FrfTable t = read_frf_csv(path);
  if (t.is_block)
    throw InputError(fmt::format("{}: holds a 2×2 block where a single FRF (frequency_hz,re,im) is needed", path));
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
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{}", series.frequency_hz[i], b(0, 0).real(),
                   b(0, 0).imag(), b(0, 1).real(), b(0, 1).imag(), b(1, 0).real(), b(1, 0).imag(), b(1, 1).real(),
                   b(1, 1).imag());
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
    fmt::format_to(std::back_inserter(s), "{},{},{}", series.frequency_hz[i], series.values[i].real(),
                   series.values[i].imag());
    if (!coherence.empty()) fmt::format_to(std::back_inserter(s), ",{}", coherence[i]);
    s += '\n';
  }
  return s;
}

void write_frf_csv(const std::string& path, const BlockSeries& series, const std::vector<std::string>& comments,
                   const std::vector<double>& coherence) {
  write_text_file(path, format_frf_csv(series, comments, coherence));
}

void write_frf_csv(const std::string& path, const FrfSeries& series, const std::vector<std::string>& comments,
                   const std::vector<double>& coherence) {
  write_text_file(path, format_frf_csv(series, comments, coherence));
}

std::string format_table_csv(const Table& table, const std::vector<std::string>& comments) {
  std::string s;
  for (const auto& c : comments) s += "# " + c + "\n";
  s += join(table.columns) + "\n";
  for (const auto& row : table.rows) {
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c) s += ',';
      fmt::format_to(std::back_inserter(s), "{}", row[c]);
    }
    s += '\n';
  }
  return s;
}

void write_table_csv(const std::string& path, const Table& table, const std::vector<std::string>& comments) {
  write_text_file(path, format_table_csv(table, comments));
}

}  // namespace toolpoint
