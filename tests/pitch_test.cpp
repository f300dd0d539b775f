// Tests of the pitch choice (stability/pitch.hpp) against what is independent of it:
//   * Budak's closed form against its defining condition, the regenerative sum Σ_j e^{−iω_c τ_j} = 0
//     (complex arithmetic, not the closed form's algebra);
//   * the chosen pattern against a brute-force search: the multi-delay full-discretization limit
//     (FullDiscretization::boundary, the test's own loop) on a grid of ΔP at the target speed;
//   * bad input: errors naming the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <vector>

#include "support/stability_util.hpp"
#include "support/test_util.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/pitch.hpp"

using namespace toolpoint;

namespace {

using namespace test::benchmark;
using test::thrown_message;

// The benchmark mode in x (rigid y), 4 teeth, a/D 0.5 down-milling, K_r 0.3: docs/stability.md's
// uniform/variable pitch figures.
ModalModel one_mode() { return ModalModel{{kBench}, {}}; }
CuttingConditions four_teeth() { return CuttingConditions{4, kKt, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)}; }

// Σ_j e^{−iω τ_j} with τ_j = p_{j−1}/Ω: the regenerative sum the closed form zeroes.
double regenerative_sum(const std::vector<double>& pitch_rad, double speed_rpm, double chatter_hz) {
  std::complex<double> s = 0.0;
  for (double p : pitch_rad) s += std::exp(std::complex<double>(0.0, -omega_of(chatter_hz) * p / rad_s_of_rpm(speed_rpm)));
  return std::abs(s);
}

}  // namespace

// The closed form's ΔP_k make the teeth's regenerative waves cancel at ω_c (to rounding: 1e-12 of
// the N terms), for both patterns and several tooth counts; the angles add up to 2π.
TEST(PitchChoice, ClosedFormCancelsTheRegenerativeSum) {
  for (const auto& [pattern, teeth] : std::vector<std::pair<PitchPattern, int>>{{PitchPattern::Alternating, 2},
                                                                                {PitchPattern::Alternating, 4},
                                                                                {PitchPattern::Alternating, 6},
                                                                                {PitchPattern::Linear, 3},
                                                                                {PitchPattern::Linear, 4},
                                                                                {PitchPattern::Linear, 5}}) {
    const double speed = 9000.0, fc = 2500.0;
    for (double dp : budak_variations(pattern, teeth, speed, fc, 3)) {
      const std::vector<double> p = pitch_pattern(pattern, teeth, dp);
      EXPECT_NEAR(std::accumulate(p.begin(), p.end(), 0.0), 2.0 * kPi, 1e-12);
      EXPECT_LT(regenerative_sum(p, speed, fc), 1e-12 * teeth) << to_string(pattern) << " N=" << teeth << " ΔP=" << dp;
      // … and not at a frequency 10 % off: the condition is specific to ω_c.
      EXPECT_GT(regenerative_sum(p, speed, 1.1 * fc), 0.05) << to_string(pattern) << " N=" << teeth;
    }
  }
}

// The check: Budak's pitch for the benchmark mode against the brute-force search over the
// pitch grid (0.5° steps of ΔP, alternating pitch, the closed form's basin k = 0) at a speed on the
// even tool's lobe (5000 rpm) and at one of its lobe minima (4130 rpm).
//  * The chosen (refined) pattern maximises the lowest limit over ΔP(1 ± 2 %): it agrees with the
//    brute-force argmax of the same quantity within the grid step (0.5°), and reaches its value
//    within 2 % (the search's finer points can land off the grid).
//  * The closed form itself is the start: measured, it lies 1.3–1.4° (7–9 %) below the brute-force
//    optimum, on the same plateau of the limit, because the chatter frequency moves with the pitch
//    (the rule keeps the even tool's). Asserted: within 12 % of the optimum's ΔP, and its limit
//    at least 0.9 of the brute-force best.
TEST(PitchChoice, BudakAndRefinedChoiceAgreeWithBruteForce) {
  const ModalModel model = one_mode();
  const CuttingConditions cutting = four_teeth();
  for (double speed : {5000.0, 4130.0}) {
    PitchChoiceOptions o;
    o.speed_rpm = speed;
    o.parallel.threads = 1;
    const PitchChoice r = choose_pitch(model, cutting, o);
    const double dp0 = r.closed_form_variation_rad;
    const double basin = 2.0 * dp0;  // halfway to ΔP_1 = 3ΔP_0
    auto limit = [&](double dp) {
      CuttingConditions c = cutting;
      c.pitch_rad = pitch_pattern(PitchPattern::Alternating, 4, dp);
      return FullDiscretization(model, c, r.steps, 2).boundary(speed, r.max_depth_m, 60, 1e-6).depth_m;
    };
    const double h = radians_of(0.5);
    double best_plain = 0.0, at_plain = 0.0, best_robust = 0.0, at_robust = 0.0;
    for (double dp = h; dp < basin; dp += h) {
      const double d = limit(dp), robust = std::min({d, limit(0.98 * dp), limit(1.02 * dp)});
      if (d > best_plain) best_plain = d, at_plain = dp;
      if (robust > best_robust) best_robust = robust, at_robust = dp;
    }
    EXPECT_LE(std::abs(r.variation_rad - at_robust), h)
        << speed << " rpm: chosen " << degrees_of(r.variation_rad) << "°, brute force " << degrees_of(at_robust) << "°";
    const auto chosen = std::find_if(r.samples.begin(), r.samples.end(),
                                     [&](const PitchSample& s) { return s.variation_rad == r.variation_rad; });
    ASSERT_NE(chosen, r.samples.end());
    EXPECT_GE(chosen->robust_depth_m, 0.98 * best_robust) << speed;
    EXPECT_LE(std::abs(dp0 - at_plain), 0.12 * at_plain)
        << speed << " rpm: Budak " << degrees_of(dp0) << "°, brute force " << degrees_of(at_plain) << "°";
    EXPECT_GE(r.closed_form_depth_m, 0.9 * best_plain) << speed;
    // The point of it: well above the even tool (measured 1.9× and 8.5×).
    EXPECT_GT(r.gain, 1.5) << speed;
    EXPECT_LE(r.chosen.depth_error_m, 0.01 * r.chosen.depth_m) << speed;
  }
}

