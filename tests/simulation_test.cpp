// Tests of the time-domain milling simulation (simulation.hpp) against what the project already
// trusts and against closed forms, never against itself:
//   * the stability boundary of full-discretization (stability.hpp, converged to 0.1 %) on the
//     Insperger–Stépán 1-DOF benchmark (docs/reference.md §7), a/D 0.05 down-milling and slotting;
//   * the periodic solution x* = (I − Φ)⁻¹ q of the full-discretization map with the feed's forcing
//     (periodic_delay.hpp), and a frequency-domain SLE (Schmitz & Mann 2006: the forced response to
//     the Fourier series of the rigid-tool force, written out here);
//   * Altintas's closed-form mean milling forces, and the plan's closed-form torque;
//   * the exact free vibration of an undamped mode; the geometry of runout and variable pitch.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/plan.hpp"
#include "support/stability_util.hpp"

using namespace toolpoint;

namespace {

const Mode kBench{0.03993, 0.011, 922.0};  // docs/reference.md §7
constexpr double kKt = 6e8, kKn = 2e8, kFeed = 1e-4, kDiameter = 0.02;

CuttingConditions conditions(double immersion, MillingDirection dir = MillingDirection::Down, int teeth = 2) {
  return {teeth, kKt, kKn / kKt, engagement_from_immersion(immersion, dir)};
}

SimulationResult simulate(const ModalModel& model, const CuttingConditions& c, double speed_rpm, double depth_m,
                          SimulationOptions o = {}) {
  return simulate_milling(tool_dynamics(model), uniform_cutter(c.teeth, kDiameter), linear_force_law(c),
                          {speed_rpm, depth_m, kFeed, c.engagement}, o);
}

// The converged full-discretization limit at one speed (error estimate ≤ 0.1 %).
double fd_limit(const ModalModel& model, const CuttingConditions& c, double speed_rpm) {
  return test::converged_limit(model, c, speed_rpm);
}

}  // namespace

// (1) The simulated stable/unstable switch brackets the converged full-discretization limit. The
// simulation's own error in the boundary (its growth estimate against FD's ρ² per revolution:
// within 0.5 % of ρ at the automatic step, measured at 7000–20 000 rpm; docs/simulation.md) moves
// the switch by under 1 % of the depth; ±3 % leaves room for the finite run's decision (40
// revolutions, the last 20 analysed).
TEST(Simulation, StableUnstableSwitchBracketsTheFullDiscretizationLimit) {
  ModalModel model;
  model.x = {kBench};
  for (double immersion : {0.05, 1.0})
    for (double n : {5000.0, 7000.0, 10000.0, 15000.0, 20000.0, 25000.0}) {
      if (immersion == 1.0 && n > 20000.0) continue;  // the slot's limit there is beyond the FD search (10 × the floor)
      const CuttingConditions c = conditions(immersion);
      const double a = fd_limit(model, c, n);
      SimulationOptions o;
      o.record = false;
      const SimulationResult below = simulate(model, c, n, 0.97 * a, o);
      const SimulationResult above = simulate(model, c, n, 1.03 * a, o);
      EXPECT_TRUE(below.stable) << "a/D " << immersion << " at " << n << " rpm, limit " << a << " m: growth " << below.growth
                                << " metric " << below.chatter_metric;
      EXPECT_FALSE(above.stable) << "a/D " << immersion << " at " << n << " rpm, limit " << a << " m: growth " << above.growth
                                 << " metric " << above.chatter_metric;
    }
}

// The growth of the once-per-period deviation is the dominant Floquet multiplier: against
// full-discretization's ρ (degree 2 at 400 steps: converged to 1e-5), per revolution ρ^N, within
// 2 % (1 % of ρ: the simulation's own discretization at its automatic step, 56 steps per tooth at
// 20 000 rpm, measured 1.2 % there, and the least-squares fit over 15 revolutions).
TEST(Simulation, GrowthIsTheFloquetMultiplierPerRevolution) {
  ModalModel model;
  model.x = {kBench};
  for (double n : {7000.0, 12000.0, 20000.0}) {
    const CuttingConditions c = conditions(1.0);
    const double a = 0.8 * fd_limit(model, c, n);
    const double rho = PeriodMap(milling_delay_system(model, c, n), 400, 2).spectral_radius(a);
    SimulationOptions o;
    o.record = false;
    o.revolutions = 30;
    const SimulationResult r = simulate(model, c, n, a, o);
    EXPECT_NEAR(r.growth, rho * rho, 0.02 * rho * rho) << n << " rpm";
  }
}

