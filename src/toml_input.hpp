// toolpoint (internal): TOML text in, a toml++ table out, every problem an InputError naming
// file:line:column. Every TOML file toolpoint reads (assembly, joint, study files) goes through
// parse_toml, never straight through toml::parse (toml_reader.hpp, the readers' helpers, includes
// this header).
//
// Why a guard before toml++: Debian's toml++ 3.3.0 reaches __builtin_unreachable (undefined
// behaviour) on a non-ASCII character where whitespace may stand (`overhang = 49 µm`), and its
// internal assertions — assumptions (__builtin_assume) in a release build — fail on inputs such as
// `[%`, `y=1979-05-27T:` and `a=[}`. The guard checks the text's structure first, as TOML 1.0
// defines it, and refuses what is not TOML with the line and column, so toml++ only ever sees
// text whose lexical structure is valid: UTF-8 without control characters, non-ASCII only inside
// strings and comments, keys where keys go, values where values go (strings, arrays, inline
// tables, bare values of [A-Za-z0-9_+-.:] that start like a number, a boolean, inf or nan), and a
// date followed by 'T' only with a time. It never refuses valid TOML 1.0; what it lets through
// that is still invalid (a bad number, a duplicate key) is toml++'s to report.
#pragma once

#include <string>
#include <string_view>

#include <toml++/toml.h>

namespace toolpoint {

// The guard alone. Throws InputError "source:line:column: TOML syntax error: what", with `hint`
// (how to fix it, e.g. which example file shows the format) unless the guard has a better one.
void check_toml_text(std::string_view text, const std::string& source, const std::string& hint);

// The guard, then toml::parse; toml++'s parse errors become the same InputError.
toml::table parse_toml(std::string_view text, const std::string& source, const std::string& hint);

}  // namespace toolpoint
