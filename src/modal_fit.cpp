// toolpoint: modal models and their identification from a point FRF (peak picking, linear least
// squares for residues, Levenberg–Marquardt on everything). Units: kg, N, m, s; Hz at interfaces.
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/measured/peaks.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <unsupported/Eigen/NonLinearOptimization>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

double Mode::stiffness() const {
  const double w = omega_of(frequency_hz);
  return mass_kg * w * w;
}

void Mode::check(const std::string& what) const {
  if (!std::isfinite(mass_kg) || !(mass_kg > 0.0))
    throw InvalidArgument(fmt::format("{}: modal mass {} kg must be positive and finite", what, mass_kg));
  if (!std::isfinite(damping_ratio) || damping_ratio < 0.0 || damping_ratio >= 1.0)
    throw InvalidArgument(fmt::format("{}: damping ratio {} must lie in [0, 1)", what, damping_ratio),
                          "give ζ as a fraction of critical damping, e.g. 0.02 for 2 %");
  if (!std::isfinite(frequency_hz) || !(frequency_hz > 0.0))
    throw InvalidArgument(fmt::format("{}: natural frequency {} Hz must be positive and finite", what, frequency_hz));
}

namespace {

// 1/(ω_r² − ω² + 2iζ_r ω_r ω): the mode's receptance times its modal mass [1/(rad/s)²].
Complex mode_shape_factor(double omega_r, double zeta, double omega) {
  return 1.0 / Complex(omega_r * omega_r - omega * omega, 2.0 * zeta * omega_r * omega);
}

}  // namespace

Complex modal_receptance(const std::vector<Mode>& modes, double frequency_hz) {
  const double w = omega_of(frequency_hz);
  Complex g = 0.0;
  for (const Mode& m : modes) g += mode_shape_factor(omega_of(m.frequency_hz), m.damping_ratio, w) / m.mass_kg;
  return g;
}

FrfSeries modal_frf(const std::vector<Mode>& modes, const std::vector<double>& frequency_hz) {
  for (std::size_t i = 0; i < modes.size(); ++i) modes[i].check(fmt::format("mode {}", i + 1));
  FrfSeries s;
  s.frequency_hz = frequency_hz;
  s.values.reserve(frequency_hz.size());
  for (double f : frequency_hz) s.values.push_back(modal_receptance(modes, f));
  return s;
}

void ModalFitOptions::check() const {
  check_fields(modal_fit_fields(), *this, "ModalFitOptions");
  if (band_hz) {
    const auto [lo, hi] = *band_hz;
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo >= 0.0) || !(hi > lo))
      throw InvalidArgument(fmt::format("ModalFitOptions::band_hz = {}:{} Hz must satisfy 0 ≤ F1 < F2", lo, hi), "e.g. 500:3000");
  }
}

const std::vector<OptionField<ModalFitOptions>>& modal_fit_fields() {
  using O = ModalFitOptions;
  using K = FieldKind;
  // 20 modes: more than a tool point's band holds; 3 dB: a peak with a half-power band; 10
  // evaluations: fewer cannot move the initial estimates.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "max_modes",
        .kind = K::Integer,
        .min = 1.0,
        .max = 20.0,
        .help = "at most this many modes fitted (the most prominent peaks)",
        .cli_name = "max-modes"},
       nullptr,
       [](O& o) -> int& { return o.max_modes; }},
      {{.name = "min_prominence_db",
        .kind = K::Real,
        .unit = "dB",
        .min = 0.0,
        .min_open = true,
        .help = "a peak of |G| must rise this much above the valleys on both sides to count as a mode",
        .cli_name = "min-prominence"},
       [](O& o) -> double& { return o.min_prominence_db; }},
      {{.name = "residual_terms", .kind = K::Flag, .help = "fit the residual terms −L/ω² + U for out-of-band modes"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.residual_terms; }},
      {{.name = "max_evaluations", .kind = K::Integer, .min = 10.0, .help = "Levenberg–Marquardt function evaluations at most"},
       nullptr,
       [](O& o) -> int& { return o.max_evaluations; }}};
  return fields;
}

