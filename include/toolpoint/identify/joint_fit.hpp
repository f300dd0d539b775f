// toolpoint: a joint's constant parameters fitted to measured FRFs over a band (output error),
// with intervals whose coverage is measured.
//
// Why. The seed reads K(ω) from the closed form (Eq. 6, 15, 18; identify.hpp) at the mode the
// joint controls. That inverts noisy data twice and throws most of the data away; once the noise
// gain times the noise approaches 1 the read-out is biased, not only scattered. Here the joint's
// constants θ are chosen so that the forward model reproduces the measured FRF entries at every
// frequency of a band. All three identifications have the form (seed Eq. 5, 1 and 17)
//     G11(θ) = A11 − A12 (A22 + K(θ)⁻¹ + B11)⁻¹ A21 = A11 − A12 K (I + M K)⁻¹ A21,  M = A22 + B11
// (A a free–free component from the model, B11 and G11 measured; the second form needs no K⁻¹,
// so a singular trial K is harmless). The fit minimises
//     Σ_set-ups Σ_i r_iᵀ Ω_i r_i,   r_i = the 8 real parts of G11_measured(f_i) − G11(θ; B11_measured(f_i))
// Residuals in the FRF, not in the inverted K: that removes the inversion bias.
//
// Weights. Ω_i⁻¹ is the noise covariance of r_i: that of G11 plus that of B11 carried through the
// model (effective variance: Σ = Σ_G + J_B Σ_B J_Bᵀ, dG11 = (A12 X) dB11 (X A21), X = (M + K⁻¹)⁻¹),
// from noise models (noise.hpp) placed around model values, never around the noisy data (whose
// noise would then correlate with the weights and bias the fit). Within each entry no direction is
// trusted more than 1/kWeightFloor times another (the seed's multiplicative noise has no phase
// error at all, which real measurements never grant); and a relative floor of 1e-6 keeps exact
// model data weighted by relative error. The weights follow θ: two passes, each to convergence.
//
// Solver. Levenberg–Marquardt with Marquardt's diagonal scaling on parameters scaled to O(1),
// Jacobian in closed form: dG11 = −U dK V, U = A12 (I + K M)⁻¹, V = (I + M K)⁻¹ A21, dK = E_rc
// (stiffness) or iω E_rc (damping). Six parameters by default (k_θf = k_ym, c_θf = c_ym: the
// Betti–Maxwell reciprocity the seed's Section 2.2 expects), eight on request. The least-cost of
// several starting points is used (the study passes the closed-form read-outs and the file's values).
//
// B11 under an additive floor. Where B11's floor reaches a tenth of an entry's magnitude (its
// antiresonances under the floor), B11 enters the model through the short smoother of
// noise_free_estimate (noise.hpp), not raw: raw values near zero put noise-driven poles into the
// model, its cost grows local minima and the estimate depends on where the search starts
// (measured on the example with a 1 % floor: an 8 % spread of k_yf from one start to another, a
// −9 % bias, linearised errors 20× too small; smoothed: 0.9 % spread, −4.7 % bias before the
// correction below). The weights carry the smoothed noise's variance, the sandwich its correlation
// between neighbours exactly (A⁻¹ (Σ Y_jᵀ Σ_G,j Y_j + Σ U_kᵀ Σ_B,k U_k) A⁻¹, U_k = Σ_j S_jk J_B,jᵀ Y_j).
// Elsewhere B11 enters raw (the smoother's distortion of sharp peaks, small as it is, stays out).
//
// Filtered data. With `filter` set, the Savitzky–Golay filter is applied here to the measured G11
// and, identically, to the model's G11 series, so the peaks it flattens are flattened in both and
// do not bias θ. B11 enters the model unfiltered: filtering it would distort the model's input (the
// seed's 81-point window cuts SH11's first peak by 40 %), a bias no weighting removes. The
// correlation the filter puts between neighbouring frequencies enters the linearised covariance
// exactly (sandwich with the filter matrix S: A⁻¹ (Σ_j Y_jᵀ Σ_j Y_j) A⁻¹, Y = Sᵀ Ω J) and the
// bootstrap repeats the filtering. Give raw data: a file filtered elsewhere hides its noise
// (noise.hpp says so when estimating).
//
// Calibration (noise.hpp): a stated sensitivity error scales a whole measured series; it enters
// neither the weights nor the fit (no data reveal it) but every interval: linearised, by the
// implicit function theorem at the optimum (dθ = δ A⁻¹ Σ Jᵀ Ω Δ for a factor 1 + δ on the data Δ);
// in the bootstrap, by drawing the factors in every replicate.
//
// Uncertainty (UncertaintyMethod).
//   Linearised: the sandwich covariance above (A = Jᵀ Ω J) with the noise models' Σ — right even
//     though the working weights are floored — scaled up by √(residual ratio) when the data
//     scatter more than the noise models explain (ratio above 1.1). With B11 measured, checked by
//     kLinearisationCheck bootstrap replicates: where B11's noise acts nonlinearly (errors in
//     variables; an additive floor makes B11 noisier than its value away from its peaks) their
//     spread exceeds the linearised error, and the result becomes the bootstrap's on them;
//     otherwise the interval stays the linearised one, centred on the estimate corrected by the
//     replicates' bias (as the bootstrap's below), its variance × (1 + 1/N) for the bias's own
//     Monte Carlo error (× (1 + m/N) with the second world below, m measured from its pairs).
//   Bootstrap (default): a parametric bootstrap on the fitted model (Efron & Tibshirani 1993,
//     ch. 6 and 10). In each replicate the "truth" is θ̂ and the smoothed measured B11; data are
//     drawn from the noise models (a fresh B11 and G11 = model(θ̂) + noise, G11 filtered if the
//     fit filters), and refitted by the same procedure, weights included (they come from the
//     smoothed B11, whose noise then correlates with the fit's). The replicates' mean minus θ̂
//     estimates the bias — second order in the noise: B11's noise inside a nonlinear model
//     (errors in variables), the weights' dependence on B11 — which is subtracted; their spread
//     gives the standard error, never below the linearised one (a spread of N replicates has a
//     Monte Carlo error of ~1/√(2N) itself; the correlations are the replicates'). Intervals:
//     bias-corrected estimate ± z·SE, SE scaled up as above. Where B11 enters smoothed, the world's
//     B11 carries smoothed noise of its own and the bias comes out smaller there than at the truth
//     (0.77 of it on the example with a 1 % floor): second_world_samples(N) more replicates in a
//     second world (the smoothed B11 of one draw in the first), each drawing the same noise as
//     its partner in the first (common random numbers), give the step b₁ − b₂ pair by pair, and
//     the bias is 2 b₁ − b₂ (the iterated bootstrap's correction, Hall 1992 §3.11); the pairs'
//     scatter gives the correction's Monte Carlo variance; kExtrapolationUncertainty times the step b₁ − b₂
//     it extrapolates by, and kCorrectionUncertainty times the correction itself, are added to the
//     covariance as systematic uncertainties of the correction. Coverage of these intervals is
//     measured over noise seeds in the tests and docs/identification.md (JointFitCoverage).
// A parameter is *determined* when its interval excludes 0 and spans less than a factor of two
// (|estimate| > 3·z·SE: the far end under twice the near one). The rule judges the estimate's own
// luck: a parameter whose standard error is a large fraction of the truth passes it only in the
// seeds that overestimate it, whose intervals then miss. A factor of three (|estimate| > 2·z·SE)
// called the example's c_yf under a 1 % floor (SE 41 % of the truth) determined in 21 of 200
// seeds, covered in 7; at a factor of two such a parameter needs a 3.5 SE overestimate.
//
// Several set-ups (the seed measured three overhangs; or several tools in one holder) share θ:
// all are fitted together, and each alone as well. Their agreement is tested: Q = Σ_s d_sᵀ C_s⁻¹
// d_s, d_s = θ_s − θ_joint, C_s the linearised covariance of set-up s alone, against the 99.9 %
// point of χ² with (S − 1)·p degrees of freedom (Wilson–Hilferty); a joint that does not transfer
// is reported, not hidden. (Set-ups sharing one measured B11 have correlated errors: the test is
// then conservative.)
//
// Units: SI throughout (joint.hpp); frequencies in Hz.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/model/joint.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint {

// Within one FRF entry, no direction of the residual is weighted more than 1/kWeightFloor times
// another (see above). Affects efficiency only: the covariance uses the unfloored noise.
inline constexpr double kWeightFloor = 0.1;

// Linearised intervals with a measured B11 are checked by this many bootstrap replicates; a spread
// beyond kLinearisationLimit times the linearised standard error replaces them (joint_fit.hpp).
inline constexpr std::size_t kLinearisationCheck = 20;
inline constexpr double kLinearisationLimit = 1.5;

// Where B11 enters smoothed, the second bootstrap world's correction 2 b₁ − b₂ extrapolates by the
// step b₁ − b₂ and is uncertain by kExtrapolationUncertainty such steps, and by
// kCorrectionUncertainty of the whole correction b = 2 b₁ − b₂ (both systematic terms in the
// covariance). Both are measured, not derived, on one case: the example's holder–tool joint under
// a 1 % floor, 200 data sets (linearised) and 40 (bootstrap, 100 replicates), each data set with
// replicate draws of its own (the ensemble two users make; with one replicate seed for all data
// sets the replicates' Monte Carlo error is common to every one of them and does not average out,
// which once made this case look covered at 95 % when it was at 85 %). The correction is 2–5
// standard errors for the stiffnesses there, and about a sixth of it is left after it (z-scores'
// mean −0.5 to −0.7); the corrected estimates also scatter 1.2× their replicates' spread (the
// correction varies with the data's B11, which no replicate of a fixed world sees). With the step
// alone the stiffnesses were covered in 85–91 %; with both terms, refitted over 200 data sets,
// 92.5 % each (linearised) and 90–94.5 % (bootstrap, 200 replicates), the dampings c_ym, c_θm
// 91–93.5 %; with the second world paired (second_world_samples), 95.0–96.0 % and 94.4–95.5 %
// (linearised), 91.5–95.5 % and 92.0–94.0 % (bootstrap) (docs/noise-and-verdict.md). The
// intervals hold by their width; their centre is still low by about 0.6 of their standard error.
inline constexpr double kExtrapolationUncertainty = 2.0;
inline constexpr double kCorrectionUncertainty = 0.2;

