// toolpoint: Universal File Format dataset 58/58b reader and writer (see uff.hpp for the layout).
#include "toolpoint/io/uff.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "text.hpp"

namespace toolpoint {

namespace {

using text::char_count;
using text::excerpt;
using text::iequal;
using text::is_blank;
using text::is_blank_char;
using text::trim;
using text::valid_utf8;

// ---------------------------------------------------------------------------------------------
// Text helpers

// Header text as UTF-8. Old software writes Latin-1 labels ("m/s²" as byte 0xB2); those bytes are
// mapped to their code points so every string the reader returns is valid UTF-8.
std::string header_text(std::string_view raw) {
  if (valid_utf8(raw)) return std::string(raw);
  std::string out;
  out.reserve(raw.size() + 8);
  for (char ch : raw) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

// The fixed-format field of `len` characters starting at character `start` (Fortran columns count
// characters, not bytes, once a label holds "²"). Empty past the end of the line.
std::string_view column_field(std::string_view s, std::size_t start, std::size_t len) {
  std::size_t i = 0, ch = 0;
  while (i < s.size() && ch < start) {
    ++i;
    while (i < s.size() && (static_cast<unsigned char>(s[i]) & 0xC0) == 0x80) ++i;
    ++ch;
  }
  const std::size_t b = i;
  const std::size_t stop = len > std::numeric_limits<std::size_t>::max() - start ? len : start + len;
  while (i < s.size() && ch < stop) {
    ++i;
    while (i < s.size() && (static_cast<unsigned char>(s[i]) & 0xC0) == 0x80) ++i;
    ++ch;
  }
  return s.substr(b, i - b);
}

std::vector<std::string_view> split_blanks(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_blank_char(s[i])) ++i;
    const std::size_t b = i;
    while (i < s.size() && !is_blank_char(s[i])) ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Numbers

// A Fortran integer field: blanks only read as 0 (Fortran's blank rule), a sign is allowed.
std::optional<long long> parse_integer(std::string_view field) {
  field = trim(field);
  if (field.empty()) return 0;
  if (field.front() == '+') field.remove_prefix(1);
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ec != std::errc() || ptr != field.data() + field.size()) return std::nullopt;
  return v;
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// For a decimal number from_chars found out of range: whether it is too small (not too large).
// The exponent of its leading digit decides: mantissa digits before the point (less leading
// zeros, or minus the zeros after the point) plus the written exponent.
bool beyond_range_is_tiny(std::string_view number) {
  long long lead = 0;  // decimal exponent of the first nonzero digit, before the written exponent
  bool seen_point = false, seen_digit = false;
  std::size_t k = number[0] == '-' ? 1 : 0;
  for (; k < number.size() && number[k] != 'e'; ++k) {
    const char c = number[k];
    if (c == '.') {
      seen_point = true;
    } else if (!seen_digit && c == '0') {
      if (seen_point) --lead;
    } else {
      if (!seen_digit) {
        seen_digit = true;
        if (seen_point) --lead;
      } else if (!seen_point) {
        ++lead;
      }
    }
  }
  long long exponent = 0;
  if (k < number.size()) {
    const bool minus = k + 1 < number.size() && number[k + 1] == '-';
    for (std::size_t j = k + 1; j < number.size(); ++j)
      if (is_digit(number[j])) exponent = std::min<long long>(exponent * 10 + (number[j] - '0'), 1'000'000'000'000LL);
    if (minus) exponent = -exponent;
  }
  return lead + exponent < 0;
}

// The slow path of scan_reals' buffer: a number longer than the small buffer goes on in `big`.
[[gnu::noinline]] void append_long(std::string& big, const char* small, std::size_t k, char ch) {
  if (big.size() != k) big.assign(small, k);
  big += ch;
}

// Scans Fortran-style reals from `text` into `out`. Numbers are separated by blanks, tabs or
// commas, or run together when a fixed-width field is full ("-1.5E-02-2.5E-02"); the exponent
// letter is E, e, D or d, or absent before a signed exponent of up to three digits ("1.5-100",
// Fortran's way of printing three-digit exponents in E format). Returns the offset of the first
// character that does not belong to a number, or npos when the whole text was read.
std::size_t scan_reals(std::string_view text, std::vector<double>& out) {
  const std::size_t n = text.size();
  std::size_t i = 0;
  // The number as from_chars reads it (D exponents and missing E letters mended), in a small
  // buffer, or in `long_number` when longer: any length is read exactly, never cut.
  char small[64];
  std::string long_number;
  while (i < n) {
    const char c = text[i];
    if (is_blank_char(c) || c == ',') {
      ++i;
      continue;
    }
    const std::size_t start = i;
    std::size_t k = 0;
    auto put = [&](char ch) __attribute__((always_inline)) {
      if (k < sizeof(small)) [[likely]]
        small[k] = ch;
      else append_long(long_number, small, k, ch);
      ++k;
    };
    bool negative = false;
    if (c == '+' || c == '-') {
      negative = c == '-';
      ++i;
    }
    if (i < n && std::isalpha(static_cast<unsigned char>(text[i]))) {  // inf, infinity, nan
      std::size_t e = i;
      while (e < n && std::isalpha(static_cast<unsigned char>(text[e]))) ++e;
      const std::string_view word = text.substr(i, e - i);
      double v = 0.0;
      if (iequal(word, "inf") || iequal(word, "infinity")) v = std::numeric_limits<double>::infinity();
      else if (iequal(word, "nan")) v = std::numeric_limits<double>::quiet_NaN();
      else return start;
      out.push_back(negative ? -v : v);
      i = e;
      if (i < n && !(is_blank_char(text[i]) || text[i] == ',' || text[i] == '+' || text[i] == '-')) return i;
      continue;
    }
    if (negative) put('-');
    std::size_t digits = 0;
    bool dot = false;
    while (i < n && (is_digit(text[i]) || (text[i] == '.' && !dot))) {
      if (text[i] == '.') dot = true;
      else ++digits;
      put(text[i++]);
    }
    if (digits == 0) return start;
    if (i < n && (text[i] == 'E' || text[i] == 'e' || text[i] == 'D' || text[i] == 'd')) {
      put('e');
      ++i;
      if (i < n && (text[i] == '+' || text[i] == '-')) put(text[i++]);
      std::size_t ed = 0;
      while (i < n && is_digit(text[i])) {
        put(text[i++]);
        ++ed;
      }
      if (ed == 0) return i;
    } else if (dot && i + 1 < n && (text[i] == '+' || text[i] == '-') && is_digit(text[i + 1])) {
      put('e');
      put(text[i++]);
      for (int d = 0; d < 3 && i < n && is_digit(text[i]); ++d) put(text[i++]);
    }
    double v = 0.0;
    const char* b = k <= sizeof(small) ? small : long_number.data();
    const char* e = b + k;
    const auto [ptr, ec] = std::from_chars(b, e, v);
    if (ec == std::errc::result_out_of_range) {
      // Beyond double range: below about 1e-308 is zero, above 1.8e308 infinite (from_chars tells
      // which by the value it would round to: decide by the decimal exponent of the mantissa).
      v = beyond_range_is_tiny(std::string_view(b, k)) ? 0.0 : std::numeric_limits<double>::infinity();
      if (negative) v = -v;
    } else if (ec != std::errc() || ptr != e) {
      return start;
    }
    out.push_back(v);
    if (i < n && !(is_blank_char(text[i]) || text[i] == ',' || text[i] == '+' || text[i] == '-')) return i;
  }
  return std::string_view::npos;
}

// ---------------------------------------------------------------------------------------------
// Lines

// `    -1` in the first six columns (the -1 right-justified in an I6 field), nothing else.
bool is_delimiter(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && line[i] == ' ') ++i;
  if (i > 4 || line.substr(i, 2) != "-1") return false;
  return is_blank(line.substr(i + 2));
}

struct Cursor {
  std::string_view data;
  std::size_t pos = 0;
  std::size_t line = 1;  // the number of the line starting at pos