namespace {

struct ModePeak {
  std::size_t index;
  double prominence_db;
};

// Local maxima of |G| away from the band edges (peaks.hpp), with their prominence in dB: the drop
// from the peak to the higher of the lowest points on each side before a higher point (or the
// band edge).
std::vector<ModePeak> peaks_in_db(const std::vector<double>& mag) {
  std::vector<ModePeak> peaks;
  for (const toolpoint::Peak& p : toolpoint::find_peaks(mag, 0.0))
    peaks.push_back({p.index, p.prominence < 1.0 ? -20.0 * std::log10(1.0 - p.prominence) : 300.0});
  return peaks;
}

// Half-power crossing on one side of peak `p` (step −1 or +1), linearly interpolated in |G|.
// The prominence test guarantees the crossing exists before a higher point or the edge.
double half_power_frequency(const std::vector<double>& f, const std::vector<double>& mag, std::size_t p, int step) {
  const double level = mag[p] / std::sqrt(2.0);
  std::size_t j = p;
  for (;;) {
    const std::size_t k = step < 0 ? j - 1 : j + 1;
    if (mag[k] < level) {
      const double t = (mag[j] - level) / (mag[j] - mag[k]);
      return f[j] + t * (f[k] - f[j]);
    }
    j = k;
  }
}

// The model G = Σ A_r/D_r − L/ω² + U and its Jacobian, for MINPACK's Levenberg–Marquardt.
// Parameters per mode: ln ω_r, ln ζ_r, A_r/S_r; then L/S_L, U/S_U. Residuals: Re and Im of
// (G_model − G)/scale.
struct FitProblem {
  const std::vector<double>* omega;
  const std::vector<Complex>* measured;
  std::vector<double> mode_scale;  // S_r
  double lower_scale = 1.0, upper_scale = 1.0, scale = 1.0;
  bool residuals = true;

  int modes() const { return static_cast<int>(mode_scale.size()); }
  int inputs() const { return 3 * modes() + (residuals ? 2 : 0); }
  int values() const { return static_cast<int>(2 * omega->size()); }

  Complex model(const Eigen::VectorXd& x, double w) const {
    Complex g = 0.0;
    for (int r = 0; r < modes(); ++r)
      g += x(3 * r + 2) * mode_scale[r] * mode_shape_factor(std::exp(x(3 * r)), std::exp(x(3 * r + 1)), w);
    if (residuals) g += -x(3 * modes()) * lower_scale / (w * w) + x(3 * modes() + 1) * upper_scale;
    return g;
  }

  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& fvec) const {
    const std::size_t n = omega->size();
    for (std::size_t i = 0; i < n; ++i) {
      const Complex e = (model(x, (*omega)[i]) - (*measured)[i]) / scale;
      fvec(static_cast<Eigen::Index>(i)) = e.real();
      fvec(static_cast<Eigen::Index>(n + i)) = e.imag();
    }
    return 0;
  }

  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& jac) const {
    const std::size_t n = omega->size();
    for (std::size_t i = 0; i < n; ++i) {
      const double w = (*omega)[i];
      const auto row_re = static_cast<Eigen::Index>(i), row_im = static_cast<Eigen::Index>(n + i);
      auto put = [&](int col, Complex d) {
        jac(row_re, col) = d.real() / scale;
        jac(row_im, col) = d.imag() / scale;
      };
      for (int r = 0; r < modes(); ++r) {
        const double wr = std::exp(x(3 * r)), z = std::exp(x(3 * r + 1)), a = x(3 * r + 2) * mode_scale[r];
        const Complex inv = mode_shape_factor(wr, z, w), inv2 = inv * inv;
        put(3 * r, -a * Complex(2.0 * wr, 2.0 * z * w) * inv2 * wr);  // ∂/∂ln ω_r
        put(3 * r + 1, -a * Complex(0.0, 2.0 * wr * w) * inv2 * z);   // ∂/∂ln ζ_r
        put(3 * r + 2, mode_scale[r] * inv);                          // ∂/∂(A_r/S_r)
      }
      if (residuals) {
        put(3 * modes(), -lower_scale / (w * w));
        put(3 * modes() + 1, upper_scale);
      }
    }
    return 0;
  }
};

