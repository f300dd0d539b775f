// The pitch choice study (studies/pitch.hpp).
#include "toolpoint/studies/pitch.hpp"

#include "toolpoint/conventions.hpp"

namespace toolpoint {

PitchStudyResult run_pitch_study(const LobesInput& input, const PitchStudyOptions& options) {
  options.choice.check();
  options.cutting.check();
  PitchStudyResult res;
  res.modes = time_domain_modes(input, options.fit, options.fit_target, res.fits, res.warnings);
  res.choice = choose_pitch(res.modes, options.cutting, options.choice);
  res.warnings.insert(res.warnings.end(), res.choice.warnings.begin(), res.choice.warnings.end());
  return res;
}

const std::vector<OptionField<PitchChoiceOptions>>& pitch_choice_fields() {
  using O = PitchChoiceOptions;
  constexpr double kDegreesPerRadian = 180.0 / kPi;  // the CLI's pitch angles are in degrees
  // The ranges are PitchChoiceOptions::check's.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "speed_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .min_open = true,
        .help = "target spindle speed",
        .cli_name = "rpm",
        .plausible = &plausible::kSpindleSpeedRpm},
       [](O& o) -> double& { return o.speed_rpm; }},
      {{.name = "min_pitch_rad",
        .kind = FieldKind::Real,
        .unit = "rad",
        .min = 0.0,
        .max = 2.0 * kPi,
        .max_open = true,
        .note = "0: half the even pitch",
        .help = "smallest pitch angle allowed",
        .cli_name = "min-pitch",
        .cli_unit = "degrees",
        .cli_per_unit = kDegreesPerRadian},
       [](O& o) -> double& { return o.min_pitch_rad; }},
      {{.name = "max_pitch_rad",
        .kind = FieldKind::Real,
        .unit = "rad",
        .min = 0.0,
        .max = 2.0 * kPi,
        .max_open = true,
        .note = "0: 1.5 × the even pitch",
        .help = "largest pitch angle allowed",
        .cli_name = "max-pitch",
        .cli_unit = "degrees",
        .cli_per_unit = kDegreesPerRadian},
       [](O& o) -> double& { return o.max_pitch_rad; }},
      {{.name = "chatter_hz",
        .kind = FieldKind::Real,
        .unit = "Hz",
        .min = 0.0,
        .note = "0: the evenly spaced tool's at the target speed",
        .help = "chatter frequency Budak's rule aims at",
        .cli_name = "chatter"},
       [](O& o) -> double& { return o.chatter_hz; }},
      {{.name = "window",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .help = "search ΔP over (1 ± window) × the closed form's",
        .cli_name = "window"},
       [](O& o) -> double& { return o.window; }},
      {{.name = "search_points",
        .kind = FieldKind::Integer,
        .min = 3.0,
        .max = 201.0,
        .help = "points of the first search grid (three-angle: per parameter, a square grid)",
        .cli_name = "search-points"},
       nullptr,
       [](O& o) -> int& { return o.search_points; }},
      {{.name = "robustness",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 0.2,
        .help = "maximise the lowest limit of ΔP and ΔP(1 ± robustness), as a speed off by as much",
        .cli_name = "robustness",
        .cli_unit = "% of ΔP",
        .cli_per_unit = 100.0},
       [](O& o) -> double& { return o.robustness; }},
      {{.name = "steps",
        .kind = FieldKind::Integer,
        .min = 4.0,
        .max = 2000.0,
        .automatic = 0.0,
        .note = "0: 12 per chatter wave",
        .help = "full-discretization: steps per tooth period",
        .cli_name = "intervals"},
       nullptr,
       [](O& o) -> int& { return o.steps; }},
      {{.name = "degree",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 3.0,
        .help = "full-discretization: degree of the polynomial the delayed state is interpolated with"},
       nullptr,
       [](O& o) -> int& { return o.degree; }},
      {{.name = "max_depth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: 20 × the even tool's zero-order floor",
        .help = "depths searched up to this",
        .cli_name = "max-depth",
        .cli_unit = "mm",
        .cli_per_unit = 1e3},
       [](O& o) -> double& { return o.max_depth_m; }},
      {{.name = "depth_steps",
        .kind = FieldKind::Integer,
        .min = 4.0,
        .max = 10000.0,
        .help = "equal depth steps of the search, up to the deepest depth searched",
        .cli_name = "depth-steps"},
       nullptr,
       [](O& o) -> int& { return o.depth_steps; }},
  };
  return fields;
}

}  // namespace toolpoint
