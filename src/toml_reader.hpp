// toolpoint (internal): reading TOML files with toml++ — the assembly file, joint files — with
// file:line in every message, strict keys (the nearest valid key suggested) and warnings for
// values implausible in SI units.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <fmt/format.h>
#include <optional>
#include <string>
#include <toml++/toml.h>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/model/joint.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/plausibility.hpp"
#include "toml_input.hpp"

namespace toolpoint {

// parse_toml (TOML text, guarded, errors as InputError "source:line:column: …" with a hint) is
// in toml_input.hpp.

inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// Reads values out of the TOML tree with file:line in every message.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  std::string where(const toml::node& n) const {
    const auto& src = n.source();
    return src.begin.line ? fmt::format("{}:{}", source_, src.begin.line) : source_;
  }

  [[noreturn]] void fail(const toml::node& n, const std::string& what, const std::string& hint = {}) const {
    throw InputError(fmt::format("{}: {}", where(n), what), hint);
  }

  // Only `allowed` keys may appear in `t`; anything else is an error with the nearest valid key.
  void only(const toml::table& t, const std::string& path, std::initializer_list<const char*> allowed) const {
    only(t, path, std::vector<const char*>(allowed));
  }
  void only(const toml::table& t, const std::string& path, const std::vector<const char*>& allowed) const {
    for (auto&& [k, v] : t) {
      const std::string key(k.str());
      if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }) != allowed.end()) continue;
      std::string best;
      std::size_t best_d = 99;
      for (const char* a : allowed) {
        const std::size_t d = edit_distance(key, a);
        if (d < best_d) {
          best_d = d;
          best = a;
        }
      }
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(v, fmt::format("unknown key '{}{}'", path.empty() ? "" : path + ".", key),
           best_d <= 3 ? fmt::format("did you mean '{}'? valid keys here: {}", best, list)
                       : fmt::format("valid keys here: {}", list));
    }
  }

  const toml::table* table(const toml::table& t, const char* key, const std::string& path, bool required) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) fail(t, fmt::format("missing table [{}{}]", path.empty() ? "" : path + ".", key));
      return nullptr;
    }
    if (!n->is_table()) fail(*n, fmt::format("'{}' must be a table ([{}])", join(path, key), join(path, key)));
    return n->as_table();
  }

  std::optional<double> number(const toml::table& t, const char* key, const std::string& path, const char* unit) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    double v;
    if (auto i = n->as_integer()) {
      v = static_cast<double>(i->get());
    } else if (auto f = n->as_floating_point()) {
      v = f->get();
    } else {
      fail(*n, fmt::format("{} must be a number in {}", join(path, key), unit),
           n->is_string() ? "write the bare number in SI units, without quotes or unit text" : "");
    }
    if (!std::isfinite(v)) fail(*n, fmt::format("{} = {} is not a finite number", join(path, key), v));
    return v;
  }

  // A number or an array of numbers (one number: a list of one).
  std::optional<std::vector<double>> numbers(const toml::table& t, const char* key, const std::string& path,
                                             const char* unit) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_array()) return std::vector<double>{*number(t, key, path, unit)};
    std::vector<double> out;
    for (const toml::node& e : *n->as_array()) {
      const auto i = e.as_integer();
      const auto f = e.as_floating_point();
      if (!i && !f)
        fail(e, fmt::format("{} must be a list of numbers in {}", join(path, key), unit),
             "write the bare numbers in SI units, e.g. [0.5, 0.6], without quotes or unit text");
      out.push_back(i ? static_cast<double>(i->get()) : f->get());
      if (!std::isfinite(out.back())) fail(e, fmt::format("{} holds {}, not a finite number", join(path, key), out.back()));
    }
    if (out.empty()) fail(*n, fmt::format("{} is an empty list", join(path, key)), "give the numbers, or leave the key out");
    return out;
  }

  double required_number(const toml::table& t, const char* key, const std::string& path, const char* unit) const {
    auto v = number(t, key, path, unit);
    if (!v) fail(t, fmt::format("missing key {} (a number in {})", join(path, key), unit));
    return *v;
  }

  std::optional<std::string> string(const toml::table& t, const char* key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_string()) fail(*n, fmt::format("{} must be a string", join(path, key)));
    return n->as_string()->get();
  }

  std::optional<bool> boolean(const toml::table& t, const char* key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_boolean()) fail(*n, fmt::format("{} must be true or false", join(path, key)));
    return n->as_boolean()->get();
  }

  // A value outside its usual range in SI units (e.g. a length given in mm): a warning; so far
  // outside that it cannot be meant: an error at its line (plausibility.hpp, the CLI's rule too).
  void plausible(const toml::table& t, const char* key, const std::string& path, double v, const PlausibleRange& range) {
    if (v == 0.0) return;
    const Plausibility p = judge(range, v);
    if (p == Plausibility::Usual) return;
    const toml::node* n = t.get(key);
    const std::string message = plausibility_message(range, v, join(path, key));
    if (p == Plausibility::Impossible && n) fail(*n, message, fmt::format("correct the value: {}", range.hint));
    warnings.push_back(fmt::format("{}: {}", n ? where(*n) : source_, message));
  }

  static std::string join(const std::string& path, const char* key) { return path.empty() ? key : path + "." + key; }

  std::vector<std::string> warnings;

 private:
  std::string source_;
};

