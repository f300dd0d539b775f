// toolpoint: the expected precision of a joint before the tap test (studies/precision.hpp).
#include "toolpoint/studies/precision.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/error.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/statistics.hpp"

namespace toolpoint {

void TapNoise::check() const {
  check_fields(tap_noise_fields(), *this, "TapNoise");
  if (sigma == 0.0 && floor == 0.0)
    throw InvalidArgument("TapNoise::sigma and TapNoise::floor are both 0: exact data leave no uncertainty to predict",
                          "state the noise of one hit, e.g. TapNoise::sigma 0.01");
}

const std::vector<OptionField<TapNoise>>& tap_noise_fields() {
  using O = TapNoise;
  using K = FieldKind;
  // The floor and the calibration are the measured-noise model's (NoiseOptions): their ranges, in a
  // planned test's words.
  const auto noise = [](const char* name, const char* help) { return with_help(option_field(noise_fields(), name).spec, help); };
  static const std::vector<OptionField<O>> fields = {
      {{.name = "sigma",
        .kind = K::Real,
        .min = 0.0,
        .max = 0.5,
        .help = "one hit's variation, relative, magnitude and phase alike (0.01 = 1 %)",
        .cli_name = "sigma"},
       [](O& o) -> double& { return o.sigma; }},
      {noise("floor", "one hit's additive floor: σ of each part relative to each FRF's peak (0.001 = 0.1 %)"),
       [](O& o) -> double& { return o.floor; }},
      {{.name = "averages",
        .kind = K::Integer,
        .min = 1.0,
        .max = 100000.0,
        .help = "hits averaged per FRF",
        .cli_name = "averages"},
       nullptr,
       [](O& o) -> int& { return o.averages; }},
      {noise("calibration", "σ of each tap test's calibration factor (one hammer, one sensor; 0.02 = 2 %)"),
       [](O& o) -> double& { return o.calibration; }},
      {{.name = "shared_calibration",
        .kind = K::Flag,
        .help = "one sensor chain for both tap tests: one calibration factor for both",
        .cli_name = "calibration-shared"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.shared_calibration; }}};
  return fields;
}

void PrecisionOptions::check() const {
  noise.check();
  const bool sht = route != Route::SpindleHolderFromSH, sh = route != Route::SpindleHolderFromSHT;
  auto test = [](const TapTestOptions& t, const char* name) {
    if (!(t.spacing_m > 0.0))
      throw InvalidArgument(fmt::format("PrecisionOptions::{}.spacing_m must be given (> 0) for this route", name),
                            "the distance between neighbouring points of that tap test [m], e.g. 0.015");
    TapTestOptions c = t;
    c.sigma = 0.0;
    try {
      c.check();
    } catch (const InvalidArgument& e) {
      std::string what = e.what();
      const std::string from = "TapTestOptions::", to = fmt::format("PrecisionOptions::{}.", name);
      for (std::size_t at = what.find(from); at != std::string::npos; at = what.find(from)) what.replace(at, from.size(), to);
      throw InvalidArgument(what, e.hint());
    }
  };
  if (sht) test(tool, "tool");
  if (sh) test(holder, "holder");
  check_fields(precision_fields(), *this, "PrecisionOptions");
  if (target && !(*target > 0.0 && *target < 1.0))
    throw InvalidArgument(fmt::format("PrecisionOptions::target = {} must lie in (0, 1) (a relative half-width)", *target),
                          "e.g. 0.01 for ±1 %");
}

const std::vector<OptionField<PrecisionOptions>>& precision_fields() {
  using O = PrecisionOptions;
  using K = FieldKind;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "reciprocal",
        .kind = K::Flag,
        .help = "six parameters (k_θf = k_ym, c_θf = c_ym), as the identification's default; else eight"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.reciprocal; }},
      {{.name = "confidence",
        .kind = K::Real,
        .min = 0.5,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "confidence level of the expected intervals"},
       [](O& o) -> double& { return o.confidence; }}};
  return fields;
}

