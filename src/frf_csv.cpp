// toolpoint: reading FRF CSV in the dialects measurement software and scripts write (io.hpp).
//
// The order of decisions, each from the file alone or from an option, never from a guess:
//   1. text: a UTF-8 byte order mark is skipped (UTF-16 is refused), CRLF ends lines, '#' and '%'
//      start comment lines; a preamble above the header (a vendor's title, date, channel lines) is
//      skipped, and said so, when the table under it is recognised (skip_preamble);
//   2. the separator: tab, ';' or ',' — the first of them the first line holds;
//   3. the decimal mark: a comma when cells hold one and the separator is not ',' (a cell with both
//      '.' and ',' is refused: thousands separators are not read);
//   4. header or not: the first line is a header unless every cell is a number;
//   5. columns: a block header (frequency, H_re … P_im), else the frequency column, the value
//      columns (re/im or magnitude/phase) and a coherence column by name, or FrfCsvOptions;
//   6. units: the frequency's (Hz, kHz, rad/s) applied here, the values' returned as text; a phase
//      said to be in degrees that stays within ±π through a resonance is refused (radians).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "text.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"

namespace toolpoint {

namespace {

using text::lower;
using text::trim;

struct Cell {
  std::string_view text;  // trimmed, outer quotes removed
  bool quoted = false;
};

// Cells of one line: `sep` between them, double quotes around a cell keep separators inside it.
// A last empty cell after a trailing separator (CutPro, some spreadsheets) is dropped.
std::vector<Cell> split_cells(std::string_view line, char sep) {
  std::vector<Cell> out;
  std::size_t i = 0;
  for (;;) {
    while (i < line.size() && (line[i] == ' ' || (line[i] == '\t' && sep != '\t'))) ++i;
    Cell c;
    std::size_t end;
    if (i < line.size() && line[i] == '"') {
      const std::size_t close = line.find('"', i + 1);
      const std::size_t stop = close == std::string_view::npos ? line.size() : close;
      c.text = line.substr(i + 1, stop - i - 1);
      c.quoted = true;
      end = line.find(sep, stop == line.size() ? stop : stop + 1);
    } else {
      end = line.find(sep, i);
      c.text = trim(line.substr(i, end == std::string_view::npos ? std::string_view::npos : end - i));
    }
    out.push_back(c);
    if (end == std::string_view::npos) break;
    i = end + 1;
  }
  if (out.size() > 1 && out.back().text.empty() && !out.back().quoted) out.pop_back();
  return out;
}

// A number in a cell: '.' or (decimal_comma) ',' as the decimal mark, an optional '+'.
std::optional<double> number_of(std::string_view cell, bool decimal_comma) {
  if (cell.empty()) return std::nullopt;
  std::string mended;
  if (decimal_comma && cell.find(',') != std::string_view::npos) {
    if (cell.find('.') != std::string_view::npos) return std::nullopt;
    mended.assign(cell);
    std::replace(mended.begin(), mended.end(), ',', '.');
    cell = mended;
  }
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  if (*first == '+') ++first;
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (ptr != last || (ec != std::errc() && ec != std::errc::result_out_of_range)) return std::nullopt;
  if (ec == std::errc::result_out_of_range) v = std::numeric_limits<double>::infinity();  // refused as not finite
  return v;
}

// ---- header names ----------------------------------------------------------------------------

enum class Role { None, Frequency, Real, Imag, Magnitude, Db, Phase, Coherence };

const char* role_name(Role r) {
  switch (r) {
    case Role::Frequency: return "frequency";
    case Role::Real: return "real part";
    case Role::Imag: return "imaginary part";
    case Role::Magnitude: return "magnitude";
    case Role::Db: return "magnitude in dB";
    case Role::Phase: return "phase";
    case Role::Coherence: return "coherence";
    case Role::None: break;
  }
  return "unused";
}

// Lower-case letters and digits only (and the characters of `also`): "Re(H)" → "reh", "|H|" → "h",
// "Freq." → "freq".
std::string squeeze(std::string_view s, std::string_view also = {}) {
  std::string kept;
  for (char c : s)
    if (std::isalnum(static_cast<unsigned char>(c)) || also.find(c) != std::string_view::npos) kept += c;
  return lower(kept);
}

Role role_of_name(std::string_view raw) {
  const std::string l = lower(raw);
  if (l.find("γ²") != std::string::npos || l.find("γ^2") != std::string::npos || l == "γ") return Role::Coherence;
  const std::string n = squeeze(raw);
  auto in = [&](std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* x) { return n == x; });
  };
  if (in({"f", "freq", "frequency", "frequencies", "frq"})) return Role::Frequency;
  if (in({"re", "real", "realpart", "reh", "realh", "refrf", "realfrf"})) return Role::Real;
  if (in({"im", "imag", "imaginary", "imaginarypart", "imh", "imagh", "imfrf", "imagfrf"})) return Role::Imag;
  if (in({"mag", "magnitude", "abs", "absh", "amplitude", "amp", "modulus", "h", "magh", "magnitudeh"})) return Role::Magnitude;
  if (in({"db", "magdb", "magnitudedb", "amplitudedb", "level", "leveldb"})) return Role::Db;
  if (in({"phase", "phi", "angle", "arg", "phaseh", "argh", "angleh"})) return Role::Phase;
  if (in({"coherence", "coh", "cohere", "gamma2", "gammasquared", "coherenceh"})) return Role::Coherence;
  return Role::None;
}

