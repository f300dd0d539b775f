// toolpoint: noise of measured FRF blocks (noise.hpp).
#include "toolpoint/noise.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include <Eigen/Cholesky>

#include "toolpoint/error.hpp"

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

// Fills the square roots (once per distinct C: stated noise has one) and the summary.
void finish(BlockNoise& n) {
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
  }
}

}  // namespace

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
  return s;
}

BlockNoise BlockNoise::subset(const std::vector<std::size_t>& indices) const {
  BlockNoise s = *this;
  if (exact()) return s;
  s.relative.clear();
  s.root.clear();
  for (std::size_t i : indices) {
    s.relative.push_back(relative.at(i));
    s.root.push_back(root.at(i));
  }
  return s;
}

void NoiseEstimateOptions::check() const {
  try {
    local.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("NoiseEstimateOptions::local: {}", e.what()), e.hint());
  }
  if (window < 21 || window % 2 == 0)
    throw InvalidArgument(fmt::format("NoiseEstimateOptions::window = {} must be odd and ≥ 21 (frequency points)", window),
                          "e.g. 201: the noise is averaged over that many points");
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
  finish(out);
  return out;
}

BlockNoise stated_block_noise(std::size_t size, double magnitude_sigma, double phase_sigma_rad) {
  if (!(magnitude_sigma >= 0.0 && std::isfinite(magnitude_sigma)) || !(phase_sigma_rad >= 0.0 && std::isfinite(phase_sigma_rad)))
    throw InvalidArgument(
        fmt::format("noise σ: magnitude {} and phase {} rad must be finite and ≥ 0", magnitude_sigma, phase_sigma_rad));
  if (magnitude_sigma == 0.0 && phase_sigma_rad == 0.0)
    throw InvalidArgument("noise σ: magnitude and phase are both 0", "for exact (model) data use no noise at all");
  Cov8 c = Cov8::Zero();
  for (int e = 0; e < 4; ++e) {
    c(2 * e, 2 * e) = magnitude_sigma * magnitude_sigma;
    c(2 * e + 1, 2 * e + 1) = phase_sigma_rad * phase_sigma_rad;
  }
  BlockNoise out;
  out.relative.assign(size, c);
  out.source = fmt::format("stated: relative magnitude σ = {:g} %, phase σ = {:g}° on every entry", 100 * magnitude_sigma,
                           phase_sigma_rad * 180.0 / std::numbers::pi);
  out.residual_correlation = std::numeric_limits<double>::quiet_NaN();
  finish(out);
  return out;
}

BlockNoise exact_block_noise() {
  BlockNoise out;
  out.source = "exact (model data, no noise)";
  out.residual_correlation = std::numeric_limits<double>::quiet_NaN();
  return out;
}

BlockSeries draw_block_noise(const BlockSeries& truth, const BlockNoise& noise, std::uint64_t seed) {
  if (noise.exact()) return truth;
  if (noise.size() != truth.size())
    throw InvalidArgument(fmt::format("noise model for {} frequencies applied to {} frequencies", noise.size(), truth.size()));
  const std::vector<double> z = standard_normals(8 * truth.size(), seed);
  BlockSeries out = truth;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Eigen::Matrix<double, 8, 1> rho = noise.root[i] * Eigen::Map<const Eigen::Matrix<double, 8, 1>>(z.data() + 8 * i);
    for (int e = 0; e < 4; ++e) {
      const Complex x = truth.blocks[i](e / 2, e % 2);
      out.blocks[i](e / 2, e % 2) = x + x * Complex(rho(2 * e), rho(2 * e + 1));
    }
  }
  return out;
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
