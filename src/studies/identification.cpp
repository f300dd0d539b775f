// toolpoint: a joint identified from measured FRFs, seed read-out and band fit (studies/identification.hpp).
#include "toolpoint/studies/identification.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numeric>

#include "toolpoint/model/coupling.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/statistics.hpp"
#include "toolpoint/version.hpp"

namespace toolpoint {

const char* to_string(IdentificationMethod m) { return m == IdentificationMethod::Fit ? "fit" : "seed"; }

const char* to_string(Route r) {
  switch (r) {
    case Route::HolderTool: return "Eq. (6)";
    case Route::SpindleHolderFromSH: return "Eq. (15)";
    case Route::SpindleHolderFromSHT: return "Eq. (18)";
  }
  return "?";
}

const char* to_string(Verdict v) { return v == Verdict::Pass ? "pass" : v == Verdict::Doubtful ? "doubtful" : "fail"; }

void NoiseSpec::check() const {
  check_fields(noise_spec_fields(), *this, "NoiseSpec");
  if (source == Source::Estimated) {
    estimate.check();
  } else if (magnitude_sigma == 0.0 && phase_sigma_rad == 0.0 && floor == 0.0) {
    throw InvalidArgument("NoiseSpec::magnitude_sigma 0, NoiseSpec::phase_sigma_rad 0 rad and NoiseSpec::floor 0: stated "
                          "noise is not all zero",
                          "state the noise the data have; for exact (model) data use no noise at all");
  }
}

const std::vector<OptionField<NoiseSpec>>& noise_spec_fields() {
  using O = NoiseSpec;
  // The floor and the calibration are the measured-noise model's (NoiseOptions), in the
  // identification's words; the σ's top is StatedNoise's (no measured FRF is noisier).
  const auto noise = [](const char* name, const char* help) { return with_help(option_field(noise_fields(), name).spec, help); };
  static const FieldSpec floor = [&] {
    FieldSpec s = noise("floor",
                        "stated: an additive floor, σ of the real and imaginary parts of every entry relative to that entry's "
                        "peak |value| (0.01 = 1 %)");
    s.plausible = &plausible::kRelativeNoise;
    return s;
  }();
  static const std::vector<OptionField<O>> fields = {
      {{.name = "magnitude_sigma",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 0.5,
        .note = "0: none stated",
        .help = "stated: relative magnitude σ of every FRF entry (0.02 = 2 %)",
        .cli_name = "sigma",
        .plausible = &plausible::kRelativeNoise},
       [](O& o) -> double& { return o.magnitude_sigma; }},
      {{.name = "phase_sigma_rad",
        .kind = FieldKind::Real,
        .unit = "rad",
        .min = 0.0,
        .max = 0.5,
        .note = "0: none stated",
        .help = "stated: phase σ of every FRF entry",
        .cli_name = "phase-sigma",
        .cli_unit = "degrees",
        .cli_per_unit = 180.0 / kPi},
       [](O& o) -> double& { return o.phase_sigma_rad; }},
      {floor, [](O& o) -> double& { return o.floor; }},
      {noise("calibration",
             "standard uncertainty (1 σ) of each measured FRF's sensitivity: a scale error no data reveal, carried into "
             "every interval (0.02 = 2 %; 1–3 % is usual)"),
       [](O& o) -> double& { return o.calibration; }},
      {{.name = "averages",
        .kind = FieldKind::Integer,
        .min = 0.0,
        .max = 100000.0,
        .note = "0: the coherence is not used",
        .help = "averages behind the files' coherence column: the variance of H from its coherence, (1 − γ²)/(2 n γ²) "
                "(Bendat & Piersol), replaces the estimated one",
        .cli_name = "averages"},
       nullptr,
       [](O& o) -> int& { return o.averages; }}};
  return fields;
}

void VerdictOptions::check() const {
  try {
    forward.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("VerdictOptions::forward: {}", e.what()), e.hint());
  }
  check_fields(verdict_fields(), *this, "VerdictOptions");
  if (!(residual_doubt <= residual_fail))
    throw InvalidArgument(fmt::format("VerdictOptions::residual_doubt {} and VerdictOptions::residual_fail {} must satisfy "
                                      "1 < doubt ≤ fail",
                                      residual_doubt, residual_fail),
                          "e.g. 1.5 and 3: the residual ratio is 1 when the model and the noise explain the data");
}