// (2) The steady state of a stable cut is the periodic solution of the full-discretization map with
// the feed's forcing, x* = (I − Φ)⁻¹ q: once-per-tooth samples and the SLE agree within 1 % (the
// issue's bound; measured 2e-5 at these steps, the two methods' discretization errors). A 2-DOF
// tool, a/D 0.05 down-milling: the wall at φ = π is where the SLE is, SLE = y*.
TEST(Simulation, SteadyStateIsTheFullDiscretizationPeriodicSolution) {
  ModalModel model;
  model.x = {kBench};
  model.y = {kBench};
  const CuttingConditions c = conditions(0.05);
  const double n = 10000.0, a = 1e-3;
  const PeriodMap map(milling_delay_system(model, c, n, kFeed), 2000, 2);
  const PeriodMap::PeriodicSolution ps = map.periodic_solution(a);
  SimulationOptions o;
  o.revolutions = 150;
  o.steps_per_tooth = 800;
  const SimulationResult r = simulate(model, c, n, a, o);
  ASSERT_TRUE(r.stable);
  const double x = ps.outputs(0, 0), y = ps.outputs(1, 0);  // at t = 0 mod τ: a tooth at φ = 0, the other at π
  const MotionSample& s = r.per_tooth.back();
  EXPECT_NEAR(s.x_m, x, 1e-2 * std::abs(x));
  EXPECT_NEAR(s.y_m, y, 1e-2 * std::abs(y));
  ASSERT_EQ(r.walls.size(), 1u);
  EXPECT_DOUBLE_EQ(r.walls[0].angle_rad, kPi);
  EXPECT_NEAR(r.sle_m, y, 1e-2 * std::abs(y));
  // Measured agreement, far inside the bound: 1e-4.
  EXPECT_NEAR(r.sle_m, y, 1e-4 * std::abs(y));
  EXPECT_NEAR(s.x_m, x, 1e-4 * std::abs(x));
}

