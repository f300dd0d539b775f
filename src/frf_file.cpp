// toolpoint: measured FRF files in any supported format (see frf_file.hpp).
#include "toolpoint/frf_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io.hpp"
#include "text.hpp"

namespace toolpoint {

namespace {

using text::cut;
using text::lower;
using text::trim;

// Units labels that are clearly not SI: a file without a units dataset that says "g" or "mm"
// would otherwise be read silently a factor 9.81 or 1000 off.
std::optional<std::string> non_si_token(const std::string& label) {
  static const std::set<std::string> bad = {"g", "mm", "cm", "um", "µm", "in", "inch", "ft", "lb", "lbf", "kgf",
                                            "mN", "kN", "ips", "mil", "mils"};
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

std::string uff_what(const std::string& source, const UffDataset58& d) {
  return fmt::format("{}: dataset 58 #{} ('{}')", source, d.index, cut(d.id[0], 40));
}

}  // namespace

FrfFormat parse_frf_format(const std::string& text, const std::string& option) {
  const std::string s = lower(trim(text));
  if (s == "auto") return FrfFormat::Auto;
  if (s == "csv") return FrfFormat::Csv;
  if (s == "uff" || s == "unv" || s == "uf") return FrfFormat::Uff;
  if (s == "uffb" || s == "uff-binary" || s == "58b") return FrfFormat::UffBinary;
  if (s == "frf" || s == "cutpro") return FrfFormat::Frf;
  throw InvalidArgument(fmt::format("{} '{}' is not a known FRF file format", option, text),
                        "use csv, uff (ASCII dataset 58), uffb (binary 58b) or frf (CutPro text)");
}

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
                        "use .csv, .uff/.unv/.uf or .frf, or name the format (--from/--to csv|uff|uffb|frf)");
}

