// toolpoint: the TOML text guard and parse (see toml_input.hpp). The guard follows the TOML 1.0
// ABNF for structure only (documents, keys, tables, arrays, inline tables, the four kinds of
// string, bare values) and leaves the meaning of values to toml++.
#include "toml_input.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "text.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

constexpr std::size_t kMaxDepth = 100;  // nested arrays / inline tables (toml++ allows 256)

const char* const kAsciiHint =
    "TOML keys and bare values are ASCII: write numbers without unit text (SI units, e.g. 4.9e-5 for 49 µm), put "
    "text in quotes and remarks after '#'";

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_bare_key_char(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || is_digit(c) || c == '_' || c == '-'; }
bool is_bare_value_char(char c) { return is_bare_key_char(c) || c == '+' || c == '.' || c == ':'; }

class Guard {
 public:
  Guard(std::string_view text, const std::string& source, const std::string& hint) : s_(text), source_(source), hint_(hint) {}

  void run() {
    check_characters();
    if (s_.substr(0, 3) == "\xEF\xBB\xBF") i_ = line_start_ = 3;  // a UTF-8 byte order mark
    while (!eof()) {
      skip_ws();
      if (eof()) break;
      if (at_newline()) {
        newline();
        continue;
      }
      if (peek() == '#') {
        comment();
        continue;
      }
      if (peek() == '[') table_header();
      else key_value(0);
      end_of_line("after a complete key = value or [table] line");
    }
  }

 private:
  // ---- characters ----
  bool eof() const { return i_ >= s_.size(); }
  char peek(std::size_t ahead = 0) const { return i_ + ahead < s_.size() ? s_[i_ + ahead] : '\0'; }
  bool at_newline() const { return peek() == '\n' || (peek() == '\r' && peek(1) == '\n'); }
  void newline() {
    i_ += peek() == '\r' ? 2 : 1;
    ++line_;
    line_start_ = i_;
  }
  void skip_ws() {
    while (!eof() && (peek() == ' ' || peek() == '\t')) ++i_;
  }
  void comment() {
    while (!eof() && !at_newline()) ++i_;
  }
  // Whitespace, comments and newlines: what may stand between the values of an array.
  void skip_ws_comments_newlines() {
    for (;;) {
      skip_ws();
      if (eof()) return;
      if (at_newline()) newline();
      else if (peek() == '#') comment();
      else return;
    }
  }

  // "'x'", "the end of the line", "'µ' (U+00B5)".
  std::string describe(std::size_t at) const {
    if (at >= s_.size()) return "the end of the file";
    const auto c = static_cast<unsigned char>(s_[at]);
    if (c == '\n' || c == '\r') return "the end of the line";
    if (c < 0x80) return fmt::format("'{}'", static_cast<char>(c));
    const std::size_t n = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : 2;
    char32_t cp = c & (n == 2 ? 0x1F : n == 3 ? 0x0F : 0x07);
    for (std::size_t k = 1; k < n && at + k < s_.size(); ++k) cp = (cp << 6) | (static_cast<unsigned char>(s_[at + k]) & 0x3F);
    return fmt::format("'{}' (U+{:04X})", s_.substr(at, n), static_cast<unsigned>(cp));
  }

  [[noreturn]] void fail_at(std::size_t at, const std::string& what, const std::string& hint = {}) const {
    const std::size_t column = text::char_count(s_.substr(line_start_, at - line_start_)) + 1;
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", source_, line_, column, what), hint.empty() ? hint_ : hint);
  }
  // "expected X, saw Y" at the current position; a non-ASCII character gets the ASCII hint.
  [[noreturn]] void expected(const std::string& what) const {
    const bool non_ascii = !eof() && static_cast<unsigned char>(peek()) >= 0x80;
    fail_at(i_, fmt::format("expected {}, saw {}{}", what, describe(i_), non_ascii ? " outside a string or comment" : ""),
            non_ascii ? kAsciiHint : std::string());
  }

  // Valid UTF-8; no control characters but tab and CRLF/LF line ends (TOML 1.0 allows no others
  // anywhere, strings and comments included).
  void check_characters() {
    if (const std::size_t bad = text::invalid_utf8_at(s_); bad != std::string_view::npos) {
      locate(bad);
      fail_at(bad, fmt::format("byte 0x{:02X} is not valid UTF-8", static_cast<unsigned char>(s_[bad])),
              "save the file as UTF-8");
    }
    for (std::size_t k = 0; k < s_.size(); ++k) {
      const auto c = static_cast<unsigned char>(s_[k]);
      const bool control = (c < 0x20 && c != '\t' && c != '\n' && !(c == '\r' && k + 1 < s_.size() && s_[k + 1] == '\n')) ||
                           c == 0x7F;
      if (control) {
        locate(k);
        fail_at(k, fmt::format("control character U+{:04X}", static_cast<unsigned>(c)),
                "remove it: TOML allows only tab, space and line ends as invisible characters");
      }
    }
  }
  // Sets line_ and line_start_ for a position found by a scan.
  void locate(std::size_t at) {
    line_ = 1;
    line_start_ = 0;
    for (std::size_t k = 0; k < at; ++k)
      if (s_[k] == '\n') {
        ++line_;
        line_start_ = k + 1;
      }
  }

