// Tests of the band fit of joint constants (joint_fit module), each against something the
// estimator does not compute itself: the joint put into the model (noise-free exactness, Monte
// Carlo over noise seeds for bias and the coverage of the intervals), the closed form's known bias,
// two set-ups with different joints, and bad input.
//
// Coverage studies: the suite runs short ones (fixed seeds, so the result is reproducible); the
// docs/identification.md's figures come from the same tests run long:
//   TOOLPOINT_COVERAGE_SEEDS=400 TOOLPOINT_COVERAGE_BOOTSTRAP=200 build/toolpoint_tests --gtest_filter='JointFitCoverage*'
#include <gtest/gtest.h>

#include <cstdlib>
#include <fmt/format.h>

#include "support/joint_data.hpp"
#include "support/test_util.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/identify/joint_fit.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

std::vector<double> grid(double step) { return FrequencyGrid{10.0, 5000.0, step}.values(); }

JointFitOptions linearised() {
  JointFitOptions o;
  o.uncertainty = UncertaintyMethod::Linearised;
  return o;
}

// |estimate − truth| against the truth, or for a zero truth against its natural scale (10 % of
// √|k_yf k_θm| for a coupling stiffness, likewise for a damping).
double relative_error(const JointParameters& got, const JointParameters& truth, int k) {
  double scale = std::abs(truth[k]);
  if (scale == 0.0) scale = 0.1 * std::sqrt(std::abs(k % 2 ? truth.c_yf * truth.c_tm : truth.k_yf * truth.k_tm));
  return std::abs(got[k] - truth[k]) / scale;
}

}  // namespace

// Noise-free data from the model give the joint back: the seed's Table 1 (Eq. 6), the example's
// spindle–holder joint (Eq. 15 and 18) and the stiff one, six and eight parameters, from starts
// 10–30 % off. Tolerance 1e-8 relative (issue 11); the fit stops within 1e-3 of a standard error of
// the 1e-6 relative weight floor, ~1e-9.
TEST(JointFit, NoiseFreeDataGiveTheJointBack) {
  const std::vector<double> f = grid(5.0);
  Assembly stiff = example_assembly();
  stiff.spindle_holder = Joint::make_elastic(stiff_spindle_holder());
  struct Case {
    const char* name;
    Assembly a;
    Route route;
  };
  const Case cases[] = {{"Eq. 6, Table 1", example_assembly(), Route::HolderTool},
                        {"Eq. 15, example", example_assembly(), Route::SpindleHolderFromSH},
                        {"Eq. 18, example", example_assembly(), Route::SpindleHolderFromSHT},
                        {"Eq. 15, stiff", stiff, Route::SpindleHolderFromSH}};
  for (const Case& c : cases)
    for (bool reciprocal : {true, false}) {
      const RouteData d = route_data(c.a, c.route, f);
      JointFitOptions o = linearised();
      o.reciprocal = reciprocal;
      const JointFit r = fit_joint({noisy_fit_data(d, 0.0, 0)}, {offset_start(d.truth)}, o);
      EXPECT_TRUE(r.converged) << c.name;
      for (int k = 0; k < 8; ++k)
        EXPECT_LT(relative_error(r.parameters, d.truth, k), 1e-8)
            << c.name << (reciprocal ? " 6" : " 8") << " " << JointParameters::name(k);
      EXPECT_TRUE(std::isnan(r.residual_ratio)) << "exact data have no noise to compare the residual with";
    }
}