BlockNoise tap_test_block_noise(const PointFrfs& frfs, const RotationalOptions& fd, const TapNoise& noise,
                                const BlockSeries& block) {
  noise.check();
  const RotationalResult base = rotational_frfs(frfs, fd);
  const std::size_t n = base.block.size();
  if (block.size() != n) throw InvalidArgument("tap_test_block_noise: the block and the tap test have different grids");
  std::vector<Cov8> sigma(n, Cov8::Zero());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!frfs.h[i][j]) continue;
      const FrfSeries& h = *frfs.h[i][j];
      double peak = 0.0;
      for (const Complex& v : h.values) peak = std::max(peak, std::abs(v));
      // Two real directions of H_ij: the block's response to each, per frequency (exact for the
      // linear differences; the N·L/H00 approximation of P linearised at a 1e-7 relative step).
      const double step = 1e-7 * peak;
      std::array<RotationalResult, 2> moved;
      for (int part = 0; part < 2; ++part) {
        PointFrfs p = frfs;
        for (Complex& v : p.h[i][j]->values) v += part == 0 ? Complex(step, 0.0) : Complex(0.0, step);
        moved[static_cast<std::size_t>(part)] = rotational_frfs(p, fd);
      }
      for (std::size_t k = 0; k < n; ++k) {
        const double var = (noise.sigma * noise.sigma * std::norm(h.values[k]) / 2.0 + std::pow(noise.floor * peak, 2)) /
                           static_cast<double>(noise.averages);
        for (int part = 0; part < 2; ++part) {
          const Vec8 d = vec8((moved[static_cast<std::size_t>(part)].block.blocks[k] - base.block.blocks[k]) / step);
          sigma[k].noalias() += var * d * d.transpose();
        }
      }
    }
  // As a relative covariance about the block's values: C = R⁻¹ Σ R⁻ᵀ (R block diagonal, one
  // rotation-and-scale per entry; an entry that is zero carries no relative noise).
  BlockNoise out;
  out.relative.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    // R(x)⁻¹ = R(1/x) entry by entry.
    Block inverse = Block::Zero();
    for (int e = 0; e < 4; ++e) {
      const Complex x = block.blocks[k](e / 2, e % 2);
      if (std::abs(x) > 0.0) inverse(e / 2, e % 2) = 1.0 / x;
    }
    const Cov8 rinv = polar_frame(inverse);
    out.relative[k] = rinv * sigma[k] * rinv.transpose();
  }
  out.calibration = noise.calibration;
  out.source = fmt::format("the tap test's noise carried through its finite differences: σ {:g} % per hit{}, {} average{}",
                           100 * noise.sigma,
                           noise.floor > 0.0 ? fmt::format(", a floor of {:g} % of each FRF's peak", 100 * noise.floor) : "",
                           noise.averages, noise.averages == 1 ? "" : "s");
  out.residual_correlation = std::numeric_limits<double>::quiet_NaN();
  finish_block_noise(out);
  return out;
}

namespace {

// The exact station FRFs of a tap test on the model, as a PointFrfs, and the differences that make
// its block.
struct PlannedTest {
  PointFrfs frfs;
  RotationalOptions fd;
  std::string description;
};

PlannedTest planned(const Assembly& assembly, const TapTestOptions& t, const char* what) {
  TapTestOptions exact = t;
  exact.sigma = 0.0;
  exact.floor = 0.0;
  exact.averages = 0;
  exact.calibration = 0.0;
  const TapTest tap = run_tap_test_study(assembly, exact);
  PlannedTest p;
  for (const TapTestFrf& h : tap.frfs) p.frfs.set(h.response, h.hammer, h.frf);
  p.fd.order = t.points - 1;
  p.fd.spacing = t.spacing_m;
  p.fd.shear_stiffness = tap.shear_stiffness_n;
  p.fd.assume_reciprocity = t.hammer == HammerPlan::Tip;
  p.description = fmt::format("{}: {}, {} points {:g} mm apart, hammer {}", what, tap_side_name(t.side), t.points,
                              1000 * t.spacing_m, hammer_plan_name(t.hammer));
  return p;
}

}  // namespace

