// toolpoint: the seed's analytical case study (Section 3).
#include "toolpoint/studies/case_study.hpp"

#include <cmath>
#include <fmt/format.h>

#include "toolpoint/model/coupling.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

void CaseStudyOptions::check() const {
  check_fields(case_study_fields(), *this, "CaseStudyOptions");
  filter.check();
  fit_options.check();
}

const std::vector<OptionField<CaseStudyOptions>>& case_study_fields() {
  using O = CaseStudyOptions;
  using K = FieldKind;
  // σ below 1: a factor 1 + σz of σ ≥ 1 flips the sign of a third of the entries; the read-out band
  // below ±50 %: wider reaches the neighbouring modes.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "noise_sigma",
        .kind = K::Real,
        .min = 0.0,
        .max = 1.0,
        .max_open = true,
        .note = "0: exact data",
        .help = "standard deviation of the multiplicative noise (0.05 = 5 %, the seed's)",
        .cli_name = "sigma"},
       [](O& o) -> double& { return o.noise_sigma; }},
      {{.name = "apply_filter", .kind = K::Flag, .help = "filter the noisy data (Savitzky–Golay) before the read-out"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.apply_filter; }},
      {{.name = "band_width",
        .kind = K::Real,
        .min = 0.0,
        .max = 0.5,
        .min_open = true,
        .max_open = true,
        .help = "read-out band half-width around the tool mode, relative: tool mode × (1 ± width) (0.02 = ±2 %)",
        .cli_name = "width"},
       [](O& o) -> double& { return o.band_width; }},
      {{.name = "fit", .kind = K::Flag, .help = "also fit the joint to the raw noisy data (the band fit)"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.fit; }}};
  return fields;
}