struct FrequencyUnit {
  double to_hz = 1.0;
};
std::optional<FrequencyUnit> frequency_unit(std::string_view u) {
  const std::string s = squeeze(u);
  if (s == "hz" || s == "1s") return FrequencyUnit{1.0};
  if (s == "khz") return FrequencyUnit{1e3};
  if (s == "rads" || s == "radsec") return FrequencyUnit{1.0 / (2.0 * std::numbers::pi)};
  return std::nullopt;
}

std::optional<bool> phase_in_degrees(std::string_view u) {
  const std::string t(trim(u));
  const std::string s = squeeze(u);
  if (t == "°" || s == "deg" || s == "degree" || s == "degrees" || s == "grad" || s == "deg°") return true;
  if (s == "rad" || s == "radian" || s == "radians") return false;
  return std::nullopt;
}

bool unitless(std::string_view u) {
  const std::string t(trim(u));
  return t.empty() || t == "-" || t == "1" || squeeze(u) == "none";
}

// One header cell understood: what the column holds and in which units.
struct Column {
  Role role = Role::None;
  std::string unit;         // as written ("m/N", "deg", "dB re 1 m/N")
  bool degrees = false;     // phase
  double to_hz = 1.0;       // frequency
  std::string value_units;  // real/imag/magnitude: the unit; dB: what follows "re" (may be empty)
};

// "dB", "dB re 1 m/N", "dB re m/N" → the reference units after "re" ("" when none).
std::optional<std::string> db_reference(std::string_view u) {
  const std::string t(trim(u));
  const std::string l = lower(t);
  if (l.rfind("db", 0) != 0) return std::nullopt;
  std::string_view rest = trim(std::string_view(t).substr(2));
  if (rest.empty()) return std::string();
  if (lower(rest.substr(0, 2)) != "re") return std::nullopt;
  rest = trim(rest.substr(2));
  if (!rest.empty() && rest.front() == '1') rest = trim(rest.substr(1));
  return std::string(rest);
}

// A role with a unit: valid combinations only (so "Real part" stays a name, not "Real" in "part").
std::optional<Column> with_unit(Role role, std::string_view unit) {
  Column c;
  c.role = role;
  c.unit = std::string(trim(unit));
  if (c.unit.empty()) return c;
  switch (role) {
    case Role::Frequency:
      if (const auto f = frequency_unit(unit)) {
        c.to_hz = f->to_hz;
        return c;
      }
      return std::nullopt;
    case Role::Phase:
      if (const auto d = phase_in_degrees(unit)) {
        c.degrees = *d;
        return c;
      }
      return std::nullopt;
    case Role::Coherence: return unitless(unit) ? std::optional<Column>(c) : std::nullopt;
    case Role::Magnitude:
    case Role::Db:
      if (const auto ref = db_reference(unit)) {
        c.role = Role::Db;
        c.value_units = *ref;
        return c;
      }
      if (role == Role::Db) return std::nullopt;
      [[fallthrough]];
    case Role::Real:
    case Role::Imag:
      if (phase_in_degrees(unit) || frequency_unit(unit) || unitless(unit)) return std::nullopt;
      if (std::none_of(c.unit.begin(), c.unit.end(), [](char ch) { return std::isalpha(static_cast<unsigned char>(ch)); }))
        return std::nullopt;
      c.value_units = c.unit;
      return c;
    case Role::None: break;
  }
  return std::nullopt;
}

