// toolpoint: results as JSON (nlohmann::json), for the CLI's --json output, summary files and
// anyone who wants a result as plain data. `nlohmann::json j = result;` finds these by ADL.
//
// One spelling per field, by one rule:
//   * a key is the C++ member's name (Peak::frequency_hz → "frequency_hz"), and its value is in
//     the member's unit (SI; Hz for frequencies; in the name where the name has one, else in the
//     member's header comment). The same field therefore has the same key in every command;
//   * enums are lower-case strings or the receptance's name: PredictedFrf "SHT11" / "SH11",
//     TapSide "tool" / "holder", HammerPlan "roving" / "tip";
//   * NaN (a mode not found) and ±inf become null: JSON has no NaN;
//   * relative errors are percentages, their keys ending "_percent" (a forward check's
//     "frequency_error_percent"); a joint parameter is always spelt k_yf, c_yf, k_ym, c_ym, k_tf,
//     c_tf, k_tm, c_tm (θ as "t") with its "unit";
//   * sampled series (BlockSeries, FrfSeries members) are left out: they go to FRF files
//     (io.hpp, frf_file.hpp, uff.hpp) or, in Python, to arrays. What a caller adds (file names,
//     the assembly's path, units) it adds under its own keys.
// Units: SI; frequencies in Hz.
#pragma once

#include <nlohmann/json.hpp>

#include "toolpoint/identify.hpp"
#include "toolpoint/joint_fit.hpp"
#include "toolpoint/noise.hpp"
#include "toolpoint/peaks.hpp"
#include "toolpoint/stability.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "toolpoint/uncertainty.hpp"

namespace toolpoint {

// {"index", "frequency_hz", "magnitude", "prominence"}
void to_json(nlohmann::json& j, const Peak& p);
// A forward check's mode: {"measured_hz", "predicted_hz", "frequency_error_percent",
// "measured_peak_m_per_n", "predicted_peak_m_per_n", "peak_error_percent"}.
void to_json(nlohmann::json& j, const ModeComparison& c);
// {"k_yf": value, …}
void to_json(nlohmann::json& j, const JointParameters& p);
// {"modes": [{"frequency_hz", "peak_m_per_n", "shift_percent_per_10_percent_k",
// "peak_change_percent_per_10_percent_c"}…], "dominant_index", "dominant_hz"}
void to_json(nlohmann::json& j, const EffectAnalysis& e);
// {"source", "magnitude_sigma": [H, L, N, P], "phase_sigma_rad": […], "residual_correlation"}
void to_json(nlohmann::json& j, const BlockNoise& n);

// ---- Joint identification ------------------------------------------------------------------------

// Per parameter {"estimate", "lower95", "upper95", "std_error", "fitted", "bias", "determined",
// "free", "unit"} under "parameters" (the interval's confidence in the key when not 95 %:
// "lower90"), and the fit's diagnostics: "confidence", "interval_method", "interval_description",
// "bootstrap_samples", "reciprocal", "points", "residual_ratio", "iterations", "converged",
// "correlation", "covariance" (8×8, SI), "setups" and "transfer" (several set-ups), "warnings".
void to_json(nlohmann::json& j, const JointFit& fit);
// The seed's read-out: "band_hz", "points", per parameter {"median", "spread", "min", "max",
// "noise_gain", "unit"}, "reciprocity", "max_condition_numbers", "warnings".
void to_json(nlohmann::json& j, const JointReadout& r);
// {"method", "center_hz", "band_hz", "effect_analysis" | "overhang_modes"}
void to_json(nlohmann::json& j, const ModeChoice& c);
// The whole study: "interface", "route", "equation", "method", "parameters" (the chosen method's
// values in JointFit's spelling; for the seed's read-out estimate = the median, no interval,
// determined from its noise gain and spread), "fit", "seed_readout", "mode_choice", "noise",
// "forward_check", "verdict", "warnings".
void to_json(nlohmann::json& j, const Identification& id);

// ---- Uncertainty carried forward ---------------------------------------------------------------

// {"frequency_hz", "levels", "samples", "magnitude_m_per_n": {"q5": […], …}, "phase_rad": {…}}
void to_json(nlohmann::json& j, const FrfBand& b);
// {"speed_rpm", "levels", "samples", "nominal_depth_m", "depth_m": {"q5": […], …}, "depth_grid_m"}
void to_json(nlohmann::json& j, const StabilityUncertainty& s);

// ---- Studies ------------------------------------------------------------------------------------

// {"receptance": "SHT11" | "SH11", "modes": [Peak…], "warnings"}
void to_json(nlohmann::json& j, const Prediction& p);
// {"overhang_m", "modes": [Peak…]}
void to_json(nlohmann::json& j, const OverhangFrf& r);
// {"tool_inside_holder_m", "overhangs": [OverhangFrf…], "reference", "tracked_modes_hz", "warnings"}
void to_json(nlohmann::json& j, const OverhangStudy& s);
// {"response", "hammer"}
void to_json(nlohmann::json& j, const TapTestFrf& r);
// {"side", "distance_m", "frfs": [TapTestFrf…], "shear_stiffness_n", "crosses_step", "warnings"}
void to_json(nlohmann::json& j, const TapTest& t);

// ---- Stability lobes (the keys of `toolpoint lobes --json`: depths in mm, speeds in rpm, as in its
// CSV files; the exception to the member-name rule, kept so scripts reading that output keep working)

// {"modal_mass_kg", "damping_ratio", "frequency_hz"}
void to_json(nlohmann::json& j, const Mode& m);
// {"frf", "modes", "normalised_residual", "band_low_hz", "band_high_hz", "target_met"}
void to_json(nlohmann::json& j, const ModalFitSummary& s);
// {"teeth", "tangential_coefficient_n_per_m2", "radial_ratio", "entry_deg", "exit_deg"}
void to_json(nlohmann::json& j, const CuttingConditions& c);
// {"spindle_speed_rpm", "axial_depth_mm", "chatter_frequency_hz", "lobe"}
void to_json(nlohmann::json& j, const EnvelopePoint& p);
// {"spindle_speed_rpm", "axial_depth_mm", "axial_depth_error_mm", "chatter_frequency_hz", "lobe", "kind", "steps"}
void to_json(nlohmann::json& j, const BoundaryPoint& b);
// {"units", "cutting", "pockets", "warnings", "method": "zoa" | "fd"}, and for zoa "floor_depth_mm",
// "floor_chatter_frequency_hz", "lobes", "lobe_points"; for fd "modes_x", "modes_y", "modal_fit",
// "max_depth_mm", "tolerance_pct", "worst_error_pct", "degree", "evaluations", "lowest_boundary",
// "flip_speeds".
void to_json(nlohmann::json& j, const LobesStudyResult& r);
// ---- The plan -------------------------------------------------------------------------------------

// {"candidate", "job", "speed_index", "overhang_m", "speed_rpm", "depth_m", "stable_depth_m", "safe_depth_m",
// "mrr_m3_per_s", "power_w", "torque_nm", "limit" ("stability" | "power" | "torque" | "depth" | "none"),
// "depth_margin", "probability", "chatter_hz", "lobe", "window_low_rpm", "window_high_rpm", "reason"}
void to_json(nlohmann::json& j, const PlanSetup& s);
// {"options", "candidates", "speeds_rpm": {"min", "max", "points"}, "jobs", "fingerprint", "best": [PlanSetup…],
// "tuning": [{"candidate", "overhang_m", "modes_hz", "best"}…], "warnings"}; the per-speed series go to CSV.
void to_json(nlohmann::json& j, const PlanResult& r);

}  // namespace toolpoint
