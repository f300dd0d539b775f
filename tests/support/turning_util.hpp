// The one-mode turning equation with process damping and its analytic stability limit (the delay
// equation's characteristic root on the imaginary axis, docs/reference.md §9): the oracle of the
// process-damping and semi-discretization tests.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "toolpoint/conventions.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/stability/stability.hpp"

namespace toolpoint::test {

// One-mode turning (orthogonal, plunge): m ẍ + c ẋ + k x = −K b (x − x(t − τ)) − (C_i b/V) ẋ,
// τ = 60/n, V = πD n/60 of the workpiece diameter D.
struct Turning {
  Mode mode{0.5, 0.02, 250.0};
  double k_cut = 2e9;        // K [N/m²]
  double c_i = 1e6;          // C_i [N/m]
  double diameter_m = 0.05;  // D [m]
  double stiffness() const { return mode.mass_kg * std::pow(omega_of(mode.frequency_hz), 2); }
  double damping() const { return 2.0 * mode.damping_ratio * mode.mass_kg * omega_of(mode.frequency_hz); }
  double speed(double n) const { return kPi * diameter_m * n / 60.0; }

  PeriodicDelaySystem system(double n) const {
    PeriodicDelaySystem s;
    const double w = omega_of(mode.frequency_hz);
    Eigen::MatrixXd a(2, 2);
    a << 0.0, 1.0, -w * w, -2.0 * mode.damping_ratio * w;
    s.a0_blocks = {a};
    s.input = Eigen::MatrixXd(2, 1);
    s.input << 0.0, 1.0 / mode.mass_kg;
    s.output = Eigen::MatrixXd(1, 2);
    s.output << 1.0, 0.0;
    s.period = 60.0 / n;
    s.regenerative = true;
    const double k = k_cut;
    s.current = [k](double, Eigen::MatrixXd& out) { out(0, 0) = -k; };
    Eigen::MatrixXd cv(1, 2);
    cv << 0.0, 1.0;
    const double g = -c_i / speed(n);
    if (c_i == 0.0) return s;
    return with_velocity_feedback(s, cv, [g](double, Eigen::MatrixXd& out) { out(0, 0) = g; });
  }

  // The analytic limit: a root s = iω of −mω² + iω(c + C_i b/V) + k + K b (1 − e^{−iωτ}) = 0.
  // The real part gives b(ω) = (mω² − k)/(K(1 − cos ωτ)); the imaginary part
  // g(ω) = ω(c + C_i b(ω)/V) + K b(ω) sin ωτ = 0 is solved for ω > ω_n by a fine scan and
  // bisection; the lowest positive b over the roots is the limit.
  double analytic_limit(double n) const {
    const double m = mode.mass_kg, k = stiffness(), c = damping(), tau = 60.0 / n, v = speed(n);
    auto b_of = [&](double w) { return (m * w * w - k) / (k_cut * (1.0 - std::cos(w * tau))); };
    auto g = [&](double w) { return w * (c + c_i * b_of(w) / v) + k_cut * b_of(w) * std::sin(w * tau); };
    const double wn = omega_of(mode.frequency_hz);
    double best = INFINITY;
    const int samples = 400000;
    double w0 = wn * (1.0 + 1e-9), g0 = g(w0);
    for (int i = 1; i <= samples; ++i) {
      const double w1 = wn * (1.0 + 2.0 * i / samples), g1 = g(w1);
      // A sign change across a pole of b (1 − cos ωτ = 0) is not a root: |g| is large there.
      if (std::isfinite(g0) && std::isfinite(g1) && (g0 < 0.0) != (g1 < 0.0) && std::abs(g0) + std::abs(g1) < 1e9) {
        double lo = w0, hi = w1, glo = g0;
        for (int it = 0; it < 100; ++it) {
          const double mid = 0.5 * (lo + hi), gm = g(mid);
          if ((gm < 0.0) == (glo < 0.0)) {
            lo = mid;
            glo = gm;
          } else {
            hi = mid;
          }
        }
        const double b = b_of(0.5 * (lo + hi));
        if (b > 0.0) best = std::min(best, b);
      }
      w0 = w1;
      g0 = g1;
    }
    return best;
  }

  // The discretized limit: ρ(b) = 1 by bisection on a map of `steps` steps (full-discretization of
  // degree 2 unless told).
  double discretized_limit(double n, int steps, double hi, int degree = 2, Discretization scheme = Discretization::Full) const {
    const PeriodMap map(system(n), steps, degree, scheme);
    double lo = 0.0;
    while (map.spectral_radius(hi) < 1.0) hi *= 2.0;
    for (int it = 0; it < 60 && hi - lo > 1e-10 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      (map.spectral_radius(mid) < 1.0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

}  // namespace toolpoint::test