// A header cell: the whole text as a name; else a unit in trailing brackets; else a unit after the
// first '_', '/' or blank that makes a valid (name, unit) pair.
Column understand(std::string_view cell) {
  cell = trim(cell);
  if (const Role r = role_of_name(cell); r != Role::None) return *with_unit(r, {});
  if (!cell.empty() && (cell.back() == ')' || cell.back() == ']')) {
    const char open = cell.back() == ')' ? '(' : '[';
    const std::size_t at = cell.rfind(open);
    if (at != std::string_view::npos && at > 0)
      if (const Role r = role_of_name(cell.substr(0, at)); r != Role::None)
        if (auto c = with_unit(r, cell.substr(at + 1, cell.size() - at - 2))) return *c;
  }
  for (std::size_t at = cell.find_first_of(" _/"); at != std::string_view::npos; at = cell.find_first_of(" _/", at + 1))
    if (const Role r = role_of_name(cell.substr(0, at)); r != Role::None)
      if (auto c = with_unit(r, cell.substr(at + 1))) return *c;
  return {};
}

const char* const kBlockNames[] = {"H_re", "H_im", "L_re", "L_im", "N_re", "N_im", "P_re", "P_im"};
const char* const kBlockUnits[] = {"m/N", "m/N", "1/N", "1/N", "rad/N", "rad/N", "rad/(N m)", "rad/(N m)"};

// The block entry a cell names (0…7) and its unit, or nullopt.
std::optional<int> block_entry(std::string_view cell, std::string& unit) {
  cell = trim(cell);
  std::string_view name = cell;
  unit.clear();
  if (!cell.empty() && (cell.back() == ')' || cell.back() == ']')) {
    const std::size_t at = cell.rfind(cell.back() == ')' ? '(' : '[');
    if (at != std::string_view::npos && at > 0) {
      name = trim(cell.substr(0, at));
      unit = std::string(trim(cell.substr(at + 1, cell.size() - at - 2)));
    }
  }
  for (int k = 0; k < 8; ++k)
    if (text::iequal(name, kBlockNames[k])) return k;
  return std::nullopt;
}

// Units of a block column as written: SI only (spaces, '·', '*' and brackets ignored).
bool block_unit_is_si(int k, const std::string& unit) {
  if (unit.empty()) return true;
  const std::string a = squeeze(unit, "/"), b = squeeze(kBlockUnits[k], "/");
  return a == b || (k >= 2 && k <= 3 && a == "m/nm") || (k >= 6 && a == "rad/nm");
}

struct Line {
  std::size_t number;
  std::string_view text;
};

class CsvReader {
 public:
  CsvReader(const std::string& text, const std::string& source, const FrfCsvOptions& options)
      : text_(text), source_(source), o_(options) {}

  FrfTable run() {
    o_.check();
    lines();
    if (lines_.empty())
      throw InputError(fmt::format("{}: no data (the file is empty or holds only comments)", source_),
                       "an FRF CSV holds a header line (e.g. frequency_hz,re,im) and one line per frequency");
    skip_preamble();
    separator();
    decimal_mark();
    header();
    if (table_.is_block) read_block();
    else read_single();
    const std::size_t n = table_.is_block ? table_.block.size() : table_.single.size();
    if (n == 0) throw InputError(fmt::format("{}: header but no data lines", source_));
    if (zero_lines_ > 0)
      table_.warnings.push_back(
          fmt::format("{}: {} line(s) at 0 Hz dropped (the first: line {}): an FRF series needs "
                      "frequencies above 0 Hz",
                      source_, zero_lines_, first_zero_line_));
    return std::move(table_);
  }

 private:
  [[noreturn]] void fail(std::size_t line, const std::string& what, const std::string& hint = {}) const {
    throw InputError(fmt::format("{}:{}: {}", source_, line, what), hint);
  }

  void lines() {
    std::string_view all = text_;
    if (all.substr(0, 3) == "\xEF\xBB\xBF") all.remove_prefix(3);
    else if (all.substr(0, 2) == "\xFF\xFE" || all.substr(0, 2) == "\xFE\xFF")
      throw InputError(fmt::format("{}: the file is UTF-16 text", source_), "save it as UTF-8 (or ASCII) CSV");
    std::size_t pos = 0, number = 0;
    while (pos < all.size()) {
      std::size_t end = all.find('\n', pos);
      if (end == std::string_view::npos) end = all.size();
      const std::string_view line = trim(all.substr(pos, end - pos));
      ++number;
      pos = end + 1;
      if (line.empty() || line.front() == '#' || line.front() == '%') continue;
      if (line.find('\0') != std::string_view::npos)
        fail(number, "holds a NUL byte: this is not a text file", "give a CSV text file");
      lines_.push_back({number, line});
    }
  }

