// Tests of the noise module: noise estimated from the data must recover noise of known statistics
// (the seed's multiplicative noise, magnitude-and-phase noise, entries correlated as finite
// differences correlate them), flag smoothed data, and draws must have the stated covariance.
#include <gtest/gtest.h>

#include <cmath>

#include "support/joint_data.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/tap_test.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

BlockSeries example_sht11() {
  const Assembly a = example_assembly();
  return AssemblyModel(a).tool_point(FrequencyGrid{10.0, 5000.0, 1.0}.values());
}

// The sample covariance of the relative errors (ε_e / x_e) of `noisy` about `truth` over all
// frequencies: an estimate of C that uses the truth, independent of estimate_block_noise.
Cov8 sample_relative_covariance(const BlockSeries& noisy, const BlockSeries& truth) {
  Cov8 c = Cov8::Zero();
  for (std::size_t i = 0; i < truth.size(); ++i) {
    Eigen::Matrix<double, 8, 1> r;
    for (int e = 0; e < 4; ++e) {
      const Complex rho = (noisy.blocks[i](e / 2, e % 2) - truth.blocks[i](e / 2, e % 2)) / truth.blocks[i](e / 2, e % 2);
      r(2 * e) = rho.real();
      r(2 * e + 1) = rho.imag();
    }
    c += r * r.transpose();
  }
  return c / static_cast<double>(truth.size());
}

Cov8 mean_of(const BlockNoise& n) {
  Cov8 c = Cov8::Zero();
  for (const Cov8& x : n.relative) c += x;
  return c / static_cast<double>(n.size());
}

}  // namespace

// The seed's noise, a real factor 1 + σz per entry (radial only), on the example's tool point FRF
// (4991 points, peaks a few tens of points wide): σ comes back within 5 % on every entry (the
// window averages of ~200 points have ~7 % scatter; the median over frequency less), the phase
// noise is absent (below 1 % of σ), and the residuals' lag-1 correlation is that of white noise
// through the 7-point cubic's complement I − S: (Σ_j c_j c_{j−1} − 2c₁)/(1 − c₀) with
// c = (−2, 3, 6, 7, 6, 3, −2)/21, i.e. (108/441 − 12/21)/(14/21) = −24/49.
TEST(BlockNoise, EstimatesTheSeedsMultiplicativeNoise) {
  const BlockSeries truth = example_sht11();
  const BlockSeries noisy = add_measurement_noise(truth, NoiseOptions{0.05, 7}).series;
  const BlockNoise n = estimate_block_noise(noisy, {}, "SHT11");
  for (int e = 0; e < 4; ++e) {
    EXPECT_NEAR(n.magnitude_sigma[static_cast<std::size_t>(e)], 0.05, 0.0025) << "entry " << e;
    EXPECT_LT(n.phase_sigma_rad[static_cast<std::size_t>(e)], 5e-4) << "entry " << e;
  }
  EXPECT_NEAR(n.residual_correlation, -24.0 / 49.0, 0.02);
  EXPECT_TRUE(n.warnings.empty()) << n.warnings.front();
}

