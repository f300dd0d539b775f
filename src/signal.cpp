// toolpoint: Savitzky–Golay smoothing, simulated measurement noise, finite-difference rotational
// FRFs. Units: Hz, m, and the FRFs' own units (see signal.hpp).
#include "toolpoint/measured/signal.hpp"

#include "toolpoint/measured/noise.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <fmt/format.h>
#include <random>
#include <tuple>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/peaks.hpp"

namespace toolpoint {

// ---- Savitzky–Golay ----------------------------------------------------------------------------

void SavgolOptions::check() const {
  check_fields(savgol_fields(), *this, "SavgolOptions");
  if (window % 2 == 0)
    throw InvalidArgument(fmt::format("SavgolOptions::window {} must be a positive odd number of points", window),
                          "use an odd window such as 5, 11 or 21 points");
  if (order >= window)
    throw InvalidArgument(fmt::format("SavgolOptions::order {} must be less than SavgolOptions::window {} points", order, window),
                          "lower the order or widen the window (a window of w points fits at most degree w − 1)");
}

const std::vector<OptionField<SavgolOptions>>& savgol_fields() {
  using O = SavgolOptions;
  // The window also odd, the order below it: checked beside the table (check()).
  static const std::vector<OptionField<O>> fields = {{{.name = "window",
                                                       .kind = FieldKind::Integer,
                                                       .min = 1.0,
                                                       .help = "points in the fitting window: odd, > order (e.g. 5, 11 or 21)",
                                                       .cli_name = "window",
                                                       .cli_unit = "frequency points"},
                                                      nullptr,
                                                      [](O& o) -> int& { return o.window; }},
                                                     {{.name = "order",
                                                       .kind = FieldKind::Integer,
                                                       .min = 0.0,
                                                       .help = "polynomial degree p, < window (e.g. 2 or 3)",
                                                       .cli_name = "order"},
                                                      nullptr,
                                                      [](O& o) -> int& { return o.order; }}};
  return fields;
}

namespace {

// The least-squares machinery for one (window, order): the QR factorisation of the scaled
// Vandermonde matrix, shared by the interior weights and the edge fits.
class SavgolKernel {
 public:
  explicit SavgolKernel(const SavgolOptions& o) : half_(o.window / 2), scale_(std::max(1, o.window / 2)) {
    o.check();
    const int w = o.window, p1 = o.order + 1;
    Eigen::MatrixXd v(w, p1);
    for (int k = 0; k < w; ++k) {
      const double t = abscissa(k);
      double tj = 1.0;
      for (int j = 0; j < p1; ++j, tj *= t) v(k, j) = tj;
    }
    // Accuracy of the weights is about ε·cond(V); beyond 1e8 they would differ from the exact
    // least-squares weights in the 8th digit, which no longer "matches scipy".
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(v);
    const auto& sv = svd.singularValues();
    const double cond = sv(0) / sv(sv.size() - 1);
    if (!(cond <= 1e8))
      throw NumericalError(fmt::format("Savitzky–Golay order {} with window {}: Vandermonde condition number {:.3g} is too large "
                                       "for accurate weights",
                                       o.order, w, cond),
                           "use a lower polynomial order (2–6 is usual for smoothing FRFs)");
    qr_.compute(v);
    const Eigen::MatrixXd q = qr_.householderQ() * Eigen::MatrixXd::Identity(w, p1);
    // Row `half` of the hat matrix Q Qᵀ: the fitted value at the centre as a weighted sum.
    const Eigen::VectorXd c = q * q.row(half_).transpose();
    centre_.assign(c.data(), c.data() + w);
  }

  const std::vector<double>& centre() const { return centre_; }

  // out[first + k] for k in [from, to): the polynomial fitted to in[first .. first+window)
  // evaluated at those positions.
  void fit_edge(std::span<const double> in, std::size_t first, int from, int to, std::vector<double>& out) const {
    const int w = static_cast<int>(centre_.size());
    const Eigen::Map<const Eigen::VectorXd> y(in.data() + first, w);
    const Eigen::VectorXd a = qr_.solve(y);
    for (int k = from; k < to; ++k) {
      const double t = abscissa(k);
      double v = 0.0;
      for (Eigen::Index j = a.size() - 1; j >= 0; --j) v = v * t + a(j);  // Horner
      out[first + static_cast<std::size_t>(k)] = v;
    }
  }

 private:
  double abscissa(int k) const { return static_cast<double>(k - half_) / scale_; }