  // The separator a line shows: tab, ';' or ',', the first of them it holds.
  static char separator_of(std::string_view line) {
    return line.find('\t') != std::string_view::npos ? '\t' : line.find(';') != std::string_view::npos ? ';' : ',';
  }

  void separator() { sep_ = separator_of(lines_.front().text); }

  // How many cells `line` splits into by `sep` when every one is a number (a decimal comma allowed
  // unless `sep` is ','), else 0.
  static std::size_t numeric_cells(std::string_view line, char sep) {
    const std::vector<Cell> cells = split_cells(line, sep);
    for (const Cell& c : cells)
      if (!number_of(c.text, sep != ',' || c.quoted)) return 0;
    return cells.size();
  }

  // A preamble — the title, date and channel lines a vendor's export writes above its table — is
  // recognised by the table under it: the first line of two or more numbers (by its own
  // separator) whose next line splits alike is the first data line, and the line above it, split
  // into as many cells, the header. The lines above the header are skipped, with a warning naming
  // them. Without such a header (no header, or one directly on the first line) nothing is skipped.
  void skip_preamble() {
    for (std::size_t k = 0; k < lines_.size(); ++k) {
      const char sep = separator_of(lines_[k].text);
      const std::size_t cells = numeric_cells(lines_[k].text, sep);
      if (cells < 2) continue;
      if (k + 1 < lines_.size() && numeric_cells(lines_[k + 1].text, sep) != cells) continue;
      if (k < 2 || split_cells(lines_[k - 1].text, sep).size() != cells) return;
      const std::size_t header = k - 1;
      const std::size_t first = lines_.front().number, last = lines_[header - 1].number;
      table_.warnings.push_back(
          fmt::format("{}: {} above the header (line {}) skipped, not being part of the table: '{}'{}", source_,
                      first == last ? fmt::format("line {}", first) : fmt::format("lines {}–{}", first, last),
                      lines_[header].number, text::excerpt(lines_.front().text, 60), header > 1 ? ", …" : ""));
      lines_.erase(lines_.begin(), lines_.begin() + static_cast<std::ptrdiff_t>(header));
      return;
    }
  }

  void decimal_mark() {
    if (sep_ == ',') return;
    for (std::size_t k = 0; k < lines_.size() && k < 50; ++k)
      for (const Cell& c : split_cells(lines_[k].text, sep_))
        if (c.text.find(',') != std::string_view::npos && c.text.find_first_of("0123456789") != std::string_view::npos &&
            std::all_of(c.text.begin(), c.text.end(), [](char ch) {
              return std::isdigit(static_cast<unsigned char>(ch)) || ch == ',' || ch == '.' || ch == '-' || ch == '+' ||
                     ch == 'e' || ch == 'E';
            })) {
          if (c.text.find('.') != std::string_view::npos)
            fail(lines_[k].number, fmt::format("'{}' holds both '.' and ',': thousands separators are not read", c.text),
                 "export the numbers without thousands separators");
          decimal_comma_ = true;
          return;
        }
  }

  std::string sep_name() const { return sep_ == '\t' ? "tab" : sep_ == ';' ? "';'" : "','"; }

  void header() {
    const std::vector<Cell> cells = split_cells(lines_.front().text, sep_);
    columns_ = cells.size();
    has_header_ = !std::all_of(cells.begin(), cells.end(), [&](const Cell& c) { return number_of(c.text, decimal_comma_); });
    if (has_header_) {
      for (const Cell& c : cells) names_.emplace_back(c.text);
      first_data_ = 1;
      if (block_header()) return;
    }
    choose_columns();
  }

