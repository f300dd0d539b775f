// Tests of the signal module: Savitzky–Golay smoothing, simulated noise, finite-difference
// rotational FRFs. Every expectation comes from something independent of the code under test:
// the docs/reference.md §6 oracle (scipy's output), closed-form Savitzky–Golay weights (Savitzky & Golay 1964
// for degree 2–3), exact reproduction of polynomials, closed-form straight-line regression at
// the edges, the statistics of white noise, the normal distribution's probabilities, the static
// cantilever flexibility G(x, ξ) = ξ²(3x − ξ)/6 (docs/reference.md §5), and an exact dynamic Green's function
// of a damped Euler–Bernoulli cantilever solved here from its boundary-value problem.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <tuple>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <sys/wait.h>
#include <unistd.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/measured/signal.hpp"
#include "support/test_util.hpp"

using namespace toolpoint;

namespace {

bool contains(const std::vector<std::string>& v, const std::string& needle) {
  for (const auto& s : v)
    if (s.find(needle) != std::string::npos) return true;
  return false;
}

std::vector<double> polynomial_samples(const std::vector<double>& coeffs, std::size_t n) {
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(n);  // keeps values O(1)
    for (std::size_t j = coeffs.size(); j-- > 0;) y[i] = y[i] * t + coeffs[j];
  }
  return y;
}

using test::single;

}  // namespace

// ---- Savitzky–Golay ------------------------------------------------------------------------------

// docs/reference.md §6 oracle (scipy): window 5, order 2 → [−3, 12, 17, 12, −3]/35. 1e-14: a few ulps of the
// QR round-off on numbers of order 1.
TEST(Savgol, CoefficientsMatchOracle) {
  const auto c = savgol_coefficients({5, 2});
  const double want[] = {-3, 12, 17, 12, -3};
  ASSERT_EQ(c.size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(c[k], want[k] / 35.0, 1e-14) << k;
}

// docs/reference.md §6: x = [2,2,5,2,1,0,1,4,9], window 5, order 2 → [58/35, 111/35, 124/35, 20/7, 23/35,
// 6/35, 1, 4, 9] (the first two and last two from the edge fits). 1e-14 as above.
TEST(Savgol, NineSampleOracleIncludingEdges) {
  const std::vector<double> x = {2, 2, 5, 2, 1, 0, 1, 4, 9};
  const double want[] = {58 / 35.0, 111 / 35.0, 124 / 35.0, 20 / 7.0, 23 / 35.0, 6 / 35.0, 1, 4, 9};
  const auto y = savgol_filter(x, {5, 2});
  ASSERT_EQ(y.size(), 9u);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(y[i], want[i], 1e-14) << i;
}

// Closed form for degree 2 and 3 (Savitzky & Golay 1964; the cubic weights at the centre equal
// the quadratic ones by symmetry): c_k = [3(3m² + 3m − 1) − 15k²] / [(2m−1)(2m+1)(2m+3)],
// k = −m..m. Degree 0 and 1: the plain mean 1/(2m+1). 1e-14: round-off on weights ≤ 1.
TEST(Savgol, CoefficientsMatchClosedForm) {
  for (int m = 1; m <= 25; ++m) {
    const int w = 2 * m + 1;
    const double den = (2.0 * m - 1) * (2.0 * m + 1) * (2.0 * m + 3);
    for (int order : {0, 1, 2, 3}) {
      if (order >= w) continue;
      const auto c = savgol_coefficients({w, order});
      for (int k = -m; k <= m; ++k) {
        const double want = order <= 1 ? 1.0 / w : (3.0 * (3.0 * m * m + 3.0 * m - 1) - 15.0 * k * k) / den;
        EXPECT_NEAR(c[k + m], want, 1e-14) << "window " << w << " order " << order << " k " << k;
      }
    }
  }
}

// A least-squares fit of degree p reproduces any polynomial of degree ≤ p exactly, at interior
// points and at both edges. Values are O(1); 1e-12 allows the round-off of the QR solve and of
// the 2m+1-term sums.
TEST(Savgol, ReproducesPolynomialsUpToTheOrder) {
  const std::vector<double> coeffs = {0.7, -2.1, 3.3, 1.9, -4.2, 2.5, -0.8, 1.1, -0.6, 0.9, -1.3, 0.4, 0.2};  // degree ≤ 12
  for (auto [w, p] : {std::pair{5, 2}, {7, 3}, {11, 4}, {21, 6}, {9, 0}, {3, 1}, {13, 12}}) {
    for (int degree = 0; degree <= p; ++degree) {
      const auto x = polynomial_samples(std::vector<double>(coeffs.begin(), coeffs.begin() + degree + 1), 40);
      const auto y = savgol_filter(x, {w, p});
      for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_NEAR(y[i], x[i], 1e-12) << "window " << w << " order " << p << " degree " << degree << " point " << i;
    }
  }
  // …and not one degree more: a filter that passed everything through would fail here.
  const auto x = polynomial_samples({0.0, 0.0, 0.0, 1.0}, 40);  // t³
  const auto y = savgol_filter(x, {9, 2});
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(y[i] - x[i]));
  EXPECT_GT(worst, 1e-4);
}

// DC gain 1: the weights sum to 1 for every (window, order) (a constant is a polynomial of degree
// 0, which every fit reproduces). 1e-13: round-off of up to 101 terms.
TEST(Savgol, UnitDcGain) {
  for (int w = 1; w <= 101; w += 4)
    for (int p = 0; p < std::min(w, 8); ++p) {
      const auto c = savgol_coefficients({w, p});
      EXPECT_NEAR(std::accumulate(c.begin(), c.end(), 0.0), 1.0, 1e-13) << w << " " << p;
    }
}

// Edges for order 1 have a closed form: the regression line through (k, y_k), k = 0..w−1,
// ŷ(k) = ȳ + (k − k̄) Σ(k − k̄)(y_k − ȳ) / Σ(k − k̄)². 1e-13 for values of order 1.
TEST(Savgol, LinearEdgesMatchRegressionLine) {
  const auto x = standard_normals(30, 11);
  const int w = 9, m = 4;
  const auto y = savgol_filter(x, {w, 1});
  auto regression = [&](std::size_t first, int k) {
    const double kbar = (w - 1) / 2.0;
    double ybar = 0.0, sxy = 0.0, sxx = 0.0;
    for (int j = 0; j < w; ++j) ybar += x[first + j] / w;
    for (int j = 0; j < w; ++j) {
      sxy += (j - kbar) * (x[first + j] - ybar);
      sxx += (j - kbar) * (j - kbar);
    }
    return ybar + (k - kbar) * sxy / sxx;
  };
  for (int k = 0; k < m; ++k) {
    EXPECT_NEAR(y[k], regression(0, k), 1e-13) << "start " << k;
    EXPECT_NEAR(y[30 - w + (w - m) + k], regression(30 - w, w - m + k), 1e-13) << "end " << k;
  }
}

