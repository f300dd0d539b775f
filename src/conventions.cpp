// toolpoint: frequency grids and range parsing.
#include "toolpoint/conventions.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

double parse_number(const std::string& text, const std::string& option, const std::string& whole) {
  double v = 0.0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  while (first < last && *first == ' ') ++first;
  while (last > first && last[-1] == ' ') --last;
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || first == last)
    throw InvalidArgument(fmt::format("{}: '{}' in '{}' is not a number", option, text, whole));
  return v;
}

std::vector<std::string> split_colon(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    std::size_t pos = text.find(':', start);
    parts.push_back(text.substr(start, pos - start));
    if (pos == std::string::npos) break;
    start = pos + 1;
  }
  return parts;
}

}  // namespace

void FrequencyGrid::check() const {
  if (!std::isfinite(start_hz) || !std::isfinite(stop_hz) || !std::isfinite(step_hz))
    throw InvalidArgument(fmt::format("frequency grid {}:{}:{} Hz is not finite", start_hz, stop_hz, step_hz));
  if (!(start_hz > 0.0))
    throw InvalidArgument(fmt::format("frequency grid start {} Hz must be > 0", start_hz),
                          "free–free and assembly receptances are unbounded at 0 Hz; start at e.g. 1 Hz");
  if (!(stop_hz >= start_hz))
    throw InvalidArgument(fmt::format("frequency grid stop {} Hz is below start {} Hz", stop_hz, start_hz));
  if (!(step_hz > 0.0)) throw InvalidArgument(fmt::format("frequency grid step {} Hz must be > 0", step_hz));
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

FrequencyGrid parse_frequency_grid(const std::string& text, const std::string& option) {
  const auto parts = split_colon(text);
  if (parts.size() != 3)
    throw InvalidArgument(fmt::format("{}: '{}' is not START:STOP:STEP (Hz)", option, text), "e.g. 10:5000:2.5");
  FrequencyGrid g{parse_number(parts[0], option, text), parse_number(parts[1], option, text),
                  parse_number(parts[2], option, text)};
  try {
    g.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("{}: {}", option, e.what()), e.hint());
  }
  return g;
}

std::pair<double, double> parse_range(const std::string& text, const std::string& option) {
  const auto parts = split_colon(text);
  if (parts.size() != 2) throw InvalidArgument(fmt::format("{}: '{}' is not A:B", option, text));
  return {parse_number(parts[0], option, text), parse_number(parts[1], option, text)};
}

}  // namespace toolpoint
