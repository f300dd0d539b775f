// toolpoint: measured FRF files in any supported format (see frf_file.hpp).
#include "toolpoint/io/frf_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/plausibility.hpp"
#include "toolpoint/io/io.hpp"
#include "text.hpp"

namespace toolpoint {

namespace {

using text::cut;
using text::lower;
using text::trim;

// Units labels that are clearly not SI: a file without a units dataset that says "g" or "mm"
// would otherwise be read silently a factor 9.81 or 1000 off.
std::optional<std::string> non_si_token(const std::string& label) {
  static const std::set<std::string> bad = {"g",  "mm",  "cm",  "um", "µm", "in",  "inch", "ft",
                                            "lb", "lbf", "kgf", "mN", "kN", "ips", "mil",  "mils"};
  std::string token;
  for (std::size_t i = 0; i <= label.size(); ++i) {
    const char c = i < label.size() ? label[i] : ' ';
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || u >= 0x80) {
      token += c;
    } else {
      if (bad.count(token)) return token;
      token.clear();
    }
  }
  return std::nullopt;
}

// ---- units -----------------------------------------------------------------------------------

constexpr double kStandardGravity = 9.80665;     // m/s² per g (CGPM 1901)
constexpr double kPoundForce = 4.4482216152605;  // N per lbf
constexpr double kInch = 0.0254;                 // m per inch

// Lower case, no blanks or brackets or product signs; µ/μ → u, ² → ^2, ** → ^, "sec" → "s".
std::string normalise_units(std::string_view in) {
  std::string s;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const auto c = static_cast<unsigned char>(in[i]);
    const std::string_view rest = in.substr(i);
    if (rest.substr(0, 2) == "\xC2\xB5" || rest.substr(0, 2) == "\xCE\xBC") {  // µ, μ
      s += 'u';
      ++i;
    } else if (rest.substr(0, 2) == "\xC2\xB2") {  // ²
      s += "^2";
      ++i;
    } else if (rest.substr(0, 2) == "\xC2\xB7") {  // ·
      ++i;
    } else if (rest.substr(0, 2) == "**") {
      s += '^';
      ++i;
    } else if (c == ' ' || c == '\t' || c == '[' || c == ']' || c == '*') {
    } else {
      s += static_cast<char>(std::tolower(c));
    }
  }
  for (std::size_t at; (at = s.find("sec")) != std::string::npos;) s.erase(at + 1, 2);  // "sec" → "s"
  return s;
}

std::optional<double> force_factor(const std::string& f) {
  if (f == "n") return 1.0;
  if (f == "kn") return 1e3;
  if (f == "mn") return 1e-3;
  if (f == "lbf" || f == "lb") return kPoundForce;
  return std::nullopt;
}

// The response part of FRF units: a length (receptance), a length per second (mobility), per
// second squared or g (accelerance), with its factor to SI.
std::optional<std::pair<FrfOrdinate, double>> response_units(std::string n) {
  if (n.size() >= 2 && n.front() == '(' && n.back() == ')') n = n.substr(1, n.size() - 2);
  if (n == "g") return std::pair{FrfOrdinate::Accelerance, kStandardGravity};
  if (n == "ips") return std::pair{FrfOrdinate::Mobility, kInch};
  static const std::pair<const char*, double> lengths[] = {{"m", 1.0},   {"mm", 1e-3},  {"um", 1e-6},   {"nm", 1e-9},
                                                           {"cm", 1e-2}, {"in", kInch}, {"inch", kInch}};
  for (const auto& [name, f] : lengths) {
    const std::string l(name);
    if (n == l) return std::pair{FrfOrdinate::Receptance, f};
    if (n == l + "/s") return std::pair{FrfOrdinate::Mobility, f};
    if (n == l + "/s^2" || n == l + "/s2" || n == l + "/s/s") return std::pair{FrfOrdinate::Accelerance, f};
  }
  return std::nullopt;
}

// SI units of an ordinate, as a label.
std::string si_label(FrfOrdinate o) { return frf_ordinate_units(o); }

// What the values are and their factor: the user's units, else the file's, else the user's
// ordinate in SI, else SI receptance. `where` names what stated the file's units.
FrfUnits resolve_units(const std::optional<FrfUnits>& file_units, const std::string& where, const FrfReadOptions& o,
                       std::vector<std::string>& warnings) {
  if (o.units) {
    if (file_units && !(*file_units == *o.units))
      warnings.push_back(fmt::format("{} says the values are in '{}' ({}); the units given, '{}' ({}), are used", where,
                                     file_units->label, frf_ordinate_name(file_units->ordinate), o.units->label,
                                     frf_ordinate_name(o.units->ordinate)));
    return *o.units;
  }
  if (file_units) {
    if (o.ordinate && *o.ordinate != file_units->ordinate) {
      warnings.push_back(
          fmt::format("{} says the values are in '{}' ({}); the ordinate given, {}, is used, in SI units "
                      "({})",
                      where, file_units->label, frf_ordinate_name(file_units->ordinate), frf_ordinate_name(*o.ordinate),
                      si_label(*o.ordinate)));
      return {*o.ordinate, 1.0, si_label(*o.ordinate)};
    }
    return *file_units;
  }
  const FrfOrdinate ord = o.ordinate.value_or(FrfOrdinate::Receptance);
  return {ord, 1.0, si_label(ord)};
}

