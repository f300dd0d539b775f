// Speed of the band fit of joint constants (joint_fit module): the example's holder–tool joint
// from SH11 and SHT11 with the seed's 5 % noise at 5 000 frequencies (10–5000 Hz), six
// parameters, from the closed-form read-out's typical error (10 % in stiffness, 30 % in damping).
// Timed: one fit with linearised intervals (two weighted passes of Levenberg–Marquardt and the
// sandwich covariance) — the aim is ≤ 50 ms on one core; and one bootstrap replicate's
// worth of work, from 20 replicates on one thread. The noise estimate (from the data, once per
// series) is timed on its own. The model and the noisy data are made outside the timed loop.
// The richer noise (issue 24: aim within 2× of the fit on the seed's noise): data with an additive
// floor at 1 % of each entry's peak and 1 % hit-to-hit variation, the floor estimated beside the
// multiplicative noise, and a 2 % calibration stated (its factors in the covariance by the implicit
// function theorem); the noise estimate with its floor fit timed alone too.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/measured/signal.hpp"

using namespace toolpoint;

namespace {

struct Problem {
  JointFitData data;
  JointParameters start;
};

Problem make_problem(const NoiseOptions& sh, const NoiseOptions& sht, double calibration) {
  Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  const std::vector<double> f = FrequencyGrid{10.0, 5000.0, 4990.0 / 4999.0}.values();
  const AssemblyModel m(a);
  Problem r;
  for (double x : f) r.data.A.push_back(m.tool(x));
  r.data.B11 = add_measurement_noise(m.holder_tip(f), sh).series;
  r.data.G11 = add_measurement_noise(m.tool_point(f), sht).series;
  r.data.b_noise = estimate_block_noise(r.data.B11, {}, "SH11");
  r.data.g_noise = estimate_block_noise(r.data.G11, {}, "SHT11");
  r.data.b_noise.calibration = r.data.g_noise.calibration = calibration;
  r.start = a.holder_tool.parameters;
  for (int k = 0; k < 8; ++k) r.start[k] *= k % 2 ? 1.3 : 1.1;
  return r;
}

const Problem& floor_problem() {
  static const Problem p = make_problem(NoiseOptions{.sigma = 0.01, .seed = 1, .floor = 0.01, .calibration = 0.02},
                                        NoiseOptions{.sigma = 0.01, .seed = 2, .floor = 0.01, .calibration = 0.02}, 0.02);
  return p;
}

const Problem& example_problem() {
  static const Problem p = make_problem(NoiseOptions{0.05, 1}, NoiseOptions{0.05, 2}, 0.0);
  return p;
}

// The timed fit: linearised intervals (checked by 20 replicates unless `unchecked`), or a
// bootstrap of `bootstrap` replicates on one thread; the Levenberg–Marquardt iterations counted.
void time_fit(benchmark::State& state, const Problem& p, int bootstrap, bool unchecked = false) {
  JointFitOptions o;
  if (bootstrap == 0) o.uncertainty = UncertaintyMethod::Linearised;
  o.bootstrap_samples = bootstrap == 0 ? o.bootstrap_samples : bootstrap;
  o.parallel.threads = 1;
  o.check_linearisation = !unchecked;
  for (auto _ : state) {
    const JointFit r = fit_joint({p.data}, {p.start}, o);
    state.counters["iterations"] = r.iterations;
    benchmark::DoNotOptimize(r);
  }
}

void time_noise_estimate(benchmark::State& state, const Problem& p, bool floor) {
  NoiseEstimateOptions o;
  o.floor = floor;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_block_noise(p.data.G11, o, "SHT11"));
}

void BM_FitJoint_Linearised_5000(benchmark::State& state) { time_fit(state, example_problem(), 0); }
BENCHMARK(BM_FitJoint_Linearised_5000)->Unit(benchmark::kMillisecond);

// The fit alone, without the linearisation's check by 20 bootstrap replicates (B11 measured).
void BM_FitJoint_Linearised_5000_Unchecked(benchmark::State& state) { time_fit(state, example_problem(), 0, true); }
BENCHMARK(BM_FitJoint_Linearised_5000_Unchecked)->Unit(benchmark::kMillisecond);

void BM_FitJoint_Bootstrap20_OneThread_5000(benchmark::State& state) { time_fit(state, example_problem(), 20); }
BENCHMARK(BM_FitJoint_Bootstrap20_OneThread_5000)->Unit(benchmark::kMillisecond);

void BM_EstimateBlockNoise_5000(benchmark::State& state) { time_noise_estimate(state, example_problem(), true); }
BENCHMARK(BM_EstimateBlockNoise_5000)->Unit(benchmark::kMillisecond);

void BM_FitJoint_Linearised_5000_FloorAndCalibration(benchmark::State& state) {
  if (!floor_problem().data.g_noise.has_floor())
    state.SkipWithError("the floor was not kept by the estimate: not the case meant");
  time_fit(state, floor_problem(), 0);
}
BENCHMARK(BM_FitJoint_Linearised_5000_FloorAndCalibration)->Unit(benchmark::kMillisecond);

void BM_FitJoint_Linearised_5000_FloorAndCalibration_Unchecked(benchmark::State& state) {
  time_fit(state, floor_problem(), 0, true);
}
BENCHMARK(BM_FitJoint_Linearised_5000_FloorAndCalibration_Unchecked)->Unit(benchmark::kMillisecond);

void BM_FitJoint_Bootstrap20_OneThread_5000_FloorAndCalibration(benchmark::State& state) { time_fit(state, floor_problem(), 20); }
BENCHMARK(BM_FitJoint_Bootstrap20_OneThread_5000_FloorAndCalibration)->Unit(benchmark::kMillisecond);

void BM_EstimateBlockNoise_5000_Floor(benchmark::State& state) { time_noise_estimate(state, floor_problem(), true); }
BENCHMARK(BM_EstimateBlockNoise_5000_Floor)->Unit(benchmark::kMillisecond);

void BM_EstimateBlockNoise_5000_NoFloorModel(benchmark::State& state) { time_noise_estimate(state, example_problem(), false); }
BENCHMARK(BM_EstimateBlockNoise_5000_NoFloorModel)->Unit(benchmark::kMillisecond);

}  // namespace