// Residues (and residual terms) by linear least squares with ω_r, ζ_r fixed. Columns are scaled
// to unit norm so modes of very different size are solved with equal care.
Eigen::VectorXd linear_residues(const FitProblem& p, const std::vector<double>& omega_r, const std::vector<double>& zeta) {
  const auto n = static_cast<Eigen::Index>(p.omega->size());
  const int k = p.modes(), cols = k + (p.residuals ? 2 : 0);
  Eigen::MatrixXd a(2 * n, cols);
  Eigen::VectorXd b(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double w = (*p.omega)[static_cast<std::size_t>(i)];
    for (int r = 0; r < k; ++r) {
      const Complex c = mode_shape_factor(omega_r[r], zeta[r], w);
      a(i, r) = c.real();
      a(n + i, r) = c.imag();
    }
    if (p.residuals) {
      a(i, k) = -1.0 / (w * w);
      a(n + i, k) = 0.0;
      a(i, k + 1) = 1.0;
      a(n + i, k + 1) = 0.0;
    }
    b(i) = (*p.measured)[static_cast<std::size_t>(i)].real();
    b(n + i) = (*p.measured)[static_cast<std::size_t>(i)].imag();
  }
  Eigen::VectorXd norms = a.colwise().norm().transpose();
  for (int c = 0; c < cols; ++c) a.col(c) /= norms(c);
  Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
  return sol.cwiseQuotient(norms);
}

double normalised_error(const std::vector<Complex>& fit, const std::vector<Complex>& meas, std::size_t lo, std::size_t hi) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = lo; i < hi; ++i) {
    num += std::norm(fit[i] - meas[i]);
    den += std::norm(meas[i]);
  }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace

namespace {

// Phase 1 of the fit: the resonance peaks to start from — prominent enough, resolved by at least
// 3 points in their half-power band (else set aside, with a warning), the max_modes most
// prominent, in frequency order.
std::vector<ModePeak> starting_peaks(const std::vector<double>& f, const std::vector<double>& mag, const ModalFitOptions& options,
                                     const std::string& what, std::vector<std::string>& warnings) {
  std::vector<ModePeak> peaks = peaks_in_db(mag);
  std::erase_if(peaks, [&](const ModePeak& p) { return p.prominence_db < options.min_prominence_db; });
  if (peaks.empty())
    throw InputError(fmt::format("{}: no resonance peak rising {} dB above its surroundings in {}–{} Hz", what,
                                 options.min_prominence_db, f.front(), f.back()),
                     "check the band (ModalFitOptions::band_hz) and that the file holds a receptance with a resonance inside it");
  std::stable_sort(peaks.begin(), peaks.end(),
                   [](const ModePeak& a, const ModePeak& b) { return a.prominence_db > b.prominence_db; });
  // A peak needs points inside its half-power band for its damping to be seen: fewer than 3 is
  // an under-resolved mode (or a noise spike). Such peaks are set aside; with none left, stop.
  auto points_inside = [&](std::size_t p) {
    std::size_t inside = 1;
    const double level = mag[p] / std::sqrt(2.0);
    for (std::size_t j = p; j-- > 0 && mag[j] >= level;) ++inside;
    for (std::size_t j = p + 1; j < f.size() && mag[j] >= level; ++j) ++inside;
    return inside;
  };
  const ModePeak strongest = peaks.front();
  std::vector<ModePeak> resolved;
  for (const ModePeak& p : peaks) {
    if (points_inside(p.index) >= 3) resolved.push_back(p);
    else if (resolved.size() < static_cast<std::size_t>(options.max_modes))
      warnings.push_back(
          fmt::format("the peak at {} Hz has fewer than 3 FRF points within its half-power band and was "
                      "not fitted (too coarse a grid there, or noise)",
                      f[p.index]));
  }
  if (resolved.empty())
    throw InputError(fmt::format("{}: the mode near {} Hz has {} FRF point(s) within its half-power band (the grid step "
                                 "there is {} Hz); at least 3 are needed to fit its damping",
                                 what, f[strongest.index], points_inside(strongest.index),
                                 f[strongest.index + 1] - f[strongest.index]),
                     "measure or compute the FRF on a finer frequency grid around that mode");
  peaks = std::move(resolved);
  if (peaks.size() > static_cast<std::size_t>(options.max_modes)) {
    warnings.push_back(fmt::format("{} peaks found, the {} most prominent kept (raise ModalFitOptions::max_modes to fit more)",
                                   peaks.size(), options.max_modes));
    peaks.resize(static_cast<std::size_t>(options.max_modes));
  }
  std::sort(peaks.begin(), peaks.end(), [](const ModePeak& a, const ModePeak& b) { return a.index < b.index; });

  return peaks;
}

// Phase 4: the fit's quality, overall and per mode (residual near each mode, points in its
// half-power band), and the warnings a user must see (outside the band, overdamped, no modal mass,
// poorly fitted).
void judge_modal_fit(ModalFitResult& res, const std::vector<double>& f, const std::vector<Complex>& g) {
  std::vector<Complex> fit(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) fit[i] = res.receptance(f[i]);
  res.normalised_residual = normalised_error(fit, g, 0, f.size());
  for (FittedMode& m : res.modes) {
    const double fr = m.mode.frequency_hz, z = m.mode.damping_ratio;
    const auto lower = [&](double v) { return static_cast<std::size_t>(std::lower_bound(f.begin(), f.end(), v) - f.begin()); };
    m.points_in_half_power_band = static_cast<int>(lower(fr * (1.0 + z)) - lower(fr * (1.0 - z)));
    std::size_t lo = lower(fr * (1.0 - 2.0 * z)), hi = lower(fr * (1.0 + 2.0 * z));
    while (hi - lo < 5 && (lo > 0 || hi < f.size())) {  // widen to the 5 nearest points
      if (lo > 0 && (hi == f.size() || fr - f[lo - 1] < f[hi] - fr)) --lo;
      else ++hi;
    }
    m.normalised_residual = normalised_error(fit, g, lo, hi);
    if (fr < f.front() || fr > f.back())
      res.warnings.push_back(fmt::format("the mode fitted at {:.2f} Hz lies outside the band {}–{} Hz", fr, f.front(), f.back()));
    if (z >= 1.0)
      res.warnings.push_back(
          fmt::format("the mode fitted at {:.2f} Hz has a damping ratio of {:.3g}: overdamped, not a "
                      "resonance (the fit spent a mode on the background; fewer modes or a narrower band)",
                      fr, z));
    else if (z > 0.3) res.warnings.push_back(fmt::format("the mode at {:.2f} Hz has a large damping ratio {:.3f}", fr, z));
    if (!(m.residue > 0.0))
      res.warnings.push_back(
          fmt::format("the mode at {:.2f} Hz has a non-positive residue {:.4g} 1/kg: no modal mass "
                      "(is this a point FRF, with the e^{{iωt}} sign convention?)",
                      fr, m.residue));
    if (m.normalised_residual > 0.1)
      res.warnings.push_back(
          fmt::format("the mode at {:.2f} Hz is fitted poorly: {:.1f} % residual near it", fr, 100.0 * m.normalised_residual));
  }
  if (res.normalised_residual > 0.1)
    res.warnings.push_back(fmt::format(
        "overall fit residual {:.1f} %: more modes (ModalFitOptions::max_modes) or a narrower ModalFitOptions::band_hz may help",
        100.0 * res.normalised_residual));
}

ModalFitResult fit_modes_at_scale(const FrfSeries& frf, const ModalFitOptions& options, const std::string& what) {
  options.check();
  validate(frf, what, 1);
  ModalFitResult res;

  std::vector<double> f, omega, mag;
  std::vector<Complex> g;
  for (std::size_t i = 0; i < frf.size(); ++i) {
    const double fi = frf.frequency_hz[i];
    if (options.band_hz && (fi < options.band_hz->first || fi > options.band_hz->second)) continue;
    f.push_back(fi);
    omega.push_back(omega_of(fi));
    g.push_back(frf.values[i]);
    mag.push_back(std::abs(frf.values[i]));
  }
  if (f.size() < 8)
    throw InputError(fmt::format("{}: {} point(s) in the fitted band {}, at least 8 needed", what, f.size(),
                                 options.band_hz ? fmt::format("{}–{} Hz", options.band_hz->first, options.band_hz->second)
                                                 : std::string("(whole FRF)")),
                     "widen ModalFitOptions::band_hz or give a finer FRF");
  require_not_mobility({f, g}, what);
  res.band_low_hz = f.front();
  res.band_high_hz = f.back();
  res.points = f.size();

  // 1. Peaks: the most prominent first, then back into frequency order.
  const std::vector<ModePeak> peaks = starting_peaks(f, mag, options, what, res.warnings);

  std::vector<double> w0, z0, peak_mag;
  for (const ModePeak& p : peaks) {
    const double f1 = half_power_frequency(f, mag, p.index, -1), f2 = half_power_frequency(f, mag, p.index, +1);
    w0.push_back(omega[p.index]);
    z0.push_back(std::max((f2 - f1) / (2.0 * f[p.index]), 1e-5));
    peak_mag.push_back(mag[p.index]);
  }

  // 2. Residues by linear least squares; 3. Levenberg–Marquardt on all parameters.
  FitProblem prob{&omega, &g, {}, 1.0, 1.0, 1.0, options.residual_terms};
  prob.scale = *std::max_element(mag.begin(), mag.end());
  for (std::size_t r = 0; r < w0.size(); ++r) prob.mode_scale.push_back(peak_mag[r] * 2.0 * z0[r] * w0[r] * w0[r]);
  prob.lower_scale = prob.scale * omega.front() * omega.front();
  prob.upper_scale = prob.scale;
  const Eigen::VectorXd lin = linear_residues(prob, w0, z0);
  const int k = prob.modes();
  Eigen::VectorXd x(prob.inputs());
  for (int r = 0; r < k; ++r) {
    x(3 * r) = std::log(w0[r]);
    x(3 * r + 1) = std::log(z0[r]);
    x(3 * r + 2) = lin(r) / prob.mode_scale[r];
  }
  if (options.residual_terms) {
    x(3 * k) = lin(k) / prob.lower_scale;
    x(3 * k + 1) = lin(k + 1) / prob.upper_scale;
  }
  Eigen::LevenbergMarquardt<FitProblem> lm(prob);
  lm.parameters.maxfev = options.max_evaluations;
  lm.parameters.ftol = 1e-14;  // stop on relative changes near round-off: noise-free data fit exactly
  lm.parameters.xtol = 1e-14;
  const auto status = lm.minimize(x);
  res.evaluations = static_cast<int>(lm.nfev);
  using namespace Eigen::LevenbergMarquardtSpace;
  res.converged = status == RelativeReductionTooSmall || status == RelativeErrorTooSmall ||
                  status == RelativeErrorAndReductionTooSmall || status == CosinusTooSmall || status == FtolTooSmall ||
                  status == XtolTooSmall || status == GtolTooSmall;
  if (!res.converged)
    res.warnings.push_back(fmt::format("the Levenberg–Marquardt fit stopped without converging (status {}, {} evaluations)",
                                       static_cast<int>(status), res.evaluations));
  if (!x.allFinite())
    throw NumericalError(fmt::format("{}: the modal fit diverged (non-finite parameters)", what),
                         "narrow ModalFitOptions::band_hz around the modes of interest or reduce ModalFitOptions::max_modes");

  for (int r = 0; r < k; ++r) {
    FittedMode m;
    const double wr = std::exp(x(3 * r));
    m.residue = x(3 * r + 2) * prob.mode_scale[r];
    m.mode = {1.0 / m.residue, std::exp(x(3 * r + 1)), wr / (2.0 * kPi)};
    m.initial_frequency_hz = w0[r] / (2.0 * kPi);
    m.initial_damping_ratio = z0[r];
    res.modes.push_back(m);
  }
  if (options.residual_terms) {
    res.lower_residual = x(3 * k) * prob.lower_scale;
    res.upper_residual = x(3 * k + 1) * prob.upper_scale;
  }

  judge_modal_fit(res, f, g);
  return res;
}

}  // namespace