  bool eof() const { return pos >= data.size(); }

  // The next line without its "\n" or "\r\n", and moves past it.
  std::string_view take() {
    std::size_t e = data.find('\n', pos);
    std::size_t next = e == std::string_view::npos ? data.size() : e + 1;
    if (e == std::string_view::npos) e = data.size();
    std::string_view s = data.substr(pos, e - pos);
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    pos = next;
    ++line;
    return s;
  }

  // Moves n bytes on (binary data), keeping the line count of an editor.
  void advance(std::size_t n) {
    n = std::min(n, data.size() - pos);
    line += static_cast<std::size_t>(
        std::count(data.begin() + static_cast<std::ptrdiff_t>(pos), data.begin() + static_cast<std::ptrdiff_t>(pos + n), '\n'));
    pos += n;
  }
};

// The dataset number line after a delimiter: "    58", "  2414", "    58b     1     2  11  4096 …".
struct TypeLine {
  int type = 0;
  bool binary = false;
  std::vector<long long> fields;  // binary: byte order, float format, ASCII lines, bytes, …
};

std::optional<TypeLine> parse_type_line(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && line[i] == ' ') ++i;
  const std::size_t b = i;
  while (i < line.size() && is_digit(line[i]) && i - b < 9) ++i;
  if (i == b) return std::nullopt;
  TypeLine t;
  std::from_chars(line.data() + b, line.data() + i, t.type);
  if (i < line.size() && (line[i] == 'b' || line[i] == 'B')) {
    t.binary = true;
    ++i;
  } else if (i < line.size() && !is_blank_char(line[i])) {
    return std::nullopt;
  }
  if (t.binary) {
    for (std::string_view tok : split_blanks(line.substr(i))) {
      const auto v = parse_integer(tok);
      if (!v) break;
      t.fields.push_back(*v);
    }
  }
  return t;
}

// Values per point of record 12: ordinate (1 real, 2 complex) plus the abscissa when uneven.
std::size_t values_per_point(bool complex, bool even) { return (complex ? 2u : 1u) + (even ? 0u : 1u); }

const char* ascii_layout(int ordinate_type, bool even) {
  const bool dbl = ordinate_type == 4 || ordinate_type == 6, cpx = ordinate_type == 5 || ordinate_type == 6;
  if (!dbl) return "6E13.5";
  if (even) return "4E20.12";
  return cpx ? "E13.5,2E20.12" : "2(E13.5,E20.12)";
}

template <typename T>
T load_value(const char* p, bool big_endian) {
  using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  U u;
  std::memcpy(&u, p, sizeof(U));
  if (big_endian != (std::endian::native == std::endian::big)) {
    U r = 0;
    for (std::size_t k = 0; k < sizeof(U); ++k) r = static_cast<U>((r << 8) | ((u >> (8 * k)) & 0xFF));
    u = r;
  }
  return std::bit_cast<T>(u);
}

// A dataset that cannot be read: the reason goes to UffFile::skipped.
struct DatasetFailure {
  std::string what;
};

// ---------------------------------------------------------------------------------------------
// The reader

class Parser {
 public:
  Parser(std::string_view bytes, const std::string& source, const UffReadOptions& options) : source_(source), options_(options) {
    cur_.data = bytes;
    file_.source = source;
  }

  UffFile run() {
    std::size_t stray_lines = 0, first_stray = 0;
    std::string first_stray_text;
    while (!cur_.eof()) {
      const std::size_t line = cur_.line, offset = cur_.pos;
      const std::string_view text = cur_.take();
      if (!is_delimiter(text)) {
        if (!is_blank(text)) {
          if (stray_lines++ == 0) {
            first_stray = line;
            first_stray_text = excerpt(trim(text));
          }
        }
        continue;
      }
      if (cur_.eof()) {
        warn(fmt::format("{}:{}: the file ends right after a '    -1' delimiter line", source_, line));
        break;
      }
      const std::size_t type_line_no = cur_.line, type_pos = cur_.pos;
      const std::string_view type_text = cur_.take();
      if (is_delimiter(type_text)) {  // an empty dataset, or a stray delimiter: the second one opens the next
        cur_.pos = type_pos;
        cur_.line = type_line_no;
        continue;
      }
      const auto type = parse_type_line(type_text);
      if (!type) {
        warn(
            fmt::format("{}:{}: '{}' after the '    -1' on line {} is not a dataset number; skipped to the next "
                        "'    -1'",
                        source_, type_line_no, excerpt(type_text), line));
        skip_to_delimiter(fmt::format("the unreadable dataset at line {}", line));
        continue;
      }
      file_.datasets.push_back({type->type, type->binary, line, offset});
      if (type->type == 58) {
        read_58(*type, line);
      } else if (type->type == 164 && !type->binary) {
        read_units(line);
      } else if (type->binary) {
        skip_binary(*type, line);
      } else {
        skip_to_delimiter(fmt::format("dataset {} at line {}", type->type, line));
      }
    }
    if (stray_lines > 0)
      warn(
          fmt::format("{}:{}: {} line(s) outside any dataset ignored (the first: '{}'); a dataset starts only on the "
                      "line after a '    -1' delimiter",
                      source_, first_stray, stray_lines, first_stray_text));
    if (file_.datasets.empty())
      warn(
          fmt::format("{}: no dataset found (no '    -1' delimiter followed by a dataset number); is this a universal "
                      "file?",
                      source_));
    return std::move(file_);
  }

 private:
  void warn(std::string message) {
    file_.file_warnings.push_back(message);
    file_.warnings.push_back(std::move(message));
  }

  // Moves past the next delimiter line (the end of the current dataset).
  void skip_to_delimiter(const std::string& what) {
    while (!cur_.eof())
      if (is_delimiter(cur_.take())) return;
    warn(fmt::format("{}: {} has no closing '    -1' (the file ends at line {}; truncated?)", source_, what, cur_.line - 1));
  }

  // After binary data: the closing delimiter should follow at once. Tolerates (and reports) a line
  // break or other bytes before it.
  void close_binary(const std::string& what, std::size_t data_end, std::vector<std::string>& sink) {
    if (cur_.eof()) {
      sink.push_back(fmt::format("{}: {} has no closing '    -1' after its binary data (the file ends at byte {}; truncated?)",
                                 source_, what, cur_.data.size()));
      return;
    }
    const std::size_t from = cur_.pos;
    // The delimiter should be right here; otherwise take the first line that is one.
    for (Cursor probe = cur_;;) {
      const std::size_t line_pos = probe.pos;
      Cursor after = probe;
      if (is_delimiter(after.take())) {
        if (line_pos > from) {
          const std::string_view gap = cur_.data.substr(from, line_pos - from);
          const bool line_break = gap.find_first_not_of(" \t\r\n") == std::string_view::npos;
          sink.push_back(
              fmt::format("{}: {}: {} byte(s) {}between the end of the binary data (byte {}) and the closing "
                          "'    -1'; the 58b format allows none; ignored",
                          source_, what, gap.size(), line_break ? "(a line break) " : "of unexpected content ", data_end));
        }
        cur_ = after;
        return;
      }
      if (after.eof()) break;
      probe = after;
    }
    sink.push_back(
        fmt::format("{}: {}: no closing '    -1' after the binary data (byte {}); the rest of the file ({} bytes) was "
                    "skipped",
                    source_, what, data_end, cur_.data.size() - from));
    cur_.advance(cur_.data.size() - from);
  }

