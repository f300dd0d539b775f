// Speed of the plan study (studies/plan.hpp) at issue 17's scale: the example assembly
// (examples/bt40_shrinkfit_16mm.toml), 100 overhangs (40–89.5 mm every 0.5 mm) × 2000 spindle
// speeds (2000–20 000 rpm), zero-order lobes, 4 teeth, half immersion down-milling, safety factor
// 1.25. Per overhang: the model's tool point FRF on the assembly's 1 Hz grid refined where its
// phase turns more than 0.25° per step (about 9 000 frequencies), the lobes and their envelope, the
// MRR and the best speed. The Arg is the thread count; real time is the figure that counts (CPU
// time sums the threads). Aim: ≤ 2 s on 2 cores.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/studies/plan.hpp"

using namespace toolpoint;

namespace {

void BM_Plan_Example100x2000(benchmark::State& state) {
  PlanCandidate c;
  c.name = "example";
  c.assembly = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  for (int i = 0; i < 100; ++i) c.overhangs_m.push_back(0.040 + 0.0005 * i);
  PlanOptions o;
  o.lobes.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.lobes.speeds = {2000.0, 20000.0, 2000};
  o.feed_per_tooth_m = 1e-4;
  o.safety.factor = 1.25;
  o.parallel.threads = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(run_plan({c}, o));
  state.SetItemsProcessed(state.iterations() * 100);
}
BENCHMARK(BM_Plan_Example100x2000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
