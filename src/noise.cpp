// toolpoint: noise of measured FRF blocks (noise.hpp).
#include "toolpoint/measured/noise.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/statistics.hpp"

namespace toolpoint {

namespace {

// A square root S of a positive semidefinite C (S Sᵀ = C), by pivoted LDLᵀ: rounding may leave
// tiny negative pivots on a singular C (the seed's radial-only noise), which are taken as zero.
Cov8 square_root(const Cov8& c) {
  const Eigen::LDLT<Cov8> ldlt(c);
  const Eigen::Matrix<double, 8, 1> d = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
  const Cov8 l = ldlt.matrixL();
  return ldlt.transpositionsP().transpose() * (l * d.asDiagonal());
}

}  // namespace

// Fills the square roots (once per distinct C: stated noise has one) and the summary.
void finish_block_noise(BlockNoise& n) {
  if (n.relative.empty()) return;
  n.root.resize(n.relative.size());
  for (std::size_t i = 0; i < n.relative.size(); ++i)
    n.root[i] = i > 0 && n.relative[i] == n.relative[i - 1] ? n.root[i - 1] : square_root(n.relative[i]);
  for (int e = 0; e < 4; ++e) {
    std::vector<double> m, p;
    for (const Cov8& c : n.relative) {
      m.push_back(std::sqrt(std::max(0.0, c(2 * e, 2 * e))));
      p.push_back(std::sqrt(std::max(0.0, c(2 * e + 1, 2 * e + 1))));
    }
    auto median = [](std::vector<double>& v) {
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      return v[v.size() / 2];
    };
    n.magnitude_sigma[static_cast<std::size_t>(e)] = median(m);
    n.phase_sigma_rad[static_cast<std::size_t>(e)] = median(p);
    std::vector<double> a;
    for (const Eigen::Vector4d& x : n.additive) a.push_back(std::sqrt(std::max(0.0, x(e))));
    n.floor[static_cast<std::size_t>(e)] = a.empty() ? 0.0 : median(a);
  }
}

namespace {

// The largest |x_e| over the series, per entry.
std::array<double, 4> peaks_of(const BlockSeries& data) {
  std::array<double, 4> p{};
  for (const Block& b : data.blocks)
    for (int e = 0; e < 4; ++e)
      p[static_cast<std::size_t>(e)] = std::max(p[static_cast<std::size_t>(e)], std::abs(b(e / 2, e % 2)));
  return p;
}

void set_floor_relative(BlockNoise& n, const std::array<double, 4>& peaks) {
  for (std::size_t e = 0; e < 4; ++e) n.floor_relative[e] = peaks[e] > 0.0 ? n.floor[e] / peaks[e] : 0.0;
}

}  // namespace

Vec8 vec8(const Block& b) {
  Vec8 v;
  for (int e = 0; e < 4; ++e) {
    v(2 * e) = b(e / 2, e % 2).real();
    v(2 * e + 1) = b(e / 2, e % 2).imag();
  }
  return v;
}

Cov8 polar_frame(const Block& x) {
  Cov8 r = Cov8::Zero();
  for (int e = 0; e < 4; ++e) {
    const Complex v = x(e / 2, e % 2);
    r(2 * e, 2 * e) = v.real();
    r(2 * e, 2 * e + 1) = -v.imag();
    r(2 * e + 1, 2 * e) = v.imag();
    r(2 * e + 1, 2 * e + 1) = v.real();
  }
  return r;
}

Cov8 BlockNoise::absolute(std::size_t i, const Block& x) const {
  if (exact()) return Cov8::Zero();
  // R is block diagonal (one 2×2 rotation-and-scale per entry): Σ_ef = R_e C_ef R_fᵀ block by block,
  // a quarter of the work of the full products.
  const Cov8& c = relative.at(i);
  Eigen::Matrix2d r[4];
  for (int e = 0; e < 4; ++e) {
    const Complex v = x(e / 2, e % 2);
    r[e] << v.real(), -v.imag(), v.imag(), v.real();
  }
  Cov8 s;
  for (int e = 0; e < 4; ++e)
    for (int f = 0; f <= e; ++f) {
      const Eigen::Matrix2d b = r[e] * c.block<2, 2>(2 * e, 2 * f) * r[f].transpose();
      s.block<2, 2>(2 * e, 2 * f) = b;
      s.block<2, 2>(2 * f, 2 * e) = b.transpose();
    }
  if (!additive.empty())
    for (int e = 0; e < 4; ++e) {
      s(2 * e, 2 * e) += additive[i](e);
      s(2 * e + 1, 2 * e + 1) += additive[i](e);
    }
  return s;
}

BlockNoise BlockNoise::subset(const std::vector<std::size_t>& indices) const {
  BlockNoise s = *this;
  if (exact()) return s;
  s.relative.clear();
  s.root.clear();
  s.additive.clear();
  for (std::size_t i : indices) {
    s.relative.push_back(relative.at(i));
    s.root.push_back(root.at(i));
    if (has_floor()) s.additive.push_back(additive.at(i));
  }
  return s;
}

void NoiseEstimateOptions::check() const {
  try {
    local.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("NoiseEstimateOptions::local: {}", e.what()), e.hint());
  }
  check_fields(noise_estimate_fields(), *this, "NoiseEstimateOptions");
  if (window % 2 == 0)
    throw InvalidArgument(fmt::format("NoiseEstimateOptions::window = {} must be odd and ≥ 21 (frequency points)", window),
                          "e.g. 201: the noise is averaged over that many points");
}