  // Any binary dataset: its ASCII header lines, then its byte count, then the delimiter.
  void skip_binary(const TypeLine& t, std::size_t line) {
    const std::string what = fmt::format("dataset {}b at line {}", t.type, line);
    if (t.fields.size() < 4 || t.fields[2] < 0 || t.fields[3] < 0) {
      warn(fmt::format("{}:{}: {}: the header line lacks the ASCII line and byte counts; skipped to the next '    -1'", source_,
                       line + 1, what));
      skip_to_delimiter(what);
      return;
    }
    for (long long k = 0; k < t.fields[2] && !cur_.eof(); ++k) {
      if (is_delimiter(cur_.take())) {
        warn(fmt::format("{}: {} ends inside its {} ASCII header lines", source_, what, t.fields[2]));
        return;
      }
    }
    const std::size_t start = cur_.pos;
    const auto n = static_cast<unsigned long long>(t.fields[3]);
    cur_.advance(static_cast<std::size_t>(std::min<unsigned long long>(n, cur_.data.size() - start)));
    close_binary(what, cur_.pos, file_.warnings);
  }

  // Dataset 164: units code and the factors from SI to file units.
  void read_units(std::size_t line) {
    const std::string what = fmt::format("dataset 164 (units) at line {}", line);
    std::string_view rec[3];
    std::size_t got = 0;
    bool closed = false;
    while (!cur_.eof() && got < 3) {
      const std::string_view text = cur_.take();
      if (is_delimiter(text)) {
        closed = true;
        break;
      }
      rec[got++] = text;
    }
    std::vector<double> factors;
    const auto code = got >= 1 ? parse_integer(column_field(header_text(rec[0]), 0, 10)) : std::nullopt;
    const bool ok = got >= 2 && code && scan_reals(rec[1], factors) == std::string_view::npos && factors.size() >= 3 &&
                    std::all_of(factors.begin(), factors.begin() + 3, [](double f) { return std::isfinite(f) && f > 0.0; });
    if (ok) {
      UffUnits u;
      u.code = static_cast<int>(std::clamp<long long>(*code, -1000000, 1000000));
      u.description = std::string(trim(column_field(header_text(rec[0]), 10, 20)));
      u.length_factor = factors[0];
      u.force_factor = factors[1];
      u.temperature_factor = factors[2];
      u.line = line;
      units_ = u;
    } else {
      units_.reset();
      warn(
          fmt::format("{}: {} is unreadable (expected a units code in columns 1–10 and three positive factors on the "
                      "next line); the datasets after it are taken as SI",
                      source_, what));
    }
    if (!closed) skip_to_delimiter(what);
  }

  [[noreturn]] void fail(std::size_t line, const std::string& what) const {
    throw DatasetFailure{fmt::format("{}:{}: {}", source_, line, what)};
  }

  void read_58(const TypeLine& t, std::size_t start_line) {
    UffDataset58 d;
    d.index = index58_++;
    d.line = start_line;
    d.binary = t.binary;
    d.units = units_;
    const std::string what = fmt::format("dataset 58{} #{} (line {})", t.binary ? "b" : "", d.index, start_line);
    enum class Recovery { ScanToDelimiter, SkipBinary, Done } recovery = Recovery::ScanToDelimiter;
    long long n_bytes = -1;
    std::size_t data_start = 0;
    try {
      if (t.binary) {
        const std::size_t hl = start_line + 1;
        if (t.fields.size() < 4)
          fail(hl, "the 58b line holds " + std::to_string(t.fields.size()) +
                       " number(s) after '58b'; expected byte order, float format, ASCII line count and byte count "
                       "(format I6,1A1,I6,I6,I12,I12,…)");
        if (t.fields[3] < 0) fail(hl, fmt::format("58b field 6 (byte count) is {}, expected ≥ 0", t.fields[3]));
        n_bytes = t.fields[3];
        if (t.fields[0] != 1 && t.fields[0] != 2)
          fail(hl, fmt::format("58b field 3 (byte order) is {}, expected 1 (little endian) or 2 (big endian)", t.fields[0]));
        d.byte_order = static_cast<int>(t.fields[0]);
        if (t.fields[1] != 2)
          fail(hl,
               fmt::format("58b field 4 (floating-point format) is {}, expected 2 (IEEE 754); {} is not supported", t.fields[1],
                           t.fields[1] == 1   ? "DEC VMS"
                           : t.fields[1] == 3 ? "IBM 5/370"
                                              : "this code"));
        if (t.fields[2] != 11)
          d.warnings.push_back(
              fmt::format("{}:{}: 58b field 5 (ASCII line count) is {}, a dataset 58 has 11 header "
                          "lines; read 11",
                          source_, hl, t.fields[2]));
      }
      // Records 1–11.
      std::array<std::string, 11> rec;
      std::array<std::size_t, 11> rec_line{};
      for (std::size_t k = 0; k < 11; ++k) {
        if (cur_.eof()) {
          recovery = Recovery::Done;
          fail(cur_.line, fmt::format("the file ends inside the header: record {} is missing (a dataset 58 has 11 "
                                      "header lines)",
                                      k + 1));
        }
        rec_line[k] = cur_.line;
        const std::string_view text = cur_.take();
        if (is_delimiter(text)) {
          recovery = Recovery::Done;
          fail(rec_line[k], fmt::format("'    -1' where record {} was expected: the header is cut short (a dataset 58 "
                                        "has 11 header lines)",
                                        k + 1));
        }
        rec[k] = header_text(text);
      }
      data_start = cur_.pos;
      if (t.binary) recovery = Recovery::SkipBinary;
      for (std::size_t k = 0; k < 5; ++k) d.id[k] = std::string(trim(rec[k]));
      parse_record6(rec[5], rec_line[5], d);
      parse_record7(rec[6], rec_line[6], d);
      UffAxis* axes[4] = {&d.abscissa, &d.ordinate, &d.denominator, &d.z_axis};
      for (std::size_t k = 0; k < 4; ++k) parse_axis(rec[7 + k], rec_line[7 + k], 8 + static_cast<int>(k), *axes[k]);

      std::vector<double> values;
      std::optional<std::size_t> present;
      if (t.binary) {
        std::size_t points = 0;
        read_binary_data(d, what, static_cast<unsigned long long>(n_bytes), values, points);
        present = points;
      } else {
        read_ascii_data(d, what, values);
      }
      recovery = Recovery::Done;
      assemble(d, what, values, present);
    } catch (const DatasetFailure& f) {
      const std::string message = fmt::format("{} skipped: {}", what, f.what);
      file_.skipped.push_back(message);
      file_.warnings.push_back(message);
      if (recovery == Recovery::SkipBinary) {
        cur_.pos = data_start;
        cur_.advance(static_cast<std::size_t>(
            std::min<unsigned long long>(static_cast<unsigned long long>(n_bytes), cur_.data.size() - data_start)));
        close_binary(what, cur_.pos, file_.warnings);
      } else if (recovery == Recovery::ScanToDelimiter && !cur_.eof()) {
        skip_to_delimiter(what);
      }
      return;
    }
    file_.warnings.insert(file_.warnings.end(), d.warnings.begin(), d.warnings.end());
    file_.functions.push_back(std::move(d));
  }

  int to_int(long long v, std::size_t line, int record, int field, const char* name) const {
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      fail(line, fmt::format("record {} field {} ({}) is {}, outside the integer range", record, field, name, v));
    return static_cast<int>(v);
  }