  void end_of_line(const char* where) {
    skip_ws();
    if (!eof() && peek() == '#') comment();
    if (eof()) return;
    if (!at_newline()) expected(fmt::format("the end of the line {}", where));
    newline();
  }

  // ---- keys ----
  void simple_key() {
    if (peek() == '"') basic_string();
    else if (peek() == '\'') literal_string();
    else if (!eof() && is_bare_key_char(peek()))
      while (!eof() && is_bare_key_char(peek())) ++i_;
    else expected("a key (letters, digits, '_' and '-', or a quoted name)");
  }
  void key() {
    simple_key();
    for (;;) {
      skip_ws();
      if (peek() != '.') return;
      ++i_;
      skip_ws();
      simple_key();
    }
  }
  void table_header() {
    ++i_;  // '['
    const bool array_of_tables = peek() == '[';
    if (array_of_tables) ++i_;
    skip_ws();
    key();
    skip_ws();
    if (peek() != ']')
      expected(array_of_tables ? "']]' closing the [[array of tables]] header" : "']' closing the [table] header");
    ++i_;
    if (array_of_tables) {
      if (peek() != ']') expected("']]' closing the [[array of tables]] header");
      ++i_;
    }
  }
  void key_value(std::size_t depth) {
    key();
    skip_ws();
    if (peek() != '=') expected("'=' after the key");
    ++i_;
    skip_ws();
    value(depth);
  }

  // ---- values ----
  void value(std::size_t depth) {
    if (depth > kMaxDepth) fail_at(i_, fmt::format("arrays and inline tables nested deeper than {} levels", kMaxDepth));
    if (eof() || at_newline()) expected("a value");
    const char c = peek();
    if (c == '"') {
      if (s_.substr(i_, 3) == "\"\"\"") multiline_string('"');
      else basic_string();
    } else if (c == '\'') {
      if (s_.substr(i_, 3) == "'''") multiline_string('\'');
      else literal_string();
    } else if (c == '[') {
      array(depth);
    } else if (c == '{') {
      inline_table(depth);
    } else {
      bare_value();
    }
  }

  void basic_string() {
    const std::size_t open = i_++;
    while (!eof() && !at_newline() && peek() != '"') {
      if (peek() == '\\') {
        escape_not_followed_by_non_ascii();
        if (i_ + 1 < s_.size() && s_[i_ + 1] != '\n' && s_[i_ + 1] != '\r') ++i_;
      }
      ++i_;
    }
    if (peek() != '"') fail_at(open, "a \"string\" not closed on its line", "close it with '\"' before the end of the line");
    ++i_;
  }
  void literal_string() {
    const std::size_t open = i_++;
    while (!eof() && !at_newline() && peek() != '\'') ++i_;
    if (peek() != '\'') fail_at(open, "a 'string' not closed on its line", "close it with \"'\" before the end of the line");
    ++i_;
  }
  // """…""" or '''…''': up to two quotes may stand right before the closing three.
  void multiline_string(char quote) {
    const std::size_t open = i_, open_line = line_, open_start = line_start_;
    i_ += 3;
    for (;;) {
      if (eof()) {
        line_ = open_line;
        line_start_ = open_start;
        fail_at(open, fmt::format("a multi-line string opened with {0}{0}{0} is never closed", quote));
      }
      if (at_newline()) {
        newline();
      } else if (quote == '"' && peek() == '\\') {
        std::size_t k = 1;
        while (peek(k) == ' ' || peek(k) == '\t') ++k;
        if (peek(k) == '\n' || (peek(k) == '\r' && peek(k + 1) == '\n')) {
          line_ending_backslash(k);
        } else {
          escape_not_followed_by_non_ascii();
          i_ += 2;
        }
      } else if (peek() == quote) {
        std::size_t run = 0;
        while (peek(run) == quote) ++run;
        i_ += run;
        if (run >= 3) {
          if (run > 5) fail_at(i_ - run, fmt::format("{} quotes in a row closing a multi-line string (at most 5)", run));
          return;
        }
      } else {
        ++i_;
      }
    }
  }