const std::vector<OptionField<NoiseEstimateOptions>>& noise_estimate_fields() {
  using O = NoiseEstimateOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "window",
        .kind = FieldKind::Integer,
        .min = 21.0,
        .help = "frequency points over which C is averaged, odd (e.g. 201)"},
       nullptr,
       [](O& o) -> int& { return o.window; }},
      {{.name = "floor", .kind = FieldKind::Flag, .help = "estimate an additive floor beside the multiplicative noise"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.floor; }}};
  return fields;
}

// The additive floor beside the multiplicative noise (noise.hpp). Per entry e, the residual u_i =
// (x_i − x̂_i) x̂_i*/|x̂_i| has a radial and a tangential part, each of mean square (without the
// smoother's share, 1 − c₀) E_r = v_r |x̂|² + a and E_t = v_t |x̂|² + a: the multiplicative noise's
// magnitude and phase variances (one each for the entry) and the floor a (the same on every part
// of a circular floor; one per chunk of `window` points). Fitted by iteratively reweighted least
// squares (each square is E χ²₁: weights 1/E²; spikes above 25 E left out; v, a ≥ 0), alternating
// between the chunks' floors and the v's. (A v per chunk is not determined where the floor
// dominates a whole chunk, and took wild values there.) A chunk's floor below twice its standard
// error is none; the floors are interpolated linearly between the chunks' centres. The floor is
// kept for the entry only where it describes the data better than the multiplicative noise
// alone (the first estimate): a lower negative log-likelihood of the squares, by more than Akaike's
// penalty of two per chunk. Then C(f) takes the v's as its variances and keeps the first
// estimate's correlations (C = D R D stays semidefinite).
void estimate_floor(const BlockSeries& data, const BlockSeries& smooth, double keep_fraction, std::size_t lo, std::size_t hi,
                    int window, BlockNoise& out) {
  const std::size_t n = data.size(), W = static_cast<std::size_t>(window);
  const std::size_t chunks = std::max<std::size_t>(1, (hi - lo) / W);  // the last chunk takes the remainder
  auto begin_of = [&](std::size_t c) { return lo + c * W; };
  auto end_of = [&](std::size_t c) { return c + 1 == chunks ? hi : lo + (c + 1) * W; };
  std::vector<Eigen::Vector4d> a(n, Eigen::Vector4d::Zero());
  std::array<std::array<double, 2>, 4> v{};  // per entry: radial, tangential
  std::array<bool, 4> kept{};
  for (int e = 0; e < 4; ++e) {
    std::vector<double> m(n, 0.0);
    std::array<std::vector<double>, 2> q{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
    for (std::size_t i = lo; i < hi; ++i) {
      const Complex xs = smooth.blocks[i](e / 2, e % 2);
      m[i] = std::norm(xs);
      const Complex u = m[i] > 0.0 ? (data.blocks[i](e / 2, e % 2) - xs) * std::conj(xs) / std::sqrt(m[i]) : Complex(0.0);
      q[0][i] = u.real() * u.real() / keep_fraction;
      q[1][i] = u.imag() * u.imag() / keep_fraction;
    }
    // Start: no floor, each v the median over the chunks of the mean of q/m.
    std::array<double, 2> vv{};
    for (int k = 0; k < 2; ++k) {
      std::vector<double> start;
      for (std::size_t c = 0; c < chunks; ++c) {
        double sum = 0.0, cnt = 0.0;
        for (std::size_t i = begin_of(c); i < end_of(c); ++i)
          if (m[i] > 0.0) {
            sum += q[static_cast<std::size_t>(k)][i] / m[i];
            cnt += 1.0;
          }
        if (cnt > 0.0) start.push_back(sum / cnt);
      }
      vv[static_cast<std::size_t>(k)] = start.empty() ? 0.0 : quantile(start, 0.5);
    }
    std::vector<double> ac(chunks, 0.0), se(chunks, 0.0), centre(chunks, 0.0);
    for (std::size_t c = 0; c < chunks; ++c) centre[c] = 0.5 * static_cast<double>(begin_of(c) + end_of(c) - 1);
    auto weight = [&](int k, std::size_t i, std::size_t c) {
      const double E = vv[static_cast<std::size_t>(k)] * m[i] + ac[c], x = q[static_cast<std::size_t>(k)][i];
      return E > 0.0 && std::isfinite(x) && x <= 25.0 * E ? 1.0 / (E * E) : 0.0;
    };
    for (int it = 0; it < 60; ++it) {
      for (std::size_t c = 0; c < chunks; ++c) {
        double num = 0.0, den = 0.0;
        for (std::size_t i = begin_of(c); i < end_of(c); ++i)
          for (int k = 0; k < 2; ++k) {
            const double w = weight(k, i, c);
            num += w * (q[static_cast<std::size_t>(k)][i] - vv[static_cast<std::size_t>(k)] * m[i]);
            den += w;
          }
        if (den > 0.0) {
          ac[c] = std::max(0.0, num / den);
          se[c] = std::sqrt(2.0 / den);  // each square has variance 2E²
        } else {                         // no variance at all yet here: start the floor from the squares
          double sum = 0.0;
          for (std::size_t i = begin_of(c); i < end_of(c); ++i) sum += 0.5 * (q[0][i] + q[1][i]);
          ac[c] = sum / static_cast<double>(end_of(c) - begin_of(c));
          se[c] = std::numeric_limits<double>::infinity();
        }
      }
      bool done = it > 2;
      for (int k = 0; k < 2; ++k) {
        double num = 0.0, den = 0.0;
        for (std::size_t c = 0; c < chunks; ++c)
          for (std::size_t i = begin_of(c); i < end_of(c); ++i) {
            const double w = weight(k, i, c);
            num += w * m[i] * (q[static_cast<std::size_t>(k)][i] - ac[c]);
            den += w * m[i] * m[i];
          }
        const double next = den > 0.0 ? std::max(0.0, num / den) : vv[static_cast<std::size_t>(k)];
        done = done && std::abs(next - vv[static_cast<std::size_t>(k)]) <= 1e-6 * std::max(next, 1e-300);
        vv[static_cast<std::size_t>(k)] = next;
      }
      if (done) break;
    }
    bool any = false;
    for (std::size_t c = 0; c < chunks; ++c) {
      if (!(ac[c] > 2.0 * se[c])) ac[c] = 0.0;  // no floor here
      any = any || ac[c] > 0.0;
    }
    if (!any) continue;
    // Linear between the chunks' centres, constant beyond them.
    std::vector<double> ae(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = static_cast<double>(std::clamp(i, lo, hi - 1));
      std::size_t c = 0;
      while (c + 1 < chunks && centre[c + 1] <= x) ++c;
      double t = 0.0;
      if (c + 1 < chunks && x > centre[c]) t = (x - centre[c]) / (centre[c + 1] - centre[c]);
      ae[i] = (1.0 - t) * ac[c] + t * ac[std::min(c + 1, chunks - 1)];
    }
    // The likelihood comparison with the multiplicative noise alone (each square E χ²₁; a point's
    // share capped at a spike's 25).
    double nll_floor = 0.0, nll_plain = 0.0;
    for (std::size_t i = lo; i < hi; ++i) {
      if (!(m[i] > 0.0)) continue;
      for (int k = 0; k < 2; ++k) {
        const double x = q[static_cast<std::size_t>(k)][i];
        auto term = [&](double E) {
          return E > 0.0 ? std::min(x / (2.0 * E), 12.5) + 0.5 * std::log(E) : 12.5 + 0.5 * std::log(x + 1e-300);
        };
        nll_floor += term(vv[static_cast<std::size_t>(k)] * m[i] + ae[i]);
        nll_plain += term(out.relative[i](2 * e + k, 2 * e + k) * m[i]);
      }
    }
    if (!(nll_floor + 2.0 * static_cast<double>(chunks) < nll_plain)) continue;
    kept[static_cast<std::size_t>(e)] = true;
    v[static_cast<std::size_t>(e)] = vv;
    for (std::size_t i = 0; i < n; ++i) a[i](e) = ae[i];
  }
  if (std::none_of(kept.begin(), kept.end(), [](bool b) { return b; })) return;
  out.additive = std::move(a);
  for (std::size_t i = 0; i < n; ++i) {
    Cov8& c = out.relative[i];
    Eigen::Matrix<double, 8, 1> d;
    for (int k = 0; k < 8; ++k) d(k) = std::sqrt(std::max(0.0, c(k, k)));
    Cov8 r = Cov8::Identity();
    for (int k = 0; k < 8; ++k)
      for (int l = 0; l < 8; ++l)
        if (k != l && d(k) > 0.0 && d(l) > 0.0) r(k, l) = c(k, l) / (d(k) * d(l));
    for (int e = 0; e < 4; ++e)
      if (kept[static_cast<std::size_t>(e)])
        for (int k = 0; k < 2; ++k) d(2 * e + k) = std::sqrt(v[static_cast<std::size_t>(e)][static_cast<std::size_t>(k)]);
    c = d.asDiagonal() * r * d.asDiagonal();
  }
}

BlockNoise estimate_block_noise(const BlockSeries& data, const NoiseEstimateOptions& options, const std::string& what) {
  options.check();
  const std::size_t n = data.size();
  const auto need = static_cast<std::size_t>(options.window + options.local.window);
  validate(data, what, 1);
  if (n < need)
    throw InputError(fmt::format("{}: {} frequencies are too few to estimate the noise from the data (need at least {})", what, n,
                                 need),
                     "state the noise level instead (magnitude and phase σ), or measure on a finer grid");
  auto smooth = savgol_filter(data, options.local, what);
  const std::vector<double> c = savgol_coefficients(options.local);
  const std::size_t m = static_cast<std::size_t>(options.local.window / 2);
  const double keep_fraction = 1.0 - c[m];  // residual variance of white noise / its variance

  // Relative residuals in each entry's polar frame, interior points only (the edge rows of the
  // filter are not the symmetric projection the factor 1 − c₀ holds for).
  const std::size_t lo = m, hi = n - m;  // valid range [lo, hi)
  std::vector<Eigen::Matrix<double, 8, 1>> rho(n, Eigen::Matrix<double, 8, 1>::Zero());
  std::vector<double> q(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = lo; i < hi; ++i) {
    bool ok = true;
    for (int e = 0; e < 4 && ok; ++e) {
      const Complex xs = smooth.series.blocks[i](e / 2, e % 2);
      if (!(std::abs(xs) > 0.0)) {
        ok = false;
        break;
      }
      const Complex r = (data.blocks[i](e / 2, e % 2) - xs) / xs;
      rho[i](2 * e) = r.real();
      rho[i](2 * e + 1) = r.imag();
    }
    if (ok) q[i] = rho[i].squaredNorm();
  }
  // The averaging window around i, shifted to stay inside [lo, hi).
  const std::size_t half = static_cast<std::size_t>(options.window / 2);
  auto window = [&](std::size_t i) {
    std::size_t a = i > lo + half ? i - half : lo;
    std::size_t b = std::min(hi, a + 2 * half + 1);
    a = b > 2 * half + 1 + lo ? b - 2 * half - 1 : lo;
    return std::pair{a, b};
  };
  // Outliers against the local median of |ρ|²: the median of the window around every
  // `stride`-th point serves the points around it (a window's median barely moves over a
  // sixteenth of its width, and a median per point would cost a sort each).
  std::vector<char> keep(n, 0);
  std::vector<double> buf;
  const std::size_t stride = std::max<std::size_t>(1, (2 * half + 1) / 16);
  double median = 0.0;
  for (std::size_t i = lo; i < hi; ++i) {
    if ((i - lo) % stride == 0) {
      const auto [a, b] = window(std::min(hi - 1, i + stride / 2));
      buf.clear();
      for (std::size_t j = a; j < b; ++j)
        if (!std::isnan(q[j])) buf.push_back(q[j]);
      if (!buf.empty()) {
        std::nth_element(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(buf.size() / 2), buf.end());
        median = buf[buf.size() / 2];
      }
    }
    keep[i] = !std::isnan(q[i]) && q[i] <= 25.0 * median;
  }
  // Prefix sums of ρρᵀ and counts over the kept points: each window's mean in O(1).
  std::vector<Cov8> sum(n + 1, Cov8::Zero());
  std::vector<std::size_t> count(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    sum[i + 1] = sum[i];
    count[i + 1] = count[i];
    if (keep[i]) {
      sum[i + 1].noalias() += rho[i] * rho[i].transpose();
      ++count[i + 1];
    }
  }
  BlockNoise out;
  out.relative.resize(n);
  std::size_t thin = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto [a, b] = window(std::clamp(i, lo, hi - 1));
    const std::size_t k = count[b] - count[a];
    if (k < 8) {
      ++thin;
      out.relative[i] = Cov8::Zero();
      continue;
    }
    out.relative[i] = (sum[b] - sum[a]) / (static_cast<double>(k) * keep_fraction);
  }
  if (thin == n)
    throw InputError(
        fmt::format("{}: no frequency has a usable residual to estimate the noise from (an entry is zero throughout?)", what),
        "state the noise level instead (magnitude and phase σ)");
  if (options.floor) estimate_floor(data, smooth.series, keep_fraction, lo, hi, options.window, out);
  // Lag-1 correlation of the residuals over consecutive kept points, per chunk of `window`
  // points, and the median over the chunks. One ratio over the whole band is dominated by the few
  // frequencies near sharp peaks and antiresonances, where the local polynomial's misfit (smooth,
  // correlated) outweighs the noise: on clean 0.5 % tap-test data that alone moved it from −0.49
  // to −0.3. Smoothing or windowing acts on every chunk, so the median still sees it.
  std::vector<double> chunks;
  for (std::size_t a = lo; a + 1 < hi; a += 2 * half + 1) {
    const std::size_t b = std::min(hi, a + 2 * half + 1);
    double num = 0.0, den = 0.0;
    for (std::size_t i = a; i + 1 < b; ++i) {
      if (!keep[i]) continue;
      den += rho[i].squaredNorm();
      if (keep[i + 1]) num += rho[i].dot(rho[i + 1]);
    }
    if (den > 0.0) chunks.push_back(num / den);
  }
  if (chunks.empty()) {
    out.residual_correlation = std::numeric_limits<double>::quiet_NaN();
  } else {
    std::sort(chunks.begin(), chunks.end());
    const std::size_t k = chunks.size();
    out.residual_correlation = k % 2 ? chunks[k / 2] : 0.5 * (chunks[k / 2 - 1] + chunks[k / 2]);
  }
  out.source =
      fmt::format("estimated from the data (residuals about a {}-point order-{} local polynomial, averaged over {} points)",
                  options.local.window, options.local.order, options.window);
  out.warnings = std::move(smooth.warnings);
  if (thin > 0)
    out.warnings.push_back(
        fmt::format("{}: {} of {} frequencies had too few usable residuals nearby; their noise is taken as zero", what, thin, n));
  if (!(out.residual_correlation > -0.6 && out.residual_correlation < -0.4))
    out.warnings.push_back(fmt::format(
        "{}: the noise does not look white (lag-1 correlation of the residuals about a local polynomial {:.2f}; white noise "
        "gives −0.49): the data look smoothed, windowed or noise-free, so the noise estimated from them, and every interval "
        "built on it, may be misjudged; give the unfiltered data, or state the noise",
        what, out.residual_correlation));
  finish_block_noise(out);
  set_floor_relative(out, peaks_of(smooth.series));
  return out;
}