  // Record 6, format 2(I5,I10),2(1X,10A1,I10,I4): fixed columns (entity names may hold blanks);
  // a line written free-format with exactly ten blank-separated fields is accepted too.
  void parse_record6(const std::string& s, std::size_t line, UffDataset58& d) const {
    static constexpr std::size_t start[] = {0, 5, 15, 20, 31, 41, 51, 56, 66, 76};
    static constexpr std::size_t width[] = {5, 10, 5, 10, 10, 10, 4, 10, 10, 4};
    static constexpr const char* names[] = {"function type",      "function ID",      "version",
                                            "load case",          "response entity",  "response node",
                                            "response direction", "reference entity", "reference node",
                                            "reference direction"};
    static constexpr bool is_text[] = {false, false, false, false, true, false, false, true, false, false};
    long long v[10] = {};
    std::string_view text[10];
    int bad = -1;
    for (int f = 0; f < 10; ++f) {
      text[f] = column_field(s, start[f], width[f]);
      if (is_text[f]) continue;
      const auto x = parse_integer(text[f]);
      if (!x) {
        if (bad < 0) bad = f;
      } else {
        v[f] = *x;
      }
    }
    if (bad >= 0) {
      const auto tok = split_blanks(s);
      bool ok = tok.size() == 10;
      for (int f = 0; ok && f < 10; ++f) {
        text[f] = tok[static_cast<std::size_t>(f)];
        if (is_text[f]) continue;
        const auto x = parse_integer(text[f]);
        ok = x.has_value();
        if (ok) v[f] = *x;
      }
      if (!ok)
        fail(line, fmt::format("record 6 field {} ({}) is '{}' in columns {}–{}, expected an integer (format "
                               "2(I5,I10),2(1X,10A1,I10,I4))",
                               bad + 1, names[bad], excerpt(trim(column_field(s, start[bad], width[bad]))), start[bad] + 1,
                               start[bad] + width[bad]));
    }
    d.function_type = to_int(v[0], line, 6, 1, names[0]);
    d.function_id = to_int(v[1], line, 6, 2, names[1]);
    d.version = to_int(v[2], line, 6, 3, names[2]);
    d.load_case = to_int(v[3], line, 6, 4, names[3]);
    d.response_entity = std::string(trim(text[4]));
    d.response_node = to_int(v[5], line, 6, 6, names[5]);
    d.response_direction = to_int(v[6], line, 6, 7, names[6]);
    d.reference_entity = std::string(trim(text[7]));
    d.reference_node = to_int(v[8], line, 6, 9, names[8]);
    d.reference_direction = to_int(v[9], line, 6, 10, names[9]);
  }

  // Record 7, format 3I10,3E13.5.
  void parse_record7(const std::string& s, std::size_t line, UffDataset58& d) const {
    std::vector<double> reals;
    long long ints[3] = {};
    bool fixed = true;
    for (std::size_t f = 0; f < 3 && fixed; ++f) {
      const auto x = parse_integer(column_field(s, 10 * f, 10));
      if (x && !trim(column_field(s, 10 * f, 10)).empty()) ints[f] = *x;
      else fixed = false;
    }
    if (fixed) fixed = scan_reals(column_field(s, 30, std::string::npos), reals) == std::string_view::npos && reals.size() >= 2;
    if (!fixed) {
      reals.clear();
      const std::size_t bad = scan_reals(s, reals);
      if (bad != std::string_view::npos)
        fail(line, fmt::format("record 7 column {}: '{}' is not a number (format 3I10,3E13.5: ordinate type, points, "
                               "spacing, abscissa minimum, increment, z value)",
                               char_count(std::string_view(s).substr(0, bad)) + 1, excerpt(std::string_view(s).substr(bad), 16)));
      if (reals.size() < 5)
        fail(line, fmt::format("record 7 holds {} number(s), expected 6 (format 3I10,3E13.5: ordinate type, points, "
                               "spacing, abscissa minimum, increment, z value)",
                               reals.size()));
      for (std::size_t f = 0; f < 3; ++f) {
        if (!(std::abs(reals[f]) < 9.2e18) || reals[f] != std::floor(reals[f]))
          fail(line, fmt::format("record 7 field {} is {}, expected an integer", f + 1, reals[f]));
        ints[f] = static_cast<long long>(reals[f]);
      }
      reals.erase(reals.begin(), reals.begin() + 3);
    }
    if (ints[0] != 2 && ints[0] != 4 && ints[0] != 5 && ints[0] != 6)
      fail(line, fmt::format("record 7 field 1 (ordinate data type) is {}, expected 2 (real single), 4 (real double), "
                             "5 (complex single) or 6 (complex double)",
                             ints[0]));
    if (ints[1] < 0) fail(line, fmt::format("record 7 field 2 (number of points) is {}, expected ≥ 0", ints[1]));
    if (ints[2] != 0 && ints[2] != 1)
      fail(line, fmt::format("record 7 field 3 (abscissa spacing) is {}, expected 0 (uneven) or 1 (even)", ints[2]));
    d.ordinate_data_type = static_cast<int>(ints[0]);
    d.declared_points = ints[1];
    d.even = ints[2] == 1;
    d.abscissa_min = reals[0];
    d.abscissa_increment = reals[1];
    d.z_value = reals.size() > 2 ? reals[2] : 0.0;
    if (d.even && !(std::isfinite(d.abscissa_min) && std::isfinite(d.abscissa_increment)))
      fail(line, fmt::format("record 7 fields 4–5 (abscissa minimum {}, increment {}) must be finite for even spacing",
                             d.abscissa_min, d.abscissa_increment));
    if (d.even && d.abscissa_increment == 0.0 && d.declared_points > 1)
      d.warnings.push_back(
          fmt::format("{}:{}: record 7 field 5 (abscissa increment) is 0 with even spacing: every "
                      "point has the same abscissa {}",
                      source_, line, d.abscissa_min));
  }

  // Records 8–11, format I10,3I5,2(1X,20A1).
  void parse_axis(const std::string& s, std::size_t line, int record, UffAxis& a) const {
    static constexpr const char* names[] = {"specific data type", "length units exponent", "force units exponent",
                                            "temperature units exponent"};
    static constexpr std::size_t start[] = {0, 10, 15, 20}, width[] = {10, 5, 5, 5};
    long long v[4] = {};
    bool fixed = true;
    for (std::size_t f = 0; f < 4 && fixed; ++f) {
      const auto x = parse_integer(column_field(s, start[f], width[f]));
      if (x) v[f] = *x;
      else fixed = false;
    }
    if (fixed) {
      a.label = std::string(trim(column_field(s, 26, 20)));
      a.units = std::string(trim(column_field(s, 47, std::string::npos)));
    } else {
      const auto tok = split_blanks(s);
      for (std::size_t f = 0; f < 4; ++f) {
        const auto x = f < tok.size() ? parse_integer(tok[f]) : std::nullopt;
        if (!x)
          fail(line, fmt::format("record {} field {} ({}) is '{}' in columns {}–{}, expected an integer (format "
                                 "I10,3I5,2(1X,20A1))",
                                 record, f + 1, names[f], excerpt(trim(column_field(s, start[f], width[f]))), start[f] + 1,
                                 start[f] + width[f]));
        v[f] = *x;
      }
      a.label = tok.size() > 4 ? std::string(tok[4]) : "NONE";
      a.units = tok.size() > 5 ? std::string(tok[5]) : "NONE";
    }
    a.data_type = to_int(v[0], line, record, 1, names[0]);
    a.length_exponent = to_int(v[1], line, record, 2, names[1]);
    a.force_exponent = to_int(v[2], line, record, 3, names[2]);
    a.temperature_exponent = to_int(v[3], line, record, 4, names[3]);
  }

