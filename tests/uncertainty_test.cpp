// Tests of uncertainty propagation: samples have the stated mean and covariance, quantiles follow
// the type-7 definition, the Monte Carlo band of the tool point FRF agrees with first-order
// (delta-method) propagation computed here by finite differences, and the probability of
// stability is consistent with the depth quantiles and with an exactly known case.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/joint_data.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"
#include "toolpoint/io/uncertainty_io.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

// 20 000 draws: the sample mean within 4 standard errors of the mean, the sample covariance of
// every entry within 5 % of its scale (the standard error of a variance estimate is √(2/N) = 1 %).
TEST(Uncertainty, SamplesHaveTheStatedMeanAndCovariance) {
  const JointParameters m = seed_table1_joint();
  const auto c = covariance_of(m, 0.02);
  const int n = 20000;
  const auto s = sample_joints(m, c, n, 7);
  Eigen::Matrix<double, 8, 1> mean = Eigen::Matrix<double, 8, 1>::Zero();
  for (const auto& p : s)
    for (int k = 0; k < 8; ++k) mean(k) += p[k] / n;
  Eigen::Matrix<double, 8, 8> cov = Eigen::Matrix<double, 8, 8>::Zero();
  for (const auto& p : s)
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) cov(i, j) += (p[i] - mean(i)) * (p[j] - mean(j)) / (n - 1);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(mean(i), m[i], 4.0 * std::sqrt(c(i, i) / n)) << JointParameters::name(i);
    for (int j = 0; j < 8; ++j) EXPECT_NEAR(cov(i, j), c(i, j), 0.05 * std::sqrt(c(i, i) * c(j, j))) << i << "," << j;
  }
  // The reciprocal pairs stay equal in every draw (the singular covariance says so).
  for (const auto& p : s) ASSERT_NEAR(p.k_tf, p.k_ym, 1e-9 * std::abs(p.k_ym));
  EXPECT_EQ(sample_joints(m, c, 5, 3)[4].k_yf, sample_joints(m, c, 5, 3)[4].k_yf);  // reproducible
  Eigen::Matrix<double, 8, 8> bad = c;
  bad(0, 6) = bad(6, 0) = 3.0 * std::sqrt(c(0, 0) * c(6, 6));
  EXPECT_THROW(sample_joints(m, bad, 5, 1), InvalidArgument);
}

// numpy.quantile([1, 2, 3, 4], [0, 0.1, 0.5, 0.9, 1]) = [1, 1.3, 2.5, 3.7, 4].
TEST(Uncertainty, QuantilesAreType7) {
  const std::vector<double> v{4, 1, 3, 2, std::nan("")};
  EXPECT_DOUBLE_EQ(quantile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.1), 1.3);
  EXPECT_DOUBLE_EQ(quantile(v, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantile(v, 0.9), 3.7);
  EXPECT_DOUBLE_EQ(quantile(v, 1.0), 4.0);
  EXPECT_TRUE(std::isnan(quantile({}, 0.5)));
  EXPECT_EQ(quantile({1.0, INFINITY, INFINITY}, 0.9), INFINITY);
}

// The Monte Carlo band of |H| against first-order propagation: with 1 % on every parameter, the
// 5–95 % half-width ≈ 1.645 √(gᵀ C g), g = ∂|H|/∂θ by central differences of the model (an
// independent route). 400 samples put the Monte Carlo quantiles within ~8 % of that; tolerance
// 15 %, at the modes (where the joint matters) and between them. The nominal is the model's own
// tool point FRF; the 50 % quantile lies within the band.
TEST(Uncertainty, ToolPointBandAgreesWithFirstOrderPropagation) {
  const Assembly a = example_assembly();
  const JointFile joint = uncertain_joint(0.01);
  const std::vector<double> f{916.0, 1300.0, 2584.0, 2700.0, 3629.0};
  UncertaintyOptions o;
  o.samples = 400;
  const FrfBand band = tool_point_band(a, joint, f, o);
  const AssemblyModel nominal(with_joint(a, joint));
  for (std::size_t i = 0; i < f.size(); ++i) {
    // The sweep's rounding differs from one frequency at a time (assembly.hpp): 1e-10 relative.
    EXPECT_LT(std::abs(band.nominal.values[i] - nominal.tool_point(f[i])(0, 0)), 1e-10 * std::abs(band.nominal.values[i]));
    Eigen::Matrix<double, 8, 1> g = Eigen::Matrix<double, 8, 1>::Zero();
    for (int k = 0; k < 8; ++k) {
      if (joint.uncertainty->covariance(k, k) == 0.0) continue;
      const double h = 1e-4 * std::abs(joint.parameters[k]);
      JointFile up = joint, down = joint;
      up.parameters[k] += h;
      down.parameters[k] -= h;
      g(k) = (std::abs(AssemblyModel(with_joint(a, up)).tool_point(f[i])(0, 0)) -
              std::abs(AssemblyModel(with_joint(a, down)).tool_point(f[i])(0, 0))) /
             (2 * h);
    }
    const double linear = 1.645 * std::sqrt(g.dot(joint.uncertainty->covariance * g));
    const double mc = 0.5 * (band.magnitude[2][i] - band.magnitude[0][i]);
    EXPECT_NEAR(mc / linear, 1.0, 0.15) << f[i] << " Hz";
    EXPECT_LT(band.magnitude[0][i], band.magnitude[1][i]);
    EXPECT_LT(band.magnitude[1][i], band.magnitude[2][i]);
  }
  JointFile none = joint;
  none.uncertainty.reset();
  EXPECT_THROW(tool_point_band(a, none, f, o), InvalidArgument);
}