const std::vector<OptionField<VerdictOptions>>& verdict_fields() {
  using O = VerdictOptions;
  // A residual ratio is 1 when the model and the noise explain the data: a level must lie above it.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "residual_doubt",
        .kind = FieldKind::Real,
        .min = 1.0,
        .min_open = true,
        .help = "the band fit's residual ratio above which the verdict is doubtful, ≤ residual_fail (e.g. 1.5)"},
       [](O& o) -> double& { return o.residual_doubt; }},
      {{.name = "residual_fail",
        .kind = FieldKind::Real,
        .min = 1.0,
        .min_open = true,
        .help = "the band fit's residual ratio above which it fails: a model that does not describe the data (e.g. 3)"},
       [](O& o) -> double& { return o.residual_fail; }}};
  return fields;
}

const std::vector<OptionField<IdentificationOptions>>& identification_fields() {
  using O = IdentificationOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "width",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 0.5,
        .min_open = true,
        .max_open = true,
        .help = "half-width of the read-out band around the mode, relative (0.02 = ±2 %)",
        .cli_name = "width"},
       [](O& o) -> double& { return o.width; }},
  };
  return fields;
}

void IdentificationOptions::check() const {
  if (band_hz && !(band_hz->first > 0.0 && band_hz->second > band_hz->first && std::isfinite(band_hz->second)))
    throw InvalidArgument(
        fmt::format("IdentificationOptions::band_hz {}–{} Hz: the upper frequency must exceed the lower, both > 0",
                    band_hz->first, band_hz->second),
        "e.g. 2500–2650 Hz");
  if (at_hz && !(*at_hz > 0.0 && std::isfinite(*at_hz)))
    throw InvalidArgument(fmt::format("IdentificationOptions::at_hz {} Hz must be > 0", *at_hz),
                          "omit IdentificationOptions::at_hz to read at the mode effect analysis picks");
  if (band_hz && at_hz)
    throw InvalidArgument(
        "IdentificationOptions::at_hz and IdentificationOptions::band_hz both given: the band would ignore "
        "IdentificationOptions::at_hz",
        "give one of them");
  check_fields(identification_fields(), *this, "IdentificationOptions");  // width
  if (filter) filter->check();
  noise.check();
  JointFitOptions f = fit;
  f.filter = filter;
  f.check();
  readout.check();
  verdict.check();
}

JointFile joint_file_of(const Identification& id, const std::vector<std::string>& inputs) {
  JointFile f;
  f.interface = id.route == Route::HolderTool ? JointInterface::HolderTool : JointInterface::SpindleHolder;
  f.parameters = id.identified;
  auto add = [&](const char* key, std::string value) { f.identification.emplace_back(key, std::move(value)); };
  add("equation", id.equation);
  add("method", id.method == IdentificationMethod::Fit ? "band fit (output error, joint_fit.hpp)"
                                                       : "the seed's closed form read at the mode");
  if (id.fit) {
    JointUncertainty u;
    u.confidence = id.fit->confidence;
    u.covariance = id.fit->covariance;
    for (std::size_t k = 0; k < 8; ++k) {
      u.lower[k] = id.fit->intervals[k].lower;
      u.upper[k] = id.fit->intervals[k].upper;
      u.determined[k] = id.fit->intervals[k].determined;
    }
    f.uncertainty = u;
    add("intervals", id.fit->method_description);
    add("parameters_fitted", id.fit->reciprocal ? "6 (k_tf = k_ym, c_tf = c_ym)" : "8");
    add("band_hz", fmt::format("{}–{}", id.fit_band_hz.first, id.fit_band_hz.second));
    add("frequencies", fmt::format("{}", id.fit->points));
    add("residual_ratio", fmt::format("{:.4g}", id.fit->residual_ratio));
  } else {
    add("band_hz", fmt::format("{}–{}", id.seed.band_lo_hz, id.seed.band_hi_hz));
  }
  for (std::size_t s = 0; s < id.g_noise.size(); ++s) {
    const std::string suffix = id.g_noise.size() > 1 ? fmt::format("_{}", s + 1) : "";
    add(("noise_g11" + suffix).c_str(), id.g_noise[s].summary());
    if (!id.b_noise[s].exact()) add(("noise_b11" + suffix).c_str(), id.b_noise[s].summary());
  }
  if (!id.g_noise.empty())
    add("calibration",
        id.g_noise.front().calibration > 0.0
            ? fmt::format("{:g} (σ of each measured FRF's sensitivity, stated; in the intervals)", id.g_noise.front().calibration)
            : std::string("0 (the sensors taken as exact)"));
  add("verdict", to_string(id.verdict.verdict));
  for (std::size_t i = 0; i < inputs.size(); ++i) add(fmt::format("input_{}", i + 1).c_str(), inputs[i]);
  add("toolpoint_version", TOOLPOINT_VERSION);
  return f;
}

