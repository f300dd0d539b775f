// Tests of the precision study (studies/precision.hpp) against Monte Carlo, which does not use it:
//   * the tap test's noise carried through its finite differences (tap_test_block_noise) against the
//     scatter of blocks made from many noisy virtual tap tests;
//   * the expected standard errors against the scatter of the joint identified from noisy virtual
//     tap tests, end to end as a user would (taptest → rotational with the model's correction →
//     identify, the noise estimated from the data): within 20 % (issue 24), each parameter.
// The suite runs the end-to-end study short (TOOLPOINT_PRECISION_SEEDS, default 40: a standard
// deviation from 40 seeds is itself uncertain by ±11 %, so the suite asks 35 % of each parameter
// and 20 % of their median; docs/noise-and-verdict.md quotes that run). A longer run:
//   TOOLPOINT_PRECISION_SEEDS=200 build/toolpoint_tests --gtest_filter='Precision.*'
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fmt/format.h>

#include "support/joint_data.hpp"
#include "support/test_util.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/statistics.hpp"
#include "toolpoint/studies/fd_correction.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/precision.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

// A tap test's exact station FRFs and the differences of its block.
struct Station {
  PointFrfs exact;
  RotationalOptions fd;
};

Station station(const Assembly& a, TapSide side, double spacing) {
  TapTestOptions t;
  t.side = side;
  t.spacing_m = spacing;
  const TapTest tap = run_tap_test_study(a, t);
  Station s;
  for (const TapTestFrf& h : tap.frfs) s.exact.set(h.response, h.hammer, h.frf);
  s.fd.order = 2;
  s.fd.spacing = spacing;
  s.fd.shear_stiffness = tap.shear_stiffness_n;
  return s;
}

// The block of one noisy tap test: each H_ij an averaged test of its own (seed + k), as
// run_tap_test_study makes them.
BlockSeries noisy_block(const Station& s, const TapNoise& n, std::uint64_t seed) {
  PointFrfs p;
  std::uint64_t k = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i, ++k) {
      NoiseOptions o;
      o.sigma = n.sigma;
      o.floor = n.floor;
      o.averages = n.averages >= 2 ? n.averages : 0;
      o.seed = seed + k;
      p.set(i, j, add_measurement_noise(*s.exact.h[i][j], o).series);
    }
  return rotational_frfs(p, s.fd).block;
}

}  // namespace

// The tap test's noise through its finite differences: over 400 noisy tap tests of the tool (3
// points 15 mm apart, roving hammer; 1 % per hit, a floor at 0.1 % of each FRF's peak, 4
// averages) on a 10 Hz grid, the scatter of each block entry about the exact differences, summed
// over the frequencies, against the predicted variance summed alike: within 3 % (the sample
// variance of 400 draws is uncertain by 7 % at one frequency; over 500 independent frequencies
// 0.3 %; the averaged test's noise is Gaussian to first order only).
TEST(Precision, TapTestNoiseThroughTheFiniteDifferences) {
  Assembly a = example_assembly();
  a.grid = FrequencyGrid{10.0, 5000.0, 10.0};
  const Station s = station(a, TapSide::Tool, 0.015);
  TapNoise n;
  n.sigma = 0.01;
  n.floor = 0.001;
  n.averages = 4;
  const BlockSeries exact = rotational_frfs(s.exact, s.fd).block;
  const BlockNoise predicted = tap_test_block_noise(s.exact, s.fd, n, exact);
  const int draws = 400;
  std::vector<BlockSeries> blocks(draws);
  parallel_for(draws, {}, [&](std::size_t d) { blocks[d] = noisy_block(s, n, 1000 + 17 * d); });
  for (int e = 0; e < 4; ++e) {
    double got = 0.0, want = 0.0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const Cov8 c = predicted.absolute(i, exact.blocks[i]);
      want += c(2 * e, 2 * e) + c(2 * e + 1, 2 * e + 1);
      double sum = 0.0;
      for (const BlockSeries& b : blocks) sum += std::norm(b.blocks[i](e / 2, e % 2) - exact.blocks[i](e / 2, e % 2));
      got += sum / draws;
    }
    EXPECT_NEAR(got / want, 1.0, 0.03) << "entry " << e;
  }
}