// The values scaled to SI, with a warning saying so when the factor is not 1.
void scale_to_si(FrfSeries& s, const FrfUnits& u, const std::string& what, std::vector<std::string>& warnings) {
  if (u.to_si == 1.0) return;
  for (auto& v : s.values) v *= u.to_si;
  warnings.push_back(fmt::format("{}: values in '{}' converted to SI ({}): × {}", what, u.label, si_label(u.ordinate), u.to_si));
}

std::string uff_what(const std::string& source, const UffDataset58& d) {
  return fmt::format("{}: dataset 58 #{} ('{}')", source, d.index, cut(d.id[0], 40));
}

}  // namespace

std::string frf_format_name(FrfFormat f) {
  switch (f) {
    case FrfFormat::Auto: return "auto";
    case FrfFormat::Csv: return "csv";
    case FrfFormat::Uff: return "uff";
    case FrfFormat::UffBinary: return "uffb";
    case FrfFormat::Frf: return "frf";
  }
  return "?";
}

FrfFormat frf_format_of_path(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext == ".csv") return FrfFormat::Csv;
  if (ext == ".uff" || ext == ".unv" || ext == ".uf") return FrfFormat::Uff;
  if (ext == ".frf") return FrfFormat::Frf;
  throw InvalidArgument(fmt::format("{}: cannot tell the FRF file format from the extension '{}'", path, ext),
                        "use .csv, .uff/.unv/.uf or .frf, or name the format (FrfReadOptions::format: csv, uff or frf)");
}

std::string frf_ordinate_name(FrfOrdinate o) {
  switch (o) {
    case FrfOrdinate::Receptance: return "receptance";
    case FrfOrdinate::Mobility: return "mobility";
    case FrfOrdinate::Accelerance: return "accelerance";
  }
  return "?";
}

std::string frf_ordinate_units(FrfOrdinate o) {
  switch (o) {
    case FrfOrdinate::Receptance: return "m/N";
    case FrfOrdinate::Mobility: return "(m/s)/N";
    case FrfOrdinate::Accelerance: return "(m/s^2)/N";
  }
  return "?";
}

namespace {

// Products some analysers write, "(1/N)*(m/s²)" or "(m/s²)*(1/N)" (normalised: no '*', no
// spaces), and "(m/s^2)/(N)", as "m/s^2/N".
std::string quotient_form(std::string n) {
  const auto unwrap = [](std::string_view v) {
    return v.size() >= 2 && v.front() == '(' && v.back() == ')' ? std::string(v.substr(1, v.size() - 2)) : std::string(v);
  };
  if (const std::size_t mid = n.find(")("); mid != std::string::npos && n.front() == '(' && n.back() == ')') {
    const std::string a = unwrap(std::string_view(n).substr(0, mid + 1)), b = unwrap(std::string_view(n).substr(mid + 1));
    if (a.rfind("1/", 0) == 0) return b + "/" + a.substr(2);
    if (b.rfind("1/", 0) == 0) return a + "/" + b.substr(2);
  }
  if (const std::size_t mid = n.find(")/("); mid != std::string::npos && n.front() == '(' && n.back() == ')')
    return unwrap(std::string_view(n).substr(0, mid + 1)) + "/" + unwrap(std::string_view(n).substr(mid + 2));
  return n;
}

}  // namespace

std::optional<FrfUnits> parse_frf_units(std::string_view text) {
  const std::string n = quotient_form(normalise_units(text));
  const std::size_t slash = n.rfind('/');
  if (slash == std::string::npos) return std::nullopt;
  const auto force = force_factor(n.substr(slash + 1));
  if (!force) return std::nullopt;
  const auto response = response_units(n.substr(0, slash));
  if (!response) return std::nullopt;
  return FrfUnits{response->first, response->second / *force, std::string(trim(text))};
}

std::optional<FrfUnits> uff_label_units(const std::string& numerator, const std::string& denominator) {
  if (const auto whole = parse_frf_units(numerator)) return whole;
  const auto response = response_units(normalise_units(numerator));
  if (!response) return std::nullopt;
  const std::string d = normalise_units(denominator);
  const auto force = d.empty() || d == "none" ? std::optional<double>(1.0) : force_factor(d);
  if (!force) return std::nullopt;
  const std::string den = d.empty() || d == "none" ? std::string("N") : std::string(trim(denominator));
  return FrfUnits{response->first, response->second / *force, fmt::format("{}/{}", trim(numerator), den)};
}

std::optional<FrfOrdinate> uff_ordinate_kind(const UffDataset58& d) {
  if (d.denominator.data_type != 13 && d.denominator.data_type != 0) return std::nullopt;
  switch (d.ordinate.data_type) {
    case 8: return FrfOrdinate::Receptance;
    case 11: return FrfOrdinate::Mobility;
    case 12: return FrfOrdinate::Accelerance;
    default: return std::nullopt;
  }
}