JointParameters weighted_median_parameters(const JointSeries& s, double lo, double hi) {
  JointParameters p;
  for (int k = 0; k < 8; ++k) {
    std::vector<std::pair<double, double>> vw;  // value, weight
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s.frequency_hz[i] < lo || s.frequency_hz[i] > hi) continue;
      const double g = s.estimates[i].noise_gain[static_cast<std::size_t>(k)];
      const double v = s.parameters[i][k];
      if (std::isfinite(v)) vw.emplace_back(v, std::isfinite(g) && g > 0.0 ? 1.0 / (g * g) : 0.0);
    }
    if (vw.empty()) continue;
    std::sort(vw.begin(), vw.end());
    double total = 0.0;
    for (const auto& x : vw) total += x.second;
    if (!(total > 0.0)) {
      p[k] = vw[vw.size() / 2].first;
      continue;
    }
    double acc = 0.0;
    for (const auto& x : vw) {
      acc += x.second;
      if (acc >= 0.5 * total) {
        p[k] = x.first;
        break;
      }
    }
  }
  return p;
}

namespace {

struct SetupModel {
  Assembly assembly;
  std::string label;
  std::vector<TwoPort> A;  // per frequency of G11
  BlockSeries B;           // measured or the model's S11
  bool b_measured = true;
};

BlockSeries smoothed(const BlockSeries& s, const std::optional<SavgolOptions>& filter) {
  const SavgolOptions o = filter ? *filter : SavgolOptions{15, 3};
  if (s.size() < static_cast<std::size_t>(o.window)) return s;
  return savgol_filter(s, o, "FRF").series;
}

BlockNoise noise_of(const BlockSeries& s, const std::vector<double>& coherence, const std::string& name, const NoiseSpec& spec,
                    std::vector<std::string>& warnings) {
  BlockNoise n;
  if (spec.source == NoiseSpec::Source::Stated) {
    n = stated_block_noise(s, spec.stated());
  } else {
    try {
      n = estimate_block_noise(s, spec.estimate, name);
    } catch (const InputError& e) {
      throw InputError(e.what(), "state the noise (magnitude and phase σ) when the data are too short to estimate it from");
    }
  }
  if (!coherence.empty()) {
    if (spec.averages > 0) apply_coherence(n, coherence, spec.averages, name);
    else
      warnings.push_back(
          fmt::format("{}: its coherence column is not used: the number of averages behind it is not given "
                      "(NoiseSpec::averages)",
                      name));
  }
  n.calibration = spec.calibration;
  return n;
}

std::vector<std::size_t> in_band(const std::vector<double>& f, double lo, double hi) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f[i] >= lo && f[i] <= hi) idx.push_back(i);
  return idx;
}

BlockSeries subset(const BlockSeries& s, const std::vector<std::size_t>& idx) {
  BlockSeries out;
  for (std::size_t i : idx) {
    out.frequency_hz.push_back(s.frequency_hz[i]);
    out.blocks.push_back(s.blocks[i]);
  }
  return out;
}