// (2, third method) Schmitz & Mann's frequency-domain SLE (IJMTM 46 (2006) 1; Schmitz & Smith,
// Machining Dynamics, §7.4): in the periodic steady state r(t) = r(t − τ), so the regenerative term
// vanishes and the force is the rigid tool's; r is its Fourier series through the receptance,
// r(t) = Σ_k G(kω_T) F_k e^{ikω_T t}, ω_T = NΩ, with F_k = (N/2π) ∫ f(φ) e^{−ikNφ} dφ over the
// engagement (f the force of one tooth, edge terms included). f is a trigonometric polynomial of
// degree 2 in φ, so F_k is exact in closed form; summed to k = 20 000 (tail ~1e-9: F_k ~ 1/k from
// the force's jumps, G ~ 1/k²). Three modes, one of them coupling x and y; down and up milling.
TEST(Simulation, SurfaceLocationErrorMatchesTheFrequencyDomainSolution) {
  using C = std::complex<double>;
  ToolDynamics dyn;
  dyn.modes = {planar_mode(kBench, 0.0), planar_mode({0.05, 0.02, 1300.0}, kPi / 2), planar_mode({0.2, 0.03, 600.0}, 0.6)};
  const int teeth = 3;
  const double kt = kKt, kr = 0.3, kte = 2e4, kre = 1e4;
  ForceLaw law{kt, kr, kte, kre};
  for (MillingDirection dir : {MillingDirection::Down, MillingDirection::Up}) {
    const Engagement e = engagement_from_immersion(0.25, dir);
    const double n = 9000.0, a = 3e-4, spin = 2.0 * kPi * n / 60.0;
    // f(φ) = Σ_ν A_ν e^{iνφ}, ν = −2…2, from F_t = a(K_te + K_t c sinφ), F_r = a(K_re + K_r K_t c sinφ),
    // f = F_t(−cosφ, sinφ) + F_r(−sinφ, −cosφ): terms in cosφ, sinφ, sinφcosφ and sin²φ.
    auto coefficients = [&](double w_cos, double w_sin, double w_sincos, double w_sin2) {
      std::array<C, 5> A{};  // index ν + 2
      const C i(0.0, 1.0);
      A[3] += w_cos / 2.0;
      A[1] += w_cos / 2.0;
      A[3] += w_sin / (2.0 * i);
      A[1] -= w_sin / (2.0 * i);
      A[4] += w_sincos / (4.0 * i);
      A[0] -= w_sincos / (4.0 * i);
      A[2] += w_sin2 / 2.0;
      A[4] -= w_sin2 / 4.0;
      A[0] -= w_sin2 / 4.0;
      return A;
    };
    const auto ax = coefficients(-a * kte, -a * kre, -a * kt * kFeed, -a * kr * kt * kFeed);
    const auto ay = coefficients(-a * kre, a * kte, -a * kr * kt * kFeed, a * kt * kFeed);
    auto integral = [&](int q) {  // ∫ e^{iqφ} dφ over the engagement
      if (q == 0) return C(e.exit_rad - e.entry_rad, 0.0);
      return (std::exp(C(0.0, q * e.exit_rad)) - std::exp(C(0.0, q * e.entry_rad))) / C(0.0, q);
    };
    const double phi_s = dir == MillingDirection::Down ? kPi : 0.0, ts = phi_s / spin;
    Eigen::Vector2cd r = Eigen::Vector2cd::Zero();
    for (int k = 0; k <= 20000; ++k) {
      C fx = 0.0, fy = 0.0;
      for (int nu = -2; nu <= 2; ++nu) {
        const C in = integral(nu - k * teeth) * (teeth / (2.0 * kPi));
        fx += ax[static_cast<std::size_t>(nu + 2)] * in;
        fy += ay[static_cast<std::size_t>(nu + 2)] * in;
      }
      const Eigen::Matrix2cd g = dyn.receptance(k * teeth * n / 60.0);
      r += (k == 0 ? 1.0 : 2.0) * (g * Eigen::Vector2cd(fx, fy)) * std::exp(C(0.0, k * teeth * spin * ts));
    }
    const double sle_fd = -(std::sin(phi_s) * r(0).real() + std::cos(phi_s) * r(1).real());
    SimulationOptions o;
    o.revolutions = 120;
    o.steps_per_tooth = 600;
    o.record = false;
    const SimulationResult s = simulate_milling(dyn, uniform_cutter(teeth, kDiameter), law, {n, a, kFeed, e}, o);
    ASSERT_TRUE(s.stable);
    EXPECT_NEAR(s.sle_m, sle_fd, 1e-2 * std::abs(sle_fd)) << (dir == MillingDirection::Down ? "down" : "up");
    EXPECT_NEAR(s.sle_m, sle_fd, 1e-5 * std::abs(sle_fd)) << "measured agreement 4e-7";
  }
}

