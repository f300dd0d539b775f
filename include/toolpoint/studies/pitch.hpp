// toolpoint study: the pitch choice (stability/pitch.hpp) from a tool point FRF or modes — the
// procedure behind `toolpoint pitch`, as one library call.
//
// In: the dynamics as for the lobes' time-domain method (LobesInput: modes given, or fitted to the
// FRF), the cut, the pitch search. Out: the chosen pattern against the evenly spaced tool at the
// target speed, the modal model used and its fits, every warning. Units: SI, radians, rpm, Hz.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/option_fields.hpp"
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
};

struct PitchStudyResult {
  PitchChoice choice;
  ModalModel modes;                   // the modal model used
  std::vector<ModalFitSummary> fits;  // one per fitted FRF
  std::vector<std::string> warnings;  // the fits' and the choice's
};

// The modal model (time_domain_modes), then choose_pitch. Throws as those (InvalidArgument,
// InputError, NumericalError).
PitchStudyResult run_pitch_study(const LobesInput& input, const PitchStudyOptions& options);

/// \brief PitchChoiceOptions' numeric fields, defined once (option_fields.hpp): their units,
/// ranges and help and the `toolpoint pitch` flags derive from it (the pattern and parallel have
/// their own definitions; PitchChoiceOptions::check is written by hand, with the same ranges:
/// tests/option_fields_test.cpp holds both to one expectation).
/// \return the table, in the order of the fields
const std::vector<OptionField<PitchChoiceOptions>>& pitch_choice_fields();

}  // namespace toolpoint
