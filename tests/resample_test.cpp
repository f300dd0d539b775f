// Resampling FRFs (resample.hpp) against what is known independently: interpolation reproduces
// straight lines exactly and measured points bit for bit; its error on the closed-form receptance
// of a lightly damped oscillator falls as Δf² (linear) and Δf⁴ (cubic spline, interior) when the
// step is halved; nothing is extrapolated (the command line: cli_files_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/measured/resample.hpp"
#include "toolpoint/studies/resample.hpp"
#include "support/scratch.hpp"
#include "support/variants.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

namespace {

using test::sdof;
using test::sdof_series;  // sdof: m = 0.04 kg, fn = 1600 Hz, ζ = 0.02: half-power bandwidth 2ζ·fn = 64 Hz

// Largest |H − H_exact| / max|H_exact| over [lo, hi], sampled every 0.05 Hz (at least 40 points
// per interval of the coarsest step, so the maximum over each interval is found to < 1 %).
double worst_error(double step, Interpolation method, double lo, double hi) {
  const FrfSeries s = sdof_series(800.0, 2400.0, step);
  std::vector<double> grid;
  for (double f = lo + 0.013; f < hi; f += 0.05) grid.push_back(f);
  const FrfSeries r = resample(s, grid, method, "sdof");
  double worst = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) worst = std::max(worst, std::abs(r.values[i] - sdof(grid[i])));
  return worst / std::abs(sdof(1600.0 * std::sqrt(1.0 - 2.0 * 0.02 * 0.02)));
}

}  // namespace

TEST(Resample, StraightLinesExactlyAndMeasuredPointsBitForBit) {
  FrfSeries line;
  for (double f : {10.0, 13.0, 20.0, 21.5, 40.0}) {
    line.frequency_hz.push_back(f);
    line.values.emplace_back(2.0 - 0.5 * f, 3.0 * f);
  }
  const std::vector<double> grid = {10.0, 11.0, 17.25, 21.5, 33.3, 40.0};
  for (Interpolation m : {Interpolation::Linear, Interpolation::Cubic}) {
    const FrfSeries r = resample(line, grid, m, "line");
    for (std::size_t i = 0; i < grid.size(); ++i)
      EXPECT_LE(std::abs(r.values[i] - Complex(2.0 - 0.5 * grid[i], 3.0 * grid[i])), 1e-13 * 120.0) << grid[i];
    EXPECT_EQ(r.values[3], line.values[3]);  // 21.5 Hz is measured: its value exactly
    EXPECT_EQ(r.values[5], line.values[4]);
  }
  const FrfSeries s = sdof_series(1000, 2000, 10);
  const FrfSeries same = resample(s, s.frequency_hz, Interpolation::Cubic, "s");
  EXPECT_EQ(same.values, s.values);
}

// Convergence: halving the step divides the error by 4 (linear, O(Δf²)) and by 16 (cubic spline
// away from the ends, O(Δf⁴)), measured every 0.05 Hz across the resonance (1400–1800 Hz,
// ≥ 25 steps from either end, where the natural end condition's influence has died out: it decays
// by 2 − √3 ≈ 0.27 per knot). Steps 4, 2, 1 Hz (1/16 to 1/64 of the 64 Hz half-power band) are
// in the asymptotic range: measured ratios 3.98, 4.00 (linear) and 17.3, 16.4 (cubic); at 8 Hz the
// cubic ratio is still 22, so 12 % is the tolerance.
TEST(Resample, ErrorFallsAsTheOrderSays) {
  for (const auto& [method, rate] : {std::pair{Interpolation::Linear, 4.0}, std::pair{Interpolation::Cubic, 16.0}}) {
    const double e4 = worst_error(4.0, method, 1400, 1800), e2 = worst_error(2.0, method, 1400, 1800),
                 e1 = worst_error(1.0, method, 1400, 1800);
    EXPECT_NEAR(e4 / e2, rate, 0.12 * rate) << (method == Interpolation::Linear ? "linear" : "cubic");
    EXPECT_NEAR(e2 / e1, rate, 0.12 * rate) << (method == Interpolation::Linear ? "linear" : "cubic");
  }
  // The figures a user can expect at the resonance, relative to the peak: 4 Hz steps (1/16 of
  // the half-power band) give 0.39 % linear and 0.0017 % cubic here.
  EXPECT_LT(worst_error(4.0, Interpolation::Cubic, 1400, 1800), 0.1 * worst_error(4.0, Interpolation::Linear, 1400, 1800));
}

