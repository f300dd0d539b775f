// toolpoint: closed-form joint identification (seed Eq. 5 → 6, 15, 18), read-out, mode choice.
#include "toolpoint/identify/identify.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/model/coupling.hpp"
#include "complex_pairs.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

JointEstimate identify_joint(const TwoPort& A, const Block& B11, const Block& G11, bool diagnostics) {
  using detail::both;
  using detail::cols;
  using detail::Cols;
  JointEstimate e;
  const Block D = A.b11 - G11;
  const Cols dinv = detail::inverse_checked(cols(D), "A11 − G11 (the component's free–free tip receptance minus the assembly's)");
  const Cols a12 = cols(A.b12);
  const Cols left = cols(A.b21) * dinv, right = dinv * a12;
  const Cols xinv = left * a12;
  const Block Kinv = detail::block(xinv - cols(A.b22) - cols(B11));
  // K⁻¹ is the difference X⁻¹ − A22 − B11 of much larger terms when the joint is stiff: below
  // 1e-12 of them it is round-off, and the joint effectively rigid for these data.
  e.flexibility_share = Kinv.norm() / (detail::block(xinv).norm() + A.b22.norm() + B11.norm());
  if (!std::isfinite(e.flexibility_share))  // inf/inf: an overflow, not a rigid joint
    throw NumericalError(fmt::format("the joint flexibility K⁻¹ = X⁻¹ − A22 − B11 is out of the range of double precision "
                                     "(‖K⁻¹‖ = {:.3g}, ‖A22‖ = {:.3g}, ‖B11‖ = {:.3g})",
                                     Kinv.norm(), A.b22.norm(), B11.norm()),
                         "check the magnitudes and units of the FRFs (m/N, 1/N, rad/(N m)) and the component model");
  if (!(e.flexibility_share > 1e-12))
    throw NumericalError(
        fmt::format("the joint flexibility K⁻¹ = X⁻¹ − A22 − B11 is {:.2g} of the terms it is the difference of: "
                    "lost in round-off, the joint is effectively rigid for these data",
                    e.flexibility_share),
        "a rigid connection has no stiffness to identify; if the joint is not rigid, the FRFs do not see it");
  const Cols k = detail::inverse_checked(cols(Kinv), "joint flexibility K⁻¹");
  e.K = detail::block(k);
  if (!diagnostics) return e;
  const double nD = D.squaredNorm(), nK = Kinv.squaredNorm();  // Frobenius, squared
  e.cond_difference = std::sqrt(nD) * detail::block(dinv).norm();
  e.cond_flexibility = std::sqrt(nK) * e.K.norm();
  e.cond_A12 = frobenius_condition(A.b12);
  const Cols L = k * left, R = right * k;
  // Noise gains, both rows r of K at once (lane r): a real relative error ε_q on entry q moves
  // K_rc by ε_q·coef_q, coef = L_ra R_bc G_ab or K_ra K_bc B_ab; Re and Im add separately (summed
  // over a, then b, as written in the docs). Few values live at a time: SSE2 has 16 registers.
  using detail::CPair;
  using detail::Lanes;
  Lanes sre[2] = {{0.0, 0.0}, {0.0, 0.0}}, sim[2] = {{0.0, 0.0}, {0.0, 0.0}};
  for (int a = 0; a < 2; ++a) {
    const CPair& La = a == 0 ? L.c0 : L.c1;
    const CPair& Ka = a == 0 ? k.c0 : k.c1;
    for (int b = 0; b < 2; ++b) {
      const CPair g = both(G11(a, b)), bb = both(B11(a, b));
      for (int c = 0; c < 2; ++c) {
        const CPair cg = La * both(detail::lane(c == 0 ? R.c0 : R.c1, b)) * g;
        const CPair cb = Ka * both(e.K(b, c)) * bb;
        sre[c] += cg.re * cg.re + cb.re * cb.re;
        sim[c] += cg.im * cg.im + cb.im * cb.im;
      }
    }
  }
  // Relative to the parameter; an off-diagonal one (k_ym, k_θf and their c) no smaller than 10 %
  // of the diagonal's geometric mean sqrt|K_yf K_θm| (of the same part, Re or Im) — its natural
  // scale (a coupling term that size changes det K by 1 %): a coupling term that is zero has no
  // relative error, only one against that scale.
  const double re_scale = 0.1 * std::sqrt(std::abs(e.K(0, 0).real() * e.K(1, 1).real()));
  const double im_scale = 0.1 * std::sqrt(std::abs(e.K(0, 0).imag() * e.K(1, 1).imag()));
  for (int c = 0; c < 2; ++c) {
    // Both rows' quotients in one vector division each (the same IEEE quotients as one by one).
    const Lanes re{std::max(std::abs(e.K(0, c).real()), c == 0 ? 0.0 : re_scale),
                   std::max(std::abs(e.K(1, c).real()), c == 1 ? 0.0 : re_scale)},
        im{std::max(std::abs(e.K(0, c).imag()), c == 0 ? 0.0 : im_scale),
           std::max(std::abs(e.K(1, c).imag()), c == 1 ? 0.0 : im_scale)};
    const Lanes gre = Lanes{std::sqrt(sre[c][0]), std::sqrt(sre[c][1])} / re,
                gim = Lanes{std::sqrt(sim[c][0]), std::sqrt(sim[c][1])} / im;
    for (int r = 0; r < 2; ++r) {
      const auto stiffness = static_cast<std::size_t>(JointParameters::stiffness_of(r, c));
      const auto damping = static_cast<std::size_t>(JointParameters::damping_of(r, c));
      e.noise_gain[stiffness] = re[r] > 0.0 ? gre[r] : std::numeric_limits<double>::infinity();
      e.noise_gain[damping] = im[r] > 0.0 ? gim[r] : std::numeric_limits<double>::infinity();
    }
  }
  return e;
}

