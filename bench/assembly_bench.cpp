// Speed of the assembly model (assembly and coupling modules) on the example assembly
// (examples/bt40_shrinkfit_16mm.toml: spindle cut at four bearings, holder with the shank
// inside, tool; ~15 segment pieces). Items are frequencies. Target (issues): SHT11 (all four
// entries) on 10 000 frequencies in ≤ 20 ms on one core, i.e. ≥ 5e5 frequencies/s.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/assembly.hpp"
#include "toolpoint/assembly_file.hpp"

using namespace toolpoint;

namespace {

const AssemblyModel& example_model() {
  static const AssemblyModel m(load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly);
  return m;
}

std::vector<double> grid(std::size_t n) {
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = 10.0 + 4990.0 * static_cast<double>(i) / static_cast<double>(n - 1);
  return f;
}

// The whole sweep of the target: 10 000 frequencies, 10–5000 Hz; time per iteration is the
// figure to compare with 20 ms.
void BM_ExampleToolPointSweep10k(benchmark::State& state) {
  const AssemblyModel& m = example_model();
  const auto f = grid(10000);
  for (auto _ : state)
    for (double x : f) benchmark::DoNotOptimize(m.tool_point(x));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(f.size()));
}
BENCHMARK(BM_ExampleToolPointSweep10k)->Unit(benchmark::kMillisecond);

// The components on their own, per frequency.
void component(benchmark::State& state, int which) {
  const AssemblyModel& m = example_model();
  const auto f = grid(1000);
  for (auto _ : state)
    for (double x : f) {
      switch (which) {
        case 0: benchmark::DoNotOptimize(m.spindle_nose(x)); break;
        case 1: benchmark::DoNotOptimize(m.holder(x)); break;
        case 2: benchmark::DoNotOptimize(m.tool(x)); break;
        default: benchmark::DoNotOptimize(m.holder_tip(x)); break;
      }
    }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(f.size()));
}
void BM_ExampleSpindleNoseS11(benchmark::State& state) { component(state, 0); }
void BM_ExampleHolderTwoPort(benchmark::State& state) { component(state, 1); }
void BM_ExampleToolTwoPort(benchmark::State& state) { component(state, 2); }
void BM_ExampleHolderTipSH11(benchmark::State& state) { component(state, 3); }
BENCHMARK(BM_ExampleSpindleNoseS11);
BENCHMARK(BM_ExampleHolderTwoPort);
BENCHMARK(BM_ExampleToolTwoPort);
BENCHMARK(BM_ExampleHolderTipSH11);

// Everything at once (S11, H, T, SH11, SHT11), as `predict` and the identification use it.
void BM_ExampleEvaluateAll(benchmark::State& state) {
  const AssemblyModel& m = example_model();
  const auto f = grid(1000);
  for (auto _ : state)
    for (double x : f) benchmark::DoNotOptimize(m.evaluate(x));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(f.size()));
}
BENCHMARK(BM_ExampleEvaluateAll);

}  // namespace
