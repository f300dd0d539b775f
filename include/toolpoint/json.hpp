// toolpoint: results as JSON (nlohmann::json), for the CLI's --json output, summary files and
// anyone who wants a result as plain data. `nlohmann::json j = result;` finds these by ADL.
//
// One to_json per result type, one spelling per field, by one rule:
//   * a key is the C++ member's name (Peak::frequency_hz → "frequency_hz"), and its value is in
//     the member's unit (SI; Hz for frequencies; rpm for speeds named _rpm; relative errors and
//     tolerances as fractions, like the members). A member that is a struct is an object under its
//     name (CuttingConditions::engagement → "engagement": {"entry_rad", "exit_rad"}); a member
//     function's value, where given, is under the function's name (BoundaryResult::
//     worst_relative_error). The same field therefore has the same key in every command, and
//     the same type the same keys wherever it appears (a CaseStudy's `seed` is an Identification
//     as `toolpoint identify` prints it);
//   * enums are strings, the library's to_string where it has one: PredictedFrf "SHT11" / "SH11",
//     TapSide "tool" / "holder", LobesMethod "zoa" / "fd", BoundaryKind "hopf" / …;
//   * a joint's eight parameters are keyed k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm (θ as
//     "t"; JointParameters::name), each with its "unit" where the value is an object;
//   * NaN (a mode not found) and ±inf become null: JSON has no NaN;
//   * sampled series (BlockSeries, FrfSeries, JointSeries members; the per-speed envelope and
//     boundary; the lobe points) are left out: they go to FRF and CSV files or, in Python, to
//     arrays. A few derived summaries are added under their own keys and said below
//     (Identification's "parameters", BoundaryResult's "lowest_boundary"). What a caller adds
//     (file names, the assembly's path, options it echoes) it adds under its own keys.
#pragma once

#include <nlohmann/json.hpp>

#include "toolpoint/model/beam.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/modal_fit.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/beam.hpp"
#include "toolpoint/studies/fd_correction.hpp"
#include "toolpoint/studies/filter.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/pitch.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/precision.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/rotational.hpp"
#include "toolpoint/studies/simulation.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "toolpoint/io/uff.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint {

// {"index", "frequency_hz", "magnitude", "prominence"}
void to_json(nlohmann::json& j, const Peak& p);
// A forward check's mode: {"measured_hz", "predicted_hz", "frequency_error", "measured_peak",
// "predicted_peak", "magnitude_error"} (errors relative, as fractions; peaks in m/N).
void to_json(nlohmann::json& j, const ModeComparison& c);
// A mode of a forward check (forward_check.hpp): {"model_hz", "lo_hz", "hi_hz", "measured_hz",
// "predicted_hz", "measured_peak", "predicted_peak", "frequency_error", "magnitude_error",
// "frequency_mean", "frequency_sd", "magnitude_mean", "magnitude_sd", "resolved_fraction",
// "clearance", "frequency_z", "magnitude_z", "frequency_rank_p", "magnitude_rank_p", "agreement"
// ("agrees" | "within tolerance" | "differs" | "not resolved" | "missing")}; NaN (not found, not
// judged) and an infinite clearance (exact data) are null.
void to_json(nlohmann::json& j, const ModeCheck& c);
// {"frequency_hz", "prominence", "p_value", "significant"}
void to_json(nlohmann::json& j, const ExtraPeak& e);
// {"label", "modes", "extra", "replicates", "false_alarm", "z", "passed", "failures", "notes"}
void to_json(nlohmann::json& j, const ForwardCheck& c);
// {"k_yf": value, …}
void to_json(nlohmann::json& j, const JointParameters& p);
// {"frequency_hz", "magnitude", "stiffness_shift", "damping_effect"}
void to_json(nlohmann::json& j, const ModeEffect& m);
// {"modes": [ModeEffect…], "dominant"}
void to_json(nlohmann::json& j, const EffectAnalysis& e);
// {"reference_peaks": [Peak…], "relative_variation", "dominant"}
void to_json(nlohmann::json& j, const OverhangModes& m);
// {"source", "magnitude_sigma": [H, L, N, P], "phase_sigma_rad": […], "floor": […] (σ per part, the
// entries' units), "floor_relative": […] (of each entry's peak), "calibration", "coherence",
// "summary", "residual_correlation", "warnings"}
void to_json(nlohmann::json& j, const BlockNoise& n);

