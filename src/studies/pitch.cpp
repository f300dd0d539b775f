// The pitch choice study (studies/pitch.hpp).
#include "toolpoint/studies/pitch.hpp"

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

}  // namespace toolpoint