  // frequency, H_re … P_im (units, if given, SI), optionally a coherence column.
  bool block_header() {
    if (names_.size() < 9 || names_.size() > 10) return false;
    std::string unit;
    if (understand(names_[0]).role != Role::Frequency) return false;
    for (int k = 0; k < 8; ++k) {
      const auto e = block_entry(names_[static_cast<std::size_t>(k) + 1], unit);
      if (!e || *e != k) return false;
      if (!block_unit_is_si(k, unit))
        fail(lines_.front().number,
             fmt::format("column {} ({}) is in '{}'; a block file is read in SI units only ({})", k + 2, kBlockNames[k], unit,
                         kBlockUnits[k]),
             "convert the block to SI units (toolpoint writes H m/N, L 1/N, N rad/N, P rad/(N m))");
    }
    if (names_.size() == 10) {
      if (understand(names_[9]).role != Role::Coherence) return false;
      coh_ = 9;
    }
    if (o_.format || !o_.columns.empty())
      throw InvalidArgument(
          fmt::format("{}: a 2×2 block file (frequency, H_re … P_im) takes no column or value-format "
                      "choice (FrfCsvOptions::columns / format)",
                      source_));
    const Column f = understand(names_[0]);
    to_hz_ = f.to_hz;
    table_.is_block = true;
    return true;
  }

  std::string column_text(std::size_t k) const {
    return has_header_ ? fmt::format("column {} ('{}')", k + 1, names_[k]) : fmt::format("column {}", k + 1);
  }

  // The column an entry of FrfCsvOptions::columns names: a number from 1, or a header cell's text.
  std::size_t column_named(const std::string& entry) const {
    std::size_t k = 0;
    const auto [p, ec] = std::from_chars(entry.data(), entry.data() + entry.size(), k);
    if (ec == std::errc() && p == entry.data() + entry.size()) {
      if (k < 1 || k > columns_)
        throw InvalidArgument(
            fmt::format("{}: FrfCsvOptions::columns names column {}, but the file has {} column(s)", source_, entry, columns_));
      return k - 1;
    }
    for (std::size_t c = 0; c < names_.size(); ++c)
      if (text::iequal(trim(names_[c]), trim(entry))) return c;
    std::string list;
    for (std::size_t c = 0; c < names_.size(); ++c) list += fmt::format("{}{} '{}'", c ? ", " : "", c + 1, names_[c]);
    throw InvalidArgument(
        fmt::format("{}: FrfCsvOptions::columns names '{}', which is {}", source_, entry,
                    has_header_ ? "no header cell; the header holds " + list : "not a column number (the file has no header)"));
  }