// Magnitude and phase noise with correlation between entries (as rotational entries from finite
// differences share the translational measurements), drawn by draw_block_noise: the draws have
// the stated covariance (checked against the truth, independently of the estimator), and the
// estimator recovers it from the noisy data alone: diagonal within 8 %, correlations within 0.05.
TEST(BlockNoise, RecoversCorrelatedMagnitudeAndPhaseNoise) {
  const BlockSeries truth = example_sht11();
  Eigen::Matrix<double, 8, 8> L = Eigen::Matrix<double, 8, 8>::Zero();
  const double sd[8] = {0.03, 0.02, 0.05, 0.03, 0.05, 0.03, 0.08, 0.04};
  for (int k = 0; k < 8; ++k) L(k, k) = sd[k];
  L(4, 0) = 0.04;  // Re ρ_N follows Re ρ_H
  L(6, 0) = 0.05;  // Re ρ_P too
  const Cov8 C = L * L.transpose();
  BlockNoise stated;
  stated.relative.assign(truth.size(), C);
  stated.root.assign(truth.size(), L);
  const BlockSeries noisy = draw_block_noise(truth, stated, 11);
  const Cov8 sample = sample_relative_covariance(noisy, truth);
  const Cov8 est = mean_of(estimate_block_noise(noisy, {}, "SHT11"));
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(sample(i, i) / C(i, i), 1.0, 0.06) << "draw, component " << i;
    EXPECT_NEAR(est(i, i) / C(i, i), 1.0, 0.08) << "estimate, component " << i;
    for (int j = 0; j < i; ++j) {
      const double want = C(i, j) / std::sqrt(C(i, i) * C(j, j));
      EXPECT_NEAR(sample(i, j) / std::sqrt(sample(i, i) * sample(j, j)), want, 0.05) << "draw " << i << "," << j;
      EXPECT_NEAR(est(i, j) / std::sqrt(est(i, i) * est(j, j)), want, 0.05) << "estimate " << i << "," << j;
    }
  }
}

// Data smoothed before the estimate hide their noise: the residuals are then no longer those of
// white noise (lag-1 −0.35 instead of −0.49), and the estimate says so (it is far below σ).
TEST(BlockNoise, FlagsSmoothedData) {
  const BlockSeries truth = example_sht11();
  const BlockSeries noisy = add_measurement_noise(truth, NoiseOptions{0.05, 3}).series;
  const BlockSeries smooth = savgol_filter(noisy, SavgolOptions{41, 2}).series;
  const BlockNoise n = estimate_block_noise(smooth, {}, "sht11_f.csv");
  EXPECT_GT(n.residual_correlation, -0.4);
  EXPECT_LT(n.magnitude_sigma[0], 0.01);
  ASSERT_FALSE(n.warnings.empty());
  EXPECT_NE(n.warnings.back().find("white"), std::string::npos) << n.warnings.back();
  EXPECT_NE(n.warnings.back().find("sht11_f.csv"), std::string::npos);
}

// Low noise on lightly damped modes: the tutorial's tap test on the tool (0.5 %, 15 mm points,
// second-order differences). Near the carbide tool's sharp peaks the local cubic's misfit outweighs
// 0.5 % noise, and one lag-1 ratio over the band read −0.37 ("smoothed data", a false alarm); the
// median over chunks reads −0.46 (white: −0.49; the misfit still nudges many chunks of this
// grid, which has a mode every ~1000 Hz and antiresonances between) and warns of nothing (the
// warning starts at −0.4); the same data smoothed by an 11-point filter are still recognised.
TEST(BlockNoise, SharpPeaksAtLowNoiseAreNotTakenForSmoothing) {
  const Assembly a = example_assembly();
  TapTestOptions t;
  t.side = TapSide::Tool;
  t.spacing_m = 0.015;
  t.sigma = 0.005;
  t.seed = 11;
  const TapTest tap = run_tap_test_study(a, t);
  PointFrfs p;
  for (const TapTestFrf& h : tap.frfs) p.set(h.response, h.hammer, h.frf);
  RotationalOptions r;
  r.spacing = 0.015;
  r.shear_stiffness = tap.shear_stiffness_n;
  const BlockSeries block = rotational_frfs(p, r).block;
  const BlockNoise n = estimate_block_noise(block, {}, "sht11.csv");
  EXPECT_NEAR(n.residual_correlation, -24.0 / 49.0, 0.05);
  for (const auto& w : n.warnings) EXPECT_EQ(w.find("white"), std::string::npos) << w;
  const BlockNoise smoothed = estimate_block_noise(savgol_filter(block, SavgolOptions{11, 2}).series, {}, "sht11_f.csv");
  EXPECT_GT(smoothed.residual_correlation, -0.4);
}