  int half_;
  double scale_;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
  std::vector<double> centre_;
};

std::vector<double> apply_savgol(const SavgolKernel& kernel, std::span<const double> x) {
  const auto& c = kernel.centre();
  const std::size_t n = x.size(), w = c.size(), m = w / 2;
  std::vector<double> y(n);
  for (std::size_t i = m; i + m < n; ++i) {
    double s = 0.0;
    for (std::size_t k = 0; k < w; ++k) s += c[k] * x[i - m + k];
    y[i] = s;
  }
  const int mi = static_cast<int>(m), wi = static_cast<int>(w);
  kernel.fit_edge(x, 0, 0, mi, y);
  kernel.fit_edge(x, n - w, wi - mi, wi, y);
  return y;
}

void require_window_fits(const SavgolOptions& o, std::size_t n, const std::string& what) {
  o.check();
  if (static_cast<std::size_t>(o.window) > n)
    throw InvalidArgument(fmt::format("Savitzky–Golay window {} points is longer than {} ({} points)", o.window, what, n),
                          "use a window no longer than the data (and much shorter, to smooth rather than fit)");
}

// Savitzky–Golay assumes even spacing; report an uneven grid rather than refuse it (a grid
// written with rounded frequencies is uneven at the 1e-9 level and harmless).
void warn_if_uneven(const std::vector<double>& f, const std::string& what, std::vector<std::string>& warnings) {
  if (f.size() < 3) return;
  double lo = f[1] - f[0], hi = lo;
  for (std::size_t i = 2; i < f.size(); ++i) {
    lo = std::min(lo, f[i] - f[i - 1]);
    hi = std::max(hi, f[i] - f[i - 1]);
  }
  if (hi - lo > 1e-6 * hi)
    warnings.push_back(
        fmt::format("{}: frequency steps vary from {} Hz to {} Hz; Savitzky–Golay treats the points as "
                    "evenly spaced",
                    what, lo, hi));
}

}  // namespace

std::vector<double> savgol_coefficients(const SavgolOptions& options) { return SavgolKernel(options).centre(); }

void check_smoothing_window(const SavgolOptions& options, std::size_t points, const std::string& what) {
  require_window_fits(options, points, what);
  if (4 * static_cast<std::size_t>(options.window) > points)
    throw InvalidArgument(fmt::format("SavgolOptions::window {} points is longer than a quarter of {} ({} points, so at most {})",
                                      options.window, what, points, points / 4),
                          "use a window much shorter than the data (a few times the points across a resonance's half-power "
                          "width at most), or give more points");
}

std::vector<double> savgol_filter(std::span<const double> samples, const SavgolOptions& options, const std::string& what) {
  require_window_fits(options, samples.size(), what);
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (!std::isfinite(samples[i]))
      throw InputError(fmt::format("{}: sample {} is {}, not a finite number", what, i + 1, samples[i]),
                       "remove or repair the NaN/Inf values in the data");
  return apply_savgol(SavgolKernel(options), samples);
}

namespace {

// Filters `columns` real columns of a series; get(i, c) reads, set(i, c, v) writes.
template <class Series, class Get, class Set>
SignalResult<Series> filter_columns(const Series& series, const SavgolOptions& options, const std::string& what, int columns,
                                    Get get, Set set) {
  validate(series, what);
  require_window_fits(options, series.size(), what);
  const SavgolKernel kernel(options);
  SignalResult<Series> r{series, {}};
  std::vector<double> col(series.size());
  for (int c = 0; c < columns; ++c) {
    for (std::size_t i = 0; i < series.size(); ++i) col[i] = get(series, i, c);
    const std::vector<double> out = apply_savgol(kernel, col);
    for (std::size_t i = 0; i < series.size(); ++i) set(r.series, i, c, out[i]);
  }
  warn_if_uneven(series.frequency_hz, what, r.warnings);
  return r;
}

// Real (c even) or imaginary (c odd) part of entry c/2 of z.
double part(const Complex& z, int c) { return c % 2 == 0 ? z.real() : z.imag(); }
void set_part(Complex& z, int c, double v) {
  if (c % 2 == 0) z.real(v);
  else z.imag(v);
}

}  // namespace

SignalResult<FrfSeries> savgol_filter(const FrfSeries& series, const SavgolOptions& options, const std::string& what) {
  return filter_columns(
      series, options, what, 2, [](const FrfSeries& s, std::size_t i, int c) { return part(s.values[i], c); },
      [](FrfSeries& s, std::size_t i, int c, double v) { set_part(s.values[i], c, v); });
}

SignalResult<BlockSeries> savgol_filter(const BlockSeries& series, const SavgolOptions& options, const std::string& what) {
  // Column c: entry c/2 of the block (H, L, N, P, row-major), real part for even c.
  return filter_columns(
      series, options, what, 8,
      [](const BlockSeries& s, std::size_t i, int c) { return part(s.blocks[i](c / 4, (c / 2) % 2), c); },
      [](BlockSeries& s, std::size_t i, int c, double v) { set_part(s.blocks[i](c / 4, (c / 2) % 2), c, v); });
}

// ---- What the filter did to the peaks -------------------------------------------------------

void PeakChangeOptions::check() const { check_fields(peak_change_fields(), *this, "PeakChangeOptions"); }

const std::vector<OptionField<PeakChangeOptions>>& peak_change_fields() {
  using O = PeakChangeOptions;
  using K = FieldKind;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "min_prominence",
        .kind = K::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "fraction of its height a peak rises above its higher valley (0.2: 25 % above it; noise ripple is not a mode)"},
       [](O& o) -> double& { return o.min_prominence; }},
      {{.name = "min_height",
        .kind = K::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "fraction of the entry's highest peak below which a peak is not reported"},
       [](O& o) -> double& { return o.min_height; }},
      {{.name = "warn_above",
        .kind = K::Real,
        .min = 0.0,
        .min_open = true,
        .help = "|relative change| of a peak's height or frequency above which a warning is given (0.02 for 2 %)"},
       [](O& o) -> double& { return o.warn_above; }},
      {{.name = "noise_prominence",
        .kind = K::Real,
        .min = 0.0,
        .note = "0: every peak above min_prominence",
        .help = "noise σ a peak must also rise above its higher valley (e.g. 8)"},
       [](O& o) -> double& { return o.noise_prominence; }}};
  return fields;
}