  void choose_columns() {
    const std::size_t header_line = lines_.front().number;
    std::vector<Column> cols(columns_);
    if (has_header_)
      for (std::size_t k = 0; k < columns_; ++k) cols[k] = understand(names_[k]);
    const std::string settle =
        "say which columns hold what (FrfCsvOptions::columns: frequency, the two values, "
        "optionally coherence) and what the values are (FrfCsvOptions::format: re-im, "
        "mag-phase-deg, mag-phase-rad, db-phase)";
    if (!o_.columns.empty()) {
      f_ = column_named(o_.columns[0]);
      a_ = column_named(o_.columns[1]);
      b_ = column_named(o_.columns[2]);
      if (o_.columns.size() == 4) coh_ = column_named(o_.columns[3]);
      std::vector<std::size_t> picked{f_, a_, b_};
      if (coh_) picked.push_back(*coh_);
      for (std::size_t i = 0; i < picked.size(); ++i)
        for (std::size_t j = i + 1; j < picked.size(); ++j)
          if (picked[i] == picked[j])
            throw InvalidArgument(fmt::format("{}: FrfCsvOptions::columns names {} twice", source_, column_text(picked[i])));
    } else if (!has_header_) {
      if (columns_ != 3 && columns_ != 4)
        fail(header_line, fmt::format("no header line and {} column(s): which hold the frequency and the FRF?", columns_),
             settle);
      if (!o_.format)
        fail(header_line,
             fmt::format("no header line: the {} columns could be frequency, real and imaginary part or magnitude and "
                         "phase{}",
                         columns_, columns_ == 4 ? ", and coherence" : ""),
             "say what the values are (FrfCsvOptions::format: re-im, mag-phase-deg, mag-phase-rad, db-phase), or add a "
             "header line such as frequency_hz,re,im");
      f_ = 0;
      a_ = 1;
      b_ = 2;
      if (columns_ == 4) coh_ = 3;
    } else {
      find_by_name(cols, header_line, settle);
    }
    // What the value columns are: the option, else their names.
    const Column& fc = cols[f_];
    if (has_header_ && !o_.columns.empty() && fc.role != Role::Frequency && fc.role != Role::None)
      fail(header_line, fmt::format("{} is the {} by its name, not the frequency", column_text(f_), role_name(fc.role)), settle);
    to_hz_ = fc.role == Role::Frequency ? fc.to_hz : 1.0;
    if (has_header_ && fc.role == Role::Frequency && !fc.unit.empty() && !frequency_unit(fc.unit))
      fail(header_line, fmt::format("{}: frequency unit '{}' not known", column_text(f_), fc.unit), "use Hz, kHz or rad/s");
    const Column &ac = cols[a_], &bc = cols[b_];
    std::optional<FrfValueFormat> named;
    if (ac.role == Role::Real && bc.role == Role::Imag) named = FrfValueFormat::ReIm;
    else if ((ac.role == Role::Magnitude || ac.role == Role::Db) && bc.role == Role::Phase) {
      const bool db = ac.role == Role::Db;
      if (bc.unit.empty()) {
        if (!o_.format)
          fail(header_line, fmt::format("{} gives no unit: degrees or radians?", column_text(b_)),
               fmt::format("name the unit in the header (e.g. 'Phase (deg)'), or say it: FrfCsvOptions::format {}",
                           db ? "db-phase-deg or db-phase-rad" : "mag-phase-deg or mag-phase-rad"));
      } else {
        named = db ? (bc.degrees ? FrfValueFormat::DbPhaseDeg : FrfValueFormat::DbPhaseRad)
                   : (bc.degrees ? FrfValueFormat::MagPhaseDeg : FrfValueFormat::MagPhaseRad);
        named_degrees_ = bc.degrees;
      }
    }
    if (o_.format) {
      if (named && *named != *o_.format)
        throw InvalidArgument(fmt::format("{}: the header says the values are {} ({} and {}), FrfCsvOptions::format says "
                                          "{}",
                                          source_, frf_value_format_name(*named), column_text(a_), column_text(b_),
                                          frf_value_format_name(*o_.format)),
                              "drop FrfCsvOptions::format, or correct the header");
      table_.format = *o_.format;
    } else if (named) {
      table_.format = *named;
    } else {
      fail(header_line,
           fmt::format("{} and {} are not a real/imaginary or magnitude/phase pair by their names", column_text(a_),
                       column_text(b_)),
           settle);
    }
    // The values' units: from whichever value column gives them; two that disagree are an error.
    for (const std::size_t k : {a_, b_}) {
      const std::string& u = cols[k].value_units;
      if (u.empty()) continue;
      if (!table_.value_units.empty() && table_.value_units != u)
        fail(header_line,
             fmt::format("{} is in '{}' but {} in '{}'", table_.value_units_column, table_.value_units, column_text(k), u),
             "give both value columns the same units");
      table_.value_units = u;
      table_.value_units_column = column_text(k);
    }
    if (coh_ && has_header_ && cols[*coh_].role != Role::Coherence && !o_.columns.empty() && cols[*coh_].role != Role::None)
      fail(header_line,
           fmt::format("{} is the {} by its name, not a coherence", column_text(*coh_), role_name(cols[*coh_].role)));
    // Everything else is reported, not read.
    std::vector<std::string> unused;
    for (std::size_t k = 0; k < columns_; ++k)
      if (k != f_ && k != a_ && k != b_ && (!coh_ || k != *coh_)) unused.push_back(column_text(k));
    if (!unused.empty()) {
      std::string list;
      for (const auto& u : unused) list += (list.empty() ? "" : ", ") + u;
      table_.warnings.push_back(fmt::format("{}: not used: {}", source_, list));
    }
  }

