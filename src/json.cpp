// toolpoint: results as JSON (json.hpp). Keys are the members' names (nlohmann::json sorts them).
#include "toolpoint/json.hpp"

namespace toolpoint {

void to_json(nlohmann::json& j, const Peak& p) {
  j = {{"index", p.index}, {"frequency_hz", p.frequency_hz}, {"magnitude", p.magnitude}, {"prominence", p.prominence}};
}

void to_json(nlohmann::json& j, const ModeComparison& c) {
  j = {{"measured_hz", c.measured_hz},     {"predicted_hz", c.predicted_hz},     {"frequency_error", c.frequency_error},
       {"measured_peak", c.measured_peak}, {"predicted_peak", c.predicted_peak}, {"magnitude_error", c.magnitude_error}};
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

}  // namespace toolpoint