namespace {

// `noise`: the entry's absolute noise σ per frequency (local_noise_sigma), empty when not estimated.
void peak_changes_of(const FrfSeries& raw, const FrfSeries& filtered, int window, const PeakChangeOptions& o,
                     const std::vector<double>& noise, const std::string& what, const std::string& entry_name,
                     PeakChangeReport& report) {
  std::vector<Peak> found = find_peaks(raw, PeakOptions{o.min_prominence});
  auto sigma_at = [&](const Peak& p) { return noise.empty() ? 0.0 : noise[p.index] / p.magnitude; };  // relative to the peak
  // The rise above the higher valley, peak − valley = prominence · peak, at least kσ.
  std::erase_if(found, [&](const Peak& p) { return p.prominence < o.noise_prominence * sigma_at(p); });
  double highest = 0.0;
  for (const Peak& p : found) highest = std::max(highest, p.magnitude);
  std::erase_if(found, [&](const Peak& p) { return p.magnitude < o.min_height * highest || !(p.magnitude > 0.0); });
  // Each raw peak with the nearest filtered peak within the window's half-width (none: smoothed
  // away). Several raw maxima on one filtered peak are noise ripple on one resonance's top: the
  // highest stands for it.
  const std::vector<Peak> after = find_peaks(filtered, PeakOptions{1e-12});
  const std::size_t half = static_cast<std::size_t>(std::max(1, window / 2));
  std::vector<std::pair<Peak, const Peak*>> pairs;
  for (const Peak& p : found) {
    const Peak* near = nullptr;
    for (const Peak& q : after) {
      const std::size_t d = q.index > p.index ? q.index - p.index : p.index - q.index;
      if (d <= half && (!near || std::abs(q.frequency_hz - p.frequency_hz) < std::abs(near->frequency_hz - p.frequency_hz)))
        near = &q;
    }
    if (near && !pairs.empty() && pairs.back().second == near) {
      if (p.magnitude > pairs.back().first.magnitude) pairs.back().first = p;
      continue;
    }
    pairs.emplace_back(p, near);
  }
  const std::string label = entry_name.empty() ? what : fmt::format("{} entry {}", what, entry_name);
  for (const auto& [p, near] : pairs) {
    PeakChange c;
    c.entry = entry_name;
    c.raw_frequency_hz = p.frequency_hz;
    c.raw_magnitude = p.magnitude;
    c.noise = sigma_at(p);
    if (near) {
      c.filtered_frequency_hz = near->frequency_hz;
      c.filtered_magnitude = near->magnitude;
      c.frequency_change = (near->frequency_hz - p.frequency_hz) / p.frequency_hz;
    } else {
      c.filtered_frequency_hz = std::numeric_limits<double>::quiet_NaN();
      c.filtered_magnitude = std::abs(filtered.values[p.index]);
      c.frequency_change = std::numeric_limits<double>::quiet_NaN();
    }
    c.height_change = (c.filtered_magnitude - p.magnitude) / p.magnitude;
    if (!near)
      report.warnings.push_back(
          fmt::format("{}: the peak at {:.6g} Hz was smoothed away (no peak within {} points after "
                      "filtering; height {:+.1f} %): shorten the window",
                      label, p.frequency_hz, half, 100.0 * c.height_change));
    else if (std::abs(c.height_change) > o.warn_above || std::abs(c.frequency_change) > o.warn_above)
      report.warnings.push_back(fmt::format(
          "{}: the filter changed the peak at {:.6g} Hz by {:+.1f} % in height and {:+.2f} % in frequency (more than {:g} %){}",
          label, p.frequency_hz, 100.0 * c.height_change, 100.0 * c.frequency_change, 100.0 * o.warn_above,
          std::abs(c.height_change) <= 2.0 * c.noise && std::abs(c.frequency_change) <= o.warn_above
              ? fmt::format(", within twice the raw data's noise there (σ = {:.1f} %): the change cannot be told from the noise",
                            100.0 * c.noise)
              : std::string(": shorten the window or raise the order")));
    report.peaks.push_back(c);
  }
}

// The absolute noise σ(f) of an FRF (E|ε|² = σ², both parts together), estimated from the data:
// the residuals r about a local 7-point cubic (which follows resonance peaks a few points wide and
// leaves white noise, its variance reduced by 1 − c₀), σ² = mean |r|² / (1 − c₀) over the 51
// points around f, leaving out points above 25 times their median (a spike, or a sharp peak the
// cubic cannot follow; for Gaussian noise, radial or isotropic, under 0.1 % of points). Local,
// because measured noise grows with the response near a resonance (a wider window averages it
// with the flanks and finds noise ripple on the peak's top prominent); absolute rather than
// relative, it holds where the noise exceeds the signal (rotational entries from finite
// differences). Empty when the series has fewer than 58 points.
std::vector<double> local_noise_sigma(const FrfSeries& raw, const std::string& what) {
  constexpr int kWindow = 51;
  const SavgolOptions local{7, 3};
  const std::size_t n = raw.size();
  if (n < static_cast<std::size_t>(kWindow + local.window)) return {};
  const FrfSeries smooth = savgol_filter(raw, local, what).series;
  const double keep_fraction = 1.0 - savgol_coefficients(local)[static_cast<std::size_t>(local.window / 2)];
  const std::size_t m = static_cast<std::size_t>(local.window / 2), lo = m, hi = n - m;  // the interior rows
  const std::size_t half = kWindow / 2, stride = std::max<std::size_t>(1, kWindow / 16);
  std::vector<double> q(n), sigma(n), buf;
  for (std::size_t i = lo; i < hi; ++i) q[i] = std::norm(raw.values[i] - smooth.values[i]);
  double level = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % stride == 0 || i == 0) {
      const std::size_t c = std::clamp(i + stride / 2, lo + half, hi - 1 - half);  // window centre, inside [lo, hi)
      buf.assign(q.begin() + static_cast<std::ptrdiff_t>(c - half), q.begin() + static_cast<std::ptrdiff_t>(c + half + 1));
      std::nth_element(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(half), buf.end());
      const double cut = 25.0 * buf[half];  // a spike, or a peak the cubic cannot follow
      double sum = 0.0;
      std::size_t kept = 0;
      for (double v : buf)
        if (v <= cut) {
          sum += v;
          ++kept;
        }
      level = kept ? std::sqrt(sum / (static_cast<double>(kept) * keep_fraction)) : 0.0;
    }
    sigma[i] = level;
  }
  return sigma;
}

