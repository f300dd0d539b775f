// Speed of the UFF reader and writer on real files (tests/data/uff) and a large written FRF.
#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>

#include "toolpoint/uff.hpp"

using namespace toolpoint;

namespace {

std::string load(const char* name) {
  std::ifstream in(std::string(TOOLPOINT_SOURCE_DIR) + "/tests/data/uff/" + name, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void parse_file(benchmark::State& state, const char* name) {
  const std::string bytes = load(name);
  for (auto _ : state) benchmark::DoNotOptimize(parse_uff(bytes, name));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(bytes.size()));
}

UffDataset58 large_frf(std::size_t n) {
  UffDataset58 d;
  d.ordinate_data_type = 6;
  d.even = false;
  for (std::size_t i = 0; i < n; ++i) {
    d.x.push_back(0.5 + 0.37 * static_cast<double>(i));
    d.y.emplace_back(1e-6 / (1.0 + static_cast<double>(i)), -2e-7 * static_cast<double>(i % 17));
  }
  return d;
}

void format_frf(benchmark::State& state) {
  const UffDataset58 d = large_frf(100000);
  UffWriteOptions o;
  o.binary = state.range(0) != 0;
  for (auto _ : state) benchmark::DoNotOptimize(format_uff({d}, o));
}

}  // namespace

BENCHMARK_CAPTURE(parse_file, ascii_79k_real_single, "Sample_UFF58_ascii.uff")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(parse_file, binary_79k_real_single, "Sample_UFF58b_bin.uff")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(parse_file, binary_4x222k, "mpstd_58b_wrong_byte_count.uff")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(parse_file, nx_182_other_datasets, "nx_simulation_mixed_datasets.uff")->Unit(benchmark::kMillisecond);
BENCHMARK(format_frf)->Arg(0)->Arg(1)->ArgName("binary")->Unit(benchmark::kMillisecond);
