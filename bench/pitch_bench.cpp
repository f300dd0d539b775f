// Benchmark of the pitch choice (stability/pitch.hpp): the example assembly's 4 modes per direction
// (as stability_bench.cpp's example), K_t 6e8 N/m², K_r 0.3, a/D 0.5 down-milling, at 5000 rpm with
// the default search: an alternating pitch for 4 teeth (≈ 80 limits at fixed steps), and a
// three-angle pitch for 6 teeth (P₀/P₁/P₂ twice: the 11 × 11 grid of (u, v) and the pattern search,
// a few hundred limits); argument: threads. No aim set by the issue; a command-line answer should
// take seconds, not minutes.
// Run: build/toolpoint_bench --benchmark_filter=Pitch
#include <benchmark/benchmark.h>

#include "example_modes.hpp"

#include "toolpoint/stability/pitch.hpp"

using namespace toolpoint;

namespace {

void choose_on_example_assembly(benchmark::State& state, int teeth, PitchPattern pattern) {
  const std::vector<Mode> modes = bench::example_modes();
  const CuttingConditions cut{teeth, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  PitchChoiceOptions o;
  o.speed_rpm = 5000.0;
  o.pattern = pattern;
  o.parallel.threads = static_cast<int>(state.range(0));
  long evaluations = 0;
  for (auto _ : state) {
    const PitchChoice r = choose_pitch(ModalModel{modes, modes}, cut, o);
    evaluations = r.evaluations;
    benchmark::DoNotOptimize(r.pitch_rad.data());
  }
  state.counters["limits"] = static_cast<double>(evaluations);
}

}  // namespace

static void BM_Pitch_ChooseExampleAssembly(benchmark::State& state) {
  choose_on_example_assembly(state, 4, PitchPattern::Alternating);
}
BENCHMARK(BM_Pitch_ChooseExampleAssembly)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_Pitch_ChooseThreeAngleExampleAssembly(benchmark::State& state) {
  choose_on_example_assembly(state, 6, PitchPattern::ThreeAngle);
}
BENCHMARK(BM_Pitch_ChooseThreeAngleExampleAssembly)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
