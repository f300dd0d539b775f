// Tests of the pitch choice (stability/pitch.hpp) against what is independent of it:
//   * Budak's closed form against its defining condition, the regenerative sum Σ_j e^{−iω_c τ_j} = 0
//     (complex arithmetic, not the closed form's algebra);
//   * the chosen pattern against a brute-force search: the multi-delay full-discretization limit
//     (FullDiscretization::boundary, the test's own loop) on a grid of ΔP at the target speed;
//   * the three-angle pattern's closed form in both parameters against the same sum, and its choice
//     against a brute-force search over a (u, v) grid;
//   * bad input: errors naming the field.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
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
  // … and the three-angle search (its batches and its order of evaluation the same for any count).
  CuttingConditions three = four_teeth();
  three.teeth = 3;
  o.pattern = PitchPattern::ThreeAngle;
  o.parallel.threads = 1;
  const PitchChoice c = choose_pitch(one_mode(), three, o);
  o.parallel.threads = 2;
  const PitchChoice d = choose_pitch(one_mode(), three, o);
  EXPECT_EQ(c.pitch_rad, d.pitch_rad);
  EXPECT_EQ(c.chosen.depth_m, d.chosen.depth_m);
  ASSERT_EQ(c.samples.size(), d.samples.size());
  for (std::size_t i = 0; i < c.samples.size(); ++i) EXPECT_EQ(c.samples[i].robust_depth_m, d.samples[i].robust_depth_m);
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
  // The three-angle pattern: a tooth count not a multiple of 3, parameters that leave an angle ≤ 0
  // (each of P₀, P₁, P₂ in turn), a second parameter given to a one-parameter pattern, limits that
  // leave no room.
  o.pattern = PitchPattern::ThreeAngle;
  EXPECT_NE(thrown_message([&] { choose_pitch(model, four_teeth(), o); }).find("PitchChoiceOptions::pattern three-angle"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { pitch_pattern(PitchPattern::ThreeAngle, 4, 0.1, 0.1); }).find("multiple of 3"),
            std::string::npos);
  for (const auto& [u, v] : std::vector<std::pair<double, double>>{{2.1, 0.0}, {0.0, 2.2}, {0.0, -2.1}}) {
    const std::string m = thrown_message([&] { pitch_pattern(PitchPattern::ThreeAngle, 3, u, v); });
    EXPECT_NE(m.find("variation_rad"), std::string::npos) << m;
    EXPECT_NE(m.find("second_variation_rad"), std::string::npos) << m;
    EXPECT_NE(m.find("≤ 0"), std::string::npos) << m;
  }
  EXPECT_NE(thrown_message([&] { pitch_pattern(PitchPattern::Linear, 3, 0.1, 0.1); }).find("second_variation_rad"),
            std::string::npos);
  CuttingConditions six = four_teeth();
  six.teeth = 6;
  o.min_pitch_rad = radians_of(61.0);
  o.max_pitch_rad = radians_of(90.0);
  EXPECT_NE(thrown_message([&] { choose_pitch(model, six, o); }).find("PitchChoiceOptions::min_pitch_rad"), std::string::npos);
}

