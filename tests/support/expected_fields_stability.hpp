// The option-field tables of the modal fit and the studies that fit modes (issue 26), tested
// against an independent expectation (expected_fields.hpp's ExpectedField): each field written
// down here by hand from the hand-written checks before the tables — ModalFitOptions::check
// (max_modes 1…20, a prominence > 0, at least 10 evaluations), SimulationStudyOptions::check
// (fit_target in (0, 1)), LobesStudyOptions' max_modes and fit_target (the same ranges) — and the
// flags `toolpoint modes`, `lobes`, `pitch` and `simulate` had (`--fit-target` in %); and
// CaseStudyOptions::check (noise_sigma in [0, 1), band_width in (0, 0.5); `toolpoint demo
// --sigma`, `--width`) and PrecisionOptions::check (confidence in (0.5, 1)).
#pragma once

#include <limits>
#include <vector>

#include "support/expected_fields.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/studies/pitch.hpp"
#include "toolpoint/studies/precision.hpp"
#include "toolpoint/studies/simulation.hpp"

namespace toolpoint::testing {

/// ModalFitOptions' scalar fields as ModalFitOptions::check had them and `toolpoint modes` its
/// flags (--max-modes, --min-prominence [dB]; residual_terms as --no-residuals, by hand).
inline std::vector<ExpectedField<ModalFitOptions>> modal_fit_expected_fields() {
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
      {type, "max_modes", true, 1.0, 20.0, false, false, 5.0, "--max-modes", "-", 1.0, "",
       TOOLPOINT_MEMBER(Study, fit.max_modes)},
      {type, "fit_target", false, 0.0, 1.0, true, true, 0.05, "--fit-target", "%", 100.0, "",
       TOOLPOINT_MEMBER(Study, fit_target)},
  };
}

/// CaseStudyOptions' scalar fields as CaseStudyOptions::check had them and `toolpoint demo` its
/// flags (apply_filter and fit: either value; `--no-fit` sets fit by hand).
inline std::vector<ExpectedField<CaseStudyOptions>> case_study_expected_fields() {
  using C = CaseStudyOptions;
  return {
      {"CaseStudyOptions", "noise_sigma", false, 0.0, 1.0, false, true, 0.03, "--sigma", "-", 1.0, "",
       TOOLPOINT_MEMBER(C, noise_sigma)},
      {"CaseStudyOptions", "apply_filter", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(C, apply_filter)},
      {"CaseStudyOptions", "band_width", false, 0.0, 0.5, true, true, 0.03, "--width", "-", 1.0, "",
       TOOLPOINT_MEMBER(C, band_width)},
      {"CaseStudyOptions", "fit", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "", TOOLPOINT_MEMBER(C, fit)},
  };
}

/// PrecisionOptions' own scalar fields as PrecisionOptions::check had them (no flags: `toolpoint
/// precision --parameters 6|8` sets reciprocal by hand).
inline std::vector<ExpectedField<PrecisionOptions>> precision_expected_fields() {
  using P = PrecisionOptions;
  return {
      {"PrecisionOptions", "reciprocal", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "", TOOLPOINT_MEMBER(P, reciprocal)},
      {"PrecisionOptions", "confidence", false, 0.5, 1.0, true, true, 0.9, "", "", 1.0, "", TOOLPOINT_MEMBER(P, confidence)},
  };
}

}  // namespace toolpoint::testing