// ---- Joint identification ------------------------------------------------------------------------

// {"estimate", "fitted", "bias", "std_error", "lower", "upper", "determined", "free"}
void to_json(nlohmann::json& j, const ParameterInterval& i);
// {"label", "fitted": {"k_yf": …}, "std_error": {"k_yf": …}, "residual_ratio", "disagreement"}
void to_json(nlohmann::json& j, const SetupFit& s);
// "intervals": per parameter ParameterInterval and its "unit" (the estimates, JointFit::parameters,
// are its "estimate"s); "confidence", "method" ("bootstrap" | "linearised"), "method_description",
// "bootstrap_samples", "reciprocal", "points", "residual_ratio", "iterations", "converged",
// "correlation" and "covariance" (8×8, SI), "calibration_std_error" (per parameter, SI), "warnings"; with several set-ups also
// "setups", "transfer_statistic", "transfer_limit", "transfers".
void to_json(nlohmann::json& j, const JointFit& fit);
// A parameter's expected precision: {"value", "half_width", "relative", "calibration_half_width",
// "averages_for_target" (null: unreachable or no target), "free", "unit"}.
void to_json(nlohmann::json& j, const ParameterPrecision& p);
// The precision study: {"route", "parameters": per parameter ParameterPrecision, "confidence",
// "averages", "target", "measured", "fit_description", "warnings"}.
void to_json(nlohmann::json& j, const PrecisionStudy& s);
// The seed's read-out: "band_lo_hz", "band_hi_hz", "points", "parameters": per parameter
// {"median", "spread", "min", "max", "determined", "noise_gain", "unit"}, "reciprocity_k",
// "reciprocity_c", "max_cond_difference", "max_cond_flexibility", "warnings".
void to_json(nlohmann::json& j, const JointReadout& r);
// {"method", "center_hz", "lo_hz", "hi_hz", "effect" | "overhang"}
void to_json(nlohmann::json& j, const ModeChoice& c);
// {"verdict": "pass" | "doubtful" | "fail", "reasons"}
void to_json(nlohmann::json& j, const IdentificationVerdict& v);
// The whole study: "interface" ("holder_tool" | "spindle_holder"), "route", "equation", "method"
// ("fit" | "seed"), "fit" (JointFit) and "fit_band_hz" (method fit), "seed" (the read-out, when
// one was made), "mode", "g_noise" and "b_noise" (per set-up), "forward_checks" (per set-up), "verdict",
// "warnings"; and, derived, "parameters": the chosen method's values per parameter — the fit's
// intervals (ParameterInterval's keys and "unit"), or for the read-out {"estimate" (the median),
// "lower": null, "upper": null, "determined" (ParameterReadout::determined), "unit"}.
void to_json(nlohmann::json& j, const Identification& id);
// The seed's case study: "reference", "clean_max_deviation" (per parameter), "effect", "mode_hz",
// "clean_readout", "noisy_readout", "filtered_readout" (JointReadout), "verification" (the
// read-out coupled back against the true SHT11), "seed" (Identification), "fitted" and
// "fit_verification" (the band fit, when run), "warnings".
void to_json(nlohmann::json& j, const CaseStudy& cs);

// ---- Uncertainty carried forward ---------------------------------------------------------------

// {"frequency_hz", "levels", "samples", "magnitude": {"q5": […], …}, "phase_rad": {…}}
void to_json(nlohmann::json& j, const FrfBand& b);
// {"speed_rpm", "levels", "samples", "nominal_depth_m", "depth_m": {"q5": […], …}, "depth_grid_m"}
void to_json(nlohmann::json& j, const StabilityUncertainty& s);

// ---- Studies ------------------------------------------------------------------------------------