void judge(Identification& r, const IdentificationOptions& o, bool same_data) {
  std::vector<std::string> fail, doubt;
  if (same_data) fail.push_back("G11 and B11 are the same data (one file given for both?): nothing to identify the joint from");
  const JointParameters& p = r.identified;
  for (JointParameter k : {JointParameter::k_yf, JointParameter::k_tm})
    if (!(p[k] > 0.0))
      fail.push_back(fmt::format("{} = {:.4g} {} ≤ 0: a joint's diagonal stiffness is positive", JointParameters::name(k), p[k],
                                 JointParameters::unit(k)));
  // A negative diagonal damping fails when it is negative beyond its noise at the verdict's
  // false-alarm level (one-sided); a poorly determined one is doubtful.
  const double z_damping = normal_quantile(1.0 - 0.5 * o.verdict.forward.false_alarm);
  for (JointParameter k : {JointParameter::c_yf, JointParameter::c_tm}) {
    if (p[k] >= 0.0) continue;
    const auto i = static_cast<std::size_t>(k);
    const bool certain = r.fit ? r.fit->intervals[i].estimate + z_damping * r.fit->intervals[i].std_error < 0.0
                               : r.seed.noise_gain[i] <= o.readout.gain_warning;
    (certain ? fail : doubt)
        .push_back(fmt::format("{} = {:.4g} {} < 0: a passive joint does not feed energy in{}", JointParameters::name(k), p[k],
                               JointParameters::unit(k), certain ? "" : " (but it is poorly determined by these data)"));
  }
  if (r.fit) {
    if (!r.fit->converged) fail.push_back("the fit did not converge");
    // With a stated calibration the limits grow by what its factors make at the false-alarm level.
    const double ratio = r.fit->residual_ratio, level = 1.0 - o.verdict.forward.false_alarm;
    const double fail_above = residual_limit(*r.fit, o.verdict.residual_fail, level),
                 doubt_above = residual_limit(*r.fit, o.verdict.residual_doubt, level);
    const std::string calibrated = r.fit->residual_calibration_share > 0.0
                                       ? fmt::format(", the stated calibration's {:.0f} % share of it included",
                                                     100 * r.fit->residual_calibration_share)
                                       : std::string();
    if (std::isfinite(ratio) && ratio > fail_above)
      fail.push_back(
          fmt::format("the fitted model leaves residuals {:.2g}× what the noise explains (fail above {:.3g}{}): the "
                      "model does not describe these data",
                      ratio, fail_above, calibrated));
    else if (std::isfinite(ratio) && ratio > doubt_above)
      doubt.push_back(fmt::format("the fitted model leaves residuals {:.2g}× what the noise explains (doubtful above {:.3g}{})",
                                  ratio, doubt_above, calibrated));
    if (!r.fit->transfers) doubt.push_back("the joint does not transfer between the set-ups");
    for (JointParameter k : {JointParameter::k_yf, JointParameter::k_tm})
      if (!r.fit->intervals[static_cast<std::size_t>(k)].determined)
        doubt.push_back(fmt::format("{} is not determined by these data (its interval is wider than its value or holds 0)",
                                    JointParameters::name(k)));
  } else {
    for (JointParameter k : {JointParameter::k_yf, JointParameter::k_tm})
      if (r.seed.noise_gain[static_cast<std::size_t>(k)] > o.readout.gain_warning)
        doubt.push_back(fmt::format("{} is poorly determined in the read-out band (noise gain {:.3g})", JointParameters::name(k),
                                    r.seed.noise_gain[static_cast<std::size_t>(k)]));
  }
  const bool several = r.forward_checks.size() > 1;
  for (const ForwardCheck& c : r.forward_checks) {
    const std::string who = several ? c.label + ": " : "";
    for (const auto& x : c.failures) fail.push_back(fmt::format("forward check: {}{}", who, x));
    const bool any = std::any_of(c.modes.begin(), c.modes.end(), [](const ModeCheck& m) {
      return m.agreement != ModeAgreement::NotResolved && m.agreement != ModeAgreement::Missing;
    });
    if (!any) doubt.push_back(fmt::format("the forward check {}found no mode the data resolve to compare", who));
  }
  r.verdict.verdict = !fail.empty() ? Verdict::Fail : !doubt.empty() ? Verdict::Doubtful : Verdict::Pass;
  r.verdict.reasons = fail;
  r.verdict.reasons.insert(r.verdict.reasons.end(), doubt.begin(), doubt.end());
}