// End to end: the precision study's expected standard errors (half-width / 1.96) against the
// scatter of the identified constants over seeds of noisy virtual tap tests of the example (both
// tap tests: 3 points, 15 mm on the tool, 20 mm on the holder; 0.5 % per hit, 3 averages).
TEST(Precision, ExpectedWidthsMatchMonteCarlo) {
  const int seeds = env_int("TOOLPOINT_PRECISION_SEEDS", 40);
  const Assembly a = example_assembly();
  const std::vector<double> f = a.grid.values();
  PrecisionOptions po;
  po.tool.spacing_m = 0.015;
  po.holder.spacing_m = 0.02;
  po.noise.sigma = 0.005;
  po.noise.averages = 3;
  const PrecisionStudy study = run_precision_study(a, po);

  const Station tool = station(a, TapSide::Tool, 0.015), holder = station(a, TapSide::Holder, 0.02);
  const FiniteDifferenceError tool_error = finite_difference_error(a, TapSide::Tool, f, tool.exact, tool.fd);
  const FiniteDifferenceError holder_error = finite_difference_error(a, TapSide::Holder, f, holder.exact, holder.fd);
  IdentificationOptions io;
  io.fit.uncertainty = UncertaintyMethod::Linearised;
  io.fit.check_linearisation = false;  // the fitted values are compared, not the intervals
  io.fit.parallel.threads = 1;
  std::vector<JointParameters> fitted(static_cast<std::size_t>(seeds));
  parallel_for(static_cast<std::size_t>(seeds), {}, [&](std::size_t s) {
    IdentificationData d;
    d.G11 = remove_finite_difference_error(noisy_block(tool, po.noise, 5000 + 100 * s), tool_error);
    d.B11 = remove_finite_difference_error(noisy_block(holder, po.noise, 90000 + 100 * s), holder_error);
    d.g_name = "SHT11";
    d.b_name = "SH11";
    const Identification id = run_identification_study(a, {d}, io);
    for (int k = 0; k < 8; ++k) fitted[s][k] = id.fit->intervals[static_cast<std::size_t>(k)].fitted;
  });
  std::vector<double> ratios;
  std::string table = fmt::format("precision vs Monte Carlo over {} seeds: parameter expected_se mc_sd ratio\n", seeds);
  for (int k = 0; k < 8; ++k) {
    const ParameterPrecision& p = study.parameters[static_cast<std::size_t>(k)];
    if (!p.free) continue;
    std::vector<double> v;
    for (const JointParameters& x : fitted) v.push_back(x[k]);
    const double sd = mean_sd(v).sd, expected = p.half_width / 1.959963984540054;
    ratios.push_back(sd / expected);
    table += fmt::format("  {:<5} {:.4g} {:.4g} {:.3f}\n", JointParameters::name(k), expected, sd, sd / expected);
    EXPECT_NEAR(sd / expected, 1.0, seeds >= 200 ? 0.2 : 0.35) << JointParameters::name(k);
  }
  std::printf("%s", table.c_str());
  EXPECT_NEAR(quantile(ratios, 0.5), 1.0, 0.2) << table;
}

// Averages for a target: the expected half-width at the averages the study names is within the
// target (recomputed, not trusted); a calibration wider than the target makes it unreachable; bad
// options are refused naming the field.
TEST(Precision, AveragesForATargetAndBadInput) {
  Assembly a = example_assembly();
  a.grid = FrequencyGrid{10.0, 5000.0, 5.0};
  PrecisionOptions po;
  po.tool.spacing_m = 0.015;
  po.holder.spacing_m = 0.02;
  po.noise.sigma = 0.02;
  po.target = 0.01;
  const PrecisionStudy s = run_precision_study(a, po);
  const ParameterPrecision& kyf = s.parameters[0];
  ASSERT_TRUE(kyf.averages_for_target);
  PrecisionOptions more = po;
  more.noise.averages = *kyf.averages_for_target;
  EXPECT_LE(run_precision_study(a, more).parameters[0].relative, 0.01 * (1.0 + 1e-9));
  if (*kyf.averages_for_target > 1) {
    more.noise.averages = *kyf.averages_for_target - 1;
    EXPECT_GT(run_precision_study(a, more).parameters[0].relative, 0.01);
  }
  PrecisionOptions cal = po;
  cal.noise.calibration = 0.03;
  cal.target = 1e-4;
  EXPECT_FALSE(run_precision_study(a, cal).parameters[0].averages_for_target);
  PrecisionOptions bad = po;
  bad.tool.spacing_m = 0.0;
  try {
    bad.check();
    ADD_FAILURE() << "no spacing refused";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("PrecisionOptions::tool.spacing_m"), std::string::npos) << e.what();
  }
  bad = po;
  bad.noise.calibration = 0.5;
  EXPECT_THROW(bad.check(), InvalidArgument);
  bad = po;
  bad.noise.sigma = 0.0;
  EXPECT_THROW(bad.check(), InvalidArgument);
}
