// libFuzzer target: FRF CSV in every dialect (separators, decimal comma, headers, units, value
// formats, coherence). The first byte picks the options a user could give (--format, --columns);
// the rest is the file. Only InputError and InvalidArgument may leave the reader; what it returns
// must be a usable series: sizes that agree, frequencies finite, positive and strictly
// increasing, values finite, a coherence per point in [0, 1]; and the units text it reports is
// safe to interpret.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_util.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"

using namespace toolpoint;
using fuzz::require;

namespace {

void require_grid(const std::vector<double>& f) {
  for (std::size_t i = 0; i < f.size(); ++i) require(std::isfinite(f[i]) && f[i] > 0.0 && (i == 0 || f[i] > f[i - 1]));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t pick = data[0];
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  FrfCsvOptions o;
  switch (pick % 7) {
    case 1: o.format = FrfValueFormat::ReIm; break;
    case 2: o.format = FrfValueFormat::MagPhaseDeg; break;
    case 3: o.format = FrfValueFormat::MagPhaseRad; break;
    case 4: o.format = FrfValueFormat::DbPhaseDeg; break;
    case 5: o.format = FrfValueFormat::DbPhaseRad; break;
    default: break;
  }
  switch ((pick / 7) % 4) {
    case 1: o.columns = {"1", "2", "3"}; break;
    case 2: o.columns = {"1", "3", "2", "4"}; break;
    case 3: o.columns = {"frequency_hz", "re", "im"}; break;
    default: break;
  }
  try {
    const FrfTable t = parse_frf_csv(text, "fuzz.csv", o);
    if (t.is_block) {
      require(t.block.frequency_hz.size() == t.block.blocks.size() && t.block.size() > 0);
      require_grid(t.block.frequency_hz);
      for (const Block& b : t.block.blocks) require(b.allFinite());
    } else {
      require(t.single.frequency_hz.size() == t.single.values.size() && t.single.size() > 0);
      require_grid(t.single.frequency_hz);
      for (const Complex& v : t.single.values) require(std::isfinite(v.real()) && std::isfinite(v.imag()));
    }
    const std::size_t n = t.is_block ? t.block.size() : t.single.size();
    require(t.coherence.empty() || t.coherence.size() == n);
    for (double g : t.coherence) require(g >= 0.0 && g <= 1.0);
    if (const auto u = parse_frf_units(t.value_units)) require(std::isfinite(u->to_si) && u->to_si > 0.0);
  } catch (const InputError&) {
  } catch (const InvalidArgument&) {}
  return 0;
}