// The second bootstrap world's replicates, paired with the first world's first ones (the same noise
// drawn: common random numbers): a quarter of the first world's N, at least 5 (at most N). The
// pairs' differences scatter less than independent replicates would, so a quarter measures the
// step b₁ − b₂ about as well as N independent replicates did, at a quarter of their time: the
// correction's Monte Carlo variance came out 3.3–4.9 times the replicates' variance over N on the
// example under a 1 % floor (N = 200, three data sets), against 5 with N independent ones.
inline constexpr std::size_t second_world_samples(std::size_t first_world) {
  const std::size_t quarter = (first_world + 3) / 4 < 5 ? 5 : (first_world + 3) / 4;
  return quarter < first_world ? quarter : first_world;
}

// One measured set-up: G11 = A11 − A12 (A22 + K⁻¹ + B11)⁻¹ A21 on one frequency grid.
struct JointFitData {
  std::string label;            // names the set-up in messages and reports, e.g. "overhang 49.0 mm"
  std::vector<TwoPort> A;       // the free–free component from the model, per frequency of G11
  BlockSeries B11, G11;         // measured (B11 may come from the model: then b_noise is exact)
  std::string b_name, g_name;   // what they are (file names) for messages
  BlockNoise b_noise, g_noise;  // their noise on the same grid (noise.hpp)
};

enum class UncertaintyMethod { Bootstrap, Linearised };

struct JointFitOptions {
  bool reciprocal = true;               // six parameters (k_θf = k_ym, c_θf = c_ym); false: all eight
  std::optional<SavgolOptions> filter;  // fit Savitzky–Golay filtered data (see above); default: raw
  UncertaintyMethod uncertainty = UncertaintyMethod::Bootstrap;
  int bootstrap_samples = 200;  // replicates (≥ 20; the interval's own Monte Carlo error
                                // shrinks like 1/√N)
  std::uint64_t seed = 1;       // of the bootstrap's noise draws (replicate b: stream_seed(seed, b))
  // The measured series' calibration (BlockNoise::calibration) is one factor for all of them (one
  // sensor chain), not one per series (set-ups with the same B11 data share its factor anyway).
  bool shared_calibration = false;
  // Linearised intervals with a measured B11: checked by kLinearisationCheck bootstrap replicates
  // (above). Off: the plain sandwich (a prediction from exact data wants the linearisation itself).
  bool check_linearisation = true;
  double confidence = 0.95;              // of the intervals, in (0.5, 1)
  int max_iterations = 200;              // Levenberg–Marquardt iterations per pass
  ParallelOptions parallel;              // bootstrap replicates on these threads (results identical for any count)
  std::function<void(double)> progress;  // fraction of the bootstrap done; the library never prints
  // Throws InvalidArgument naming the JointFitOptions field.
  void check() const;
};

/// \brief JointFitOptions' scalar fields but the seed, defined once (option_fields.hpp): their
/// ranges and help, check() (bootstrap_samples only for the bootstrap) and the Python class's
/// docstring derive from it (filter, uncertainty, seed, parallel and progress have their own).
/// \return the table, in the order of the fields
const std::vector<OptionField<JointFitOptions>>& joint_fit_fields();