// Noise model (b): an additive floor at 1 % of each entry's peak plus 1 % multiplicative, drawn by
// draw_block_noise from the stated model, on the example's SH11 (whose entries away from their
// peaks lie far below them, so the floor dominates most of the band). The estimate separates the
// two: each entry's floor within 10 % of the 1 % put in (one floor per 201-point chunk, a variance
// to ~10 %, the median over chunks better), and the noise variance of H over the band, against the
// truth's, within 10 % on average (what the fit's weights need). The multiplicative part shows
// only at the peak here (a few tens of points): with 5 % instead of 1 % it is recovered within
// 20 %. The seed's multiplicative noise alone gets no floor.
TEST(BlockNoise, EstimatesAnAdditiveFloorBesideMultiplicativeNoise) {
  const Assembly a = example_assembly();
  const BlockSeries truth = AssemblyModel(a).holder_tip(FrequencyGrid{10.0, 5000.0, 1.0}.values());
  const BlockNoise stated = stated_block_noise(truth, StatedNoise{0.01, 0.0, 0.01});
  const BlockNoise n = estimate_block_noise(draw_block_noise(truth, stated, 21), {}, "SH11");
  ASSERT_TRUE(n.has_floor());
  for (int e = 0; e < 4; ++e) EXPECT_NEAR(n.floor_relative[static_cast<std::size_t>(e)], 0.01, 0.001) << "entry " << e;
  double ratio = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Cov8 est = n.absolute(i, truth.blocks[i]), want = stated.absolute(i, truth.blocks[i]);
    ratio += (est(0, 0) + est(1, 1)) / (want(0, 0) + want(1, 1)) / static_cast<double>(truth.size());
  }
  EXPECT_NEAR(ratio, 1.0, 0.1);
  EXPECT_NE(n.summary().find("floor"), std::string::npos) << n.summary();
  const BlockNoise five =
      estimate_block_noise(draw_block_noise(truth, stated_block_noise(truth, StatedNoise{0.05, 0.0, 0.01}), 22), {}, "SH11");
  EXPECT_NEAR(five.magnitude_sigma[0], 0.05, 0.01);
  EXPECT_NEAR(five.floor_relative[0], 0.01, 0.001);
  const BlockNoise plain = estimate_block_noise(add_measurement_noise(truth, NoiseOptions{0.05, 7}).series, {}, "SH11");
  EXPECT_FALSE(plain.has_floor()) << plain.summary();
}