// The demo's 5 % case fitted (raw data, 1 Hz, noise estimated from the data, bootstrap): the aims
// of issue 11 — every stiffness within 1 % of Table 1, c_θm within 3 %, c_ym within 10 %, c_yf
// determined and within its interval or undetermined with an interval holding 54 N s/m. Observed
// (seed 1): stiffnesses within 0.15 %, c_θm 0.1 %, c_ym 0.2 %, c_yf 1 % with a 2 % standard error.
TEST(JointFit, TheSeedsFivePercentCaseMeetsTheAims) {
  const RouteData d = route_data(example_assembly(), Route::HolderTool, grid(1.0));
  JointFitOptions o;
  o.bootstrap_samples = 100;
  const JointFit r = fit_joint({noisy_fit_data(d, 0.05, 1)}, {offset_start(d.truth)}, o);
  for (int k : {0, 2, 4, 6}) EXPECT_LT(relative_error(r.parameters, d.truth, k), 0.01) << JointParameters::name(k);
  EXPECT_LT(relative_error(r.parameters, d.truth, 7), 0.03);
  EXPECT_LT(relative_error(r.parameters, d.truth, 3), 0.10);
  EXPECT_LT(relative_error(r.parameters, d.truth, 5), 0.10);
  const ParameterInterval& cyf = r.intervals[1];
  EXPECT_TRUE(cyf.lower <= 54.0 && 54.0 <= cyf.upper) << cyf.lower << " … " << cyf.upper;
  EXPECT_NEAR(r.residual_ratio, 1.0, 0.1) << "the model and the estimated noise explain the data";
  EXPECT_EQ(r.bootstrap_samples, 100);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  // k_θf, c_θf are not free in the six-parameter fit: equal to k_ym, c_ym, perfectly correlated.
  EXPECT_FALSE(r.intervals[4].free);
  EXPECT_EQ(r.parameters.k_tf, r.parameters.k_ym);
  EXPECT_NEAR(r.correlation()(2, 4), 1.0, 1e-12);
}

// The case where the seed's read-out is known to be biased: a stiff spindle–holder joint, Eq. 15,
// 2 % noise. The closed form read at the mode effect analysis picks is off by tens of % in k_yf
// (observed −45 % over 20 seeds; consistent, not scatter: −26 % at 0.5 % noise) while the band fit
// lands within its interval and within 0.2 %.
TEST(JointFit, RemovesTheClosedFormsBiasOnAStiffJoint) {
  Assembly a = example_assembly();
  a.spindle_holder = Joint::make_elastic(stiff_spindle_holder());
  const std::vector<double> f = grid(5.0);
  const RouteData d = route_data(a, Route::SpindleHolderFromSH, f);
  const JointFitData x = noisy_fit_data(d, 0.02, 5);
  const AssemblyModel m(a);
  const EffectAnalysis ea = effect_analysis(a, Route::SpindleHolderFromSH, f);
  const double mode = ea.modes[ea.dominant].frequency_hz;
  const JointSeries js = identify_series([&](double y) { return m.holder(y); }, x.B11, "S11", x.G11, "SH11");
  const JointReadout seed = band_readout(js, 0.98 * mode, 1.02 * mode);
  EXPECT_LT(seed.parameters[0].median / d.truth.k_yf - 1.0, -0.2) << "the closed form's bias this test is about";
  const JointFit r = fit_joint({x}, {seed.medians(), offset_start(d.truth)}, linearised());
  for (int k : {0, 6}) {
    const ParameterInterval& iv = r.intervals[static_cast<std::size_t>(k)];
    EXPECT_TRUE(iv.lower <= d.truth[k] && d.truth[k] <= iv.upper) << JointParameters::name(k);
    EXPECT_LT(relative_error(r.parameters, d.truth, k), 0.002) << JointParameters::name(k);
  }
}

