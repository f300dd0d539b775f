// Shared helpers for the stability tests: the converged full-discretization limit at one speed.
#pragma once

#include <gtest/gtest.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/stability/stability.hpp"

namespace toolpoint::test {

// The Insperger–Stépán benchmark (docs/reference.md §7): its mode, cutting coefficients, and a
// 20 mm cutter; degrees in radians.
namespace benchmark {
inline constexpr double kDeg = kPi / 180.0;
inline const Mode kBench{0.03993, 0.011, 922.0};
inline constexpr double kKt = 6e8, kKn = 2e8, kDiameter = 0.02;
}  // namespace benchmark

// Hayes: ẋ = a x + b x(t − 1), written as A₀ = a, B = C = 1, Q = b, period 1.
inline PeriodicDelaySystem hayes(double a, double b) {
  PeriodicDelaySystem s;
  s.a0_blocks = {Eigen::MatrixXd::Constant(1, 1, a)};
  s.input = Eigen::MatrixXd::Ones(1, 1);
  s.output = Eigen::MatrixXd::Ones(1, 1);
  s.period = 1.0;
  s.delayed = [b](double, Eigen::MatrixXd& out) { out(0, 0) = b; };
  return s;
}

// The converged full-discretization limit at one speed [m] (estimated error ≤ 0.1 %, checked).
inline double converged_limit(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm) {
  BoundaryOptions o;
  o.speeds = {speed_rpm, speed_rpm * (1.0 + 1e-6), 2};
  o.tolerance = 1e-3;
  o.parallel.threads = 1;
  const BoundaryResult b = stability_boundary(model, cutting, o);
  EXPECT_NE(b.boundary[0].kind, BoundaryKind::None) << speed_rpm;
  EXPECT_LE(b.boundary[0].depth_error_m, 1e-3 * b.boundary[0].depth_m);
  return b.boundary[0].depth_m;
}

}  // namespace toolpoint::test
