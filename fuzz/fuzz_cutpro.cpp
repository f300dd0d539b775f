// libFuzzer target: the CutPro .frf reader. Only InputError may leave it; what it returns is a
// usable series, and writing it and reading it back gives the same numbers bit for bit.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz_util.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"

using namespace toolpoint;
using fuzz::require;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  FrfText t;
  try {
    t = parse_cutpro_frf(text, "fuzz.frf");
  } catch (const InputError&) {
    return 0;
  }
  const FrfSeries& s = t.series;
  require(s.frequency_hz.size() == s.values.size() && s.size() > 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    require(std::isfinite(s.frequency_hz[i]) && s.frequency_hz[i] > 0.0 && (i == 0 || s.frequency_hz[i] > s.frequency_hz[i - 1]));
    require(std::isfinite(s.values[i].real()) && std::isfinite(s.values[i].imag()));
  }
  const FrfText again = parse_cutpro_frf(format_cutpro_frf(s), "again.frf");
  require(again.series.frequency_hz == s.frequency_hz && again.series.values == s.values);
  return 0;
}
