// toolpoint: frequency grids.
#include "toolpoint/conventions.hpp"

#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

void FrequencyGrid::check() const {
  if (!std::isfinite(start_hz) || !std::isfinite(stop_hz) || !std::isfinite(step_hz))
    throw InvalidArgument(fmt::format("frequency grid {}:{}:{} Hz is not finite", start_hz, stop_hz, step_hz));
  if (!(start_hz > 0.0))
    throw InvalidArgument(fmt::format("frequency grid start {} Hz must be > 0", start_hz),
                          "free–free and assembly receptances are unbounded at 0 Hz; start at e.g. 1 Hz");
  if (!(stop_hz >= start_hz))
    throw InvalidArgument(fmt::format("frequency grid stop {} Hz is below start {} Hz", stop_hz, start_hz));
  if (!(step_hz > 0.0)) throw InvalidArgument(fmt::format("frequency grid step {} Hz must be > 0", step_hz));
  // Grids are compared to 1e-9 relative (require_same_grid): a finer step would make neighbours equal there,
  // and below double resolution (2.2e-16 relative) the written frequencies repeat.
  if (stop_hz > start_hz && step_hz < 1e-9 * stop_hz)
    throw InvalidArgument(fmt::format("frequency grid step {:g} Hz is below the resolution of frequencies near {:g} Hz "
                                      "(1e-9 relative, {:g} Hz): the frequencies would repeat or be indistinguishable",
                                      step_hz, stop_hz, 1e-9 * stop_hz),
                          "give a step of at least a millionth of a hertz per kHz, e.g. 0.01 Hz");
  if ((stop_hz - start_hz) / step_hz > 1e7)
    throw InvalidArgument(fmt::format("frequency grid {}:{}:{} Hz has more than 10 million points", start_hz, stop_hz, step_hz));
}

std::vector<double> FrequencyGrid::values() const {
  check();
  const auto n = static_cast<std::size_t>(std::floor((stop_hz - start_hz) / step_hz * (1.0 + 1e-12) + 1e-9)) + 1;
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = start_hz + static_cast<double>(i) * step_hz;
  return f;
}

}  // namespace toolpoint