FrfSeries to_receptance(const FrfSeries& s, FrfOrdinate ordinate, std::vector<std::string>& warnings, const std::string& what) {
  FrfSeries out;
  out.frequency_hz.reserve(s.size());
  out.values.reserve(s.size());
  std::size_t dropped = 0;
  const Complex i_unit(0.0, 1.0);
  for (std::size_t k = 0; k < s.size() && k < s.values.size(); ++k) {
    const double f = s.frequency_hz[k];
    if (f == 0.0) {
      ++dropped;
      continue;
    }
    const double w = omega_of(f);
    Complex h = s.values[k];
    if (ordinate == FrfOrdinate::Mobility) h = h / (i_unit * w);
    else if (ordinate == FrfOrdinate::Accelerance) h = h / (-w * w);
    out.frequency_hz.push_back(f);
    out.values.push_back(h);
  }
  if (dropped > 0)
    warnings.push_back(
        fmt::format("{}: {} point(s) at 0 Hz dropped: {}", what, dropped,
                    ordinate == FrfOrdinate::Receptance
                        ? "an FRF series needs frequencies above 0 Hz"
                        : fmt::format("{} cannot be converted to receptance at ω = 0 (division by {})",
                                      frf_ordinate_name(ordinate), ordinate == FrfOrdinate::Mobility ? "iω" : "−ω²")));
  return out;
}

UffReceptance uff_receptance(const UffDataset58& d, std::optional<FrfOrdinate> ordinate, const std::string& source,
                             const std::optional<FrfUnits>& units) {
  UffReceptance r;
  const std::string what = uff_what(source, d);
  const std::string list_hint = fmt::format("pick an FRF among the datasets 58 of {} (UffFile::functions)", source);
  if (d.function_type == 0)
    r.warnings.push_back(fmt::format("{}: record 6 function type 0 (general or unknown); taken as an FRF", what));
  else if (d.function_type != 4)
    throw InputError(fmt::format("{}: record 6 function type {} ({}), expected 4 (frequency response function)", what,
                                 d.function_type, uff_function_type_name(d.function_type)),
                     list_hint);
  if (d.abscissa.data_type == 0)
    r.warnings.push_back(
        fmt::format("{}: record 8 abscissa data type 0 (unknown, units label '{}'); taken as frequency "
                    "in Hz",
                    what, d.abscissa.units));
  else if (d.abscissa.data_type != 18)
    throw InputError(fmt::format("{}: record 8 abscissa data type {} ({}), expected 18 (frequency, Hz)", what,
                                 d.abscissa.data_type, uff_data_type_name(d.abscissa.data_type)),
                     list_hint);
  if (units && ordinate && units->ordinate != *ordinate)
    throw InvalidArgument(fmt::format("units '{}' are {}, but the ordinate given is {}", units->label,
                                      frf_ordinate_name(units->ordinate), frf_ordinate_name(*ordinate)),
                          "give one of them, or both alike");
  const auto stated = uff_ordinate_kind(d);
  const auto labelled = uff_label_units(d.ordinate.units, d.denominator.units);
  const std::string codes =
      fmt::format("record 9 ordinate data type {} ({}, units '{}') over record 10 data type {} ({}, units '{}')",
                  d.ordinate.data_type, uff_data_type_name(d.ordinate.data_type), d.ordinate.units, d.denominator.data_type,
                  uff_data_type_name(d.denominator.data_type), d.denominator.units);
  const std::optional<FrfOrdinate> given = units ? std::optional(units->ordinate) : ordinate;
  if (given) {
    if (stated && *stated != *given)
      r.warnings.push_back(fmt::format("{}: {} states {}, but {} was given; taken as {}", what, codes, frf_ordinate_name(*stated),
                                       frf_ordinate_name(*given), frf_ordinate_name(*given)));
    r.ordinate = *given;
  } else if (stated) {
    if (labelled && labelled->ordinate != *stated)
      throw InputError(fmt::format("{}: {} states {}, but the units labels say {} ('{}')", what, codes,
                                   frf_ordinate_name(*stated), frf_ordinate_name(labelled->ordinate), labelled->label),
                       "say which is right: FrfReadOptions::ordinate (receptance, mobility, accelerance), or "
                       "FrfReadOptions::units (e.g. g/N)");
    r.ordinate = *stated;
    if (d.denominator.data_type == 0)
      r.warnings.push_back(fmt::format("{}: record 10 (ordinate denominator) data type 0 (not given); taken as force", what));
  } else if (labelled) {
    r.ordinate = labelled->ordinate;
    r.warnings.push_back(fmt::format("{}: {} names no response per force; the units labels ('{}') say {}, taken as such", what,
                                     codes, labelled->label, frf_ordinate_name(labelled->ordinate)));
  } else {
    throw InputError(fmt::format("{}: {} is not displacement, velocity or acceleration per force", what, codes),
                     "if you know what the values are, give the ordinate (FrfReadOptions::ordinate: receptance, mobility, "
                     "accelerance) or the units (FrfReadOptions::units, e.g. g/N)");
  }
  if (!d.is_complex())
    r.warnings.push_back(fmt::format("{}: the ordinate is real ({}); an FRF is complex — is this a magnitude?", what,
                                     uff_ordinate_type_name(d.ordinate_data_type)));

  FrfSeries raw;
  raw.frequency_hz = d.x;
  raw.values = d.y;
  if (units) {
    if (labelled && !(*labelled == *units))
      r.warnings.push_back(
          fmt::format("{}: the units labels say '{}'; the units given, '{}', are used", what, labelled->label, units->label));
    scale_to_si(raw, *units, what, r.warnings);
    r.units = *units;
  } else if (d.units && (d.units->force_factor != d.units->length_factor)) {
    // SI value = file value / factor: X_SI/F_SI = (X/fL)/(F/fF) = (X/F)·fF/fL; time stays in s.
    const double scale = d.units->force_factor / d.units->length_factor;
    for (auto& v : raw.values) v *= scale;
    r.warnings.push_back(
        fmt::format("{}: values converted to SI with the units of dataset 164 at line {} (code {}, "
                    "'{}'): × force factor {} / length factor {} = × {}",
                    what, d.units->line, d.units->code, d.units->description, d.units->force_factor, d.units->length_factor,
                    scale));
    r.units = {r.ordinate, scale, fmt::format("dataset 164 '{}'", d.units->description)};
  } else if (labelled && labelled->ordinate == r.ordinate) {
    scale_to_si(raw, *labelled, what, r.warnings);  // g/N × 9.80665, mm/N × 1e-3, …
    r.units = *labelled;
  } else {
    r.units = {r.ordinate, 1.0, si_label(r.ordinate)};
    if (!d.units || d.units->code == 1)
      for (const UffAxis* a : {&d.ordinate, &d.denominator})
        if (const auto t = non_si_token(a->units))
          r.warnings.push_back(
              fmt::format("{}: units label '{}' mentions '{}', which is not SI; toolpoint takes the "
                          "values as SI (m, s, N) — give FrfReadOptions::units if they are not",
                          what, a->units, *t));
  }
  r.receptance = to_receptance(raw, r.ordinate, r.warnings, what);
  validate(r.receptance, what);
  return r;
}

