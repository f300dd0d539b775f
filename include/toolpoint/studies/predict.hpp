// toolpoint: the forward prediction study — an assembly's tool point FRF SHT11 (or its holder-tip
// FRF SH11) by receptance coupling (seed Eq. 1–5), with its modes.
//
//   SH11  = H11 − H12 (H22 + K_sh⁻¹ + S11)⁻¹ H21      holder tip, the tool outside removed (Eq. 1)
//   SHT11 = T11 − T12 (T22 + K_ht⁻¹ + SH11)⁻¹ T21     tool point (Eq. 5)
//
// With a joint uncertain (PredictOptions::uncertain_joint), also the band of the tool point FRF:
// the quantiles of |H| and ∠H over joints drawn from the joint file's covariance (uncertainty.hpp).
//
// Units: SI (H m/N, L 1/N, N rad/N, P rad/(N·m)); frequencies in Hz. Sign convention:
// conventions.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/studies/study.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint {

// Which point receptance of the assembly.
enum class PredictedFrf {
  ToolPoint,  // SHT11 at the tool tip, the whole assembly
  HolderTip,  // SH11 at the holder tip, the tool outside the holder removed
};
// "SHT11" or "SH11".
const char* predicted_frf_name(PredictedFrf frf);

struct PredictOptions {
  PredictedFrf receptance = PredictedFrf::ToolPoint;
  PeakOptions peaks{};  // which local maxima of |H| count as modes
  // The joint uncertain: the band of the tool point FRF (receptance ToolPoint only) over joints drawn
  // from this file's [uncertainty] (tool_point_band); the file's joint is in place at its
  // interface for the prediction itself too (its FRF and modes: the band's nominal). None: no band.
  std::optional<JointFile> uncertain_joint;
  UncertaintyOptions band;  // the band's samples, seed, levels and threads (its progress: the study's)
  // The spindle's speed [rpm], ≥ 0 (docs/spindle-at-speed.md): > 0, or bearings that differ in x
  // and y, give the tool point in two planes (Prediction::two_plane); the FRF and the modes are
  // then its x–x part. The tool point only, without uncertain_joint; plausibility as
  // plausible::kSpinSpeedRpm (below 1000 rpm a warning: rad/s?).
  double speed_rpm = 0.0;
  // Bearings with speed tables (Bearing::speed_table) take their values at speed_rpm (at_speed();
  // at 0 rpm too, whose row the table must then hold); a speed outside a table is refused unless
  // this is set (then the end rows' line is extended).
  bool extrapolate_bearings = false;
  // Throws InvalidArgument naming `PredictOptions::<field>`: the range and plausibility of
  // predict_fields(), the peaks, a speed with the holder tip or the band, the band's options.
  void check() const;
};

// PredictOptions' scalar fields (option_fields.hpp), with the `toolpoint predict` flags: speed_rpm
// (--speed; plausible::kSpinSpeedRpm), extrapolate_bearings (--extrapolate-bearings).
const std::vector<OptionField<PredictOptions>>& predict_fields();

struct Prediction {
  PredictedFrf receptance = PredictedFrf::ToolPoint;
  BlockSeries frf;                    // the 2×2 block [[H, L], [N, P]] on the assembly's grid
  std::vector<Peak> modes;            // peaks of |H|, each refined on the model between its grid neighbours
  std::optional<FrfBand> band;        // with options.uncertain_joint: the tool point FRF's quantiles on the grid
  std::vector<std::string> warnings;  // the model's (AssemblyModel::warnings)
  double speed_rpm = 0.0;             // options.speed_rpm
  // At speed or with anisotropic bearings: the tool point's 4×4 block on (w_x, ψ_x, w_y, ψ_y) on
  // the grid (AssemblyModel::tool_point_two_plane); empty otherwise.
  BlockSeries4 two_plane;
};

// The translational part [[H_xx, H_xy], [H_yx, H_yy]] [m/N] of each two-plane block, as CSV text:
// frequency_hz and the real and imaginary parts of the four (the cross receptances' file).
std::string cross_receptance_csv(const BlockSeries4& series);

// The tool point FRF at several spindle speeds (docs/spindle-at-speed.md), as a figure: |H_xx| and
// |H_xy| [m/N] against frequency [Hz] on the assembly's grid, one curve per speed [rpm, ≥ 0], the
// bearings at each speed (their tables read there; a speed outside a table refused unless
// `extrapolate_bearings`) and the spindle spinning at it (AssemblyModel::tool_point_two_plane).
// Throws InvalidArgument (no speed, a negative one, a speed outside a bearing's table naming it).
plot::Figure speed_frf_figure(const Assembly& assembly, const std::vector<double>& speeds_rpm, bool extrapolate_bearings = false);

// The prediction on `assembly.grid`, through AssemblyModel's sweeps (SIMD lanes where available;
// the same values as one frequency at a time up to rounding). Progress is reported per block of
// frequencies, then per joint sample of the band. Throws InvalidArgument (the assembly or options,
// a joint file without [uncertainty]), NumericalError naming the frequency where a coupling is
// singular.
Prediction run_prediction_study(const Assembly& assembly, const PredictOptions& options = {},
                                const ProgressCallback& progress = {});

}  // namespace toolpoint