// {"receptance": "SHT11" | "SH11", "modes": [Peak…], "warnings"}, "band" (FrfBand) when computed, "speed_rpm" in two planes
void to_json(nlohmann::json& j, const Prediction& p);
// {"overhang_m", "modes": [Peak…]}
void to_json(nlohmann::json& j, const OverhangFrf& r);
// {"tool_inside_holder_m", "overhangs": [OverhangFrf…], "reference", "tracked_modes_hz", "warnings"} and "band"
// (FrfBand) when computed
void to_json(nlohmann::json& j, const OverhangStudy& s);
// {"response", "hammer"}
void to_json(nlohmann::json& j, const TapTestFrf& r);
// {"side", "distance_m", "frfs": [TapTestFrf…], "shear_stiffness_n", "crosses_step", "warnings"}
void to_json(nlohmann::json& j, const TapTest& t);
// {"p_from_cross_terms", "l_equals_n_by_reciprocity", "reciprocity_mismatch" (null: none), "filled_by_reciprocity",
// "warnings"}
void to_json(nlohmann::json& j, const RotationalResult& r);
// {"max_relative": [H, L, N, P], "warnings"}
void to_json(nlohmann::json& j, const FiniteDifferenceError& e);
// {"differences": RotationalResult, "correction": FiniteDifferenceError | null, "order", "spacing_m", "method",
// "reciprocity", "correction_note", "warnings"}
void to_json(nlohmann::json& j, const RotationalStudy& s);

// ---- Filter -------------------------------------------------------------------------------------

// {"entry", "raw_frequency_hz", "raw_magnitude", "filtered_frequency_hz" (null: smoothed away), "filtered_magnitude",
// "height_change", "frequency_change" (null: smoothed away), "noise"} (changes and noise relative, as fractions)
void to_json(nlohmann::json& j, const PeakChange& c);
// {"peaks": [PeakChange…], "warnings"}
void to_json(nlohmann::json& j, const PeakChangeReport& r);
// {"noise_gain", "peaks": PeakChangeReport, "warnings"}; the filtered series goes to an FRF file.
void to_json(nlohmann::json& j, const FilterStudy<FrfSeries>& s);
void to_json(nlohmann::json& j, const FilterStudy<BlockSeries>& s);

// ---- Modal fit and stability lobes --------------------------------------------------------------

// {"mass_kg", "damping_ratio", "frequency_hz"}
void to_json(nlohmann::json& j, const Mode& m);
// {"mode": Mode, "residue", "initial_frequency_hz", "initial_damping_ratio", "points_in_half_power_band",
// "normalised_residual"}
void to_json(nlohmann::json& j, const FittedMode& m);
// {"modes": [FittedMode…], "lower_residual", "upper_residual", "normalised_residual", "band_low_hz", "band_high_hz",
// "points", "evaluations", "converged", "warnings"}
void to_json(nlohmann::json& j, const ModalFitResult& r);
// {"fit": ModalFitResult, "model": [Mode…], "warnings"}; the fitted series goes to an FRF file.
void to_json(nlohmann::json& j, const ModalFitStudy& s);
// {"x": [Mode…], "y": [Mode…]}
void to_json(nlohmann::json& j, const ModalModel& m);
// {"what", "modes", "residual", "band_low_hz", "band_high_hz", "target_met"}
void to_json(nlohmann::json& j, const ModalFitSummary& s);
// {"entry_rad", "exit_rad"}
void to_json(nlohmann::json& j, const Engagement& e);
// {"teeth", "tangential_coefficient", "radial_ratio", "engagement", "pitch_rad", "helix_rad", "helix_slices",
//  "runout_m", "feed_per_tooth_m", "diameter_m", "process_damping_n_per_m"} (empty lists, 0: not used)
void to_json(nlohmann::json& j, const CuttingConditions& c);
// {"min_rpm", "max_rpm", "points"}
void to_json(nlohmann::json& j, const SpeedRange& s);
// {"speed_rpm", "depth_m", "chatter_hz", "lobe"}
void to_json(nlohmann::json& j, const EnvelopePoint& p);
// {"speed_rpm", "depth_m", "depth_error_m", "steps", "chatter_hz", "lobe", "kind"} (the multiplier left out)
void to_json(nlohmann::json& j, const BoundaryPoint& b);
// {"alpha" (2×2), "floor_depth_m", "floor_chatter_hz", "lobes", "teeth", "speeds", "max_depth_m", "warnings"} and,
// derived, "lobe_points": how many lobe points there are (the points themselves go to CSV).
void to_json(nlohmann::json& j, const ZeroOrderResult& r);
// {"max_depth_m", "tolerance", "scheme" ("fd" full- or "sd" semi-discretization), "degree" (fd: the
// interpolation degree; sd: the delayed term's order), "evaluations", "worst_relative_error", "warnings"} and, derived from
// the boundary (which goes to CSV), "lowest_boundary" (BoundaryPoint) and "flip_speeds" (how many are flips).
void to_json(nlohmann::json& j, const BoundaryResult& r);
// {"options" (fields_json of lobes_study_fields), "method", "cutting", "speeds", "pockets": [EnvelopePoint…],
// "warnings"} and "zero_order" (method zoa), or
// "boundary", "modes", "fits" and "pocket_depth_error_m" (method fd); "uncertainty" (StabilityUncertainty),
// "uncertain_joint", "pocket_quantiles" and "worst_speed" when the joint was uncertain.
void to_json(nlohmann::json& j, const LobesStudyResult& r);
// {"variation_rad", "second_variation_rad" (three-angle: v; else 0), "depth_m", "robust_depth_m", "chatter_hz", "kind"}
void to_json(nlohmann::json& j, const PitchSample& s);
// {"pattern", "teeth", "speed_rpm", "chatter_hz", "max_variation_rad",
//  "closed_form_variation_rad", "closed_form_second_variation_rad", "closed_form_pitch_rad", "closed_form_depth_m",
//  "closed_form_robust_depth_m", "variation_rad", "second_variation_rad", "pitch_rad", "chosen", "uniform" (BoundaryPoint),
//  "gain", "max_depth_m", "steps", "samples", "evaluations", "warnings"}
void to_json(nlohmann::json& j, const PitchChoice& c);
// {"choice", "modes", "fits", "warnings"}
void to_json(nlohmann::json& j, const PitchStudyResult& r);
// {"speed_rpm", "nominal_depth_m", "depth_m": per level}
void to_json(nlohmann::json& j, const SpeedQuantiles& q);

