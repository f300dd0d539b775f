// toolpoint: the noise of measured FRF blocks — estimated from the data themselves, or stated.
//
// Model. Each complex entry x_e (e = H, L, N, P) of a measured 2×2 receptance block carries an
// error ε_e with up to three parts, as real measurements have them:
//   * multiplicative (hit-to-hit variation, the seed's noise): in the entry's own polar frame the
//     relative error ρ_e = ε_e / x_e has a radial part Re ρ_e (δ|x|/|x|) and a tangential part
//     Im ρ_e (the phase error δφ, rad). The eight real parts (Re ρ_H, Im ρ_H, …, Im ρ_P) have an
//     8×8 covariance C(f) that varies slowly with frequency: magnitude and phase noise, their
//     correlation, and the correlation between entries (rotational entries from finite differences
//     share the translational measurements). The seed's factor 1 + σz per entry is radial only:
//     C = σ² on the radial diagonal, 0 elsewhere.
//   * additive (a floor from the sensors and the hammer, constant in absolute terms): a variance
//     a_e(f) of each of the real and imaginary parts of ε_e, independent of x. It is what makes
//     antiresonances and weak entries poorly measured: there the floor outweighs x ρ. A measured
//     translational FRF has a constant floor; entries made from several measurements (rotations by
//     finite differences) carry their sum, which varies slowly with frequency — so a_e(f) may.
//   * calibration: a sensor's sensitivity error scales the whole series by 1 + δ, δ ~ N(0, σ_c²),
//     the same factor at every frequency and on every entry (the rotational entries are differences
//     of FRFs measured with the same sensors). No amount of data reveals it: it is stated, and the
//     estimators carry it into their intervals (joint_fit.hpp).
// At one frequency, around the value x the noise rides on, the covariance of the real and
// imaginary parts of ε (without calibration) is Σ = R(x) C R(x)ᵀ + A, R(x) = blockdiag_e [[Re x_e,
// −Im x_e], [Im x_e, Re x_e]] (ε_e = x_e ρ_e as a real 2×2 product), A = diag(a_H, a_H, a_L, …).
// Units: C dimensionless (rad² for the phase parts); a and Σ in the squared units of the entries
// (H m²/N², …).
//
// Coherence (Bendat & Piersol, Random Data, 4th ed. 2010, §9.2.4): an H1 estimate from n_d
// averages with coherence γ² has a normalised random error of its magnitude, and a standard
// deviation of its phase in radians, of ε = √(1 − γ²) / (|γ| √(2 n_d)) each. The coherence a
// measurement reports is itself estimated from the same n_d averages, and 1 − γ̂² then sees the
// scatter of n_d − 1 degrees of freedom: ε² = (1 − γ̂²)/(2 (n_d − 1) γ̂²) removes that bias (to
// first order in the noise; checked against averaged simulated hits in the tests). These are the
// radial and tangential variances of that entry at that frequency. Where a measured block carries
// the coherence of its H entry (a CSV coherence column), apply_coherence puts it there.
//
// Estimated from the data (estimate_block_noise): the residual of each entry about a local
// Savitzky–Golay polynomial (default 7 points, cubic: it follows resonance peaks a few points wide
// and leaves white noise) estimates ε. For white noise the residual variance is the noise variance
// times 1 − c₀ (c₀ the filter's centre weight; the projection is symmetric and idempotent). The
// floor and the multiplicative level of each entry are told apart by how they depend on |x|: the
// radial and tangential squares of the residual have means v_r|x|² + a(f) and v_t|x|² + a(f), one
// magnitude and one phase variance per entry and a floor per chunk of `window` points, fitted by
// iteratively reweighted least squares (weights 1/E²; v, a ≥ 0; a floor below twice its standard
// error is none), the floor interpolated between the chunks' centres. The floor is kept for an
// entry only where it describes the data better than the multiplicative noise alone (a likelihood
// comparison with Akaike's penalty).
// C(f) then has the variances v (split between magnitude and phase as the multiplicative-only
// estimate splits them) and that estimate's correlations. That estimate, the mean of ρρᵀ/(1 − c₀)
// over a window of frequencies, is C(f) when no entry has a floor. Points whose residual
// exceeds 25 times its expectation are spikes and left out (for Gaussian noise that discards
// below 0.1 % of points). The lag-1 correlation of the residuals is that of white noise through
// I − S, (Σ_j c_j c_{j−1} − 2c₁)/(1 − c₀) = −0.49 for the default polynomial; far from it
// (outside −0.6…−0.4) the noise is not white — smoothed, windowed or noise-free data — the
// estimate may be misjudged, and the result says so.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint {

using Cov8 = Eigen::Matrix<double, 8, 8>;
using Vec8 = Eigen::Matrix<double, 8, 1>;

// The 8 real parts of a block: Re and Im of H, L, N, P, in that order (the order of Cov8's rows).
Vec8 vec8(const Block& b);

// R(x): ε_e = x_e ρ_e as a real 8×8 map from the relative parts to the absolute ones.
Cov8 polar_frame(const Block& x);

struct BlockNoise {
  // C(f) per frequency of the data it describes (zero where there is no multiplicative part);
  // empty for exact data (no noise at all).
  std::vector<Cov8> relative;
  // A square root S(f) of each C(f) (S Sᵀ = C), for drawing noise; filled with `relative`.
  std::vector<Cov8> root;
  // The additive floor: per frequency, the variance a_e of each part of each entry (H, L, N, P),
  // in the entries' squared units; empty when there is none.
  std::vector<Eigen::Vector4d> additive;
  // σ of the calibration factor 1 + δ common to the whole series (0.02 = 2 %); 0: none.
  double calibration = 0.0;
  // Where it came from, for reports: "estimated from the data (…)", "stated (…)", "exact".
  std::string source;
  // Median over frequency of each entry's relative magnitude σ (√C radial) and phase σ (√C
  // tangential, rad): H, L, N, P.
  std::array<double, 4> magnitude_sigma{}, phase_sigma_rad{};
  // The floor: the median over frequency of √a_e per entry [entry units], and the same over the
  // entry's largest |x| in the data (0.01 = 1 % of the peak).
  std::array<double, 4> floor{}, floor_relative{};
  // How a coherence entered (apply_coherence); empty when none did.
  std::string coherence;
  // Estimated noise only: the lag-1 correlation of the local-fit residuals, the median over chunks
  // of `window` points (white noise: −0.49 for the 7-point cubic; otherwise smoothed, windowed or
  // noise-free data), NaN otherwise.
  double residual_correlation = 0.0;
  std::vector<std::string> warnings;

  bool exact() const { return relative.empty(); }
  bool has_floor() const { return !additive.empty(); }
  std::size_t size() const { return relative.size(); }
  // Σ_i = R(x) C_i R(x)ᵀ + A: the absolute covariance at frequency i around the value x (without
  // the calibration, which is common to every frequency).
  Cov8 absolute(std::size_t i, const Block& x) const;
  // The same noise on the frequencies of `indices` only (a band of the data), in that order.
  BlockNoise subset(const std::vector<std::size_t>& indices) const;
  // One line for reports: the multiplicative σ, the floor, the calibration, the coherence, the source.
  std::string summary() const;
};

// The short smoother of measured data: the 7-point cubic follows resonance peaks a few points
// wide. The noise estimate takes residuals about it; noise_free_estimate is it.
inline constexpr SavgolOptions kNoiseFreeSmoothing{7, 3};

struct NoiseEstimateOptions {
  SavgolOptions local = kNoiseFreeSmoothing;  // the local polynomial the residuals are taken about
  int window = 201;                           // frequency points over which C is averaged (odd, ≥ 21)
  bool floor = true;                          // estimate an additive floor beside the multiplicative noise
  // Throws InvalidArgument naming NoiseEstimateOptions::local or NoiseEstimateOptions::window (the
  // range of noise_estimate_fields(), and odd).
  void check() const;
};

/// \brief NoiseEstimateOptions' scalar fields defined once (option_fields.hpp): check() and the
/// attributes of Python's NoiseEstimateOptions derive from this table (`local`, a SavgolOptions,
/// is checked by its own check(); the window's oddness beside the table).
/// \return the table, in the order of the fields
const std::vector<OptionField<NoiseEstimateOptions>>& noise_estimate_fields();

