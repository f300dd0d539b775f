// toolpoint study: one free–free Timoshenko segment — section, modes, receptance (studies/beam.hpp).
#include "toolpoint/studies/beam.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

const char* beam_method_name(BeamMethod method) { return method == BeamMethod::Modal ? "modal" : "exact"; }

void BeamStudyOptions::check() const {
  // ModalBeam's own limit (ModalOptions::check), said here under this option's name.
  if (modes < 0 || modes > 20000)
    throw InvalidArgument(fmt::format("BeamStudyOptions::modes {} must lie in 0..20000", modes),
                          "the number of free–free natural frequencies to list");
  if (shear_coefficient && !(std::isfinite(*shear_coefficient) && *shear_coefficient > 0.0))
    throw InvalidArgument(fmt::format("BeamStudyOptions::shear_coefficient {} must be > 0", *shear_coefficient),
                          "leave it unset for the shear model's value");
  for (double f : frequency_hz)
    if (!(std::isfinite(f) && f > 0.0))
      throw InvalidArgument(fmt::format("BeamStudyOptions::frequency_hz holds {} Hz; each frequency must be > 0", f),
                            "a free–free segment has rigid-body modes: its receptance is unbounded at 0 Hz");
  if (method == BeamMethod::Modal) modal.check();
}

BeamStudy run_beam_study(const BeamStudyOptions& options) {
  options.check();
  BeamStudy r;
  r.segment = Segment::tube(options.length, options.outer_diameter, options.inner_diameter, options.material);
  r.segment.shear_model = options.shear_model;
  r.segment.layers[0].shear_coefficient = options.shear_coefficient;
  r.segment.check();
  r.properties = r.segment.properties();
  const Annulus& a = r.segment.layers[0];
  // One layer: the section's κ is the layer's override or the shear model's value for this annulus
  // (what Segment::properties() used).
  r.section = {a.area(),
               a.second_moment(),
               a.shear_coefficient.value_or(shear_coefficient(options.shear_model, options.material.poisson,
                                                              options.outer_diameter, options.inner_diameter)),
               r.properties.rhoA,
               r.properties.rhoI,
               r.properties.cutoff_frequency_hz()};

  // The modes as ModalBeam finds them (the exact frequency equation on both branches), with their
  // mass-normalised end values (undamped frequencies).
  if (options.modes > 0) r.modes = ModalBeam(r.properties, options.length, ModalOptions{options.modes, false}).modes();

  const bool modal = options.method == BeamMethod::Modal;
  r.method = modal ? fmt::format("modal ({} modes{})", options.modal.modes,
                                 options.modal.static_residual ? " + static residual" : "")
                   : std::string("exact");
  if (options.frequency_hz.empty()) return r;
  if (modal) {
    const ModalBeam beam(r.properties, options.length, options.modal);
    r.receptance = beam.receptance(options.frequency_hz, options.block);
    // A modal sum is truncated: above its highest mode it misses the resonances of the modes left
    // out (their static part only, with the residual), so the receptance there is not the segment's.
    const double top = beam.modes().back().frequency_hz;
    const double highest = *std::max_element(options.frequency_hz.begin(), options.frequency_hz.end());
    if (highest > top)
      r.warnings.push_back(fmt::format(
          "the modal receptance reaches {} Hz, above the highest of the BeamStudyOptions::modal.modes {} modes summed "
          "({:.6g} Hz): there it lacks the modes left out",
          highest, options.modal.modes, top));
  } else {
    r.receptance = exact_receptance(r.properties, options.length, options.frequency_hz, options.block);
  }
  return r;
}

}  // namespace toolpoint