JointSeries identify_series(const std::function<TwoPort(double)>& A, const BlockSeries& B11, const std::string& b_name,
                            const BlockSeries& G11, const std::string& g_name) {
  validate(B11, b_name, 3);
  validate(G11, g_name, 3);
  require_same_grid(B11.frequency_hz, b_name, G11.frequency_hz, g_name);
  JointSeries s;
  s.frequency_hz = G11.frequency_hz;
  s.estimates.reserve(s.size());
  s.parameters.reserve(s.size());
  for (std::size_t i = 0; i < G11.size(); ++i) {
    const double f = G11.frequency_hz[i];
    try {
      s.estimates.push_back(identify_joint(A(f), B11.blocks[i], G11.blocks[i]));
    } catch (const NumericalError& e) {
      throw NumericalError(fmt::format("identification at {} Hz: {}", f, e.what()), e.hint());
    }
    s.parameters.push_back(parameters_from_stiffness(s.estimates.back().K, f));
  }
  return s;
}

JointParameters JointReadout::medians() const {
  JointParameters p;
  for (int i = 0; i < 8; ++i) p[i] = parameters[static_cast<std::size_t>(i)].median;
  return p;
}

void ReadoutOptions::check() const { check_fields(readout_fields(), *this, "ReadoutOptions"); }

const std::vector<OptionField<ReadoutOptions>>& readout_fields() {
  using O = ReadoutOptions;
  constexpr double kNever = std::numeric_limits<double>::infinity();  // a level never exceeded: no warning
  static const std::vector<OptionField<O>> fields = {
      {{.name = "cond_warning",
        .kind = FieldKind::Real,
        .min = 1.0,
        .min_open = true,
        .automatic = kNever,
        .note = "inf: never warn",
        .help = "warn when cond(A11 − G11) exceeds this in the band"},
       [](O& o) -> double& { return o.cond_warning; }},
      {{.name = "reciprocity_warning",
        .kind = FieldKind::Real,
        .min = 0.0,
        .min_open = true,
        .automatic = kNever,
        .note = "inf: never warn",
        .help = "warn when k_ym and k_θf (or c) differ by more than this fraction"},
       [](O& o) -> double& { return o.reciprocity_warning; }},
      {{.name = "gain_warning",
        .kind = FieldKind::Real,
        .min = 0.0,
        .min_open = true,
        .automatic = kNever,
        .note = "inf: never warn",
        .help = "warn when a parameter's noise gain exceeds this (20: a 5 % FRF error moves it by 100 %)"},
       [](O& o) -> double& { return o.gain_warning; }}};
  return fields;
}

namespace {

double median_of(std::vector<double> v) {
  const std::size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  const double hi = v[n / 2];
  if (n % 2) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2)));
}

// |a − b| relative to the larger, or to `floor` when both are smaller (a coupling term near zero).
double relative_difference(double a, double b, double floor) {
  const double m = std::max({std::abs(a), std::abs(b), floor});
  return m > 0.0 ? std::abs(a - b) / m : 0.0;
}

}  // namespace