struct ParameterInterval {
  double estimate = 0.0;            // reported value: bias-corrected (bootstrap) or the fit (linearised)
  double fitted = 0.0;              // the least-squares value
  double bias = 0.0;                // bootstrap estimate of fitted's bias (0 when linearised)
  double std_error = 0.0;           // of estimate, SI units
  double lower = 0.0, upper = 0.0;  // the interval at JointFit::confidence
  bool determined = false;          // the interval excludes 0 and spans less than a factor of two
  bool free = true;                 // false: k_θf, c_θf of a reciprocal fit (equal to k_ym, c_ym)
};

// One set-up fitted alone (several set-ups only).
struct SetupFit {
  std::string label;
  JointParameters fitted;
  std::array<double, 8> std_error{};  // linearised
  double residual_ratio = 0.0;        // as JointFit::residual_ratio, for this set-up alone
  double disagreement = 0.0;          // d_sᵀ C_s⁻¹ d_s of the transfer test
};

struct JointFit {
  JointParameters parameters;                  // the estimates (ParameterInterval::estimate)
  std::array<ParameterInterval, 8> intervals;  // k_yf, c_yf, k_ym, c_ym, k_θf, c_θf, k_θm, c_θm
  Eigen::Matrix<double, 8, 8> covariance;      // of the estimates, SI units (reciprocal: θf rows = ym rows)
  // The stated calibration's share of each standard error (linearised, SI units; 0 without one).
  std::array<double, 8> calibration_std_error{};
  double confidence = 0.95;
  UncertaintyMethod method = UncertaintyMethod::Bootstrap;
  std::string method_description;  // for reports: how the intervals were made
  int bootstrap_samples = 0;       // replicates used (0: linearised)
  bool reciprocal = true;
  std::size_t points = 0;  // frequencies fitted, all set-ups
  // Weighted residual sum over its expectation under the noise models (≈ 1 when the model and the
  // noise models explain the data; NaN for exact data). Intervals are widened by √ratio above 1.1
  // (above residual_limit(fit, 1.1, 0.95) with a stated calibration).
  double residual_ratio = 0.0;
  // The stated calibration's share of that expectation. The noise's share concentrates (a sum
  // over thousands of frequencies); the calibration's is one draw of a factor per FRF, c σ² χ²₁:
  // a ratio is judged with residual_limit, not against a fixed number.
  double residual_calibration_share = 0.0;
  int iterations = 0;
  bool converged = false;
  std::vector<SetupFit> setups;                           // each set-up alone (only with several)
  double transfer_statistic = 0.0, transfer_limit = 0.0;  // Q and its 99.9 % limit (several set-ups)
  bool transfers = true;                                  // Q ≤ limit
  std::vector<std::string> warnings;

  Eigen::Matrix<double, 8, 8> correlation() const;
  bool determined(JointParameter p) const { return intervals[static_cast<std::size_t>(p)].determined; }
};

// The residual ratio that the noise at `noise_limit` times its expectation, plus the stated
// calibration factors at their `probability` quantile, reach: noise_limit (1 − s) + χ²₁(p) s, s the
// calibration's share (conservative for several factors: a weighted sum of χ²₁ has a lighter tail
// than one χ²₁ of the same mean). Without a calibration it is noise_limit.
double residual_limit(const JointFit& fit, double noise_limit, double probability);

// Fits the joint to the set-ups (all on their own grids; give each only the band to be fitted)
// from the best of `starts` (lowest weighted cost; at least one). Throws InvalidArgument (options,
// no start, empty data), InputError (sizes that differ, NaN, fewer frequencies than free
// parameters, a grid that is not increasing), NumericalError (a parameter that does not act on the
// FRFs in the band, or two that the data cannot tell apart — named; a singular model).
JointFit fit_joint(const std::vector<JointFitData>& data, const std::vector<JointParameters>& starts,
                   const JointFitOptions& options);

// The forward model of the fit at one frequency: G11 = A11 − A12 K (I + (A22 + B11) K)⁻¹ A21.
Block forward_g11(const TwoPort& A, const Block& B11, const Block& K);

// Its sensitivity to B11 as a real 8×8 map on the real and imaginary parts (entries H, L, N, P;
// noise.hpp's order): dG11 = (A12 X) dB11 (X A21), X = K (I + (A22 + B11) K)⁻¹.
Cov8 b11_jacobian(const TwoPort& A, const Block& B11, const Block& K);

}  // namespace toolpoint
