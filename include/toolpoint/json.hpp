// toolpoint: results as JSON (nlohmann::json), one to_json per result type and one spelling per
// field, for the CLI's --json, summary files and the Python package.
//
// Conventions: SI units, named in the key where a reader could doubt them (`_hz`, `_m`,
// `_m_per_n`); relative errors as percentages in keys ending `_percent`; a joint parameter is
// always spelt k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm (θ as "t") with its `unit`.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "toolpoint/identify.hpp"
#include "toolpoint/joint_fit.hpp"
#include "toolpoint/noise.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/uncertainty.hpp"

namespace toolpoint {

// {"k_yf": value, …}
nlohmann::json to_json(const JointParameters& p);
// Per parameter {"estimate", "lower95", "upper95", "std_error", "fitted", "bias", "determined",
// "free", "unit"} (the interval's confidence in the key when it is not 95 %: "lower90", …), and the
// fit's diagnostics.
nlohmann::json to_json(const JointFit& fit);
// The seed's read-out: band, points, per parameter {"median", "spread", "min", "max",
// "noise_gain", "unit"}, reciprocity, conditioning, warnings.
nlohmann::json to_json(const JointReadout& readout);
// Forward check, mode by mode: {"measured_hz", "predicted_hz", "frequency_error_percent",
// "measured_peak_m_per_n", "predicted_peak_m_per_n", "peak_error_percent"}.
nlohmann::json to_json(const std::vector<ModeComparison>& check);
nlohmann::json to_json(const EffectAnalysis& effect);
nlohmann::json to_json(const ModeChoice& choice);
// {"source", "magnitude_sigma": [H, L, N, P], "phase_sigma_rad": […], "residual_correlation"}.
nlohmann::json to_json(const BlockNoise& noise);
// The whole study; "parameters" holds the chosen method's values in JointFit's spelling (for the
// seed's read-out: estimate = the median, no interval, determined from its noise gain and spread).
nlohmann::json to_json(const Identification& id);
nlohmann::json to_json(const FrfBand& band);
nlohmann::json to_json(const StabilityUncertainty& s);

}  // namespace toolpoint