// Coherence (Bendat & Piersol): H's variance from it replaces the estimate's, ε² = (1 − γ²)/(2 (n − 1) γ²)
// radial and tangential, H's correlations with the other entries kept in proportion, its floor
// removed; the other entries untouched. Bad input names the data: another length, values outside
// [0, 1], no averages.
TEST(BlockNoise, CoherenceGivesHsVariance) {
  const BlockSeries truth = example_sht11();
  BlockNoise n = stated_block_noise(truth, StatedNoise{0.02, 0.01, 0.01});
  n.relative[5](0, 2) = n.relative[5](2, 0) = 0.5 * 0.02 * 0.02;  // a correlation of Re ρ_H with Re ρ_L
  std::vector<double> gamma2(truth.size(), 0.9);
  gamma2[5] = 0.99;
  const Cov8 before = n.relative[5];
  apply_coherence(n, gamma2, 10, "sht11.csv");
  const double eps2 = (1.0 - 0.99) / (2.0 * 9 * 0.99);
  EXPECT_NEAR(n.relative[5](0, 0), eps2, 1e-15);
  EXPECT_NEAR(n.relative[5](1, 1), eps2, 1e-15);
  EXPECT_NEAR(n.relative[5](0, 2) / std::sqrt(n.relative[5](0, 0) * n.relative[5](2, 2)), 0.5, 1e-12);
  EXPECT_EQ(n.relative[5](2, 2), before(2, 2));
  EXPECT_EQ(n.relative[5](7, 7), before(7, 7));
  EXPECT_EQ(n.additive[5](0), 0.0);
  EXPECT_GT(n.additive[5](1), 0.0);
  EXPECT_NEAR(n.relative[6](0, 0), (1.0 - 0.9) / (2.0 * 9 * 0.9), 1e-15);
  EXPECT_FALSE(n.coherence.empty());
  BlockNoise m = stated_block_noise(truth, StatedNoise{0.02, 0.0, 0.0});
  auto message = [&](const std::vector<double>& c, int averages) {
    try {
      apply_coherence(m, c, averages, "sht11.csv");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(std::vector<double>(truth.size() - 1, 0.9), 10).find("sht11.csv: the coherence column has"), std::string::npos);
  std::vector<double> percent(truth.size(), 0.9);
  percent[7] = 90.0;
  EXPECT_NE(message(percent, 10).find("outside [0, 1]"), std::string::npos);
  EXPECT_NE(message(gamma2, 0).find("averages"), std::string::npos);
  EXPECT_THROW(h1_relative_variance(1.5, 10), InvalidArgument);
  EXPECT_EQ(h1_relative_variance(0.0, 10), 1.0);
}

TEST(BlockNoise, StatedNoiseAndBadInput) {
  BlockSeries ten;
  for (int i = 0; i < 10; ++i) {
    ten.frequency_hz.push_back(100.0 + i);
    ten.blocks.push_back(Block::Constant(Complex(1.0, 0.5)));
  }
  const BlockNoise n = stated_block_noise(ten, StatedNoise{0.02, 0.01, 0.0});
  ASSERT_EQ(n.size(), 10u);
  EXPECT_DOUBLE_EQ(n.magnitude_sigma[3], 0.02);
  EXPECT_DOUBLE_EQ(n.phase_sigma_rad[1], 0.01);
  // Σ = R C Rᵀ around x: a pure phase error of σ on x = 2i moves the real part by 2σ.
  Block x = Block::Zero();
  x(0, 0) = Complex(0.0, 2.0);
  x(0, 1) = x(1, 0) = x(1, 1) = 1.0;
  const Cov8 s = n.absolute(0, x);
  EXPECT_NEAR(s(0, 0), 4.0 * 0.01 * 0.01, 1e-15);
  EXPECT_NEAR(s(1, 1), 4.0 * 0.02 * 0.02, 1e-15);
  EXPECT_THROW(stated_block_noise(ten, StatedNoise{-0.1, 0.0, 0.0}), InvalidArgument);
  EXPECT_THROW(stated_block_noise(ten, StatedNoise{0.0, 0.0, 0.0}), InvalidArgument);
  EXPECT_THROW(stated_block_noise(ten, StatedNoise{std::nan(""), 0.0, 0.0}), InvalidArgument);
  EXPECT_THROW(stated_block_noise(ten, StatedNoise{0.01, 0.0, -0.01}), InvalidArgument) << "a negative floor";
  EXPECT_THROW(stated_block_noise(ten, StatedNoise{0.01, 0.0, 2.0}), InvalidArgument) << "a floor of 200 %: per cent meant";
  BlockSeries few;
  for (int i = 0; i < 50; ++i) {
    few.frequency_hz.push_back(100.0 + i);
    few.blocks.push_back(Block::Constant(Complex(1.0, 0.5)));
  }
  EXPECT_THROW(estimate_block_noise(few, {}, "short.csv"), InputError);
  EXPECT_THROW(NoiseEstimateOptions({{7, 3}, 20}).check(), InvalidArgument);
  EXPECT_TRUE(draw_block_noise(few, exact_block_noise(), 1).blocks == few.blocks);
  EXPECT_THROW(draw_block_noise(few, n, 1), InvalidArgument);
}

TEST(BlockNoise, StreamSeedsDiffer) {
  EXPECT_NE(stream_seed(1, 0), stream_seed(1, 1));
  EXPECT_NE(stream_seed(1, 0), stream_seed(2, 0));
  EXPECT_EQ(stream_seed(5, 9), stream_seed(5, 9));
}