// (3) A rigid tool: the mean forces are Altintas's closed form (Manufacturing Automation, 2nd ed.,
// Eq. 2.20, edge terms included),
//   F̄x = {(N a c/8π)[K_t cos2φ − K_r(2φ − sin2φ)] + (N a/2π)[−K_te sinφ + K_re cosφ]} from φ_st to φ_ex,
//   F̄y = {(N a c/8π)[K_t(2φ − sin2φ) + K_r cos2φ] − (N a/2π)[K_te cosφ + K_re sinφ]},
// to 1e-6 relative (the force's piecewise-linear representation errs by (dφ)²/12 ≈ 2e-7 at 4000
// steps per revolution); the torque and power those of the plan's closed form (torque_per_depth).
TEST(Simulation, RigidToolMeanForcesAreAltintasClosedForm) {
  for (auto [imm, dir] : {std::pair{0.3, MillingDirection::Down}, {0.7, MillingDirection::Up}, {1.0, MillingDirection::Down}}) {
    const int teeth = 4;
    const double a = 2e-3, c = 1.2e-4, kte = 3e4, kre = 1.5e4, kt = 8e8, krc = 2.4e8;
    const Engagement e = engagement_from_immersion(imm, dir);
    ForceLaw law{kt, krc / kt, kte, kre};
    SimulationOptions o;
    o.revolutions = 2;
    o.steps_per_tooth = 1000;
    const SimulationResult r = simulate_milling({}, uniform_cutter(teeth, kDiameter), law, {6000.0, a, c, e}, o);
    auto fx = [&](double p) {
      return teeth * a * c / (8 * kPi) * (kt * std::cos(2 * p) - krc * (2 * p - std::sin(2 * p))) +
             teeth * a / (2 * kPi) * (-kte * std::sin(p) + kre * std::cos(p));
    };
    auto fy = [&](double p) {
      return teeth * a * c / (8 * kPi) * (kt * (2 * p - std::sin(2 * p)) + krc * std::cos(2 * p)) -
             teeth * a / (2 * kPi) * (kte * std::cos(p) + kre * std::sin(p));
    };
    const double ex = fx(e.exit_rad) - fx(e.entry_rad), ey = fy(e.exit_rad) - fy(e.entry_rad);
    const double scale = std::hypot(ex, ey);
    EXPECT_NEAR(r.mean_force_x_n, ex, 1e-6 * scale) << imm;
    EXPECT_NEAR(r.mean_force_y_n, ey, 1e-6 * scale) << imm;
    const CuttingConditions cc{teeth, kt, krc / kt, e};
    const double torque = a * torque_per_depth(cc, kDiameter, c, kte);
    EXPECT_NEAR(r.mean_torque_nm, torque, 1e-6 * torque);
    EXPECT_NEAR(r.power_w, a * power_per_depth(cc, kDiameter, c, kte, 6000.0), 1e-6 * r.power_w);
    // A helix only shifts the slices' phases: the mean over a revolution is the same.
    Cutter helical = uniform_cutter(teeth, kDiameter);
    helical.helix_rad = 30.0 * kPi / 180.0;
    const SimulationResult rh = simulate_milling({}, helical, law, {6000.0, a, c, e}, o);
    EXPECT_GT(rh.slices, 10);
    EXPECT_NEAR(rh.mean_force_x_n, ex, 1e-6 * scale) << imm;
    EXPECT_NEAR(rh.mean_force_y_n, ey, 1e-6 * scale) << imm;
    EXPECT_LT(rh.peak_force_n, r.peak_force_n);  // the helix spreads the entry over the slices
  }
}

// (4) Free vibration of an undamped mode: the propagator is exact, so after 1000 revolutions
// (~10⁶ steps) the energy and the phase are those of x(t) = x₀ cos ωt + (v₀/ω) sin ωt to rounding
// (2·10⁵ steps × ~1e-16 per step: 1e-10 for the energy and 1e-9 of the amplitude for the
// displacement; measured 1.5e-11 and 1e-11). No scheme error at all: the order shows only when a
// force acts (ConvergesAtSecondOrder).
TEST(Simulation, FreeVibrationOfAnUndampedModeKeepsItsEnergy) {
  ToolDynamics dyn;
  dyn.modes = {planar_mode({0.04, 0.0, 922.0}, 0.0)};
  SimulationOptions o;
  o.revolutions = 200;
  o.steps_per_tooth = 500;
  o.initial_state = {1e-6, 2e-3};  // q [m kg^½], q̇
  const double w = omega_of(922.0), q0 = 1e-6, v0 = 2e-3, psi = 1.0 / std::sqrt(0.04);
  const SimulationResult r = simulate_milling(dyn, uniform_cutter(2, kDiameter), {kKt},
                                              {7000.0, 0.0, kFeed, conditions(0.5).engagement}, o);
  const double e0 = 0.5 * (v0 * v0 + w * w * q0 * q0);
  const double amplitude = psi * std::sqrt(2.0 * e0) / w;
  for (std::size_t k : {r.time_s.size() / 3, r.time_s.size() - 1}) {
    const double q = r.x_m[k] / psi, v = r.vx_m_per_s[k] / psi;
    EXPECT_NEAR(0.5 * (v * v + w * w * q * q), e0, 1e-10 * e0);
    const double t = r.time_s[k];
    EXPECT_NEAR(r.x_m[k], psi * (q0 * std::cos(w * t) + v0 / w * std::sin(w * t)), 1e-9 * amplitude);
  }
}