JointReadout band_readout(const JointSeries& s, double lo, double hi, const ReadoutOptions& options) {
  options.check();
  JointReadout r;
  r.band_lo_hz = lo;
  r.band_hi_hz = hi;
  std::array<std::vector<double>, 8> vals, gains;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.frequency_hz[i] < lo || s.frequency_hz[i] > hi) continue;
    for (int k = 0; k < 8; ++k) {
      vals[static_cast<std::size_t>(k)].push_back(s.parameters[i][k]);
      gains[static_cast<std::size_t>(k)].push_back(s.estimates[i].noise_gain[static_cast<std::size_t>(k)]);
    }
    r.max_cond_difference = std::max(r.max_cond_difference, s.estimates[i].cond_difference);
    r.max_cond_flexibility = std::max(r.max_cond_flexibility, s.estimates[i].cond_flexibility);
  }
  r.points = vals[0].size();
  if (r.points == 0)
    throw InvalidArgument(fmt::format("read-out band {}–{} Hz holds no frequency point of the data ({}–{} Hz)", lo, hi,
                                      s.frequency_hz.empty() ? 0.0 : s.frequency_hz.front(),
                                      s.frequency_hz.empty() ? 0.0 : s.frequency_hz.back()),
                          "choose a band inside the data's frequency range");
  for (std::size_t k = 0; k < 8; ++k) {
    ParameterReadout& p = r.parameters[k];
    p.median = median_of(vals[k]);
    std::vector<double> dev;
    for (double v : vals[k]) dev.push_back(std::abs(v - p.median));
    p.spread = 1.4826 * median_of(dev);
    p.min = *std::min_element(vals[k].begin(), vals[k].end());
    p.max = *std::max_element(vals[k].begin(), vals[k].end());
    r.noise_gain[k] = median_of(gains[k]);
    p.determined = r.noise_gain[k] <= options.gain_warning && p.spread <= std::abs(p.median);
  }
  // Against the off-diagonal's natural scale too (10 % of sqrt|k_yf k_θm|), as the noise gain.
  using P = JointParameter;
  const auto median = [&](P p) { return r.parameters[static_cast<std::size_t>(p)].median; };
  r.reciprocity_k = relative_difference(median(P::k_ym), median(P::k_tf),
                                        0.1 * std::sqrt(std::abs(median(P::k_yf) * median(P::k_tm))));
  r.reciprocity_c = relative_difference(median(P::c_ym), median(P::c_tf),
                                        0.1 * std::sqrt(std::abs(median(P::c_yf) * median(P::c_tm))));
  if (r.max_cond_difference > options.cond_warning)
    r.warnings.push_back(
        fmt::format("cond(A11 − G11) reaches {:.3g} in the band: a 1 % error in the measured FRF can move "
                    "K by up to that factor; check the band sits on the joint's dominant mode",
                    r.max_cond_difference));
  if (r.reciprocity_k > options.reciprocity_warning)
    r.warnings.push_back(
        fmt::format("k_ym = {:.4g} and k_tf = {:.4g} differ by {:.0f} %: finite-difference error in L/N or a "
                    "non-linear joint (seed Section 2.2)",
                    median(P::k_ym), median(P::k_tf), 100 * r.reciprocity_k));
  if (r.reciprocity_c > options.reciprocity_warning)
    r.warnings.push_back(fmt::format("c_ym = {:.4g} and c_tf = {:.4g} differ by {:.0f} %", median(P::c_ym), median(P::c_tf),
                                     100 * r.reciprocity_c));
  for (int k = 0; k < 8; ++k) {
    const auto& p = r.parameters[static_cast<std::size_t>(k)];
    const double gain = r.noise_gain[static_cast<std::size_t>(k)];
    if (gain > options.gain_warning)
      r.warnings.push_back(
          fmt::format("{}: noise gain {:.3g} — a 1 % error in the FRFs moves it by about {:.3g} %: poorly "
                      "determined by measured data in this band",
                      JointParameters::name(k), gain, gain));
    else if (r.points >= 3 && p.spread > std::abs(p.median))
      r.warnings.push_back(fmt::format("{}: spread {:.3g} exceeds the value {:.3g} {} — undetermined by these data in this band",
                                       JointParameters::name(k), p.spread, p.median, JointParameters::unit(k)));
  }
  if (r.points < 3) r.warnings.push_back(fmt::format("only {} point(s) in the read-out band", r.points));
  return r;
}

// ---- Mode choice --------------------------------------------------------------------------------

namespace {

std::vector<Peak> model_peaks(const Assembly& a, bool tool_point, const std::vector<double>& f) {
  const AssemblyModel m(a);
  auto at = [&](double x) { return tool_point ? m.tool_point(x) : m.holder_tip(x); };
  const BlockSeries s = tool_point ? m.tool_point(f) : m.holder_tip(f);
  return find_peaks(entry(s, 0), PeakOptions{}, [&](double x) { return std::abs(at(x)(0, 0)); });
}

// Index of the peak in `peaks` nearest to frequency f.
std::size_t nearest(const std::vector<Peak>& peaks, double f) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < peaks.size(); ++i)
    if (std::abs(peaks[i].frequency_hz - f) < std::abs(peaks[best].frequency_hz - f)) best = i;
  return best;
}

}  // namespace

