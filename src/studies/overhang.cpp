// toolpoint: the overhang study (studies/overhang.hpp).
#include "toolpoint/studies/overhang.hpp"

#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/parallel.hpp"

namespace toolpoint {

void OverhangStudyOptions::check() const {
  for (std::size_t i = 0; i < overhangs_m.size(); ++i) {
    const double L = overhangs_m[i];
    if (!std::isfinite(L) || !(L > 0.0))
      throw InvalidArgument(fmt::format("OverhangStudyOptions::overhangs_m[{}] = {} m must be > 0", i, L),
                            "give the tool's length outside the holder in metres, e.g. 0.05");
    // No end mill sticks out a metre: such a value is millimetres given as metres.
    if (L > 1.0)
      throw InvalidArgument(fmt::format("OverhangStudyOptions::overhangs_m[{}] = {} m is over 1 m: millimetres?", i, L),
                            fmt::format("overhangs are in metres: {} mm is {:g} m", L, L / 1000.0));
    if (i > 0 && !(L > overhangs_m[i - 1]))
      throw InvalidArgument(fmt::format("OverhangStudyOptions::overhangs_m must be strictly increasing: [{}] = {} m follows {} m",
                                        i, L, overhangs_m[i - 1]),
                            "sort the overhangs and drop repeats (modes are followed from one overhang to the next)");
  }
  try {
    peaks.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("OverhangStudyOptions::peaks: {}", e.what()), e.hint());
  }
  check_fields(overhang_study_fields(), *this, "OverhangStudyOptions");
  if (!uncertain_joint) return;
  if (overhangs_m.size() > 1)
    throw InvalidArgument(fmt::format("OverhangStudyOptions::uncertain_joint: the band is computed for one overhang, not {}",
                                      overhangs_m.size()),
                          "give one overhang, or leave uncertain_joint empty");
  band.check();
}

const std::vector<OptionField<OverhangStudyOptions>>& overhang_study_fields() {
  using O = OverhangStudyOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "tracking_tolerance",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "a mode moves at most this fraction of its frequency from one overhang to the next (e.g. 0.15)"},
       [](O& o) -> double& { return o.tracking_tolerance; }},
      {option_field(parallel_fields(), "threads").spec, nullptr, [](O& o) -> int& { return o.threads; }}};
  return fields;
}

namespace {

std::string millimetres(const std::vector<double>& overhangs, const std::vector<std::size_t>& which) {
  constexpr std::size_t kShown = 6;
  std::string s;
  for (std::size_t k = 0; k < which.size() && k < kShown; ++k)
    s += fmt::format("{}{:.1f}", k ? ", " : "", 1000.0 * overhangs[which[k]]);
  if (which.size() > kShown) s += ", …";
  return s + " mm";
}

}  // namespace

