// Tests of the periodic delay kernel (periodic_delay.hpp) against results from outside it:
// the first-order semi-discretization of the Hayes equation published with
// SemiDiscretizationMethod.jl (Insperger & Stépán's book, p. 13), the exact characteristic root
// of the Hayes equation (Lambert W), the delayed Mathieu equation of the same package (p. 77),
// and Eigen's dense eigen-decomposition of the same map (for the Arnoldi path).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/stability/stability.hpp"
#include "support/stability_util.hpp"

using namespace toolpoint;

namespace {

using test::hayes;

// Delayed Mathieu: ẍ + a₁ẋ + (δ + ε cos t) x = b₀ x(t − 2π); A₀ carries δ and a₁, the periodic
// part −ε cos t acts on the current x, b₀ on the delayed x.
PeriodicDelaySystem mathieu(double delta, double eps, double b0, double a1) {
  PeriodicDelaySystem s;
  Eigen::MatrixXd a(2, 2);
  a << 0.0, 1.0, -delta, -a1;
  s.a0_blocks = {a};
  s.input = Eigen::MatrixXd(2, 1);
  s.input << 0.0, 1.0;
  s.output = Eigen::MatrixXd(1, 2);
  s.output << 1.0, 0.0;
  s.period = 2.0 * kPi;
  s.current = [eps](double t, Eigen::MatrixXd& out) { out(0, 0) = -eps * std::cos(t); };
  s.delayed = [b0](double, Eigen::MatrixXd& out) { out(0, 0) = b0; };
  return s;
}

// The rightmost root of λ = a + b e^{−λ} for a = b = −1: (λ + 1)e^{λ+1} = −e, so λ = W₀(−e) − 1,
// W₀ by Newton's method on w e^w = −e from the principal branch's neighbourhood.
std::complex<double> hayes_root() {
  std::complex<double> w(0.5, 1.5);
  for (int i = 0; i < 50; ++i) w -= (w * std::exp(w) + std::exp(1.0)) / (std::exp(w) * (w + 1.0));
  return w - 1.0;
}

}  // namespace

// SemiDiscretizationMethod.jl's README: Hayes a = b = −1, first-order semi-discretization with
// Δt = 0.1, spectral radius of the one-step map 0.941189374166563. For constant coefficients the
// kernel at degree 1 is that method (exact exponential of a, the delayed term interpolated
// linearly between the two samples one delay back), and the period map over m = 10 steps is the
// one-step map to the 10th power. Tolerance 1e-13: round-off of 10 steps.
TEST(PeriodicDelay, HayesReproducesPublishedFirstOrderSemiDiscretization) {
  const PeriodMap map(hayes(-1.0, -1.0), 10, 1);
  EXPECT_NEAR(std::pow(map.spectral_radius(1.0), 0.1), 0.941189374166563, 1e-13);
}

// The period map's spectral radius converges to e^{Re λ} with λ the exact characteristic root,
// at order p + 1 for degree p: errors fall ≥ 3.5×, ≥ 7×, ≥ 12× per doubling (observed 4.0, 8.0,
// 13–16; 4th order is spoiled a little by round-off near 1e-10), and are below 3e-5, 2e-6, 1e-8 at
// m = 80.
TEST(PeriodicDelay, HayesConvergesToTheCharacteristicRootAtOrderPPlusOne) {
  const double exact = std::exp(hayes_root().real());
  const std::complex<double> root = hayes_root();
  EXPECT_LT(std::abs(root + 1.0 + std::exp(-root)), 1e-14);  // it is a root (Newton converged)
  const double min_ratio[] = {3.5, 7.0, 12.0}, max_error[] = {3e-5, 2e-6, 1e-8};
  for (int p = 1; p <= 3; ++p) {
    const double e40 = std::abs(PeriodMap(hayes(-1.0, -1.0), 40, p).spectral_radius(1.0) - exact);
    const double e80 = std::abs(PeriodMap(hayes(-1.0, -1.0), 80, p).spectral_radius(1.0) - exact);
    EXPECT_GT(e40 / e80, min_ratio[p - 1]) << "degree " << p;
    EXPECT_LT(e80, max_error[p - 1]) << "degree " << p;
  }
}

