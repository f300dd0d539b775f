// toolpoint: results as JSON (nlohmann::json), for the CLI's --json output, summary files and
// anyone who wants a result as plain data. `nlohmann::json j = result;` finds these by ADL.
//
// One spelling per field, by one rule:
//   * a key is the C++ member's name (Peak::frequency_hz → "frequency_hz"), and its value is in
//     the member's unit (SI; Hz for frequencies; in the name where the name has one, else in the
//     member's header comment). The same field therefore has the same key in every command;
//   * enums are lower-case strings or the receptance's name: PredictedFrf "SHT11" / "SH11",
//     TapSide "tool" / "holder", HammerPlan "roving" / "tip";
//   * NaN (a mode not found) becomes null: JSON has no NaN;
//   * sampled series (BlockSeries, FrfSeries members) are left out: they go to FRF files
//     (io.hpp, frf_file.hpp, uff.hpp) or, in Python, to arrays. What a caller adds (file names,
//     the assembly's path, units) it adds under its own keys.
// Units: SI; frequencies in Hz.
#pragma once

#include <nlohmann/json.hpp>

#include "toolpoint/identify.hpp"
#include "toolpoint/peaks.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/tap_test.hpp"

namespace toolpoint {

// {"index", "frequency_hz", "magnitude", "prominence"}
void to_json(nlohmann::json& j, const Peak& p);
// {"measured_hz", "predicted_hz", "frequency_error", "measured_peak", "predicted_peak", "magnitude_error"}
void to_json(nlohmann::json& j, const ModeComparison& c);

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

}  // namespace toolpoint