  // Values record 12 should hold, saturating (a lying header may declare anything).
  static unsigned long long wanted_values(const UffDataset58& d) {
    const auto per = values_per_point(d.is_complex(), d.even);
    const auto n = static_cast<unsigned long long>(d.declared_points);
    return n > std::numeric_limits<unsigned long long>::max() / per ? std::numeric_limits<unsigned long long>::max() : n * per;
  }

  // Record 12 in ASCII: the values up to the closing delimiter. A record without its closing
  // delimiter is cut off (its last number may be cut short: "-6.766" of "-6.766E-10"), so the
  // dataset is refused rather than read. Headers only: the lines are passed over, and only the
  // first and the last are read for the abscissa range.
  void read_ascii_data(UffDataset58& d, const std::string& what, std::vector<double>& values) {
    const unsigned long long wanted = wanted_values(d);
    const std::size_t first_line = cur_.line;
    std::vector<double> line_values;
    unsigned long long found = 0;
    std::size_t extra_line = 0;
    std::string_view first_text, last_text;
    std::size_t last_line = 0;
    bool closed = false;
    if (!options_.headers_only) {
      // Never reserve what the header claims: each value takes at least two bytes of the file.
      const std::size_t present_max = (cur_.data.size() - cur_.pos) / 2 + 1;
      values.reserve(static_cast<std::size_t>(std::min<unsigned long long>(wanted, present_max)));
    }
    while (!cur_.eof()) {
      const std::size_t line = cur_.line;
      const std::string_view text = cur_.take();
      if (is_delimiter(text)) {
        closed = true;
        break;
      }
      if (options_.headers_only) {
        if (!is_blank(text)) {
          if (first_text.empty()) first_text = text;
          last_text = text;
          last_line = line;
        }
        continue;
      }
      line_values.clear();
      const std::size_t bad = scan_reals(text, line_values);
      if (bad != std::string_view::npos)
        fail(line, fmt::format("record 12 (data) column {}: '{}' is not a number (expected {} values, then '    -1')",
                               char_count(header_text(text.substr(0, bad))) + 1, excerpt(text.substr(bad), 16),
                               ascii_layout(d.ordinate_data_type, d.even)));
      for (double v : line_values) {
        if (found < wanted) values.push_back(v);
        else if (extra_line == 0) extra_line = line;
        ++found;
      }
    }
    if (!closed)
      fail(cur_.line - 1, fmt::format("record 12 (data, from line {}) is cut off: the file ends without the closing "
                                      "'    -1' after {} of the {} values record 7 declares, and its last number may be "
                                      "cut short",
                                      first_line, found, wanted));
    if (found > wanted)
      d.warnings.push_back(
          fmt::format("{}:{}: {}: record 12 holds {} values, more than the {} that record 7's {} "
                      "points need; the extra values were ignored",
                      source_, extra_line, what, found, wanted, d.declared_points));
    if (options_.headers_only && !d.even && !first_text.empty()) {
      // The abscissa range of uneven data from the first and the last line alone.
      const std::size_t per = values_per_point(d.is_complex(), d.even);
      std::vector<double> v;
      if (scan_reals(first_text, v) == std::string_view::npos && !v.empty()) d.abscissa_first = v.front();
      v.clear();
      if (scan_reals(last_text, v) == std::string_view::npos && v.size() >= per) d.abscissa_last = v[(v.size() / per - 1) * per];
      else
        d.warnings.push_back(fmt::format("{}:{}: {}: the last line of record 12 holds no whole point", source_, last_line, what));
    }
  }

  // Where the closing delimiter stands if binary data end at byte `end`: right there, after
  // stray line-break bytes, or the end of the file (reported by close_binary).
  bool closes_at(std::size_t end) const {
    const std::string_view s = cur_.data;
    if (end > s.size()) return false;
    std::size_t p = end;
    while (p < s.size() && (s[p] == '\r' || s[p] == '\n')) ++p;
    if (p == s.size()) return true;
    Cursor probe{s, p, 0};
    return is_delimiter(probe.take());
  }

  // Record 12 in binary. Which bytes it holds is decided by where the closing delimiter stands,
  // not by trust in one count: record 7's point count and the 58b byte count (pyuff writes
  // num_pts × 8 for complex double, half the real size) are both tried, each also after a stray
  // line break before the data (Test.Lab exports). When neither ends at a delimiter the file may
  // be cut off inside the data (an error) or carry junk after them (read, warned).
  void read_binary_data(UffDataset58& d, const std::string& what, unsigned long long declared_bytes, std::vector<double>& values,
                        std::size_t& points_present) {
    const std::size_t start = cur_.pos;
    const std::size_t available = cur_.data.size() - start;
    const std::size_t size = d.is_double() ? 8 : 4;
    const std::size_t per = values_per_point(d.is_complex(), d.even);
    const unsigned long long wanted = wanted_values(d);
    const unsigned long long expected_bytes = wanted > std::numeric_limits<unsigned long long>::max() / size
                                                  ? std::numeric_limits<unsigned long long>::max()
                                                  : wanted * size;
    const auto fits = [&](std::size_t lead, unsigned long long bytes) {
      return lead <= available && bytes <= available - lead && closes_at(start + lead + static_cast<std::size_t>(bytes));
    };
    std::size_t lead = 0;  // stray line-break bytes before the data
    while (lead < 2 && lead < available && (cur_.data[start + lead] == '\r' || cur_.data[start + lead] == '\n')) ++lead;
    std::optional<std::pair<std::size_t, unsigned long long>> found;  // (lead, bytes)
    const auto try_lead = [&](std::size_t l) {
      if (fits(l, expected_bytes)) found = {l, expected_bytes};
      else if (declared_bytes != expected_bytes && fits(l, declared_bytes)) found = {l, declared_bytes};
      return found.has_value();
    };
    if (!try_lead(0) && lead > 0) try_lead(lead);
    const std::string counts = fmt::format("record 7: {} points × {} value(s) × {} bytes = {} bytes; 58b field 6: {} bytes",
                                           d.declared_points, per, size, expected_bytes, declared_bytes);
    unsigned long long bytes = 0;
    if (found) {
      cur_.pos = start + found->first;
      bytes = found->second;
      if (found->first > 0)
        d.warnings.push_back(
            fmt::format("{}: {}: {} stray line-break byte(s) before the binary data (byte {}), as some "
                        "exporters write; skipped",
                        source_, what, found->first, start));
      if (bytes == expected_bytes && declared_bytes != expected_bytes)
        d.warnings.push_back(fmt::format(
            "{}: {}: the 58b byte count disagrees with record 7 ({}); the data present agree "
            "with record 7 (the closing '    -1' follows them), so all {} points were read{}",
            source_, what, counts, d.declared_points,
            declared_bytes * 2 == expected_bytes && d.is_complex() ? " (pyuff writes num_pts × 8 bytes for complex data)" : ""));
      else if (bytes != expected_bytes)
        d.warnings.push_back(
            fmt::format("{}: {}: the data present agree with the 58b byte count, not with record 7 ({}); "
                        "read {} whole point(s){}",
                        source_, what, counts, std::min(bytes, expected_bytes) / (per * size),
                        bytes > expected_bytes ? " (record 7's count; the bytes after them ignored)" : ""));
    } else {
      // Neither count ends at a delimiter: the data run to the first `    -1` (written right after
      // the last byte, so not necessarily at a line start) that ends its line.
      std::optional<std::size_t> end;
      for (std::size_t at = cur_.data.find("    -1", start); at != std::string_view::npos;
           at = cur_.data.find("    -1", at + 1)) {
        Cursor probe{cur_.data, at, 0};
        if (is_delimiter(probe.take())) {
          end = at;
          break;
        }
      }
      if (!end)
        fail(cur_.line, fmt::format("record 12 (binary data from byte {}) is cut off: no closing '    -1' follows, and "
                                    "the file ends {} bytes into the data ({})",
                                    start, available, counts));
      std::size_t e = *end;
      for (int k = 0; k < 2 && e > start && (cur_.data[e - 1] == '\n' || cur_.data[e - 1] == '\r'); ++k) --e;
      bytes = e - start;
      d.warnings.push_back(
          fmt::format("{}: {}: the data agree with neither count ({}): the closing '    -1' at byte {} "
                      "makes them {} bytes; read {} whole point(s)",
                      source_, what, counts, *end, bytes, std::min(bytes, expected_bytes) / (per * size)));
    }
    // Never more points than record 7 declares (the extra bytes are passed over).
    const std::size_t count = static_cast<std::size_t>(std::min(bytes, expected_bytes) / size);
    points_present = count / per;
    const bool big = d.byte_order == 2;
    const char* p = cur_.data.data() + cur_.pos;
    const auto value_at = [&](std::size_t i) {
      return size == 8 ? load_value<double>(p + 8 * i, big) : static_cast<double>(load_value<float>(p + 4 * i, big));
    };
    if (!options_.headers_only) {
      values.resize(count);
      for (std::size_t i = 0; i < count; ++i) values[i] = value_at(i);
    } else if (!d.even && points_present > 0) {
      d.abscissa_first = value_at(0);
      d.abscissa_last = value_at((points_present - 1) * per);
    }
    cur_.advance(static_cast<std::size_t>(bytes));
    close_binary(what, cur_.pos, d.warnings);
  }