UffDataset58 uff_from_receptance(const FrfSeries& h, const UffDof& dof, const std::string& description) {
  UffDataset58 d;
  d.id[0] = trim(description).empty() ? std::string("toolpoint receptance") : cut(description, 80);
  d.id[1] = "toolpoint receptance, frequency in Hz, m/N";
  d.function_type = 4;
  d.response_node = dof.response_node;
  d.response_direction = dof.response_direction;
  d.reference_node = dof.reference_node;
  d.reference_direction = dof.reference_direction;
  d.ordinate_data_type = 6;
  d.abscissa = {18, 0, 0, 0, "Frequency", "Hz"};
  d.ordinate = {8, 0, 0, 0, "Receptance", "m/N"};
  d.denominator = {13, 0, 0, 0, "Force", "N"};
  d.z_axis = {0, 0, 0, 0, "NONE", "NONE"};
  d.x = h.frequency_hz;
  d.y = h.values;
  d.declared_points = static_cast<long long>(h.size());
  const std::size_t n = h.size();
  d.even = false;
  // Even only when a reader rebuilds every frequency bit for bit from record 7 (min + i·step), so
  // binary files stay exact; the step may be known as f1 − f0 or as the span over n − 1.
  if (n >= 2) {
    const double f0 = h.frequency_hz.front();
    for (double step : {h.frequency_hz[1] - f0, (h.frequency_hz.back() - f0) / static_cast<double>(n - 1)}) {
      bool even = uff_field13_roundtrip(f0) == f0 && uff_field13_roundtrip(step) == step;
      for (std::size_t i = 0; even && i < n; ++i) even = f0 + static_cast<double>(i) * step == h.frequency_hz[i];
      if (even) {
        d.even = true;
        d.abscissa_min = f0;
        d.abscissa_increment = step;
        break;
      }
    }
  }
  return d;
}

UffDataset58 uff_coherence(const std::vector<double>& f, const std::vector<double>& coherence, const UffDof& dof,
                           const std::string& description) {
  if (coherence.size() != f.size())
    throw InvalidArgument(fmt::format("uff_coherence: {} coherence values for {} frequencies", coherence.size(), f.size()));
  for (double c : coherence)
    if (!(c >= 0.0 && c <= 1.0)) throw InvalidArgument(fmt::format("uff_coherence: coherence {} outside [0, 1]", c));
  FrfSeries s;
  s.frequency_hz = f;
  for (double c : coherence) s.values.emplace_back(c, 0.0);
  UffDataset58 d = uff_from_receptance(s, dof, description);
  d.id[1] = "toolpoint coherence (gamma^2), frequency in Hz";
  d.function_type = 6;
  d.ordinate_data_type = 4;
  d.ordinate = {0, 0, 0, 0, "Coherence", "NONE"};
  d.denominator = {0, 0, 0, 0, "NONE", "NONE"};
  return d;
}

std::vector<double> uff_coherence_values(const UffDataset58& d, const std::string& source) {
  if (d.function_type != 6)
    throw InputError(
        fmt::format("{}: dataset {} is a {}, not a coherence", source, d.index, uff_function_type_name(d.function_type)));
  std::vector<double> out;
  out.reserve(d.y.size());
  for (std::size_t i = 0; i < d.y.size(); ++i) {
    const double c = d.y[i].real();
    if (!(c >= 0.0 && c <= 1.0))
      throw InputError(fmt::format("{}: dataset {} (coherence, nodes {}/{}), point {}: {} is outside [0, 1]", source, d.index,
                                   d.response_node, d.reference_node, i + 1, c),
                       "a coherence γ² lies in [0, 1]: not in per cent, not in dB");
    out.push_back(c);
  }
  return out;
}

