// toolpoint: results as JSON (json.hpp). nlohmann::json sorts the keys.
#include "toolpoint/json.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/conventions.hpp"

namespace toolpoint {

namespace {

// NaN and ±inf are not JSON numbers: null.
nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json numbers(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(number(x));
  return a;
}

std::string level_key(const char* side, double confidence) { return fmt::format("{}{}", side, std::lround(100.0 * confidence)); }

}  // namespace

void to_json(nlohmann::json& j, const Peak& p) {
  j = {{"index", p.index}, {"frequency_hz", p.frequency_hz}, {"magnitude", p.magnitude}, {"prominence", p.prominence}};
}

// ---- Studies ------------------------------------------------------------------------------------

void to_json(nlohmann::json& j, const Prediction& p) {
  j = {{"receptance", predicted_frf_name(p.receptance)}, {"modes", p.modes}, {"warnings", p.warnings}};
}

void to_json(nlohmann::json& j, const OverhangFrf& r) { j = {{"overhang_m", r.overhang_m}, {"modes", r.modes}}; }

void to_json(nlohmann::json& j, const OverhangStudy& s) {
  j = {{"tool_inside_holder_m", s.tool_inside_holder_m},
       {"overhangs", s.overhangs},
       {"reference", s.reference},
       {"tracked_modes_hz", s.tracked_modes_hz},
       {"warnings", s.warnings}};
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

// The plan (studies/plan.hpp): the per-speed series go to its CSV files.

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

void to_json(nlohmann::json& j, const PlanResult& r) {
  const PlanHeader& h = r.header;
  const PlanOptions& o = h.options;
  const CuttingConditions& c = o.lobes.cutting;
  nlohmann::json options = {
      {"name", o.name},
      {"method", o.lobes.method == LobesMethod::ZeroOrder ? "zero_order" : "full_discretization"},
      {"cutting",
       {{"teeth", c.teeth},
        {"tangential_coefficient", c.tangential_coefficient},
        {"radial_ratio", c.radial_ratio},
        {"entry_rad", c.engagement.entry_rad},
        {"exit_rad", c.engagement.exit_rad}}},
      {"feed_per_tooth_m", o.feed_per_tooth_m},
      {"edge_coefficient_n_per_m", o.edge_coefficient_n_per_m},
      {"max_depth_m", o.max_depth_m},
      {"machine",
       {{"power_w", o.machine.power_w}, {"torque_nm", o.machine.torque_nm}, {"min_overhang_m", o.machine.min_overhang_m}}},
      {"safety",
       {{"kind", o.safety.kind == SafetyRule::Kind::Factor ? "factor" : "probability"},
        {"factor", o.safety.factor},
        {"probability", o.safety.probability},
        {"samples", o.safety.samples},
        {"seed", o.safety.seed}}}};
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
  nlohmann::json tuning = nlohmann::json::array();
  for (const PlanJob& job : r.jobs)
    tuning.push_back(
        {{"candidate", job.candidate}, {"overhang_m", job.overhang_m}, {"modes_hz", numbers(job.modes_hz)}, {"best", job.best}});
  j = {{"options", options},
       {"candidates", candidates},
       {"speeds_rpm", {{"min", o.lobes.speeds.min_rpm}, {"max", o.lobes.speeds.max_rpm}, {"points", o.lobes.speeds.points}}},
       {"jobs", h.jobs},
       {"fingerprint", fmt::format("{:016x}", h.fingerprint)},
       {"best", r.best},
       {"tuning", tuning},
       {"warnings", r.warnings}};
}

// ---- Joint identification and uncertainty --------------------------------------------------------

void to_json(nlohmann::json& out, const JointParameters& p) {
  nlohmann::json j;
  for (int k = 0; k < 8; ++k) j[JointParameters::name(k)] = number(p[k]);
  out = std::move(j);
}

void to_json(nlohmann::json& out, const JointFit& f) {
  nlohmann::json j;
  for (int k = 0; k < 8; ++k) {
    const ParameterInterval& iv = f.intervals[static_cast<std::size_t>(k)];
    j["parameters"][JointParameters::name(k)] = {{"estimate", number(iv.estimate)},
                                                 {level_key("lower", f.confidence), number(iv.lower)},
                                                 {level_key("upper", f.confidence), number(iv.upper)},
                                                 {"std_error", number(iv.std_error)},
                                                 {"fitted", number(iv.fitted)},
                                                 {"bias", number(iv.bias)},
                                                 {"determined", iv.determined},
                                                 {"free", iv.free},
                                                 {"unit", JointParameters::unit(k)}};
  }
  j["confidence"] = f.confidence;
  j["interval_method"] = f.method == UncertaintyMethod::Bootstrap ? "bootstrap" : "linearised";
  j["interval_description"] = f.method_description;
  j["bootstrap_samples"] = f.bootstrap_samples;
  j["reciprocal"] = f.reciprocal;
  j["points"] = f.points;
  j["residual_ratio"] = number(f.residual_ratio);
  j["iterations"] = f.iterations;
  j["converged"] = f.converged;
  nlohmann::json corr = nlohmann::json::array(), cov = nlohmann::json::array();
  const auto c = f.correlation();
  for (int i = 0; i < 8; ++i) {
    nlohmann::json rc = nlohmann::json::array(), rv = nlohmann::json::array();
    for (int k = 0; k < 8; ++k) {
      rc.push_back(number(c(i, k)));
      rv.push_back(number(f.covariance(i, k)));
    }
    corr.push_back(rc);
    cov.push_back(rv);
  }
  j["correlation"] = corr;
  j["covariance"] = cov;
  if (!f.setups.empty()) {
    nlohmann::json s = nlohmann::json::array();
    for (const SetupFit& x : f.setups) {
      nlohmann::json se;
      for (int k = 0; k < 8; ++k) se[JointParameters::name(k)] = number(x.std_error[static_cast<std::size_t>(k)]);
      s.push_back({{"label", x.label},
                   {"parameters", nlohmann::json(x.fitted)},
                   {"std_error", se},
                   {"residual_ratio", number(x.residual_ratio)},
                   {"disagreement", number(x.disagreement)}});
    }
    j["setups"] = s;
    j["transfer"] = {{"statistic", number(f.transfer_statistic)},
                     {"limit_99_9", number(f.transfer_limit)},
                     {"transfers", f.transfers}};
  }
  j["warnings"] = f.warnings;
  out = std::move(j);
}

void to_json(nlohmann::json& out, const JointReadout& r) {
  nlohmann::json j;
  j["band_hz"] = {r.band_lo_hz, r.band_hi_hz};
  j["points"] = r.points;
  for (int k = 0; k < 8; ++k) {
    const auto& p = r.parameters[static_cast<std::size_t>(k)];
    j["parameters"][JointParameters::name(k)] = {{"median", number(p.median)},
                                                 {"spread", number(p.spread)},
                                                 {"min", number(p.min)},
                                                 {"max", number(p.max)},
                                                 {"noise_gain", number(r.noise_gain[static_cast<std::size_t>(k)])},
                                                 {"unit", JointParameters::unit(k)}};
  }
  j["reciprocity"] = {{"k_ym_vs_k_tf", number(r.reciprocity_k)}, {"c_ym_vs_c_tf", number(r.reciprocity_c)}};
  j["max_condition_numbers"] = {{"A11_minus_G11", number(r.max_cond_difference)}, {"K_inverse", number(r.max_cond_flexibility)}};
  j["warnings"] = r.warnings;
  out = std::move(j);
}

void to_json(nlohmann::json& out, const ModeComparison& c) {
  out = {{"measured_hz", number(c.measured_hz)},
         {"predicted_hz", number(c.predicted_hz)},
         {"frequency_error_percent", number(100 * c.frequency_error)},
         {"measured_peak_m_per_n", number(c.measured_peak)},
         {"predicted_peak_m_per_n", number(c.predicted_peak)},
         {"peak_error_percent", number(100 * c.magnitude_error)}};
}

void to_json(nlohmann::json& out, const EffectAnalysis& e) {
  nlohmann::json modes = nlohmann::json::array();
  for (const ModeEffect& m : e.modes)
    modes.push_back({{"frequency_hz", number(m.frequency_hz)},
                     {"peak_m_per_n", number(m.magnitude)},
                     {"shift_percent_per_10_percent_k", number(100 * m.stiffness_shift)},
                     {"peak_change_percent_per_10_percent_c", number(100 * m.damping_effect)}});
  out = {{"modes", modes}, {"dominant_index", e.dominant}, {"dominant_hz", number(e.modes.at(e.dominant).frequency_hz)}};
}

void to_json(nlohmann::json& out, const ModeChoice& c) {
  nlohmann::json j = {{"method", c.method}, {"center_hz", number(c.center_hz)}, {"band_hz", {number(c.lo_hz), number(c.hi_hz)}}};
  if (c.effect) j["effect_analysis"] = nlohmann::json(*c.effect);
  if (c.overhang)
    j["overhang_modes"] = {{"relative_variation", numbers(c.overhang->relative_variation)},
                           {"dominant_index", c.overhang->dominant}};
  out = std::move(j);
}

void to_json(nlohmann::json& out, const BlockNoise& n) {
  out = {{"source", n.source},
         {"magnitude_sigma", numbers({n.magnitude_sigma.begin(), n.magnitude_sigma.end()})},
         {"phase_sigma_rad", numbers({n.phase_sigma_rad.begin(), n.phase_sigma_rad.end()})},
         {"residual_correlation", number(n.residual_correlation)}};
}

void to_json(nlohmann::json& out, const Identification& id) {
  nlohmann::json j;
  j["interface"] = id.route == Route::HolderTool ? "holder_tool" : "spindle_holder";
  j["route"] = to_string(id.route);
  j["equation"] = id.equation;
  j["method"] = to_string(id.method);
  if (id.fit) {
    nlohmann::json f = nlohmann::json(*id.fit);
    j["parameters"] = f["parameters"];
    f.erase("parameters");
    f["band_hz"] = {id.fit_band_hz.first, id.fit_band_hz.second};
    j["fit"] = f;
  } else {
    for (int k = 0; k < 8; ++k) {
      const auto& p = id.seed.parameters[static_cast<std::size_t>(k)];
      const double gain = id.seed.noise_gain[static_cast<std::size_t>(k)];
      j["parameters"][JointParameters::name(k)] = {{"estimate", number(p.median)},
                                                   {"lower95", nullptr},
                                                   {"upper95", nullptr},
                                                   {"determined", gain <= 20.0 && p.spread <= std::abs(p.median)},
                                                   {"unit", JointParameters::unit(k)}};
    }
  }
  if (id.seed.points > 0) j["seed_readout"] = nlohmann::json(id.seed);
  j["mode_choice"] = nlohmann::json(id.mode);
  nlohmann::json noise = nlohmann::json::array();
  for (std::size_t s = 0; s < id.g_noise.size(); ++s)
    noise.push_back({{"G11", nlohmann::json(id.g_noise[s])}, {"B11", nlohmann::json(id.b_noise[s])}});
  j["noise"] = noise;
  j["forward_check"] = nlohmann::json(id.forward_check);
  j["verdict"] = {{"verdict", to_string(id.verdict.verdict)}, {"reasons", id.verdict.reasons}};
  j["warnings"] = id.warnings;
  out = std::move(j);
}

void to_json(nlohmann::json& out, const FrfBand& b) {
  nlohmann::json mag = nlohmann::json::object(), ph = nlohmann::json::object();
  for (std::size_t l = 0; l < b.levels.size(); ++l) {
    const std::string key = fmt::format("q{:g}", 100 * b.levels[l]);
    mag[key] = numbers(b.magnitude[l]);
    ph[key] = numbers(b.phase_rad[l]);
  }
  out = {{"frequency_hz", numbers(b.frequency_hz)},
         {"levels", b.levels},
         {"samples", b.samples},
         {"magnitude_m_per_n", mag},
         {"phase_rad", ph}};
}

void to_json(nlohmann::json& out, const StabilityUncertainty& s) {
  nlohmann::json d = nlohmann::json::object();
  for (std::size_t l = 0; l < s.levels.size(); ++l) d[fmt::format("q{:g}", 100 * s.levels[l])] = numbers(s.depth_m[l]);
  out = {{"speed_rpm", numbers(s.speed_rpm)},
         {"levels", s.levels},
         {"samples", s.samples},
         {"nominal_depth_m", numbers(s.nominal_depth_m)},
         {"depth_m", d},
         {"depth_grid_m", numbers(s.depth_grid_m)}};
}

// ---- Stability lobes ------------------------------------------------------------------------------

void to_json(nlohmann::json& j, const Mode& m) {
  j = {{"modal_mass_kg", m.mass_kg}, {"damping_ratio", m.damping_ratio}, {"frequency_hz", m.frequency_hz}};
}

void to_json(nlohmann::json& j, const ModalFitSummary& s) {
  j = {{"frf", s.what},
       {"modes", s.modes},
       {"normalised_residual", s.residual},
       {"band_low_hz", s.band_low_hz},
       {"band_high_hz", s.band_high_hz},
       {"target_met", s.target_met}};
}

void to_json(nlohmann::json& j, const CuttingConditions& c) {
  j = {{"teeth", c.teeth},
       {"tangential_coefficient_n_per_m2", c.tangential_coefficient},
       {"radial_ratio", c.radial_ratio},
       {"entry_deg", c.engagement.entry_rad * 180.0 / kPi},
       {"exit_deg", c.engagement.exit_rad * 180.0 / kPi}};
}

void to_json(nlohmann::json& j, const EnvelopePoint& p) {
  j = {{"spindle_speed_rpm", p.speed_rpm},
       {"axial_depth_mm", p.depth_m * 1e3},
       {"chatter_frequency_hz", p.chatter_hz},
       {"lobe", p.lobe}};
}

void to_json(nlohmann::json& j, const BoundaryPoint& b) {
  j = {{"spindle_speed_rpm", b.speed_rpm},
       {"axial_depth_mm", b.depth_m * 1e3},
       {"axial_depth_error_mm", number(b.depth_error_m * 1e3)},
       {"chatter_frequency_hz", number(b.chatter_hz)},
       {"lobe", b.lobe},
       {"kind", to_string(b.kind)},
       {"steps", b.steps}};
}

void to_json(nlohmann::json& j, const LobesStudyResult& r) {
  nlohmann::json out;
  out["units"] = "spindle speed rpm, axial depth mm, chatter frequency Hz";
  out["cutting"] = r.cutting;
  out["pockets"] = r.pockets;
  out["warnings"] = r.warnings;
  if (r.zero_order) {
    const ZeroOrderResult& z = *r.zero_order;
    out["method"] = "zoa";
    out["floor_depth_mm"] = z.floor_depth_m * 1e3;
    out["floor_chatter_frequency_hz"] = z.floor_chatter_hz;
    std::size_t points = 0;
    z.for_each_point([&](const LobePoint&) { ++points; });
    out["lobes"] = z.lobes;
    out["lobe_points"] = points;
  }
  if (r.boundary) {
    const BoundaryResult& b = *r.boundary;
    out["method"] = "fd";
    out["modes_x"] = r.modes.x;
    out["modes_y"] = r.modes.y;
    out["modal_fit"] = r.fits;
    out["max_depth_mm"] = b.max_depth_m * 1e3;
    out["tolerance_pct"] = 100.0 * b.tolerance;
    out["worst_error_pct"] = 100.0 * b.worst_relative_error();
    out["degree"] = b.degree;
    out["evaluations"] = b.evaluations;
    const auto lowest = std::min_element(b.boundary.begin(), b.boundary.end(),
                                         [](const BoundaryPoint& x, const BoundaryPoint& y) { return x.depth_m < y.depth_m; });
    if (lowest != b.boundary.end()) out["lowest_boundary"] = *lowest;
    out["flip_speeds"] = std::count_if(b.boundary.begin(), b.boundary.end(),
                                       [](const BoundaryPoint& x) { return x.kind == BoundaryKind::Flip; });
  }
  j = std::move(out);
}

}  // namespace toolpoint