TEST(Resample, NeverExtrapolatesAndCropsInclusively) {
  const FrfSeries s = sdof_series(1000, 2000, 10);
  try {
    resample(s, {995.0, 1500.0}, Interpolation::Linear, "tip.csv");
    FAIL() << "extrapolated below the measured range";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tip.csv: target frequency 995 Hz lies outside the measured range 1000–2000 Hz"),
              std::string::npos)
        << e.what();
    EXPECT_NE(e.hint().find("1000:2000"), std::string::npos) << e.hint();
  }
  EXPECT_THROW(resample(s, {1500.0, 2000.5}, Interpolation::Linear, "tip.csv"), InputError);
  EXPECT_THROW(resample(s, {1500.0, 1400.0}, Interpolation::Linear, "tip.csv"), InvalidArgument);
  EXPECT_THROW(resample(sdof_series(1000, 1010, 10), {1005.0}, Interpolation::Cubic, "two points"), InputError);

  const FrfSeries c = crop(s, 1500.0, 1600.0, "tip.csv");
  EXPECT_EQ(c.frequency_hz.front(), 1500.0);
  EXPECT_EQ(c.frequency_hz.back(), 1600.0);
  EXPECT_EQ(c.size(), 11u);
  EXPECT_THROW(crop(s, 3000.0, 4000.0, "tip.csv"), InputError);
  EXPECT_THROW(crop(s, 4000.0, 3000.0, "tip.csv"), InvalidArgument);

  // A block: each entry as its own series; a coherence linearly.
  BlockSeries b;
  for (std::size_t i = 0; i < s.size(); ++i) {
    b.frequency_hz.push_back(s.frequency_hz[i]);
    b.blocks.push_back(make_block(s.values[i], 2.0 * s.values[i], 3.0 * s.values[i], 4.0 * s.values[i]));
  }
  const std::vector<double> grid = {1003.0, 1555.5, 1999.0};
  const BlockSeries rb = resample(b, grid, Interpolation::Cubic, "b");
  const FrfSeries rs = resample(s, grid, Interpolation::Cubic, "s");
  for (std::size_t i = 0; i < grid.size(); ++i) {
    EXPECT_EQ(rb.blocks[i](0, 0), rs.values[i]);
    EXPECT_NEAR(std::abs(rb.blocks[i](1, 1) - 4.0 * rs.values[i]), 0.0, 1e-15 * std::abs(rs.values[i]));
  }
  EXPECT_EQ(resample_values({1.0, 2.0, 4.0}, {0.5, 1.0, 0.0}, {1.5, 3.0}, "coh"), (std::vector<double>{0.75, 0.5}));
}

