// Speed of the assembly model (assembly and coupling modules) on the example assembly
// (examples/bt40_shrinkfit_16mm.toml: spindle cut at its four bearings, holder with the shank
// inside, tool; 15 segment pieces). Items are frequencies, swept over 10–5000 Hz. Target
// (issues): SHT11, all four entries, on 10 000 frequencies in ≤ 20 ms on one core, i.e.
// ≥ 5e5 frequencies/s; BM_Assembly/ExampleToolPointSHT11_10k reports the time of one such sweep.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/assembly_file.hpp"

using namespace toolpoint;

namespace {

const AssemblyModel& example_model() {
  static const AssemblyModel m(load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly);
  return m;
}

// `at` of the example model at n frequencies evenly spread over 10–5000 Hz, per iteration.
template <class R>
void BM_Assembly(benchmark::State& state, R (AssemblyModel::*at)(double) const, std::size_t n) {
  const AssemblyModel& m = example_model();
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = 10.0 + 4990.0 * static_cast<double>(i) / static_cast<double>(n - 1);
  for (auto _ : state)
    for (double x : f) benchmark::DoNotOptimize((m.*at)(x));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
}

// A whole grid through the sweep (AssemblyModel::tool_point/holder_tip of a vector: SIMD lanes).
void BM_Sweep(benchmark::State& state,
              BlockSeries (AssemblyModel::*sweep)(const std::vector<double>&, AssemblyModel::SweepDiagnostics*) const,
              std::size_t n) {
  const AssemblyModel& m = example_model();
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = 10.0 + 4990.0 * static_cast<double>(i) / static_cast<double>(n - 1);
  AssemblyModel::SweepDiagnostics d;
  for (auto _ : state) benchmark::DoNotOptimize((m.*sweep)(f, &d));
  state.counters["simd_share"] = static_cast<double>(d.simd) / static_cast<double>(n);  // 1: no frequency left the lanes
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
}

// The target's figure: one 10 000-frequency sweep of SHT11.
BENCHMARK_CAPTURE(BM_Sweep, ExampleToolPointSHT11_10k, &AssemblyModel::tool_point, 10000)->Unit(benchmark::kMillisecond);

// The tool point in two planes at 24 000 rpm (issue 28's aim: ≤ 4× ExampleToolPointSHT11_10k):
// isotropic bearings (the example: one sweep per whirl through the lanes), and the bearings made
// anisotropic (k_y = 0.7 k_x: the spindle walked in 4×4 in the whirl basis, through the lanes).
void BM_TwoPlane(benchmark::State& state, bool anisotropic) {
  Assembly a = example_model().assembly();
  if (anisotropic)
    for (Bearing& b : a.spindle.bearings) b.stiffness_y = 0.7 * b.stiffness;
  const AssemblyModel m(a);
  const std::size_t n = 10000;
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = 10.0 + 4990.0 * static_cast<double>(i) / static_cast<double>(n - 1);
  const double spin = 24000.0 * 2.0 * 3.141592653589793 / 60.0;
  for (auto _ : state) benchmark::DoNotOptimize(m.tool_point_two_plane(f, spin));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
}
BENCHMARK_CAPTURE(BM_TwoPlane, ExampleToolPointTwoPlane_10k, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TwoPlane, ExampleToolPointTwoPlaneAnisotropic_10k, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, ExampleHolderTipSH11_10k, &AssemblyModel::holder_tip, 10000)->Unit(benchmark::kMillisecond);
// The same one frequency at a time (the per-frequency functions, as evaluate() uses them).
BENCHMARK_CAPTURE(BM_Assembly, ExampleToolPointSHT11_10k_PerFrequency, &AssemblyModel::tool_point, 10000)
    ->Unit(benchmark::kMillisecond);
// Its parts, per frequency: the spindle's point sweep (9 pieces, 4 bearings), the holder and
// tool chains (4 and 2 pieces), SH11 (spindle + holder); and everything at once (S11, H, T, SH11,
// SHT11) as the identification's forward model uses it.
BENCHMARK_CAPTURE(BM_Assembly, ExampleSpindleNoseS11, &AssemblyModel::spindle_nose, 1000);
BENCHMARK_CAPTURE(BM_Assembly, ExampleHolderTwoPort, &AssemblyModel::holder, 1000);
BENCHMARK_CAPTURE(BM_Assembly, ExampleToolTwoPort, &AssemblyModel::tool, 1000);
BENCHMARK_CAPTURE(BM_Assembly, ExampleHolderTipSH11, &AssemblyModel::holder_tip, 1000);
BENCHMARK_CAPTURE(BM_Assembly, ExampleEvaluateAll, &AssemblyModel::evaluate, 1000);

}  // namespace