// The three-angle closed form against its defining condition: the pattern's angles computed here
// (2π/N − u, 2π/N + u − v, 2π/N + v, repeated) make the regenerative sum vanish at ω_c to
// rounding (1e-12 of the N terms), for 3 and 6 teeth and the first six (u, v) of
// budak_three_angle_variations; each lies on the lattice (m, n)·2πΩ/(3ω_c), P₀ the smallest angle.
TEST(PitchChoice, ThreeAngleClosedFormCancelsTheRegenerativeSum) {
  const double speed = 9000.0, fc = 2500.0;
  const double q = 2.0 * kPi * rad_s_of_rpm(speed) / (3.0 * omega_of(fc));
  const std::vector<std::pair<double, double>> uv = budak_three_angle_variations(speed, fc, 6);
  ASSERT_EQ(uv.size(), 6u);
  EXPECT_NEAR(uv[0].first, q, 1e-15);  // (q, q): the equal steps, the linear rule for three teeth
  EXPECT_NEAR(uv[0].second, q, 1e-15);
  EXPECT_NEAR(uv[1].first, q, 1e-15);  // (q, 0): its mirror image
  EXPECT_NEAR(uv[1].second, 0.0, 1e-15);
  for (int teeth : {3, 6}) {
    const double even = 2.0 * kPi / teeth;
    for (const auto& [u, v] : uv) {
      std::vector<double> p;
      for (int j = 0; j < teeth; ++j) p.push_back(even + (j % 3 == 0 ? -u : j % 3 == 1 ? u - v : v));
      EXPECT_LT(regenerative_sum(p, speed, fc), 1e-12 * teeth) << "u " << u / q << " q, v " << v / q << " q";
      EXPECT_GT(regenerative_sum(p, speed, 1.1 * fc), 0.05) << "u " << u / q << " q, v " << v / q << " q";
      const std::vector<double> lib = pitch_pattern(PitchPattern::ThreeAngle, teeth, u, v);
      for (int j = 0; j < teeth; ++j) EXPECT_NEAR(lib[j], p[j], 1e-15);
      EXPECT_NEAR(std::accumulate(lib.begin(), lib.end(), 0.0), 2.0 * kPi, 1e-12);
      EXPECT_LT(p[0], std::min(p[1], p[2]));
      const double m = u / q, n = v / q;
      EXPECT_NEAR(m, std::round(m), 1e-12);
      EXPECT_NEAR(n, std::round(n), 1e-12);
      EXPECT_NE((static_cast<long>(std::round(m + n)) % 3 + 3) % 3, 0);
    }
  }
  // The diagonal of the one-parameter entry point is Linear's three-tooth rule.
  EXPECT_EQ(budak_variations(PitchPattern::ThreeAngle, 6, speed, fc, 3), budak_variations(PitchPattern::Linear, 3, speed, fc, 3));
}