void StatedNoise::check() const {
  for (const auto& [name, v, limit, hint] :
       {std::tuple{"StatedNoise::magnitude_sigma", magnitude_sigma, 0.5, "a relative σ: 0.05 for 5 %"},
        std::tuple{"StatedNoise::phase_sigma_rad", phase_sigma_rad, 0.5, "in radians: 1° is 0.01745 rad"},
        std::tuple{"StatedNoise::floor", floor, 0.5, "relative to each entry's peak: 0.01 for 1 %"}}) {
    if (!(v >= 0.0 && std::isfinite(v))) throw InvalidArgument(fmt::format("{} = {} must be finite and ≥ 0", name, v), hint);
    if (v > limit) throw InvalidArgument(fmt::format("{} = {} is above {}: no measured FRF is that noisy", name, v, limit), hint);
  }
  if (magnitude_sigma == 0.0 && phase_sigma_rad == 0.0 && floor == 0.0)
    throw InvalidArgument(
        "StatedNoise::magnitude_sigma 0, StatedNoise::phase_sigma_rad 0 rad and StatedNoise::floor 0: stated "
        "noise is not all zero",
        "state the noise the data have; for exact (model) data use no noise at all");
}

BlockNoise stated_block_noise(const BlockSeries& data, const StatedNoise& stated) {
  stated.check();
  validate(data, "stated noise's data", 1);
  Cov8 c = Cov8::Zero();
  for (int e = 0; e < 4; ++e) {
    c(2 * e, 2 * e) = stated.magnitude_sigma * stated.magnitude_sigma;
    c(2 * e + 1, 2 * e + 1) = stated.phase_sigma_rad * stated.phase_sigma_rad;
  }
  BlockNoise out;
  out.relative.assign(data.size(), c);
  const std::array<double, 4> peaks = peaks_of(data);
  if (stated.floor > 0.0) {
    Eigen::Vector4d a;
    for (int e = 0; e < 4; ++e) a(e) = std::pow(stated.floor * peaks[static_cast<std::size_t>(e)], 2);
    out.additive.assign(data.size(), a);
  }
  out.source = fmt::format("stated: relative magnitude σ = {:g} %, phase σ = {:g}°{} on every entry",
                           100 * stated.magnitude_sigma, degrees_of(stated.phase_sigma_rad),
                           stated.floor > 0.0 ? fmt::format(", a floor of {:g} % of each entry's peak", 100 * stated.floor)
                                              : std::string());
  out.residual_correlation = std::numeric_limits<double>::quiet_NaN();
  finish_block_noise(out);
  set_floor_relative(out, peaks);
  return out;
}

