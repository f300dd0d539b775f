// Tests of semi-discretization (periodic_delay.hpp's Discretization::Semi, stability.hpp's
// BoundaryOptions::scheme, docs/reference.md §13) against what is independent of it:
//   * the first-order semi-discretization of the Hayes equation published with
//     SemiDiscretizationMethod.jl (Insperger & Stépán's book, p. 13);
//   * the zeroth-order map of the Hayes equation written out by hand as a companion matrix
//     (Insperger & Stépán 2004: x_{k+1} = e^{ah} x_k + b(e^{ah} − 1)/a · ½(x_{k−m} + x_{k+1−m}));
//   * the analytic limit of one-mode turning (the delay equation's root on the imaginary axis);
//   * full-discretization, a different scheme, on the variable-pitch and runout cases of
//     variable_pitch_test.cpp and on uniform-pitch lobes: both converge to the same boundary.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "support/stability_util.hpp"
#include "support/test_util.hpp"
#include "support/turning_util.hpp"

using namespace toolpoint;

namespace {

using test::hayes;

using namespace test::benchmark;

CuttingConditions half_immersion(std::vector<double> pitch_deg) {
  CuttingConditions c{4, kKt, kKn / kKt, engagement_from_immersion(0.5, MillingDirection::Down)};
  for (double p : pitch_deg) c.pitch_rad.push_back(p * kDeg);
  return c;
}

// The limit at one speed by semi-discretization of order `order` at m steps per tooth period.
double semi_limit(const ModalModel& model, const CuttingConditions& c, double n, int m, int order) {
  return FullDiscretization(model, c, m, order, Discretization::Semi).boundary(n, 0.01, 100, 1e-9).depth_m;
}

}  // namespace

// SemiDiscretizationMethod.jl's README: Hayes a = b = −1, first-order semi-discretization with
// Δt = 0.1: spectral radius of the one-step map 0.941189374166563 (the period map over 10 steps is
// its 10th power). Tolerance 1e-13: round-off of 10 steps.
TEST(SemiDiscretization, HayesReproducesThePublishedFirstOrderValue) {
  const PeriodMap map(hayes(-1.0, -1.0), 10, 1, Discretization::Semi);
  EXPECT_EQ(map.scheme(), Discretization::Semi);
  EXPECT_EQ(map.degree(), 1);
  EXPECT_NEAR(std::pow(map.spectral_radius(1.0), 0.1), 0.941189374166563, 1e-13);
}

// Zeroth order: the one-step map written out as an (m + 1)-state companion matrix on
// (x_k, x_{k−1}, …, x_{k−m}); its spectral radius to the m-th power is the period map's. 1e-12:
// round-off.
TEST(SemiDiscretization, HayesZerothOrderIsTheHandWrittenMap) {
  const double a = -1.0, b = -1.0;
  for (int m : {5, 10, 23}) {
    const double h = 1.0 / m, e = std::exp(a * h), g = b * (e - 1.0) / a;
    Eigen::MatrixXd step = Eigen::MatrixXd::Zero(m + 1, m + 1);
    step(0, 0) = e;
    step(0, m) += 0.5 * g;      // x_{k−m}
    step(0, m - 1) += 0.5 * g;  // x_{k+1−m}
    for (int i = 1; i <= m; ++i) step(i, i - 1) = 1.0;
    const double one_step = step.eigenvalues().cwiseAbs().maxCoeff();
    const PeriodMap map(hayes(a, b), m, 0, Discretization::Semi);
    EXPECT_NEAR(map.spectral_radius(1.0), std::pow(one_step, m), 1e-12) << m;
  }
}

// One-mode turning, no process damping (m ẍ + c ẋ + k x = −Kb(x − x(t − τ))) and with it: the
// semi-discretized limit against the analytic one at 60 steps per wave of the mode over a
// revolution (450 and 1500 steps), 2000 and 600 rpm. The current term −Kb is exponentiated exactly, so only the delayed
// term's interpolation errs. Measured: first order 0.08–0.45 % (the most with process damping at
// 600 rpm), zeroth order twice that (0.16–0.91 %); doubling m divides both by 4.0 (second order,
// the q = 2 of boundary_error_order). Tolerances 0.5 %, 1 % and a fall ≥ 3.5× per doubling.
TEST(SemiDiscretization, TurningLimitIsTheAnalyticOne) {
  test::Turning with;
  test::Turning bare = with;
  bare.c_i = 0.0;
  for (const test::Turning* t : {&bare, &with})
    for (double n : {2000.0, 600.0}) {
      const double exact = t->analytic_limit(n);
      ASSERT_TRUE(std::isfinite(exact)) << n;
      // 60 steps per wave of the mode's frequency over one revolution.
      const int m = static_cast<int>(std::ceil(60.0 * t->mode.frequency_hz * 60.0 / n));
      for (int order : {1, 0}) {
        const double coarse = t->discretized_limit(n, m, exact, order, Discretization::Semi);
        const double fine = t->discretized_limit(n, 2 * m, exact, order, Discretization::Semi);
        const double e1 = std::abs(coarse / exact - 1.0), e2 = std::abs(fine / exact - 1.0);
        EXPECT_LT(e1, order == 1 ? 5e-3 : 1e-2) << n << " rpm, order " << order << ", C_i " << t->c_i;
        EXPECT_LT(e2, e1 / 3.5) << n << " rpm, order " << order << ", C_i " << t->c_i;
      }
    }
}

