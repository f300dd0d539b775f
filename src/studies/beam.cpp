// toolpoint study: one free–free Timoshenko segment — section, modes, receptance (studies/beam.hpp).
#include "toolpoint/studies/beam.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <string>
#include <utility>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/plausibility.hpp"

namespace toolpoint {

const char* beam_method_name(BeamMethod method) { return method == BeamMethod::Modal ? "modal" : "exact"; }

void BeamStudyOptions::check() const {
  check_fields(beam_study_fields(), *this, "BeamStudyOptions");
  if (inner_diameter >= outer_diameter)
    throw InvalidArgument(fmt::format("BeamStudyOptions::inner_diameter {} m must be below BeamStudyOptions::outer_diameter {} m",
                                      inner_diameter, outer_diameter),
                          "the inner diameter is the bore of a hollow section (0: solid)");
  if (shear_coefficient && !(std::isfinite(*shear_coefficient) && *shear_coefficient > 0.0))
    throw InvalidArgument(fmt::format("BeamStudyOptions::shear_coefficient {} must be > 0", *shear_coefficient),
                          "leave it unset for the shear model's value");
  for (double f : frequency_hz)
    if (!(std::isfinite(f) && f > 0.0))
      throw InvalidArgument(fmt::format("BeamStudyOptions::frequency_hz holds {} Hz; each frequency must be > 0", f),
                            "a free–free segment has rigid-body modes: its receptance is unbounded at 0 Hz");
  if (method == BeamMethod::Modal) modal.check();
  if (speed_rpm > 0.0 && method == BeamMethod::Modal)
    throw InvalidArgument("BeamStudyOptions::speed_rpm > 0 needs BeamStudyOptions::method exact",
                          "the whirls' receptances are exact only; a modal sum at speed is not provided");
  for (std::size_t k = 0; k < campbell_rpm.size(); ++k) {
    const double n = campbell_rpm[k];
    if (!(std::isfinite(n) && n >= 0.0) || (n > 0.0 && judge(plausible::kSpinSpeedRpm, n) == Plausibility::Impossible))
      throw InvalidArgument(fmt::format("BeamStudyOptions::campbell_rpm holds {}: each speed must be ≥ 0 rpm and plausible", n),
                            plausible::kSpinSpeedRpm.hint);
    if (k > 0 && !(n > campbell_rpm[k - 1]))
      throw InvalidArgument(
          fmt::format("BeamStudyOptions::campbell_rpm is not increasing at {} rpm after {} rpm", n, campbell_rpm[k - 1]));
  }
  if ((speed_rpm > 0.0 || !campbell_rpm.empty()) && modes < 1)
    throw InvalidArgument("BeamStudyOptions::modes must be ≥ 1 with a speed or a Campbell diagram",
                          "the whirls' natural frequencies listed");
}

const std::vector<OptionField<BeamStudyOptions>>& beam_study_fields() {
  using O = BeamStudyOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "length",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "the segment's length L (no default)",
        .cli_name = "length",
        .plausible = &plausible::kSegmentLength},
       [](O& o) -> double& { return o.length; }},
      {{.name = "outer_diameter",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "the outer diameter D (no default)",
        .cli_name = "diameter",
        .plausible = &plausible::kOuterDiameter},
       [](O& o) -> double& { return o.outer_diameter; }},
      {{.name = "inner_diameter",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: a solid section",
        .help = "the inner diameter d of a hollow section",
        .cli_name = "inner-diameter",
        .plausible = &plausible::kInnerDiameter},
       [](O& o) -> double& { return o.inner_diameter; }},
      {{.name = "modes",
        .kind = FieldKind::Integer,
        .min = 0.0,
        .max = 20000.0,
        .help = "free–free natural frequencies listed (with a speed or a Campbell diagram: of each whirl, ≥ 1)",
        .cli_name = "modes"},
       nullptr,
       [](O& o) -> int& { return o.modes; }},
      {{.name = "speed_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .note = "0: standing",
        .help = "spin about the axis: the natural frequencies of the forward and backward whirl, and the x–x block of "
                "the spinning segment (exact method only)",
        .cli_name = "speed",
        .plausible = &plausible::kSpinSpeedRpm},
       [](O& o) -> double& { return o.speed_rpm; }}};
  return fields;
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

  r.speed_rpm = options.speed_rpm;
  // The geometry and the speed judged as the flags and the files judge them: unusual, said.
  for (std::string& w : field_plausibility_warnings(beam_study_fields(), options, "BeamStudyOptions"))
    r.warnings.push_back(std::move(w));
  if (options.speed_rpm > 0.0) {
    r.whirl = whirl_frequencies(r.properties, options.length, rad_s_of_rpm(options.speed_rpm), options.modes);
  }
  for (double n : options.campbell_rpm)
    r.campbell.push_back(whirl_frequencies(r.properties, options.length, rad_s_of_rpm(n), options.modes));

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
  } else if (options.speed_rpm > 0.0) {
    const double spin = rad_s_of_rpm(options.speed_rpm);
    r.receptance = block_series(options.frequency_hz, [&](double f) -> Block {
      // The x–x part of two_plane(): (F + B)/2.
      return 0.5 * (end_block(whirl_receptance(r.properties, options.length, f, spin, Whirl::Forward), options.block) +
                    end_block(whirl_receptance(r.properties, options.length, f, spin, Whirl::Backward), options.block));
    });
  } else {
    r.receptance = exact_receptance(r.properties, options.length, options.frequency_hz, options.block);
  }
  return r;
}

plot::Figure campbell_figure(const BeamStudy& study, const std::string& title) {
  const std::vector<WhirlFrequencies>& c = study.campbell;
  if (c.size() < 2)
    throw InvalidArgument(fmt::format("campbell_figure: {} speed(s) in the study; at least 2 needed", c.size()),
                          "give BeamStudyOptions::campbell_rpm two or more speeds");
  plot::Figure fig;
  fig.title = title;
  fig.x.label = "Spindle speed [rpm]";
  plot::Panel p;
  p.legend = plot::Legend::Outside;
  p.y.label = "Natural frequency [Hz]";
  std::vector<double> rpm;
  for (const WhirlFrequencies& w : c) rpm.push_back(rpm_of_rad_s(w.spin_rad_s));
  const std::size_t modes = c.front().forward_hz.size();
  for (std::size_t m = 0; m < modes; ++m) {
    std::vector<double> fwd, bwd;
    for (const WhirlFrequencies& w : c) {
      fwd.push_back(w.forward_hz[m]);
      bwd.push_back(w.backward_hz[m]);
    }
    p.curves.push_back({rpm, fwd, fmt::format("mode {} forward", m + 1), plot::CurveStyle::Line, static_cast<int>(m)});
    p.curves.push_back({rpm, bwd, fmt::format("mode {} backward", m + 1), plot::CurveStyle::Dashed, static_cast<int>(m)});
  }
  std::vector<double> conical, once;
  for (std::size_t k = 0; k < c.size(); ++k) {
    conical.push_back(c[k].conical_hz);
    once.push_back(rpm[k] / 60.0);
  }
  p.curves.push_back({rpm, conical, "conical (forward)", plot::CurveStyle::LinePoints, static_cast<int>(modes)});
  p.curves.push_back({rpm, once, "once per revolution", plot::CurveStyle::Dashed, static_cast<int>(modes) + 1});
  fig.panels.push_back(std::move(p));
  return fig;
}

}  // namespace toolpoint