namespace {

// CutPro's column labels, as its own files and the MATLAB scripts that write for it have them.
const char* const kCutProLabels[] = {"Freq Hz Real m/N Imag m/N", "Freq Hz Real m/N Imag Real"};

bool is_cutpro_labels(const std::vector<std::string_view>& tokens) {
  std::string joined;
  for (const auto t : tokens) {
    if (!joined.empty()) joined += ' ';
    joined += t;
  }
  return std::any_of(std::begin(kCutProLabels), std::end(kCutProLabels), [&](const char* l) { return text::iequal(joined, l); });
}

}  // namespace

FrfText parse_cutpro_frf(std::string_view text_in, const std::string& source) {
  FrfText out;
  std::size_t pos = 0, line_no = 0, zero_lines = 0;
  double last_f = -1.0;
  std::size_t last_line = 0;
  const std::string fix_table =
      "if it is a magnitude/phase or other table, read it as CSV: FrfReadOptions::format = FrfFormat::Csv with "
      "FrfCsvOptions::format (e.g. mag-phase-deg) and FrfCsvOptions::columns";
  if (text_in.substr(0, 3) == "\xEF\xBB\xBF") text_in.remove_prefix(3);
  bool data_seen = false;
  while (pos < text_in.size()) {
    std::size_t end = text_in.find('\n', pos);
    if (end == std::string_view::npos) end = text_in.size();
    const std::string_view line = trim(text_in.substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line.empty() || line.front() == '#' || line.front() == '%' || line.front() == '!' || line.front() == ';' ||
        line.substr(0, 2) == "//")
      continue;
    // Fields separated by any run of blanks, tabs, commas or semicolons.
    std::vector<std::string_view> fields;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && std::string_view(" \t\r,;").find(line[i]) != std::string_view::npos) ++i;
      const std::size_t b = i;
      while (i < line.size() && std::string_view(" \t\r,;").find(line[i]) == std::string_view::npos) ++i;
      if (i > b) fields.push_back(line.substr(b, i - b));
    }
    if (fields.empty()) continue;  // separators only (a spreadsheet's empty row): blank
    double v[3] = {};
    std::size_t parsed = 0;
    for (; parsed < fields.size() && parsed < 3; ++parsed) {
      std::string_view f = fields[parsed];
      if (!f.empty() && f.front() == '+') f.remove_prefix(1);
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v[parsed]);
      if (ec != std::errc() || ptr != f.data() + f.size()) break;
    }
    // Labels: only CutPro's own, and only before the data (alone, or after the first numbers).
    if (parsed == 0 || (parsed == 3 && fields.size() > 3)) {
      const std::vector<std::string_view> labels(fields.begin() + static_cast<std::ptrdiff_t>(parsed), fields.end());
      const bool header_place = !data_seen && out.labels.empty();
      if (header_place && is_cutpro_labels(labels)) {
        for (const auto t : labels) {
          if (!out.labels.empty()) out.labels += ' ';
          out.labels += t;
        }
        if (parsed == 0) continue;
        fields.resize(3);
      } else if (header_place) {
        throw InputError(fmt::format("{}:{}: '{}' is not CutPro's header ('{}' or '{}'): the columns may not be "
                                     "frequency, real and imaginary part",
                                     source, line_no, text::excerpt(line.substr(line.find(labels.front())), 60), kCutProLabels[0],
                                     kCutProLabels[1]),
                         fix_table);
      } else if (parsed == 0) {
        throw InputError(fmt::format("{}:{}: field 1 (frequency [Hz]) is '{}', not a number", source, line_no,
                                     text::excerpt(fields[0], 40)),
                         "each data line holds three numbers: frequency [Hz], real and imaginary receptance [m/N]");
      }
    }
    const char* names[] = {"frequency [Hz]", "real part [m/N]", "imaginary part [m/N]"};
    if (parsed < fields.size() && parsed < 3)
      throw InputError(fmt::format("{}:{}: field {} ({}) is '{}', not a number", source, line_no, parsed + 1, names[parsed],
                                   text::excerpt(fields[parsed], 40)),
                       "each data line holds three numbers: frequency [Hz], real and imaginary receptance [m/N]");
    if (fields.size() != 3)
      throw InputError(fmt::format("{}:{}: {} field(s), expected 3 (frequency [Hz], real, imaginary [m/N])", source, line_no,
                                   fields.size()),
                       "separate the three numbers by tabs, blanks or commas; use '.' as the decimal point");
    for (std::size_t k = 0; k < 3; ++k)
      if (!std::isfinite(v[k]))
        throw InputError(fmt::format("{}:{}: field {} ({}) is {}, expected a finite number", source, line_no, k + 1, names[k],
                                     v[k]),
                         "remove or repair the NaN/Inf values in the data");
    data_seen = true;
    if (v[0] < 0.0) throw InputError(fmt::format("{}:{}: frequency {} Hz is negative", source, line_no, v[0]));
    if (v[0] == 0.0) {
      ++zero_lines;
      continue;
    }
    if (!(v[0] > last_f))
      throw InputError(fmt::format("{}:{}: frequency {} Hz is not above {} Hz on line {}", source, line_no, v[0], last_f,
                                   last_line),
                       "frequencies must increase strictly, one line per frequency");
    last_f = v[0];
    last_line = line_no;
    out.series.frequency_hz.push_back(v[0]);
    out.series.values.emplace_back(v[1], v[2]);
  }
  if (zero_lines > 0)
    out.warnings.push_back(
        fmt::format("{}: {} line(s) at 0 Hz dropped: an FRF series needs frequencies above 0 Hz", source, zero_lines));
  if (out.series.size() == 0)
    throw InputError(fmt::format("{}: no data lines ({} line(s){})", source, line_no,
                                 out.labels.empty() ? "" : ", CutPro labels only"),
                     "an .frf file holds one line per frequency: frequency [Hz], real, imaginary [m/N]");
  // A magnitude/phase table without a header: real parts never negative, "imaginary parts" within
  // ±180 and a thousand times larger. A receptance is never like that (its real part changes sign
  // at a resonance, and where it does not, below the first one, it dominates the imaginary part).
  double max_re = 0.0, max_im = 0.0;
  bool re_negative = false, im_beyond_180 = false;
  for (const Complex& h : out.series.values) {
    re_negative = re_negative || h.real() < 0.0;
    im_beyond_180 = im_beyond_180 || std::abs(h.imag()) > 180.0;
    max_re = std::max(max_re, std::abs(h.real()));
    max_im = std::max(max_im, std::abs(h.imag()));
  }
  if (out.series.size() >= 3 && !re_negative && !im_beyond_180 && max_im > 1e3 * max_re)
    throw InputError(fmt::format("{}: looks like magnitude and phase, not real and imaginary parts: every second column "
                                 "value is ≥ 0 (largest {:.3g}), every third within ±180 and up to {:.3g}",
                                 source, max_re, max_im),
                     fix_table +
                         "; if it really holds real and imaginary parts, read it as CSV with FrfCsvOptions::format re-im");
  return out;
}