// Each set-up's assembly (at its overhang), label, the model's A per frequency of its G11 and its B
// (measured, or the model's spindle nose); the model's own remarks, once, into `warnings`.
std::vector<SetupModel> setup_models(const Assembly& assembly, const std::vector<IdentificationData>& data,
                                     const IdentificationOptions& o, std::vector<std::string>& warnings) {
  const bool ht = o.route == Route::HolderTool;
  std::vector<SetupModel> setups;
  for (std::size_t s = 0; s < data.size(); ++s) {
    const IdentificationData& d = data[s];
    SetupModel u;
    u.assembly = d.overhang_m ? with_overhang(assembly, *d.overhang_m) : assembly;
    u.label = !d.label.empty() ? d.label : fmt::format("overhang {:.1f} mm", 1000 * u.assembly.tool.overhang);
    const std::string gname = d.g_name.empty() ? (ht || o.route == Route::SpindleHolderFromSHT ? "SHT11" : "SH11") : d.g_name;
    validate(d.G11, gname, 3);
    const AssemblyModel m(u.assembly);
    // The model's own remarks (a piece computed exactly, …), once: they are the assembly's.
    if (s == 0) {
      const std::vector<std::string> w = m.warnings();  // by value: one vector for both iterators
      warnings.insert(warnings.end(), w.begin(), w.end());
    }
    if (d.B11) {
      validate(*d.B11, d.b_name.empty() ? "B11" : d.b_name, 3);
      require_same_grid(d.B11->frequency_hz, d.b_name.empty() ? "B11" : d.b_name, d.G11.frequency_hz, gname);
      u.B = *d.B11;
    } else if (ht) {
      throw InputError(fmt::format("{}: Eq. (6) needs the measured SH11 (holder tip, tool outside removed) as well as SHT11",
                                   u.label),
                       "give SH11 with SHT11");
    } else {
      u.B = block_series(d.G11.frequency_hz, [&](double f) { return m.spindle_nose(f); });
      u.b_measured = false;
    }
    for (double f : d.G11.frequency_hz)
      u.A.push_back(ht ? m.tool(f) : o.route == Route::SpindleHolderFromSH ? m.holder(f) : m.holder_tool(f));
    setups.push_back(std::move(u));
  }
  return setups;
}

// The band the joint is read in (and fitted in, without band_hz): given, or around a frequency
// given, the mode that moves most with the overhang, or the model's dominant mode (effect analysis)
// moved to the nearest peak of the smoothed G11.
ModeChoice choose_mode(const IdentificationOptions& o, const Assembly& assembly, const std::vector<double>& frequency_hz,
                       const BlockSeries& G0s, const std::string& g0, std::vector<std::string>& warnings) {
  ModeChoice mc;
  if (o.band_hz) {
    mc.method = "band given";
    mc.lo_hz = o.band_hz->first;
    mc.hi_hz = o.band_hz->second;
    mc.center_hz = 0.5 * (mc.lo_hz + mc.hi_hz);
  } else {
    if (o.at_hz) {
      mc.method = "frequency given";
      mc.center_hz = *o.at_hz;
    } else if (!o.overhang_frfs.empty()) {
      std::vector<FrfSeries> frfs{entry(G0s, 0)};
      frfs.insert(frfs.end(), o.overhang_frfs.begin(), o.overhang_frfs.end());
      mc.overhang = overhang_mode(frfs, 0);
      mc.method = "mode that moves most with the overhang";
      mc.center_hz = mc.overhang->reference_peaks[mc.overhang->dominant].frequency_hz;
    } else {
      mc.effect = effect_analysis(assembly, o.route, frequency_hz);
      mc.method = "effect analysis on the model";
      const double model_f = mc.effect->modes[mc.effect->dominant].frequency_hz;
      const auto peaks = find_peaks(entry(G0s, 0), PeakOptions{0.1});
      mc.center_hz = model_f;
      if (peaks.empty())
        warnings.push_back(
            fmt::format("{}: no resonance peak in |H|: the band is centred on the model's mode at {:.1f} Hz", g0, model_f));
      else
        mc.center_hz = std::min_element(peaks.begin(), peaks.end(), [&](const Peak& x, const Peak& y) {
                         return std::abs(x.frequency_hz - model_f) < std::abs(y.frequency_hz - model_f);
                       })->frequency_hz;
    }
    mc.lo_hz = mc.center_hz * (1.0 - o.width);
    mc.hi_hz = mc.center_hz * (1.0 + o.width);
  }
  return mc;
}