// run_resample_study (a file's FRF on another grid, one call) against closed forms and the lower-level
// calls: a straight line H = a + b·f and a linear coherence interpolate exactly (1e-14 relative:
// a few roundings per value), the target first cropped to the band; the same values as resample()
// and resample_values() on the cropped grid called directly; crop as crop(); the band named in
// the refusals.
TEST(ResampleFrf, TargetCroppedToTheBandThenInterpolated) {
  const Complex a(1e-6, 2e-6), b(3e-9, -1e-9);
  FrfFileData in;
  for (int i = 0; i <= 100; ++i) {
    const double f = 1000.0 + 10.0 * i;
    in.single.frequency_hz.push_back(f);
    in.single.values.push_back(a + b * f);
    in.coherence.push_back(0.5 + f / 4000.0);
  }
  in.dof.response_node = 7;
  FrfResampleOptions o;
  o.band_hz = std::make_pair(1000.0, 2000.0);
  o.target_hz = std::vector<double>{};
  for (int i = 0; i <= 404; ++i) o.target_hz->push_back(995.0 + 2.5 * i);  // 995…2005 Hz: beyond the data at both ends
  o.target_name = "the frequencies of t.csv";
  const FrfResampled r = run_resample_study(in, o, "line.csv");
  const std::vector<double>& f = r.data.single.frequency_hz;
  ASSERT_EQ(f.size(), 401u);  // 1000…2000 Hz
  EXPECT_EQ(f.front(), 1000.0);
  EXPECT_EQ(f.back(), 2000.0);
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_LT(std::abs(r.data.single.values[i] - (a + b * f[i])), 1e-14 * std::abs(a + b * f[i])) << f[i];
    EXPECT_NEAR(r.data.coherence[i], 0.5 + f[i] / 4000.0, 1e-14) << f[i];
  }
  EXPECT_EQ(r.data.single.values, resample(in.single, f, Interpolation::Linear, "line.csv").values);
  EXPECT_EQ(r.data.coherence, resample_values(in.single.frequency_hz, in.coherence, f, "line.csv"));
  EXPECT_EQ(r.data.dof.response_node, 7);
  EXPECT_FALSE(r.data.is_block);
  EXPECT_EQ(r.description, "linear interpolation of real and imaginary parts onto the frequencies of t.csv, within 1000–2000 Hz");
  EXPECT_TRUE(r.warnings.empty());

  // Without the band the target reaches outside the data: refused, the fix naming the band.
  o.band_hz.reset();
  try {
    run_resample_study(in, o, "line.csv");
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("target frequency 995 Hz"), std::string::npos) << e.what();
    EXPECT_NE(e.hint().find("FrfResampleOptions::band_hz"), std::string::npos) << e.hint();
  }
  // A band that misses the target entirely names both.
  o.band_hz = std::make_pair(3000.0, 4000.0);
  try {
    run_resample_study(in, o, "line.csv");
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("FrfResampleOptions::band_hz 3000:4000"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the frequencies of t.csv spans 995–2005 Hz"), std::string::npos) << e.what();
  }

  // No target: cropped, as crop() and crop_values() give it.
  o.target_hz.reset();
  o.band_hz = std::make_pair(1200.0, 1500.0);
  const FrfResampled c = run_resample_study(in, o, "line.csv");
  EXPECT_EQ(c.data.single.values, crop(in.single, 1200.0, 1500.0, "line.csv").values);
  EXPECT_EQ(c.data.coherence, crop_values(in.single.frequency_hz, in.coherence, 1200.0, 1500.0));
  EXPECT_EQ(c.data.single.size(), 31u);
  EXPECT_EQ(c.description, "cropped to 1200–1500 Hz");

  o.band_hz.reset();
  EXPECT_THROW(run_resample_study(in, o, "line.csv"), InvalidArgument);  // neither a band nor a target
}

// A block: every entry, as resample() of the block gives it.
TEST(ResampleFrf, Block) {
  const FrfSeries s = sdof_series(1000.0, 2000.0, 10.0);
  FrfFileData in;
  in.is_block = true;
  in.block.frequency_hz = s.frequency_hz;
  for (const Complex& v : s.values) in.block.blocks.push_back((Block() << v, 2.0 * v, 3.0 * v, 4.0 * v).finished());
  FrfResampleOptions o;
  o.target_hz = std::vector<double>{1001.0, 1500.5, 1999.0};
  o.method = Interpolation::Cubic;
  const FrfResampled r = run_resample_study(in, o, "block.csv");
  ASSERT_TRUE(r.data.is_block);
  const BlockSeries direct = resample(in.block, *o.target_hz, Interpolation::Cubic, "block.csv");
  ASSERT_EQ(r.data.block.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(r.data.block.blocks[i], direct.blocks[i]);
  EXPECT_TRUE(r.data.coherence.empty());
  EXPECT_EQ(r.description, "cubic interpolation of real and imaginary parts onto the target grid");
}
