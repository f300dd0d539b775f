// Benchmarks of milling stability (stability module). Aims (one core unless stated): zero-order
// lobes, 50 lobes from a 10 000-point FRF, ≤ 5 ms; the Insperger–Stépán benchmark's ρ map (200
// speeds × 100 depths) ≤ 0.2 s and its boundary at 200 speeds ≤ 20 ms; the example assembly's
// boundary at 200 speeds ≤ 1 s (≤ 0.6 s on two threads).
// Run: build/toolpoint_bench --benchmark_filter=Stability
#include <benchmark/benchmark.h>

#include "example_modes.hpp"

#include "toolpoint/stability/stability.hpp"

using namespace toolpoint;

namespace {

const Mode kBench{0.03993, 0.011, 922.0};  // docs/reference.md §7

CuttingConditions benchmark_cut(double immersion) {
  return {2, 6e8, 2e8 / 6e8, engagement_from_immersion(immersion, MillingDirection::Down)};
}

std::vector<double> linear(double lo, double hi, int n) {
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = lo + (hi - lo) * i / (n - 1);
  return v;
}

}  // namespace

// 10 000-point FRF (symmetric 2-DOF tool, 100–5000 Hz), lobes k = 0…50, 2000-point envelope.
// Speeds: 5000–25 000 rpm (argument 0) or 500–30 000 rpm (1: every lobe falls in the range).
// Argument 2 = 1 also materialises every lobe point (vector<LobePoint>), as writing the CSV would.
static void BM_Stability_ZeroOrder50Lobes(benchmark::State& state) {
  const MillingFrfs frfs = modal_milling_frfs({kBench}, {kBench}, linear(100.0, 5000.0, 10000));
  ZeroOrderOptions o;
  o.lobes = 50;
  o.speeds = state.range(0) ? SpeedRange{500.0, 30000.0, 2000} : SpeedRange{5000.0, 25000.0, 2000};
  const CuttingConditions cut = benchmark_cut(0.05);
  std::size_t points = 0;
  for (auto _ : state) {
    const ZeroOrderResult r = zero_order_lobes(frfs, cut, o);
    if (state.range(1)) points = r.points().size();
    benchmark::DoNotOptimize(r.envelope.data());
  }
  state.counters["lobe_points"] = static_cast<double>(points);
}
BENCHMARK(BM_Stability_ZeroOrder50Lobes)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);

// The benchmark system (1-DOF in x, a/D = 0.05 down-milling): ρ on 200 speeds (5000–25 000 rpm)
// × 100 depths (0.1–10 mm), 40 steps per tooth period, one thread. Aim ≤ 0.2 s.
static void BM_Stability_FullDiscretizationGrid(benchmark::State& state) {
  const FullDiscretization fd(ModalModel{{kBench}, {}}, benchmark_cut(0.05), 40);
  const std::vector<double> speeds = linear(5000.0, 25000.0, 200), depths = linear(1e-4, 1e-2, 100);
  for (auto _ : state) {
    const Eigen::MatrixXd rho = fd.spectral_radius_map(speeds, depths, ParallelOptions{1});
    benchmark::DoNotOptimize(rho.data());
  }
}
BENCHMARK(BM_Stability_FullDiscretizationGrid)->Unit(benchmark::kMillisecond);