// Every set-up on all its frequencies with its noise, as the forward check sees it.
std::vector<JointFitData> fit_data(const std::vector<SetupModel>& setups, const std::vector<IdentificationData>& data,
                                   const std::vector<BlockNoise>& g_noise, const std::vector<BlockNoise>& b_noise) {
  std::vector<JointFitData> full;
  for (std::size_t s = 0; s < setups.size(); ++s) {
    JointFitData x;
    x.label = setups[s].label;
    x.A = setups[s].A;
    x.G11 = data[s].G11;
    x.B11 = setups[s].B;
    x.g_name = data[s].g_name.empty() ? "G11" : data[s].g_name;
    x.b_name = data[s].b_name.empty() ? (setups[s].b_measured ? "B11" : "S11 (model)") : data[s].b_name;
    x.g_noise = g_noise[s];
    x.b_noise = b_noise[s];
    full.push_back(std::move(x));
  }
  return full;
}

// The band fit (joint_fit.hpp) on each set-up's band, from the seed's read-out, the closed form's
// weighted medians and the assembly's joint (the finite ones): r.fit_band_hz, r.fit, r.identified.
void fit_in_band(Identification& r, const Assembly& assembly, const std::vector<SetupModel>& setups,
                 const std::vector<JointFitData>& full, const IdentificationOptions& o, bool have_closed_form,
                 const ProgressCallback& report) {
  const bool ht = o.route == Route::HolderTool;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  std::vector<JointFitData> fd;
  for (std::size_t s = 0; s < setups.size(); ++s) {
    const auto& f = full[s].G11.frequency_hz;
    if (!o.band_hz) {
      fd.push_back(full[s]);
    } else {
      const auto idx = in_band(f, o.band_hz->first, o.band_hz->second);
      if (idx.empty())
        throw InvalidArgument(fmt::format("{}: the band {}–{} Hz holds none of the data's frequencies ({}–{} Hz)",
                                          setups[s].label, o.band_hz->first, o.band_hz->second, f.front(), f.back()),
                              "choose a band inside the data's frequency range");
      JointFitData x = full[s];
      x.G11 = subset(full[s].G11, idx);
      x.B11 = subset(full[s].B11, idx);
      x.A.clear();
      for (std::size_t i : idx) x.A.push_back(full[s].A[i]);
      x.g_noise = full[s].g_noise.subset(idx);
      x.b_noise = full[s].b_noise.subset(idx);
      fd.push_back(std::move(x));
    }
    lo = std::min(lo, fd.back().G11.frequency_hz.front());
    hi = std::max(hi, fd.back().G11.frequency_hz.back());
  }
  r.fit_band_hz = {lo, hi};
  std::vector<JointParameters> starts;
  auto finite = [](const JointParameters& p) {
    for (int k = 0; k < 8; ++k)
      if (!std::isfinite(p[k])) return false;
    return p.k_yf != 0.0 || p.k_tm != 0.0;
  };
  if (have_closed_form) {
    starts.push_back(r.seed.medians());
    starts.push_back(weighted_median_parameters(r.closed_form, lo, hi));
  }
  const Joint& trial = ht ? assembly.holder_tool : assembly.spindle_holder;
  if (!trial.rigid) starts.push_back(trial.parameters);
  starts.erase(std::remove_if(starts.begin(), starts.end(), [&](const JointParameters& p) { return !finite(p); }), starts.end());
  if (starts.empty())
    throw InvalidArgument(
        fmt::format("the fit has no starting values: the closed form failed and joints.{} is rigid in the assembly",
                    ht ? "holder_tool" : "spindle_holder"),
        "give the joint trial values in the assembly file");
  JointFitOptions fo = o.fit;
  fo.filter = o.filter;
  fo.shared_calibration = o.noise.calibration_shared;
  if (report) fo.progress = [&](double x) { report(0.3 + 0.6 * x); };  // the fit is 30–90 % of the study
  r.fit = fit_joint(fd, starts, fo);
  r.identified = r.fit->parameters;
  for (const auto& w : r.fit->warnings)
    if (std::find(r.warnings.begin(), r.warnings.end(), w) == r.warnings.end()) r.warnings.push_back(w);
}

}  // namespace

