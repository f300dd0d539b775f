// Tests of the helix in the full-discretization stability (stability.hpp's CuttingConditions::
// helix_rad, milling_delay_system_at_depth: the directional matrix integrated over the lagged
// angles, a variable helix through axial slices) against what is independent of that code:
//   * the straight-flute path (today's point evaluation of A(φ)), for a helix so small that its lag
//     is below rounding;
//   * the averaged (constant-coefficient) system, which a uniform helix whose lag over the depth is
//     exactly one pitch reproduces identically (the teeth's windows tile the revolution), built
//     from directional_factors (docs/reference.md §7);
//   * the time-domain simulation (simulation.hpp: its own slices, edges lagging by z tan β/R, each
//     against the surface the tooth ahead left at the same height) and its stable/unstable switch.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "support/stability_util.hpp"
#include "support/test_util.hpp"

using namespace toolpoint;

namespace {

using namespace test::benchmark;
using test::thrown_message;

CuttingConditions cut(int teeth, std::vector<double> helix_deg, double immersion, MillingDirection dir) {
  CuttingConditions c{teeth, kKt, kKn / kKt, engagement_from_immersion(immersion, dir)};
  for (double b : helix_deg) c.helix_rad.push_back(b * kDeg);
  c.diameter_m = kDiameter;
  return c;
}

ModalModel two_dof() {
  ModalModel model;
  model.x = {kBench};
  model.y = {Mode{0.05, 0.02, 1100.0}};
  return model;
}

}  // namespace

// helix_rad {0}: not helical, today's path bit for bit (the dispatch). A helix of 1e-10 rad takes
// the new path — the directional matrix integrated in closed form over lagged angles of ~1e-11
// rad — and must give the straight flutes' limits to 1e-9 relative (roots narrowed to 1e-12; the
// lag itself moves the limit by ~1e-11). A variable helix of 1e-10/2e-10 rad also takes the
// revolution map with its slices and per-slice delays (as the variable-pitch test, 40 steps per
// tooth so that the delays are whole steps).
TEST(Helix, VanishingHelixReproducesStraightFlutes) {
  const ModalModel model = two_dof();
  for (auto dir : {MillingDirection::Down, MillingDirection::Up}) {
    const CuttingConditions straight = cut(4, {}, 0.3, dir), zero = cut(4, {0.0}, 0.3, dir);
    CuttingConditions tiny = straight, varied = straight;
    tiny.helix_rad = {1e-10};
    varied.helix_rad = {1e-10, 2e-10, 1e-10, 2e-10};
    ASSERT_FALSE(zero.helical());
    ASSERT_TRUE(tiny.helical() && tiny.uniform());
    ASSERT_FALSE(varied.uniform());
    const FullDiscretization fs(model, straight, 40), fz(model, zero, 40), ft(model, tiny, 40), fv(model, varied, 40);
    for (double n : {6000.0, 9000.0, 14000.0}) {
      const BoundaryPoint bs = fs.boundary(n, 0.02, 50, 1e-12);
      ASSERT_NE(bs.kind, BoundaryKind::None) << n;
      EXPECT_EQ(fz.boundary(n, 0.02, 50, 1e-12).depth_m, bs.depth_m) << n;
      const BoundaryPoint bt = ft.boundary(n, 0.02, 50, 1e-12), bv = fv.boundary(n, 0.02, 50, 1e-12);
      EXPECT_NEAR(bt.depth_m, bs.depth_m, 1e-9 * bs.depth_m) << n;
      EXPECT_NEAR(bv.depth_m, bs.depth_m, 1e-9 * bs.depth_m) << n;
      EXPECT_NEAR(bt.chatter_hz, bs.chatter_hz, 1e-6 * bs.chatter_hz) << n;
      EXPECT_EQ(bv.lobe, bs.lobe) << n;
    }
  }
}