// White noise of variance 1 filtered by weights c has variance Σc² at interior points. The
// output is a moving average, so its sample variance over n points has standard error
// sqrt(2 Σ_h γ_h² / n), γ_h = Σ_k c_k c_{k+h}; we allow 5 standard errors (for any seed a
// failure by chance has probability < 1e-6). A plain mean or an identity filter would be off by
// many times that.
TEST(Savgol, WhiteNoiseVarianceReductionEqualsSumOfSquares) {
  const std::size_t n = 200000;
  const auto x = standard_normals(n, 2024);
  for (auto [w, p] : {std::pair{21, 3}, {11, 2}, {31, 5}}) {
    const auto c = savgol_coefficients({w, p});
    const auto y = savgol_filter(x, {w, p});
    double gain = 0.0;
    for (double ck : c) gain += ck * ck;
    double sum_gamma2 = 0.0;
    for (int h = -(w - 1); h < w; ++h) {
      double g = 0.0;
      for (int k = 0; k < w; ++k)
        if (k + h >= 0 && k + h < w) g += c[k] * c[k + h];
      sum_gamma2 += g * g;
    }
    const std::size_t m = w / 2, count = n - 2 * m;
    double mean = 0.0, var = 0.0;
    for (std::size_t i = m; i < n - m; ++i) mean += y[i] / count;
    for (std::size_t i = m; i < n - m; ++i) var += (y[i] - mean) * (y[i] - mean) / (count - 1);
    const double se = std::sqrt(2.0 * sum_gamma2 / count);
    EXPECT_NEAR(var, gain, 5.0 * se) << "window " << w << " order " << p;
    EXPECT_GT(std::abs(gain - 1.0 / w), 10.0 * se);  // the test can tell these weights from a mean
  }
}

// Complex data: real and imaginary parts are filtered separately; a 2×2 block series: its eight
// real columns each on their own. Each column holds a different polynomial of degree ≤ 3, so
// a (3, 7) filter must give every column back unchanged; a mixed-up column would show. 1e-12
// as in ReproducesPolynomialsUpToTheOrder.
TEST(Savgol, BlockAndComplexColumnsAreFilteredSeparately) {
  const std::size_t n = 25;
  std::vector<std::vector<double>> cols;
  for (int c = 0; c < 8; ++c) cols.push_back(polynomial_samples({1.0 + c, -0.5 * c, 0.3 * (c - 4), 0.1 * c * c}, n));
  BlockSeries b;
  for (std::size_t i = 0; i < n; ++i) {
    b.frequency_hz.push_back(100.0 + 10.0 * static_cast<double>(i));
    b.blocks.push_back(
        make_block({cols[0][i], cols[1][i]}, {cols[2][i], cols[3][i]}, {cols[4][i], cols[5][i]}, {cols[6][i], cols[7][i]}));
  }
  const auto r = savgol_filter(b, {7, 3});
  ASSERT_EQ(r.series.size(), n);
  EXPECT_TRUE(r.warnings.empty());
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_DOUBLE_EQ(r.series.frequency_hz[i], b.frequency_hz[i]);
    EXPECT_LT((r.series.blocks[i] - b.blocks[i]).cwiseAbs().maxCoeff(), 1e-12) << i;
  }
  // Noisy complex FRF: the result's real part is the filtered real part, the imaginary part the
  // filtered imaginary part (equal to round-off: the same arithmetic on the same numbers).
  const auto re = standard_normals(n, 1), im = standard_normals(n, 2);
  std::vector<Complex> z(n);
  for (std::size_t i = 0; i < n; ++i) z[i] = {re[i], im[i]};
  const auto fz = savgol_filter(single(z), {7, 3}).series;
  const auto fre = savgol_filter(re, {7, 3}), fim = savgol_filter(im, {7, 3});
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_DOUBLE_EQ(fz.values[i].real(), fre[i]);
    EXPECT_DOUBLE_EQ(fz.values[i].imag(), fim[i]);
  }
}

TEST(Savgol, UnevenGridIsFlagged) {
  FrfSeries s = single(std::vector<Complex>(9, {1.0, 0.0}));
  EXPECT_TRUE(savgol_filter(s, {5, 2}).warnings.empty());
  s.frequency_hz[4] += 0.5;
  EXPECT_TRUE(contains(savgol_filter(s, {5, 2}, "h.csv").warnings, "h.csv: frequency steps vary"));
}

// Noise does not make peaks. A single-DOF peak (916 Hz, ζ = 0.01, 1 Hz grid, 4001 points) with
// complex white noise of σ = 3 % of the peak (a drawn, known σ): over 40 noise seeds the report lists
// exactly the one resonance each time (without the noise rule, dozens of maxima rise 25 % above
// their valleys in the flanks, where the noise is comparable to the response), the σ it reports
// at the peak is the drawn one to within 25 % (a 51-point estimate has a spread of about 10 %), and
// the height change of a 21-point window is the noise-free change to within 2σ. An entry that
// is noise only (P, σ nine times its signal's peak) lists no peak at all.
TEST(Savgol, PeakChangesIgnoreNoisePeaks) {
  const double fn = 916.0, zeta = 0.01, k = 4e7, peak = 1.0 / (2.0 * zeta * k), sigma = 0.03 * peak;
  FrfSeries clean;
  for (double f = 0.0; f <= 4000.0; f += 1.0) {
    const double r = (f + 10.0) / fn;
    clean.frequency_hz.push_back(f + 10.0);
    clean.values.push_back(1.0 / (k * Complex(1.0 - r * r, 2.0 * zeta * r)));
  }
  const double bias = peak_changes(clean, savgol_filter(clean, {21, 2}).series, 21).peaks.at(0).height_change;
  int without_rule_max = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    FrfSeries noisy = clean;
    const std::vector<double> z = standard_normals(2 * noisy.size(), seed);
    for (std::size_t i = 0; i < noisy.size(); ++i) noisy.values[i] += sigma / std::sqrt(2.0) * Complex(z[2 * i], z[2 * i + 1]);
    const FrfSeries filtered = savgol_filter(noisy, {21, 2}).series;
    const PeakChangeReport r = peak_changes(noisy, filtered, 21);
    ASSERT_EQ(r.peaks.size(), 1u) << "seed " << seed;
    const PeakChange& c = r.peaks[0];
    EXPECT_NEAR(c.raw_frequency_hz, fn, 3.0) << seed;
    EXPECT_NEAR(c.noise * c.raw_magnitude / sigma, 1.0, 0.25) << seed;
    EXPECT_NEAR(c.height_change, bias, 2.0 * c.noise) << seed;
    PeakChangeOptions no_rule;
    no_rule.noise_prominence = 0.0;
    without_rule_max = std::max(without_rule_max, static_cast<int>(peak_changes(noisy, filtered, 21, no_rule).peaks.size()));
  }
  EXPECT_GT(without_rule_max, 10);  // the rule is what removes them
  BlockSeries b;
  b.frequency_hz = clean.frequency_hz;
  const std::vector<double> z = standard_normals(2 * clean.size(), 99);
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const Complex h = clean.values[i], p = 0.01 * h + 0.03 * sigma / std::sqrt(2.0) * Complex(z[2 * i], z[2 * i + 1]) * 100.0;
    b.blocks.push_back(make_block(h, h, h, p));
  }
  const PeakChangeReport rb = peak_changes(b, savgol_filter(b, {21, 2}).series, 21);
  for (const PeakChange& c : rb.peaks) EXPECT_NE(c.entry, "P") << c.raw_frequency_hz;
  EXPECT_EQ(rb.peaks.size(), 3u);
}