std::string format_cutpro_frf(const FrfSeries& s) {
  std::string out;
  out.reserve(s.size() * 64);
  for (std::size_t i = 0; i < s.size(); ++i)
    fmt::format_to(std::back_inserter(out), "{}\t{}\t{}\n", s.frequency_hz[i], s.values[i].real(), s.values[i].imag());
  return out;
}

void FrfReadOptions::check() const {
  if (format == FrfFormat::UffBinary)
    throw InvalidArgument("reading format 'uffb' is not needed: 'uff' reads both ASCII 58 and binary 58b");
  if (units && ordinate && units->ordinate != *ordinate)
    throw InvalidArgument(fmt::format("FrfReadOptions::units '{}' are {}, but FrfReadOptions::ordinate is {}", units->label,
                                      frf_ordinate_name(units->ordinate), frf_ordinate_name(*ordinate)),
                          "give the units alone (they say the ordinate), or both alike");
  if (units && !(units->to_si > 0.0)) throw InvalidArgument("FrfReadOptions::units: the factor to SI must be > 0");
  csv.check();
}

namespace {

bool csv_options_given(const FrfCsvOptions& c) { return c.format.has_value() || !c.columns.empty(); }

}  // namespace

namespace {

// The largest |H| from 5 Hz up (the H entry of a block) against the plausible range of a tool
// point receptance: a unit slip (µm/N read as m/N) or data that is not a receptance at all. An
// impossible magnitude is refused, since every result downstream would be out of range too.
// `from_file`: the fix speaks of the file's units, else of the data's.
template <class H>
void judge_peak_receptance(const std::vector<double>& f, H h, std::vector<std::string>& warnings, const std::string& what,
                           bool from_file) {
  // From 5 Hz up: below, a mobility or accelerance converted to receptance (÷ω, ÷ω²) is its noise
  // magnified, and no structural mode of a machine tool lies there.
  constexpr double kFrom = 5.0;
  double peak = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f[i] >= kFrom) peak = std::max(peak, std::abs(h(i)));
  if (peak == 0.0) return;  // nothing above 5 Hz, or an all-zero file (refused where it is used)
  const PlausibleRange& range = plausible::kPeakReceptance;
  const std::string about = fmt::format("{}: the largest receptance magnitude |H| [m/N]", what);
  switch (judge(range, peak)) {
    case Plausibility::Usual: break;
    case Plausibility::Unusual: warnings.push_back(plausibility_message(range, peak, about)); break;
    case Plausibility::Impossible:
      throw InputError(
          plausibility_message(range, peak, about),
          from_file ? "read the file in its units (FrfReadOptions::units, e.g. um/N or mm/N), or check that it holds an FRF"
                    : "give the receptance in m/N (mm/N × 1e-3, µm/N × 1e-6), or check that it is an FRF");
  }
}