// What `toolpoint lobes --method fd` does for the benchmark: the boundary at 200 speeds with the
// default 1 % error target (two levels per speed, refined where needed), ceiling 10 mm; argument:
// threads. Aim ≤ 20 ms on one thread.
static void benchmark_boundary(benchmark::State& state, Discretization scheme) {
  BoundaryOptions o;
  o.speeds = {5000.0, 25000.0, 200};
  o.max_depth_m = 1e-2;
  o.scheme = scheme;
  if (scheme == Discretization::Semi) o.degree = 1;
  o.parallel.threads = static_cast<int>(state.range(0));
  long evaluations = 0;
  for (auto _ : state) {
    const BoundaryResult r = stability_boundary(ModalModel{{kBench}, {}}, benchmark_cut(0.05), o);
    evaluations = r.evaluations;
    benchmark::DoNotOptimize(r.boundary.data());
  }
  state.counters["evaluations"] = static_cast<double>(evaluations);
}
static void BM_Stability_Boundary(benchmark::State& state) { benchmark_boundary(state, Discretization::Full); }
BENCHMARK(BM_Stability_Boundary)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same by first-order semi-discretization (`lobes --method sd`): a matrix exponential per step
// in the cut per depth evaluated; argument: threads.
static void BM_Stability_SemiDiscretizationBoundary(benchmark::State& state) { benchmark_boundary(state, Discretization::Semi); }
BENCHMARK(BM_Stability_SemiDiscretizationBoundary)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The example assembly's case (issue 16's command): 4 modes per direction fitted to the example's
// tool point FRF (`toolpoint modes`), 4 teeth, K_t 6e8 N/m², K_r 0.3, a/D 0.5 down-milling,
// 200 speeds 2000–20 000 rpm, 1 % error target; argument: threads. Aim ≤ 1 s on one, ≤ 0.6 s on two.
// With `pitch_deg`, the same cutter at that pitch.
static void example_assembly_boundary(benchmark::State& state, const std::vector<double>& pitch_deg,
                                      const std::vector<double>& helix_deg = {}, Discretization scheme = Discretization::Full,
                                      int speeds = 200) {
  const std::vector<Mode> modes = bench::example_modes();
  CuttingConditions cut{4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  for (double p : pitch_deg) cut.pitch_rad.push_back(p * 3.14159265358979323846 / 180.0);
  for (double b : helix_deg) cut.helix_rad.push_back(b * 3.14159265358979323846 / 180.0);
  cut.diameter_m = 0.016;  // the example's 16 mm end mill (read only with a helix)
  BoundaryOptions o;
  o.speeds = {2000.0, 20000.0, speeds};
  o.scheme = scheme;
  if (scheme == Discretization::Semi) o.degree = 1;
  o.parallel.threads = static_cast<int>(state.range(0));
  long evaluations = 0;
  for (auto _ : state) {
    const BoundaryResult r = stability_boundary(ModalModel{modes, modes}, cut, o);
    evaluations = r.evaluations;
    benchmark::DoNotOptimize(r.boundary.data());
  }
  state.counters["evaluations"] = static_cast<double>(evaluations);
}
static void BM_Stability_ExampleAssemblyBoundary(benchmark::State& state) { example_assembly_boundary(state, {}); }
BENCHMARK(BM_Stability_ExampleAssemblyBoundary)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same case with a variable-pitch cutter, 70°/110°/70°/110° (issue 27's aim: ≤ 1 s on two
// threads): the map spans a revolution (4 tooth periods), one delay per pitch; argument: threads.
static void BM_Stability_ExampleAssemblyVariablePitchBoundary(benchmark::State& state) {
  example_assembly_boundary(state, {70.0, 110.0, 70.0, 110.0});
}
BENCHMARK(BM_Stability_ExampleAssemblyVariablePitchBoundary)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
// The same by first-order semi-discretization at 20 of the speeds (a 48 × 48 matrix exponential per
// step in the cut per depth: about two orders of magnitude slower than fd); argument: threads.
static void BM_Stability_ExampleAssemblyVariablePitchSemi20(benchmark::State& state) {
  example_assembly_boundary(state, {70.0, 110.0, 70.0, 110.0}, {}, Discretization::Semi, 20);
}
BENCHMARK(BM_Stability_ExampleAssemblyVariablePitchSemi20)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same case with a 30° helix (the map rebuilt at every depth the search evaluates; tooth
// period), and with a 30°/35° variable helix (a revolution, 8 axial slices, a delay per slice and
// tooth); argument: threads.
static void BM_Stability_ExampleAssemblyHelixBoundary(benchmark::State& state) { example_assembly_boundary(state, {}, {30.0}); }
BENCHMARK(BM_Stability_ExampleAssemblyHelixBoundary)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
static void BM_Stability_ExampleAssemblyVariableHelixBoundary(benchmark::State& state) {
  example_assembly_boundary(state, {}, {30.0, 35.0, 30.0, 35.0});
}
BENCHMARK(BM_Stability_ExampleAssemblyVariableHelixBoundary)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// One dominant multiplier of a large map: slotting (every step in the cut, no reduction), 2-DOF
// symmetric, 160 steps: a 340-state map, by restarted Arnoldi.
static void BM_Stability_DominantMultiplierSlot2Dof(benchmark::State& state) {
  const FullDiscretization fd(ModalModel{{kBench}, {kBench}}, benchmark_cut(1.0), 160);
  const PeriodMap map = fd.period_map(10000.0);
  for (auto _ : state) benchmark::DoNotOptimize(map.spectral_radius(1e-4));
}
BENCHMARK(BM_Stability_DominantMultiplierSlot2Dof)->Unit(benchmark::kMillisecond);