// The example's variable-pitch tool (4 teeth at 70°/110°) and its runout case (an axis offset of
// 10 µm, feed 50 µm per tooth), a/D 0.5 down-milling, the benchmark mode: first-order
// semi-discretization at m = 40, 80, 160 steps per tooth period against the converged
// full-discretization limit (estimated error ≤ 0.1 %), 3000 and 4500 rpm (and 10 000 rpm with
// runout; the pitched tool is stable to the ceiling there). The two are different schemes (averaged
// coefficients exponentiated vs. interpolated outputs) with one limit: the gap falls ≥ 2× per
// doubling of m (measured 2.4–11×; runout ~4×, second order) and is ≤ 0.3 % at m = 160 (measured
// 0.02–0.25 %). At m = 20 it is erratic (5.8 % then 4.6 % at 40 for the pitch at 3000 rpm): the
// delays of 70° and 110° fall between steps, and the line through two samples that first order
// reads them from changes its error's sign with the fraction.
TEST(SemiDiscretization, ConvergesToTheFullDiscretizationLimitWithSeveralDelays) {
  ModalModel model;
  model.x = {kBench};
  const CuttingConditions pitch = half_immersion({70, 110, 70, 110});
  CuttingConditions runout = half_immersion({});
  runout.runout_m = offset_runout(uniform_cutter(4, kDiameter).pitch_rad, 1e-5, 0.3);
  runout.feed_per_tooth_m = 5e-5;
  runout.diameter_m = kDiameter;
  for (const CuttingConditions* c : std::vector<const CuttingConditions*>{&pitch, &runout})
    for (double n : {3000.0, 4500.0, 10000.0}) {
      if (c == &pitch && n == 10000.0) continue;
      const double fd = test::converged_limit(model, *c, n);
      double previous = INFINITY;
      for (int m : {40, 80, 160}) {
        const double gap = std::abs(semi_limit(model, *c, n, m, 1) / fd - 1.0);
        EXPECT_LT(gap, 0.5 * previous) << n << " rpm, m " << m;
        previous = gap;
      }
      EXPECT_LT(previous, 3e-3) << n << " rpm";
    }
}

// Uniform pitch: the semi-discretized lobes (stability_boundary with Discretization::Semi, error
// target 0.1 %) against today's full-discretization lobes (same target), 4 teeth a/D 0.5 and 0.1
// down-milling, 2-DOF tool, 5000–15000 rpm: the same kind and lobe number at every speed and the
// depths within 0.2 % (each within its estimated 0.1 %; measured 0–0.034 %). A speed stable up to
// the ceiling must be so by both.
TEST(SemiDiscretization, UniformPitchLobesAreTheFullDiscretizationOnes) {
  ModalModel model;
  model.x = {kBench};
  model.y = {Mode{0.05, 0.02, 1100.0}};
  for (double immersion : {0.5, 0.1}) {
    const CuttingConditions c{4, kKt, kKn / kKt, engagement_from_immersion(immersion, MillingDirection::Down)};
    BoundaryOptions o;
    o.speeds = {5000.0, 15000.0, 11};
    o.tolerance = 1e-3;
    o.parallel.threads = 2;
    const BoundaryResult fd = stability_boundary(model, c, o);
    o.scheme = Discretization::Semi;
    o.degree = 1;
    const BoundaryResult sd = stability_boundary(model, c, o);
    EXPECT_EQ(sd.scheme, Discretization::Semi);
    for (std::size_t i = 0; i < fd.boundary.size(); ++i) {
      const BoundaryPoint &f = fd.boundary[i], &s = sd.boundary[i];
      EXPECT_EQ(s.kind, f.kind) << f.speed_rpm;
      EXPECT_EQ(s.lobe, f.lobe) << f.speed_rpm;
      EXPECT_NEAR(s.depth_m, f.depth_m, 2e-3 * f.depth_m) << f.speed_rpm;
    }
  }
}

// Orders outside 0…1, and a forced periodic solution (not implemented), are refused by name.
TEST(SemiDiscretization, BadOrderIsRefused) {
  EXPECT_THROW(PeriodMap(hayes(-1.0, -1.0), 10, 2, Discretization::Semi), InvalidArgument);
  BoundaryOptions o;
  o.speeds = {5000.0, 6000.0, 2};
  o.scheme = Discretization::Semi;
  o.degree = 2;
  EXPECT_NE(test::thrown_message([&] { o.check(); }).find("BoundaryOptions::degree"), std::string::npos);
  PeriodicDelaySystem s = hayes(-1.0, -1.0);
  s.forcing = [](double, Eigen::VectorXd& out) { out(0) = 1.0; };
  EXPECT_THROW(PeriodMap(s, 10, 1, Discretization::Semi).periodic_solution(1.0), InvalidArgument);
}