// Several set-ups: the seed's three overhangs. One joint at both overhangs transfers; a joint
// 20 % stiffer in k_yf at the second overhang does not, and the fit says so.
TEST(JointFit, TellsWhetherTheJointTransfersBetweenSetUps) {
  const std::vector<double> f = grid(5.0);
  const Assembly a49 = example_assembly();
  Assembly a60 = with_overhang(a49, 0.060);
  auto data = [&](const Assembly& a, std::uint64_t seed, const char* label) {
    JointFitData x = noisy_fit_data(route_data(a, Route::HolderTool, f), 0.02, seed);
    x.label = label;
    return x;
  };
  const JointFit same = fit_joint({data(a49, 1, "49 mm"), data(a60, 3, "60 mm")}, {offset_start(a49.holder_tool.parameters)},
                                  linearised());
  EXPECT_TRUE(same.transfers) << same.transfer_statistic << " vs " << same.transfer_limit;
  ASSERT_EQ(same.setups.size(), 2u);
  EXPECT_EQ(same.setups[1].label, "60 mm");
  EXPECT_LT(relative_error(same.parameters, a49.holder_tool.parameters, 0), 0.003);
  a60.holder_tool.parameters.k_yf *= 1.2;
  const JointFit differ = fit_joint({data(a49, 1, "49 mm"), data(a60, 3, "60 mm")}, {offset_start(a49.holder_tool.parameters)},
                                    linearised());
  EXPECT_FALSE(differ.transfers);
  EXPECT_GT(differ.transfer_statistic, 10.0 * differ.transfer_limit);
  ASSERT_FALSE(differ.warnings.empty());
  EXPECT_NE(differ.warnings.back().find("does not transfer"), std::string::npos) << differ.warnings.back();
  // Each set-up alone finds its own joint.
  EXPECT_LT(std::abs(differ.setups[1].fitted.k_yf / a60.holder_tool.parameters.k_yf - 1.0), 0.01);
}

// The bootstrap's replicates run on any number of threads with the same result, bit for bit.
TEST(JointFit, BootstrapIsIdenticalForAnyThreadCount) {
  const RouteData d = route_data(example_assembly(), Route::HolderTool, grid(10.0));
  const JointFitData x = noisy_fit_data(d, 0.05, 2);
  JointFitOptions o;
  o.bootstrap_samples = 24;
  o.parallel.threads = 1;
  const JointFit one = fit_joint({x}, {offset_start(d.truth)}, o);
  o.parallel.threads = 3;
  const JointFit three = fit_joint({x}, {offset_start(d.truth)}, o);
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ(one.intervals[static_cast<std::size_t>(k)].estimate, three.intervals[static_cast<std::size_t>(k)].estimate);
    EXPECT_EQ(one.intervals[static_cast<std::size_t>(k)].std_error, three.intervals[static_cast<std::size_t>(k)].std_error);
  }
}

// A stated calibration's misfit is one draw of a factor, not averaged over frequencies: data off by
// a factor 1.05 (2.5 σ of a 2 % calibration) leave residuals several times the noise's, which the
// calibration explains. Its share of the expected cost is reported, and residual_limit allows for
// it at the stated probability; without a calibration the limit is the noise's alone. Independent
// check of the share: the cost a factor δ adds is δ² (ΔᵀΩΔ − dᵀA⁻¹d) (the part the joint cannot
// absorb), so the ratio's excess over 1 with the factor applied, divided by that with δ = σ, is
// (δ/σ)² = 6.25 to within the noise's scatter of the ratio (±0.02 here) over the share.
TEST(JointFit, ACalibrationsMisfitIsJudgedAsOneDraw) {
  const RouteData d = route_data(example_assembly(), Route::HolderTool, grid(5.0));
  JointFitData x = noisy_fit_data(d, 0.02, 77);
  for (Block& b : x.G11.blocks) b *= 1.05;
  for (Block& b : x.B11.blocks) b *= 1.05;
  x.g_noise.calibration = x.b_noise.calibration = 0.02;
  JointFitOptions o = linearised();
  o.shared_calibration = true;  // one factor on both, as applied
  const JointFit r = fit_joint({x}, {offset_start(d.truth)}, o);
  const double s = r.residual_calibration_share;
  ASSERT_GT(s, 0.05);
  EXPECT_NEAR((r.residual_ratio - (1.0 - s)) / s, 6.25, 0.02 / s + 0.5) << r.residual_ratio << " share " << s;
  EXPECT_GT(r.residual_ratio, 1.5);
  EXPECT_LT(r.residual_ratio, residual_limit(r, 3.0, 0.99));
  EXPECT_NEAR(residual_limit(r, 3.0, 0.99), 3.0 * (1.0 - s) + 6.634897 * s, 1e-5);
  x.g_noise.calibration = x.b_noise.calibration = 0.0;
  const JointFit plain = fit_joint({x}, {offset_start(d.truth)}, o);
  EXPECT_EQ(plain.residual_calibration_share, 0.0);
  EXPECT_EQ(residual_limit(plain, 3.0, 0.99), 3.0);
}