double h1_relative_variance(double coherence, int averages) {
  if (!(coherence >= 0.0 && coherence <= 1.0))
    throw InvalidArgument(fmt::format("coherence {} must lie in [0, 1]", coherence), "γ² is a fraction, not a percentage");
  if (averages < 2)
    throw InvalidArgument(fmt::format("{} averages: a coherence needs at least 2", averages),
                          "give the number of averages behind the coherence");
  if (coherence <= 0.0) return 1.0;
  return std::min(1.0, (1.0 - coherence) / (2.0 * (averages - 1) * coherence));
}

void apply_coherence(BlockNoise& noise, const std::vector<double>& coherence, int averages, const std::string& what) {
  if (noise.exact()) throw InvalidArgument(fmt::format("{}: a coherence cannot be applied to exact data's noise", what));
  if (averages < 2)
    throw InvalidArgument(fmt::format("{}: {} averages: the coherence needs the number of averages (≥ 2) behind it", what,
                                      averages),
                          "give the number of averages the measurement software used");
  if (coherence.size() != noise.size())
    throw InputError(fmt::format("{}: the coherence column has {} values for {} frequencies", what, coherence.size(),
                                 noise.size()),
                     "give one coherence value per frequency");
  for (std::size_t i = 0; i < coherence.size(); ++i)
    if (!(coherence[i] >= 0.0 && coherence[i] <= 1.0))
      throw InputError(fmt::format("{}: coherence {} at point {} is outside [0, 1]", what, coherence[i], i + 1),
                       "a coherence γ² lies in [0, 1]; a column in per cent or in dB is not one");
  for (std::size_t i = 0; i < coherence.size(); ++i) {
    const double eps2 = h1_relative_variance(coherence[i], averages);
    Cov8& c = noise.relative[i];
    Eigen::Matrix<double, 8, 1> d = Eigen::Matrix<double, 8, 1>::Ones();
    for (int k : {0, 1}) d(k) = c(k, k) > 0.0 ? std::sqrt(eps2 / c(k, k)) : 0.0;
    c = d.asDiagonal() * c * d.asDiagonal();  // H's correlations kept in proportion (D C D stays semidefinite)
    c(0, 0) = c(1, 1) = eps2;
  }
  for (Eigen::Vector4d& a : noise.additive) a(0) = 0.0;
  noise.coherence = fmt::format("H from its coherence and {} averages (Bendat & Piersol: (1 − γ²)/(2 (n − 1) γ²))", averages);
  const std::array<double, 4> relative_floor = noise.floor_relative, floor = noise.floor;
  finish_block_noise(noise);
  for (std::size_t e = 0; e < 4; ++e)
    if (floor[e] > 0.0) noise.floor_relative[e] = relative_floor[e] * noise.floor[e] / floor[e];
}

