// Monte Carlo studies of the identification over noise seeds (issue 24): data made from a known
// joint with the noise models real tap tests have, identified as a user would (the identification
// study, the noise estimated from the data), and judged against the truth:
//   * false alarms: how often data made from the true joint get the verdict fail (aim ≤ 1 %);
//   * detection: how often data that cannot identify the joint are flagged (fail or doubtful, or
//     refused with an error; aim ≥ 95 %): SH11 given as SHT11, the model's tool 10 % too thin,
//     data in µm/N read as m/N; and the forward check given a joint from another assembly;
//   * coverage: how often each determined parameter's 95 % interval holds the truth (aim 90–98 %),
//     whether the median error lies inside the median half-width, and how many seeds leave a
//     parameter undetermined.
// The noise models: (a) the seed's multiplicative noise at 2 % and 5 %; (b) an additive floor at
// 1 % of each entry's peak plus 1 % multiplicative; (c) (a) at 2 % with a 2 % calibration error on
// each measured FRF, stated to the fit. On the example assembly (holder–tool, Eq. 6, SH11 and
// SHT11 measured) and on the second assembly's stiff spindle–holder joint (Eq. 15, SH11 measured,
// S11 from the model).
//
// The suite runs them short (TOOLPOINT_MC_SEEDS seeds, default 8; linearised intervals) and fails
// when a rate is clearly off; the README's table comes from the long run:
//   TOOLPOINT_MC_SEEDS=200 TOOLPOINT_MC_BOOTSTRAP=200 build/toolpoint_tests --gtest_filter='IdentificationMonteCarlo*'
// (TOOLPOINT_MC_BOOTSTRAP=0, the default here, gives linearised intervals; TOOLPOINT_MC_THREADS
// the threads over seeds; TOOLPOINT_MC_CASE="example, holder–tool (Table 1), Eq. 6, (b)" runs only
// the cases whose title contains the text.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <mutex>

#include "support/joint_data.hpp"
#include "support/test_util.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/identify/forward_check.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/statistics.hpp"
#include "toolpoint/studies/identification.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

Assembly second_assembly() {
  return load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/hsk63_hydraulic_12mm.toml").assembly;
}

enum class NoiseKind { Multiplicative, FloorAndMultiplicative };

struct Noise {
  std::string name;
  NoiseKind kind = NoiseKind::Multiplicative;
  double sigma = 0.02;       // multiplicative
  double floor = 0.0;        // of each entry's peak
  double calibration = 0.0;  // true σ of each measured FRF's factor, and stated to the fit
};

std::vector<Noise> noise_models() {
  return {{"(a) multiplicative 2 %", NoiseKind::Multiplicative, 0.02, 0.0, 0.0},
          {"(a) multiplicative 5 %", NoiseKind::Multiplicative, 0.05, 0.0, 0.0},
          {"(b) floor 1 % of the peak + 1 % multiplicative", NoiseKind::FloorAndMultiplicative, 0.01, 0.01, 0.0},
          {"(c) multiplicative 2 % + calibration 2 % stated", NoiseKind::Multiplicative, 0.02, 0.0, 0.02}};
}

// One measured series: the truth with the noise model drawn from `seed`.
BlockSeries measure(const BlockSeries& truth, const Noise& n, std::uint64_t seed) {
  BlockSeries out = n.kind == NoiseKind::Multiplicative
                        ? add_measurement_noise(truth, NoiseOptions{n.sigma, seed}).series
                        : draw_block_noise(truth, stated_block_noise(truth, StatedNoise{n.sigma, 0.0, n.floor}), seed);
  if (n.calibration > 0.0) {
    const double scale = 1.0 + n.calibration * calibration_normal(stream_seed(seed, 77));
    for (Block& b : out.blocks) b *= scale;
  }
  return out;
}

struct Setting {
  std::string name;
  Assembly assembly;  // makes the data and is identified with (unless a case changes it)
  Route route;
  std::vector<double> grid;
};

std::vector<Setting> settings() {
  Assembly a = example_assembly();
  Assembly b = second_assembly();
  return {{"example, holder–tool (Table 1), Eq. 6", a, Route::HolderTool, a.grid.values()},
          {"second assembly, stiff spindle–holder, Eq. 15", b, Route::SpindleHolderFromSH, b.grid.values()}};
}

IdentificationOptions options_for(Route route, const Noise& n, int bootstrap) {
  IdentificationOptions o;
  o.route = route;
  if (bootstrap > 0) {
    o.fit.bootstrap_samples = bootstrap;
  } else {
    o.fit.uncertainty = UncertaintyMethod::Linearised;
  }
  o.fit.parallel.threads = 1;  // the seeds run in parallel
  o.noise.calibration = n.calibration;
  return o;
}