// The probability of stability: P = 1 at zero depth, non-increasing with depth, the depth quantiles
// ordered, and P at each sample count's own order statistic exact. With no uncertainty (a covariance
// of zeros) every sample is the nominal, so P is exactly 1 below the nominal envelope and 0 above.
TEST(Uncertainty, ProbabilityOfStabilityIsConsistent) {
  const Assembly a = example_assembly();
  const std::vector<double> f = FrequencyGrid{200.0, 5000.0, 2.0}.values();
  CuttingConditions cut;
  cut.teeth = 4;
  cut.tangential_coefficient = 6e8;
  cut.radial_ratio = 0.3;
  cut.engagement = engagement_from_immersion(0.5, MillingDirection::Down);
  ZeroOrderOptions lobes;
  lobes.speeds = SpeedRange{5000.0, 20000.0, 60};
  std::vector<double> depths;
  for (int j = 0; j <= 40; ++j) depths.push_back(j * 0.25e-3);
  UncertaintyOptions o;
  o.samples = 100;
  const StabilityUncertainty s = stability_uncertainty(a, uncertain_joint(0.05), f, cut, lobes, depths, o);
  ASSERT_EQ(s.speed_rpm.size(), 60u);
  for (Eigen::Index i = 0; i < s.probability.rows(); ++i) {
    EXPECT_EQ(s.probability(i, 0), 1.0);
    for (Eigen::Index j = 1; j < s.probability.cols(); ++j) ASSERT_LE(s.probability(i, j), s.probability(i, j - 1));
  }
  for (std::size_t i = 0; i < s.speed_rpm.size(); i += 7) {
    EXPECT_LE(s.depth_m[0][i], s.depth_m[1][i]);
    EXPECT_LE(s.depth_m[1][i], s.depth_m[2][i]);
  }
  JointFile exact = uncertain_joint(0.0);
  const StabilityUncertainty e = stability_uncertainty(a, exact, f, cut, lobes, depths, o);
  for (std::size_t i = 0; i < e.speed_rpm.size(); ++i)
    for (std::size_t j = 0; j < depths.size(); ++j)
      ASSERT_EQ(e.probability(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)),
                depths[j] < e.nominal_depth_m[i] ? 1.0 : 0.0)
          << i << "," << j;
  // Identical for any thread count.
  o.parallel.threads = 1;
  const StabilityUncertainty one = stability_uncertainty(a, uncertain_joint(0.05), f, cut, lobes, depths, o);
  o.parallel.threads = 3;
  const StabilityUncertainty three = stability_uncertainty(a, uncertain_joint(0.05), f, cut, lobes, depths, o);
  EXPECT_EQ(one.probability, three.probability);
  EXPECT_EQ(one.depth_m, three.depth_m);
}