  // Columns by their header names: exactly one frequency; re/im, else magnitude (or dB)/phase;
  // at most one coherence.
  void find_by_name(const std::vector<Column>& cols, std::size_t header_line, const std::string& settle) {
    std::vector<std::size_t> by[8];
    for (std::size_t k = 0; k < cols.size(); ++k) by[static_cast<int>(cols[k].role)].push_back(k);
    auto one = [&](Role r) -> std::optional<std::size_t> {
      const auto& v = by[static_cast<int>(r)];
      if (v.size() > 1)
        fail(header_line,
             fmt::format("{} and {} are both the {} by their names", column_text(v[0]), column_text(v[1]), role_name(r)), settle);
      return v.empty() ? std::nullopt : std::optional<std::size_t>(v[0]);
    };
    const auto f = one(Role::Frequency);
    if (!f)
      fail(header_line, fmt::format("no frequency column in the header '{}'", text::excerpt(lines_.front().text, 120)),
           "name it (frequency_hz, Freq (Hz), Frequency [Hz], …), or " + settle);
    f_ = *f;
    const auto re = one(Role::Real), im = one(Role::Imag), mag = one(Role::Magnitude), db = one(Role::Db), ph = one(Role::Phase);
    coh_ = one(Role::Coherence);
    if (mag && db)
      fail(header_line, fmt::format("{} and {} are both magnitudes (linear and dB)", column_text(*mag), column_text(*db)),
           settle);
    if (re && im) {
      a_ = *re;
      b_ = *im;
    } else if ((mag || db) && ph) {
      a_ = mag ? *mag : *db;
      b_ = *ph;
    } else {
      std::string found;
      for (std::size_t k = 0; k < cols.size(); ++k)
        found += fmt::format("{}{}: {}", k ? ", " : "", column_text(k), role_name(cols[k].role));
      fail(header_line, fmt::format("the header names no real/imaginary or magnitude/phase pair ({})", found),
           "name the columns (re, im; or Magnitude, Phase (deg)), or " + settle);
    }
  }

  double value(const std::vector<Cell>& cells, std::size_t k, std::size_t line) const {
    const std::string_view c = cells[k].text;
    const auto v = number_of(c, decimal_comma_ || cells[k].quoted);
    if (!v)
      fail(line, fmt::format("{} is '{}', not a number{}", column_text(k), text::excerpt(c, 40),
                             c.find(',') != std::string_view::npos && sep_ == ','
                                 ? " (a decimal comma needs ';' or tab between columns)"
                                 : ""));
    if (!std::isfinite(*v))
      fail(line, fmt::format("{} is {}, expected a finite number", column_text(k), text::excerpt(c, 40)),
           "remove or repair the NaN/Inf values in the data");
    return *v;
  }

  std::vector<Cell> row(const Line& l) const {
    std::vector<Cell> cells = split_cells(l.text, sep_);
    if (cells.size() != columns_)
      fail(l.number,
           fmt::format("{} cell(s) separated by {}, the {} has {}", cells.size(), sep_name(),
                       has_header_ ? "header" : "first line", columns_),
           cells.size() > columns_ && sep_ == ','
               ? "a decimal comma with ',' between the columns cannot be read: use ';' or tab between columns"
               : "one value per column on every line");
    return cells;
  }

  // The frequency of a row in Hz; false for a 0 Hz line (dropped).
  bool frequency(const std::vector<Cell>& cells, std::size_t k, std::size_t line, double& f) {
    f = value(cells, k, line) * to_hz_;
    if (f < 0.0) fail(line, fmt::format("frequency {} Hz is negative", f));
    if (f == 0.0) {
      if (zero_lines_++ == 0) first_zero_line_ = line;
      return false;
    }
    if (!(f > last_f_))
      fail(line, fmt::format("frequency {} Hz is not above the previous line's {} Hz", f, last_f_),
           "frequencies must increase strictly, one line per frequency");
    last_f_ = f;
    return true;
  }

  void coherence(const std::vector<Cell>& cells, std::size_t line) {
    if (!coh_) return;
    const double g = value(cells, *coh_, line);
    if (g < 0.0 || g > 1.0 + 1e-9)
      fail(line, fmt::format("{} is {}, but a coherence lies in [0, 1]", column_text(*coh_), g),
           "check the column (coherence is the squared one, γ², between 0 and 1)");
    table_.coherence.push_back(std::min(g, 1.0));
  }

  void read_block() {
    for (std::size_t k = first_data_; k < lines_.size(); ++k) {
      const std::vector<Cell> cells = row(lines_[k]);
      double f = 0.0;
      if (!frequency(cells, 0, lines_[k].number, f)) continue;
      double v[8];
      for (std::size_t c = 0; c < 8; ++c) v[c] = value(cells, c + 1, lines_[k].number);
      table_.block.frequency_hz.push_back(f);
      table_.block.blocks.push_back(make_block({v[0], v[1]}, {v[2], v[3]}, {v[4], v[5]}, {v[6], v[7]}));
      coherence(cells, lines_[k].number);
    }
  }