// A uniform helix whose lag over the depth is exactly one pitch (κa = 2π/N): the teeth's windows
// [φ_j − 2π/N, φ_j] tile the revolution, so P(t) is the constant (N/2π)·½K_t·α(φ_st, φ_ex) — the
// zero-order method's averaged matrix, from directional_factors. The same map with that constant
// coefficient has the same multipliers: 1e-10 (the coefficient's closed forms to rounding; the map
// is otherwise the same, so quadrature errors are shared).
TEST(Helix, LagOfOnePitchGivesTheAveragedSystem) {
  const ModalModel model = two_dof();
  for (auto dir : {MillingDirection::Down, MillingDirection::Up})
    for (double beta : {20.0, 45.0}) {
      const CuttingConditions c = cut(4, {beta}, 0.3, dir);
      const double depth = 2.0 * kPi / 4.0 * 0.5 * kDiameter / std::tan(beta * kDeg);
      for (double n : {5000.0, 11000.0}) {
        const PeriodicDelaySystem helical = milling_delay_system_at_depth(model, c, n, depth);
        PeriodicDelaySystem averaged = helical;
        const Eigen::Matrix2d p = 4.0 / (2.0 * kPi) * 0.5 * kKt * directional_factors(c);
        averaged.current = [p](double, Eigen::MatrixXd& out) { out = p; };
        const double scale = 1e-4 / depth;  // a gain near the limits, not the depth itself
        const double rh = PeriodMap(helical, 60, 2).spectral_radius(depth * scale);
        const double ra = PeriodMap(averaged, 60, 2).spectral_radius(depth * scale);
        EXPECT_NEAR(rh, ra, 1e-10) << beta << "° " << n << " rpm";
      }
    }
}

// The small-depth limit: at a fixed gain σ the helical map built at depth a tends to the straight
// one as a → 0, like a (the window [φ − κa, φ] averages A about φ − κa/2: a first-order shift).
// The difference in ρ must halve with a (ratio 1.7…2.3 per halving, 7e-5…6e-4 rad of lag) and be
// below 1e-3 at the smallest.
TEST(Helix, SmallDepthTendsToStraightFlutes) {
  const ModalModel model = two_dof();
  const CuttingConditions c = cut(4, {30.0}, 0.3, MillingDirection::Down);
  CuttingConditions straight = c;
  straight.helix_rad.clear();
  const double n = 9000.0, gain = 4e-4;
  const double rs = PeriodMap(milling_delay_system(model, straight, n), 80, 2).spectral_radius(gain);
  std::vector<double> diff;
  for (double depth : {1e-5, 5e-6, 2.5e-6, 1.25e-6})
    diff.push_back(std::abs(PeriodMap(milling_delay_system_at_depth(model, c, n, depth), 80, 2).spectral_radius(gain) - rs));
  for (std::size_t i = 1; i < diff.size(); ++i) {
    EXPECT_GT(diff[i - 1] / diff[i], 1.7) << i;
    EXPECT_LT(diff[i - 1] / diff[i], 2.3) << i;
  }
  EXPECT_LT(diff.back(), 1e-3);
}

// The simulation's stable/unstable switch (stable at 0.97 a, unstable at 1.03 a: its stated error,
// variable_pitch_test.cpp) around the converged limit a, the stable run in the cut throughout.
static void expect_switch_at(const ModalModel& model, const CuttingConditions& c, const Cutter& cutter, double n,
                             int revolutions) {
  const double a = test::converged_limit(model, c, n);
  SimulationOptions so;
  so.record = false;
  so.revolutions = revolutions;
  const ForceLaw law = linear_force_law(c);
  const SimulationResult below = simulate_milling(tool_dynamics(model), cutter, law, {n, 0.97 * a, 1e-4, c.engagement}, so);
  const SimulationResult above = simulate_milling(tool_dynamics(model), cutter, law, {n, 1.03 * a, 1e-4, c.engagement}, so);
  EXPECT_EQ(below.out_of_cut_fraction, 0.0) << n;
  EXPECT_TRUE(below.stable) << n << " rpm, limit " << a << " m: growth " << below.growth << " metric " << below.chatter_metric;
  EXPECT_FALSE(above.stable) << n << " rpm, limit " << a << " m: growth " << above.growth;
}

// A low-immersion cut (a/D 0.05 down-milling, 4 teeth of a 20 mm cutter, the 1-DOF benchmark mode,
// K_t lowered to 1.5e8 N/m² so that the limits, 9–22 mm, give a 30° helix a lag of 30–70° over the
// depth). There the helix suppresses flip lobes: the limit rises 1.5× at 5000 rpm, 1.8× at 8000
// rpm and falls 12 % at 9000 rpm against straight flutes (checked: more than 10 % either way, so
// that agreeing with the simulation tests the helix). The simulation (its own slices, one per step
// of lag) switches within ±3 % of the helical limit at each. Not at 7000 rpm: there the limit (35
// mm) lies where the simulated teeth leave the cut below it (6 % of the samples), its nonlinear regime.
TEST(Helix, SimulationSwitchBracketsTheLimit) {
  ModalModel model;
  model.x = {kBench};
  CuttingConditions c = cut(4, {30.0}, 0.05, MillingDirection::Down);
  c.tangential_coefficient = 1.5e8;
  CuttingConditions straight = c;
  straight.helix_rad.clear();
  Cutter cutter = uniform_cutter(4, kDiameter);
  cutter.helix_rad = 30.0 * kDeg;
  for (double n : {5000.0, 8000.0, 9000.0}) {
    const double a = test::converged_limit(model, c, n), a0 = test::converged_limit(model, straight, n);
    EXPECT_GT(std::abs(a / a0 - 1.0), 0.1) << n << " rpm: helical " << a << " straight " << a0;
    expect_switch_at(model, c, cutter, n, 40);
  }
}

