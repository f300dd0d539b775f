// toolpoint: the forward check of an identified joint — does the joint, put back into the forward
// model, reproduce the measured FRF mode by mode, as far as the noise allows?
//
// Predicted: G11 = A11 − A12 (A22 + K⁻¹ + B11)⁻¹ A21 (seed Eq. 5, 1 or 17) with the measured B11;
// measured: G11. Both are smoothed by one Savitzky–Golay filter (the same operator, so it cannot
// bias the comparison) and compared on |H|.
//
// Modes are paired by what they are, never across modes. The modes are those of the forward model
// in a noise-free world: the identified joint with B11 smoothed (the 7-point cubic of noise.hpp's
// estimate), G_ref = G11(θ̂; B̄11) — weak ones included (peaks down to a fifth of
// `min_prominence` that stand clear of the ripple B11's noise leaves in G_ref: a mode the model
// has explains data that show it, however weak). Each mode is sought only inside its window: ± twice its
// half-power half-width (at least 3 grid steps), never beyond the valleys that separate it from
// the neighbouring modes of G_ref. A window where the data show no peak of the required prominence
// holds a mode the data do not resolve: reported, no reason to fail — unless the noise would
// almost always have shown it (below).
//
// The test. Whether a difference is more than the noise makes is decided by Monte Carlo in the
// world the check assumes: the truth G_ref and B̄11, data drawn from the noise models (noise.hpp,
// calibration included), each replicate compared exactly as the measured data are (Efron &
// Tibshirani 1993, ch. 16: a parametric bootstrap test). Per resolved mode the replicates give the
// mean and standard deviation of the frequency and peak errors; the measured errors are judged
// by z-scores against them. Three kinds of evidence make the check fail, with a total false-alarm
// probability `false_alarm` for data that do come from the identified model with the stated
// noise (Bonferroni: half of it to the z-tests, split evenly; half to the rank test):
//   * a mode whose frequency or peak error lies beyond z standard deviations of the noise's,
//     further from the replicates' mean than every replicate's, and beyond the material tolerance
//     (`frequency_tolerance`, `peak_tolerance`): "differs". The rank condition guards the z-test
//     where the noise's errors are not normal: a weak mode under an additive floor is sometimes
//     taken for a noise peak at its window's edge (10 % away), an error the replicates make too,
//     rarely, which puts the data's at z ≈ 5 of a spread the usual case sets (5 of 200 data sets
//     from the true joint failed so; docs/noise-and-verdict.md);
//   * a mode the data do not show whose prominence in the replicates lies z deviations above
//     the data's: "missing" (the model has a mode the data do not have);
//   * a peak of the measured data outside every window standing higher than any replicate made
//     (rank test, p = (1 + count)/(1 + replicates)): a mode the model does not have.
// A difference beyond the noise but within the tolerances is noted, not failed (modelling error
// too small to matter). With exact data (no noise at all) the tolerances alone decide.
// Units: frequencies in Hz; errors relative (fractions); peaks in the FRF's units (m/N).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/joint.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint {

struct ForwardCheckOptions {
  std::optional<SavgolOptions> smoothing;  // applied to measured and predicted alike; default {15, 3}
  double min_prominence = 0.1;             // a peak counts when it stands this fraction above its valleys (peaks.hpp)
  int replicates = 200;       // Monte Carlo replicates of the noise (≥ 50; the rank test needs 1/(1+R) ≤ false_alarm/2)
  double false_alarm = 0.01;  // P(fail) for data made by the identified model with the stated noise
  double frequency_tolerance = 0.01;  // relative natural-frequency error that matters
  double peak_tolerance = 0.15;       // relative peak-height error that matters
  std::uint64_t seed = 1;             // replicate r draws from stream_seed(seed, r)
  bool shared_calibration = false;    // B11 and G11 share one calibration factor (one sensor chain)
  ParallelOptions parallel;           // replicates on these threads (results identical for any count)
  // Throws InvalidArgument naming `ForwardCheckOptions::<field>`.
  void check() const;
};

