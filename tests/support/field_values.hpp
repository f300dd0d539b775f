// Test support: another valid value of an option field (option_fields.hpp), for tests that check a
// surface carries every field of a table (a part file, a fingerprint).
#pragma once

#include <algorithm>
#include <cmath>

#include "toolpoint/option_fields.hpp"

namespace toolpoint::test {

// A value of the field valid by its own range and different from `current`: a flag toggled, an
// integer one up or down, a real moved by a hundredth of its range (or a tenth of itself where the range is
// unbounded); from an automatic value (outside the range), the range's lower end or middle; where
// those cannot be meant in the field's unit (FieldSpec::plausible), the usual range's lower end.
// NaN when none is found.
inline double other_valid_value(const FieldSpec& s, double current) {
  if (s.kind == FieldKind::Flag) return current != 0.0 ? 0.0 : 1.0;
  const bool bounded = std::isfinite(s.min) && std::isfinite(s.max);
  const double step = s.kind == FieldKind::Integer ? 1.0
                      : bounded                    ? 0.01 * (s.max - s.min)
                                                   : 0.1 * std::max(std::abs(current), 1e-3);
  const double middle = bounded ? (s.kind == FieldKind::Integer ? std::floor(0.5 * (s.min + s.max)) : 0.5 * (s.min + s.max))
                                : current + step;
  // check() refuses a nonzero value the field's unit cannot mean (spec.plausible): the usual range's
  // lower end is then a candidate too.
  const double usual = s.plausible ? s.plausible->low : std::nan("");
  for (double v : {current + step, current - step, s.min, middle, usual})
    if (v != current && std::isfinite(v) && field_value_valid(s, v) &&
        (!s.plausible || v == 0.0 || judge(*s.plausible, v) != Plausibility::Impossible))
      return v;
  return std::nan("");
}

}  // namespace toolpoint::test