// ---- The plan -------------------------------------------------------------------------------------

// {"candidate", "job", "speed_index", "overhang_m", "speed_rpm", "depth_m", "stable_depth_m", "safe_depth_m",
// "mrr_m3_per_s", "power_w", "torque_nm", "limit" ("stability" | "power" | "torque" | "depth" | "none"),
// "depth_margin", "probability", "chatter_hz", "lobe", "window_low_rpm", "window_high_rpm", "reason"}
void to_json(nlohmann::json& j, const PlanSetup& s);
// {"candidate", "overhang_index", "overhang_m", "modes_hz", "best": PlanSetup, "warnings"}; the per-speed
// series go to CSV.
void to_json(nlohmann::json& j, const PlanJob& job);
// The header's {"options", "candidates", "fingerprint"} ("options": PlanOptions' members, with its
// LobesStudyOptions' "method", "cutting" and "speeds"), then {"jobs": [PlanJob…], "best": [PlanSetup…],
// "warnings"}.
void to_json(nlohmann::json& j, const PlanResult& r);

// ---- The time-domain simulation (simulation.hpp, studies/simulation.hpp) ------------------------

// {"frequency_hz", "damping_ratio", "shape_x", "shape_y"}
void to_json(nlohmann::json& j, const PlanarMode& m);
// {"modes": [PlanarMode…]}
void to_json(nlohmann::json& j, const ToolDynamics& d);
// {"teeth", "diameter_m", "pitch_rad", "helix_rad", "tooth_helix_rad", "runout_m", "flute_length_m"}
void to_json(nlohmann::json& j, const Cutter& c);
// {"tangential_coefficient", "radial_ratio", "tangential_edge", "radial_edge", "exponent", "reference_chip_m",
//  "process_damping_n_per_m"}
void to_json(nlohmann::json& j, const ForceLaw& f);
// {"speed_rpm", "depth_m", "feed_per_tooth_m", "engagement"}
void to_json(nlohmann::json& j, const MillingCut& c);
// {"revolutions", "steps_per_tooth", "slices", "analysed_fraction", "record", "memory_revolutions"}
void to_json(nlohmann::json& j, const SimulationOptions& o);
// {"angle_rad", "slice_height_m", "sle_m", "mean_sle_m"} (the passes go to CSV)
void to_json(nlohmann::json& j, const Wall& w);
// The discretization {"step_s", "steps_per_tooth", "steps_per_revolution", "slices", "revolutions", "steps",
// "analysed_from"}, the summary {"mean_force_x_n", "mean_force_y_n", "mean_torque_nm", "power_w", "peak_force_n",
// "sle_m", "growth", "chatter_metric", "chatter_hz", "stable", "diverged", "out_of_cut_fraction"}, "walls", "warnings"; the
// histories and samples go to CSV.
void to_json(nlohmann::json& j, const SimulationResult& r);
// {"dynamics", "fits", "cutter", "force", "cut", "simulation", "warnings"}
void to_json(nlohmann::json& j, const SimulationStudyResult& r);
// {"min_m", "max_m", "points"}
void to_json(nlohmann::json& j, const DepthRange& d);
// The header's {"dynamics", "options": {"cutter", "force", "cut" (feed and engagement), "simulation", "speeds",
// "depths"}, "fingerprint"}, and derived from the per-cell results (which go to CSV): "cells", "stable_cells",
// "lowest_unstable" (EnvelopePoint: the lowest unstable depth over the speeds), "warnings".
void to_json(nlohmann::json& j, const SimulatedMap& m);