/// \brief ForwardCheckOptions' scalar fields but the seed, defined once (option_fields.hpp): their
/// ranges and help, check() and the Python class's docstring derive from it (smoothing, seed and
/// parallel have their own; the replicates' floor for the false-alarm probability is checked apart).
/// \return the table, in the order of the fields
const std::vector<OptionField<ForwardCheckOptions>>& forward_check_fields();

// A mode counts where it stands this many times √2 σ above its higher valley: σ the ripple B11's
// noise leaves in the prediction (which modes the model has), or G11's own noise after the
// check's smoothing (whether the data can show it; ModeCheck::clearance).
inline constexpr double kModeClearance = 5.0;

enum class ModeAgreement {
  Agrees,           // within what the noise allows
  WithinTolerance,  // beyond the noise, within the tolerances: noted
  Differs,          // beyond the noise and the tolerances: fails
  NotResolved,      // the data do not show the mode (the noise hides it): not judged
  Missing,          // the noise would show the mode, the data do not: fails
};
const char* to_string(ModeAgreement a);  // "agrees", "within tolerance", "differs", "not resolved", "missing"

struct ModeCheck {
  double model_hz = 0.0;                         // the mode of G_ref
  double lo_hz = 0.0, hi_hz = 0.0;               // its window
  double measured_hz = 0.0, predicted_hz = 0.0;  // NaN when not found
  double measured_peak = 0.0, predicted_peak = 0.0;
  double frequency_error = 0.0, magnitude_error = 0.0;  // (predicted − measured)/measured
  // Under the noise (replicates showing the mode in both): mean and standard deviation of the
  // errors, and the fraction of replicates that show it.
  double frequency_mean = 0.0, frequency_sd = 0.0, magnitude_mean = 0.0, magnitude_sd = 0.0;
  double resolved_fraction = 0.0;
  double frequency_z = 0.0, magnitude_z = 0.0;  // |error − mean| / sd (NaN when not resolved)
  // The fraction, plus one, of the replicates whose error lies at least as far from their mean as
  // the data's: (1 + count)/(1 + replicates), its least value when the data's is the most extreme
  // (NaN when not resolved).
  double frequency_rank_p = 0.0, magnitude_rank_p = 0.0;
  // The mode's height above its higher valley in G_ref over √2 times the standard deviation G11's
  // own noise leaves there after the check's smoothing (infinite for exact data). Under
  // kModeClearance a noise peak elsewhere in the window is as likely to be the highest: the
  // mode is not resolved and not judged.
  double clearance = 0.0;
  ModeAgreement agreement = ModeAgreement::Agrees;
};

// A peak of the measured data in no mode's window.
struct ExtraPeak {
  double frequency_hz = 0.0, prominence = 0.0;
  double p_value = 1.0;  // fraction of replicates (plus one) with an unexplained peak at least as prominent
  bool significant = false;
};

struct ForwardCheck {
  std::string label;             // the set-up
  std::vector<ModeCheck> modes;  // ascending in frequency
  std::vector<ExtraPeak> extra;  // ascending in frequency
  int replicates = 0;            // 0 for exact data
  double false_alarm = 0.0;
  double z = 0.0;                     // the z-tests' limit (standard deviations)
  std::vector<std::string> failures;  // why it fails (empty: it passes)
  std::vector<std::string> notes;     // differences worth knowing that do not fail it
  bool passed() const { return failures.empty(); }
};

// The check of `joint` on one set-up (JointFitData: the model component A, the measured B11 and
// G11 and their noise models, on the band given). With the joint's `covariance` (SI units, as
// JointFit::covariance) its uncertainty is part of what the noise allows: each replicate's data
// come from a joint drawn from N(joint, covariance) (uncertainty.hpp's sample_joints; the
// prediction stays the identified joint's, as for the measured data), and each mode's window is
// at least four standard deviations of its frequency over such joints wide — a joint the data
// determine poorly is not failed for the spread the data leave it. Throws InvalidArgument
// (options, a covariance that is not positive semidefinite), InputError (data: as fit_joint),
// NumericalError (a singular forward model).
ForwardCheck check_forward(const JointFitData& data, const JointParameters& joint, const ForwardCheckOptions& options = {},
                           const std::optional<Eigen::Matrix<double, 8, 8>>& covariance = std::nullopt);

}  // namespace toolpoint
