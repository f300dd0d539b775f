// Shared helpers for the tests: materials, block access, relative errors, peak finding on a
// model by golden-section search.
#pragma once

#include <cmath>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "toolpoint/model/beam.hpp"
#include "toolpoint/model/receptance.hpp"

namespace toolpoint::test {

// What `f` throws (what()), or "" when it does not throw.
inline std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

inline Material steel(double eta = 0.0) { return Material{"steel", 200e9, 0.3, 0.0, 7800.0, eta}; }
inline Material carbide(double eta = 0.0) { return Material{"carbide", 580e9, 0.22, 0.0, 14500.0, eta}; }

inline Complex entry_of(const Block& b, int k) { return b(k / 2, k % 2); }
inline const Block& block_of(const TwoPort& t, int j) { return j == 0 ? t.b11 : j == 1 ? t.b12 : j == 2 ? t.b21 : t.b22; }

// ‖a − b‖ / ‖b‖ over the four blocks.
inline double rel_error(const TwoPort& a, const TwoPort& b) {
  const double num = (a.b11 - b.b11).squaredNorm() + (a.b12 - b.b12).squaredNorm() + (a.b21 - b.b21).squaredNorm() +
                     (a.b22 - b.b22).squaredNorm();
  const double den = b.b11.squaredNorm() + b.b12.squaredNorm() + b.b21.squaredNorm() + b.b22.squaredNorm();
  return std::sqrt(num / den);
}
inline double rel_error(const Block& a, const Block& b) { return (a - b).norm() / b.norm(); }

// Frequencies of the local maxima of `mag` on [lo, hi], scanned with `step` and refined by
// golden-section search to 1e-10 relative.
inline std::vector<double> model_peaks(const std::function<double(double)>& mag, double lo, double hi, double step) {
  std::vector<double> out;
  double f0 = lo, m0 = mag(f0), f1 = lo + step, m1 = mag(f1);
  for (double f2 = lo + 2 * step; f2 <= hi; f2 += step) {
    const double m2 = mag(f2);
    if (m1 > m0 && m1 >= m2) {
      double a = f0, b = f2;
      const double g = (std::sqrt(5.0) - 1.0) / 2.0;
      double c = b - g * (b - a), d = a + g * (b - a), fc = mag(c), fd = mag(d);
      while (b - a > 1e-10 * b) {
        if (fc > fd) {
          b = d;
          d = c;
          fd = fc;
          c = b - g * (b - a);
          fc = mag(c);
        } else {
          a = c;
          c = d;
          fc = fd;
          d = a + g * (b - a);
          fd = mag(d);
        }
      }
      out.push_back(0.5 * (a + b));
    }
    f0 = f1;
    m0 = m1;
    f1 = f2;
    m1 = m2;
  }
  return out;
}

// Static cantilever flexibility (EI = 1, clamp at x = 0): deflection at x for a unit force at ξ,
// G = ξ²(3x − ξ)/6 for ξ ≤ x, symmetric otherwise. Exact tip values: N = L = 1/2, P = 1 (L = 1).
inline double cantilever_static(double x, double xi) {
  if (xi > x) std::swap(x, xi);
  return xi * xi * (3.0 * x - xi) / 6.0;
}

// A single FRF with `values` at f0, f0 + df, … [Hz].
inline FrfSeries single(std::vector<Complex> values, double f0 = 10.0, double df = 2.5) {
  FrfSeries s;
  for (std::size_t i = 0; i < values.size(); ++i) s.frequency_hz.push_back(f0 + df * static_cast<double>(i));
  s.values = std::move(values);
  return s;
}

// An integer from the environment (the long Monte Carlo studies' seed counts), or `fallback`.
inline int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

}  // namespace toolpoint::test