// SemiDiscretizationMethod.jl's README: delayed Mathieu δ = 3, ε = 2, b₀ = −0.15, a₁ = 0.1,
// T = τ = 2π, first-order semi-discretization with Δt = 0.01: 0.5131596340374617. Its definitions
// differ from a converged monodromy in two ways (checked in its source and example): the map spans
// 628 steps of 0.01 (6.28, 0.05 % short of the period 2π, so it is not exactly the monodromy), and
// first order keeps an O(Δt²) error. The kernel's limit (degrees 2 and 3 agree to 1e-8 at
// m = 1600: 3e-9) must therefore match only to the size of those effects: 3e-3 (observed 1.1e-3).
TEST(PeriodicDelay, DelayedMathieuAgreesWithThePublishedValueToItsDefinitionsAccuracy) {
  const PeriodicDelaySystem s = mathieu(3.0, 2.0, -0.15, 0.1);
  const double p2 = PeriodMap(s, 1600, 2).spectral_radius(1.0), p3 = PeriodMap(s, 1600, 3).spectral_radius(1.0);
  EXPECT_NEAR(p2, p3, 1e-8);
  EXPECT_NEAR(p3, 0.5131596340374617, 3e-3);
}

// The Arnoldi path (maps above 40 states) against Eigen's dense decomposition of the same map:
// slotting, 2-DOF, 80 steps (a 180-state map), below, near and above the boundary. 1e-9: the
// Arnoldi tolerance (1e-10 relative residual) with the map's modest non-normality.
TEST(PeriodicDelay, ArnoldiMatchesTheDenseDecomposition) {
  const Mode m{0.03993, 0.011, 922.0};
  const FullDiscretization fd(ModalModel{{m}, {m}}, {2, 6e8, 1.0 / 3.0, engagement_from_immersion(1.0, MillingDirection::Down)},
                              80);
  const PeriodMap map = fd.period_map(10000.0);
  ASSERT_GT(map.size(), 100);
  for (double depth : {1e-4, 3e-4, 1e-3}) {
    const DominantMultiplier dm = map.dominant(depth);
    EXPECT_TRUE(dm.krylov);
    Eigen::EigenSolver<Eigen::MatrixXd> es(map.matrix(depth), false);
    double rho = 0.0;
    for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) rho = std::max(rho, std::abs(es.eigenvalues()(i)));
    EXPECT_NEAR(dm.spectral_radius / rho, 1.0, 1e-9) << depth;
    // The eigenvector is one: ‖Φv − μv‖ small against ‖v‖.
    Eigen::VectorXcd w(map.size());
    map.apply(depth, dm.vector.data(), w.data());
    EXPECT_LT((w - dm.multiplier * dm.vector).norm() / dm.vector.norm(), 1e-8) << depth;
  }
}

// Samples no step reads are dropped (their columns are zero, so they only add zero multipliers):
// slotting keeps the state and every delayed sample, n + d(m + p − 1) = 2 + 41 at m = 40, p = 2;
// at a/D = 0.05 the cut reads a few samples only.
TEST(PeriodicDelay, UnreadSamplesAreDropped) {
  const Mode m{0.03993, 0.011, 922.0};
  const FullDiscretization low(ModalModel{{m}, {}}, {2, 6e8, 1.0 / 3.0, engagement_from_immersion(0.05, MillingDirection::Down)},
                               40);
  const FullDiscretization slot(ModalModel{{m}, {}}, {2, 6e8, 1.0 / 3.0, engagement_from_immersion(1.0, MillingDirection::Down)},
                                40);
  EXPECT_EQ(slot.period_map(10000.0).size(), 2 + 41);
  EXPECT_LT(low.period_map(10000.0).size(), 15);
}

// Two propagation paths agree: the map (as applied for the eigenvalues) jumps over the steps out
// of the cut with e^{A₀kh}; outputs() steps through them one by one. For the dominant eigenvector
// v (found densely: inverse iteration on the shifted map), the output after one period must be μ
// times the output at its start. Also, v is Eigen's eigenvector up to a complex factor.
// Tolerances: 1e-9 relative, the rounding of ~50 steps and of the eigen-decomposition.
TEST(PeriodicDelay, FreeMotionJumpsAgreeWithStepping) {
  const Mode m{0.03993, 0.011, 922.0};
  const FullDiscretization fd(ModalModel{{m}, {}}, {2, 6e8, 1.0 / 3.0, engagement_from_immersion(0.05, MillingDirection::Down)},
                              50);
  const PeriodMap map = fd.period_map(7000.0);
  ASSERT_LT(map.size(), 40);  // the dense path
  for (double depth : {5e-4, 2e-3, 6e-3}) {
    const DominantMultiplier dm = map.dominant(depth);
    EXPECT_FALSE(dm.krylov);
    const Eigen::MatrixXcd r = map.outputs(depth, dm.vector);
    EXPECT_LT(std::abs(r(0, map.steps()) - dm.multiplier * r(0, 0)), 1e-9 * std::abs(r(0, 0))) << depth;
    Eigen::EigenSolver<Eigen::MatrixXd> es(map.matrix(depth), true);
    Eigen::Index k = 0;
    for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
      if (std::abs(es.eigenvalues()(i) - dm.multiplier) < std::abs(es.eigenvalues()(k) - dm.multiplier)) k = i;
    const Eigen::VectorXcd v = es.eigenvectors().col(k);
    EXPECT_NEAR(std::abs(v.dot(dm.vector)) / (v.norm() * dm.vector.norm()), 1.0, 1e-9) << depth;
  }
}