// Issue 24's additive floor (1 % of each entry's peak plus 1 % multiplicative, stated) on the
// example's SH11 and SHT11: B11's antiresonances lie under the floor. Raw in the model, B11's
// noise put poles into it: the optimum moved by up to 8 % in k_yf (some 20 standard errors) between
// two starts (10 % off and the truth) and the spread over seeds was 20× the linearised error.
// Smoothed (joint_fit.hpp), the two starts must agree within 0.3 standard errors (the weights of
// the two passes follow each start's path: 0.1–0.2 seen), and the linearised standard error
// (its sandwich with the smoother's correlation, unchecked) must match the spread of the
// estimates over 40 noise seeds — a Monte Carlo the fit does not compute — within 25 % (the
// spread's own sampling error at 40 seeds is 11 %; raw, the ratio was 20).
TEST(JointFit, B11UnderAFloorEntersSmoothedWithAnHonestCovariance) {
  const RouteData d = route_data(example_assembly(), Route::HolderTool, grid(1.0));
  JointFitOptions o = linearised();
  o.check_linearisation = false;
  const StatedNoise floor{0.01, 0.0, 0.01};
  auto data = [&](std::uint64_t seed) {
    JointFitData x;
    x.label = "floor";
    x.A = d.A;
    x.G11 = draw_block_noise(d.G, stated_block_noise(d.G, floor), seed);
    x.B11 = draw_block_noise(d.B, stated_block_noise(d.B, floor), seed + 1);
    x.g_noise = stated_block_noise(x.G11, floor);
    x.b_noise = stated_block_noise(x.B11, floor);
    return x;
  };
  const int seeds = 40;
  std::vector<double> k;
  double se = 0.0;
  for (int s = 0; s < seeds; ++s) {
    const JointFitData x = data(2000u + 2u * static_cast<std::uint64_t>(s));
    const JointFit a = fit_joint({x}, {offset_start(d.truth)}, o);
    if (s < 4) {
      const JointFit b = fit_joint({x}, {d.truth}, o);
      EXPECT_NEAR(a.parameters.k_yf, b.parameters.k_yf, 0.3 * a.intervals[0].std_error) << "seed " << s;
      EXPECT_NE(a.method_description.find("enters the model smoothed"), std::string::npos) << a.method_description;
    }
    k.push_back(a.parameters.k_yf);
    se += a.intervals[0].std_error / seeds;
  }
  double mean = 0.0, var = 0.0;
  for (double v : k) mean += v / seeds;
  for (double v : k) var += (v - mean) * (v - mean) / (seeds - 1);
  EXPECT_NEAR(std::sqrt(var) / se, 1.0, 0.25) << "spread " << std::sqrt(var) << " against the linearised " << se;
}