void require_same_grid(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
  if (a != b)
    throw InvalidArgument(fmt::format("{}: the raw and filtered series have different frequency grids ({} and {} points)", what,
                                      a.size(), b.size()),
                          "compare a series with its own filtered copy");
}

}  // namespace

PeakChangeReport peak_changes(const FrfSeries& raw, const FrfSeries& filtered, int window, const PeakChangeOptions& options,
                              const std::string& what) {
  options.check();
  require_same_grid(raw.frequency_hz, filtered.frequency_hz, what);
  PeakChangeReport r;
  peak_changes_of(raw, filtered, window, options, local_noise_sigma(raw, what), what, "", r);
  return r;
}

PeakChangeReport peak_changes(const BlockSeries& raw, const BlockSeries& filtered, int window, const PeakChangeOptions& options,
                              const std::string& what) {
  options.check();
  require_same_grid(raw.frequency_hz, filtered.frequency_hz, what);
  PeakChangeReport r;
  static const char* names[4] = {"H", "L", "N", "P"};
  for (int k = 0; k < 4; ++k) {
    const FrfSeries e = entry(raw, k);
    peak_changes_of(e, entry(filtered, k), window, options, local_noise_sigma(e, what), what, names[k], r);
  }
  return r;
}

// ---- Simulated measurement noise ------------------------------------------------------------

