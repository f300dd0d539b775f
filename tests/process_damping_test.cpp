// Tests of process damping (periodic_delay.hpp's with_velocity_feedback, stability.hpp's
// CuttingConditions::process_damping_n_per_m) against the analytic stability limit of the delay
// equation with the added damping, and the model's own prediction that the limit rises as the
// speed falls.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "support/stability_util.hpp"
#include "support/turning_util.hpp"
#include "support/test_util.hpp"

using namespace toolpoint;

namespace {

using test::thrown_message;
using test::Turning;

}  // namespace

// The full-discretization limit of the turning equation with process damping agrees with the
// analytic one within 0.2 % (60 steps per chatter wave: measured 4e-5…1.4e-4), at speeds where
// the bare limit is at its lobes' minimum (2000, 1200, 600, 400 rpm: 2.5–2.8e-5 m), and the
// analytic limit over the bare one rises as the speed falls (1.16, 1.38, 2.2, 7.0): the model's
// C_i b/V. At 300 rpm and below no depth is unstable for chatter near the mode (the damping C_i/V
// per unit depth outweighs the cutting stiffness K): the limit is infinite, and not tested here.
TEST(ProcessDamping, TurningLimitIsTheAnalyticOne) {
  const Turning t;
  Turning bare = t;
  bare.c_i = 0.0;
  double previous_ratio = 0.0;
  for (double n : {2000.0, 1200.0, 600.0, 400.0}) {
    const double exact = t.analytic_limit(n);
    ASSERT_TRUE(std::isfinite(exact)) << n << " rpm";
    const double waves = t.mode.frequency_hz * 1.1 * 60.0 / n;
    const int steps = static_cast<int>(std::ceil(60.0 * waves));
    const double fd = t.discretized_limit(n, steps, exact);

    EXPECT_NEAR(fd, exact, 2e-3 * exact) << n << " rpm";
    // Without process damping the minimum over a lobe is 2kζ(1+ζ)/K; with it, higher, and more so
    // at low speed (the ratio over the bare limit grows as n falls).
    const double ratio = exact / bare.analytic_limit(n);
    EXPECT_GT(ratio, previous_ratio) << n << " rpm";
    previous_ratio = ratio;
  }
  EXPECT_GT(previous_ratio, 5.0);  // at 400 rpm the limit is 7× the bare one (at 2000 rpm 1.16×)
}

// Milling: process damping raises the limit, more at low speed; zero coefficient is today's path
// (the same system, bit for bit).
TEST(ProcessDamping, MillingLimitRisesAsTheSpeedFalls) {
  ModalModel model;
  model.x = {Mode{0.03993, 0.011, 922.0}};
  CuttingConditions c{4, 2e9, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  c.diameter_m = 0.02;
  CuttingConditions pd = c;
  pd.process_damping_n_per_m = 2e5;
  double previous = INFINITY;
  for (double n : {800.0, 1600.0, 3200.0, 6400.0}) {
    const FullDiscretization bare(model, c, 100), damped(model, pd, 100);
    const double b0 = bare.boundary(n, 0.01, 100, 1e-6).depth_m, b1 = damped.boundary(n, 0.01, 100, 1e-6).depth_m;
    EXPECT_GT(b1, b0) << n;
    EXPECT_LT(b1 / b0, previous) << n;  // the rise shrinks as the speed grows
    previous = b1 / b0;
  }
}

// The simulation with the same damping (ForceLaw::process_damping_n_per_m from linear_force_law:
// each slice in the cut adds −C_i dz (u·ṙ)/V u) switches from stable to unstable within ±3 % of
// the process-damped limit a (stable at 0.97 a, unstable at 1.03 a: the simulation's stated error,
// variable_pitch_test.cpp) where process damping raises the limit 1.8–2.7× (700 rpm with C_i 5e4
// N/m; 1800 and 2500 rpm with 2e5 N/m): so the agreement tests the damping term, not the bare cut.
// (Lower, with 2e5 N/m, the damped limit lies beyond the search ceiling of 10 × the zero-order floor.)
TEST(ProcessDamping, SimulationSwitchBracketsTheDampedLimit) {
  ModalModel model;
  model.x = {Mode{0.03993, 0.011, 922.0}};
  CuttingConditions c{4, 2e9, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  c.diameter_m = 0.02;
  const Cutter cutter = uniform_cutter(4, c.diameter_m);
  for (const auto& [n, ci] : {std::pair{700.0, 5e4}, {1800.0, 2e5}, {2500.0, 2e5}}) {
    CuttingConditions pd = c;
    pd.process_damping_n_per_m = ci;
    const double a = test::converged_limit(model, pd, n), a0 = test::converged_limit(model, c, n);
    EXPECT_GT(a / a0, 1.5) << n;
    SimulationOptions so;
    so.record = false;
    const ForceLaw law = linear_force_law(pd);
    ASSERT_EQ(law.process_damping_n_per_m, ci);
    const SimulationResult below = simulate_milling(tool_dynamics(model), cutter, law, {n, 0.97 * a, 1e-4, c.engagement}, so);
    const SimulationResult above = simulate_milling(tool_dynamics(model), cutter, law, {n, 1.03 * a, 1e-4, c.engagement}, so);
    EXPECT_EQ(below.out_of_cut_fraction, 0.0) << n;
    EXPECT_TRUE(below.stable) << n << " rpm, limit " << a << " m: growth " << below.growth;
    EXPECT_FALSE(above.stable) << n << " rpm, limit " << a << " m: growth " << above.growth;
  }
  // A coefficient in the wrong unit is refused by the simulation's law too.
  ForceLaw bad = linear_force_law(c);
  bad.process_damping_n_per_m = 2e11;
  EXPECT_NE(thrown_message([&] { bad.check(); }).find("ForceLaw::process_damping_n_per_m"), std::string::npos);
}

TEST(ProcessDamping, ImplausibleCoefficientNamesTheFieldAndUnit) {
  CuttingConditions c{4, 2e9, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  c.diameter_m = 0.02;
  c.process_damping_n_per_m = 2e11;  // N/m² (a cutting pressure) by mistake
  std::string m = thrown_message([&] { c.check(); });
  EXPECT_NE(m.find("CuttingConditions::process_damping_n_per_m"), std::string::npos) << m;
  EXPECT_NE(m.find("N/m"), std::string::npos) << m;
  // The indentation coefficient's range (kProcessDampingMin…Max, cutting_fields), said with "0: none".
  c.process_damping_n_per_m = 0.2;  // N/µm by mistake
  m = thrown_message([&] { c.check(); });
  EXPECT_NE(m.find("N/m must lie in 1000…1e+08 (0: none)"), std::string::npos) << m;
  c.process_damping_n_per_m = -1.0;
  m = thrown_message([&] { c.check(); });
  EXPECT_NE(m.find("N/m must lie in 1000…1e+08 (0: none)"), std::string::npos) << m;
  c.process_damping_n_per_m = 2e5;
  c.diameter_m = 0.0;
  EXPECT_NE(thrown_message([&] { c.check(); }).find("CuttingConditions::diameter_m"), std::string::npos);
}