  void read_single() {
    const FrfValueFormat form = table_.format;
    const bool db = form == FrfValueFormat::DbPhaseDeg || form == FrfValueFormat::DbPhaseRad;
    const bool deg = form == FrfValueFormat::MagPhaseDeg || form == FrfValueFormat::DbPhaseDeg;
    double largest_phase = 0.0;
    for (std::size_t k = first_data_; k < lines_.size(); ++k) {
      const std::size_t line = lines_[k].number;
      const std::vector<Cell> cells = row(lines_[k]);
      double f = 0.0;
      if (!frequency(cells, f_, line, f)) continue;
      const double a = value(cells, a_, line), b = value(cells, b_, line);
      Complex h;
      if (form == FrfValueFormat::ReIm) {
        h = {a, b};
      } else {
        if (!db && a < 0.0)
          fail(line, fmt::format("{} is {}: a linear magnitude cannot be negative", column_text(a_), a),
               "if the magnitudes are in dB, say so in the header ('Magnitude (dB)') or with FrfCsvOptions::format "
               "db-phase");
        const double mag = db ? std::pow(10.0, a / 20.0) : a;
        if (!std::isfinite(mag)) fail(line, fmt::format("{} = {} dB overflows", column_text(a_), a));
        h = std::polar(mag, deg ? radians_of(b) : b);
        largest_phase = std::max(largest_phase, std::abs(b));
      }
      table_.single.frequency_hz.push_back(f);
      table_.single.values.push_back(h);
      coherence(cells, line);
    }
    if (deg) judge_degrees(largest_phase);
  }

  // A phase said to be in degrees (by the header or FrfCsvOptions::format) that stays within ±π
  // although |H| rises to a resonance — an interior maximum at least twice both ends, where the
  // phase of a receptance passes ±90° — is a phase in radians: refused, since read as degrees it
  // would make the FRF nearly real.
  void judge_degrees(double largest_phase) const {
    const std::vector<Complex>& v = table_.single.values;
    if (v.size() < 5 || largest_phase > std::numbers::pi * (1.0 + 1e-9)) return;
    std::size_t top = 0;
    for (std::size_t i = 1; i < v.size(); ++i)
      if (std::abs(v[i]) > std::abs(v[top])) top = i;
    const double ends = std::max(std::abs(v.front()), std::abs(v.back()));
    if (top == 0 || top + 1 == v.size() || !(std::abs(v[top]) >= 2.0 * ends)) return;
    fail(lines_.front().number,
         fmt::format("{} is read in degrees, but every phase lies within ±π (the largest |phase| is {:.4g}) while |H| rises "
                     "{:.3g}-fold to a resonance at {:g} Hz, where a receptance's phase passes 90°: the phases are radians",
                     column_text(b_), largest_phase, std::abs(v[top]) / ends, table_.single.frequency_hz[top]),
         has_header_ && named_degrees_ ? "name the unit in the header: 'Phase (rad)' (or '[rad]')"
                                       : "read them as radians (FrfCsvOptions::format mag-phase-rad or db-phase-rad)");
  }

  const std::string& text_;
  const std::string& source_;
  const FrfCsvOptions& o_;
  std::vector<Line> lines_;
  std::vector<std::string_view> names_;
  char sep_ = ',';
  bool decimal_comma_ = false, has_header_ = false, named_degrees_ = false;
  std::size_t columns_ = 0, first_data_ = 0, f_ = 0, a_ = 1, b_ = 2;
  std::optional<std::size_t> coh_;
  double to_hz_ = 1.0, last_f_ = 0.0;
  std::size_t zero_lines_ = 0, first_zero_line_ = 0;
  FrfTable table_;
};

}  // namespace

std::string frf_value_format_name(FrfValueFormat f) {
  switch (f) {
    case FrfValueFormat::ReIm: return "re-im";
    case FrfValueFormat::MagPhaseDeg: return "mag-phase-deg";
    case FrfValueFormat::MagPhaseRad: return "mag-phase-rad";
    case FrfValueFormat::DbPhaseDeg: return "db-phase";
    case FrfValueFormat::DbPhaseRad: return "db-phase-rad";
  }
  return "?";
}

void FrfCsvOptions::check() const {
  if (!columns.empty() && columns.size() != 3 && columns.size() != 4)
    throw InvalidArgument(fmt::format("FrfCsvOptions::columns has {} entries; give 3 (frequency, value, value) or 4 (and "
                                      "coherence)",
                                      columns.size()),
                          "e.g. 1,2,3 or \"Freq (Hz),Magnitude,Phase (deg)\"");
}

FrfTable parse_frf_csv(const std::string& text, const std::string& source, const FrfCsvOptions& options) {
  return CsvReader(text, source, options).run();
}

}  // namespace toolpoint
