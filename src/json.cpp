// toolpoint: results as JSON (json.hpp). nlohmann::json sorts the keys.
#include "toolpoint/json.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/conventions.hpp"

namespace toolpoint {

namespace {

// NaN and ±inf are not JSON numbers: null.
nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

template <class Values>
nlohmann::json numbers(const Values& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(number(x));
  return a;
}

// {"k_yf": value(0), …}: one value per joint parameter.
template <class Value>
nlohmann::json per_parameter(Value value) {
  nlohmann::json j = nlohmann::json::object();
  for (int k = 0; k < 8; ++k) j[JointParameters::name(k)] = value(k, static_cast<std::size_t>(k));
  return j;
}

// An object per parameter with its unit.
nlohmann::json with_unit(nlohmann::json j, int k) {
  j["unit"] = JointParameters::unit(k);
  return j;
}

template <class Matrix>
nlohmann::json matrix(const Matrix& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) row.push_back(number(m(i, k)));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

void to_json(nlohmann::json& j, const Peak& p) {
  j = {{"index", p.index}, {"frequency_hz", p.frequency_hz}, {"magnitude", p.magnitude}, {"prominence", p.prominence}};
}

void to_json(nlohmann::json& j, const ModeComparison& c) {
  j = {{"measured_hz", number(c.measured_hz)},         {"predicted_hz", number(c.predicted_hz)},
       {"frequency_error", number(c.frequency_error)}, {"measured_peak", number(c.measured_peak)},
       {"predicted_peak", number(c.predicted_peak)},   {"magnitude_error", number(c.magnitude_error)}};
}

void to_json(nlohmann::json& j, const ModeCheck& c) {
  j = {{"model_hz", number(c.model_hz)},
       {"lo_hz", number(c.lo_hz)},
       {"hi_hz", number(c.hi_hz)},
       {"measured_hz", number(c.measured_hz)},
       {"predicted_hz", number(c.predicted_hz)},
       {"measured_peak", number(c.measured_peak)},
       {"predicted_peak", number(c.predicted_peak)},
       {"frequency_error", number(c.frequency_error)},
       {"magnitude_error", number(c.magnitude_error)},
       {"frequency_mean", number(c.frequency_mean)},
       {"frequency_sd", number(c.frequency_sd)},
       {"magnitude_mean", number(c.magnitude_mean)},
       {"magnitude_sd", number(c.magnitude_sd)},
       {"resolved_fraction", number(c.resolved_fraction)},
       {"clearance", number(c.clearance)},
       {"frequency_z", number(c.frequency_z)},
       {"magnitude_z", number(c.magnitude_z)},
       {"frequency_rank_p", number(c.frequency_rank_p)},
       {"magnitude_rank_p", number(c.magnitude_rank_p)},
       {"agreement", to_string(c.agreement)}};
}

void to_json(nlohmann::json& j, const ExtraPeak& e) {
  j = {{"frequency_hz", number(e.frequency_hz)},
       {"prominence", number(e.prominence)},
       {"p_value", number(e.p_value)},
       {"significant", e.significant}};
}

void to_json(nlohmann::json& j, const ForwardCheck& c) {
  j = {{"label", c.label},
       {"modes", c.modes},
       {"extra", c.extra},
       {"replicates", c.replicates},
       {"false_alarm", c.false_alarm},
       {"z", number(c.z)},
       {"passed", c.passed()},
       {"failures", c.failures},
       {"notes", c.notes}};
}

void to_json(nlohmann::json& j, const JointParameters& p) {
  j = per_parameter([&](int k, std::size_t) { return number(p[k]); });
}

void to_json(nlohmann::json& j, const ModeEffect& m) {
  j = {{"frequency_hz", number(m.frequency_hz)},
       {"magnitude", number(m.magnitude)},
       {"stiffness_shift", number(m.stiffness_shift)},
       {"damping_effect", number(m.damping_effect)}};
}

void to_json(nlohmann::json& j, const EffectAnalysis& e) { j = {{"modes", e.modes}, {"dominant", e.dominant}}; }

void to_json(nlohmann::json& j, const OverhangModes& m) {
  j = {{"reference_peaks", m.reference_peaks}, {"relative_variation", numbers(m.relative_variation)}, {"dominant", m.dominant}};
}

void to_json(nlohmann::json& j, const BlockNoise& n) {
  j = {{"source", n.source},
       {"magnitude_sigma", numbers(n.magnitude_sigma)},
       {"phase_sigma_rad", numbers(n.phase_sigma_rad)},
       {"floor", numbers(n.floor)},
       {"floor_relative", numbers(n.floor_relative)},
       {"calibration", number(n.calibration)},
       {"coherence", n.coherence},
       {"summary", n.summary()},
       {"residual_correlation", number(n.residual_correlation)},
       {"warnings", n.warnings}};
}

// ---- Joint identification ------------------------------------------------------------------------

void to_json(nlohmann::json& j, const ParameterInterval& i) {
  j = {{"estimate", number(i.estimate)}, {"fitted", number(i.fitted)},
       {"bias", number(i.bias)},         {"std_error", number(i.std_error)},
       {"lower", number(i.lower)},       {"upper", number(i.upper)},
       {"determined", i.determined},     {"free", i.free}};
}

void to_json(nlohmann::json& j, const SetupFit& s) {
  j = {{"label", s.label},
       {"fitted", s.fitted},
       {"std_error", per_parameter([&](int, std::size_t k) { return number(s.std_error[k]); })},
       {"residual_ratio", number(s.residual_ratio)},
       {"disagreement", number(s.disagreement)}};
}

void to_json(nlohmann::json& j, const JointFit& f) {
  j = {{"intervals", per_parameter([&](int k, std::size_t ks) { return with_unit(f.intervals[ks], k); })},
       {"confidence", f.confidence},
       {"method", f.method == UncertaintyMethod::Bootstrap ? "bootstrap" : "linearised"},
       {"method_description", f.method_description},
       {"bootstrap_samples", f.bootstrap_samples},
       {"reciprocal", f.reciprocal},
       {"points", f.points},
       {"residual_ratio", number(f.residual_ratio)},
       {"residual_calibration_share", number(f.residual_calibration_share)},
       {"iterations", f.iterations},
       {"converged", f.converged},
       {"correlation", matrix(f.correlation())},
       {"covariance", matrix(f.covariance)},
       {"calibration_std_error", per_parameter([&](int, std::size_t ks) { return number(f.calibration_std_error[ks]); })},
       {"warnings", f.warnings}};
  if (!f.setups.empty()) {
    j["setups"] = f.setups;
    j["transfer_statistic"] = number(f.transfer_statistic);
    j["transfer_limit"] = number(f.transfer_limit);
    j["transfers"] = f.transfers;
  }
}

void to_json(nlohmann::json& j, const ParameterPrecision& p) {
  j = {{"value", number(p.value)},
       {"half_width", number(p.half_width)},
       {"relative", number(p.relative)},
       {"calibration_half_width", number(p.calibration_half_width)},
       {"averages_for_target", p.averages_for_target ? nlohmann::json(*p.averages_for_target) : nlohmann::json(nullptr)},
       {"free", p.free}};
}

void to_json(nlohmann::json& j, const PrecisionStudy& s) {
  j = {{"route", to_string(s.route)},
       {"parameters", per_parameter([&](int k, std::size_t ks) { return with_unit(s.parameters[ks], k); })},
       {"confidence", s.confidence},
       {"averages", s.averages},
       {"target", s.target ? nlohmann::json(*s.target) : nlohmann::json(nullptr)},
       {"measured", s.measured},
       {"fit_description", s.fit_description},
       {"warnings", s.warnings}};
}

void to_json(nlohmann::json& j, const JointReadout& r) {
  j = {{"band_lo_hz", r.band_lo_hz},
       {"band_hi_hz", r.band_hi_hz},
       {"points", r.points},
       {"parameters", per_parameter([&](int k, std::size_t ks) {
          const ParameterReadout& p = r.parameters[ks];
          return with_unit({{"median", number(p.median)},
                            {"spread", number(p.spread)},
                            {"min", number(p.min)},
                            {"max", number(p.max)},
                            {"determined", p.determined},
                            {"noise_gain", number(r.noise_gain[ks])}},
                           k);
        })},
       {"reciprocity_k", number(r.reciprocity_k)},
       {"reciprocity_c", number(r.reciprocity_c)},
       {"max_cond_difference", number(r.max_cond_difference)},
       {"max_cond_flexibility", number(r.max_cond_flexibility)},
       {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const ModeChoice& c) {
  j = {{"method", c.method}, {"center_hz", number(c.center_hz)}, {"lo_hz", number(c.lo_hz)}, {"hi_hz", number(c.hi_hz)}};
  if (c.effect) j["effect"] = *c.effect;
  if (c.overhang) j["overhang"] = *c.overhang;
}

void to_json(nlohmann::json& j, const IdentificationVerdict& v) {
  j = {{"verdict", to_string(v.verdict)}, {"reasons", v.reasons}};
}

void to_json(nlohmann::json& j, const Identification& id) {
  j = {{"interface", to_string(id.route == Route::HolderTool ? JointInterface::HolderTool : JointInterface::SpindleHolder)},
       {"route", to_string(id.route)},
       {"equation", id.equation},
       {"method", to_string(id.method)},
       {"mode", id.mode},
       {"g_noise", id.g_noise},
       {"b_noise", id.b_noise},
       {"forward_checks", id.forward_checks},
       {"verdict", id.verdict},
       {"warnings", id.warnings}};
  if (id.fit) {
    j["fit"] = *id.fit;
    j["fit_band_hz"] = {id.fit_band_hz.first, id.fit_band_hz.second};
    j["parameters"] = j["fit"]["intervals"];
  } else {
    j["parameters"] = per_parameter([&](int k, std::size_t ks) {
      const ParameterReadout& p = id.seed.parameters[ks];
      return with_unit({{"estimate", number(p.median)}, {"lower", nullptr}, {"upper", nullptr}, {"determined", p.determined}}, k);
    });
  }
  if (id.seed.points > 0) j["seed"] = id.seed;
}

void to_json(nlohmann::json& j, const CaseStudy& cs) {
  j = {{"reference", cs.reference},
       {"clean_max_deviation", per_parameter([&](int, std::size_t k) { return number(cs.clean_max_deviation[k]); })},
       {"effect", cs.effect},
       {"mode_hz", cs.mode_hz},
       {"clean_readout", cs.clean_readout},
       {"noisy_readout", cs.noisy_readout},
       {"filtered_readout", cs.filtered_readout},
       {"verification", cs.verification},
       {"seed", cs.seed},
       {"warnings", cs.warnings}};
  if (cs.fitted) {
    j["fitted"] = *cs.fitted;
    j["fit_verification"] = cs.fit_verification;
  }
}

// ---- Uncertainty carried forward -----------------------------------------------------------------

namespace {

// {"q5": […], "q50": […], …}: one series per quantile level.
nlohmann::json quantiles(const std::vector<double>& levels, const std::vector<std::vector<double>>& values) {
  nlohmann::json q = nlohmann::json::object();
  for (std::size_t l = 0; l < levels.size(); ++l) q[fmt::format("q{:g}", 100 * levels[l])] = numbers(values[l]);
  return q;
}

}  // namespace

void to_json(nlohmann::json& j, const FrfBand& b) {
  j = {{"frequency_hz", numbers(b.frequency_hz)},
       {"levels", b.levels},
       {"samples", b.samples},
       {"magnitude", quantiles(b.levels, b.magnitude)},
       {"phase_rad", quantiles(b.levels, b.phase_rad)}};
}

void to_json(nlohmann::json& j, const StabilityUncertainty& s) {
  j = {{"speed_rpm", numbers(s.speed_rpm)},
       {"levels", s.levels},
       {"samples", s.samples},
       {"nominal_depth_m", numbers(s.nominal_depth_m)},
       {"depth_m", quantiles(s.levels, s.depth_m)},
       {"depth_grid_m", numbers(s.depth_grid_m)}};
}

// ---- Studies ------------------------------------------------------------------------------------

void to_json(nlohmann::json& j, const Prediction& p) {
  j = {{"receptance", predicted_frf_name(p.receptance)}, {"modes", p.modes}, {"warnings", p.warnings}};
  if (p.band) j["band"] = *p.band;
  if (p.two_plane.size() > 0) j["speed_rpm"] = p.speed_rpm;
}

void to_json(nlohmann::json& j, const OverhangFrf& r) { j = {{"overhang_m", r.overhang_m}, {"modes", r.modes}}; }

void to_json(nlohmann::json& j, const OverhangStudy& s) {
  j = {{"tool_inside_holder_m", s.tool_inside_holder_m},
       {"overhangs", s.overhangs},
       {"reference", s.reference},
       {"tracked_modes_hz", s.tracked_modes_hz},
       {"warnings", s.warnings}};
  if (s.band) j["band"] = *s.band;
}

void to_json(nlohmann::json& j, const TapTestFrf& r) { j = {{"response", r.response}, {"hammer", r.hammer}}; }

void to_json(nlohmann::json& j, const TapTest& t) {
  j = {{"side", tap_side_name(t.side)},
       {"distance_m", t.distance_m},
       {"frfs", t.frfs},
       {"shear_stiffness_n", t.shear_stiffness_n},
       {"crosses_step", t.crosses_step},
       {"warnings", t.warnings}};
}

void to_json(nlohmann::json& j, const RotationalResult& r) {
  j = {{"p_from_cross_terms", r.p_from_cross_terms},
       {"l_equals_n_by_reciprocity", r.l_equals_n_by_reciprocity},
       {"reciprocity_mismatch", r.reciprocity_mismatch ? number(*r.reciprocity_mismatch) : nlohmann::json(nullptr)},
       {"filled_by_reciprocity", r.filled_by_reciprocity},
       {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const FiniteDifferenceError& e) {
  j = {{"max_relative", numbers(e.max_relative)}, {"warnings", e.warnings}};
}

void to_json(nlohmann::json& j, const RotationalStudy& s) {
  j = {{"differences", s.differences},
       {"correction", s.correction ? nlohmann::json(*s.correction) : nlohmann::json(nullptr)},
       {"order", s.order},
       {"spacing_m", s.spacing_m},
       {"method", s.method},
       {"reciprocity", s.reciprocity},
       {"correction_note", s.correction_note},
       {"warnings", s.warnings}};
}

// ---- Filter -------------------------------------------------------------------------------------

void to_json(nlohmann::json& j, const PeakChange& c) {
  j = {{"entry", c.entry},
       {"raw_frequency_hz", number(c.raw_frequency_hz)},
       {"raw_magnitude", number(c.raw_magnitude)},
       {"filtered_frequency_hz", number(c.filtered_frequency_hz)},
       {"filtered_magnitude", number(c.filtered_magnitude)},
       {"height_change", number(c.height_change)},
       {"frequency_change", number(c.frequency_change)},
       {"noise", number(c.noise)}};
}

void to_json(nlohmann::json& j, const PeakChangeReport& r) { j = {{"peaks", r.peaks}, {"warnings", r.warnings}}; }

namespace {
template <class Series>
nlohmann::json filter_study_json(const FilterStudy<Series>& s) {
  return {{"noise_gain", s.noise_gain}, {"peaks", s.peaks}, {"warnings", s.warnings}};
}
}  // namespace

void to_json(nlohmann::json& j, const FilterStudy<FrfSeries>& s) { j = filter_study_json(s); }
void to_json(nlohmann::json& j, const FilterStudy<BlockSeries>& s) { j = filter_study_json(s); }

// ---- Modal fit and stability lobes ----------------------------------------------------------------

void to_json(nlohmann::json& j, const Mode& m) {
  j = {{"mass_kg", number(m.mass_kg)}, {"damping_ratio", number(m.damping_ratio)}, {"frequency_hz", number(m.frequency_hz)}};
}

void to_json(nlohmann::json& j, const FittedMode& m) {
  j = {{"mode", m.mode},
       {"residue", number(m.residue)},
       {"initial_frequency_hz", number(m.initial_frequency_hz)},
       {"initial_damping_ratio", number(m.initial_damping_ratio)},
       {"points_in_half_power_band", m.points_in_half_power_band},
       {"normalised_residual", number(m.normalised_residual)}};
}

void to_json(nlohmann::json& j, const ModalFitResult& r) {
  j = {{"modes", r.modes},
       {"lower_residual", number(r.lower_residual)},
       {"upper_residual", number(r.upper_residual)},
       {"normalised_residual", number(r.normalised_residual)},
       {"band_low_hz", r.band_low_hz},
       {"band_high_hz", r.band_high_hz},
       {"points", r.points},
       {"evaluations", r.evaluations},
       {"converged", r.converged},
       {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const ModalFitStudy& s) { j = {{"fit", s.fit}, {"model", s.model}, {"warnings", s.warnings}}; }

void to_json(nlohmann::json& j, const ModalModel& m) {
  j = {{"x", m.x}, {"y", m.y}};
  if (m.terms.empty()) return;
  nlohmann::json c = nlohmann::json::array();
  for (const ResidueTerm& t : m.terms)
    c.push_back({{"to", t.to == 0 ? "x" : "y"},
                 {"from", t.from == 0 ? "x" : "y"},
                 {"pole_re", t.pole.real()},
                 {"pole_im", t.pole.imag()},
                 {"residue_re", t.residue.real()},
                 {"residue_im", t.residue.imag()}});
  j["terms"] = c;
}

void to_json(nlohmann::json& j, const ModalFitSummary& s) {
  j = {{"what", s.what},
       {"modes", s.modes},
       {"residual", number(s.residual)},
       {"band_low_hz", s.band_low_hz},
       {"band_high_hz", s.band_high_hz},
       {"target_met", s.target_met}};
}

void to_json(nlohmann::json& j, const Engagement& e) { j = {{"entry_rad", e.entry_rad}, {"exit_rad", e.exit_rad}}; }

void to_json(nlohmann::json& j, const CuttingConditions& c) {
  j = fields_json(cutting_fields(), c);
  j["engagement"] = c.engagement;
  j["pitch_rad"] = c.pitch_rad;
  j["helix_rad"] = c.helix_rad;
  j["runout_m"] = c.runout_m;
}

void to_json(nlohmann::json& j, const SpeedRange& s) { j = fields_json(speed_range_fields(), s); }

void to_json(nlohmann::json& j, const EnvelopePoint& p) {
  j = {{"speed_rpm", p.speed_rpm}, {"depth_m", number(p.depth_m)}, {"chatter_hz", number(p.chatter_hz)}, {"lobe", p.lobe}};
}

void to_json(nlohmann::json& j, const BoundaryPoint& b) {
  j = {{"speed_rpm", b.speed_rpm}, {"depth_m", number(b.depth_m)},       {"depth_error_m", number(b.depth_error_m)},
       {"steps", b.steps},         {"chatter_hz", number(b.chatter_hz)}, {"lobe", b.lobe},
       {"kind", to_string(b.kind)}};
}

void to_json(nlohmann::json& j, const ZeroOrderResult& r) {
  std::size_t points = 0;
  r.for_each_point([&](const LobePoint&) { ++points; });
  j = {{"alpha", matrix(r.alpha)},
       {"floor_depth_m", number(r.floor_depth_m)},
       {"floor_chatter_hz", number(r.floor_chatter_hz)},
       {"lobes", r.lobes},
       {"teeth", r.teeth},
       {"speeds", r.speeds},
       {"max_depth_m", r.max_depth_m},
       {"lobe_points", points},
       {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const BoundaryResult& r) {
  // The scheme named with its degree (fd: interpolation degree 1…3; sd: the delayed term's order 0…1),
  // so the JSON alone says which method the boundary is.
  j = {{"max_depth_m", r.max_depth_m},
       {"tolerance", r.tolerance},
       {"scheme", r.scheme == Discretization::Semi ? "sd" : "fd"},
       {"degree", r.degree},
       {"evaluations", r.evaluations},
       {"worst_relative_error", number(r.worst_relative_error())},
       {"flip_speeds",
        std::count_if(r.boundary.begin(), r.boundary.end(), [](const BoundaryPoint& x) { return x.kind == BoundaryKind::Flip; })},
       {"warnings", r.warnings}};
  const auto lowest = std::min_element(r.boundary.begin(), r.boundary.end(),
                                       [](const BoundaryPoint& x, const BoundaryPoint& y) { return x.depth_m < y.depth_m; });
  if (lowest != r.boundary.end()) j["lowest_boundary"] = *lowest;
}

void to_json(nlohmann::json& j, const PitchSample& s) {
  j = {{"variation_rad", s.variation_rad},   {"second_variation_rad", s.second_variation_rad},
       {"depth_m", number(s.depth_m)},       {"robust_depth_m", number(s.robust_depth_m)},
       {"chatter_hz", number(s.chatter_hz)}, {"kind", to_string(s.kind)}};
}

void to_json(nlohmann::json& j, const PitchChoice& c) {
  j = {{"pattern", to_string(c.pattern)},
       {"teeth", c.teeth},
       {"speed_rpm", c.speed_rpm},
       {"chatter_hz", number(c.chatter_hz)},
       {"max_variation_rad", c.max_variation_rad},
       {"closed_form_variation_rad", c.closed_form_variation_rad},
       {"closed_form_second_variation_rad", c.closed_form_second_variation_rad},
       {"closed_form_pitch_rad", c.closed_form_pitch_rad},
       {"closed_form_depth_m", number(c.closed_form_depth_m)},
       {"closed_form_robust_depth_m", number(c.closed_form_robust_depth_m)},
       {"variation_rad", c.variation_rad},
       {"second_variation_rad", c.second_variation_rad},
       {"pitch_rad", c.pitch_rad},
       {"chosen", c.chosen},
       {"uniform", c.uniform},
       {"gain", number(c.gain)},
       {"max_depth_m", c.max_depth_m},
       {"steps", c.steps},
       {"samples", c.samples},
       {"evaluations", c.evaluations},
       {"warnings", c.warnings}};
}

void to_json(nlohmann::json& j, const PitchStudyResult& r) {
  j = {{"choice", r.choice}, {"modes", r.modes}, {"fits", r.fits}, {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const LobesStudyResult& r) {
  j = {{"options", fields_json(lobes_study_fields(), r.options)},
       {"method", to_string(r.method)},
       {"cutting", r.cutting},
       {"speeds", r.speeds},
       {"pockets", r.pockets},
       {"warnings", r.warnings}};
  if (r.zero_order) j["zero_order"] = *r.zero_order;
  if (r.boundary) {
    j["boundary"] = *r.boundary;
    j["modes"] = r.modes;
    j["fits"] = r.fits;
  }
  if (r.boundary) j["pocket_depth_error_m"] = numbers(r.pocket_depth_error_m);
  if (!r.frf_speeds_rpm.empty()) {  // at speed (SpeedModel): the speeds the FRF was evaluated at, the interpolation's error
    j["speed_model"] = to_string(r.speed_model);
    j["frf_speeds_rpm"] = r.frf_speeds_rpm;
    j["frf_interpolation_error"] = number(r.frf_interpolation_error);
    j["envelope_interpolation_error"] = number(r.envelope_interpolation_error);
    if (r.boundary) {  // the time domain at speed: the modal fits' largest residuals over the speeds
      j["fit_residual"] = number(r.fit_residual);
      j["block_fit_residual"] = number(r.block_fit_residual);
    }
  }
  if (r.uncertainty) {
    j["uncertainty"] = *r.uncertainty;
    j["uncertain_joint"] = r.uncertain_joint;
    j["pocket_quantiles"] = r.pocket_quantiles;
    if (r.worst_speed) j["worst_speed"] = *r.worst_speed;
  }
}

void to_json(nlohmann::json& j, const SpeedQuantiles& q) {
  j = {{"speed_rpm", q.speed_rpm}, {"nominal_depth_m", number(q.nominal_depth_m)}, {"depth_m", numbers(q.depth_m)}};
}

// ---- The plan (studies/plan.hpp): the per-speed series go to its CSV files. ---------------------------

void to_json(nlohmann::json& j, const PlanSetup& s) {
  j = {{"candidate", s.candidate},
       {"job", s.job},
       {"speed_index", s.speed_index},
       {"overhang_m", number(s.overhang_m)},
       {"speed_rpm", number(s.speed_rpm)},
       {"depth_m", number(s.depth_m)},
       {"stable_depth_m", number(s.stable_depth_m)},
       {"safe_depth_m", number(s.safe_depth_m)},
       {"mrr_m3_per_s", number(s.mrr_m3_per_s)},
       {"power_w", number(s.power_w)},
       {"torque_nm", number(s.torque_nm)},
       {"limit", to_string(s.limit)},
       {"depth_margin", number(s.depth_margin)},
       {"probability", number(s.probability)},
       {"chatter_hz", number(s.chatter_hz)},
       {"lobe", s.lobe},
       {"window_low_rpm", number(s.window_low_rpm)},
       {"window_high_rpm", number(s.window_high_rpm)},
       {"reason", s.reason}};
}

void to_json(nlohmann::json& j, const PlanJob& job) {
  j = {{"candidate", job.candidate},
       {"overhang_index", job.overhang_index},
       {"overhang_m", number(job.overhang_m)},
       {"modes_hz", numbers(job.modes_hz)},
       {"best", job.best},
       {"warnings", job.warnings}};
}

void to_json(nlohmann::json& j, const PlanResult& r) {
  const PlanHeader& h = r.header;
  const PlanOptions& o = h.options;
  // The scalar fields from their tables (plan_fields, machine_limits_fields, safety_rule_fields).
  nlohmann::json options = fields_json(plan_fields(), o);
  options.update({{"name", o.name},
                  {"method", to_string(o.lobes.method)},
                  {"cutting", o.lobes.cutting},
                  {"speeds", o.lobes.speeds},
                  {"lobes", fields_json(lobes_study_fields(), o.lobes)},
                  {"machine", fields_json(machine_limits_fields(), o.machine)},
                  {"safety", fields_json(safety_rule_fields(), o.safety)}});
  options["safety"].update(
      {{"kind", o.safety.kind == SafetyRule::Kind::Factor ? "factor" : "probability"}, {"seed", o.safety.seed}});
  nlohmann::json candidates = nlohmann::json::array();
  for (const PlanCandidateSummary& cs : h.candidates)
    candidates.push_back({{"name", cs.name},
                          {"measured_holder", cs.measured_holder},
                          {"sh11_name", cs.sh11_name},
                          {"uncertain_joint", cs.uncertain_joint},
                          {"tool_diameter_m", cs.tool_diameter_m},
                          {"flute_length_m", cs.flute_length_m},
                          {"overhangs_m", numbers(cs.overhangs_m)},
                          {"left_out", cs.left_out}});
  j = {{"options", options}, {"candidates", candidates}, {"fingerprint", fmt::format("{:016x}", h.fingerprint)},
       {"jobs", r.jobs},     {"best", r.best},           {"warnings", r.warnings}};
}

// ---- Files ----------------------------------------------------------------------------------------

void to_json(nlohmann::json& j, const PlanarMode& m) {
  j = {{"frequency_hz", m.frequency_hz}, {"damping_ratio", m.damping_ratio}, {"shape_x", m.shape_x}, {"shape_y", m.shape_y}};
}

void to_json(nlohmann::json& j, const ToolDynamics& d) { j = {{"modes", d.modes}}; }

void to_json(nlohmann::json& j, const Cutter& c) {
  j = {{"teeth", c.teeth()},
       {"diameter_m", c.diameter_m},
       {"pitch_rad", c.pitch_rad},
       {"helix_rad", c.helix_rad},
       {"tooth_helix_rad", c.tooth_helix_rad},
       {"runout_m", c.runout_m},
       {"flute_length_m", c.flute_length_m}};
}

void to_json(nlohmann::json& j, const ForceLaw& f) {
  j = {{"tangential_coefficient", f.tangential_coefficient},
       {"radial_ratio", f.radial_ratio},
       {"tangential_edge", f.tangential_edge},
       {"radial_edge", f.radial_edge},
       {"exponent", f.exponent},
       {"reference_chip_m", f.reference_chip_m},
       {"process_damping_n_per_m", f.process_damping_n_per_m}};
}

void to_json(nlohmann::json& j, const MillingCut& c) {
  j = {{"speed_rpm", c.speed_rpm},
       {"depth_m", c.depth_m},
       {"feed_per_tooth_m", c.feed_per_tooth_m},
       {"engagement", c.engagement}};
}

void to_json(nlohmann::json& j, const SimulationOptions& o) {
  j = fields_json(simulation_fields(), o);  // the scalar fields (simulation_fields)
}

void to_json(nlohmann::json& j, const Wall& w) {
  nlohmann::json sle = nlohmann::json::array();
  for (double v : w.sle_m) sle.push_back(number(v));
  j = {{"angle_rad", w.angle_rad}, {"slice_height_m", w.slice_height_m}, {"sle_m", sle}, {"mean_sle_m", number(w.mean_sle_m)}};
}

void to_json(nlohmann::json& j, const SimulationResult& r) {
  j = {{"step_s", r.step_s},
       {"steps_per_tooth", r.steps_per_tooth},
       {"steps_per_revolution", r.steps_per_revolution},
       {"slices", r.slices},
       {"revolutions", r.revolutions},
       {"steps", r.steps},
       {"analysed_from", r.analysed_from},
       {"mean_force_x_n", number(r.mean_force_x_n)},
       {"mean_force_y_n", number(r.mean_force_y_n)},
       {"mean_torque_nm", number(r.mean_torque_nm)},
       {"power_w", number(r.power_w)},
       {"peak_force_n", number(r.peak_force_n)},
       {"sle_m", number(r.sle_m)},
       {"growth", number(r.growth)},
       {"chatter_metric", number(r.chatter_metric)},
       {"chatter_hz", number(r.chatter_hz)},
       {"stable", r.stable},
       {"diverged", r.diverged},
       {"out_of_cut_fraction", number(r.out_of_cut_fraction)},
       {"walls", r.walls},
       {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const SimulationStudyResult& r) {
  j = {{"dynamics", r.dynamics},     {"fits", r.fits},        {"cutter", r.cutter}, {"force", r.force}, {"cut", r.cut},
       {"simulation", r.simulation}, {"warnings", r.warnings}};
}

void to_json(nlohmann::json& j, const DepthRange& d) { j = {{"min_m", d.min_m}, {"max_m", d.max_m}, {"points", d.points}}; }

void to_json(nlohmann::json& j, const SimulatedMap& m) {
  const SimulatedMapOptions& o = m.header.options;
  std::size_t cells = 0, stable = 0;
  for (const SimulatedMapRow& r : m.rows)
    for (int s : r.stable) {
      ++cells;
      stable += s != 0;
    }
  EnvelopePoint lowest;
  lowest.depth_m = std::numeric_limits<double>::infinity();
  lowest.chatter_hz = std::numeric_limits<double>::quiet_NaN();
  for (const EnvelopePoint& e : m.boundary)
    if (e.depth_m < lowest.depth_m) lowest = e;
  j = {{"dynamics", m.header.dynamics},
       {"options",
        {{"cutter", o.cutter},
         {"force", o.force},
         {"cut", {{"feed_per_tooth_m", o.cut.feed_per_tooth_m}, {"engagement", o.cut.engagement}}},
         {"simulation", o.simulation},
         {"speeds", o.speeds},
         {"depths", o.depths}}},
       {"fingerprint", fmt::format("{:016x}", m.header.fingerprint)},
       {"cells", cells},
       {"stable_cells", stable},
       {"lowest_unstable", lowest},
       {"warnings", m.warnings}};
}

void to_json(nlohmann::json& j, const FreeMode& m) {
  j = {{"frequency_hz", m.frequency_hz}, {"w1", m.w1}, {"psi1", m.psi1}, {"w2", m.w2}, {"psi2", m.psi2},
       {"above_cutoff", m.above_cutoff}};
}

void to_json(nlohmann::json& j, const BeamSection& s) {
  j = {{"area", s.area},
       {"second_moment", s.second_moment},
       {"shear_coefficient", s.shear_coefficient},
       {"rhoA", s.rhoA},
       {"rhoI", s.rhoI},
       {"cutoff_frequency_hz", s.cutoff_frequency_hz}};
}

void to_json(nlohmann::json& j, const BeamStudy& s) {
  nlohmann::json modes = nlohmann::json::array();
  for (std::size_t i = 0; i < s.modes.size(); ++i) {
    nlohmann::json m = s.modes[i];
    m["mode"] = i + 1;  // numbered as printed: mode 1 is the lowest elastic mode
    modes.push_back(std::move(m));
  }
  j = {{"section", s.section}, {"modes", modes}, {"method", s.method}, {"warnings", s.warnings}};
  if (s.speed_rpm > 0.0) j["speed_rpm"] = s.speed_rpm;
  if (s.whirl) j["whirl"] = *s.whirl;
  if (!s.campbell.empty()) j["campbell"] = s.campbell;
}

void to_json(nlohmann::json& j, const WhirlFrequencies& w) {
  j = {{"spin_rad_s", w.spin_rad_s},
       {"speed_rpm", rpm_of_rad_s(w.spin_rad_s)},
       {"forward_hz", w.forward_hz},
       {"backward_hz", w.backward_hz},
       {"conical_hz", std::isfinite(w.conical_hz) ? nlohmann::json(w.conical_hz) : nlohmann::json(nullptr)}};
}

void to_json(nlohmann::json& j, const UffDof& d) {
  j = {{"response_node", d.response_node},
       {"response_direction", d.response_direction},
       {"reference_node", d.reference_node},
       {"reference_direction", d.reference_direction}};
}

void to_json(nlohmann::json& j, const FrfUnits& u) {
  j = {{"ordinate", frf_ordinate_name(u.ordinate)}, {"to_si", u.to_si}, {"label", u.label}};
}

void to_json(nlohmann::json& j, const FrfFileData& d) {
  j = {{"format", frf_format_name(d.format)},
       {"is_block", d.is_block},
       {"ordinate", frf_ordinate_name(d.ordinate)},
       {"units", d.units},
       {"description", d.description},
       {"dof", d.dof},
       {"warnings", d.warnings}};
}

void to_json(nlohmann::json& j, const UffAxis& a) {
  j = {{"data_type", a.data_type},
       {"data_type_name", uff_data_type_name(a.data_type)},
       {"length_exponent", a.length_exponent},
       {"force_exponent", a.force_exponent},
       {"temperature_exponent", a.temperature_exponent},
       {"label", a.label},
       {"units", a.units}};
}

void to_json(nlohmann::json& j, const UffUnits& u) {
  j = {{"code", u.code},
       {"description", u.description},
       {"length_factor", u.length_factor},
       {"force_factor", u.force_factor},
       {"temperature_factor", u.temperature_factor},
       {"line", u.line}};
}

void to_json(nlohmann::json& j, const UffDataset58& d) {
  j = {{"id", d.id},
       {"function_type", d.function_type},
       {"function_type_name", uff_function_type_name(d.function_type)},
       {"function_id", d.function_id},
       {"version", d.version},
       {"load_case", d.load_case},
       {"response_entity", d.response_entity},
       {"response_node", d.response_node},
       {"response_direction", d.response_direction},
       {"response_direction_name", uff_direction_name(d.response_direction)},
       {"reference_entity", d.reference_entity},
       {"reference_node", d.reference_node},
       {"reference_direction", d.reference_direction},
       {"reference_direction_name", uff_direction_name(d.reference_direction)},
       {"ordinate_data_type", d.ordinate_data_type},
       {"ordinate_data_type_name", uff_ordinate_type_name(d.ordinate_data_type)},
       {"declared_points", d.declared_points},
       {"even", d.even},
       {"abscissa_min", d.abscissa_min},
       {"abscissa_increment", d.abscissa_increment},
       {"z_value", d.z_value},
       {"abscissa", d.abscissa},
       {"ordinate", d.ordinate},
       {"denominator", d.denominator},
       {"z_axis", d.z_axis},
       {"index", d.index},
       {"line", d.line},
       {"binary", d.binary},
       {"byte_order", d.byte_order},
       {"units", d.units ? nlohmann::json(*d.units) : nlohmann::json(nullptr)},
       {"warnings", d.warnings},
       {"headers_only", d.headers_only},
       {"abscissa_first", d.abscissa_first},
       {"abscissa_last", d.abscissa_last}};
}

void to_json(nlohmann::json& j, const UffDatasetEntry& e) {
  j = {{"type", e.type}, {"binary", e.binary}, {"line", e.line}, {"offset", e.offset}};
}

void to_json(nlohmann::json& j, const UffFile& f) {
  j = {{"source", f.source},     {"datasets", f.datasets}, {"functions", f.functions},
       {"warnings", f.warnings}, {"skipped", f.skipped},   {"file_warnings", f.file_warnings}};
}

}  // namespace toolpoint