struct Tally {
  int seeds = 0, pass = 0, doubtful = 0, fail = 0, refused = 0;
  std::array<int, 8> determined{}, covered{};
  std::array<std::vector<double>, 8> error, half_width;  // |estimate − truth| and the half-width, determined seeds
  std::vector<std::string> fail_reasons;
};

void count(Tally& t, const Identification& id, const JointParameters& truth) {
  ++t.seeds;
  switch (id.verdict.verdict) {
    case Verdict::Pass: ++t.pass; break;
    case Verdict::Doubtful: ++t.doubtful; break;
    case Verdict::Fail:
      ++t.fail;
      if (!id.verdict.reasons.empty()) t.fail_reasons.push_back(id.verdict.reasons.front());
      break;
  }
  if (!id.fit) return;
  for (std::size_t k = 0; k < 8; ++k) {
    const ParameterInterval& iv = id.fit->intervals[k];
    if (!iv.free || !iv.determined) continue;
    ++t.determined[k];
    t.covered[k] += iv.lower <= truth[static_cast<int>(k)] && truth[static_cast<int>(k)] <= iv.upper;
    t.error[k].push_back(std::abs(iv.estimate - truth[static_cast<int>(k)]));
    t.half_width[k].push_back(0.5 * (iv.upper - iv.lower));
  }
}

// Runs `seeds` identifications of data made by `make(seed)` and tallies them.
template <class Make>
Tally run(int seeds, const Assembly& model, const IdentificationOptions& o, const JointParameters& truth, Make make) {
  Tally t;
  std::mutex lock;
  ParallelOptions par;
  par.threads = env_int("TOOLPOINT_MC_THREADS", 0);
  std::vector<std::optional<Identification>> results(static_cast<std::size_t>(seeds));
  std::vector<char> refused(static_cast<std::size_t>(seeds), 0);
  parallel_for(static_cast<std::size_t>(seeds), par, [&](std::size_t s) {
    // The replicates' draws (the fit's bootstrap, the forward check's) are independent of the
    // data's noise and differ from one data set to the next, as for two users: with one seed for
    // every data set, the Monte Carlo error of the bias the replicates estimate is common to all
    // of them and does not average out (20 replicates: about 0.2 standard errors of k_yf under the
    // floor, all seeds shifted alike).
    IdentificationOptions os = o;
    os.fit.seed = 1000 + 7 * s;
    os.verdict.forward.seed = 1000 + 7 * s;
    try {
      results[s] = run_identification_study(model, {make(1000 + 7 * s)}, os);
    } catch (const Error&) {
      refused[s] = 1;
    }
  });
  for (std::size_t s = 0; s < results.size(); ++s) {
    if (refused[s]) {
      ++t.seeds;
      ++t.refused;
    } else {
      count(t, *results[s], truth);
    }
  }
  return t;
}

std::string table(const std::string& title, const Tally& t) {
  std::string s = fmt::format("{}: {} seeds — pass {}, doubtful {}, fail {}, refused {}\n", title, t.seeds, t.pass, t.doubtful,
                              t.fail, t.refused);
  for (std::size_t k = 0; k < 8; ++k) {
    if (JointParameters::row(static_cast<int>(k)) > JointParameters::column(static_cast<int>(k))) continue;  // k_tf, c_tf tied
    const int d = t.determined[k];
    s += fmt::format("  {:<5} determined {:3d}/{:<3d} covered {:5.1f} %  median error / median half-width {:.2f}\n",
                     JointParameters::name(static_cast<int>(k)), d, t.seeds - t.refused,
                     d ? 100.0 * t.covered[k] / d : std::nan(""),
                     d ? quantile(t.error[k], 0.5) / quantile(t.half_width[k], 0.5) : std::nan(""));
  }
  for (std::size_t i = 0; i < std::min<std::size_t>(3, t.fail_reasons.size()); ++i) s += "  fail: " + t.fail_reasons[i] + "\n";
  return s;
}

IdentificationData data_of(const BlockSeries& G, const std::optional<BlockSeries>& B) {
  IdentificationData d;
  d.G11 = G;
  d.g_name = "G11";
  if (B) {
    d.B11 = *B;
    d.b_name = "B11";
  }
  return d;
}

}  // namespace

