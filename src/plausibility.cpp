// toolpoint: plausible magnitudes of physical inputs (plausibility.hpp).
#include "toolpoint/plausibility.hpp"

#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

Plausibility judge(const PlausibleRange& r, double value) {
  if (!std::isfinite(value)) return Plausibility::Impossible;
  const double v = std::abs(value);
  if (v >= r.low && v <= r.high) return Plausibility::Usual;
  if (v > r.high * r.slack || (r.low > 0.0 && v < r.low / r.slack)) return Plausibility::Impossible;
  return Plausibility::Unusual;
}

std::string plausibility_message(const PlausibleRange& r, double value, const std::string& what) {
  const bool impossible = judge(r, value) == Plausibility::Impossible;
  return fmt::format("{} = {:g} {} the usual range [{:g}, {:g}]{}{}", what, value,
                     impossible ? "is so far outside" : "is outside", r.low, r.high, impossible ? " that it cannot be meant" : "",
                     *r.hint ? fmt::format("; {}", r.hint) : "");
}

std::string require_plausible(const PlausibleRange& range, double value, const std::string& what, const std::string& fix) {
  switch (judge(range, value)) {
    case Plausibility::Usual: return {};
    case Plausibility::Unusual: return plausibility_message(range, value, what);
    case Plausibility::Impossible: break;
  }
  throw InvalidArgument(plausibility_message(range, value, what), fix);
}

}  // namespace toolpoint