// Scale-aware: the fit runs on the FRF divided by a power of two near its largest magnitude
// (exact: only the exponent changes), so magnitudes near the limits of double precision (1e-317,
// 1e300) fit as well as 1e-6 m/N does; the residues and residual terms are multiplied back and the
// modal masses divided (H = 2^e H' gives A = 2^e A', m = 2^−e m'). FRFs whose largest magnitude lies
// in [1e-30, 1e10] are fitted as they are (every physical receptance: results unchanged). A modal
// mass or stiffness that does not fit in a double after scaling back is a NumericalError giving its
// value in powers of ten, never an infinite mass.
ModalFitResult fit_modes(const FrfSeries& frf, const ModalFitOptions& options, const std::string& what) {
  options.check();
  validate(frf, what, 1);
  double top = 0.0;
  for (const Complex& v : frf.values) top = std::max({top, std::abs(v.real()), std::abs(v.imag())});
  if (top == 0.0 || (top >= 1e-30 && top <= 1e10)) return fit_modes_at_scale(frf, options, what);
  const int e = std::ilogb(top);
  FrfSeries scaled = frf;
  for (Complex& v : scaled.values) v = {std::ldexp(v.real(), -e), std::ldexp(v.imag(), -e)};
  ModalFitResult r = fit_modes_at_scale(scaled, options, what);
  const double log2_10 = std::log2(10.0);
  for (FittedMode& m : r.modes) {
    const double mass = std::ldexp(m.mode.mass_kg, -e), residue = std::ldexp(m.residue, e);
    const double stiffness = mass * std::pow(omega_of(m.mode.frequency_hz), 2);
    if (!std::isfinite(mass) || !std::isfinite(stiffness) || (m.mode.mass_kg != 0.0 && (mass == 0.0 || !std::isnormal(residue))))
      throw NumericalError(
          fmt::format("{}: the mode at {:.6g} Hz has a modal mass of about 1e{:.0f} kg (stiffness 1e{:.0f} N/m): out of "
                      "the range of double precision (the FRF's largest magnitude is {:.3g}), so it cannot be "
                      "reported or used",
                      what, m.mode.frequency_hz, std::log10(std::abs(m.mode.mass_kg)) - e / log2_10,
                      std::log10(std::abs(m.mode.mass_kg) * std::pow(omega_of(m.mode.frequency_hz), 2)) - e / log2_10, top),
          "check the FRF's units (a receptance in m/N is typically 1e-9 to 1e-4); rescale the data (FrfReadOptions::units)");
    m.mode.mass_kg = mass;
    m.residue = residue;
  }
  r.lower_residual = std::ldexp(r.lower_residual, e);
  r.upper_residual = std::ldexp(r.upper_residual, e);
  r.warnings.push_back(
      fmt::format("{}: its largest magnitude is {:.3g}, far from a receptance in m/N; fitted on the FRF scaled by "
                  "2^{} and scaled back",
                  what, top, -e));
  return r;
}