PrecisionStudy run_precision_study(const Assembly& assembly, const PrecisionOptions& o, const ProgressCallback& progress) {
  o.check();
  auto report = [&](double x) {
    if (progress) progress(x);
  };
  const bool ht = o.route == Route::HolderTool;
  const bool measure_sht = o.route != Route::SpindleHolderFromSH, measure_sh = o.route != Route::SpindleHolderFromSHT;
  const Joint& joint = ht ? assembly.holder_tool : assembly.spindle_holder;
  if (joint.rigid)
    throw InvalidArgument(fmt::format("joints.{} is rigid in the assembly: the study needs the joint's trial values",
                                      ht ? "holder_tool" : "spindle_holder"),
                          "give the joint's expected stiffness and damping in the assembly file");
  const AssemblyModel model(assembly);
  const std::vector<double> f = assembly.grid.values();
  PrecisionStudy r;
  r.route = o.route;
  r.confidence = o.confidence;
  r.averages = o.noise.averages;
  r.target = o.target;
  r.warnings = model.warnings();

  JointFitData d;
  d.label = "planned test";
  for (double x : f)
    d.A.push_back(ht ? model.tool(x) : o.route == Route::SpindleHolderFromSH ? model.holder(x) : model.holder_tool(x));
  const BlockSeries sht = measure_sht ? model.tool_point(f) : BlockSeries{};
  const BlockSeries sh = measure_sh ? model.holder_tip(f) : BlockSeries{};
  d.G11 = o.route == Route::SpindleHolderFromSH ? sh : sht;
  d.g_name = o.route == Route::SpindleHolderFromSH ? "SH11" : "SHT11";
  report(0.1);
  auto noise_of = [&](const TapTestOptions& t, const BlockSeries& block, const char* what) {
    const PlannedTest p = planned(assembly, t, what);
    r.measured.push_back(p.description);
    return tap_test_block_noise(p.frfs, p.fd, o.noise, block);
  };
  d.g_noise = noise_of(o.route == Route::SpindleHolderFromSH ? o.holder : o.tool, d.G11, d.g_name.c_str());
  if (ht) {
    d.B11 = sh;
    d.b_name = "SH11";
    d.b_noise = noise_of(o.holder, sh, "SH11");
  } else {
    d.B11 = block_series(f, [&](double x) { return model.spindle_nose(x); });
    d.b_name = "S11 (model)";
    d.b_noise = exact_block_noise();
  }
  report(0.5);
  JointFitOptions fo;
  fo.uncertainty = UncertaintyMethod::Linearised;
  fo.reciprocal = o.reciprocal;
  fo.confidence = o.confidence;
  fo.shared_calibration = o.noise.shared_calibration;
  fo.check_linearisation = false;  // the linearised prediction itself (the study's Monte Carlo test checks it)
  const JointFit fit = fit_joint({d}, {joint.parameters}, fo);
  r.fit_description = fit.method_description;
  r.warnings.insert(r.warnings.end(), fit.warnings.begin(), fit.warnings.end());
  const double z = normal_quantile(0.5 + 0.5 * o.confidence);
  for (std::size_t k = 0; k < 8; ++k) {
    ParameterPrecision& p = r.parameters[k];
    p.value = joint.parameters[static_cast<int>(k)];
    const double se = fit.intervals[k].std_error, se_cal = fit.calibration_std_error[k];
    p.half_width = z * se;
    p.relative = std::abs(p.value) > 0.0 ? p.half_width / std::abs(p.value) : std::numeric_limits<double>::infinity();
    p.calibration_half_width = z * se_cal;
    p.free = fit.intervals[k].free;
    if (o.target && std::abs(p.value) > 0.0) {
      // SE² = a/n + b: the noise's share at the stated averages scaled to one hit.
      const double a = std::max(0.0, se * se - se_cal * se_cal) * static_cast<double>(o.noise.averages);
      const double want = *o.target * std::abs(p.value) / z, room = want * want - se_cal * se_cal;
      if (room > 0.0) p.averages_for_target = std::max(1, static_cast<int>(std::ceil(a / room)));
    }
  }
  report(1.0);
  return r;
}

}  // namespace toolpoint