// The measured order of the scheme: against the periodic solution of full-discretization at 8000
// steps (third order: converged to 1e-9 here), the error of the once-per-tooth samples falls 4× per
// halving of the step (second order; measured ratios 3.8–4.6 from 200 to 1600 steps per tooth).
TEST(Simulation, ConvergesAtSecondOrder) {
  ModalModel model;
  model.x = {kBench};
  const CuttingConditions c = conditions(0.05);
  const double n = 10000.0, a = 2e-3;
  const double x = PeriodMap(milling_delay_system(model, c, n, kFeed), 8000, 2).periodic_solution(a).outputs(0, 0);
  std::vector<double> err;
  for (int m : {200, 400, 800, 1600}) {
    SimulationOptions o;
    o.revolutions = 120;
    o.steps_per_tooth = m;
    o.record = false;
    err.push_back(std::abs(simulate(model, c, n, a, o).per_tooth.back().x_m - x) / std::abs(x));
  }
  for (std::size_t i = 0; i + 1 < err.size(); ++i) {
    const double order = std::log2(err[i] / err[i + 1]);
    EXPECT_GT(order, 1.7) << i;
    EXPECT_LT(order, 2.3) << i;
  }
}

// (4) Uniform pitch, no runout: every tooth's force is the same curve, a tooth period apart (exactly
// for a rigid tool; to 1e-9 of the peak in a stable cut's steady state).
TEST(Simulation, UniformPitchGivesTheSameForceOnEveryTooth) {
  ModalModel model;
  model.x = {kBench};
  model.y = {kBench};
  const CuttingConditions c = conditions(0.5, MillingDirection::Down, 4);
  for (bool rigid : {true, false}) {
    SimulationOptions o;
    o.revolutions = 200;  // the transient decays by 0.83 per revolution here: 1e-16 by the end
    o.steps_per_tooth = 100;
    const SimulationResult r = rigid ? simulate({}, c, 8000.0, 1e-3, o) : simulate(model, c, 8000.0, 5e-5, o);
    ASSERT_TRUE(r.stable) << r.growth;
    const std::size_t m = 100, last = r.tooth_force_n[0].size() - 1, start = last - 400;
    double peak = 0.0;
    for (std::size_t k = start; k <= last; ++k) peak = std::max(peak, r.tooth_force_n[0][k]);
    ASSERT_GT(peak, 0.0);
    for (std::size_t j = 1; j < 4; ++j)
      for (std::size_t k = start; k <= last; ++k)
        ASSERT_NEAR(r.tooth_force_n[j][k], r.tooth_force_n[0][k - j * m], (rigid ? 1e-12 : 1e-9) * peak) << j << " " << k;
  }
}