bool FittedMode::is_resonance() const { return residue > 0.0 && mode.damping_ratio < 1.0; }

std::vector<Mode> ModalFitResult::modal_model() const {
  std::vector<Mode> out;
  for (const FittedMode& m : modes) {
    if (m.is_resonance()) {
      out.push_back(m.mode);
      continue;
    }
    // Which half of the rule failed, for the message.
    if (!(m.residue > 0.0))
      throw NumericalError(fmt::format("the fitted mode at {:.2f} Hz has residue {:.4g} 1/kg: it has no positive modal mass",
                                       m.mode.frequency_hz, m.residue),
                           "fit a point (direct) FRF, narrow ModalFitOptions::band_hz, or give the modes explicitly");
    if (!(m.mode.damping_ratio < 1.0))  // a fit's artefact, not the caller's input: no Mode::check message about it
      throw NumericalError(fmt::format("the fitted mode at {:.2f} Hz has a damping ratio of {:.3g}: overdamped, not a resonance",
                                       m.mode.frequency_hz, m.mode.damping_ratio),
                           "fit fewer modes (ModalFitOptions::max_modes) or a narrower ModalFitOptions::band_hz");
  }
  return out;
}

Complex ModalFitResult::receptance(double frequency_hz) const {
  const double w = omega_of(frequency_hz);
  Complex g = -lower_residual / (w * w) + upper_residual;
  for (const FittedMode& m : modes) g += m.residue * mode_shape_factor(omega_of(m.mode.frequency_hz), m.mode.damping_ratio, w);
  return g;
}

FrfSeries ModalFitResult::fitted_frf(const std::vector<double>& frequency_hz) const {
  FrfSeries s;
  for (double f : frequency_hz)
    if (f >= band_low_hz && f <= band_high_hz) {
      s.frequency_hz.push_back(f);
      s.values.push_back(receptance(f));
    }
  return s;
}

}  // namespace toolpoint