// Data made from the true joint: the verdict's false alarms and the intervals' coverage. In the
// suite (8 seeds per case): no more than one fail per case (at a 1 % rate two or more happen with
// probability 0.3 %), and every determined stiffness covered in at least 5 of 8 seeds (at a 95 %
// coverage fewer happen with probability 0.06 %).
TEST(IdentificationMonteCarlo, FalseAlarmsAndCoverage) {
  const int seeds = env_int("TOOLPOINT_MC_SEEDS", 8), bootstrap = env_int("TOOLPOINT_MC_BOOTSTRAP", 0);
  const char* only = std::getenv("TOOLPOINT_MC_CASE");  // run only the cases whose title contains it
  for (const Setting& st : settings()) {
    const RouteData d = route_data(st.assembly, st.route, st.grid);
    for (const Noise& n : noise_models()) {
      if (only && fmt::format("{}, {}", st.name, n.name).find(only) == std::string::npos) continue;
      const Tally t = run(seeds, st.assembly, options_for(st.route, n, bootstrap), d.truth, [&](std::uint64_t seed) {
        return data_of(measure(d.G, n, seed), d.b_measured ? std::optional(measure(d.B, n, seed + 1)) : std::nullopt);
      });
      const std::string title = fmt::format("{}, {}", st.name, n.name);
      std::printf("%s", table(title, t).c_str());
      EXPECT_EQ(t.refused, 0) << title;
      EXPECT_LE(t.fail, std::max(1, static_cast<int>(std::ceil(0.03 * seeds)))) << table(title, t);
      for (std::size_t k : {std::size_t{0}, std::size_t{6}})
        if (t.determined[k] >= 8)
          EXPECT_GE(static_cast<double>(t.covered[k]) / t.determined[k], 0.6) << title << " " << JointParameters::name(static_cast<int>(k));
    }
  }
}

// Data that cannot identify the joint: flagged (fail or doubtful) or refused in at least 95 % of
// seeds (in the suite: every seed but at most one of 8).
TEST(IdentificationMonteCarlo, DetectsWhatIsWrong) {
  const int seeds = env_int("TOOLPOINT_MC_SEEDS", 8);
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, a.grid.values());
  const Noise n = noise_models()[0];  // 2 %
  const IdentificationOptions o = options_for(Route::HolderTool, n, 0);
  Assembly thin = a;
  thin.tool.diameter *= 0.9;
  thin.tool.shank_diameter *= 0.9;
  struct Wrong {
    std::string name;
    Assembly model;
    std::function<IdentificationData(std::uint64_t)> make;
  };
  const std::vector<Wrong> cases = {
      {"SH11 given as SHT11 (an independent measurement of SH11)", a,
       [&](std::uint64_t s) { return data_of(measure(d.B, n, s), measure(d.B, n, s + 1)); }},
      {"the model's tool 10 % thinner than the one measured", thin,
       [&](std::uint64_t s) { return data_of(measure(d.G, n, s), measure(d.B, n, s + 1)); }},
      {"data in µm/N read as m/N", a,
       [&](std::uint64_t s) {
         BlockSeries G = measure(d.G, n, s), B = measure(d.B, n, s + 1);
         for (Block& x : G.blocks) x *= 1e6;
         for (Block& x : B.blocks) x *= 1e6;
         return data_of(G, B);
       }},
  };
  for (const Wrong& w : cases) {
    const Tally t = run(seeds, w.model, o, d.truth, w.make);
    std::printf("%s", table(w.name, t).c_str());
    const int flagged = t.fail + t.doubtful + t.refused;
    EXPECT_GE(flagged, seeds - std::max(1, static_cast<int>(std::floor(0.05 * seeds)))) << table(w.name, t);
  }
}

// The forward check given a joint from another assembly (the second assembly's holder–tool joint)
// on the example's data: it fails in at least 95 % of seeds; given the true joint, it passes.
TEST(IdentificationMonteCarlo, ForwardCheckCatchesAJointFromAnotherAssembly) {
  const int seeds = env_int("TOOLPOINT_MC_SEEDS", 8);
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, a.grid.values());
  const JointParameters other = second_assembly().holder_tool.parameters;
  int failed = 0, true_failed = 0;
  for (int s = 0; s < seeds; ++s) {
    JointFitData x = noisy_fit_data(d, 0.02, 2000 + 7 * static_cast<std::uint64_t>(s));
    ForwardCheckOptions o;
    o.seed = static_cast<std::uint64_t>(s) + 1;
    failed += !check_forward(x, other, o).passed();
    true_failed += !check_forward(x, d.truth, o).passed();
  }
  std::printf("forward check, joint of another assembly: failed %d of %d; the true joint failed %d\n", failed, seeds, true_failed);
  EXPECT_GE(failed, seeds - std::max(1, static_cast<int>(std::floor(0.05 * seeds))));
  EXPECT_LE(true_failed, 1);
}