  // The points from record 12's values (or, headers only, the abscissa range of those present:
  // `present` points, unknown for ASCII). Even spacing: x_i = min + i·increment, never summed.
  void assemble(UffDataset58& d, const std::string& what, const std::vector<double>& values,
                std::optional<std::size_t> present) const {
    const std::size_t per = values_per_point(d.is_complex(), d.even);
    if (options_.headers_only) {
      d.headers_only = true;
      const auto n = present.value_or(static_cast<std::size_t>(std::min<long long>(d.declared_points, 1LL << 40)));
      if (present && *present < static_cast<unsigned long long>(d.declared_points))
        d.warnings.push_back(
            fmt::format("{}: {}: record 7 declares {} points but the file holds {}", source_, what, d.declared_points, *present));
      if (d.even && n > 0) {
        d.abscissa_first = d.abscissa_min;
        d.abscissa_last = d.abscissa_min + static_cast<double>(n - 1) * d.abscissa_increment;
      }
      return;
    }
    const std::size_t n = values.size() / per;
    if (values.size() % per != 0)
      d.warnings.push_back(
          fmt::format("{}: {}: record 12 ends inside a point ({} value(s) left over, {} per point); the "
                      "incomplete point was dropped",
                      source_, what, values.size() % per, per));
    if (static_cast<unsigned long long>(n) < static_cast<unsigned long long>(d.declared_points))
      d.warnings.push_back(
          fmt::format("{}: {}: record 7 declares {} points but the file holds {}; read the {} present "
                      "(the file is truncated or its header is wrong)",
                      source_, what, d.declared_points, n, n));
    d.x.resize(n);
    d.y.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double* v = values.data() + i * per;
      std::size_t k = 0;
      d.x[i] = d.even ? d.abscissa_min + static_cast<double>(i) * d.abscissa_increment : v[k++];
      d.y[i] = d.is_complex() ? Complex(v[k], v[k + 1]) : Complex(v[k], 0.0);
    }
    if (n > 0) {
      d.abscissa_first = d.x.front();
      d.abscissa_last = d.x.back();
    }
  }

  const std::string& source_;
  UffReadOptions options_;
  Cursor cur_;
  UffFile file_;
  std::optional<UffUnits> units_;
  std::size_t index58_ = 0;
};

// ---------------------------------------------------------------------------------------------
// The writer

// A number right-aligned in `width` characters, E format, with as many significant digits as fit
// after one leading blank (so blank-separated and fixed-column readers both read it).
std::string fortran_e(double v, int width) {
  std::string s;
  for (int digits = width - 7; digits >= 0; --digits) {
    s = fmt::format("{:.{}E}", v, digits);
    if (static_cast<int>(s.size()) < width) break;
  }
  return fmt::format("{:>{}}", s, width);
}

double reparse(const std::string& field) {
  std::vector<double> v;
  scan_reals(field, v);
  return v.empty() ? 0.0 : v.front();
}

template <typename T>
void store_value(std::string& out, T value, bool big_endian) {
  using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  const U u = std::bit_cast<U>(value);
  for (std::size_t k = 0; k < sizeof(U); ++k) {
    const std::size_t shift = 8 * (big_endian ? sizeof(U) - 1 - k : k);
    out += static_cast<char>((u >> shift) & 0xFF);
  }
}

// Text fields must be one line of UTF-8; their length is the writer's business (see Field).
void check_text(const std::string& s, const std::string& what) {
  if (s.find_first_of("\r\n") != std::string::npos)
    throw InvalidArgument(fmt::format("UFF {} '{}' holds a line break", what, excerpt(s)), "use a single line of text");
  if (!valid_utf8(s)) throw InvalidArgument(fmt::format("UFF {} is not valid UTF-8 text", what));
}

std::string or_none(const std::string& s) { return trim(s).empty() ? std::string("NONE") : s; }

// Text fields of one dataset as written: "NONE" for blank text, cut to the field's width with a
// warning (a 95-character ID line read from another program's file must not stop a copy), padded
// to it (code points: fmt may count display width differently).
struct Fields {
  const UffDataset58& d;
  std::size_t k;
  std::vector<std::string>& warnings;

  std::string operator()(const std::string& text, std::size_t width, const std::string& what) const {
    std::string s = or_none(text);
    const std::size_t n = char_count(s);
    if (n > width) {
      s = text::cut(s, width);
      warnings.push_back(fmt::format("UFF dataset {} ('{}'): the {} has {} characters, its field holds {}; written as '{}'", k,
                                     excerpt(d.id[0]), what, n, width, s));
      return s;
    }
    return s + std::string(width - n, ' ');
  }
};

std::string axis_line(const UffAxis& a, const Fields& field, int record) {
  return fmt::format("{:>10}{:>5}{:>5}{:>5} {} {}\n", a.data_type, a.length_exponent, a.force_exponent, a.temperature_exponent,
                     field(a.label, 20, fmt::format("record {} axis label", record)),
                     field(a.units, 20, fmt::format("record {} units label", record)));
}

