// Speed of the UFF reader and writer on real files (tests/data/uff) and a large written FRF.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "toolpoint/io/uff.hpp"

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

// ---- Listing large files: headers only (what `toolpoint convert FILE --list` does) ----------------
//
// Generated once into TOOLPOINT_BENCH_DIR (default /tmp) and kept for later runs: about 1 GB of
// complex-double FRF datasets of 100 000 points each, binary 58b (671 datasets of 1.6 MB) and ASCII
// 58 (266 datasets of 4 MB, written by format_uff). The figures are for a file in the page cache;
// from a cold disk add its read time (binary data are skipped by size, but their line breaks are
// still counted, at memory speed, so that messages can give line numbers).
namespace {

std::string bench_path(const std::string& name) {
  const char* dir = std::getenv("TOOLPOINT_BENCH_DIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/" + name;
}

// A file of `copies` copies of one dataset, about `bytes` in all, written once.
std::string large_file(const std::string& name, bool binary, std::size_t bytes) {
  const std::string path = bench_path(name);
  std::ifstream probe(path, std::ios::binary | std::ios::ate);
  if (probe && static_cast<std::size_t>(probe.tellg()) >= bytes) return path;
  UffDataset58 d = large_frf(100000);
  d.even = true;
  d.abscissa_min = 0.5;
  d.abscissa_increment = 0.375;
  for (std::size_t i = 0; i < d.x.size(); ++i) d.x[i] = 0.5 + 0.375 * static_cast<double>(i);
  const std::string one = format_uff({d}, {.binary = binary}).bytes;
  std::ofstream out(path, std::ios::binary);
  for (std::size_t written = 0; written < bytes; written += one.size()) out << one;
  return path;
}

void list_large(benchmark::State& state, bool binary) {
  const std::string path = large_file(binary ? "toolpoint_bench_1GB_58b.uff" : "toolpoint_bench_1GB_58.uff", binary,
                                      std::size_t{1} << 30);
  std::size_t datasets = 0;
  for (auto _ : state) {
    const UffFile f = read_uff(path, {.headers_only = true});
    datasets = f.functions.size();
    benchmark::DoNotOptimize(datasets);
  }
  state.counters["datasets"] = static_cast<double>(datasets);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(in.tellg()));
}

// Linear in the number of datasets: the fuzz finding was 200 000 empty datasets (4.2 MB) taking
// 23–27 s to list, quadratic. Google Benchmark fits the complexity.
void list_empty_datasets(benchmark::State& state) {
  std::string bytes;
  for (int64_t i = 0; i < state.range(0); ++i) bytes += "    -1\n    58\n    -1\n";
  for (auto _ : state) benchmark::DoNotOptimize(parse_uff(bytes, "empty.uff", {.headers_only = true}));
  state.SetComplexityN(state.range(0));
}

}  // namespace

BENCHMARK_CAPTURE(list_large, binary_58b_1GB, true)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(list_large, ascii_58_1GB, false)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(list_empty_datasets)->RangeMultiplier(4)->Range(12500, 200000)->Unit(benchmark::kMillisecond)->Complexity();
