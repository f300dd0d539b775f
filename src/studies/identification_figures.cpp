// toolpoint study: the identification's figure data — K(ω)'s curves with the identified values
// (studies/identification.hpp). Units: SI (JointParameters::unit); frequencies in Hz.
#include <fmt/format.h>

#include "toolpoint/studies/identification.hpp"

namespace toolpoint {

plot::JointParameterCurve joint_curve(const JointSeries& series, int row, int column,
                                      const std::optional<JointParameters>& reference,
                                      const std::optional<JointParameters>& identified, const JointFit* fit,
                                      const JointReadout* seed) {
  static const char* subscripts[2][2] = {{"yf", "ym"}, {"{/Symbol q}f", "{/Symbol q}m"}};
  const int stiffness = JointParameters::stiffness_of(row, column), damping = JointParameters::damping_of(row, column);
  plot::JointParameterCurve c;
  c.name = subscripts[row][column];
  c.stiffness_unit = JointParameters::unit(stiffness);
  c.damping_unit = JointParameters::unit(damping);
  for (const auto& p : series.parameters) {
    c.stiffness.push_back(p[stiffness]);
    c.damping.push_back(p[damping]);
  }
  if (reference) {
    c.reference_stiffness = (*reference)[stiffness];
    c.reference_damping = (*reference)[damping];
  }
  if (identified) {
    c.identified_stiffness = (*identified)[stiffness];
    c.identified_damping = (*identified)[damping];
  }
  const auto k = static_cast<std::size_t>(stiffness), d = static_cast<std::size_t>(damping);
  if (fit) {
    c.stiffness_interval = std::make_pair(fit->intervals[k].lower, fit->intervals[k].upper);
    c.damping_interval = std::make_pair(fit->intervals[d].lower, fit->intervals[d].upper);
    c.stiffness_undetermined = !fit->intervals[k].determined;
    c.damping_undetermined = !fit->intervals[d].determined;
  } else if (seed) {
    c.stiffness_undetermined = !seed->parameters[k].determined;
    c.damping_undetermined = !seed->parameters[d].determined;
  }
  return c;
}

plot::Figure identification_figure(const Identification& id) {
  plot::JointFigureData d;
  d.frequency_hz = id.closed_form.frequency_hz;
  if (id.seed.points > 0) d.band_hz = std::make_pair(id.seed.band_lo_hz, id.seed.band_hi_hz);
  d.title = fmt::format("{} joint, {}: closed form and {}", id.route == Route::HolderTool ? "Holder–tool" : "Spindle–holder",
                        to_string(id.route), id.fit ? "band fit (95 % interval)" : "seed read-out (shaded band)");
  for (int row = 0; row < 2; ++row)
    for (int column = 0; column < 2; ++column)
      d.parameters.push_back(joint_curve(id.closed_form, row, column, std::nullopt, id.identified, id.fit ? &*id.fit : nullptr,
                                         id.seed.points > 0 ? &id.seed : nullptr));
  return plot::joint_figure(d);
}

}  // namespace toolpoint