void NoiseOptions::check() const { check_fields(noise_fields(), *this, "NoiseOptions"); }

const std::vector<OptionField<NoiseOptions>>& noise_fields() {
  using O = NoiseOptions;
  using K = FieldKind;
  // Fractions: a floor above half the peak buries the FRF; a calibration σ above 10 % is a broken
  // sensor, not an uncertain one; an averaged test needs two hits for its coherence.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "sigma",
        .kind = K::Real,
        .min = 0.0,
        .help = "standard deviation of the multiplicative factor, or of each averaged hit's variation (0.05 = 5 %)",
        .cli_name = "sigma"},
       [](O& o) -> double& { return o.sigma; }},
      {{.name = "floor",
        .kind = K::Real,
        .min = 0.0,
        .max = 0.5,
        .note = "0: none",
        .help = "additive floor: σ of the real and imaginary parts relative to each entry's peak |value| (0.01 = 1 %)",
        .cli_name = "floor"},
       [](O& o) -> double& { return o.floor; }},
      {{.name = "calibration",
        .kind = K::Real,
        .min = 0.0,
        .max = 0.1,
        .note = "0: none",
        .help = "σ of one calibration factor scaling the whole series (a sensor's sensitivity error; 0.02 = 2 %)",
        .cli_name = "calibration"},
       [](O& o) -> double& { return o.calibration; }},
      {{.name = "averages",
        .kind = K::Integer,
        .min = 2.0,
        .max = 10000.0,
        .automatic = 0.0,
        .note = "0: one noisy copy, the seed's single factor",
        .help = "hits of an averaged test (each varying by sigma in magnitude and phase, with the floor), whose coherence is "
                "given",
        .cli_name = "averages"},
       nullptr,
       [](O& o) -> int& { return o.averages; }}};
  return fields;
}

std::vector<double> standard_normals(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  constexpr double k2to53 = 0x1p-53;
  std::vector<double> z;
  z.reserve(count + 1);
  while (z.size() < count) {
    // The top 53 bits make a double exactly; +1 keeps u1 away from 0, where ln diverges.
    const double u1 = static_cast<double>((engine() >> 11) + 1) * k2to53;
    const double u2 = static_cast<double>(engine() >> 11) * k2to53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    z.push_back(r * std::cos(2.0 * kPi * u2));
    z.push_back(r * std::sin(2.0 * kPi * u2));
  }
  z.resize(count);
  return z;
}

namespace {

// The factors 1 + σz for `count` values, and a warning if any is ≤ 0.
std::vector<double> noise_factors(std::size_t count, const NoiseOptions& o, std::vector<std::string>& warnings) {
  std::vector<double> f = standard_normals(count, o.seed);
  std::size_t non_positive = 0;
  for (double& v : f) {
    v = 1.0 + o.sigma * v;
    if (v <= 0.0) ++non_positive;
  }
  if (non_positive > 0)
    warnings.push_back(
        fmt::format("noise sigma {}: {} of {} factors are ≤ 0, so those values changed sign", o.sigma, non_positive, count));
  return f;
}

// The simulated measurement of `e` complex entries per frequency (values[i·e + k]): signal.hpp.
// Returns the coherence of entry 0 with averages.
std::vector<double> measure(std::vector<Complex>& values, std::size_t entries, const NoiseOptions& o,
                            std::vector<std::string>& warnings, double& calibration_factor) {
  const std::size_t n = values.size() / entries;
  std::vector<double> peak(entries, 0.0);
  for (std::size_t i = 0; i < values.size(); ++i) peak[i % entries] = std::max(peak[i % entries], std::abs(values[i]));
  std::vector<double> coherence;
  if (o.averages == 0) {
    const auto f = noise_factors(values.size(), o, warnings);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] *= f[i];
    if (o.floor > 0.0) {
      const std::vector<double> z = standard_normals(2 * values.size(), stream_seed(o.seed, 0xF100A));
      for (std::size_t i = 0; i < values.size(); ++i)
        values[i] += o.floor * peak[i % entries] * Complex(z[2 * i], z[2 * i + 1]);
    }
  } else {
    // Hit k of entry value i: c from z[2(k·size + i)…], d from the floor's stream likewise.
    const auto N = static_cast<std::size_t>(o.averages);
    const std::vector<double> zc = standard_normals(2 * N * values.size(), o.seed);
    const std::vector<double> zd =
        o.floor > 0.0 ? standard_normals(2 * N * values.size(), stream_seed(o.seed, 0xF100A)) : std::vector<double>{};
    coherence.assign(n, 1.0);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const Complex x = values[i];
      const double a = o.floor * peak[i % entries];
      Complex sum = 0.0;
      double power = 0.0;
      for (std::size_t k = 0; k < N; ++k) {
        const std::size_t at = 2 * (k * values.size() + i);
        Complex hit = x * (1.0 + o.sigma * Complex(zc[at], zc[at + 1]) / std::sqrt(2.0));
        if (a > 0.0) hit += a * Complex(zd[at], zd[at + 1]);
        sum += hit;
        power += std::norm(hit);
      }
      values[i] = sum / static_cast<double>(N);
      // γ² ≤ 1 by Cauchy–Schwarz; identical noise-free hits reach it, and rounding can pass it by
      // an ulp, which a coherence check (uff_coherence) would refuse.
      if (i % entries == 0)
        coherence[i / entries] = power > 0.0 ? std::min(1.0, std::norm(sum) / (static_cast<double>(N) * power)) : 1.0;
    }
  }
  calibration_factor = 1.0;
  if (o.calibration > 0.0) {
    calibration_factor = 1.0 + o.calibration * standard_normals(1, stream_seed(o.seed, 0xCA11B7A7E))[0];
    for (Complex& v : values) v *= calibration_factor;
  }
  return coherence;
}

}  // namespace