// What the filter does to a resonance, against an independent computation: a single-DOF
// receptance H = 1/(k (1 − r² + 2iζr)), r = f/f_n (f_n = 916 Hz, ζ = 0.01, half-power width
// 18 Hz) on a 1 Hz grid, smoothed by quadratic Savitzky–Golay weights from their closed form
// c_j = 3(3m² + 3m − 1 − 5j²) / ((2m + 1)(4m² + 4m − 3)) (Savitzky & Golay 1964, Table I;
// not the QR of the code under test), convolved by hand. The height change at the grid peak
// agrees with the report to 0.3 percentage points (the report refines both peaks by a parabola
// through log|H|, which moves the heights by less than that on a peak 18 points wide); the peak
// itself lies at f_n √(1 − 2ζ²). Windows of 41 and 81 points cut it by about a fifth and nearly
// half (a warning each); 5 points change it by less than 0.1 % (no warning).
TEST(Savgol, PeakChangesMatchAHandConvolutionOfTheClosedFormWeights) {
  const double fn = 916.0, zeta = 0.01, k = 4e7;
  FrfSeries s;
  for (double f = 600.0; f <= 1300.0; f += 1.0) {
    const double r = f / fn;
    s.frequency_hz.push_back(f);
    s.values.push_back(1.0 / (k * Complex(1.0 - r * r, 2.0 * zeta * r)));
  }
  const std::size_t peak = 316;  // 916 Hz
  ASSERT_DOUBLE_EQ(s.frequency_hz[peak], fn);
  for (const auto& [window, expected] : std::vector<std::pair<int, double>>{{5, 0.0}, {41, -0.21}, {81, -0.45}}) {
    const int m = window / 2;
    Complex smoothed = 0.0;
    for (int j = -m; j <= m; ++j) {
      const double c = 3.0 * (3.0 * m * m + 3.0 * m - 1.0 - 5.0 * j * j) / ((2.0 * m + 1) * (4.0 * m * m + 4.0 * m - 3.0));
      smoothed += c * s.values[static_cast<std::size_t>(static_cast<long>(peak) + j)];
    }
    const double by_hand = std::abs(smoothed) / std::abs(s.values[peak]) - 1.0;
    const auto filtered = savgol_filter(s, {window, 2}).series;
    const PeakChangeReport r = peak_changes(s, filtered, window, {}, "sdof.csv");
    ASSERT_EQ(r.peaks.size(), 1u) << window;
    EXPECT_NEAR(r.peaks[0].raw_frequency_hz, fn * std::sqrt(1.0 - 2.0 * zeta * zeta), 0.01);
    EXPECT_NEAR(r.peaks[0].height_change, by_hand, 0.003) << window;
    if (window == 5) {
      EXPECT_GT(r.peaks[0].height_change, -0.001);
      EXPECT_TRUE(r.warnings.empty());
    } else {
      EXPECT_NEAR(r.peaks[0].height_change, expected, 0.01) << window;
      ASSERT_EQ(r.warnings.size(), 1u);
      EXPECT_TRUE(contains(r.warnings, "sdof.csv: the filter changed the peak at 915.9")) << r.warnings[0];
    }
  }
  // A block: every entry reported by name.
  BlockSeries b;
  b.frequency_hz = s.frequency_hz;
  for (const Complex& h : s.values) b.blocks.push_back(make_block(h, 2.0 * h, 2.0 * h, 4.0 * h));
  const PeakChangeReport rb = peak_changes(b, savgol_filter(b, {41, 2}).series, 41);
  ASSERT_EQ(rb.peaks.size(), 4u);
  for (int e = 0; e < 4; ++e) EXPECT_EQ(rb.peaks[static_cast<std::size_t>(e)].entry, std::string(1, "HLNP"[e]));
  EXPECT_EQ(rb.warnings.size(), 4u);
  // Windows longer than a quarter of the data are refused, naming the field and the length.
  try {
    check_smoothing_window({177, 2}, s.size(), "sdof.csv");
    ADD_FAILURE();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("SavgolOptions::window 177 points is longer than a quarter of sdof.csv (701 points"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(check_smoothing_window({175, 2}, s.size(), "sdof.csv"));
}

TEST(Savgol, BadOptionsAndDataAreRejected) {
  const std::vector<double> x(9, 1.0);
  EXPECT_THROW(savgol_filter(x, {4, 2}), InvalidArgument);   // even window
  EXPECT_THROW(savgol_filter(x, {5, 5}), InvalidArgument);   // order = window
  EXPECT_THROW(savgol_filter(x, {5, 7}), InvalidArgument);   // order > window
  EXPECT_THROW(savgol_filter(x, {5, -1}), InvalidArgument);  // negative order
  EXPECT_THROW(savgol_filter(x, {0, 0}), InvalidArgument);
  EXPECT_THROW(savgol_filter(x, {-3, 0}), InvalidArgument);
  try {
    savgol_filter(x, {11, 2}, "tip.csv");  // window longer than the data
    ADD_FAILURE();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("tip.csv (9 points)"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(savgol_filter(x, {9, 8}));  // window = length is allowed (scipy 'interp')
  EXPECT_NO_THROW(savgol_filter(x, {1, 0}));
  std::vector<double> bad = x;
  bad[3] = std::nan("");
  EXPECT_THROW(savgol_filter(bad, {5, 2}), InputError);
  FrfSeries s = single(std::vector<Complex>(9, {1.0, 0.0}));
  s.values[2] = {0.0, INFINITY};
  EXPECT_THROW(savgol_filter(s, {5, 2}), InputError);
  // Orders so high that monomials on 2m+1 points lose accuracy are refused, not silently wrong.
  EXPECT_THROW(savgol_coefficients({61, 40}), NumericalError);
  EXPECT_NO_THROW(savgol_coefficients({61, 10}));
}

// ---- Simulated measurement noise ---------------------------------------------------------------

// Factors 1 + σz: over n = 200 000 draws the sample mean lies within 5 σ/√n of 1 and the sample
// standard deviation within 5 σ/√(2n) of σ (its standard error for a normal sample), for each
// of several seeds. The factor is real: a complex value keeps its phase (1e-15: round-off).
TEST(Noise, FactorsHaveMeanOneAndStandardDeviationSigma) {
  const std::size_t n = 200000;
  for (double sigma : {0.05, 0.2}) {
    for (std::uint64_t seed : {1u, 7u, 123456789u}) {
      const FrfSeries s = single(std::vector<Complex>(n, {2.0, -3.0}), 1.0, 0.1);
      const auto r = add_measurement_noise(s, {sigma, seed});
      double mean = 0.0, var = 0.0;
      for (const Complex& v : r.series.values) {
        const Complex ratio = v / Complex(2.0, -3.0);
        EXPECT_LT(std::abs(ratio.imag()), 1e-15);
        mean += ratio.real() / n;
      }
      for (const Complex& v : r.series.values) var += std::pow((v / Complex(2.0, -3.0)).real() - mean, 2) / (n - 1);
      EXPECT_NEAR(mean, 1.0, 5.0 * sigma / std::sqrt(n)) << sigma << " " << seed;
      EXPECT_NEAR(std::sqrt(var), sigma, 5.0 * sigma / std::sqrt(2.0 * n)) << sigma << " " << seed;
      if (sigma <= 0.05) EXPECT_TRUE(r.warnings.empty());  // a factor <= 0 needs z <= -20
    }
  }
}

// The draws are standard normal: P(|z| < 1) = 0.682689, P(|z| < 2) = 0.954500 (binomial standard
// error sqrt(p(1−p)/n), 5 of them allowed). Block entries and neighbouring frequencies are
// independent: sample correlations within 5/√n of 0.
TEST(Noise, DrawsAreNormalAndIndependent) {
  const std::size_t n = 200000;
  const auto z = standard_normals(n, 99);
  double in1 = 0, in2 = 0;
  for (double v : z) {
    in1 += std::abs(v) < 1.0;
    in2 += std::abs(v) < 2.0;
  }
  EXPECT_NEAR(in1 / n, 0.682689, 5.0 * std::sqrt(0.6827 * 0.3173 / n));
  EXPECT_NEAR(in2 / n, 0.954500, 5.0 * std::sqrt(0.9545 * 0.0455 / n));

  const std::size_t nf = 50000;
  BlockSeries b;
  for (std::size_t i = 0; i < nf; ++i) {
    b.frequency_hz.push_back(1.0 + static_cast<double>(i));
    b.blocks.push_back(make_block(1.0, 1.0, 1.0, 1.0));
  }
  const auto r = add_measurement_noise(b, {0.05, 5}).series;
  auto corr = [&](auto a, auto c, std::size_t count) {
    double sa = 0, sc = 0, saa = 0, scc = 0, sac = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const double x = a(i), y = c(i);
      sa += x;
      sc += y;
      saa += x * x;
      scc += y * y;
      sac += x * y;
    }
    const double k = static_cast<double>(count);
    return (sac / k - sa / k * sc / k) / std::sqrt((saa / k - sa * sa / k / k) * (scc / k - sc * sc / k / k));
  };
  const double tol = 5.0 / std::sqrt(static_cast<double>(nf));
  EXPECT_NEAR(corr([&](std::size_t i) { return r.blocks[i](0, 0).real(); },
                   [&](std::size_t i) { return r.blocks[i](0, 1).real(); }, nf),
              0.0, tol);  // H vs L at one frequency
  EXPECT_NEAR(corr([&](std::size_t i) { return r.blocks[i](1, 1).real(); },
                   [&](std::size_t i) { return r.blocks[i + 1](0, 0).real(); }, nf - 1),
              0.0, tol);  // P at one frequency vs H at the next
}

TEST(Noise, ReproducibleFromTheSeed) {
  const FrfSeries s = single({{1.0, 2.0}, {3.0, -1.0}, {0.5, 0.5}, {-2.0, 1.0}, {1e-6, -3e-6}});
  const auto a = add_measurement_noise(s, {0.05, 42}).series, b = add_measurement_noise(s, {0.05, 42}).series;
  const auto c = add_measurement_noise(s, {0.05, 43}).series;
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(a.values[i], b.values[i]);  // bit for bit
    EXPECT_NE(a.values[i], c.values[i]);
  }
  // The draws for a series are the first draws of the stream: a prefix of a longer run.
  const auto z5 = standard_normals(5, 42), z8 = standard_normals(8, 42);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(z5[i], z8[i]);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(a.values[i], s.values[i] * (1.0 + 0.05 * z5[i]));
}

TEST(Noise, EdgeCasesAndBadSigma) {
  const FrfSeries s = single({{1.0, 2.0}, {3.0, -1.0}});
  const auto same = add_measurement_noise(s, {0.0, 3}).series;
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(same.values[i], s.values[i]);
  EXPECT_THROW(add_measurement_noise(s, {-0.01, 1}), InvalidArgument);
  EXPECT_THROW(add_measurement_noise(s, {std::nan(""), 1}), InvalidArgument);
  // σ = 2: about 31 % of factors are negative, which flips signs; said so.
  const FrfSeries many = single(std::vector<Complex>(100, {1.0, 0.0}));
  EXPECT_TRUE(contains(add_measurement_noise(many, {2.0, 1}).warnings, "changed sign"));
}

// An averaged test (NoiseOptions::averages) against Bendat & Piersol: over many frequencies of one
// value x with hit-to-hit variation σ and a floor, the H1 estimate's scatter about x per part is
// |x|²σ²/(2 n_d) + σ_a²/n_d (the mean of n_d hits), independently of the coherence; and the
// coherence-based variance (1 − γ²)/(2 n_d γ²)|x|², averaged over the frequencies, agrees with that
// scatter (with n_d − 1: the coherence is estimated from the same hits). n = 100 000 frequencies:
// the sample variance's standard error is √(2/n) ≈ 0.45 %; the coherence formula is first order in
// the noise, 5 % here.
TEST(Noise, AveragedTestMatchesBendatAndPiersol) {
  const std::size_t n = 100000;
  const Complex x(3.0, -4.0);  // |x| = 5
  const FrfSeries s = single(std::vector<Complex>(n, x), 1.0, 0.1);
  for (const auto& [sigma, floor, averages] : {std::tuple{0.1, 0.0, 10}, std::tuple{0.05, 0.02, 5}, std::tuple{0.0, 0.05, 20}}) {
    NoiseOptions o;
    o.sigma = sigma;
    o.floor = floor;
    o.averages = averages;
    o.seed = 3;
    const auto r = add_measurement_noise(s, o);
    ASSERT_EQ(r.coherence.size(), n);
    const double want = (std::norm(x) * sigma * sigma / 2.0 + std::pow(floor * std::abs(x), 2)) / averages;  // per part
    double scatter = 0.0, from_coherence = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      scatter += std::norm(r.series.values[i] - x) / 2.0;
      from_coherence += h1_relative_variance(r.coherence[i], averages) * std::norm(x);
      ASSERT_GE(r.coherence[i], 0.0);
      ASSERT_LE(r.coherence[i], 1.0);
    }
    scatter /= static_cast<double>(n);
    from_coherence /= static_cast<double>(n);
    EXPECT_NEAR(scatter / want, 1.0, 5.0 * std::sqrt(2.0 / n)) << sigma << " " << floor << " " << averages;
    EXPECT_NEAR(from_coherence / want, 1.0, 0.05) << sigma << " " << floor << " " << averages;
  }
}

// Noise-free hits (σ = 0, no floor) averaged: every hit is the value itself, so γ² = 1 exactly.
// |Σh|²/(N Σ|h|²) computed in floating point passed 1 by an ulp at some values (N not a power of 2), and the coherence
// was then refused when written (taptest --sigma 0 --averages 4 failed).
TEST(Noise, NoiseFreeAveragedHitsHaveCoherenceOne) {
  std::vector<Complex> v;
  for (int i = 1; i <= 2000; ++i) v.emplace_back(std::cos(0.37 * i) * 1e-6 * i, std::sin(1.3 * i) * 3e-7);
  for (int averages : {3, 5, 10}) {  // a power of two sums exactly; these did not (a third of the values)
    NoiseOptions o;
    o.sigma = 0.0;
    o.averages = averages;
    const auto r = add_measurement_noise(single(v, 1.0, 0.5), o);
    ASSERT_EQ(r.coherence.size(), v.size());
    for (double c : r.coherence) {
      ASSERT_LE(c, 1.0) << averages;
      ASSERT_GE(c, 1.0 - 1e-15) << averages;
    }
    EXPECT_NO_THROW(uff_coherence(r.series.frequency_hz, r.coherence, UffDof{}, "noise-free"));
  }
}

// The floor without averaging: the seed's factor as before (the same draws), plus normal noise of
// σ_a = floor × the largest |x| on each part; the calibration: one factor on the whole series,
// reported, of the stated σ over seeds (1000 seeds: the sample σ within 5 √(1/2000) of it).
TEST(Noise, FloorAndCalibration) {
  const std::size_t n = 100000;
  std::vector<Complex> v(n, Complex(1.0, 0.0));
  v[0] = Complex(10.0, 0.0);  // the peak: σ_a = floor × 10
  const FrfSeries s = single(v, 1.0, 0.1);
  NoiseOptions plain;
  plain.sigma = 0.05;
  plain.seed = 11;
  NoiseOptions floored = plain;
  floored.floor = 0.01;
  const auto a = add_measurement_noise(s, plain).series, b = add_measurement_noise(s, floored).series;
  double var = 0.0;
  for (std::size_t i = 1; i < n; ++i) var += std::norm(b.values[i] - a.values[i]) / 2.0;
  EXPECT_NEAR(std::sqrt(var / (n - 1)), 0.01 * 10.0, 5.0 * 0.1 / std::sqrt(2.0 * n));
  double ss = 0.0;
  for (std::uint64_t seed = 0; seed < 1000; ++seed) {
    NoiseOptions c;
    c.sigma = 0.0;
    c.calibration = 0.02;
    c.seed = seed;
    const auto r = add_measurement_noise(single({{2.0, 1.0}, {1.0, -1.0}}), c);
    EXPECT_NEAR(std::abs(r.series.values[0] / Complex(2.0, 1.0) - r.calibration_factor), 0.0, 1e-15);
    EXPECT_NEAR(std::abs(r.series.values[1] / Complex(1.0, -1.0) - r.calibration_factor), 0.0, 1e-15);
    ss += std::pow(r.calibration_factor - 1.0, 2);
  }
  EXPECT_NEAR(std::sqrt(ss / 1000.0), 0.02, 5.0 * 0.02 / std::sqrt(2000.0));
  // Bad input names the field.
  NoiseOptions bad;
  bad.floor = -0.01;
  EXPECT_THROW(add_measurement_noise(s, bad), InvalidArgument);
  bad = NoiseOptions{};
  bad.calibration = 0.5;
  try {
    add_measurement_noise(s, bad);
    ADD_FAILURE() << "a calibration of 50 % is refused";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("NoiseOptions::calibration"), std::string::npos) << e.what();
  }
  bad = NoiseOptions{};
  bad.averages = 1;
  EXPECT_THROW(add_measurement_noise(s, bad), InvalidArgument);
}

