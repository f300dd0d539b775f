// Speed of the segment receptances (beam module), items = segment-frequency evaluations: the
// exact closed form (section_waves + the length-dependent part, as one exact_receptance call) on
// a 70/25 mm steel shaft, 0.2 m, η = 0.01, over 10–5000 Hz, and on a 16 mm carbide tool piece
// across its shear cut-off (0.9–1.1 f_c, where one wavenumber passes through zero); and the
// modal sum (seed Eq. 11–14) per frequency with 100 and 300 modes, the modes computed once
// outside the timed loop. Target (issues): exact ≥ 2e6 evaluations/s on one core.
#include <benchmark/benchmark.h>

#include <vector>

#include "toolpoint/model/beam.hpp"

using namespace toolpoint;

namespace {

Material steel() {
  Material m;
  m.name = "steel";
  m.youngs_modulus = 2.05e11;
  m.poisson = 0.29;
  m.density = 7800.0;
  m.loss_factor = 0.01;
  return m;
}

std::vector<double> grid(double lo, double hi, std::size_t n) {
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1);
  return f;
}

const Segment kShaft = Segment::tube(0.2, 0.070, 0.025, steel(), "shaft");

void BM_ExactSegmentReceptance(benchmark::State& state) {
  const SectionProperties p = kShaft.properties();
  const auto f = grid(10.0, 5000.0, 1000);
  for (auto _ : state)
    for (double x : f) benchmark::DoNotOptimize(exact_receptance(p, kShaft.length, x));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(f.size()));
}
BENCHMARK(BM_ExactSegmentReceptance);

void BM_ExactSegmentReceptanceNearCutoff(benchmark::State& state) {
  Material carbide = steel();
  carbide.youngs_modulus = 5.8e11;
  carbide.poisson = 0.22;
  carbide.density = 14500.0;
  carbide.loss_factor = 0.002;
  const Segment s = Segment::tube(0.03, 0.016, 0.0, carbide, "tool");
  const SectionProperties p = s.properties();
  const double fc = p.cutoff_frequency_hz();
  const auto f = grid(0.9 * fc, 1.1 * fc, 1000);
  for (auto _ : state)
    for (double x : f) benchmark::DoNotOptimize(exact_receptance(p, s.length, x));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(f.size()));
}
BENCHMARK(BM_ExactSegmentReceptanceNearCutoff);

void BM_ModalSegmentReceptance(benchmark::State& state) {
  const ModalBeam beam(kShaft.properties(), kShaft.length, ModalOptions{static_cast<int>(state.range(0)), false});
  const auto f = grid(10.0, 5000.0, 1000);
  for (auto _ : state)
    for (double x : f) benchmark::DoNotOptimize(beam.receptance(x));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(f.size()));
  state.counters["modes"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_ModalSegmentReceptance)->Arg(100)->Arg(300);

}  // namespace
