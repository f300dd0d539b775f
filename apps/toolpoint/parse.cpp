// toolpoint CLI: text parsers for option values (parse.hpp).
#include "parse.hpp"

#include <charconv>
#include <fmt/format.h>
#include <vector>

#include "toolpoint/error.hpp"

namespace toolpoint::cli {

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

std::pair<int, int> parse_shard(const std::string& text, const std::string& option) {
  const std::size_t slash = text.find('/');
  int v[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const char* first = text.data() + (k == 0 ? 0 : slash + 1);
    const char* last = text.data() + (k == 0 ? slash : text.size());
    if (slash == std::string::npos) break;
    const auto [ptr, ec] = std::from_chars(first, last, v[k]);
    if (ec != std::errc() || ptr != last || first == last) {
      v[1] = 0;
      break;
    }
  }
  if (slash == std::string::npos || v[1] < 1 || v[1] > 100000 || v[0] < 0 || v[0] >= v[1])
    throw InvalidArgument(fmt::format("{} '{}' is not I/N with 0 ≤ I < N ≤ 100000 (shard I of N, counted from 0)", option, text),
                          "e.g. --shard 0/8 … --shard 7/8; in a Slurm array --shard $SLURM_ARRAY_TASK_ID/8");
  return {v[0], v[1]};
}

}  // namespace toolpoint::cli