void append_dataset(std::string& out, const UffDataset58& d, const UffWriteOptions& o, std::size_t k,
                    std::vector<std::string>& warnings) {
  const std::size_t n = d.y.size();
  const bool cpx = d.is_complex(), dbl = d.is_double();
  const std::size_t per = values_per_point(cpx, d.even);
  const std::size_t size = dbl ? 8 : 4;
  out += "    -1\n";
  if (o.binary)
    out += fmt::format("{:>6}b{:>6}{:>6}{:>12}{:>12}{:>6}{:>6}{:>12}{:>12}\n", 58, o.byte_order, 2, 11, n * per * size, 0, 0, 0,
                       0);
  else out += "    58\n";
  const Fields field{d, k, warnings};
  for (std::size_t i = 0; i < d.id.size(); ++i) {
    std::string line = field(d.id[i], 80, fmt::format("ID line {}", i + 1));
    // An ID line reading "-1" would end the dataset when read back: moved past column 6, where a
    // delimiter cannot stand (the reader trims it back to "-1"). Found by fuzz/fuzz_uff.cpp.
    if (is_delimiter(line)) line = std::string(5, ' ') + line.substr(0, line.size() > 75 ? 75 : line.size());
    out += line + "\n";
  }
  out += fmt::format("{:>5}{:>10}{:>5}{:>10} {}{:>10}{:>4} {}{:>10}{:>4}\n", d.function_type, d.function_id, d.version,
                     d.load_case, field(d.response_entity, 10, "response entity name"), d.response_node, d.response_direction,
                     field(d.reference_entity, 10, "reference entity name"), d.reference_node, d.reference_direction);
  const std::string xmin = fortran_e(d.even ? d.abscissa_min : 0.0, 13);
  const std::string xinc = fortran_e(d.even ? d.abscissa_increment : 0.0, 13);
  out += fmt::format("{:>10}{:>10}{:>10}{}{}{}\n", d.ordinate_data_type, n, d.even ? 1 : 0, xmin, xinc, fortran_e(d.z_value, 13));
  out += axis_line(d.abscissa, field, 8) + axis_line(d.ordinate, field, 9) + axis_line(d.denominator, field, 10) +
         axis_line(d.z_axis, field, 11);

  // The abscissa a reader will compute or read, against the one given.
  auto x_given = [&](std::size_t i) {
    return d.x.empty() ? d.abscissa_min + static_cast<double>(i) * d.abscissa_increment : d.x[i];
  };
  double worst = 0.0, worst_at = 0.0, scale = 0.0;
  auto track = [&](std::size_t i, double read_back) {
    const double given = x_given(i);
    scale = std::max(scale, std::abs(given));
    if (std::abs(read_back - given) > worst) {
      worst = std::abs(read_back - given);
      worst_at = given;
    }
  };

  const double xmin_read = reparse(xmin), xinc_read = reparse(xinc);
  if (o.binary) {
    const bool big = o.byte_order == 2;
    out.reserve(out.size() + n * per * size + 8);
    for (std::size_t i = 0; i < n; ++i) {
      double v[3];
      std::size_t m = 0;
      if (!d.even) v[m++] = d.x[i];
      v[m++] = d.y[i].real();
      if (cpx) v[m++] = d.y[i].imag();
      for (std::size_t j = 0; j < m; ++j) {
        if (dbl) store_value<double>(out, v[j], big);
        else store_value<float>(out, static_cast<float>(v[j]), big);
      }
      if (d.even) track(i, xmin_read + static_cast<double>(i) * xinc_read);
      else track(i, dbl ? d.x[i] : static_cast<double>(static_cast<float>(d.x[i])));
    }
  } else {
    // Field widths of one point and points per 80-column line (the specification's 8 cases).
    const int w = dbl ? 20 : 13;
    std::vector<int> widths;
    if (!d.even) widths.push_back(13);
    widths.push_back(w);
    if (cpx) widths.push_back(w);
    int line_width = 0;
    for (int x : widths) line_width += x;
    const std::size_t per_line = static_cast<std::size_t>(80 / line_width);
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t f = 0;
      if (!d.even) {
        const std::string xs = fortran_e(d.x[i], widths[f++]);
        out += xs;
        track(i, reparse(xs));
      } else {
        track(i, xmin_read + static_cast<double>(i) * xinc_read);
      }
      out += fortran_e(d.y[i].real(), widths[f++]);
      if (cpx) out += fortran_e(d.y[i].imag(), widths[f++]);
      if ((i + 1) % per_line == 0 || i + 1 == n) out += '\n';
    }
  }
  out += "    -1\n";
  if (worst > 1e-12 * scale) {
    const char* why = d.even     ? "record 7 holds the abscissa minimum and increment in 13-column fields (7 significant "
                                   "digits); write uneven binary 58b for exact abscissae"
                      : o.binary ? "single precision keeps about 7 significant digits; use ordinate type 4 or 6"
                                 : "ASCII holds uneven abscissae in 13-column fields (7 significant digits); write "
                                   "binary 58b for exact abscissae";
    warnings.push_back(
        fmt::format("UFF dataset {} ('{}'): the abscissa as written differs from the given one by up to "
                    "{:.3g} (at {:.9g}); {}",
                    k, excerpt(d.id[0]), worst, worst_at, why));
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public functions

UffFile parse_uff(std::string_view bytes, const std::string& source, const UffReadOptions& options) {
  return Parser(bytes, source, options).run();
}

UffFile read_uff(const std::string& path, const UffReadOptions& options) {
  const MappedFile file(path);
  return parse_uff(file.bytes(), path, options);
}

std::vector<std::string> UffFile::warnings_for(const std::vector<const UffDataset58*>& sets) const {
  constexpr std::size_t kShown = 10;  // messages for a person: the first few, then a count
  std::vector<std::string> out(file_warnings.begin(), file_warnings.begin() + std::min(file_warnings.size(), kShown));
  if (file_warnings.size() > kShown)
    out.push_back(fmt::format("{}: … and {} more problems in the file (see UffFile::file_warnings)", source,
                              file_warnings.size() - kShown));
  for (const UffDataset58* d : sets) out.insert(out.end(), d->warnings.begin(), d->warnings.end());
  if (!skipped.empty())
    out.push_back(
        fmt::format("{}: {} dataset(s) 58 could not be read and were skipped (see UffFile::skipped)", source, skipped.size()));
  return out;
}

bool UffSelection::empty() const {
  return !index && !response_node && !response_direction && !reference_node && !reference_direction;
}

std::string UffSelection::describe() const {
  std::vector<std::string> parts;
  if (index) parts.push_back(fmt::format("dataset {}", *index));
  if (response_node) parts.push_back(fmt::format("response node {}", *response_node));
  if (response_direction) parts.push_back(fmt::format("response direction {}", uff_direction_name(*response_direction)));
  if (reference_node) parts.push_back(fmt::format("reference node {}", *reference_node));
  if (reference_direction) parts.push_back(fmt::format("reference direction {}", uff_direction_name(*reference_direction)));
  if (parts.empty()) return "no selection";
  std::string s = parts[0];
  for (std::size_t i = 1; i < parts.size(); ++i) s += ", " + parts[i];
  return s;
}

namespace {

std::string candidate_line(const UffDataset58& d) {
  return fmt::format("  {}: {} (type {}), response {} {}, reference {} {}, {} points, '{}'", d.index,
                     uff_function_type_name(d.function_type), d.function_type, d.response_node,
                     uff_direction_name(d.response_direction), d.reference_node, uff_direction_name(d.reference_direction),
                     d.size(), excerpt(d.id[0], 60));
}

std::string candidate_list(const std::vector<const UffDataset58*>& sets) {
  std::string s;
  const std::size_t shown = std::min<std::size_t>(sets.size(), 20);
  for (std::size_t i = 0; i < shown; ++i) s += "\n" + candidate_line(*sets[i]);
  if (sets.size() > shown) s += fmt::format("\n  … and {} more", sets.size() - shown);
  return s;
}

}  // namespace

const UffDataset58& select_dataset58(const UffFile& file, const UffSelection& sel) {
  constexpr std::size_t kShown = 5;  // the first few reasons, then a count
  std::string skipped;
  for (std::size_t i = 0; i < file.skipped.size() && i < kShown; ++i) skipped += "\n  " + file.skipped[i];
  if (file.skipped.size() > kShown) skipped += fmt::format("\n  … and {} more (UffFile::skipped)", file.skipped.size() - kShown);
  if (file.functions.empty())
    throw InputError(fmt::format("{}: no readable dataset 58 (function at nodal DOF) in the file ({} dataset(s) of "
                                 "other types, {} dataset(s) 58 unreadable){}",
                                 file.source, file.datasets.size() - file.skipped.size(), file.skipped.size(), skipped),
                     "a tap-test FRF is exported as UFF dataset 58 or 58b; check the export settings");
  std::vector<const UffDataset58*> all, match;
  for (const auto& d : file.functions) {
    all.push_back(&d);
    const bool ok = (!sel.index || d.index == *sel.index) && (!sel.response_node || d.response_node == *sel.response_node) &&
                    (!sel.response_direction || d.response_direction == *sel.response_direction) &&
                    (!sel.reference_node || d.reference_node == *sel.reference_node) &&
                    (!sel.reference_direction || d.reference_direction == *sel.reference_direction);
    if (ok) match.push_back(&d);
  }
  if (match.size() == 1) return *match.front();
  if (match.empty())
    throw InputError(fmt::format("{}: no dataset 58 matches {}; the file holds:{}{}", file.source, sel.describe(),
                                 candidate_list(all), skipped.empty() ? "" : "\nskipped:" + skipped),
                     "pick an index or node/direction from the list (UffFile::functions)");
  throw InputError(fmt::format("{}: {} datasets 58 match {}:{}", file.source, match.size(), sel.describe(),
                               candidate_list(match)),
                   "choose one by index (UffSelection::index) or add node/direction criteria");
}

void UffWriteOptions::check() const { check_fields(uff_write_fields(), *this, "UffWriteOptions"); }

const std::vector<OptionField<UffWriteOptions>>& uff_write_fields() {
  using O = UffWriteOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "binary", .kind = FieldKind::Flag, .help = "write binary dataset 58b instead of ASCII", .cli_name = "binary"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.binary; }},
      {{.name = "byte_order",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 2.0,
        .help = "the binary data's byte order: 1 little endian, 2 big endian (binary only)"},
       nullptr,
       [](O& o) -> int& { return o.byte_order; }}};
  return fields;
}