// ---- Rotational FRFs by finite differences -------------------------------------------------------

namespace {

using test::cantilever_static;

// Exact dynamic receptances of a uniform Euler–Bernoulli cantilever (clamped at x = 0, free at
// x = len or held there by a spring k to ground), EI complex (structural damping), ρA real:
// EI w'''' − ρAΩ² w = f δ(x − ξ) − m δ'(x − ξ). Solved as a boundary-value problem on [0, ξ] and
// [ξ, len] with w = Σ a_k φ_k(βx), φ = (cos, sin, cosh, sinh), β⁴ = ρAΩ²/EI: clamp w = w' = 0,
// end w'' = 0 and EI w''' = k w, and at ξ w, w' continuous, [w''] = −m/EI, [w'''] = f/EI (signs:
// a tip force f gives w = fx²(3L−x)/(6EI), a tip moment m gives w = mx²/(2EI), θ = dw/dx).
struct Cantilever {
  double len = 1.0, rhoA = 1.0;
  Complex EI{1.0, 0.0};
  double spring = 0.0;  // k [N/m] to ground at x = len

  // d-th derivative of the basis at x.
  Eigen::Matrix<Complex, 1, 4> basis(Complex beta, double x, int d) const {
    const Complex bx = beta * x, bd = std::pow(beta, d);
    const Complex c = std::cos(bx), s = std::sin(bx), ch = std::cosh(bx), sh = std::sinh(bx);
    const Complex trig[4] = {c, -s, -c, s};  // cos and its derivatives; sin is the next one along
    const Complex hyp[4] = {ch, sh, ch, sh};
    Eigen::Matrix<Complex, 1, 4> r;
    r << bd * trig[d % 4], bd * trig[(d + 3) % 4], bd * hyp[d % 2], bd * hyp[(d + 1) % 2];
    return r;
  }

