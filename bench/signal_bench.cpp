// Benchmarks of the signal module: Savitzky–Golay on a measured-size block series (8 real
// columns), noise, and finite-difference rotational FRFs. Sizes: frequency points.
#include <benchmark/benchmark.h>

#include "toolpoint/measured/signal.hpp"

using namespace toolpoint;

namespace {

BlockSeries block_series(std::size_t n) {
  BlockSeries b;
  const auto z = standard_normals(8 * n, 3);
  for (std::size_t i = 0; i < n; ++i) {
    b.frequency_hz.push_back(1.0 + 0.5 * static_cast<double>(i));
    b.blocks.push_back(make_block({z[8 * i], z[8 * i + 1]}, {z[8 * i + 2], z[8 * i + 3]}, {z[8 * i + 4], z[8 * i + 5]},
                                  {z[8 * i + 6], z[8 * i + 7]}));
  }
  return b;
}

void BM_SavgolBlock(benchmark::State& state) {
  const BlockSeries b = block_series(static_cast<std::size_t>(state.range(0)));
  const SavgolOptions o{static_cast<int>(state.range(1)), 3};
  for (auto _ : state) benchmark::DoNotOptimize(savgol_filter(b, o));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SavgolBlock)->Args({10000, 11})->Args({10000, 51})->Args({100000, 11});

void BM_NoiseBlock(benchmark::State& state) {
  const BlockSeries b = block_series(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(add_measurement_noise(b, {0.05, 1}));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_NoiseBlock)->Arg(10000);

void BM_RotationalSecondOrder(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  PointFrfs p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.set(i, j, entry(block_series(n), (i + j) % 4));
  for (auto _ : state) benchmark::DoNotOptimize(rotational_frfs(p, {2, 0.01, false, PMethod::Auto}));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_RotationalSecondOrder)->Arg(10000);

}  // namespace