void UffDataset58::check() const {
  const std::string what = fmt::format("dataset 58 '{}'", excerpt(id[0]));
  if (ordinate_data_type != 2 && ordinate_data_type != 4 && ordinate_data_type != 5 && ordinate_data_type != 6)
    throw InvalidArgument(fmt::format("{}: ordinate data type {} is not 2, 4, 5 or 6", what, ordinate_data_type));
  if (even && !x.empty() && x.size() != y.size())
    throw InvalidArgument(fmt::format("{}: {} abscissa values for {} ordinates", what, x.size(), y.size()));
  if (!even && x.size() != y.size())
    throw InvalidArgument(
        fmt::format("{}: uneven spacing needs one abscissa per point: {} for {} ordinates", what, x.size(), y.size()));
  if (even) {
    if (!std::isfinite(abscissa_min) || !std::isfinite(abscissa_increment))
      throw InvalidArgument(
          fmt::format("{}: abscissa minimum {} and increment {} must be finite", what, abscissa_min, abscissa_increment));
    double scale = std::abs(abscissa_min);
    for (double v : x) scale = std::max(scale, std::abs(v));
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double grid = abscissa_min + static_cast<double>(i) * abscissa_increment;
      if (std::abs(x[i] - grid) > 1e-9 * scale)
        throw InvalidArgument(fmt::format("{}: point {} has abscissa {}, not {} + {} × {} = {} as even spacing needs", what, i,
                                          x[i], abscissa_min, i, abscissa_increment, grid),
                              "write with uneven spacing, or give x on the even grid");
    }
  }
  if (!is_complex())
    for (std::size_t i = 0; i < y.size(); ++i)
      if (y[i].imag() != 0.0)
        throw InvalidArgument(fmt::format("{}: point {} has imaginary part {} but ordinate data type {} is real", what, i,
                                          y[i].imag(), ordinate_data_type),
                              "use type 5 or 6 for complex data");
  for (std::size_t k = 0; k < id.size(); ++k) check_text(id[k], fmt::format("ID line {}", k + 1));
  check_text(response_entity, "response entity name");
  check_text(reference_entity, "reference entity name");
  const UffAxis* axes[] = {&abscissa, &ordinate, &denominator, &z_axis};
  for (std::size_t k = 0; k < 4; ++k) {
    check_text(axes[k]->label, fmt::format("record {} axis label", 8 + k));
    check_text(axes[k]->units, fmt::format("record {} units label", 8 + k));
    for (int e : {axes[k]->length_exponent, axes[k]->force_exponent, axes[k]->temperature_exponent})
      if (e < -9999 || e > 99999)
        throw InvalidArgument(fmt::format("{}: record {} units exponent {} does not fit 5 columns", what, 8 + k, e));
  }
  for (int v : {function_type, version})
    if (v < -9999 || v > 99999) throw InvalidArgument(fmt::format("{}: record 6 value {} does not fit 5 columns", what, v));
  for (int v : {response_direction, reference_direction})
    if (v < -999 || v > 9999) throw InvalidArgument(fmt::format("{}: direction {} does not fit 4 columns", what, v));
  for (int v : {function_id, load_case, response_node, reference_node})
    if (v < -999'999'999) throw InvalidArgument(fmt::format("{}: record 6 value {} does not fit 10 columns", what, v));
}

UffText format_uff(const std::vector<UffDataset58>& sets, const UffWriteOptions& options) {
  options.check();
  UffText t;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    sets[k].check();
    append_dataset(t.bytes, sets[k], options, k, t.warnings);
  }
  return t;
}

std::vector<std::string> write_uff(const std::string& path, const std::vector<UffDataset58>& sets,
                                   const UffWriteOptions& options) {
  UffText t = format_uff(sets, options);
  write_text_file(path, t.bytes);
  return t.warnings;
}

double uff_field13_roundtrip(double v) { return reparse(fortran_e(v, 13)); }

std::string uff_direction_name(int d) {
  static const char* names[] = {"X", "Y", "Z", "RX", "RY", "RZ"};
  if (d == 0) return "scalar";
  if (d < -6 || d > 6) return fmt::format("code {}", d);
  return std::string(d > 0 ? "+" : "-") + names[std::abs(d) - 1];
}

std::string uff_function_type_name(int t) {
  static const char* names[] = {"general",
                                "time response",
                                "auto spectrum",
                                "cross spectrum",
                                "frequency response function",
                                "transmissibility",
                                "coherence",
                                "auto correlation",
                                "cross correlation",
                                "power spectral density",
                                "energy spectral density",
                                "probability density function",
                                "spectrum",
                                "cumulative frequency distribution",
                                "peaks valley",
                                "stress/cycles",
                                "strain/cycles",
                                "orbit",
                                "mode indicator function",
                                "force pattern",
                                "partial power",
                                "partial coherence",
                                "eigenvalue",
                                "eigenvector",
                                "shock response spectrum",
                                "finite impulse response filter",
                                "multiple coherence",
                                "order function"};
  if (t < 0 || t > 27) return fmt::format("function type {}", t);
  return names[t];
}

std::string uff_data_type_name(int t) {
  static const std::map<int, const char*> names = {{0, "unknown"},
                                                   {1, "general"},
                                                   {2, "stress"},
                                                   {3, "strain"},
                                                   {5, "temperature"},
                                                   {6, "heat flux"},
                                                   {8, "displacement"},
                                                   {9, "reaction force"},
                                                   {11, "velocity"},
                                                   {12, "acceleration"},
                                                   {13, "excitation force"},
                                                   {15, "pressure"},
                                                   {16, "mass"},
                                                   {17, "time"},
                                                   {18, "frequency"},
                                                   {19, "rpm"},
                                                   {20, "order"}};
  const auto it = names.find(t);
  return it == names.end() ? fmt::format("data type {}", t) : std::string(it->second);
}

std::string uff_ordinate_type_name(int t) {
  switch (t) {
    case 2: return "real single";
    case 4: return "real double";
    case 5: return "complex single";
    case 6: return "complex double";
    default: return fmt::format("ordinate type {}", t);
  }
}

}  // namespace toolpoint