// A variable helix, 30°/40°/30°/40°, in the same cut: the teeth's delays change along z (8 slices).
// Its limits differ from the uniform 30° helix's by more than 5 % at the speeds checked (6000,
// 10 000, 12 000 rpm: +17 %, +6 %, +6 %) and the simulation (Cutter::tooth_helix_rad: each slice
// against the tooth ahead at the same height) switches within ±3 % of them. 100 revolutions: with
// 40, the growth fit at 11 000 rpm still carried the start's transient (1.004 at 0.97 a, 0.989 with
// 100). Slices: 8 and 32 give limits within 0.03 % at these speeds (checked to 0.3 %); at 3000 rpm,
// where the limit is 30 mm deep and the teeth's lags drift apart by 45° over it, 8 slices are 11 %
// below the limit of 16 or 32 (the slice count matters where that drift is large).
TEST(VariableHelix, SimulationSwitchBracketsTheLimit) {
  ModalModel model;
  model.x = {kBench};
  CuttingConditions c = cut(4, {30.0, 40.0, 30.0, 40.0}, 0.05, MillingDirection::Down);
  c.tangential_coefficient = 1.5e8;
  CuttingConditions uniform = c, fine = c;
  uniform.helix_rad = {30.0 * kDeg};
  fine.helix_slices = 32;
  Cutter cutter = uniform_cutter(4, kDiameter);
  cutter.tooth_helix_rad = c.helix_rad;
  for (double n : {6000.0, 10000.0, 12000.0}) {
    const double a = test::converged_limit(model, c, n), au = test::converged_limit(model, uniform, n);
    EXPECT_GT(std::abs(a / au - 1.0), 0.05) << n << " rpm: variable " << a << " uniform " << au;
    EXPECT_NEAR(test::converged_limit(model, fine, n), a, 3e-3 * a) << n;
    expect_switch_at(model, c, cutter, n, 100);
  }
}

TEST(Helix, BadHelixNamesTheField) {
  CuttingConditions c = cut(4, {-10.0}, 0.5, MillingDirection::Down);
  const std::string negative = thrown_message([&] { c.check(); });
  EXPECT_NE(negative.find("CuttingConditions::helix_rad[0]"), std::string::npos) << negative;
  c.helix_rad = {90.0 * kDeg};
  EXPECT_NE(thrown_message([&] { c.check(); }).find("must lie in 0…80°"), std::string::npos);
  c.helix_rad = {30.0 * kDeg, 35.0 * kDeg};
  EXPECT_NE(thrown_message([&] { c.check(); }).find("2 angles for 4 teeth"), std::string::npos);
  c.helix_rad = {30.0 * kDeg};
  c.diameter_m = 0.0;
  EXPECT_NE(thrown_message([&] { c.check(); }).find("CuttingConditions::diameter_m"), std::string::npos);
  c.diameter_m = kDiameter;
  c.helix_slices = 500;
  EXPECT_NE(thrown_message([&] { c.check(); }).find("CuttingConditions::helix_slices"), std::string::npos);
  c.helix_slices = 0;
  // The map depends on the depth: the depth-free builder refuses, the zero-order method too.
  EXPECT_NE(thrown_message([&] { milling_delay_system(two_dof(), c, 9000.0); }).find("depends on the depth"), std::string::npos);
  const MillingFrfs frfs = modal_milling_frfs({kBench}, {}, modal_frequency_grid({kBench}));
  ZeroOrderOptions zo;
  zo.speeds = {5000.0, 10000.0, 100};
  EXPECT_NE(thrown_message([&] { zero_order_lobes(frfs, c, zo); }).find("helix_rad"), std::string::npos);
}
