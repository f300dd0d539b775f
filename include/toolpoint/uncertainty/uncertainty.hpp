// toolpoint: a joint's uncertainty carried forward — to the tool point FRF (a band) and to the
// chatter stability of a cut (quantile envelopes and the probability that a depth is stable).
//
// Method: Monte Carlo over the joint (the identified constants with their covariance, identified_joint.hpp
// / joint_fit.hpp): N joints drawn from the multivariate normal N(θ̂, C) — x = θ̂ + V √Λ z with
// C = V Λ Vᵀ (negative rounding eigenvalues taken as 0: a reciprocal fit's covariance is singular by
// construction, k_θf ≡ k_ym), z from standard_normals with seed stream_seed(seed, i) for sample i —
// each pushed through the model, the results summarised per frequency or per spindle speed.
// Samples run on every core (parallel.hpp) with results identical for any thread count.
// Only the joint's uncertainty is carried: the other components come from the model as given.
//
// Quantiles: linear between order statistics (Hyndman & Fan type 7, numpy's default).
// Units: SI (depths in m, receptances in m/N), frequencies in Hz, spindle speeds in rpm.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/model/joint.hpp"
#include "toolpoint/identify/identified_joint.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/statistics.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/stability/stability.hpp"

namespace toolpoint {

// `count` joints drawn from N(mean, covariance) (above). Throws InvalidArgument for count < 1, a
// covariance that is not finite, or one with a clearly negative eigenvalue.
std::vector<JointParameters> sample_joints(const JointParameters& mean, const Eigen::Matrix<double, 8, 8>& covariance, int count,
                                           std::uint64_t seed);

struct UncertaintyOptions {
  int samples = 200;  // Monte Carlo samples, 10…1000000
  std::uint64_t seed = 1;
  std::vector<double> levels{0.05, 0.5, 0.95};  // quantile levels, increasing in (0, 1)
  ParallelOptions parallel;
  std::function<void(double)> progress;  // fraction of the samples done
  // Throws InvalidArgument naming `UncertaintyOptions::<field>` (the ranges of uncertainty_fields();
  // levels not increasing within (0, 1)).
  void check() const;
};

// UncertaintyOptions' fields (option_fields.hpp): samples (flag --samples), and parallel.threads
// as parallel_fields()' threads. The seed (64 bits) and the levels (a list) are checked beside it.
const std::vector<OptionField<UncertaintyOptions>>& uncertainty_fields();

// The tool point FRF (H of SHT11) with the joint uncertain.
struct FrfBand {
  std::vector<double> frequency_hz;
  std::vector<double> levels;
  FrfSeries nominal;                           // with the joint's constants
  std::vector<std::vector<double>> magnitude;  // [level][frequency] quantiles of |H| [m/N]
  std::vector<std::vector<double>> phase_rad;  // [level][frequency] quantiles of ∠H, unwrapped around the nominal [rad]
  int samples = 0;
};

// Samples the joint of `joint` (its uncertainty must be present) inside `assembly` and returns the
// quantiles of the tool point FRF on `frequency_hz`. Throws InvalidArgument (options; a joint
// file without [uncertainty]) and what the model throws.
FrfBand tool_point_band(const Assembly& assembly, const JointFile& joint, const std::vector<double>& frequency_hz,
                        const UncertaintyOptions& options);

// The same for a tool point coupled to a measured SH11 (Eq. 5, couple_tool): the holder–tool joint
// uncertain, the measurement taken as exact.
FrfBand coupled_tool_point_band(const Assembly& assembly, const JointFile& joint, const BlockSeries& sh11,
                                const std::string& sh_name, const UncertaintyOptions& options);

// Stability with the joint uncertain: per spindle speed the quantiles of the stable depth (the
// zero-order envelope of each sample's tool point FRF, a symmetric tool: G_yy = G_xx), and the
// probability of stability on a speed × depth grid, P(n, a) = the fraction of samples whose
// envelope at n lies above a.
struct StabilityUncertainty {
  std::vector<double> speed_rpm;
  std::vector<double> levels;
  std::vector<double> nominal_depth_m;       // the envelope with the joint's constants
  std::vector<std::vector<double>> depth_m;  // [level][speed] quantiles of the stable depth [m]
  std::vector<double> depth_grid_m;          // the probability map's depths [m]
  Eigen::MatrixXd probability;               // (speed, depth) in [0, 1]
  int samples = 0;
};

// `frequency_hz`: the grid of the tool point FRFs the lobes come from (fine enough for the modes:
// a step ≤ ζf/5 near each). `depth_grid_m`: where the probability map is evaluated (increasing, ≥ 0).
// Throws InvalidArgument (options, an empty or decreasing depth grid, a joint file without
// uncertainty) and what zero_order_lobes throws.
StabilityUncertainty stability_uncertainty(const Assembly& assembly, const JointFile& joint,
                                           const std::vector<double>& frequency_hz, const CuttingConditions& cutting,
                                           const ZeroOrderOptions& lobes, const std::vector<double>& depth_grid_m,
                                           const UncertaintyOptions& options);

// One assembly's stable envelope: the spindle speeds [rpm] and the stable depth at each [m].
using StabilityEnvelope = std::pair<std::vector<double>, std::vector<double>>;

// The same by any method: `envelope` gives the envelope of each sample's assembly, and of the
// nominal's (the same speeds for all; it is called from every core at once). The lobes study's
// stability_uncertainty (studies/lobes.hpp) is this with the study's envelope. Throws
// InvalidArgument (options, the depth grid, a joint file without uncertainty) and what `envelope`
// throws.
StabilityUncertainty envelope_uncertainty(const Assembly& assembly, const JointFile& joint,
                                          const std::function<StabilityEnvelope(const Assembly&)>& envelope,
                                          const std::vector<double>& depth_grid_m, const UncertaintyOptions& options);

}  // namespace toolpoint