NoisyMeasurement<FrfSeries> add_measurement_noise(const FrfSeries& series, const NoiseOptions& options, const std::string& what) {
  options.check();
  validate(series, what);
  NoisyMeasurement<FrfSeries> r{series, {}, 1.0, {}};
  r.coherence = measure(r.series.values, 1, options, r.warnings, r.calibration_factor);
  return r;
}

NoisyMeasurement<BlockSeries> add_measurement_noise(const BlockSeries& series, const NoiseOptions& options,
                                                    const std::string& what) {
  options.check();
  validate(series, what);
  NoisyMeasurement<BlockSeries> r{series, {}, 1.0, {}};
  std::vector<Complex> v;
  v.reserve(4 * series.size());
  for (const Block& b : series.blocks)
    for (int k = 0; k < 4; ++k) v.push_back(b(k / 2, k % 2));
  r.coherence = measure(v, 4, options, r.warnings, r.calibration_factor);
  for (std::size_t i = 0; i < series.size(); ++i)
    for (int k = 0; k < 4; ++k) r.series.blocks[i](k / 2, k % 2) = v[4 * i + static_cast<std::size_t>(k)];
  return r;
}

// ---- Rotational FRFs by finite differences ----------------------------------------------------

void RotationalOptions::check() const {
  check_fields(rotational_fields(), *this, "RotationalOptions");
  if (shear_stiffness && !(std::isfinite(*shear_stiffness) && *shear_stiffness > 0.0))
    throw InvalidArgument(fmt::format("RotationalOptions::shear_stiffness κGA = {} N must be > 0", *shear_stiffness),
                          "the shear stiffness of the section under the points, or unset for the total slope");
}

const std::vector<OptionField<RotationalOptions>>& rotational_fields() {
  using O = RotationalOptions;
  using K = FieldKind;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "order",
        .kind = K::Integer,
        .min = 1.0,
        .max = 2.0,
        .help = "finite-difference order: 1 (points 0, 1) or 2 (points 0, 1, 2)",
        .cli_name = "order"},
       nullptr,
       [](O& o) -> int& { return o.order; }},
      {{.name = "spacing",
        .kind = K::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "distance s between neighbouring points (e.g. 0.01 for 10 mm)",
        .cli_name = "spacing"},
       [](O& o) -> double& { return o.spacing; }},
      {{.name = "symmetrise",
        .kind = K::Flag,
        .help = "replace L and N by their mean (reciprocity L = N); default keeps both",
        .cli_name = "symmetrise"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.symmetrise; }},
      {{.name = "assume_reciprocity",
        .kind = K::Flag,
        .help = "fill a missing H_ij with H_ji (Maxwell–Betti), e.g. L from N when the hammer stayed at the tip; said in "
                "the output file's header. Default: a missing H_0k or H_k0 is an error (nothing is invented)",
        .cli_name = "assume-reciprocity"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.assume_reciprocity; }}};
  return fields;
}

void PointFrfs::set(int response, int force, FrfSeries series, std::string src) {
  if (response < 0 || response > 2 || force < 0 || force > 2)
    throw InvalidArgument(fmt::format("measurement point indices ({}, {}) must be 0, 1 or 2", response, force));
  h[response][force] = std::move(series);
  source[response][force] = std::move(src);
}

