// Tests of run_filter_study (studies/filter.hpp): the noise gain against the closed-form
// Savitzky–Golay weights, and the peak comparison on a synthetic single-degree-of-freedom FRF
// against its analytic peak and the filter's weights applied by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/filter.hpp"

namespace toolpoint {
namespace {

// Known weights (Savitzky & Golay 1964, Table I): window 5 order 2 (−3, 12, 17, 12, −3)/35, so
// Σc² = 595/1225 = 17/35; window 7 order 2 (−2, 3, 6, 7, 6, 3, −2)/21, Σc² = 147/441 = 1/3; order 0
// is the moving average, Σc² = 1/w. Tolerance 1e-14: the weights come from a QR solve, exact to a
// few ulps.
TEST(FilterStudy, NoiseGainIsTheKnownSumOfSquaredWeights) {
  EXPECT_NEAR(savgol_noise_gain({5, 2}), 17.0 / 35.0, 1e-14);
  EXPECT_NEAR(savgol_noise_gain({7, 2}), 1.0 / 3.0, 1e-14);
  EXPECT_NEAR(savgol_noise_gain({7, 3}), 1.0 / 3.0, 1e-14);  // odd order p+1 adds nothing about the centre
  EXPECT_NEAR(savgol_noise_gain({9, 0}), 1.0 / 9.0, 1e-14);
}

// 1-DOF receptance H = 1/(k(1 − r² + 2iζr)), r = f/f_n: |H| peaks at f_n sqrt(1 − 2ζ²) with
// 1/(2ζ sqrt(1 − ζ²) k).
constexpr double kFn = 1000.0, kZeta = 0.01, kK = 1.0e7;
Complex sdof(double f) {
  const double r = f / kFn;
  return 1.0 / (kK * Complex(1.0 - r * r, 2.0 * kZeta * r));
}
FrfSeries sdof_series() {
  FrfSeries s;
  for (int i = 0; i <= 1000; ++i) {
    const double f = 500.0 + i;  // 1 Hz steps: the half-power band 2ζf_n = 20 Hz holds 20 points
    s.frequency_hz.push_back(f);
    s.values.push_back(sdof(f));
  }
  return s;
}

TEST(FilterStudy, PeakChangesOnASingleMode) {
  const FrfSeries raw = sdof_series();
  FilterStudyOptions o;
  o.savgol = {5, 2};
  const FilterStudy<FrfSeries> r = run_filter_study(raw, o, "sdof");
  // The filtered series is savgol_filter's, called directly.
  const SignalResult<FrfSeries> direct = savgol_filter(raw, o.savgol, "sdof");
  EXPECT_EQ(r.filtered.values, direct.series.values);
  EXPECT_EQ(r.filtered.frequency_hz, raw.frequency_hz);
  EXPECT_NEAR(r.noise_gain, 17.0 / 35.0, 1e-14);
  ASSERT_EQ(r.peaks.peaks.size(), 1u);
  const PeakChange& p = r.peaks.peaks[0];
  // The raw peak, refined by a parabola through log|H| at 1 Hz spacing: within 0.05 Hz (the
  // parabola's error on a peak 20 points wide) and 1e-4 of the analytic height.
  EXPECT_NEAR(p.raw_frequency_hz, kFn * std::sqrt(1.0 - 2.0 * kZeta * kZeta), 0.05);
  EXPECT_NEAR(p.raw_magnitude * 2.0 * kZeta * std::sqrt(1.0 - kZeta * kZeta) * kK, 1.0, 1e-4);
  // The filter at the peak's sample by the weights (−3, 12, 17, 12, −3)/35 applied by hand: the
  // relative height change (−2.0e-4), within 1e-6 absolute, 0.5 % of it — the study refines both
  // peaks between samples (0.1 Hz from the sample here), which moves the ratio by ~2e-8.
  const double f0 = std::round(p.raw_frequency_hz);
  const double c[] = {-3.0, 12.0, 17.0, 12.0, -3.0};
  Complex y = 0.0;
  for (int k = -2; k <= 2; ++k) y += c[k + 2] / 35.0 * sdof(f0 + k);
  const double expected = std::abs(y) / std::abs(sdof(f0)) - 1.0;
  EXPECT_LT(expected, 0.0);  // a peak is always lowered by a smoothing fit
  EXPECT_NEAR(p.height_change, expected, 1e-6);
  EXPECT_LT(std::abs(p.height_change), 0.02);  // below the warning threshold: no warning
  EXPECT_TRUE(r.warnings.empty());

  // A window of 41 points (twice the half-power band) flattens the peak: a warning, in both lists.
  o.savgol = {41, 2};
  const FilterStudy<FrfSeries> wide = run_filter_study(raw, o, "sdof");
  ASSERT_EQ(wide.peaks.peaks.size(), 1u);
  EXPECT_LT(wide.peaks.peaks[0].height_change, -0.02);
  ASSERT_EQ(wide.peaks.warnings.size(), 1u);
  EXPECT_EQ(wide.warnings, wide.peaks.warnings);
  const nlohmann::json j = wide;
  EXPECT_EQ(j["peaks"]["peaks"].size(), 1u);
  EXPECT_EQ(j["noise_gain"], wide.noise_gain);
}

// A block: every entry filtered and compared (H, L, N, P), as savgol_filter and peak_changes give it.
TEST(FilterStudy, BlockEntries) {
  const FrfSeries h = sdof_series();
  BlockSeries b;
  b.frequency_hz = h.frequency_hz;
  for (const Complex& v : h.values) b.blocks.push_back((Block() << v, 2.0 * v, 2.0 * v, 4.0 * v).finished());
  FilterStudyOptions o;
  o.savgol = {5, 2};
  const FilterStudy<BlockSeries> r = run_filter_study(b, o, "block");
  const PeakChangeReport direct = peak_changes(b, savgol_filter(b, o.savgol).series, 5);
  ASSERT_EQ(r.peaks.peaks.size(), direct.peaks.size());
  ASSERT_EQ(r.peaks.peaks.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(r.peaks.peaks[i].entry, direct.peaks[i].entry);
    EXPECT_EQ(r.peaks.peaks[i].height_change, direct.peaks[i].height_change);
  }
}

// The window is checked against the data (at most a quarter of the points), naming the field.
TEST(FilterStudy, WindowAgainstThePoints) {
  FilterStudyOptions o;
  o.savgol = {301, 2};  // 1001 points: at most 250
  try {
    run_filter_study(sdof_series(), o, "sdof");
    ADD_FAILURE() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("SavgolOptions::window"), std::string::npos) << e.what();
  }
  o.savgol = {4, 2};
  EXPECT_THROW(run_filter_study(sdof_series(), o), InvalidArgument);
}

}  // namespace
}  // namespace toolpoint
