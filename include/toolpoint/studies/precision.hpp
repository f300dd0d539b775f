// toolpoint study: how tight will the joint be — before the tap test. For an assembly, the tap
// tests a joint's identification needs (their points, spacing and hammer plan), the noise of one
// hit and the number of averages, the 95 % half-width each joint parameter's interval is expected
// to have, and the averages a target width needs. No data: the model's own FRFs and the stated
// noise.
//
// Method.
//   1. The tap tests on the model (tap_test.hpp, exact): the station FRFs H_ij of the tool (for
//      SHT11) and/or the holder (for SH11), as the identification route needs them (Eq. 6: both;
//      Eq. 15: the holder; Eq. 18: the tool).
//   2. Their noise, averaged over n_d hits (signal.hpp's averaged test): per part of H_ij, a variance
//      (σ²|H_ij|²/2 + σ_a²)/n_d, σ the hit-to-hit variation (magnitude and phase alike), σ_a the
//      floor (relative to H_ij's peak). Carried exactly through the finite differences that make
//      the tip block (rotational_frfs: linear in the H_ij, the shear correction a constant; the
//      N·L/H00 approximation of P linearised), by perturbing each H_ij: the block's 8×8 covariance
//      at every frequency, correlations between the entries included (noise.hpp's relative C(f),
//      no floor left over). Each tap test's calibration is one factor (stated).
//   3. The band fit on the model's exact blocks with that noise (joint_fit.hpp, linearised): its
//      covariance is what the identification of such data would report — the noise's part scales
//      as 1/n_d, the calibration's does not: SE²(n_d) = a/n_d + b. The averages a target relative
//      half-width w needs: n_d = ⌈a / ((w |θ| / z)² − b)⌉, none when the calibration's share alone
//      exceeds it.
// Checked against Monte Carlo: data from noisy virtual tap tests with the same noise, through
// rotational and identify (tests/precision_test.cpp).
// Units: SI (joint parameters as joint.hpp); spacing in m; relative widths as fractions.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/model/joint.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/study.hpp"
#include "toolpoint/studies/tap_test.hpp"

namespace toolpoint {

// The noise of the tap tests being planned.
struct TapNoise {
  double sigma = 0.01;              // one hit's variation, relative, magnitude and phase alike (0.01 = 1 %)
  double floor = 0.0;               // one hit's additive floor, σ per part relative to each FRF's peak
  int averages = 1;                 // hits averaged per FRF
  double calibration = 0.0;         // σ of each tap test's calibration factor (one hammer, one sensor)
  bool shared_calibration = false;  // one sensor chain for both tap tests: one factor for both
  void check() const;               // throws InvalidArgument naming `TapNoise::<field>`
};

/// \brief TapNoise's fields defined once (option_fields.hpp): check(), the noise flags of
/// `toolpoint precision` and Python's TapNoise attributes derive from this table (calibration takes
/// noise_fields' range; sigma and floor both 0 is refused by check() beside it).
/// \return the table, in the order of the fields
const std::vector<OptionField<TapNoise>>& tap_noise_fields();

struct PrecisionOptions {
  Route route = Route::HolderTool;
  TapTestOptions tool{TapSide::Tool};      // spacing_m (required when the route measures SHT11), points, hammer
  TapTestOptions holder{TapSide::Holder};  // spacing_m (required when the route measures SH11), points, hammer
  TapNoise noise;
  bool reciprocal = true;  // six parameters, as the identification's default
  double confidence = 0.95;
  std::optional<double> target;  // a relative half-width wanted for each parameter (0.01 = ±1 %)
  // Throws InvalidArgument naming `PrecisionOptions::<field>`: the noise, each tap test the route
  // measures, precision_fields' ranges, the target in (0, 1).
  void check() const;
};

/// \brief PrecisionOptions' own scalar fields defined once (option_fields.hpp): check() and
/// Python's PrecisionOptions attributes derive from this table (route, the tap tests, the noise and
/// the optional target have their own definitions; `toolpoint precision --parameters 6|8` sets
/// reciprocal by hand).
/// \return the table, in the order of the fields
const std::vector<OptionField<PrecisionOptions>>& precision_fields();

struct ParameterPrecision {
  double value = 0.0;                      // the assembly's (the trial) value [SI]
  double half_width = 0.0;                 // expected half-width of its interval at the confidence [SI]
  double relative = 0.0;                   // half_width / |value| (∞ for a zero value)
  double calibration_half_width = 0.0;     // the calibration's share alone [SI]
  std::optional<int> averages_for_target;  // hits per FRF for PrecisionOptions::target (none: unreachable)
  bool free = true;                        // false: k_θf, c_θf of a reciprocal fit (equal to k_ym, c_ym)
};

struct PrecisionStudy {
  Route route = Route::HolderTool;
  std::array<ParameterPrecision, 8> parameters;  // k_yf, c_yf, k_ym, c_ym, k_θf, c_θf, k_θm, c_θm
  double confidence = 0.95;
  int averages = 1;
  std::optional<double> target;
  std::vector<std::string> measured;  // what would be measured ("SHT11: tool, 3 points 15 mm apart, roving hammer")
  std::string fit_description;        // the band fit's interval method
  std::vector<std::string> warnings;
};

// The tip block's noise from a tap test's station FRFs H_ij (step 2 above): `frfs` the exact H_ij,
// `fd` the finite differences that make the block (rotational_frfs), `noise` one hit's variation
// and floor and the averages (its calibration is set on the result). Throws as rotational_frfs,
// InvalidArgument naming TapNoise fields.
BlockNoise tap_test_block_noise(const PointFrfs& frfs, const RotationalOptions& fd, const TapNoise& noise,
                                const BlockSeries& block);

// Runs the study on `assembly` (its joints are the trial values; its grid the band). Throws
// InvalidArgument (options, points that do not fit), NumericalError (a joint the band does not
// determine at all).
PrecisionStudy run_precision_study(const Assembly& assembly, const PrecisionOptions& options,
                                   const ProgressCallback& progress = {});

}  // namespace toolpoint