  // (w(x), w'(x)) for a force f and a moment m at ξ, at frequency Ω [rad/s].
  std::pair<Complex, Complex> response(double x, double xi, Complex f, Complex m, double omega) const {
    const Complex beta = std::pow(rhoA * omega * omega / EI, 0.25);
    Eigen::Matrix<Complex, 8, 8> a = Eigen::Matrix<Complex, 8, 8>::Zero();
    Eigen::Matrix<Complex, 8, 1> rhs = Eigen::Matrix<Complex, 8, 1>::Zero();
    a.block<1, 4>(0, 0) = basis(beta, 0.0, 0);
    a.block<1, 4>(1, 0) = basis(beta, 0.0, 1);
    a.block<1, 4>(2, 4) = basis(beta, len, 2);
    a.block<1, 4>(3, 4) = EI * basis(beta, len, 3) - spring * basis(beta, len, 0);
    for (int d = 0; d < 4; ++d) {
      a.block<1, 4>(4 + d, 0) = -basis(beta, xi, d);
      a.block<1, 4>(4 + d, 4) = basis(beta, xi, d);
    }
    rhs(6) = -m / EI;
    rhs(7) = f / EI;
    const Eigen::Matrix<Complex, 8, 1> coef = a.fullPivLu().solve(rhs);
    const int off = x <= xi ? 0 : 4;
    return {(basis(beta, x, 0) * coef.segment<4>(off))(0), (basis(beta, x, 1) * coef.segment<4>(off))(0)};
  }
  Complex H(double x, double xi, double w) const { return response(x, xi, 1.0, 0.0, w).first; }
  Complex N(double x, double xi, double w) const { return response(x, xi, 1.0, 0.0, w).second; }
  Complex L(double x, double xi, double w) const { return response(x, xi, 0.0, 1.0, w).first; }
  Complex P(double x, double xi, double w) const { return response(x, xi, 0.0, 1.0, w).second; }
};

// H_ij for points x_i = tip − i·s, from a kernel k(x, ξ, frequency index), on a frequency grid.
template <class Kernel>
PointFrfs point_frfs(const std::vector<double>& freqs, double tip, double s, Kernel k, int points = 3) {
  PointFrfs p;
  for (int i = 0; i < points; ++i)
    for (int j = 0; j < points; ++j) {
      FrfSeries series;
      series.frequency_hz = freqs;
      for (std::size_t f = 0; f < freqs.size(); ++f) series.values.push_back(k(tip - i * s, tip - j * s, f));
      p.set(i, j, series);
    }
  return p;
}

RotationalOptions fd(int order, double s, PMethod p = PMethod::Auto, bool symmetrise = false, bool reciprocity = false) {
  return RotationalOptions{order, s, symmetrise, p, std::nullopt, reciprocity};
}
RotationalOptions with_reciprocity(int order, double s) { return fd(order, s, PMethod::Auto, false, true); }

}  // namespace