// The check for the three-angle pattern: the benchmark mode, 3 teeth, a/D 0.5 down-milling,
// at 5000 rpm (on the even tool's lobe) and 4130 rpm (a lobe minimum). Brute force, independent of
// choose_pitch's search: the full-discretization limit (FullDiscretization::boundary at the choice's
// steps and ceiling) of the angles computed here, on a grid of (u, v) with step h = 1° over
// 0 < u ≤ 1.5q, −u < v < 2u (every tool with P₀ the smallest angle and u up to halfway to the next
// closed forms (2q, 2q) and (2q, 0): the basin of (q, q) and (q, 0)), maximising the same robust limit (the lowest at
// (u, v) and (u, v)(1 ± 2 %)). Asserted:
//  * the chosen pattern's robust limit lies within what one grid step can change of the brute-force
//    optimum: |chosen − best| ≤ the largest change of the robust limit from the optimum to its 8
//    grid neighbours (the grid cannot resolve the optimum better than that; the search's finer
//    steps can land above the grid's best). That change is large here (measured 1.09 and 1.10 mm
//    on 2.75 and 2.57 mm: the limit rises towards cliffs), so also, one-sided and tight:
//  * the search, local around the closed forms, misses no better pattern the global grid finds:
//    chosen ≥ 0.98 × best (measured 1.07 and 1.06 × best: the search's finer steps; 2 % for a grid
//    point between the search's points);
//  * the chosen sample's robust limit is what the brute force's own loop gives for its angles
//    (to 1e-5: the depth bisection's 1e-6 on angles that may differ from pitch_pattern's by rounding);
//  * Budak's closed form itself (the better of (q, q) and (q, 0)) is the start, on the optimum's
//    plateau: its robust limit at least 0.9 of the grid's best (measured 0.93 at 5000 rpm, 1.02 at
//    4130 rpm; the chatter frequency moves with the pitch, which the rule, holding ω_c, does not see);
//  * the two-parameter family holds Linear's three-tooth pattern (u = v): its choice is at least
//    as deep as Linear's (to 2 %, the 1-D search's finer steps).
// Where the optimum lies is not asserted: at 5000 rpm the grid's best is near the mirror-image
// closed form (q, 0) and the search's near (q, q), two basins of about equal height (the order of
// the angles matters only through the partial immersion).
TEST(PitchChoice, ThreeAngleChoiceAgreesWithBruteForce) {
  const ModalModel model = one_mode();
  CuttingConditions cutting = four_teeth();
  cutting.teeth = 3;
  for (double speed : {5000.0, 4130.0}) {
    PitchChoiceOptions o;
    o.speed_rpm = speed;
    o.pattern = PitchPattern::ThreeAngle;
    const PitchChoice r = choose_pitch(model, cutting, o);
    const double q = 2.0 * kPi * rad_s_of_rpm(speed) / (3.0 * omega_of(r.chatter_hz));
    const double even = 2.0 * kPi / 3.0;
    auto limit = [&](double u, double v) {
      CuttingConditions c = cutting;
      c.pitch_rad = {even - u, even + u - v, even + v};
      return FullDiscretization(model, c, r.steps, 2).boundary(speed, r.max_depth_m, 60, 1e-6).depth_m;
    };
    auto robust = [&](double u, double v) {
      return std::min({limit(u, v), limit(0.98 * u, 0.98 * v), limit(1.02 * u, 1.02 * v)});
    };
    const double h = radians_of(1.0);
    const int nu = static_cast<int>(std::floor(1.5 * q / h));
    std::map<std::pair<int, int>, double> grid;  // (i, j) → robust limit at (i h, j h)
    for (int i = 1; i <= nu; ++i)
      for (int j = -i + 1; j < 2 * i; ++j) grid[{i, j}] = robust(i * h, j * h);
    const auto best = std::max_element(grid.begin(), grid.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    double step_change = 0.0;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        if (const auto nb = grid.find({best->first.first + di, best->first.second + dj}); nb != grid.end())
          step_change = std::max(step_change, std::abs(nb->second - best->second));
    const auto chosen = std::find_if(r.samples.begin(), r.samples.end(), [&](const PitchSample& s) {
      return s.variation_rad == r.variation_rad && s.second_variation_rad == r.second_variation_rad;
    });
    ASSERT_NE(chosen, r.samples.end());
    const std::string where = fmt::format(
        "{} rpm: brute force ({}°, {}°) {:.4g} mm (a grid step changes it by {:.3g} mm); "
        "chosen ({:.3f}°, {:.3f}°) {:.4g} mm",
        speed, degrees_of(best->first.first * h), degrees_of(best->first.second * h), best->second * 1e3, step_change * 1e3,
        degrees_of(r.variation_rad), degrees_of(r.second_variation_rad), chosen->robust_depth_m * 1e3);
    EXPECT_LE(std::abs(chosen->robust_depth_m - best->second), step_change) << where;
    EXPECT_GE(chosen->robust_depth_m, 0.98 * best->second) << where;
    EXPECT_GE(r.closed_form_robust_depth_m, 0.9 * best->second) << where;
    EXPECT_NEAR(robust(r.variation_rad, r.second_variation_rad), chosen->robust_depth_m, 1e-5 * chosen->robust_depth_m) << where;
    PitchChoiceOptions lin = o;
    lin.pattern = PitchPattern::Linear;
    const PitchChoice l = choose_pitch(model, cutting, lin);
    const auto l_best = std::find_if(l.samples.begin(), l.samples.end(),
                                     [&](const PitchSample& s) { return s.variation_rad == l.variation_rad; });
    ASSERT_NE(l_best, l.samples.end());
    EXPECT_GE(chosen->robust_depth_m, 0.98 * l_best->robust_depth_m) << where;
    EXPECT_GT(r.gain, 1.5) << where;
    EXPECT_LE(r.chosen.depth_error_m, 0.01 * r.chosen.depth_m) << where;
  }
}
