// toolpoint study: the modal fit (modal_fit.hpp) and what it gives.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/plot/plot.hpp"

namespace toolpoint {

// The procedure behind `toolpoint modes`, as one library call: fit_modes, the fitted receptance on
// the measured grid of the band (ModalFitResult::fitted_frf), and the modal model of the fitted
// modes that are resonances (FittedMode::is_resonance), which the stability lobes take.
struct ModalFitStudy {
  ModalFitResult fit;
  FrfSeries fitted;                   // the fitted receptance [m/N], residual terms included, at the band's measured frequencies
  std::vector<Mode> model;            // the fitted modes that are resonances (is_resonance), ascending; the others left out
  std::vector<std::string> warnings;  // the fit's (a non-resonance among them: fit_modes warns of a non-positive residue)
};

// Runs fit_modes(frf, options, what) and the above. Throws as fit_modes.
ModalFitStudy run_modal_fit_study(const FrfSeries& frf, const ModalFitOptions& options = {}, const std::string& what = "FRF");

// The fit's figure: `measured` (points) and fit.fitted_frf on its grid (line), |H| [m/N] and phase
// [deg] over frequency [Hz], each fitted mode labelled on the fitted curve with its frequency [Hz]
// and damping ratio; the title names `what` (a file name, printed verbatim).
plot::Figure modal_fit_figure(const FrfSeries& measured, const ModalFitResult& fit, const std::string& what);

}  // namespace toolpoint
