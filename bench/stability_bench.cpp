// Benchmarks of milling stability (stability module). Aims (one core): zero-order lobes, 50 lobes
// from a 10 000-point FRF, ≤ 5 ms; semi-discretization of the Insperger–Stépán benchmark on a
// 200 speed × 100 depth grid with 40 intervals, ≤ 1 s.
// Run: build/toolpoint_bench --benchmark_filter=Stability
#include <benchmark/benchmark.h>

#include "toolpoint/stability.hpp"

using namespace toolpoint;

namespace {

const Mode kBench{0.03993, 0.011, 922.0};  // NOTES §7

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
// × 100 depths (0.1–10 mm), 40 intervals per tooth period.
static void BM_Stability_SemiDiscretizationGrid(benchmark::State& state) {
  const SemiDiscretization sd(ModalModel{{kBench}, {}}, benchmark_cut(0.05), 40);
  const std::vector<double> speeds = linear(5000.0, 25000.0, 200), depths = linear(1e-4, 1e-2, 100);
  for (auto _ : state) {
    const Eigen::MatrixXd rho = sd.spectral_radius_map(speeds, depths);
    benchmark::DoNotOptimize(rho.data());
  }
}
BENCHMARK(BM_Stability_SemiDiscretizationGrid)->Unit(benchmark::kMillisecond);

// What `toolpoint lobes --method sd` does for the benchmark: the boundary at 200 speeds by scan
// (50 steps to 10 mm) and bisection to 1e-4.
static void BM_Stability_SemiDiscretizationBoundary(benchmark::State& state) {
  SemiDiscretizationOptions o;
  o.speeds = {5000.0, 25000.0, 200};
  o.max_depth_m = 1e-2;
  for (auto _ : state) {
    const SemiDiscretizationResult r = semi_discretization_boundary(ModalModel{{kBench}, {}}, benchmark_cut(0.05), o);
    benchmark::DoNotOptimize(r.boundary.data());
  }
}
BENCHMARK(BM_Stability_SemiDiscretizationBoundary)->Unit(benchmark::kMillisecond);

// The expensive case: slotting (every interval in the cut, no reduction), 2-DOF symmetric:
// a 84 × 84 monodromy matrix per point; 20 speeds × 10 depths.
static void BM_Stability_SemiDiscretizationSlot2Dof(benchmark::State& state) {
  const SemiDiscretization sd(ModalModel{{kBench}, {kBench}}, benchmark_cut(1.0), 40);
  const std::vector<double> speeds = linear(5000.0, 25000.0, 20), depths = linear(1e-5, 1e-4, 10);
  for (auto _ : state) {
    const Eigen::MatrixXd rho = sd.spectral_radius_map(speeds, depths);
    benchmark::DoNotOptimize(rho.data());
  }
}
BENCHMARK(BM_Stability_SemiDiscretizationSlot2Dof)->Unit(benchmark::kMillisecond);