// envelope_uncertainty with an envelope known in closed form (depth k_yf × 1e-12 m at 1000 rpm,
// twice that at 2000 rpm): its quantiles and P(stable) are those of the k_yf of the joints
// sample_joints draws from the file's covariance with the same seed, counted here.
TEST(Uncertainty, EnvelopeUncertaintyOfAKnownEnvelope) {
  const Assembly a = example_assembly();
  const JointFile joint = uncertain_joint(0.05);
  const auto envelope = [](const Assembly& x) {
    const double d = x.holder_tool.parameters.k_yf * 1e-12;
    return StabilityEnvelope{{1000.0, 2000.0}, {d, 2.0 * d}};
  };
  UncertaintyOptions o;
  o.samples = 50;
  o.seed = 3;
  const double nominal = joint.parameters.k_yf * 1e-12;
  const std::vector<double> grid{0.0, nominal, 1.0};
  const StabilityUncertainty s = envelope_uncertainty(a, joint, envelope, grid, o);
  std::vector<double> depth;
  for (const JointParameters& p : sample_joints(joint.parameters, joint.uncertainty->covariance, 50, 3))
    depth.push_back(p.k_yf * 1e-12);
  ASSERT_EQ(s.speed_rpm, (std::vector<double>{1000.0, 2000.0}));
  EXPECT_EQ(s.samples, 50);
  EXPECT_EQ(s.nominal_depth_m, (std::vector<double>{nominal, 2.0 * nominal}));
  for (std::size_t l = 0; l < o.levels.size(); ++l) {
    EXPECT_DOUBLE_EQ(s.depth_m[l][0], quantile(depth, o.levels[l])) << l;
    EXPECT_DOUBLE_EQ(s.depth_m[l][1], 2.0 * quantile(depth, o.levels[l])) << l;
  }
  const auto above = static_cast<double>(std::count_if(depth.begin(), depth.end(), [&](double d) { return d > nominal; }));
  EXPECT_GT(above, 5.0);  // the nominal lies inside the samples: the count is not trivially 0 or 50
  EXPECT_LT(above, 45.0);
  EXPECT_EQ(s.probability(0, 0), 1.0);
  EXPECT_EQ(s.probability(0, 1), above / 50.0);
  EXPECT_EQ(s.probability(1, 1), 1.0);  // 2 k_yf × 1e-12 > k_yf × 1e-12 for every sample
  EXPECT_EQ(s.probability(0, 2), 0.0);
  EXPECT_THROW(envelope_uncertainty(a, joint, envelope, {1.0, 0.5}, o), InvalidArgument);  // a decreasing grid
}

// The I/O layer (uncertainty_io.hpp) on hand-made results: the band as a table (|H| per level,
// then ∠H in degrees: π/2 rad is 90°) and as traces (the nominal, then every level but the median,
// |H|∠H recombined), the probability map as one row per (speed, depth), speed slowest, depth in mm.
TEST(Uncertainty, TablesAndTracesOfHandMadeResults) {
  FrfBand b;
  b.frequency_hz = {100.0, 200.0};
  b.levels = {0.05, 0.5, 0.95};
  b.samples = 12;
  b.nominal = FrfSeries{b.frequency_hz, {Complex(1e-6, 0.0), Complex(0.0, -2e-6)}};
  b.magnitude = {{1.0, 2.0}, {3.0, 4.0}, {5.0, 6.0}};
  b.phase_rad = {{0.0, M_PI / 2}, {M_PI, -M_PI / 2}, {0.0, 0.0}};
  const Table t = band_table(b);
  EXPECT_EQ(t.columns, (std::vector<std::string>{"frequency_hz", "magnitude_q5_m_per_n", "magnitude_q50_m_per_n",
                                                 "magnitude_q95_m_per_n", "phase_q5_deg", "phase_q50_deg", "phase_q95_deg"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[1], (std::vector<double>{200.0, 2.0, 4.0, 6.0, 90.0, -90.0, 0.0}));
  const std::vector<plot::FrfTrace> traces = band_traces(b);
  ASSERT_EQ(traces.size(), 3u);  // the nominal, q5, q95
  EXPECT_EQ(traces[0].label, "identified joint");
  EXPECT_EQ(traces[0].frf.values, b.nominal.values);
  EXPECT_EQ(traces[2].label, "95 % quantile (12 joint samples)");
  EXPECT_EQ(traces[2].style, plot::CurveStyle::Dashed);
  EXPECT_NEAR(traces[1].frf.values[1].imag(), 2.0, 1e-15);  // 2 at +90°
  EXPECT_NEAR(traces[1].frf.values[1].real(), 0.0, 1e-15);

  StabilityUncertainty s;
  s.speed_rpm = {1000.0, 2000.0};
  s.depth_grid_m = {0.0, 1e-3, 2e-3};
  s.probability = Eigen::MatrixXd(2, 3);
  s.probability << 1.0, 0.5, 0.0, 1.0, 1.0, 0.25;
  const Table p = probability_table(s);
  EXPECT_EQ(p.columns, (std::vector<std::string>{"spindle_speed_rpm", "axial_depth_mm", "probability_stable"}));
  ASSERT_EQ(p.rows.size(), 6u);
  EXPECT_EQ(p.rows[1], (std::vector<double>{1000.0, 1.0, 0.5}));
  EXPECT_EQ(p.rows[5], (std::vector<double>{2000.0, 2.0, 0.25}));
}