FrfOrdinate parse_frf_ordinate(const std::string& text, const std::string& option) {
  const std::string s = lower(trim(text));
  if (s == "receptance" || s == "compliance") return FrfOrdinate::Receptance;
  if (s == "mobility") return FrfOrdinate::Mobility;
  if (s == "accelerance" || s == "inertance") return FrfOrdinate::Accelerance;
  throw InvalidArgument(fmt::format("{} '{}' is not an FRF ordinate", option, text),
                        "use receptance (m/N), mobility ((m/s)/N) or accelerance ((m/s²)/N)");
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

std::optional<FrfOrdinate> uff_ordinate_kind(const UffDataset58& d) {
  if (d.denominator.data_type != 13 && d.denominator.data_type != 0) return std::nullopt;
  switch (d.ordinate.data_type) {
    case 8: return FrfOrdinate::Receptance;
    case 11: return FrfOrdinate::Mobility;
    case 12: return FrfOrdinate::Accelerance;
    default: return std::nullopt;
  }
}

FrfSeries to_receptance(const FrfSeries& s, FrfOrdinate ordinate, std::vector<std::string>& warnings,
                        const std::string& what) {
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
    warnings.push_back(fmt::format("{}: {} point(s) at 0 Hz dropped: {}", what, dropped,
                                   ordinate == FrfOrdinate::Receptance
                                       ? "an FRF series needs frequencies above 0 Hz"
                                       : fmt::format("{} cannot be converted to receptance at ω = 0 (division by {})",
                                                     frf_ordinate_name(ordinate),
                                                     ordinate == FrfOrdinate::Mobility ? "iω" : "−ω²")));
  return out;
}

UffReceptance uff_receptance(const UffDataset58& d, std::optional<FrfOrdinate> ordinate, const std::string& source) {
  UffReceptance r;
  const std::string what = uff_what(source, d);
  const std::string list_hint = fmt::format("list the datasets with `toolpoint convert {} --list` and pick an FRF", source);
  if (d.function_type == 0)
    r.warnings.push_back(fmt::format("{}: record 6 function type 0 (general or unknown); taken as an FRF", what));
  else if (d.function_type != 4)
    throw InputError(fmt::format("{}: record 6 function type {} ({}), expected 4 (frequency response function)", what,
                                 d.function_type, uff_function_type_name(d.function_type)),
                     list_hint);
  if (d.abscissa.data_type == 0)
    r.warnings.push_back(fmt::format("{}: record 8 abscissa data type 0 (unknown, units label '{}'); taken as frequency "
                                     "in Hz",
                                     what, d.abscissa.units));
  else if (d.abscissa.data_type != 18)
    throw InputError(fmt::format("{}: record 8 abscissa data type {} ({}), expected 18 (frequency, Hz)", what,
                                 d.abscissa.data_type, uff_data_type_name(d.abscissa.data_type)),
                     list_hint);
  const auto stated = uff_ordinate_kind(d);
  const std::string codes =
      fmt::format("record 9 ordinate data type {} ({}, units '{}') over record 10 data type {} ({}, units '{}')",
                  d.ordinate.data_type, uff_data_type_name(d.ordinate.data_type), d.ordinate.units,
                  d.denominator.data_type, uff_data_type_name(d.denominator.data_type), d.denominator.units);
  if (ordinate) {
    if (stated && *stated != *ordinate)
      r.warnings.push_back(fmt::format("{}: {} states {}, but {} was given; taken as {}", what, codes,
                                       frf_ordinate_name(*stated), frf_ordinate_name(*ordinate),
                                       frf_ordinate_name(*ordinate)));
    r.ordinate = *ordinate;
  } else if (stated) {
    r.ordinate = *stated;
    if (d.denominator.data_type == 0)
      r.warnings.push_back(fmt::format("{}: record 10 (ordinate denominator) data type 0 (not given); taken as force",
                                       what));
  } else {
    throw InputError(fmt::format("{}: {} is not displacement, velocity or acceleration per force", what, codes),
                     "if you know what the values are, give the ordinate (--ordinate receptance|mobility|accelerance)");
  }
  if (!d.is_complex())
    r.warnings.push_back(fmt::format("{}: the ordinate is real ({}); an FRF is complex — is this a magnitude?", what,
                                     uff_ordinate_type_name(d.ordinate_data_type)));

  FrfSeries raw;
  raw.frequency_hz = d.x;
  raw.values = d.y;
  if (d.units && (d.units->force_factor != d.units->length_factor)) {
    // SI value = file value / factor: X_SI/F_SI = (X/fL)/(F/fF) = (X/F)·fF/fL; time stays in s.
    const double scale = d.units->force_factor / d.units->length_factor;
    for (auto& v : raw.values) v *= scale;
    r.warnings.push_back(fmt::format("{}: values converted to SI with the units of dataset 164 at line {} (code {}, "
                                     "'{}'): × force factor {} / length factor {} = × {}",
                                     what, d.units->line, d.units->code, d.units->description, d.units->force_factor,
                                     d.units->length_factor, scale));
  } else if (!d.units || d.units->code == 1) {
    for (const UffAxis* a : {&d.ordinate, &d.denominator})
      if (const auto t = non_si_token(a->units))
        r.warnings.push_back(fmt::format("{}: units label '{}' mentions '{}', which is not SI; toolpoint takes the "
                                         "values as SI (m, s, N) — convert them first if they are not",
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

FrfText parse_cutpro_frf(std::string_view text, const std::string& source) {
  FrfText out;
  std::size_t pos = 0, line_no = 0, header_lines = 0, zero_lines = 0;
  double last_f = -1.0;
  std::size_t last_line = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trim(text.substr(pos, end - pos));
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
    double v[3] = {};
    std::size_t parsed = 0;
    for (; parsed < fields.size() && parsed < 3; ++parsed) {
      std::string_view f = fields[parsed];
      if (!f.empty() && f.front() == '+') f.remove_prefix(1);
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v[parsed]);
      if (ec != std::errc() || ptr != f.data() + f.size()) break;
    }
    if (parsed == 0 && out.series.size() == 0 && zero_lines == 0) {  // a header line before the data
      ++header_lines;
      continue;
    }
    const char* names[] = {"frequency [Hz]", "real part [m/N]", "imaginary part [m/N]"};
    if (parsed < fields.size() && parsed < 3)
      throw InputError(fmt::format("{}:{}: field {} ({}) is '{}', not a number", source, line_no, parsed + 1,
                                   names[parsed], std::string(fields[parsed].substr(0, 40))),
                       "each data line holds three numbers: frequency [Hz], real and imaginary receptance [m/N]");
    if (fields.size() != 3)
      throw InputError(fmt::format("{}:{}: {} field(s), expected 3 (frequency [Hz], real, imaginary [m/N])", source,
                                   line_no, fields.size()),
                       "separate the three numbers by tabs, blanks or commas; use '.' as the decimal point");
    for (std::size_t k = 0; k < 3; ++k)
      if (!std::isfinite(v[k]))
        throw InputError(fmt::format("{}:{}: field {} ({}) is {}, expected a finite number", source, line_no, k + 1,
                                     names[k], v[k]),
                         "remove or repair the NaN/Inf values in the data");
    if (v[0] < 0.0)
      throw InputError(fmt::format("{}:{}: frequency {} Hz is negative", source, line_no, v[0]));
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
    out.warnings.push_back(fmt::format("{}: {} line(s) at 0 Hz dropped: an FRF series needs frequencies above 0 Hz",
                                       source, zero_lines));
  if (out.series.size() == 0)
    throw InputError(fmt::format("{}: no data lines ({} line(s), {} header line(s))", source, line_no, header_lines),
                     "an .frf file holds one line per frequency: frequency [Hz], real, imaginary [m/N]");
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
}

FrfFileData read_frf_file(const std::string& path, const FrfReadOptions& o) {
  o.check();
  FrfFileData out;
  out.format = o.format == FrfFormat::Auto ? frf_format_of_path(path) : o.format;
  if (out.format != FrfFormat::Uff && !o.uff.empty())
    throw InvalidArgument(fmt::format("{}: a dataset selection ({}) only applies to UFF files, not {}", path,
                                      o.uff.describe(), frf_format_name(out.format)));
  const FrfOrdinate given = o.ordinate.value_or(FrfOrdinate::Receptance);
  switch (out.format) {
    case FrfFormat::Csv: {
      FrfTable t = read_frf_csv(path);
      out.is_block = t.is_block;
      out.ordinate = given;
      out.description = path;
      if (t.is_block) {
        if (given != FrfOrdinate::Receptance)
          throw InvalidArgument(fmt::format("{}: a 2×2 block CSV holds receptances; it cannot be read as {}", path,
                                            frf_ordinate_name(given)));
        out.block = std::move(t.block);
      } else {
        out.single = to_receptance(t.single, given, out.warnings, path);
        validate(out.single, path);
      }
      break;
    }
    case FrfFormat::Frf: {
      FrfText t = parse_cutpro_frf(read_text_file(path), path);
      out.warnings = std::move(t.warnings);
      out.ordinate = given;
      out.description = path;
      out.single = to_receptance(t.series, given, out.warnings, path);
      validate(out.single, path);
      break;
    }
    case FrfFormat::Uff: {
      const UffFile file = read_uff(path);
      const UffDataset58& d = select_dataset58(file, o.uff);
      out.warnings = file.warnings_for({&d});
      UffReceptance r = uff_receptance(d, o.ordinate, path);
      out.warnings.insert(out.warnings.end(), r.warnings.begin(), r.warnings.end());
      out.single = std::move(r.receptance);
      out.ordinate = r.ordinate;
      out.dof = {d.response_node, d.response_direction, d.reference_node, d.reference_direction};
      out.description = fmt::format("{} dataset {} '{}', response {} {}, reference {} {}", path, d.index, d.id[0],
                                    d.response_node, uff_direction_name(d.response_direction), d.reference_node,
                                    uff_direction_name(d.reference_direction));
      break;
    }
    case FrfFormat::Auto:
    case FrfFormat::UffBinary:
      break;
  }
  return out;
}

std::vector<std::string> write_frf_file(const std::string& path, const FrfSeries& h, const FrfWriteOptions& o) {
  const FrfFormat format = o.format == FrfFormat::Auto ? frf_format_of_path(path) : o.format;
  validate(h, "the series to write to " + path);
  switch (format) {
    case FrfFormat::Csv: {
      std::vector<std::string> comments = o.comments;
      if (!o.description.empty()) comments.insert(comments.begin(), o.description);
      write_frf_csv(path, h, comments);
      return {};
    }
    case FrfFormat::Frf:
      write_text_file(path, format_cutpro_frf(h));
      return {};
    case FrfFormat::Uff:
    case FrfFormat::UffBinary: {
      UffWriteOptions w;
      w.binary = format == FrfFormat::UffBinary;
      return write_uff(path, {uff_from_receptance(h, o.dof, o.description)}, w);
    }
    case FrfFormat::Auto:
      break;
  }
  return {};
}

std::vector<std::string> write_frf_file(const std::string& path, const BlockSeries& b, const FrfWriteOptions& o) {
  const FrfFormat format = o.format == FrfFormat::Auto ? frf_format_of_path(path) : o.format;
  if (format != FrfFormat::Csv)
    throw InvalidArgument(fmt::format("{}: a 2×2 receptance block can only be written as FRF CSV, not {}", path,
                                      frf_format_name(format)),
                          "write to a .csv file");
  validate(b, "the series to write to " + path);
  std::vector<std::string> comments = o.comments;
  if (!o.description.empty()) comments.insert(comments.begin(), o.description);
  write_frf_csv(path, b, comments);
  return {};
}

}  // namespace toolpoint