// (5) Runout, rigid tool: the chip of tooth j is the geometry's, h_j = max(0, min_{k=1…N}(k c sin φ
// + ρ_j − ρ_{j−k})) (the surface of every earlier tooth; Altintas §2.4), so its force at every step
// is K_t a h_j + K_te a where h_j > 0, to 1e-9; everything repeats once per revolution; the wall
// is left by the largest tooth: SLE = −max ρ_j.
TEST(Simulation, RunoutRepeatsOncePerRevolutionWithTheGeometrysChips) {
  const int teeth = 4;
  Cutter cutter = uniform_cutter(teeth, kDiameter);
  cutter.runout_m = {12e-6, -3e-6, 0.0, 150e-6};  // tooth 3 so far out that tooth 0 behind it cuts air at times
  const double c = 1e-4, a = 1e-3, kte = 2e4;
  ForceLaw law{kKt, 0.3, kte, 0.0};
  const Engagement e = engagement_from_immersion(0.5, MillingDirection::Down);
  SimulationOptions o;
  o.revolutions = 5;
  o.steps_per_tooth = 90;
  const SimulationResult r = simulate_milling({}, cutter, law, {5000.0, a, c, e}, o);
  const int M = r.steps_per_revolution;
  const double dphi = 2 * kPi / M;
  double checked = 0, zero = 0;
  for (int j = 0; j < teeth; ++j)
    for (long k = 2L * M; k <= 3L * M; ++k) {  // from the third revolution: the start's surfaces are gone
      const double phi = std::fmod(k * dphi - j * kPi / 2 + 8 * kPi, 2 * kPi);
      double expected = 0.0;
      // At φ = π the chip is 0 (the tooth meets its own wall of a revolution before): the edge force jumps there.
      if (std::abs(phi - e.exit_rad) < 1e-9) continue;
      if (phi >= e.entry_rad && phi <= e.exit_rad) {
        double chip = 1e9;
        for (int q = 1; q <= teeth; ++q)
          chip = std::min(chip, q * c * std::sin(phi) + cutter.runout_m[j] - cutter.runout_m[(j - q + 4 * teeth) % teeth]);
        if (chip > 0.0) expected = a * (kKt * chip + kte);
        else ++zero;
        ++checked;
      }
      ASSERT_NEAR(r.tooth_force_n[j][k], expected, 1e-9 * a * kKt * c) << j << " " << k;
      ASSERT_EQ(r.tooth_force_n[j][k], r.tooth_force_n[j][k + M]);  // once per revolution
    }
  EXPECT_GT(zero, 0);  // the runout is large enough that a tooth leaves the cut
  EXPECT_GT(checked, 100);
  ASSERT_EQ(r.walls.size(), 1u);
  EXPECT_NEAR(r.sle_m, -150e-6, 1e-15);
}

// Variable pitch: tooth j's feed is N c p_j/2π (its spacing from the tooth ahead), so a rigid tool's
// chip is that feed × sin φ, exactly, although the delays fall between steps (interpolated).
TEST(Simulation, VariablePitchFeedsEachToothItsShare) {
  Cutter cutter;
  cutter.diameter_m = kDiameter;
  const double deg = kPi / 180.0;
  cutter.pitch_rad = {83.3 * deg, 96.7 * deg, 83.3 * deg, 96.7 * deg};  // from tooth j to j + 1
  const double c = 1e-4, a = 1e-3;
  ForceLaw law{kKt, 0.3};
  const Engagement e = engagement_from_immersion(1.0, MillingDirection::Down);
  SimulationOptions o;
  o.revolutions = 3;
  o.steps_per_tooth = 77;
  const SimulationResult r = simulate_milling({}, cutter, law, {5000.0, a, c, e}, o);
  const int M = r.steps_per_revolution;
  double theta = 0.0;
  for (int j = 0; j < 4; ++j) {
    const double p_in = cutter.pitch_rad[(j + 3) % 4], feed = 4 * c * p_in / (2 * kPi);
    for (long k = M; k <= 2L * M; ++k) {
      const double phi = std::fmod(k * 2 * kPi / M + theta + 8 * kPi, 2 * kPi);
      const double expected = phi >= 0.0 && phi <= kPi ? a * kKt * feed * std::sin(phi) : 0.0;
      ASSERT_NEAR(r.tooth_force_n[j][k], expected, 1e-9 * a * kKt * c) << j << " " << k;
    }
    theta -= cutter.pitch_rad[j];
  }
}

