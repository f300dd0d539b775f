// toolpoint CLI: text parsers for option values (parse.hpp).
#include "parse.hpp"

#include <charconv>
#include <fmt/format.h>
#include <initializer_list>
#include <map>
#include <string_view>
#include <utility>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/studies/shards.hpp"

namespace toolpoint::cli {

namespace {

double parse_number(const std::string& text, const std::string& option, const std::string& whole) {
  double v = 0.0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  while (first < last && *first == ' ') ++first;
  while (last > first && last[-1] == ' ') --last;
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || first == last)
    throw InvalidArgument(fmt::format("{}: '{}' in '{}' is not a number", option, text, whole));
  return v;
}

std::vector<std::string> split_colon(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    std::size_t pos = text.find(':', start);
    parts.push_back(text.substr(start, pos - start));
    if (pos == std::string::npos) break;
    start = pos + 1;
  }
  return parts;
}

// One of `names` (case and surrounding blanks ignored), or InvalidArgument "OPTION 'TEXT' is not WHAT".
template <class E>
E parse_name(const std::string& text, const std::string& option, std::initializer_list<std::pair<std::string_view, E>> names,
             const char* what, const char* hint) {
  const std::string s = option_word(text);
  for (const auto& [name, value] : names)
    if (s == name) return value;
  throw InvalidArgument(fmt::format("{} '{}' is not {}", option, text, what), hint);
}

}  // namespace

std::string option_word(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  std::string out(text);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

FrequencyGrid parse_frequency_grid(const std::string& text, const std::string& option) {
  const auto parts = split_colon(text);
  if (parts.size() != 3)
    throw InvalidArgument(fmt::format("{}: '{}' is not START:STOP:STEP (Hz)", option, text), "e.g. 10:5000:2.5");
  FrequencyGrid g{parse_number(parts[0], option, text), parse_number(parts[1], option, text),
                  parse_number(parts[2], option, text)};
  try {
    g.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("{}: {}", option, e.what()), e.hint());
  }
  return g;
}

double parse_value(const std::string& text, const std::string& option) { return parse_number(text, option, text); }

std::pair<double, double> parse_range(const std::string& text, const std::string& option) {
  const auto parts = split_colon(text);
  if (parts.size() != 2) throw InvalidArgument(fmt::format("{}: '{}' is not A:B", option, text));
  return {parse_number(parts[0], option, text), parse_number(parts[1], option, text)};
}