// The reference kernel itself, against independent facts: Maxwell–Betti reciprocity
// (H(x,ξ) = H(ξ,x), N(x,ξ) = L(ξ,x)), the static flexibility at low frequency (relative
// deviation O((βL)⁴) ≈ 1e-4 at βL = 0.1; round-off in the nearly collinear basis is ~1e-10), and
// resonance at the first clamped–free root β₁L = 1.8751040687 (undamped: |H| there exceeds
// 1e6 times its value 2 % away). With a tip spring k the kernel must equal the free one modified
// by Özgüven's formula (docs/reference.md §4), H_k(x,ξ) = H(x,ξ) − H(x,L) H(L,ξ) / (1/k + H(L,L)), to
// round-off (1e-12 on values of order 0.1).
TEST(Rotational, ReferenceCantileverKernelIsRight) {
  Cantilever c;
  c.EI = {1.0, 0.02};
  const double w = 2.5 * 2.5;  // βL = 2.5
  EXPECT_LT(std::abs(c.H(0.7, 0.4, w) - c.H(0.4, 0.7, w)), 1e-12);
  EXPECT_LT(std::abs(c.N(0.7, 0.4, w) - c.L(0.4, 0.7, w)), 1e-12);
  EXPECT_LT(std::abs(c.N(1.0, 1.0, w) - c.L(1.0, 1.0, w)), 1e-12);
  Cantilever st;
  const double w0 = 0.01;  // βL = 0.1
  for (auto [x, xi] : {std::pair{1.0, 1.0}, {0.9, 1.0}, {1.0, 0.8}, {0.5, 0.3}})
    EXPECT_NEAR(st.H(x, xi, w0).real() / cantilever_static(x, xi), 1.0, 2e-4) << x << " " << xi;
  EXPECT_NEAR(st.N(1.0, 1.0, w0).real(), 0.5, 1e-4);
  EXPECT_NEAR(st.P(1.0, 1.0, w0).real(), 1.0, 1e-4);
  const double b1 = 1.8751040687;
  EXPECT_GT(std::abs(st.H(1.0, 1.0, b1 * b1 * (1 + 1e-9))), 1e6 * std::abs(st.H(1.0, 1.0, b1 * b1 * 1.02)));
  Cantilever held = c;
  held.spring = 10.0;
  for (auto [x, xi] : {std::pair{0.6, 0.6}, {0.3, 0.8}, {1.0, 0.5}}) {
    const Complex want = c.H(x, xi, w) - c.H(x, 1.0, w) * c.H(1.0, xi, w) / (1.0 / held.spring + c.H(1.0, 1.0, w));
    EXPECT_LT(std::abs(held.H(x, xi, w) - want), 1e-12) << x << " " << xi;
  }
}

// docs/reference.md §5 static check: EI = 1, L = 1, s = 0.1, from the closed-form flexibility. First order
// N = L = 299/600, P = 14/15; second order N = L = 151/300, P = 31/30. 1e-12: round-off of
// differences of O(1) numbers divided by s² = 0.01.
TEST(Rotational, StaticCantileverMatchesNotes) {
  const std::vector<double> f = {1.0};
  const auto kernel = [](double x, double xi, std::size_t) { return Complex(cantilever_static(x, xi), 0.0); };
  const PointFrfs p = point_frfs(f, 1.0, 0.1, kernel);
  const RotationalResult r1 = rotational_frfs(p, fd(1, 0.1));
  const RotationalResult r2 = rotational_frfs(p, fd(2, 0.1));
  for (const auto& [r, n, pp] : {std::tuple{&r1, 299.0 / 600, 14.0 / 15}, {&r2, 151.0 / 300, 31.0 / 30}}) {
    const Block& b = r->block.blocks[0];
    EXPECT_NEAR(H_of(b).real(), 1.0 / 3.0, 1e-15);
    EXPECT_NEAR(N_of(b).real(), n, 1e-12);
    EXPECT_NEAR(L_of(b).real(), n, 1e-12);
    EXPECT_NEAR(P_of(b).real(), pp, 1e-12);
    EXPECT_TRUE(r->p_from_cross_terms);
    EXPECT_FALSE(r->l_equals_n_by_reciprocity);
    ASSERT_TRUE(r->reciprocity_mismatch.has_value());
    EXPECT_LT(*r->reciprocity_mismatch, 1e-14);  // the kernel is symmetric
  }
  EXPECT_TRUE(contains(r1.warnings, "H02 is not used by order-1"));
}

// The shear correction removes exactly what a pure shear flexibility adds. For a segment that
// only shears (G(x, ξ) = c₀ + min(x, ξ)/κGA, x and ξ measured from the support outwards), the true
// section rotation is zero: corrected N, L and P must come out 0 (to round-off), while the raw
// differences give 1/κGA for N and L and 1/(sκGA), 2.5/(sκGA) for P (orders 1, 2).
TEST(Rotational, ShearCorrectionOnAPureShearKernel) {
  const double kGA = 3.0e7, s = 0.01;
  const std::vector<double> f = {100.0};
  const auto kernel = [&](double x, double xi, std::size_t) { return Complex(1e-6 + std::min(x, xi) / kGA, 0.0); };
  const PointFrfs p = point_frfs(f, 1.0, s, kernel);
  for (int order : {1, 2}) {
    RotationalOptions o = fd(order, s);
    const Block raw = rotational_frfs(p, o).block.blocks[0];
    EXPECT_NEAR(N_of(raw).real() * kGA, 1.0, 1e-9);
    EXPECT_NEAR(L_of(raw).real() * kGA, 1.0, 1e-9);
    EXPECT_NEAR(P_of(raw).real() * s * kGA, order == 1 ? 1.0 : 2.5, 1e-9);
    o.shear_stiffness = kGA;
    const Block corrected = rotational_frfs(p, o).block.blocks[0];
    EXPECT_LT(std::abs(N_of(corrected)) * kGA, 1e-9);
    EXPECT_LT(std::abs(L_of(corrected)) * kGA, 1e-9);
    EXPECT_LT(std::abs(P_of(corrected)) * s * kGA, 1e-9);
  }
  RotationalOptions bad = fd(2, s);
  bad.shear_stiffness = -1.0;
  EXPECT_THROW(bad.check(), InvalidArgument);
}

