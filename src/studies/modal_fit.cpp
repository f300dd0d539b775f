// toolpoint study: the modal fit and what it gives (studies/modal_fit.hpp).
#include "toolpoint/studies/modal_fit.hpp"

#include <cmath>
#include <fmt/format.h>

namespace toolpoint {

ModalFitStudy run_modal_fit_study(const FrfSeries& frf, const ModalFitOptions& options, const std::string& what) {
  ModalFitStudy r;
  r.fit = fit_modes(frf, options, what);
  r.fitted = r.fit.fitted_frf(frf.frequency_hz);
  for (const FittedMode& m : r.fit.modes)
    if (m.is_resonance()) r.model.push_back(m.mode);
  r.warnings = r.fit.warnings;
  return r;
}

plot::Figure modal_fit_figure(const FrfSeries& measured, const ModalFitResult& fit, const std::string& what) {
  plot::FrfFigureOptions po;
  po.title = fmt::format("Modal fit of {}: {} mode(s), residual {:.3g} %", plot::literal(what), fit.modes.size(),
                         100.0 * fit.normalised_residual);
  plot::Figure fig = plot::frf_figure({{measured, "measured", plot::CurveStyle::Points},
                                       {fit.fitted_frf(measured.frequency_hz), "fitted modal model", plot::CurveStyle::Line}},
                                      po);
  for (const FittedMode& m : fit.modes)
    fig.panels[0].labels.push_back({m.mode.frequency_hz, std::abs(fit.receptance(m.mode.frequency_hz)),
                                    fmt::format("{:.1f} Hz, ζ {:.3g}", m.mode.frequency_hz, m.mode.damping_ratio), true});
  return fig;
}

}  // namespace toolpoint