TEST(PeriodicDelay, BadSystemsAreRejected) {
  PeriodicDelaySystem s = hayes(-1.0, -1.0);
  s.period = 0.0;
  EXPECT_THROW(s.check(), InvalidArgument);
  s = hayes(-1.0, -1.0);
  s.input = Eigen::MatrixXd::Ones(2, 1);
  EXPECT_THROW(s.check(), InvalidArgument);
  s = hayes(-1.0, -1.0);
  s.breakpoints = {1.5};
  EXPECT_THROW(s.check(), InvalidArgument);
  s = hayes(-1.0, -1.0);
  Eigen::MatrixXd jordan(2, 2);
  jordan << 0.0, 1.0, 0.0, 0.0;  // not diagonalisable
  s.a0_blocks = {jordan};
  s.input = Eigen::MatrixXd::Ones(2, 1);
  s.output = Eigen::MatrixXd::Ones(1, 2);
  EXPECT_THROW(PeriodMap(s, 10, 1), InvalidArgument);
  EXPECT_THROW(PeriodMap(hayes(-1.0, -1.0), 1, 1), InvalidArgument);
  EXPECT_THROW(PeriodMap(hayes(-1.0, -1.0), 10, 4), InvalidArgument);
  s = hayes(-1.0, -1.0);
  s.delayed = [](double, Eigen::MatrixXd& out) { out = Eigen::MatrixXd::Constant(2, 2, 1.0); };  // wrong size
  EXPECT_THROW(PeriodMap(s, 10, 1), InvalidArgument);
}

// The forcing's periodic solution against closed forms. A damped oscillator ẍ + 2ζωẋ + ω²x =
// σ cos(2πt/T) with no feedback: x* is the steady harmonic response Re[σ e^{iΩt}/(ω² − Ω² +
// 2iζωΩ)] (the forcing is integrated by 5-point Gauss–Legendre, exact here to 1e-10). With the
// Hayes feedback ẋ = −x + σ(−x(t − 1) + w) and constant w, x* is the equilibrium σw/(1 + σ).
TEST(PeriodicDelay, PeriodicSolutionOfTheForcingIsTheSteadyResponse) {
  PeriodicDelaySystem s;
  const double w = 2.0 * kPi * 3.0, z = 0.05, big_t = 0.7;
  Eigen::MatrixXd a(2, 2);
  a << 0.0, 1.0, -w * w, -2.0 * z * w;
  s.a0_blocks = {a};
  s.input = Eigen::MatrixXd(2, 1);
  s.input << 0.0, 1.0;
  s.output = Eigen::MatrixXd(1, 2);
  s.output << 1.0, 0.0;
  s.period = big_t;
  s.forcing = [&](double t, Eigen::VectorXd& out) { out(0) = std::cos(2.0 * kPi * t / big_t); };
  const int m = 50;
  const PeriodMap map(s, m, 2);
  const PeriodMap::PeriodicSolution ps = map.periodic_solution(2.5);
  const double om = 2.0 * kPi / big_t;
  const std::complex<double> g = 1.0 / std::complex<double>(w * w - om * om, 2.0 * z * w * om);
  double peak = std::abs(2.5 * g);
  for (int k = 0; k <= m; ++k)
    EXPECT_NEAR(ps.outputs(0, k), (2.5 * g * std::exp(std::complex<double>(0.0, om * k * big_t / m))).real(), 1e-10 * peak) << k;

  PeriodicDelaySystem h = hayes(-1.0, -1.0);
  h.forcing = [](double, Eigen::VectorXd& out) { out(0) = 3.0; };
  const PeriodMap::PeriodicSolution eq = PeriodMap(h, 20, 2).periodic_solution(0.5);
  for (int k = 0; k <= 20; ++k) EXPECT_NEAR(eq.outputs(0, k), 0.5 * 3.0 / 1.5, 1e-12);
  EXPECT_THROW(PeriodMap(hayes(-1.0, -1.0), 20, 2).periodic_solution(1.0), InvalidArgument);  // no forcing
}