// Schmitz & Smith with the hammer at the tip only (H00, H10): P = N²/H00. With the first-order
// N = 299/600 and H00 = 1/3 that is 3(299/600)² = 0.745, and with the exact N = 1/2 it is 3/4:
// about 25 % below P = 1 (docs/reference.md §5). L = N by reciprocity — only when asked for (otherwise L is
// missing, an error naming H01) — and both are flagged.
TEST(Rotational, SchmitzSmithIsAbout25PercentLowOnStaticCantilever) {
  PointFrfs p;
  FrfSeries h00 = single({cantilever_static(1.0, 1.0)}), h10 = single({cantilever_static(0.9, 1.0)});
  p.set(0, 0, h00, "tip.csv");
  p.set(1, 0, h10, "p1.csv");
  try {
    rotational_frfs(p, fd(1, 0.1));
    FAIL() << "L was invented from N without assume_reciprocity";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("H01 (response at the tip, force s inward) is not given, and L needs it; H10 "
                                         "(p1.csv) is"),
              std::string::npos)
        << e.what();
    EXPECT_NE(e.hint().find("RotationalOptions::assume_reciprocity"), std::string::npos);
  }
  const RotationalResult r = rotational_frfs(p, with_reciprocity(1, 0.1));
  const Block& b = r.block.blocks[0];
  EXPECT_NEAR(N_of(b).real(), 299.0 / 600, 1e-12);
  EXPECT_EQ(L_of(b), N_of(b));
  EXPECT_NEAR(P_of(b).real(), 3.0 * std::pow(299.0 / 600, 2), 1e-12);
  EXPECT_FALSE(r.p_from_cross_terms);
  EXPECT_TRUE(r.l_equals_n_by_reciprocity);
  EXPECT_FALSE(r.reciprocity_mismatch.has_value());
  EXPECT_TRUE(contains(r.warnings, "P approximated as N·L/H00"));
  EXPECT_TRUE(contains(r.warnings, "H01 := H10 (p1.csv)"));
  EXPECT_EQ(r.filled_by_reciprocity, std::vector<std::string>{"H01 := H10 (p1.csv)"});
  // As s → 0 the approximation tends to N²/H = (1/2)²/(1/3) = 3/4 of the true P = 1: 25 % low.
  PointFrfs fine = point_frfs({1.0}, 1.0, 1e-5,
                              [](double x, double xi, std::size_t) { return Complex(cantilever_static(x, xi)); });
  const Complex p_ss = P_of(rotational_frfs(fine, fd(2, 1e-5, PMethod::SchmitzSmith)).block.blocks[0]);
  EXPECT_NEAR(p_ss.real(), 0.75, 1e-6);  // second-order N error ~ s² plus round-off ~1e-16/s
}

// Convergence on the exact dynamic kernel (damped cantilever, EI = 1 + 0.02i, ρA = 1, L = 1) at
// βL = 0.8, 2.5 and 3.5 (below and between the first two resonances 1.875 and 4.694), with s =
// 0.01 and 0.02. Observed order = log2(error(2s)/error(s)).
// * At an inner point x0 = 0.6 of the beam held by a tip spring k = 10 (so that a force at x0
//   bends the beam there, w'' ≠ 0; on the plain cantilever w''(x0) is zero statically): N and L
//   are first order (1 ± 0.1) with the first-order formulas, second order (2 ± 0.15) with the
//   second-order ones.
// * P is first order (1 ± 0.1) with either: the stencils straddle the kink of ∂²H/∂x∂ξ at x = ξ.
// * At the free tip of the plain cantilever w'' = 0, so Taylor expansion gives N₁ − N = s²w'''/6 + O(s³) and
//   N₂ − N = −s²w'''/3 + O(s³): both second order, the first-order formula with −1/2 times the
//   second-order error (±0.05 for the O(s) relative remainder). Likewise L by reciprocity.
// Tolerances allow for the next term of the error expansion (relative size ~ s·βL).
TEST(Rotational, ConvergenceOrdersOnDynamicCantilever) {
  Cantilever free;
  free.EI = {1.0, 0.02};
  Cantilever held = free;
  held.spring = 10.0;
  const std::vector<double> beta_l = {0.8, 2.5, 3.5};
  std::vector<double> omegas, freqs;
  for (double bl : beta_l) {
    omegas.push_back(bl * bl);
    freqs.push_back(bl * bl / (2.0 * kPi));
  }
  // Per frequency: the errors of N, L, P at point x0 (complex, FD minus exact).
  auto errors = [&](int order, double s, double x0) {
    const Cantilever& c = x0 < 1.0 ? held : free;
    const auto kernel = [&](double x, double xi, std::size_t f) { return c.H(x, xi, omegas[f]); };
    const RotationalResult r = rotational_frfs(point_frfs(freqs, x0, s, kernel), fd(order, s));
    std::vector<std::array<Complex, 3>> e;
    for (std::size_t f = 0; f < freqs.size(); ++f) {
      const Block& b = r.block.blocks[f];
      const double w = omegas[f];
      e.push_back({N_of(b) - c.N(x0, x0, w), L_of(b) - c.L(x0, x0, w), P_of(b) - c.P(x0, x0, w)});
    }
    return e;
  };
  for (double x0 : {0.6, 1.0}) {
    for (int order : {1, 2}) {
      const auto coarse = errors(order, 0.02, x0), fine = errors(order, 0.01, x0);
      for (std::size_t f = 0; f < freqs.size(); ++f) {
        const double nl = x0 < 1.0 ? order : 2.0;
        const double want[3] = {nl, nl, 1.0}, tol[3] = {nl > 1 ? 0.15 : 0.1, nl > 1 ? 0.15 : 0.1, 0.1};
        for (int q = 0; q < 3; ++q)
          EXPECT_NEAR(std::log2(std::abs(coarse[f][q]) / std::abs(fine[f][q])), want[q], tol[q])
              << "x0 " << x0 << " order " << order << " βL " << beta_l[f] << " entry "
              << "NLP"[q];
      }
    }
  }
  const auto first = errors(1, 0.01, 1.0), second = errors(2, 0.01, 1.0);
  for (std::size_t f = 0; f < freqs.size(); ++f)
    for (int q = 0; q < 2; ++q) {
      const Complex ratio = first[f][q] / second[f][q];
      EXPECT_NEAR(ratio.real(), -0.5, 0.05) << "βL " << beta_l[f] << " entry "
                                            << "NL"[q];
      EXPECT_NEAR(ratio.imag(), 0.0, 0.05) << "βL " << beta_l[f] << " entry "
                                           << "NL"[q];
    }
}