// The frequencies of what was read. An end point far from the rest (a stray line: 1e9 Hz after
// 10–5000 Hz) or a top frequency no tool point measurement reaches (rad/s or Hz × 1000 read as Hz)
// would enter every result — a grid, a band, a fit — so it is refused; a top frequency merely
// outside the usual range is said.
void judge_frequencies(const std::vector<double>& f, std::vector<std::string>& warnings, const std::string& what,
                       bool from_file) {
  const std::size_t n = f.size();
  // A measured band has steps within a few times one another (a file of two bands, a handful of
  // times); an end point more than a hundred median steps from its neighbour is not one of them.
  constexpr double kStrayGap = 100.0;
  constexpr std::size_t kEnough = 10;  // points for a median step worth comparing with
  if (n >= kEnough) {
    std::vector<double> steps(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) steps[i] = f[i + 1] - f[i];
    std::vector<double> sorted = steps;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double median = sorted[sorted.size() / 2];
    for (const bool last : {true, false}) {
      const double gap = last ? steps.back() : steps.front();
      if (gap > kStrayGap * median)
        throw InputError(fmt::format("{}: its {} point, at {:g} Hz (point {} of {}), lies {:g} Hz from the {} one, {:.0f} times "
                                     "the median step of {:g} Hz: a stray {}, not part of the measured band",
                                     what, last ? "last" : "first", last ? f.back() : f.front(), last ? n : 1, n, gap,
                                     last ? "previous" : "next", gap / median, median, from_file ? "line" : "point"),
                         from_file ? "remove that line from the file (or correct its frequency)"
                                   : "remove that point from the data (or correct its frequency)");
    }
  }
  // Judged from above only: a file that ends low is a low band (a slow structure), not a slip.
  if (n == 0 || f.back() <= plausible::kTopFrequency.high) return;
  const PlausibleRange& range = plausible::kTopFrequency;
  const std::string about = fmt::format("{}: the top frequency [Hz]", what);
  switch (judge(range, f.back())) {
    case Plausibility::Usual: break;
    case Plausibility::Unusual: warnings.push_back(plausibility_message(range, f.back(), about)); break;
    case Plausibility::Impossible:
      throw InputError(plausibility_message(range, f.back(), about),
                       from_file
                           ? "check the frequency column's unit (Hz; a header such as 'Frequency (kHz)' or 'rad/s' is converted)"
                           : "give frequencies in Hz (rad/s ÷ 2π)");
  }
}

void judge_file_data(FrfFileData& data, const std::string& path) {
  if (data.is_block) {
    judge_frequencies(data.block.frequency_hz, data.warnings, path, true);
    judge_peak_receptance(
        data.block.frequency_hz, [&](std::size_t i) { return H_of(data.block.blocks[i]); }, data.warnings, path, true);
  } else {
    judge_frequencies(data.single.frequency_hz, data.warnings, path, true);
    judge_peak_receptance(
        data.single.frequency_hz, [&](std::size_t i) { return data.single.values[i]; }, data.warnings, path, true);
  }
}

}  // namespace

FrfFileData read_frf_file(const std::string& path, const FrfReadOptions& o) {
  o.check();
  FrfFileData out;
  out.format = o.format == FrfFormat::Auto ? frf_format_of_path(path) : o.format;
  if (out.format != FrfFormat::Uff && !o.uff.empty())
    throw InvalidArgument(fmt::format("{}: a dataset selection ({}) only applies to UFF files, not {}", path, o.uff.describe(),
                                      frf_format_name(out.format)));
  if (out.format != FrfFormat::Csv && csv_options_given(o.csv))
    throw InvalidArgument(fmt::format("{}: a column or value-format choice only applies to CSV files, not {}", path,
                                      frf_format_name(out.format)),
                          "drop it, or read the file as CSV (FrfReadOptions::format)");
  switch (out.format) {
    case FrfFormat::Csv: {
      FrfTable t = read_frf_csv(path, o.csv);
      out.warnings = std::move(t.warnings);
      out.is_block = t.is_block;
      out.description = path;
      out.coherence = std::move(t.coherence);
      if (t.is_block) {
        const FrfUnits u = resolve_units(std::nullopt, path, o, out.warnings);
        if (u.ordinate != FrfOrdinate::Receptance || u.to_si != 1.0)
          throw InvalidArgument(fmt::format("{}: a 2×2 block CSV holds receptances in SI units; it cannot be read as {} "
                                            "in '{}'",
                                            path, frf_ordinate_name(u.ordinate), u.label),
                                "drop FrfReadOptions::ordinate and FrfReadOptions::units for block files");
        out.ordinate = u.ordinate;
        out.units = u;
        out.block = std::move(t.block);
        break;
      }
      std::optional<FrfUnits> file_units;
      const std::string where = t.value_units_column.empty() ? path : fmt::format("{}: {}", path, t.value_units_column);
      if (!t.value_units.empty()) {
        file_units = parse_frf_units(t.value_units);
        if (!file_units && !o.units)
          throw InputError(fmt::format("{} gives the units '{}', which toolpoint does not know", where, t.value_units),
                           "give the units (FrfReadOptions::units, e.g. mm/N, m/s^2/N, g/N) or correct the header");
      }
      const FrfUnits u = resolve_units(file_units, where, o, out.warnings);
      scale_to_si(t.single, u, path, out.warnings);
      out.ordinate = u.ordinate;
      out.units = u;
      out.single = to_receptance(t.single, u.ordinate, out.warnings, path);
      validate(out.single, path);
      break;
    }
    case FrfFormat::Frf: {
      FrfText t = parse_cutpro_frf(read_text_file(path), path);
      out.warnings = std::move(t.warnings);
      out.description = path;
      // CutPro's values are receptance in m/N by the format (its labels say so when present).
      const std::optional<FrfUnits> file_units = t.labels.empty()
                                                     ? std::nullopt
                                                     : std::optional<FrfUnits>(FrfUnits{FrfOrdinate::Receptance, 1.0, "m/N"});
      const FrfUnits u = resolve_units(file_units, fmt::format("{}: CutPro labels '{}'", path, t.labels), o, out.warnings);
      scale_to_si(t.series, u, path, out.warnings);
      out.ordinate = u.ordinate;
      out.units = u;
      out.single = to_receptance(t.series, u.ordinate, out.warnings, path);
      validate(out.single, path);
      break;
    }
    case FrfFormat::Uff: {
      const UffFile file = read_uff(path);
      const UffDataset58& d = select_dataset58(file, o.uff);
      out.warnings = file.warnings_for({&d});
      UffReceptance r = uff_receptance(d, o.ordinate, path, o.units);
      out.warnings.insert(out.warnings.end(), r.warnings.begin(), r.warnings.end());
      out.single = std::move(r.receptance);
      out.ordinate = r.ordinate;
      out.units = r.units;
      out.dof = {d.response_node, d.response_direction, d.reference_node, d.reference_direction};
      out.description = fmt::format("{} dataset {} '{}', response {} {}, reference {} {}", path, d.index, d.id[0],
                                    d.response_node, uff_direction_name(d.response_direction), d.reference_node,
                                    uff_direction_name(d.reference_direction));
      break;
    }
    case FrfFormat::Auto:
    case FrfFormat::UffBinary: break;
  }
  judge_file_data(out, path);
  return out;
}