  // An escape is a backslash and ASCII (\n, \u00B5, …). toml++ 3.3.0 tests what follows a
  // backslash (after blanks) with a whitespace function that reaches __builtin_unreachable for
  // most non-ASCII characters, so "\µ" must not reach it (it is no valid escape anyway).
  void escape_not_followed_by_non_ascii() const {
    std::size_t k = 1;
    while (peek(k) == ' ' || peek(k) == '\t') ++k;
    if (static_cast<unsigned char>(peek(k)) >= 0x80)
      fail_at(i_, fmt::format("'\\' followed by {} is not an escape sequence", describe(i_ + k)),
              "escapes are \\\" \\\\ \\b \\f \\n \\r \\t \\uXXXX \\UXXXXXXXX; write a backslash as \\\\");
  }

  // A backslash ending a line of a """string""" trims the whitespace and line ends after it.
  // toml++ 3.3.0 tests the first other character with a whitespace function that reaches
  // __builtin_unreachable for most code points in U+00A0–U+FEFF, so such a character is refused
  // there (the one case of valid TOML the guard refuses).
  void line_ending_backslash(std::size_t spaces) {
    i_ += spaces;  // the backslash and the blanks after it
    for (;;) {
      if (at_newline()) newline();
      else if (peek() == ' ' || peek() == '\t') ++i_;
      else break;
    }
    const std::string_view head = s_.substr(i_, 3);  // UTF-8 orders as the code points do
    if (head >= std::string_view("\xC2\xA0") && head <= std::string_view("\xEF\xBB\xBF"))
      fail_at(i_, fmt::format("{} right after a line-ending backslash in a multi-line string", describe(i_)),
              "start the continued text with an ASCII character (the TOML library mishandles this case), or join the lines");
  }

  void array(std::size_t depth) {
    ++i_;  // '['
    for (;;) {
      skip_ws_comments_newlines();
      if (peek() == ']') break;
      value(depth + 1);
      skip_ws_comments_newlines();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() != ']') expected("',' or ']' in the array");
      break;
    }
    ++i_;
  }

  void inline_table(std::size_t depth) {
    ++i_;  // '{'
    skip_ws();
    if (peek() == '}') {
      ++i_;
      return;
    }
    for (;;) {
      key_value(depth + 1);
      skip_ws();
      if (peek() == ',') {
        ++i_;
        skip_ws();
        continue;
      }
      if (peek() != '}') expected("',' or '}' in the inline table (which stays on one line)");
      ++i_;
      return;
    }
  }

  // Numbers, booleans, inf/nan, dates and times: a run of [A-Za-z0-9_+-.:] that starts like one
  // of them. A date (YYYY-MM-DD) then ' ' and a digit continues as a date-time; a date then 'T'
  // must go on with the time's digits.
  void bare_value() {
    const char c = peek();
    if (!(is_digit(c) || c == '+' || c == '-' || c == 't' || c == 'f' || c == 'i' || c == 'n'))
      expected("a value (a number, true/false, a \"string\", [array] or {inline table})");
    const std::size_t start = i_;
    while (!eof() && is_bare_value_char(peek())) ++i_;
    const std::string_view token = s_.substr(start, i_ - start);
    const bool date = token.size() >= 10 && token[4] == '-' && token[7] == '-' &&
                      std::all_of(token.begin(), token.begin() + 10, [](char d) { return is_digit(d) || d == '-'; });
    if (date && token.size() == 10 && peek() == ' ' && is_digit(peek(1))) {
      // toml++ reads on past the first digit of the time without checking for the end of the value.
      if (!is_bare_value_char(peek(2)))
        fail_at(i_ + 2, fmt::format("a date-time needs the time (HH:MM:SS) after the space, saw {}", describe(i_ + 2)));
      ++i_;
      while (!eof() && is_bare_value_char(peek())) ++i_;
    } else if (date && token.size() > 10 && (token[10] == 'T' || token[10] == 't') &&
               (token.size() == 11 || !is_digit(token[11]))) {
      fail_at(start + 11,
              fmt::format("a date-time needs the time (HH:MM:SS) after '{}', saw {}", token[10], describe(start + 11)));
    }
  }

  std::string_view s_;
  const std::string& source_;
  const std::string& hint_;
  std::size_t i_ = 0, line_ = 1, line_start_ = 0;
};

}  // namespace

void check_toml_text(std::string_view text, const std::string& source, const std::string& hint) {
  Guard(text, source, hint).run();
}

toml::table parse_toml(std::string_view text, const std::string& source, const std::string& hint) {
  check_toml_text(text, source, hint);
  try {
    return toml::parse(text, std::string(source));
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", source, e.source().begin.line, e.source().begin.column,
                                 e.description()),
                     hint);
  }
}

}  // namespace toolpoint
