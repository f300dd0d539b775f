// Tests of peak finding and mode tracking (peaks module), against closed-form resonances.
#include <gtest/gtest.h>

#include <cmath>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/peaks.hpp"

using namespace toolpoint;

namespace {

// Receptance of modes (f_n Hz, ζ, modal mass kg) on a grid.
FrfSeries modes_frf(const std::vector<std::array<double, 3>>& modes, double f0, double f1, double df) {
  FrfSeries s;
  for (double f = f0; f <= f1; f += df) {
    Complex h = 0.0;
    const double w = omega_of(f);
    for (const auto& m : modes) {
      const double wn = omega_of(m[0]);
      h += 1.0 / (m[2] * Complex(wn * wn - w * w, 2.0 * m[1] * wn * w));
    }
    s.frequency_hz.push_back(f);
    s.values.push_back(h);
  }
  return s;
}

}  // namespace

// A single-mode receptance peaks at f_n sqrt(1 − 2ζ²) with magnitude 1/(2ζ sqrt(1 − ζ²) k)
// (closed form). Grid of 2 Hz: the parabola through log|H| finds it within 0.05 Hz and 1e-3.
TEST(Peaks, RefinedPeakOfOneModeMatchesClosedForm) {
  const double fn = 1000.0, zeta = 0.02, m = 1.0;
  const FrfSeries s = modes_frf({{fn, zeta, m}}, 500.0, 1500.0, 2.0);
  const auto p = find_peaks(s);
  ASSERT_EQ(p.size(), 1u);
  const double k = m * omega_of(fn) * omega_of(fn);
  EXPECT_NEAR(p[0].frequency_hz, fn * std::sqrt(1 - 2 * zeta * zeta), 0.05);
  EXPECT_NEAR(p[0].magnitude * 2 * zeta * std::sqrt(1 - zeta * zeta) * k, 1.0, 1e-3);
  // Refinement on the exact magnitude: to 1e-6 Hz.
  const auto q = find_peaks(s, PeakOptions{}, [&](double f) {
    return std::abs(modes_frf({{fn, zeta, m}}, f, f, 1.0).values[0]);
  });
  EXPECT_NEAR(q[0].frequency_hz, fn * std::sqrt(1 - 2 * zeta * zeta), 1e-6);
}

// Prominence: a small ripple on a flank is no peak; its prominence (1 − valley/peak) is computed
// as defined, and the threshold keeps or drops it.
TEST(Peaks, ProminenceDecides) {
  FrfSeries s;
  const double mag[] = {1.0, 2.0, 3.0, 2.9, 2.95, 2.0, 1.0};  // a 1.7 % bump after the main peak
  for (int i = 0; i < 7; ++i) {
    s.frequency_hz.push_back(100.0 + i);
    s.values.push_back(mag[i]);
  }
  EXPECT_EQ(find_peaks(s, PeakOptions{0.02}).size(), 1u);
  const auto all = find_peaks(s, PeakOptions{0.0});
  ASSERT_EQ(all.size(), 2u);
  EXPECT_NEAR(all[1].prominence, 1.0 - 2.9 / 2.95, 1e-15);
  EXPECT_THROW(find_peaks(s, PeakOptions{1.5}), InvalidArgument);
}

// Shapes of sampled data: a flat top (two grid points straddling a maximum equally) is one peak
// at its middle; a shoulder (a plateau that then rises) is none; ends are none; a gap (NaN, as a
// plot's line break) is no peak and does not end a valley walk.
TEST(Peaks, PlateausShouldersEndsAndGaps) {
  auto indices = [](const std::vector<double>& m, double prom) {
    std::vector<std::size_t> v;
    for (const Peak& p : find_peaks(m, prom)) v.push_back(p.index);
    return v;
  };
  EXPECT_EQ(indices({1.0, 4.0, 4.0, 4.0, 1.0}, 0.0), std::vector<std::size_t>{2});
  EXPECT_EQ(indices({1.0, 4.0, 4.0, 1.0}, 0.0), std::vector<std::size_t>{1});
  EXPECT_TRUE(indices({1.0, 4.0, 4.0, 5.0, 1.0}, 0.0) == std::vector<std::size_t>{3});
  EXPECT_TRUE(indices({5.0, 1.0, 1.0, 5.0}, 0.0).empty());
  EXPECT_TRUE(indices({1.0, 2.0, 3.0}, 0.0).empty());
  const double nan = std::nan("");
  // 4 at index 3: valleys 1 (left, across the gap) and 2 (right): prominence 1 − 2/4.
  const auto p = find_peaks({1.0, nan, 3.0, 4.0, 2.0, 3.0}, 0.0);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].index, 3u);
  EXPECT_DOUBLE_EQ(p[0].prominence, 0.5);
  EXPECT_TRUE(indices({1.0, nan, 1.0}, 0.0).empty());
}

// Mode tracking: three modes moving through a sweep with a noise peak appearing in one member
// and a mode vanishing in another; every mode is followed, the noise ignored, the gap NaN.
TEST(Peaks, TrackModesThroughASweep) {
  auto peaks = [](std::vector<double> f) {
    std::vector<Peak> v;
    for (double x : f) v.push_back(Peak{0, x, 1.0, 0.5});
    return v;
  };
  const std::vector<std::vector<Peak>> family = {peaks({900, 2800, 3800}), peaks({895, 2650, 1120, 3720}),
                                                 peaks({890, 2500, 3650}), peaks({885, 3600})};
  const auto t = track_modes(family, 0);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0], (std::vector<double>{900, 895, 890, 885}));
  EXPECT_EQ(t[2], (std::vector<double>{3800, 3720, 3650, 3600}));
  EXPECT_DOUBLE_EQ(t[1][2], 2500);
  EXPECT_TRUE(std::isnan(t[1][3]));  // 2500 → 3600 is beyond 15 %: lost, not confused with mode 3
  // From the middle outwards gives the same modes.
  const auto m = track_modes(family, 2);
  EXPECT_EQ(m[1][0], 2800);
  // Unordered: each member against the reference; 2800 → 2500 is 11 %, found; 3600 in the last
  // member is 5 % from 3800 and still mode 3.
  const auto u = track_modes(family, 0, 0.15, false);
  EXPECT_DOUBLE_EQ(u[1][2], 2500);
  EXPECT_DOUBLE_EQ(u[2][3], 3600);
  EXPECT_THROW(track_modes(family, 4), InvalidArgument);
  EXPECT_THROW(track_modes(family, 0, 1.5), InvalidArgument);
}