OverhangStudy run_overhang_study(const Assembly& given, const BlockSeries& sh11, const OverhangStudyOptions& options,
                                 const ProgressCallback& progress) {
  options.check();
  // A sampled joint file's joint is the nominal one, so the coupled FRFs and the band describe the
  // same joint (the samples replace the assembly's joint too).
  const Assembly assembly = options.uncertain_joint ? with_joint(given, *options.uncertain_joint) : given;
  validate(sh11, options.sh11_name, 3);
  const bool own = options.overhangs_m.empty();
  const std::vector<double> overhangs = own ? std::vector<double>{assembly.tool.overhang} : options.overhangs_m;
  // With a band, each overhang is one unit of work and each joint sample another.
  const double share = options.uncertain_joint
                           ? static_cast<double>(overhangs.size()) / static_cast<double>(overhangs.size() + options.band.samples)
                           : 1.0;
  ProgressCallback overhang_progress;
  if (progress) overhang_progress = [&](double f) { progress(share * f); };
  OverhangStudy s;
  s.warnings = assembly.warnings();  // what the joint's source says against it
  s.tool_inside_holder_m = assembly.tool.length - assembly.tool.overhang;
  s.overhangs.resize(overhangs.size());
  // Each overhang writes its own slot only: identical results for any thread count.
  parallel_for(
      overhangs.size(), ParallelOptions{options.threads},
      [&](std::size_t i) {
        const double L = overhangs[i];
        const std::string which = own ? fmt::format("the assembly's tool.overhang = {} m", L)
                                      : fmt::format("OverhangStudyOptions::overhangs_m[{}] = {} m", i, L);
        OverhangFrf& r = s.overhangs[i];
        r.overhang_m = L;
        Assembly a;
        try {
          a = with_overhang(assembly, L);
        } catch (const InvalidArgument& e) {
          throw InvalidArgument(fmt::format("{}: {}", which, e.what()), e.hint());
        }
        try {
          r.sht11 = couple_tool(a, sh11, options.sh11_name);
        } catch (const NumericalError& e) {
          throw NumericalError(fmt::format("overhang {} m: {}", L, e.what()), e.hint());
        }
        r.modes = find_peaks(entry(r.sht11, 0), options.peaks);
      },
      overhang_progress);

  // Modes followed from the overhang nearest the assembly's own (the first of two equally near).
  for (std::size_t i = 1; i < overhangs.size(); ++i)
    if (std::abs(overhangs[i] - assembly.tool.overhang) < std::abs(overhangs[s.reference] - assembly.tool.overhang))
      s.reference = i;
  std::vector<std::vector<Peak>> family;
  for (const OverhangFrf& r : s.overhangs) family.push_back(r.modes);
  s.tracked_modes_hz = track_modes(family, s.reference, options.tracking_tolerance, true);

  if (s.overhangs[s.reference].modes.empty())
    s.warnings.push_back(
        fmt::format("no peak of |H| rises {:g} % above its valleys at the reference overhang {} m: no modes to follow",
                    100.0 * options.peaks.min_prominence, overhangs[s.reference]));
  for (std::size_t m = 0; m < s.tracked_modes_hz.size(); ++m) {
    std::vector<std::size_t> lost;
    for (std::size_t i = 0; i < overhangs.size(); ++i)
      if (std::isnan(s.tracked_modes_hz[m][i])) lost.push_back(i);
    if (!lost.empty())
      s.warnings.push_back(fmt::format("mode {} ({:.1f} Hz at {:.1f} mm) not found within {:g} % at {} of {} overhangs: {}",
                                       m + 1, s.tracked_modes_hz[m][s.reference], 1000.0 * overhangs[s.reference],
                                       100.0 * options.tracking_tolerance, lost.size(), overhangs.size(),
                                       millimetres(overhangs, lost)));
  }
  if (options.uncertain_joint) {
    UncertaintyOptions band = options.band;
    band.progress = {};
    if (progress) band.progress = [&](double f) { progress(share + (1.0 - share) * f); };
    s.band = coupled_tool_point_band(with_overhang(assembly, overhangs.front()), *options.uncertain_joint, sh11,
                                     options.sh11_name, band);
  }
  return s;
}

std::size_t overhang_sweep_size(double start_m, double stop_m, double step_m) {
  if (!std::isfinite(start_m) || !std::isfinite(stop_m) || !std::isfinite(step_m) || !(start_m > 0.0) || !(stop_m >= start_m))
    throw InvalidArgument(fmt::format("overhang sweep {}:{}:{} m: the overhangs must satisfy 0 < start ≤ stop", start_m, stop_m,
                                      step_m),
                          "give START:STOP:STEP in metres, e.g. 0.040:0.060:0.002");
  if (!(step_m >= 1e-9))
    throw InvalidArgument(fmt::format("overhang sweep step {} m is below a nanometre", step_m),
                          "give the step in metres, e.g. 0.002 (2 mm)");
  return static_cast<std::size_t>(std::floor((stop_m - start_m) / step_m * (1.0 + 1e-12) + 1e-9)) + 1;
}

std::vector<double> overhang_sweep(double start_m, double stop_m, double step_m) {
  const std::size_t n = overhang_sweep_size(start_m, stop_m, step_m);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = std::round((start_m + static_cast<double>(i) * step_m) * 1e9) / 1e9;
  return v;
}

Table natural_frequency_table(const OverhangStudy& study) {
  Table table;
  table.columns = {"overhang_m"};
  for (std::size_t m = 0; m < study.tracked_modes_hz.size(); ++m) table.columns.push_back(fmt::format("mode_{}_hz", m + 1));
  table.may_be_empty.assign(table.columns.begin() + 1, table.columns.end());
  for (std::size_t i = 0; i < study.overhangs.size(); ++i) {
    std::vector<double> row{study.overhangs[i].overhang_m};
    for (const auto& mode : study.tracked_modes_hz) row.push_back(mode[i]);
    table.rows.push_back(row);
  }
  return table;
}

plot::OverhangSweep natural_frequency_sweep(const OverhangStudy& study) {
  plot::OverhangSweep sweep;
  for (const OverhangFrf& r : study.overhangs) sweep.overhang_m.push_back(r.overhang_m);
  sweep.frequency_hz = study.tracked_modes_hz;
  sweep.title = "Modes of H^{sht}_{11} against tool overhang (seed Fig. 10)";
  return sweep;
}

std::vector<FrfSeries> tool_point_frfs(const OverhangStudy& study) {
  std::vector<FrfSeries> frfs;
  for (const OverhangFrf& r : study.overhangs) frfs.push_back(entry(r.sht11, 0));
  return frfs;
}

}  // namespace toolpoint
