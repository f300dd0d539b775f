// Speed of the closed-form joint identification (identify module, seed Eq. 6): identify_joint on
// precomputed 2×2 inputs (A = the example's tool T, B11 = SH11, G11 = SHT11 from the model, so
// every inversion is well-posed) plus parameters_from_stiffness, per frequency point, with and
// without the per-point diagnostics (condition numbers, noise gains). The model runs once,
// outside the timed loop. Target (issues): ≥ 1e7 points/s on one core for K, k and c.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/identify/identify.hpp"

using namespace toolpoint;

namespace {

struct Inputs {
  std::vector<double> f;
  std::vector<TwoPort> A;
  std::vector<Block> B11, G11;
};

const Inputs& example_inputs() {
  static const Inputs in = [] {
    const AssemblyModel m(load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly);
    Inputs r;
    for (int i = 0; i < 4096; ++i) {
      const double f = 10.0 + 4990.0 * i / 4095.0;
      const auto e = m.evaluate(f);
      r.f.push_back(f);
      r.A.push_back(e.T);
      r.B11.push_back(e.SH11);
      r.G11.push_back(e.SHT11);
    }
    return r;
  }();
  return in;
}

void BM_IdentifyJointPerPoint(benchmark::State& state) {
  const Inputs& in = example_inputs();
  const std::size_t n = in.f.size();
  const bool diagnostics = state.range(0) != 0;
  for (auto _ : state)
    for (std::size_t i = 0; i < n; ++i) {
      const JointEstimate e = identify_joint(in.A[i], in.B11[i], in.G11[i], diagnostics);
      benchmark::DoNotOptimize(e);
      benchmark::DoNotOptimize(parameters_from_stiffness(e.K, in.f[i]));
    }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
}
BENCHMARK(BM_IdentifyJointPerPoint)->ArgName("diagnostics")->Arg(0)->Arg(1);

}  // namespace