// Estimates C(f) and the floor A from a measured block series (above). Throws InputError (naming
// `what`) when the series is invalid or has fewer than window + local.window points, or when no
// point is usable.
BlockNoise estimate_block_noise(const BlockSeries& data, const NoiseEstimateOptions& options, const std::string& what);

// The parts of a noise model a user states.
struct StatedNoise {
  double magnitude_sigma = 0.0;  // multiplicative: relative σ of the magnitude (0.05 = 5 %, the seed's noise)
  double phase_sigma_rad = 0.0;  // multiplicative: σ of the phase [rad]
  double floor = 0.0;            // additive: σ of each part relative to each entry's largest |x| (0.01 = 1 %)
  // Throws InvalidArgument naming `StatedNoise::<field>`: negative or non-finite values, all zero
  // (exact data: use exact_block_noise), or implausible ones (a σ or floor above 0.5 is a
  // percentage given as a number; a phase σ above 0.5 rad is degrees).
  void check() const;
};

// Noise stated for `data` (the floor relative to each entry's largest |x| there), independent
// between entries and frequencies. Throws as StatedNoise::check, and InputError for invalid data.
BlockNoise stated_block_noise(const BlockSeries& data, const StatedNoise& stated);

// No noise: data from a model.
BlockNoise exact_block_noise();

// Completes a noise model built from its parts (relative, additive, source set): the square roots
// for drawing and the summary (magnitude_sigma, phase_sigma_rad, floor). The floor relative to the
// peak needs the data (stated_block_noise and estimate_block_noise set it).
void finish_block_noise(BlockNoise& noise);

// The relative variance of an H1 estimate from `averages` averages with the coherence γ̂² estimated
// from them (above): (1 − γ̂²) / (2 (n_d − 1) γ̂²), for the radial and the tangential part each;
// capped at 1 (γ̂² → 0: the estimate carries no information). Throws InvalidArgument for γ̂² outside
// [0, 1] or n_d < 2.
double h1_relative_variance(double coherence, int averages);

// Puts the variance of the H entry that its coherence and number of averages give into `noise`
// (H's radial and tangential variance in C(f); H's correlations with the other entries kept in
// proportion; H's share of the floor removed: the coherence already counts it). The other entries
// keep theirs. Throws InputError naming `what` for a coherence of another length than the noise
// or values outside [0, 1] (NaN too), InvalidArgument for exact noise or averages < 1.
void apply_coherence(BlockNoise& noise, const std::vector<double>& coherence, int averages, const std::string& what);

// One draw of data: (1 + δ)(truth_i + ε_i) with ε_i Gaussian of covariance R(truth_i) C_i
// R(truth_i)ᵀ + A and δ ~ N(0, calibration²) when `with_calibration`, reproducible from `seed`
// (standard_normals of signal.hpp: 8 numbers per frequency in frequency order for C; the floor and
// δ from streams of their own, so a model without them draws exactly as a multiplicative one).
// Exact noise returns `truth`. Throws InvalidArgument when the sizes differ.
BlockSeries draw_block_noise(const BlockSeries& truth, const BlockNoise& noise, std::uint64_t seed, bool with_calibration = true);

// The standard normal behind the calibration factor of draw_block_noise(…, seed): δ = calibration × it.
double calibration_normal(std::uint64_t seed);

// The data with their noise smoothed away, the truth of a bootstrap world (joint_fit.hpp,
// forward_check.hpp): exact data as they are, measured data through the 7-point cubic the noise
// estimate uses (it follows resonance peaks a few points wide). Throws InputError (naming `what`)
// for measured data shorter than 7 points.
BlockSeries noise_free_estimate(const BlockSeries& data, const BlockNoise& noise, const std::string& what);

// Seeds for independent streams (bootstrap replicates, Monte Carlo samples): splitmix64 of `seed`
// and `stream`, so neighbouring streams are unrelated and the same for any thread count.
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream);

}  // namespace toolpoint