BlockNoise exact_block_noise() {
  BlockNoise out;
  out.source = "exact (model data, no noise)";
  out.residual_correlation = std::numeric_limits<double>::quiet_NaN();
  return out;
}

double calibration_normal(std::uint64_t seed) { return standard_normals(1, stream_seed(seed, 0xCA11B7A7E))[0]; }

BlockSeries draw_block_noise(const BlockSeries& truth, const BlockNoise& noise, std::uint64_t seed, bool with_calibration) {
  if (noise.exact()) return truth;
  if (noise.size() != truth.size())
    throw InvalidArgument(fmt::format("noise model for {} frequencies applied to {} frequencies", noise.size(), truth.size()));
  const std::vector<double> z = standard_normals(8 * truth.size(), seed);
  const bool floor = noise.has_floor();
  const std::vector<double> za = floor ? standard_normals(8 * truth.size(), stream_seed(seed, 0xF100A)) : std::vector<double>{};
  const double scale = with_calibration && noise.calibration > 0.0 ? 1.0 + noise.calibration * calibration_normal(seed) : 1.0;
  BlockSeries out = truth;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Eigen::Matrix<double, 8, 1> rho = noise.root[i] * Eigen::Map<const Eigen::Matrix<double, 8, 1>>(z.data() + 8 * i);
    Eigen::Matrix<double, 8, 1> add = Eigen::Matrix<double, 8, 1>::Zero();
    if (floor)
      for (int k = 0; k < 8; ++k) add(k) = std::sqrt(noise.additive[i](k / 2)) * za[8 * i + static_cast<std::size_t>(k)];
    for (int e = 0; e < 4; ++e) {
      const Complex x = truth.blocks[i](e / 2, e % 2);
      out.blocks[i](e / 2, e % 2) = scale * (x + x * Complex(rho(2 * e), rho(2 * e + 1)) + Complex(add(2 * e), add(2 * e + 1)));
    }
  }
  return out;
}

std::string BlockNoise::summary() const {
  if (exact()) return source;
  std::string s = fmt::format("magnitude σ {:.3g} % (H) … {:.3g} % (P), phase σ {:.3g}° (H)", 100 * magnitude_sigma[0],
                              100 * magnitude_sigma[3], degrees_of(phase_sigma_rad[0]));
  if (has_floor())
    s += fmt::format("; floor {:.3g} % (H) … {:.3g} % (P) of each entry's peak", 100 * floor_relative[0],
                     100 * floor_relative[3]);
  if (!coherence.empty()) s += "; " + coherence;
  if (calibration > 0.0) s += fmt::format("; calibration σ {:g} % (stated)", 100 * calibration);
  return s + "; " + source;
}

BlockSeries noise_free_estimate(const BlockSeries& data, const BlockNoise& noise, const std::string& what) {
  if (noise.exact()) return data;
  if (data.size() < 7)
    throw InputError(fmt::format("{}: {} frequencies are too few for measured data (need at least 7)", what, data.size()),
                     "fit a wider band");
  return savgol_filter(data, kNoiseFreeSmoothing, what).series;
}

std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  // splitmix64 (Steele, Lea & Flood 2014) of a combination of both: consecutive streams differ
  // in every bit.
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace toolpoint