// A roving hammer (sensor fixed at the tip: H00, H01, H02) gives N from L by reciprocity; with
// both directions measured but different (noise), --symmetrise averages them and the mismatch
// is reported.
TEST(Rotational, ReciprocityFillAndSymmetrise) {
  const auto kernel = [](double x, double xi, std::size_t) { return Complex(cantilever_static(x, xi)); };
  const PointFrfs all = point_frfs({1.0}, 1.0, 0.1, kernel);
  PointFrfs roving;
  for (int j = 0; j < 3; ++j) roving.set(0, j, *all.h[0][j]);
  EXPECT_THROW(rotational_frfs(roving, fd(2, 0.1)), InputError);  // N not measured, not invented
  const RotationalResult r = rotational_frfs(roving, with_reciprocity(2, 0.1));
  EXPECT_NEAR(N_of(r.block.blocks[0]).real(), 151.0 / 300, 1e-12);
  EXPECT_EQ(N_of(r.block.blocks[0]), L_of(r.block.blocks[0]));
  EXPECT_TRUE(r.l_equals_n_by_reciprocity);

  PointFrfs skew = all;  // H10 measured 1 % high: N differs from L
  skew.h[1][0]->values[0] *= 1.01;
  const double h10 = cantilever_static(0.9, 1.0);
  const RotationalResult kept = rotational_frfs(skew, fd(1, 0.1));
  const RotationalResult sym = rotational_frfs(skew, fd(1, 0.1, PMethod::Auto, true));
  const double n_skew = 299.0 / 600 - 0.01 * h10 / 0.1, l_true = 299.0 / 600;
  EXPECT_NEAR(N_of(kept.block.blocks[0]).real(), n_skew, 1e-12);
  EXPECT_NEAR(L_of(kept.block.blocks[0]).real(), l_true, 1e-12);
  EXPECT_NEAR(N_of(sym.block.blocks[0]).real(), 0.5 * (n_skew + l_true), 1e-12);
  EXPECT_EQ(N_of(sym.block.blocks[0]), L_of(sym.block.blocks[0]));
  ASSERT_TRUE(kept.reciprocity_mismatch.has_value());
  EXPECT_NEAR(*kept.reciprocity_mismatch, std::abs(n_skew - l_true) / l_true, 1e-12);
  // A missing cross term (H21): without reciprocity P falls back to N·L/H00, saying that H12
  // could stand in; with it, H21 is filled from H12 and P is by cross terms, and said so.
  PointFrfs no21 = all;
  no21.h[2][1].reset();
  const RotationalResult plain = rotational_frfs(no21, fd(2, 0.1));
  EXPECT_FALSE(plain.p_from_cross_terms);
  EXPECT_TRUE(contains(plain.warnings, "because H21 is not given (their transposes are: assume_reciprocity would use them)"));
  EXPECT_TRUE(plain.filled_by_reciprocity.empty());
  const RotationalResult r21 = rotational_frfs(no21, with_reciprocity(2, 0.1));
  EXPECT_TRUE(r21.p_from_cross_terms);
  EXPECT_NEAR(P_of(r21.block.blocks[0]).real(), 31.0 / 30, 1e-12);
  EXPECT_TRUE(contains(r21.warnings, "H21 := H12"));
}

TEST(Rotational, BadInputIsRejected) {
  const auto kernel = [](double x, double xi, std::size_t) { return Complex(cantilever_static(x, xi)); };
  const PointFrfs all = point_frfs({1.0, 2.0}, 1.0, 0.1, kernel);
  EXPECT_THROW(rotational_frfs(all, fd(3, 0.1)), InvalidArgument);
  EXPECT_THROW(rotational_frfs(all, fd(1, 0.0)), InvalidArgument);
  EXPECT_THROW(rotational_frfs(all, fd(1, -0.01)), InvalidArgument);
  EXPECT_THROW(rotational_frfs(all, fd(1, std::nan(""))), InvalidArgument);
  PointFrfs no_tip = all;
  no_tip.h[0][0].reset();
  EXPECT_THROW(rotational_frfs(no_tip, fd(1, 0.1)), InputError);
  PointFrfs no_point2 = all;  // neither H20 nor H02
  no_point2.h[2][0].reset();
  no_point2.h[0][2].reset();
  EXPECT_NO_THROW(rotational_frfs(no_point2, fd(1, 0.1)));
  EXPECT_THROW(rotational_frfs(no_point2, fd(2, 0.1)), InputError);
  PointFrfs no_h11 = all;  // cross terms demanded but H11 missing
  no_h11.h[1][1].reset();
  try {
    rotational_frfs(no_h11, fd(1, 0.1, PMethod::CrossTerms));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("H11"), std::string::npos) << e.what();
  }
  PointFrfs grid = all;  // a different grid, named by its source
  FrfSeries shifted = *all.h[1][0];
  shifted.frequency_hz[1] = 2.5;
  grid.set(1, 0, shifted, "p1.csv");
  try {
    rotational_frfs(grid, fd(1, 0.1));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("H10 (p1.csv)"), std::string::npos) << e.what();
  }
  PointFrfs nan = all;
  nan.h[1][1]->values[0] = {std::nan(""), 0.0};
  EXPECT_THROW(rotational_frfs(nan, fd(1, 0.1)), InputError);
  // A source that could not read all it held (a truncated file): a missing H11 may be there, so P
  // is not approximated around it unless asked for; the message names what was not read.
  PointFrfs truncated = no_h11;
  truncated.unread = {"tap.uff: dataset 58b #4 (line 1010) skipped: record 12 is cut off"};
  try {
    rotational_frfs(truncated, fd(1, 0.1));
    ADD_FAILURE() << "P approximated around an unread dataset";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "needs H11, not given, and the source could not read one part of what it holds (tap.uff: dataset 58b #4"),
              std::string::npos)
        << e.what();
    EXPECT_NE(e.hint().find("RotationalOptions::p_method SchmitzSmith"), std::string::npos) << e.hint();
  }
  EXPECT_NO_THROW(rotational_frfs(truncated, fd(1, 0.1, PMethod::SchmitzSmith)));
  EXPECT_FALSE(rotational_frfs(no_h11, fd(1, 0.1)).p_from_cross_terms);  // complete source: approximated, said
  PointFrfs zero = all;                                                  // P ≈ N·L/H00 with H00 = 0
  zero.h[0][0]->values[1] = 0.0;
  EXPECT_THROW(rotational_frfs(zero, fd(1, 0.1, PMethod::SchmitzSmith)), NumericalError);
}