Identification run_identification_study(const Assembly& assembly, const std::vector<IdentificationData>& data,
                                        const IdentificationOptions& o, const ProgressCallback& report) {
  o.check();
  if (data.empty()) throw InvalidArgument("identification: no measured FRFs given");
  auto progress = [&](double x) {
    if (report) report(x);
  };
  const bool ht = o.route == Route::HolderTool;
  Identification r;
  r.route = o.route;
  r.method = o.method;
  r.equation = ht ? "Eq. (6) from Eq. (5): A = T (tool, model), B11 = SH11, G11 = SHT11"
               : o.route == Route::SpindleHolderFromSH
                   ? "Eq. (15): A = H (holder with shank, model), B11 = S11, G11 = SH11"
                   : "Eq. (18): A = HT (holder + tool through the assembly's K_ht, model), B11 = S11, G11 = SHT11";

  // Each set-up's model and data.
  const std::vector<SetupModel> setups = setup_models(assembly, data, o, r.warnings);
  progress(0.05);
  const IdentificationData& d0 = data.front();
  const SetupModel& s0 = setups.front();
  const std::string g0 = d0.g_name.empty() ? "G11" : d0.g_name,
                    b0 = d0.b_name.empty() ? (s0.b_measured ? "B11" : "S11 (model spindle)") : d0.b_name;

  // The seed: closed form on (filtered) data, read in the band at the mode.
  const BlockSeries G0f = o.filter ? savgol_filter(d0.G11, *o.filter, g0).series : d0.G11;
  const BlockSeries B0f = o.filter && s0.b_measured ? savgol_filter(s0.B, *o.filter, b0).series : s0.B;
  bool have_closed_form = true;
  try {
    const std::vector<TwoPort>& A0 = s0.A;
    const auto& f0 = d0.G11.frequency_hz;
    r.closed_form = identify_series(
        [&](double f) { return A0[static_cast<std::size_t>(std::lower_bound(f0.begin(), f0.end(), f) - f0.begin())]; }, B0f, b0,
        G0f, g0);
  } catch (const NumericalError& e) {
    if (o.method == IdentificationMethod::Seed) throw;
    have_closed_form = false;
    r.warnings.push_back(
        fmt::format("the closed form failed ({}): no seed read-out; the fit starts from the assembly's joint values", e.what()));
  }
  progress(0.15);
  const BlockSeries G0s = smoothed(d0.G11, o.filter);
  r.mode = choose_mode(o, s0.assembly, d0.G11.frequency_hz, G0s, g0, r.warnings);
  if (have_closed_form) {
    r.seed = band_readout(r.closed_form, r.mode.lo_hz, r.mode.hi_hz, o.readout);
    for (const auto& w : r.seed.warnings) r.warnings.push_back("seed read-out: " + w);
  }
  progress(0.25);

  // Noise of every measured series (the fit's weights and bootstrap; the verdict reads its warnings).
  for (std::size_t s = 0; s < setups.size(); ++s) {
    r.g_noise.push_back(
        noise_of(data[s].G11, data[s].g_coherence, data[s].g_name.empty() ? "G11" : data[s].g_name, o.noise, r.warnings));
    r.b_noise.push_back(setups[s].b_measured ? noise_of(setups[s].B, data[s].b_coherence,
                                                        data[s].b_name.empty() ? "B11" : data[s].b_name, o.noise, r.warnings)
                                             : exact_block_noise());
  }
  for (const auto* v : {&r.g_noise, &r.b_noise})
    for (const BlockNoise& n : *v) r.warnings.insert(r.warnings.end(), n.warnings.begin(), n.warnings.end());

  // Every set-up on all its frequencies, as the forward check sees it; the fit takes the band.
  const std::vector<JointFitData> full = fit_data(setups, data, r.g_noise, r.b_noise);

  if (o.method == IdentificationMethod::Fit) fit_in_band(r, assembly, setups, full, o, have_closed_form, report);
  else r.identified = r.seed.medians();
  progress(0.9);

  // Forward check of every set-up: the same smoothing on data and prediction, judged against the noise.
  {
    ForwardCheckOptions fc = o.verdict.forward;
    fc.smoothing = o.filter;
    fc.seed = o.fit.seed;
    fc.parallel = o.fit.parallel;
    fc.shared_calibration = o.noise.calibration_shared;
    const std::optional<Eigen::Matrix<double, 8, 8>> cov = r.fit ? std::optional(r.fit->covariance)
                                                                 : std::optional<Eigen::Matrix<double, 8, 8>>();
    for (const JointFitData& x : full) r.forward_checks.push_back(check_forward(x, r.identified, fc, cov));
  }
  judge(r, o, s0.b_measured && s0.B.blocks == d0.G11.blocks);
  progress(1.0);
  return r;
}

}  // namespace toolpoint