CaseStudy run_case_study(const Assembly& assembly, const CaseStudyOptions& o, const ProgressCallback& progress) {
  o.check();
  if (assembly.holder_tool.rigid)
    throw InvalidArgument("the case study needs an elastic holder–tool joint to identify (joints.holder_tool is rigid)",
                          "give [joints.holder_tool] the 8 parameters, e.g. the seed's Table 1");
  CaseStudy cs;
  cs.assembly = assembly;
  cs.reference = assembly.holder_tool.parameters;
  const AssemblyModel model(assembly);
  const std::vector<double> f = assembly.grid.values();
  if (f.size() < 3) throw InvalidArgument("the case study needs at least 3 frequencies in [analysis]");

  // Forward model, once per frequency; the tool's free–free blocks are reused by every
  // identification below.
  std::vector<TwoPort> T(f.size());
  cs.sh_true.frequency_hz = cs.sht_true.frequency_hz = f;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto r = model.evaluate(f[i]);
    T[i] = r.T;
    cs.sh_true.blocks.push_back(r.SH11);
    cs.sht_true.blocks.push_back(r.SHT11);
  }
  // Every series here is on the grid f, so the tool's block at x is T at x's index.
  auto tool_at = [&](double x) { return T[static_cast<std::size_t>(std::lower_bound(f.begin(), f.end(), x) - f.begin())]; };
  auto identify = [&](const BlockSeries& sh, const BlockSeries& sht, const char* what) {
    return identify_series(tool_at, sh, fmt::format("SH11 ({})", what), sht, fmt::format("SHT11 ({})", what));
  };

  cs.clean = identify(cs.sh_true, cs.sht_true, "noise-free");
  for (std::size_t i = 0; i < cs.clean.size(); ++i)
    for (int k = 0; k < 8; ++k)
      if (cs.reference[k] != 0.0)
        cs.clean_max_deviation[static_cast<std::size_t>(k)] = std::max(cs.clean_max_deviation[static_cast<std::size_t>(k)],
                                                                       std::abs(cs.clean.parameters[i][k] / cs.reference[k] -
                                                                                1.0));

  auto sh_n = add_measurement_noise(cs.sh_true, NoiseOptions{.sigma = o.noise_sigma, .seed = o.seed}, "SH11");
  auto sht_n = add_measurement_noise(cs.sht_true, NoiseOptions{.sigma = o.noise_sigma, .seed = o.seed + 1}, "SHT11");
  cs.sh_noisy = std::move(sh_n.series);
  cs.sht_noisy = std::move(sht_n.series);
  for (auto* w : {&sh_n.warnings, &sht_n.warnings}) cs.warnings.insert(cs.warnings.end(), w->begin(), w->end());
  if (o.apply_filter) {
    check_smoothing_window(o.filter, cs.sh_noisy.size(), "SH11");
    auto a = savgol_filter(cs.sh_noisy, o.filter, "SH11");
    auto b = savgol_filter(cs.sht_noisy, o.filter, "SHT11");
    cs.sh_filtered = std::move(a.series);
    cs.sht_filtered = std::move(b.series);
    for (auto* w : {&a.warnings, &b.warnings}) cs.warnings.insert(cs.warnings.end(), w->begin(), w->end());
    // The filter's own bias on the peaks: the noise-free curves against their filtered copies (on
    // the noisy data, noise ripple would be reported as peaks).
    for (const auto& [truth, name] : {std::pair{&cs.sh_true, "SH11 (noise-free)"}, {&cs.sht_true, "SHT11 (noise-free)"}}) {
      const PeakChangeReport pc = peak_changes(*truth, savgol_filter(*truth, o.filter, name).series, o.filter.window, {}, name);
      cs.warnings.insert(cs.warnings.end(), pc.warnings.begin(), pc.warnings.end());
    }
  } else {
    cs.sh_filtered = cs.sh_noisy;
    cs.sht_filtered = cs.sht_noisy;
  }
  cs.noisy = identify(cs.sh_noisy, cs.sht_noisy, "noisy");

  // The seed's procedure (filtered data, read at the mode effect analysis picks) and the band fit
  // (raw data), by the one identification study.
  IdentificationOptions io;
  io.route = Route::HolderTool;
  io.method = IdentificationMethod::Seed;
  io.width = o.band_width;
  if (o.apply_filter) io.filter = o.filter;
  IdentificationData measured;
  measured.label = "overhang as modelled";
  measured.G11 = cs.sht_noisy;
  measured.g_name = "SHT11 (noisy)";
  measured.B11 = cs.sh_noisy;
  measured.b_name = "SH11 (noisy)";
  cs.seed = run_identification_study(assembly, {measured}, io);
  cs.filtered = cs.seed.closed_form;
  cs.effect = *cs.seed.mode.effect;
  cs.mode_hz = cs.seed.mode.center_hz;
  const double lo = cs.seed.mode.lo_hz, hi = cs.seed.mode.hi_hz;
  cs.clean_readout = band_readout(cs.clean, lo, hi);
  cs.noisy_readout = band_readout(cs.noisy, lo, hi);
  cs.filtered_readout = cs.seed.seed;

  // Forward check: the constants into Eq. (5) with the true SH11, against the true SHT11, so that
  // what differs is the identified joint alone.
  auto couple_back = [&](const JointParameters& p, BlockSeries& out) {
    const Joint joint = Joint::make_elastic(p);
    out.frequency_hz = f;
    for (std::size_t i = 0; i < f.size(); ++i) out.blocks.push_back(couple_point(T[i], cs.sh_true.blocks[i], joint, f[i]));
    return compare_modes(entry(cs.sht_true, 0), entry(out, 0));
  };
  cs.verification = couple_back(cs.filtered_readout.medians(), cs.sht_verified);
  if (o.fit) {
    IdentificationOptions fo;
    fo.route = Route::HolderTool;
    fo.method = IdentificationMethod::Fit;
    fo.width = o.band_width;
    fo.at_hz = cs.mode_hz;  // the same read-out band as the seed's; the fit uses every frequency
    fo.fit = o.fit_options;
    cs.fitted = run_identification_study(assembly, {measured}, fo, progress);
    cs.fit_verification = couple_back(cs.fitted->identified, cs.sht_fitted);
  }
  // Every warning in one list: the identifications' too (the fit's own, since it repeats the
  // read-out's, which the seed's identification already gave).
  cs.warnings.insert(cs.warnings.end(), cs.seed.warnings.begin(), cs.seed.warnings.end());
  if (cs.fitted)
    for (const std::string& w : cs.fitted->warnings)
      if (w.rfind("seed read-out: ", 0) != 0) cs.warnings.push_back("band fit: " + w);
  return cs;
}

}  // namespace toolpoint
