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

using text::trim;

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t pos = line.find(',', start);
    out.push_back(trim(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

const std::vector<std::string> kBlockHeader = {"frequency_hz", "H_re", "H_im", "L_re", "L_im",
                                               "N_re",         "N_im", "P_re", "P_im"};
const std::vector<std::string> kSingleHeader = {"frequency_hz", "re", "im"};

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
  return s;
}

bool header_matches(const std::vector<std::string_view>& cells, const std::vector<std::string>& want) {
  if (cells.size() != want.size()) return false;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cells[i].size() != want[i].size()) return false;
    for (std::size_t k = 0; k < cells[i].size(); ++k)
      if (std::tolower(static_cast<unsigned char>(cells[i][k])) != std::tolower(static_cast<unsigned char>(want[i][k])))
        return false;
  }
  return true;
}

double parse_cell(std::string_view cell, const std::string& source, std::size_t line_no, std::size_t column,
                  const std::string& column_name) {
  double v = 0.0;
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  if (first != last && *first == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (cell.empty() || ec != std::errc() || ptr != last)
    throw InputError(fmt::format("{}:{}: column {} ({}) is '{}', not a number", source, line_no, column, column_name, cell));
  if (!std::isfinite(v))
    throw InputError(fmt::format("{}:{}: column {} ({}) is {}, expected a finite number", source, line_no, column, column_name,
                                 cell),
                     "remove or repair the NaN/Inf values in the data");
  return v;
}

}  // namespace

FrfTable parse_frf_csv(const std::string& text, const std::string& source) {
  FrfTable table;
  const std::vector<std::string>* header = nullptr;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  double last_f = -1.0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line = trim(std::string_view(text).substr(pos, end - pos));
    ++line_no;
    pos = end + 1;
    if (line.empty() || line.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    const auto cells = split_commas(line);
    if (!header) {
      if (header_matches(cells, kBlockHeader)) {
        header = &kBlockHeader;
        table.is_block = true;
      } else if (header_matches(cells, kSingleHeader)) {
        header = &kSingleHeader;
      } else {
        throw InputError(fmt::format("{}:{}: header '{}' is not an FRF CSV header", source, line_no, line),
                         fmt::format("expected '{}' (2×2 block) or '{}' (single FRF)", join(kBlockHeader), join(kSingleHeader)));
      }
      if (end == text.size()) break;
      continue;
    }
    if (cells.size() != header->size())
      throw InputError(fmt::format("{}:{}: {} column(s), the header has {}", source, line_no, cells.size(), header->size()));
    double v[9];
    for (std::size_t c = 0; c < cells.size(); ++c) v[c] = parse_cell(cells[c], source, line_no, c + 1, (*header)[c]);
    if (!(v[0] > 0.0))
      throw InputError(fmt::format("{}:{}: frequency {} Hz must be > 0", source, line_no, v[0]),
                       "drop the 0 Hz line; receptances are unbounded there");
    if (!(v[0] > last_f))
      throw InputError(fmt::format("{}:{}: frequency {} Hz is not above the previous line's {} Hz", source, line_no, v[0], last_f),
                       "frequencies must increase strictly, one line per frequency");
    last_f = v[0];
    if (table.is_block) {
      table.block.frequency_hz.push_back(v[0]);
      table.block.blocks.push_back(make_block({v[1], v[2]}, {v[3], v[4]}, {v[5], v[6]}, {v[7], v[8]}));
    } else {
      table.single.frequency_hz.push_back(v[0]);
      table.single.values.emplace_back(v[1], v[2]);
    }
    if (end == text.size()) break;
  }
  if (!header)
    throw InputError(fmt::format("{}: no header line found (the file is empty or holds only comments)", source),
                     fmt::format("the first non-comment line must be '{}' or '{}'", join(kBlockHeader), join(kSingleHeader)));
  if ((table.is_block ? table.block.size() : table.single.size()) == 0)
    throw InputError(fmt::format("{}: header but no data lines", source));
  return table;
}

FrfTable read_frf_csv(const std::string& path) { return parse_frf_csv(read_text_file(path), path); }

BlockSeries read_block_csv(const std::string& path) {
  FrfTable t = read_frf_csv(path);
  if (!t.is_block)
    throw InputError(fmt::format("{}: holds a single FRF (frequency_hz,re,im) where a 2×2 block is needed", path),
                     fmt::format("give a file with columns {} (e.g. from `toolpoint rotational`)", join(kBlockHeader)));
  return std::move(t.block);
}

FrfSeries read_single_csv(const std::string& path) {
  FrfTable t = read_frf_csv(path);
  if (t.is_block)
    throw InputError(fmt::format("{}: holds a 2×2 block where a single FRF (frequency_hz,re,im) is needed", path));
  return std::move(t.single);
}

namespace {

std::string comment_lines(const std::string& units, const std::vector<std::string>& comments) {
  std::string s = "# " + units + "\n";
  for (const auto& c : comments) s += "# " + c + "\n";
  return s;
}

}  // namespace

std::string format_frf_csv(const BlockSeries& series, const std::vector<std::string>& comments) {
  std::string s = comment_lines(
      "toolpoint FRF block [[H, L], [N, P]]; units: frequency Hz, H m/N, L 1/N (m/(N m)), N rad/N, P rad/(N m)", comments);
  s += join(kBlockHeader) + "\n";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Block& b = series.blocks[i];
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{}\n", series.frequency_hz[i], b(0, 0).real(),
                   b(0, 0).imag(), b(0, 1).real(), b(0, 1).imag(), b(1, 0).real(), b(1, 0).imag(), b(1, 1).real(),
                   b(1, 1).imag());
  }
  return s;
}

std::string format_frf_csv(const FrfSeries& series, const std::vector<std::string>& comments) {
  std::string s = comment_lines("toolpoint FRF; units: frequency Hz, value in the FRF's own units (receptance m/N)", comments);
  s += join(kSingleHeader) + "\n";
  for (std::size_t i = 0; i < series.size(); ++i)
    fmt::format_to(std::back_inserter(s), "{},{},{}\n", series.frequency_hz[i], series.values[i].real(),
                   series.values[i].imag());
  return s;
}

void write_frf_csv(const std::string& path, const BlockSeries& series, const std::vector<std::string>& comments) {
  write_text_file(path, format_frf_csv(series, comments));
}

void write_frf_csv(const std::string& path, const FrfSeries& series, const std::vector<std::string>& comments) {
  write_text_file(path, format_frf_csv(series, comments));
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
