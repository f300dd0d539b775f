// The option-field tables of the modal fit and the studies that fit modes (issue 26), tested
// against an independent expectation (expected_fields.hpp's ExpectedField): each field written
// down here by hand from the hand-written checks before the tables — ModalFitOptions::check
// (max_modes 1…20, a prominence > 0, at least 10 evaluations), SimulationStudyOptions::check
// (fit_target in (0, 1)), LobesStudyOptions' max_modes and fit_target (the same ranges) — and the
// flags `toolpoint modes`, `lobes`, `pitch` and `simulate` had (`--fit-target` in %).
#pragma once

#include <limits>
#include <vector>

#include "support/expected_fields.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/pitch.hpp"
#include "toolpoint/studies/simulation.hpp"

namespace toolpoint::testing {

/// ModalFitOptions' scalar fields as ModalFitOptions::check had them and `toolpoint modes` its
/// flags (--max-modes, --min-prominence [dB]; residual_terms as --no-residuals, by hand).
inline std::vector<ExpectedField<ModalFitOptions>> modal_fit_expected_fields() {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  using M = ModalFitOptions;
  return {
      {"ModalFitOptions", "max_modes", true, 1.0, 20.0, false, false, 5.0, "--max-modes", "-", 1.0, "",
       TOOLPOINT_MEMBER(M, max_modes)},
      {"ModalFitOptions", "min_prominence_db", false, 0.0, kInf, true, false, 6.0, "--min-prominence", "dB", 1.0, "",
       TOOLPOINT_MEMBER(M, min_prominence_db)},
      {"ModalFitOptions", "residual_terms", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(M, residual_terms)},
      {"ModalFitOptions", "max_evaluations", true, 10.0, kInf, false, false, 500.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(M, max_evaluations)},
  };
}

/// A study's fit.max_modes and fit_target as the lobes study's (1…20; (0, 1), the CLI in %),
/// named `type::max_modes`, `type::fit_target`.
template <class Study>
std::vector<ExpectedField<Study>> fitted_modes_expected_fields(const std::string& type) {
  return {
      {type, "max_modes", true, 1.0, 20.0, false, false, 5.0, "--max-modes", "-", 1.0, "", TOOLPOINT_MEMBER(Study, fit.max_modes)},
      {type, "fit_target", false, 0.0, 1.0, true, true, 0.05, "--fit-target", "%", 100.0, "",
       TOOLPOINT_MEMBER(Study, fit_target)},
  };
}

}  // namespace toolpoint::testing
