// Benchmarks of the time-domain milling simulation (simulation.hpp, studies/simulation.hpp). Aims:
// one mode, 100 revolutions, 2 teeth, a step of 1/200 tooth period, histories recorded ≤ 5 ms; a
// simulated stability map of the Insperger–Stépán benchmark, 200 speeds × 100 depths, ≤ 10 s on 2
// cores (real time).
// Run: build/toolpoint_bench --benchmark_filter=Simulation
#include <benchmark/benchmark.h>

#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/studies/simulation.hpp"

using namespace toolpoint;

namespace {

const Mode kBench{0.03993, 0.011, 922.0};  // docs/reference.md §7

ToolDynamics bench_dynamics() {
  ModalModel m;
  m.x = {kBench};
  return tool_dynamics(m);
}

}  // namespace

// The benchmark mode (rigid in y), 2 teeth, a/D 0.05 down-milling at 10 000 rpm and 2 mm (half the
// 4.09 mm limit), feed 0.1 mm: 100 revolutions of 400 steps. Argument: histories recorded (1) or not.
static void BM_Simulation_OneMode100Revolutions(benchmark::State& state) {
  SimulationOptions o;
  o.revolutions = 100;
  o.steps_per_tooth = 200;
  o.record = state.range(0) != 0;
  const MillingCut cut{10000.0, 2e-3, 1e-4, engagement_from_immersion(0.05, MillingDirection::Down)};
  const ToolDynamics d = bench_dynamics();
  const Cutter c = uniform_cutter(2, 0.02);
  const ForceLaw law{6e8, 1.0 / 3.0};
  for (auto _ : state) benchmark::DoNotOptimize(simulate_milling(d, c, law, cut, o).sle_m);
  state.counters["steps"] = 100.0 * 400.0;
}
BENCHMARK(BM_Simulation_OneMode100Revolutions)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The same in slotting (every step cuts).
static void BM_Simulation_OneMode100RevolutionsSlot(benchmark::State& state) {
  SimulationOptions o;
  o.revolutions = 100;
  o.steps_per_tooth = 200;
  const MillingCut cut{10000.0, 0.2e-3, 1e-4, engagement_from_immersion(1.0, MillingDirection::Down)};
  const ToolDynamics d = bench_dynamics();
  for (auto _ : state) benchmark::DoNotOptimize(simulate_milling(d, uniform_cutter(2, 0.02), {6e8, 1.0 / 3.0}, cut, o).sle_m);
}
BENCHMARK(BM_Simulation_OneMode100RevolutionsSlot)->Unit(benchmark::kMillisecond);

// 200 speeds (5000–25 000 rpm) × 100 depths (0.1–10 mm), a/D 0.05 down-milling, 40 revolutions per
// cell at the automatic step (40 per period of the mode, at least 40 per tooth period). Argument:
// threads.
static void BM_Simulation_Map200x100(benchmark::State& state) {
  SimulatedMapOptions o;
  o.cutter = uniform_cutter(2, 0.02);
  o.force = {6e8, 1.0 / 3.0};
  o.cut.feed_per_tooth_m = 1e-4;
  o.cut.engagement = engagement_from_immersion(0.05, MillingDirection::Down);
  o.speeds = {5000.0, 25000.0, 200};
  o.depths = {0.1e-3, 10e-3, 100};
  o.parallel.threads = static_cast<int>(state.range(0));
  const ToolDynamics d = bench_dynamics();
  for (auto _ : state) benchmark::DoNotOptimize(run_simulated_map(d, o).boundary.size());
}
BENCHMARK(BM_Simulation_Map200x100)->Arg(2)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
