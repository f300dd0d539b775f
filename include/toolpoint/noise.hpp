// toolpoint: the noise of measured FRF blocks — estimated from the data themselves, or stated.
//
// Model. Each complex entry x_e (e = H, L, N, P) of a measured 2×2 receptance block carries an
// error ε_e. In the entry's own polar frame the relative error ρ_e = ε_e / x_e has a radial part
// Re ρ_e (the relative magnitude error δ|x|/|x|) and a tangential part Im ρ_e (the phase error δφ,
// rad). The eight real parts (Re ρ_H, Im ρ_H, Re ρ_L, Im ρ_L, Re ρ_N, Im ρ_N, Re ρ_P, Im ρ_P) have
// an 8×8 covariance C(f) that varies slowly with frequency. It holds magnitude and phase noise,
// their correlation (the seed's multiplicative noise, a real factor 1 + σz per entry, is radial
// only: C = σ² on the radial diagonal, 0 elsewhere), and the correlation between entries
// (rotational entries from finite differences share the translational measurements).
// The absolute covariance of the real and imaginary parts of ε at a frequency, around the value x
// the noise rides on, is Σ = R(x) C R(x)ᵀ with R(x) = blockdiag_e [[Re x_e, −Im x_e], [Im x_e,
// Re x_e]] (ε_e = x_e ρ_e as a real 2×2 product). Units: C is dimensionless (rad² for the phase
// parts), Σ in the squared units of the entries (H m²/N², …).
//
// Estimated from the data (estimate_block_noise): the residual of each entry about a local
// Savitzky–Golay polynomial (default 7 points, cubic: it follows resonance peaks a few points wide
// and leaves white noise), divided by the smoothed value, gives ρ per frequency. For white noise the
// residual variance is the noise variance times 1 − c₀ (c₀ the filter's centre weight; the
// projection is symmetric and idempotent), so C(f) is the mean of ρρᵀ over a window of frequencies
// (default 201 points) divided by 1 − c₀, leaving out points whose |ρ|² exceeds 25 times the local
// median (a spike, or a peak the polynomial cannot follow: for Gaussian noise that discards below
// 0.1 % of points). The lag-1 correlation of the residuals is that of white noise through I − S,
// (Σ_j c_j c_{j−1} − 2c₁)/(1 − c₀) = −0.49 for the default polynomial; far from it (outside
// −0.6…−0.4) the noise is not white — smoothed, windowed or noise-free data — the estimate may be
// misjudged, and the result says so.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/receptance.hpp"
#include "toolpoint/signal.hpp"

namespace toolpoint {

using Cov8 = Eigen::Matrix<double, 8, 8>;

// R(x): ε_e = x_e ρ_e as a real 8×8 map from the relative parts to the absolute ones.
Cov8 polar_frame(const Block& x);

struct BlockNoise {
  // C(f) per frequency of the data it describes; empty for exact data (no noise).
  std::vector<Cov8> relative;
  // A square root S(f) of each C(f) (S Sᵀ = C), for drawing noise; filled with `relative`.
  std::vector<Cov8> root;
  // Where it came from, for reports: "estimated from the data (…)", "stated (…)", "exact".
  std::string source;
  // Median over frequency of each entry's relative magnitude σ (√C radial) and phase σ (√C
  // tangential, rad): H, L, N, P.
  std::array<double, 4> magnitude_sigma{}, phase_sigma_rad{};
  // Estimated noise only: the lag-1 correlation of the local-fit residuals, the median over chunks
  // of `window` points (white noise: −0.49 for the 7-point cubic; otherwise smoothed, windowed or
  // noise-free data), NaN otherwise.
  double residual_correlation = 0.0;
  std::vector<std::string> warnings;

  bool exact() const { return relative.empty(); }
  std::size_t size() const { return relative.size(); }
  // Σ_i = R(x) C_i R(x)ᵀ: the absolute covariance at frequency i around the value x.
  Cov8 absolute(std::size_t i, const Block& x) const;
  // The same noise on the frequencies of `indices` only (a band of the data), in that order.
  BlockNoise subset(const std::vector<std::size_t>& indices) const;
};

struct NoiseEstimateOptions {
  SavgolOptions local{7, 3};  // the local polynomial the residuals are taken about
  int window = 201;           // frequency points over which C is averaged (odd, ≥ 21)
  // Throws InvalidArgument naming NoiseEstimateOptions::local or ::window.
  void check() const;
};

// Estimates C(f) from a measured block series (above). Throws InputError (naming `what`) when the
// series is invalid or has fewer than window + local.window points, or when no point is usable.
BlockNoise estimate_block_noise(const BlockSeries& data, const NoiseEstimateOptions& options, const std::string& what);

// Noise stated by the user on `size` frequencies: relative magnitude σ (0.05 = 5 %, the seed's
// multiplicative noise) and phase σ [rad] on every entry, independent. Throws InvalidArgument for
// negative or non-finite values, or both zero (use exact_block_noise).
BlockNoise stated_block_noise(std::size_t size, double magnitude_sigma, double phase_sigma_rad);

// No noise: data from a model.
BlockNoise exact_block_noise();

// One draw of data: truth_i + ε_i with ε_i Gaussian of covariance R(truth_i) C_i R(truth_i)ᵀ,
// reproducible from `seed` (standard_normals of signal.hpp; 8 numbers per frequency, in frequency
// order). Exact noise returns `truth`. Throws InvalidArgument when the sizes differ.
BlockSeries draw_block_noise(const BlockSeries& truth, const BlockNoise& noise, std::uint64_t seed);

// Seeds for independent streams (bootstrap replicates, Monte Carlo samples): splitmix64 of `seed`
// and `stream`, so neighbouring streams are unrelated and the same for any thread count.
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream);

}  // namespace toolpoint
