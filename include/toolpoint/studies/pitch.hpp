// toolpoint study: the pitch choice (stability/pitch.hpp) from a tool point FRF or modes — the
// procedure behind `toolpoint pitch`, as one library call.
//
// In: the dynamics as for the lobes' time-domain method (LobesInput: modes given, or fitted to the
// FRF), the cut, the pitch search. Out: the chosen pattern against the evenly spaced tool at the
// target speed, the modal model used and its fits, every warning. Units: SI, radians, rpm, Hz.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/stability/pitch.hpp"
#include "toolpoint/studies/lobes.hpp"

namespace toolpoint {

struct PitchStudyOptions {
  CuttingConditions cutting;  // its pitch_rad empty: the pitch is chosen
  PitchChoiceOptions choice;
  // Modes fitted (no modes given): at most fit.max_modes per FRF, the fewest within fit_target (as
  // LobesStudyOptions).
  ModalFitOptions fit = [] {
    ModalFitOptions o;
    o.max_modes = 8;
    return o;
  }();
  double fit_target = 0.02;
  // Throws InvalidArgument naming the field: the choice's, the cut's and the fit's checks, then
  // pitch_study_fields' ranges.
  void check() const;
};

/// \brief PitchStudyOptions' own scalar fields defined once (option_fields.hpp): fit.max_modes and
/// fit_target, the lobes study's fields (fitted_modes_field: range, unit, help,
/// flag); check() derives from it, and `toolpoint pitch`'s `--max-modes` and `--fit-target` are the
/// lobes study's flags. The choice's fields: pitch_choice_fields (stability/pitch.hpp).
/// \return the table, in the order of the fields
const std::vector<OptionField<PitchStudyOptions>>& pitch_study_fields();

struct PitchStudyResult {
  PitchChoice choice;
  ModalModel modes;                   // the modal model used
  std::vector<ModalFitSummary> fits;  // one per fitted FRF
  std::vector<std::string> warnings;  // the fits' and the choice's
};

// The options checked, the modal model (time_domain_modes), then choose_pitch. Throws as those
// (InvalidArgument, InputError, NumericalError).
PitchStudyResult run_pitch_study(const LobesInput& input, const PitchStudyOptions& options);

}  // namespace toolpoint