// ---- Files ----------------------------------------------------------------------------------------

// {"frequency_hz", "w1", "psi1", "w2", "psi2", "above_cutoff"}
void to_json(nlohmann::json& j, const FreeMode& m);
// {"area", "second_moment", "shear_coefficient", "rhoA", "rhoI", "cutoff_frequency_hz"}
void to_json(nlohmann::json& j, const BeamSection& s);
// {"section": BeamSection, "modes": [FreeMode… each with its "mode" number, 1 first], "method", "warnings"}; the
// segment, its complex SectionProperties and the receptance are left out (the receptance goes to an FRF file);
// spinning, also "speed_rpm" and "whirl" (WhirlFrequencies); with a Campbell diagram "campbell" (one per speed).
void to_json(nlohmann::json& j, const BeamStudy& s);
// {"spin_rad_s", "speed_rpm", "forward_hz", "backward_hz", "conical_hz"}
void to_json(nlohmann::json& j, const WhirlFrequencies& w);
// {"response_node", "response_direction", "reference_node", "reference_direction"}
void to_json(nlohmann::json& j, const UffDof& d);
// {"ordinate", "to_si", "label"}
void to_json(nlohmann::json& j, const FrfUnits& u);
// Everything but the series: {"format", "is_block", "ordinate", "units", "description", "dof", "warnings"}.
void to_json(nlohmann::json& j, const FrfFileData& d);
// {"data_type", "data_type_name", "length_exponent", "force_exponent", "temperature_exponent", "label", "units"}
void to_json(nlohmann::json& j, const UffAxis& a);
// {"code", "description", "length_factor", "force_factor", "temperature_factor", "line"}
void to_json(nlohmann::json& j, const UffUnits& u);
// Every field but x and y, with names beside the codes ("function_type_name", "response_direction_name",
// "reference_direction_name", "ordinate_data_type_name"); "units": null without a dataset 164.
void to_json(nlohmann::json& j, const UffDataset58& d);
// {"type", "binary", "line", "offset"}
void to_json(nlohmann::json& j, const UffDatasetEntry& e);
// {"source", "datasets", "functions", "warnings", "skipped", "file_warnings"}
void to_json(nlohmann::json& j, const UffFile& f);

/// \brief The echo of an Options type's scalar fields (option_fields.hpp): {name: value} in the
/// fields' units (integers as integers, flags as booleans).
/// \param fields the Options type's table
/// \param o the options echoed
/// \param real how a real value is written (nullptr: as a JSON number; a part file writes it as
/// exact hexadecimal text)
/// \return the JSON object
template <class Options>
nlohmann::json fields_json(const std::vector<OptionField<Options>>& fields, const Options& o,
                           nlohmann::json (*real)(double) = nullptr) {
  nlohmann::json j = nlohmann::json::object();
  Options& m = const_cast<Options&>(o);  // the accessors are shared by reading and writing
  for (const OptionField<Options>& f : fields) {
    if (f.integer) j[f.spec.name] = f.integer(m);
    else if (f.flag) j[f.spec.name] = f.flag(m);
    else j[f.spec.name] = real ? real(f.real(m)) : nlohmann::json(f.real(m));
  }
  return j;
}

}  // namespace toolpoint
