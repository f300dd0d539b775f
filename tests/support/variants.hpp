// The single-degree-of-freedom receptance the files of tests/data/variants/ hold (make_variants.py,
// in Python; computed again here), for the tests that read them, through the library or the CLI.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "toolpoint/io/frf_file.hpp"

namespace toolpoint::test {

inline const std::string kVariantsDir = std::string(TOOLPOINT_TEST_DATA_DIR) + "/variants/";

// The oscillator of make_variants.py: m = 0.04 kg, fn = 1600 Hz, ζ = 0.02 (half-power bandwidth
// 2ζ·fn = 64 Hz).
inline Complex sdof(double f) {
  const double m = 0.04, wn = 2.0 * std::numbers::pi * 1600.0, zeta = 0.02;
  const double k = m * wn * wn, c = 2.0 * zeta * std::sqrt(k * m), w = 2.0 * std::numbers::pi * f;
  return 1.0 / Complex(k - m * w * w, c * w);
}
// sdof sampled every `step` Hz from `from` to `to` (inclusive to rounding).
inline FrfSeries sdof_series(double from, double to, double step) {
  FrfSeries s;
  for (double f = from; f <= to + 1e-9; f += step) {
    s.frequency_hz.push_back(f);
    s.values.push_back(sdof(f));
  }
  return s;
}
inline double coherence(double f) { return 0.9 + 0.09 * std::sin(f / 300.0); }
inline const std::vector<double> kVariantFrequencies = {1000, 1200, 1400, 1600, 1800, 2000, 2200};

// Every point against the closed form, |H − H_exact| ≤ tol·|H_exact|. Python (the file) and C++
// (here) evaluate the formula each with its own rounding; at the resonance k − mω² cancels, which
// amplifies that 1/(2ζ) = 25×, so no tolerance is below 1e-13, whatever the file's digits.
inline void expect_sdof(const FrfFileData& r, double tol) {
  tol = std::max(tol, 1e-13);
  ASSERT_FALSE(r.is_block);
  ASSERT_EQ(r.single.frequency_hz, kVariantFrequencies);
  for (std::size_t i = 0; i < r.single.size(); ++i) {
    const Complex h = sdof(r.single.frequency_hz[i]);
    EXPECT_LE(std::abs(r.single.values[i] - h), tol * std::abs(h)) << "at " << r.single.frequency_hz[i] << " Hz";
  }
}

}  // namespace toolpoint::test