std::string PointFrfs::label(int i, int j) const {
  const std::string name = fmt::format("H{}{}", i, j);
  return source[i][j].empty() ? name : fmt::format("{} ({})", name, source[i][j]);
}

namespace {

// H_ij as used: measured, or its transpose by reciprocity, or absent.
struct Available {
  const FrfSeries* h[3][3] = {};
  bool transposed[3][3] = {};
};

Available gather(const PointFrfs& in, int points, bool reciprocity) {
  Available a;
  for (int i = 0; i < points; ++i)
    for (int j = 0; j < points; ++j) {
      if (in.h[i][j]) {
        a.h[i][j] = &*in.h[i][j];
      } else if (reciprocity && in.h[j][i]) {
        a.h[i][j] = &*in.h[j][i];
        a.transposed[i][j] = true;
      }
    }
  return a;
}

// Σ_k d_k H(k) at frequency index f, where H(k) picks the FRF for stencil point k.
template <class Pick>
Complex difference(const std::vector<double>& d, std::size_t f, Pick pick) {
  Complex s = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) s += d[k] * pick(static_cast<int>(k))->values[f];
  return s;
}

std::string list(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
  return s;
}

}  // namespace

RotationalResult rotational_frfs(const PointFrfs& in, const RotationalOptions& o) {
  o.check();
  const int points = o.order + 1;
  if (!in.h[0][0])
    throw InputError("rotational FRFs: H00 (response and force at the tip) is missing",
                     "give the tip point FRF measured with the hammer and the sensor at the tip");
  const FrfSeries& h00 = *in.h[0][0];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!in.h[i][j]) continue;
      validate(*in.h[i][j], in.label(i, j));
      require_same_grid(h00.frequency_hz, in.label(0, 0), in.h[i][j]->frequency_hz, in.label(i, j));
    }

  RotationalResult r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (in.h[i][j] && (i >= points || j >= points))
        r.warnings.push_back(
            fmt::format("{} is not used by order-{} differences (points 0..{})", in.label(i, j), o.order, points - 1));

  const Available a = gather(in, points, o.assume_reciprocity);
  for (int k = 1; k < points; ++k)
    if (!in.h[k][0] && !in.h[0][k])
      throw InputError(fmt::format("rotational FRFs of order {}: neither H{}0 (response {} s inward, force at the tip) "
                                   "nor H0{} (response at the tip, force {} s inward) is given",
                                   o.order, k, k, k, k),
                       "N and L need the response (or the hammer) moved to every point inward of the tip");
  for (int k = 1; k < points; ++k)
    for (const auto& [i, j, needs] : {std::tuple{k, 0, "N"}, std::tuple{0, k, "L"}})
      if (!a.h[i][j])
        throw InputError(fmt::format("rotational FRFs: H{}{} ({}) is not given, and {} needs it; {} is, but a measurement "
                                     "is not invented from another unless asked for",
                                     i, j,
                                     i == 0 ? fmt::format("response at the tip, force {} inward", k == 1 ? "s" : "2s")
                                            : fmt::format("response {} inward, force at the tip", k == 1 ? "s" : "2s"),
                                     needs, in.label(j, i)),
                         fmt::format("measure H{}{}, or let reciprocity stand in (H{}{} := H{}{}; "
                                     "RotationalOptions::assume_reciprocity), which makes L = N",
                                     i, j, i, j, j, i));
  std::vector<std::string> filled;
  for (int i = 0; i < points; ++i)
    for (int j = 0; j < points; ++j)
      if (a.transposed[i][j]) filled.push_back(fmt::format("H{}{} := {}", i, j, in.label(j, i)));
  r.filled_by_reciprocity = filled;
  bool n_transposed = false, l_transposed = false;
  for (int k = 1; k < points; ++k) {
    n_transposed = n_transposed || a.transposed[k][0];
    l_transposed = l_transposed || a.transposed[0][k];
  }
  r.l_equals_n_by_reciprocity = n_transposed || l_transposed;

  std::vector<std::string> missing;
  bool reciprocity_would_do = false;  // a missing H_ij whose transpose is given
  for (int i = 1; i < points; ++i)
    for (int j = i; j < points; ++j) {
      const bool have_ij = a.h[i][j] != nullptr, have_ji = a.h[j][i] != nullptr;
      if (i == j) {
        if (!have_ij) missing.push_back(fmt::format("H{}{}", i, j));
      } else if (!have_ij && !have_ji) {
        missing.push_back(o.assume_reciprocity ? fmt::format("H{}{} (or H{}{})", i, j, j, i)
                                               : fmt::format("H{}{} and H{}{}", i, j, j, i));
      } else if (!have_ij || !have_ji) {
        missing.push_back(fmt::format("H{}{}", have_ij ? j : i, have_ij ? i : j));
        reciprocity_would_do = true;
      }
    }
  r.p_from_cross_terms = missing.empty() && o.p_method != PMethod::SchmitzSmith;
  if (o.p_method == PMethod::CrossTerms && !missing.empty())
    throw InputError(fmt::format("rotational FRFs: P by finite differences of order {} needs {}, not given", o.order,
                                 list(missing)),
                     "measure with the hammer moved to the inner points too, or let P be approximated (p-method auto)");
  // A file that could not be read whole may have held what is missing: approximating P would
  // hide that (a truncated file reads as a test with the hammer at the tip only).
  if (o.p_method == PMethod::Auto && !missing.empty() && !in.unread.empty())
    throw InputError(fmt::format("rotational FRFs: P by finite differences of order {} needs {}, not given, and the source "
                                 "could not read {} of what it holds ({}{}): what is missing may be there",
                                 o.order, list(missing),
                                 in.unread.size() == 1 ? "one part" : fmt::format("{} parts", in.unread.size()),
                                 in.unread.front(), in.unread.size() > 1 ? "; …" : ""),
                     "repair or export the file again; to approximate P as N·L/H00 all the same, ask for it "
                     "(RotationalOptions::p_method SchmitzSmith)");

  const std::vector<double> d = o.order == 1 ? std::vector<double>{1.0 / o.spacing, -1.0 / o.spacing}
                                             : std::vector<double>{1.5 / o.spacing, -2.0 / o.spacing, 0.5 / o.spacing};
  const std::size_t n = h00.size();
  r.block.frequency_hz = h00.frequency_hz;
  r.block.blocks.resize(n);
  double mismatch = 0.0, peak = 0.0;
  // Shear corrections (see RotationalOptions::shear_stiffness): 1/κGA on N and L, c/(s κGA) on P.
  const double shear_nl = o.shear_stiffness ? 1.0 / *o.shear_stiffness : 0.0;
  const double shear_p = o.shear_stiffness ? (o.order == 1 ? 1.0 : 2.5) / (o.spacing * *o.shear_stiffness) : 0.0;
  for (std::size_t f = 0; f < n; ++f) {
    const Complex nn = difference(d, f, [&](int k) { return a.h[k][0]; }) - shear_nl;
    const Complex ll = difference(d, f, [&](int k) { return a.h[0][k]; }) - shear_nl;
    mismatch = std::max(mismatch, std::abs(ll - nn));
    peak = std::max({peak, std::abs(ll), std::abs(nn)});
    const Complex l_used = o.symmetrise ? 0.5 * (ll + nn) : ll;
    const Complex n_used = o.symmetrise ? 0.5 * (ll + nn) : nn;
    Complex p;
    if (r.p_from_cross_terms) {
      for (int i = 0; i < points; ++i) p += d[i] * difference(d, f, [&](int k) { return a.h[i][k]; });
      p -= shear_p;
    } else {
      const Complex h = h00.values[f];
      if (h == 0.0)
        throw NumericalError(fmt::format("P ≈ N·L/H00 at {} Hz: H00 is exactly 0", h00.frequency_hz[f]),
                             "give the cross terms (hammer moved to the inner points) so P needs no division");
      p = n_used * l_used / h;
    }
    r.block.blocks[f] = make_block(h00.values[f], l_used, n_used, p);
  }
  if (!r.l_equals_n_by_reciprocity) r.reciprocity_mismatch = peak > 0.0 ? mismatch / peak : 0.0;

  if (!filled.empty()) r.warnings.push_back(fmt::format("reciprocity H_ij = H_ji assumed for {}", list(filled)));
  if (r.l_equals_n_by_reciprocity)
    r.warnings.push_back("L and N come from the same data (reciprocity), so L = N is assumed, not measured");
  if (!r.p_from_cross_terms)
    r.warnings.push_back(fmt::format(
        "P approximated as N·L/H00 (Schmitz & Smith){}: exact for one mode only, about 25 % low on a static cantilever",
        o.p_method == PMethod::SchmitzSmith
            ? " as requested"
            : fmt::format(" because {} {} not given{}", list(missing), missing.size() == 1 ? "is" : "are",
                          reciprocity_would_do ? " (their transposes are: assume_reciprocity would use them)" : "")));
  return r;
}

}  // namespace toolpoint