// A joint's table: `rigid = true`, or the eight parameters (k_θf, c_θf default to k_ym, c_ym: a
// reciprocal joint needs six). `t` null: rigid (the table is absent). A joint file's [joint]
// (`joint_file`) has the key `interface` and no `rigid`.
Joint read_joint_table(Reader& r, const toml::table* t, const std::string& path, bool joint_file = false);

// The keys of a table that are option fields (option_fields.hpp: each field's plan_key, in the
// table's order), for Reader::only.
template <class Options>
std::vector<const char*> field_keys(const std::vector<OptionField<Options>>& fields) {
  std::vector<const char*> keys;
  for (const OptionField<Options>& f : fields)
    if (f.spec.plan_key) keys.push_back(f.spec.plan_key);
  return keys;
}

// Each option field whose plan_key `t` holds, read into `o`: a flag true or false, a number in the
// field's unit and range (an integer a whole number; the automatic value is the key's absence),
// failing at the key with the range and the field's help; then judged plausible (FieldSpec::
// plausible: a warning, or refused at the key when it cannot be meant).
template <class Options>
void read_fields(Reader& r, const toml::table& t, const std::string& path, const std::vector<OptionField<Options>>& fields,
                 Options& o) {
  for (const OptionField<Options>& f : fields) {
    const FieldSpec& s = f.spec;
    const toml::node* n = s.plan_key ? t.get(s.plan_key) : nullptr;
    if (!n) continue;
    const std::string key = Reader::join(path, s.plan_key);
    if (s.kind == FieldKind::Flag) {
      if (!n->is_boolean()) r.fail(*n, fmt::format("{} must be true or false", key), fmt::format("{}: {}", key, s.help));
      f.set(o, n->as_boolean()->get() ? 1.0 : 0.0);
      continue;
    }
    const bool integer = s.kind == FieldKind::Integer;
    const double v = *r.number(t, s.plan_key, path, *s.unit ? s.unit : integer ? "(count)" : "(fraction)");
    FieldSpec range = s;
    range.automatic = std::numeric_limits<double>::quiet_NaN();  // not written in a file: the key left out
    if (!field_value_valid(range, v))
      r.fail(*n,
             fmt::format("{} = {} {}{}", key, field_value_text(s, v),
                         integer ? "must be an integer in " + field_range_text(s) : field_range_phrase(s),
                         *s.unit ? fmt::format(" {}", s.unit) : std::string()),
             fmt::format("{}: {}", key, s.help));
    if (s.plausible) r.plausible(t, s.plan_key, path, v, *s.plausible);
    f.set(o, v);
  }
}

}  // namespace toolpoint