EffectAnalysis effect_analysis(const Assembly& assembly, Route route, const std::vector<double>& f, double step) {
  const bool holder_tool = route == Route::HolderTool, tool_point_frf = route != Route::SpindleHolderFromSH;
  const Joint& j = holder_tool ? assembly.holder_tool : assembly.spindle_holder;
  const char* which = holder_tool ? "holder_tool" : "spindle_holder";
  if (j.rigid)
    throw InvalidArgument(fmt::format("effect analysis needs trial values for joints.{} (it is rigid in the assembly file)",
                                      which),
                          "give the joint estimated stiffness and damping values in the assembly file");
  if (!(step > 0.0 && step < 1.0)) throw InvalidArgument(fmt::format("effect-analysis step {} must lie in (0, 1)", step));
  const auto base = model_peaks(assembly, tool_point_frf, f);
  if (base.empty())
    throw InvalidArgument(fmt::format("the model's {} FRF has no peak in {}–{} Hz", tool_point_frf ? "tool point" : "holder tip",
                                      f.front(), f.back()),
                          "widen the frequency range");
  auto perturbed = [&](bool stiffness) {
    Assembly a = assembly;
    JointParameters& p = (holder_tool ? a.holder_tool : a.spindle_holder).parameters;
    for (int i = 0; i < 8; ++i)
      if (JointParameters::is_damping(i) != stiffness) p[i] *= 1.0 + step;
    return model_peaks(a, tool_point_frf, f);
  };
  const auto pk = perturbed(true), pc = perturbed(false);
  EffectAnalysis r;
  for (const Peak& b : base) {
    ModeEffect m;
    m.frequency_hz = b.frequency_hz;
    m.magnitude = b.magnitude;
    if (!pk.empty()) m.stiffness_shift = (pk[nearest(pk, b.frequency_hz)].frequency_hz - b.frequency_hz) / b.frequency_hz;
    if (!pc.empty()) m.damping_effect = (pc[nearest(pc, b.frequency_hz)].magnitude - b.magnitude) / b.magnitude;
    r.modes.push_back(m);
  }
  for (std::size_t i = 1; i < r.modes.size(); ++i)
    if (std::abs(r.modes[i].stiffness_shift) > std::abs(r.modes[r.dominant].stiffness_shift)) r.dominant = i;
  if (r.modes[r.dominant].stiffness_shift == 0.0)
    throw InvalidArgument(fmt::format("effect analysis: no mode of the {} FRF moves when joints.{} changes",
                                      tool_point_frf ? "tool point" : "holder tip", which),
                          "the FRF does not depend on this joint; pick the band by hand (IdentificationOptions::band_hz)");
  return r;
}

OverhangModes overhang_mode(const std::vector<FrfSeries>& frfs, std::size_t reference, const PeakOptions& options) {
  if (frfs.size() < 2)
    throw InvalidArgument(fmt::format("overhang mode choice needs FRFs at ≥ 2 overhangs, got {}", frfs.size()));
  if (reference >= frfs.size()) throw InvalidArgument(fmt::format("reference FRF {} outside 0..{}", reference, frfs.size() - 1));
  std::vector<std::vector<Peak>> family;
  for (const auto& s : frfs) family.push_back(find_peaks(s, options));
  OverhangModes r;
  r.reference_peaks = family[reference];
  if (r.reference_peaks.empty())
    throw InputError("the reference FRF has no resonance peak", "check the FRF, or lower the peak prominence");
  // Each reference mode found in every FRF (in any order: matched against the reference, within
  // 25 %); its variation is the range it spans.
  for (const auto& mode : track_modes(family, reference, 0.25, false)) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double f : mode)
      if (!std::isnan(f)) {
        lo = std::min(lo, f);
        hi = std::max(hi, f);
      }
    r.relative_variation.push_back((hi - lo) / mode[reference]);
  }
  r.dominant = static_cast<std::size_t>(std::max_element(r.relative_variation.begin(), r.relative_variation.end()) -
                                        r.relative_variation.begin());
  return r;
}

std::vector<ModeComparison> compare_modes(const FrfSeries& measured, const FrfSeries& predicted, const PeakOptions& options) {
  require_same_grid(measured.frequency_hz, "measured FRF", predicted.frequency_hz, "predicted FRF");
  const auto pm = find_peaks(measured, options), pp = find_peaks(predicted, options);
  std::vector<ModeComparison> out;
  if (pp.empty()) return out;
  for (const Peak& m : pm) {
    const Peak& p = pp[nearest(pp, m.frequency_hz)];
    ModeComparison c;
    c.measured_hz = m.frequency_hz;
    c.predicted_hz = p.frequency_hz;
    c.frequency_error = (p.frequency_hz - m.frequency_hz) / m.frequency_hz;
    c.measured_peak = m.magnitude;
    c.predicted_peak = p.magnitude;
    c.magnitude_error = (p.magnitude - m.magnitude) / m.magnitude;
    out.push_back(c);
  }
  return out;
}

}  // namespace toolpoint
