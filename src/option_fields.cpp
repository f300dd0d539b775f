// One definition per option field (option_fields.hpp): the checks and texts every surface shares.
#include "toolpoint/option_fields.hpp"

#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

std::string field_flag(const FieldSpec& s) { return s.cli_name ? fmt::format("--{}", s.cli_name) : std::string(); }

bool field_value_valid(const FieldSpec& s, double v) {
  if (!std::isnan(s.automatic) && v == s.automatic) return true;
  if (!std::isfinite(v)) return false;
  if (s.kind == FieldKind::Flag) return v == 0.0 || v == 1.0;
  if (s.kind == FieldKind::Integer && v != std::floor(v)) return false;
  const bool above = s.min_open ? v > s.min : v >= s.min;
  const bool below = s.max_open ? v < s.max : v <= s.max;
  return above && below;
}

std::string field_value_text(const FieldSpec& s, double v) {
  // An integer in full: {:g} would show 1000001 as 1e+06.
  if (s.kind == FieldKind::Integer && std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15)
    return fmt::format("{}", static_cast<long long>(v));
  return fmt::format("{:g}", v);
}

std::string field_range_text(const FieldSpec& s, double scale) {
  const std::string lo = field_value_text(s, s.min * scale), hi = field_value_text(s, s.max * scale);
  if (!std::isfinite(s.max)) return fmt::format("{} {}", s.min_open ? ">" : "≥", lo);
  if (s.min_open || s.max_open) return fmt::format("{}{}, {}{}", s.min_open ? "(" : "[", lo, hi, s.max_open ? ")" : "]");
  return fmt::format("{}…{}", lo, hi);
}

std::string field_range_value(const FieldSpec& s, double scale) {
  return fmt::format("{}{}", std::isfinite(s.max) ? "in " : "", field_range_text(s, scale));
}

std::string field_range_phrase(const FieldSpec& s, double scale) {
  return fmt::format("must {} {}", std::isfinite(s.max) ? "lie in" : "be", field_range_text(s, scale));
}

Plausibility field_plausibility(const FieldSpec& s, double v) {
  if (!s.plausible || v == 0.0 || v == s.automatic || !field_value_valid(s, v)) return Plausibility::Usual;
  return judge(*s.plausible, v);
}

void check_field(const FieldSpec& s, double v, std::string_view options) {
  if (field_value_valid(s, v)) {
    // The range says what the library can compute with; the plausible range what a user can mean.
    if (field_plausibility(s, v) == Plausibility::Impossible)
      throw InvalidArgument(plausibility_message(*s.plausible, v, fmt::format("{}::{}", options, s.name)), s.plausible->hint);
    return;
  }
  const std::string unit = *s.unit ? fmt::format(" {}", s.unit) : std::string(),
                    note = *s.note ? fmt::format(" ({})", s.note) : std::string();
  throw InvalidArgument(fmt::format("{}::{} {}{} {}{}", options, s.name, field_value_text(s, v), unit, field_range_phrase(s), note),
                        fmt::format("give {}::{} a value {}{}{} ({})", options, s.name, field_range_value(s), unit, note, s.help));
}

}  // namespace toolpoint