// The same threads-independence as the rest of the library: 1 and 2 threads give the same result.
TEST(PitchChoice, IdenticalForAnyThreadCount) {
  PitchChoiceOptions o;
  o.speed_rpm = 9000.0;
  o.search_points = 5;
  o.parallel.threads = 1;
  const PitchChoice a = choose_pitch(one_mode(), four_teeth(), o);
  o.parallel.threads = 2;
  const PitchChoice b = choose_pitch(one_mode(), four_teeth(), o);
  EXPECT_EQ(a.variation_rad, b.variation_rad);
  EXPECT_EQ(a.chosen.depth_m, b.chosen.depth_m);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t i = 0; i < a.samples.size(); ++i) EXPECT_EQ(a.samples[i].depth_m, b.samples[i].depth_m);
}

TEST(PitchChoice, BadInputNamesTheField) {
  const ModalModel model = one_mode();
  PitchChoiceOptions o;
  o.speed_rpm = 5000.0;
  // Limits that leave no room around the even pitch (90°).
  o.min_pitch_rad = radians_of(95.0);
  o.max_pitch_rad = radians_of(120.0);
  EXPECT_NE(thrown_message([&] { choose_pitch(model, four_teeth(), o); }).find("min_pitch_rad"), std::string::npos);
  o.min_pitch_rad = radians_of(100.0);
  o.max_pitch_rad = radians_of(80.0);
  EXPECT_NE(thrown_message([&] { o.check(); }).find("PitchChoiceOptions::min_pitch_rad"), std::string::npos);
  o = PitchChoiceOptions{};
  EXPECT_NE(thrown_message([&] { o.check(); }).find("PitchChoiceOptions::speed_rpm"), std::string::npos);
  o.speed_rpm = 5000.0;
  o.robustness = 0.5;
  EXPECT_NE(thrown_message([&] { o.check(); }).find("PitchChoiceOptions::robustness"), std::string::npos);
  o.robustness = 0.02;
  // An alternating pitch needs an even tooth count.
  CuttingConditions three = four_teeth();
  three.teeth = 3;
  EXPECT_NE(thrown_message([&] { choose_pitch(model, three, o); }).find("PitchChoiceOptions::pattern"), std::string::npos);
  // The pitch is what is chosen: a given one is refused.
  CuttingConditions given = four_teeth();
  given.pitch_rad = pitch_pattern(PitchPattern::Alternating, 4, 0.2);
  EXPECT_NE(thrown_message([&] { choose_pitch(model, given, o); }).find("CuttingConditions::pitch_rad"), std::string::npos);
  // Pitch angles that do not add up to a revolution (CuttingConditions::check).
  given.pitch_rad = {1.0, 1.0, 1.0, 1.0};
  EXPECT_NE(thrown_message([&] { given.check(); }).find("pitch"), std::string::npos);
  // A variation that leaves an angle ≤ 0.
  EXPECT_THROW(pitch_pattern(PitchPattern::Linear, 4, 1.1), InvalidArgument);  // 90° − 1.5 × 63° < 0
}
