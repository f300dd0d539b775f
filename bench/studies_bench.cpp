// Speed of the studies (include/toolpoint/studies/) on the example assembly
// (examples/bt40_shrinkfit_16mm.toml). The overhang study couples the model's tool to a measured
// SH11 (here the model's, 10–5000 Hz every 1 Hz: 4991 frequencies) for 11 overhangs, 40–60 mm;
// items are overhangs. Run with threads 1 and 2 (the Arg) to see the parallel speed-up; real time
// is the figure that counts (CPU time sums the threads).
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"

using namespace toolpoint;

namespace {

const Assembly& example() {
  static const Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  return a;
}

void BM_OverhangStudy(benchmark::State& state) {
  PredictOptions holder;
  holder.receptance = PredictedFrf::HolderTip;
  const BlockSeries sh = run_prediction(example(), holder).frf;
  OverhangStudyOptions o;
  for (int k = 0; k <= 10; ++k) o.overhangs_m.push_back(0.040 + 0.002 * k);
  o.threads = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(run_overhang_study(example(), sh, o));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(o.overhangs_m.size()));
}
BENCHMARK(BM_OverhangStudy)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The prediction study: SHT11 on the example's grid (4991 frequencies) and its modes refined on
// the model.
void BM_PredictionStudy(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(run_prediction(example()));
}
BENCHMARK(BM_PredictionStudy)->Unit(benchmark::kMillisecond);

}  // namespace
