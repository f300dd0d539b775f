// The pitch choice study (studies/pitch.hpp).
#include "toolpoint/studies/pitch.hpp"

namespace toolpoint {

void PitchStudyOptions::check() const {
  choice.check();
  cutting.check();
  fit.check();
  check_fields(pitch_study_fields(), *this, "PitchStudyOptions");
}

const std::vector<OptionField<PitchStudyOptions>>& pitch_study_fields() {
  using O = PitchStudyOptions;
  static const std::vector<OptionField<O>> fields = {{fitted_modes_field("max_modes"), nullptr,
                                                      [](O& o) -> int& { return o.fit.max_modes; }},
                                                     {fitted_modes_field("fit_target"),
                                                      [](O& o) -> double& { return o.fit_target; }}};
  return fields;
}

PitchStudyResult run_pitch_study(const LobesInput& input, const PitchStudyOptions& options) {
  options.check();
  PitchStudyResult res;
  res.modes = time_domain_modes(input, options.fit, options.fit_target, res.fits, res.warnings);
  res.choice = choose_pitch(res.modes, options.cutting, options.choice);
  res.warnings.insert(res.warnings.end(), res.choice.warnings.begin(), res.choice.warnings.end());
  return res;
}

}  // namespace toolpoint