TEST(JointFit, BadInputGetsAClearMessage) {
  const RouteData d = route_data(example_assembly(), Route::HolderTool, grid(5.0));
  const JointFitData good = noisy_fit_data(d, 0.02, 1);
  const std::vector<JointParameters> start{offset_start(d.truth)};
  auto message = [&](const std::vector<JointFitData>& x, const JointFitOptions& o) {
    try {
      fit_joint(x, start, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Too few frequencies.
  JointFitData few = noisy_fit_data(route_data(example_assembly(), Route::HolderTool, {2500, 2510, 2520, 2530, 2540}), 0.0, 1);
  EXPECT_THROW(fit_joint({few}, start, linearised()), InputError);
  // A component that transmits nothing (A12 = A21 = 0): no parameter acts on G11.
  JointFitData deaf = good;
  for (TwoPort& t : deaf.A) t.b12 = t.b21 = Block::Zero();
  EXPECT_THROW(fit_joint({deaf}, start, linearised()), NumericalError);
  EXPECT_NE(message({deaf}, linearised()).find("does not act"), std::string::npos) << message({deaf}, linearised());
  // NaN, grids that differ, sizes that differ.
  JointFitData nan = good;
  nan.G11.blocks[10](1, 1) = Complex(std::nan(""), 0.0);
  EXPECT_THROW(fit_joint({nan}, start, linearised()), InputError);
  JointFitData shifted = good;
  shifted.B11.frequency_hz[3] += 1.0;
  EXPECT_NE(message({shifted}, linearised()).find("B11"), std::string::npos);
  JointFitData short_a = good;
  short_a.A.pop_back();
  EXPECT_THROW(fit_joint({short_a}, start, linearised()), InputError);
  // Options and empty input.
  JointFitOptions o;
  o.bootstrap_samples = 5;
  EXPECT_THROW(fit_joint({good}, start, o), InvalidArgument);
  o = {};
  o.confidence = 1.2;
  EXPECT_NE(message({good}, o).find("confidence"), std::string::npos);
  EXPECT_THROW(fit_joint({}, start, linearised()), InvalidArgument);
  EXPECT_THROW(fit_joint({good}, {}, linearised()), InvalidArgument);
  // P out of range by 1e250 (a rotational entry made with a κGA of 1e-300 N): the weighted cost
  // overflows and the fit cannot move from its start. Refused as out of range, not returned as
  // the start with "residual ratio inf".
  JointFitData huge = good;
  for (Block& b : huge.G11.blocks) b(1, 1) *= 1e250;
  EXPECT_THROW(fit_joint({huge}, start, linearised()), NumericalError);
  EXPECT_NE(message({huge}, linearised()).find("out of the range of double precision"), std::string::npos)
      << message({huge}, linearised());
}

// ---- Coverage over noise seeds ------------------------------------------------------------------

namespace {

struct CoverageCase {
  std::string name;
  Assembly assembly;
  Route route;
  double sigma;
  std::optional<SavgolOptions> filter;
};

struct Coverage {
  std::array<int, 8> covered{}, determined{}, covered_determined{};
  std::array<double, 8> rms{}, mean{};
  int seeds = 0;
};

Coverage coverage(const CoverageCase& c, const JointFitOptions& base, int seeds, double step) {
  const RouteData d = route_data(c.assembly, c.route, grid(step));
  Coverage cv;
  cv.seeds = seeds;
  for (int s = 0; s < seeds; ++s) {
    JointFitOptions o = base;
    o.filter = c.filter;
    o.seed = 1000u + static_cast<std::uint64_t>(s);
    const JointFit r = fit_joint({noisy_fit_data(d, c.sigma, 100u + 2u * static_cast<std::uint64_t>(s))}, {offset_start(d.truth)},
                                 o);
    for (int k = 0; k < 8; ++k) {
      const auto ks = static_cast<std::size_t>(k);
      const ParameterInterval& iv = r.intervals[ks];
      const bool in = iv.lower <= d.truth[k] && d.truth[k] <= iv.upper;
      cv.covered[ks] += in;
      cv.determined[ks] += iv.determined;
      cv.covered_determined[ks] += in && iv.determined;
      const double e = relative_error(r.parameters, d.truth, k) * (r.parameters[k] >= d.truth[k] ? 1.0 : -1.0);
      cv.rms[ks] += e * e / seeds;
      cv.mean[ks] += e / seeds;
    }
  }
  for (double& x : cv.rms) x = std::sqrt(x);
  return cv;
}

// Prints the table (what docs/identification.md quotes) and checks every parameter that is determined in most
// seeds: coverage at least 95 % − 3 binomial standard errors (a correct 95 % interval fails this
// once in ~700), and — only when the study is long enough to tell (≥ 200 seeds) — at most 98 % plus
// 2 binomial standard errors at 98 % (a coverage of 98 % would exceed it once in 40: the estimate
// itself scatters by 0.7 % at 400 seeds).
void check(const CoverageCase& c, const Coverage& cv, const std::string& method) {
  std::string table = fmt::format("{} ({}), {} seeds: parameter coverage determined rms_error mean_error\n", c.name, method,
                                  cv.seeds);
  const double n = cv.seeds, lo = 0.95 - 3.0 * std::sqrt(0.95 * 0.05 / n);
  for (int k = 0; k < 8; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    table += fmt::format("  {:5}  {:5.3f}  {:4.2f}  {:8.3g} %  {:+8.3g} %\n", JointParameters::name(k), cv.covered[ks] / n,
                         cv.determined[ks] / n, 100 * cv.rms[ks], 100 * cv.mean[ks]);
    if (cv.determined[ks] < 0.9 * n) continue;
    EXPECT_GE(cv.covered[ks] / n, lo) << c.name << " " << method << " " << JointParameters::name(k);
    if (n >= 200)
      EXPECT_LE(cv.covered[ks] / n, 0.98 + 2.0 * std::sqrt(0.98 * 0.02 / n))
          << c.name << " " << method << " " << JointParameters::name(k);
  }
  std::printf("%s", table.c_str());
}

std::vector<CoverageCase> coverage_cases() {
  Assembly stiff = example_assembly();
  stiff.spindle_holder = Joint::make_elastic(stiff_spindle_holder());
  return {{"holder–tool (Table 1), Eq. 6, 5 % noise", example_assembly(), Route::HolderTool, 0.05, std::nullopt},
          {"holder–tool (Table 1), Eq. 6, 5 % noise, filtered 21/2", example_assembly(), Route::HolderTool, 0.05,
           SavgolOptions{21, 2}},
          {"spindle–holder (example), Eq. 18, 2 % noise", example_assembly(), Route::SpindleHolderFromSHT, 0.02, std::nullopt},
          {"spindle–holder (example), Eq. 18, 2 % noise, filtered 21/2", example_assembly(), Route::SpindleHolderFromSHT, 0.02,
           SavgolOptions{21, 2}},
          {"stiff spindle–holder, Eq. 15, 2 % noise", stiff, Route::SpindleHolderFromSH, 0.02, std::nullopt},
          {"stiff spindle–holder, Eq. 15, 2 % noise, filtered 21/2", stiff, Route::SpindleHolderFromSH, 0.02,
           SavgolOptions{21, 2}}};
}

}  // namespace

// Linearised (sandwich) intervals over noise seeds: the six cases above on a 5 Hz grid (999
// frequencies). Short in the suite (60 seeds); TOOLPOINT_COVERAGE_SEEDS for the long study.
TEST(JointFitCoverage, LinearisedIntervals) {
  const int seeds = env_int("TOOLPOINT_COVERAGE_SEEDS", 60);
  for (const CoverageCase& c : coverage_cases()) check(c, coverage(c, linearised(), seeds, 5.0), "linearised");
}

// The bootstrap (the default): short in the suite (two cases, 30 seeds × 40 replicates);
// TOOLPOINT_COVERAGE_SEEDS and TOOLPOINT_COVERAGE_BOOTSTRAP for the long study of all six.
TEST(JointFitCoverage, BootstrapIntervals) {
  const int seeds = env_int("TOOLPOINT_COVERAGE_SEEDS", 30);
  JointFitOptions o;
  o.bootstrap_samples = env_int("TOOLPOINT_COVERAGE_BOOTSTRAP", 40);
  const auto cases = coverage_cases();
  const bool long_study = std::getenv("TOOLPOINT_COVERAGE_SEEDS") != nullptr;
  for (std::size_t i = 0; i < cases.size(); ++i)
    if (long_study || i == 0 || i == 4)
      check(cases[i], coverage(cases[i], o, seeds, 5.0), fmt::format("bootstrap {}", o.bootstrap_samples));
}