double parse_fraction(const std::string& text, const std::string& option) {
  std::string t = text;
  while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
  const bool percent = !t.empty() && t.back() == '%';
  if (percent) t.pop_back();
  double v = 0.0;
  std::size_t used = 0;
  try {
    v = std::stod(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  while (used < t.size() && std::isspace(static_cast<unsigned char>(t[used]))) ++used;
  if (t.empty() || used != t.size() || !std::isfinite(v) || v < 0.0)
    throw InvalidArgument(fmt::format("{} '{}' is not a fraction ≥ 0", option, text),
                          fmt::format("write e.g. {} 2% or {} 0.02", option, option));
  return percent ? v / 100.0 : v;
}

std::pair<int, int> parse_shard(const std::string& text, const std::string& option) {
  const std::size_t slash = text.find('/');
  int v[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const char* first = text.data() + (k == 0 ? 0 : slash + 1);
    const char* last = text.data() + (k == 0 ? slash : text.size());
    if (slash == std::string::npos) break;
    const auto [ptr, ec] = std::from_chars(first, last, v[k]);
    if (ec != std::errc() || ptr != last || first == last) {
      v[1] = 0;
      break;
    }
  }
  if (slash == std::string::npos || v[1] < 1 || v[1] > kMaxShards || v[0] < 0)
    throw InvalidArgument(fmt::format("{} '{}' is not I/N with 0 ≤ I < N ≤ {} (shard I of N, counted from 0)", option, text,
                                      kMaxShards),
                          "e.g. --shard 0/8 … --shard 7/8; in a Slurm array --shard $SLURM_ARRAY_TASK_ID/8");
  try {
    check_shard({v[0], v[1]});  // I ≥ N: which, and the array numbered from 1
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(
        fmt::format("{} '{}' (0 ≤ I < N): {}", option, text, e.what()),
        v[0] == v[1] ? fmt::format("submit the array as --array=0-{} (sbatch), or pass --shard $((SLURM_ARRAY_TASK_ID-1))/{} "
                                   "to an array numbered from 1",
                                   v[1] - 1, v[1])
                     : e.hint());
  }
  return {v[0], v[1]};
}

FrfUnits parse_frf_units_option(const std::string& text, const std::string& option) {
  if (const auto u = parse_frf_units(text)) return *u;
  throw InvalidArgument(fmt::format("{} '{}' are not FRF units toolpoint knows", option, text),
                        "use m/N, mm/N, um/N (receptance); m/s/N, mm/s/N (mobility); m/s^2/N, g/N (accelerance); "
                        "force N, kN or lbf, e.g. in/lbf");
}

FrfFormat parse_frf_format(const std::string& text, const std::string& option) {
  return parse_name<FrfFormat>(text, option,
                               {{"auto", FrfFormat::Auto},
                                {"csv", FrfFormat::Csv},
                                {"uff", FrfFormat::Uff},
                                {"unv", FrfFormat::Uff},
                                {"uf", FrfFormat::Uff},
                                {"uffb", FrfFormat::UffBinary},
                                {"uff-binary", FrfFormat::UffBinary},
                                {"58b", FrfFormat::UffBinary},
                                {"frf", FrfFormat::Frf},
                                {"cutpro", FrfFormat::Frf}},
                               "a known FRF file format",
                               "use csv, uff (ASCII dataset 58), uffb (binary 58b) or frf (CutPro text)");
}

FrfOrdinate parse_frf_ordinate(const std::string& text, const std::string& option) {
  return parse_name<FrfOrdinate>(text, option,
                                 {{"receptance", FrfOrdinate::Receptance},
                                  {"compliance", FrfOrdinate::Receptance},
                                  {"mobility", FrfOrdinate::Mobility},
                                  {"accelerance", FrfOrdinate::Accelerance},
                                  {"inertance", FrfOrdinate::Accelerance}},
                                 "an FRF ordinate", "use receptance (m/N), mobility ((m/s)/N) or accelerance ((m/s²)/N)");
}

FrfValueFormat parse_frf_value_format(const std::string& text, const std::string& option) {
  return parse_name<FrfValueFormat>(text, option,
                                    {{"re-im", FrfValueFormat::ReIm},
                                     {"reim", FrfValueFormat::ReIm},
                                     {"mag-phase-deg", FrfValueFormat::MagPhaseDeg},
                                     {"mag-phase-rad", FrfValueFormat::MagPhaseRad},
                                     {"db-phase", FrfValueFormat::DbPhaseDeg},
                                     {"db-phase-deg", FrfValueFormat::DbPhaseDeg},
                                     {"db-phase-rad", FrfValueFormat::DbPhaseRad}},
                                    "a value format",
                                    "use re-im, mag-phase-deg, mag-phase-rad, db-phase (dB and degrees) or db-phase-rad");
}

Interpolation parse_interpolation(const std::string& text, const std::string& option) {
  return parse_name<Interpolation>(
      text, option, {{"linear", Interpolation::Linear}, {"cubic", Interpolation::Cubic}, {"spline", Interpolation::Cubic}},
      "an interpolation", "use linear (no overshoot) or cubic (natural cubic spline)");
}

int parse_uff_direction(const std::string& text, const std::string& option) {
  std::string s = option_word(text);
  // A code: an integer with an optional sign.
  const char* first = s.data() + (!s.empty() && s.front() == '+' ? 1 : 0);
  const char* last = s.data() + s.size();
  long long code = 0;
  if (const auto [ptr, ec] = std::from_chars(first, last, code); first != last && ec == std::errc() && ptr == last) {
    if (code < -6 || code > 6)
      throw InvalidArgument(fmt::format("{} {}: a UFF direction code is −6..6", option, code),
                            "0 scalar, 1/2/3 +X/+Y/+Z, 4/5/6 +RX/+RY/+RZ, negative for the minus directions");
    return static_cast<int>(code);
  }
  if (s == "scalar" || s == "s") return 0;
  int sign = 1;
  if (!s.empty() && (s.front() == '+' || s.front() == '-')) {
    sign = s.front() == '-' ? -1 : 1;
    s.erase(0, 1);
  } else if (!s.empty() && (s.back() == '+' || s.back() == '-')) {
    sign = s.back() == '-' ? -1 : 1;
    s.pop_back();
  }
  static const std::map<std::string, int> names = {{"x", 1}, {"y", 2}, {"z", 3}, {"rx", 4}, {"ry", 5}, {"rz", 6}};
  const auto it = names.find(s);
  if (it == names.end())
    throw InvalidArgument(fmt::format("{} '{}' is not a UFF direction", option, text),
                          "give +X, -Y, Z, +RZ, scalar, or a code −6..6");
  return sign * it->second;
}

}  // namespace toolpoint::cli