// Bad input: clear errors naming the field.
TEST(Simulation, BadInputNamesTheField) {
  ModalModel model;
  model.x = {kBench};
  const CuttingConditions c = conditions(0.5);
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SimulationOptions coarse;
  coarse.steps_per_tooth = 4;  // at 2000 rpm a 7.5 ms tooth period: 4 steps, 1.9 ms > a quarter of 1.08 ms
  EXPECT_NE(message([&] { simulate(model, c, 2000.0, 1e-3, coarse); }).find("SimulationOptions::steps_per_tooth"),
            std::string::npos);
  Cutter short_flutes = uniform_cutter(2, kDiameter);
  short_flutes.flute_length_m = 0.01;
  EXPECT_NE(message([&] {
              simulate_milling(tool_dynamics(model), short_flutes, linear_force_law(c), {8000.0, 0.012, kFeed, c.engagement});
            }).find("Cutter::flute_length_m"),
            std::string::npos);
  Cutter odd = uniform_cutter(3, kDiameter);
  odd.pitch_rad = {2.0, 2.0, 2.0};
  EXPECT_NE(message([&] { odd.check(); }).find("Cutter::pitch_rad"), std::string::npos);
  Cutter wobbly = uniform_cutter(2, kDiameter);
  wobbly.runout_m = {0.0, 0.011};
  EXPECT_NE(message([&] { wobbly.check(); }).find("Cutter::runout_m[1]"), std::string::npos);
  SimulationOptions huge;
  huge.revolutions = 1000000;
  huge.steps_per_tooth = 100000;
  EXPECT_NE(message([&] { simulate(model, c, 8000.0, 1e-3, huge); }).find("physical memory"), std::string::npos);
  SimulationOptions capped;
  capped.memory_limit_bytes = 1e5;
  EXPECT_NE(message([&] { simulate(model, c, 8000.0, 1e-3, capped); }).find("SimulationOptions::memory_limit_bytes"),
            std::string::npos);
  EXPECT_NE(message([&] { ForceLaw{-1.0}.check(); }).find("ForceLaw::tangential_coefficient"), std::string::npos);
  EXPECT_NE(message([&] {
              MillingCut{8000.0, -1.0, kFeed, c.engagement}.check();
            }).find("MillingCut::depth_m"),
            std::string::npos);
}

// The exponential force law, rigid tool: the mean forces are the engagement's average of
// F_t = a[K_te + K_t h₀(c sinφ/h₀)^x], F_r likewise, taken here by composite Simpson on 2·10⁵ panels
// (a quadrature of the law itself, not of the scheme); 1e-4 relative: the law's infinite slope
// where the chip starts at 0 (up-milling's entry) costs the scheme's linear pieces accuracy there.
TEST(Simulation, ExponentialLawMeanForcesAreTheLawsAverage) {
  for (MillingDirection dir : {MillingDirection::Up, MillingDirection::Down}) {
    const int teeth = 3;
    const double a = 1e-3, c = 8e-5, x = 0.7, h0 = 1e-4;
    ForceLaw law{7e8, 0.35, 1.5e4, 8e3, x, h0};
    const Engagement e = engagement_from_immersion(0.4, dir);
    SimulationOptions o;
    o.revolutions = 2;
    o.steps_per_tooth = 2000;
    const SimulationResult r = simulate_milling({}, uniform_cutter(teeth, kDiameter), law, {7000.0, a, c, e}, o);
    const int panels = 200000;
    const double d = (e.exit_rad - e.entry_rad) / panels;
    double fx = 0.0, fy = 0.0;
    for (int i = 0; i <= 2 * panels; ++i) {
      const double phi = e.entry_rad + 0.5 * i * d, w = (i == 0 || i == 2 * panels) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      const double hc = h0 * std::pow(std::max(0.0, c * std::sin(phi)) / h0, x);
      const double ft = a * (law.tangential_edge + law.tangential_coefficient * hc);
      const double fr = a * (law.radial_edge + law.radial_ratio * law.tangential_coefficient * hc);
      fx += w * (-ft * std::cos(phi) - fr * std::sin(phi));
      fy += w * (ft * std::sin(phi) - fr * std::cos(phi));
    }
    fx *= d / 6.0 * teeth / (2.0 * kPi);
    fy *= d / 6.0 * teeth / (2.0 * kPi);
    const double scale = std::hypot(fx, fy);
    EXPECT_NEAR(r.mean_force_x_n, fx, 1e-4 * scale) << (dir == MillingDirection::Up ? "up" : "down");
    EXPECT_NEAR(r.mean_force_y_n, fy, 1e-4 * scale) << (dir == MillingDirection::Up ? "up" : "down");
  }
}
