// toolpoint: the finite-difference error of a tap test, on the model (studies/fd_correction.hpp).
#include "toolpoint/studies/fd_correction.hpp"

#include <algorithm>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

FiniteDifferenceError finite_difference_error(const Assembly& assembly, TapSide side, const std::vector<double>& frequency_hz,
                                              const PointFrfs& layout, const RotationalOptions& options) {
  options.check();
  if (frequency_hz.empty()) throw InvalidArgument("finite_difference_error: no frequencies");
  const AssemblyModel model(assembly);
  const int points = options.order + 1;
  std::vector<double> x;
  for (int i = 0; i < points; ++i) x.push_back(i * options.spacing);
  const double reach = side == TapSide::Tool ? assembly.tool.overhang : model.holder_chain().length();
  if (x.back() > reach)
    throw InvalidArgument(fmt::format("finite_difference_error: points {} m apart reach {} m from the tip, beyond the {} ({} m)",
                                      options.spacing, x.back(), side == TapSide::Tool ? "tool's overhang" : "holder", reach),
                          "check RotationalOptions::spacing (in metres)");
  // The model's FRFs in the measurement's slots.
  PointFrfs m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (layout.h[i][j] && i < points && j < points) m.set(i, j, FrfSeries{frequency_hz, {}}, layout.label(i, j) + " (model)");
  for (double f : frequency_hz) {
    const Eigen::MatrixXcd G = side == TapSide::Tool ? model.tool_stations(f, x) : model.holder_stations(f, x);
    for (int i = 0; i < points; ++i)
      for (int j = 0; j < points; ++j)
        if (m.h[i][j]) m.h[i][j]->values.push_back(G(2 * i, 2 * j));
  }
  const RotationalResult fd = rotational_frfs(m, options);
  FiniteDifferenceError r;
  r.exact = side == TapSide::Tool ? model.tool_point(frequency_hz) : model.holder_tip(frequency_hz);
  r.error.frequency_hz = frequency_hz;
  std::array<double, 4> emax{}, xmax{};
  for (std::size_t k = 0; k < frequency_hz.size(); ++k) {
    Block e = fd.block.blocks[k] - r.exact.blocks[k];
    e(0, 0) = 0.0;  // H00 is the measurement itself
    r.error.blocks.push_back(e);
    for (int q = 0; q < 4; ++q) {
      emax[static_cast<std::size_t>(q)] = std::max(emax[static_cast<std::size_t>(q)], std::abs(e(q / 2, q % 2)));
      xmax[static_cast<std::size_t>(q)] = std::max(xmax[static_cast<std::size_t>(q)], std::abs(r.exact.blocks[k](q / 2, q % 2)));
    }
  }
  for (int q = 0; q < 4; ++q)
    r.max_relative[static_cast<std::size_t>(q)] = xmax[static_cast<std::size_t>(q)] > 0.0
                                                      ? emax[static_cast<std::size_t>(q)] / xmax[static_cast<std::size_t>(q)]
                                                      : 0.0;
  r.warnings = fd.warnings;
  for (const auto& w : model.warnings()) r.warnings.push_back(w);
  return r;
}

BlockSeries remove_finite_difference_error(const BlockSeries& measured, const FiniteDifferenceError& error) {
  if (measured.frequency_hz != error.error.frequency_hz)
    throw InvalidArgument(fmt::format("remove_finite_difference_error: the measured block has {} frequencies, the error {} "
                                      "on another grid",
                                      measured.size(), error.error.size()),
                          "compute FiniteDifferenceError on the measurement's own frequencies");
  BlockSeries r = measured;
  for (std::size_t k = 0; k < r.size(); ++k) r.blocks[k] -= error.error.blocks[k];
  return r;
}

}  // namespace toolpoint