std::vector<std::string> judge_receptance_data(const FrfSeries& receptance, const std::string& what) {
  std::vector<std::string> warnings;
  judge_frequencies(receptance.frequency_hz, warnings, what, false);
  judge_peak_receptance(
      receptance.frequency_hz, [&](std::size_t i) { return receptance.values[i]; }, warnings, what, false);
  return warnings;
}

std::vector<std::string> judge_receptance_data(const BlockSeries& receptance, const std::string& what) {
  std::vector<std::string> warnings;
  judge_frequencies(receptance.frequency_hz, warnings, what, false);
  judge_peak_receptance(
      receptance.frequency_hz, [&](std::size_t i) { return H_of(receptance.blocks[i]); }, warnings, what, false);
  return warnings;
}

namespace {

// What a format without a coherence column loses.
std::vector<std::string> coherence_lost(const std::vector<double>& coherence, const std::string& path, FrfFormat f) {
  if (coherence.empty()) return {};
  return {fmt::format("{}: the coherence column is not written: {} has no place for it (write CSV to keep it)", path,
                      f == FrfFormat::Frf ? "a CutPro .frf file" : "a UFF dataset 58")};
}

}  // namespace

void FrfWriteOptions::check() const {
  const auto one_line = [](const std::string& text, const std::string& field) {
    if (text.find_first_of("\r\n") != std::string::npos)
      throw InvalidArgument(fmt::format("{} has more than one line: '{}'", field, text),
                            "give each line as its own entry of FrfWriteOptions::comments");
  };
  one_line(description, "FrfWriteOptions::description");
  for (std::size_t i = 0; i < comments.size(); ++i) one_line(comments[i], fmt::format("FrfWriteOptions::comments[{}]", i));
  for (std::size_t i = 0; i < coherence.size(); ++i)
    if (!(coherence[i] >= 0.0 && coherence[i] <= 1.0))
      throw InvalidArgument(fmt::format("FrfWriteOptions::coherence[{}] is {}; a coherence γ² lies in [0, 1]", i, coherence[i]),
                            "give the magnitude-squared coherence, one value per frequency");
}

std::vector<std::string> write_frf_file(const std::string& path, const FrfSeries& h, const FrfWriteOptions& o) {
  o.check();
  const FrfFormat format = o.format == FrfFormat::Auto ? frf_format_of_path(path) : o.format;
  require_finite_output(h, path);
  validate(h, "the series to write to " + path);
  switch (format) {
    case FrfFormat::Csv: {
      std::vector<std::string> comments = o.comments;
      if (!o.description.empty()) comments.insert(comments.begin(), o.description);
      write_frf_csv(path, h, comments, o.coherence);
      return {};
    }
    case FrfFormat::Frf: write_text_file(path, format_cutpro_frf(h)); return coherence_lost(o.coherence, path, format);
    case FrfFormat::Uff:
    case FrfFormat::UffBinary: {
      UffWriteOptions w;
      w.binary = format == FrfFormat::UffBinary;
      std::vector<std::string> lost = write_uff(path, {uff_from_receptance(h, o.dof, o.description)}, w);
      for (auto& m : coherence_lost(o.coherence, path, format)) lost.push_back(std::move(m));
      return lost;
    }
    case FrfFormat::Auto: break;
  }
  return {};
}

std::vector<std::string> write_frf_file(const std::string& path, const BlockSeries& b, const FrfWriteOptions& o) {
  o.check();
  const FrfFormat format = o.format == FrfFormat::Auto ? frf_format_of_path(path) : o.format;
  if (format != FrfFormat::Csv)
    throw InvalidArgument(fmt::format("{}: a 2×2 receptance block can only be written as FRF CSV, not {}", path,
                                      frf_format_name(format)),
                          "write to a .csv file");
  require_finite_output(b, path);
  validate(b, "the series to write to " + path);
  std::vector<std::string> comments = o.comments;
  if (!o.description.empty()) comments.insert(comments.begin(), o.description);
  write_frf_csv(path, b, comments, o.coherence);
  return {};
}

}  // namespace toolpoint
