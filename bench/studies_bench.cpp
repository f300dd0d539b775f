// Speed of the studies (include/toolpoint/studies/) on the example assembly
// (examples/bt40_shrinkfit_16mm.toml). The overhang study couples the model's tool to a measured
// SH11 (here the model's, 10–5000 Hz every 1 Hz: 4991 frequencies) for 11 overhangs, 40–60 mm;
// items are overhangs. Run with threads 1 and 2 (the Arg) to see the parallel speed-up; real time
// is the figure that counts (CPU time sums the threads).
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/studies/lobes.hpp"
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
  const BlockSeries sh = run_prediction_study(example(), holder).frf;
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
  for (auto _ : state) benchmark::DoNotOptimize(run_prediction_study(example()));
}
BENCHMARK(BM_PredictionStudy)->Unit(benchmark::kMillisecond);

// Lobes at speed (issue 28): the example's zero-order lobes at 50 speeds, 5000–30 000 rpm, 4 teeth,
// half immersion, with the x–y tool point FRF at each speed: the spindle spinning (SpeedModel::
// Spinning), the FRF on the file's grid (4991 frequencies) at the default 17 nodes and their 16
// midpoints, the lobes from all 33 and from the 17 (the error estimate). Arg 0: isotropic bearings
// (one lane sweep per whirl); Arg 1: the front bearings 30 % softer in y, the rear ones with a speed
// table (the spindle in 4×4: the whirl-basis lanes). Range(1): threads.
void BM_LobesAtSpeed(benchmark::State& state) {
  LobesInput in;
  in.assembly = example();
  if (state.range(0) == 1) {
    // Tables and y values do not mix on one bearing (Bearing::check): the front pair softer in y,
    // the rear pair softening with speed.
    std::vector<Bearing>& b = in.assembly->spindle.bearings;
    for (int k : {0, 1}) b[k].stiffness_y = 0.7 * b[k].stiffness;
    for (int k : {2, 3}) b[k].speed_table = {{0.0, b[k].stiffness, b[k].damping}, {30000.0, 0.7 * b[k].stiffness, b[k].damping}};
  }
  LobesStudyOptions o;
  o.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.speeds = {5000.0, 30000.0, 50};
  o.speed_model = SpeedModel::Spinning;
  o.parallel.threads = static_cast<int>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(run_lobes_study(in, o));
}
BENCHMARK(BM_LobesAtSpeed)->Args({0, 1})->Args({0, 2})->Args({1, 1})->Args({1, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
