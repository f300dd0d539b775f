// The choice of a variable pitch (pitch.hpp): Budak's closed form, then the full-discretization
// limit over a bounded search around it.
#include "toolpoint/stability/pitch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The even pitch's limits when the options leave them at 0.
std::pair<double, double> pitch_limits(const PitchChoiceOptions& o, int teeth) {
  const double even = 2.0 * kPi / teeth;
  return {o.min_pitch_rad > 0.0 ? o.min_pitch_rad : 0.5 * even, o.max_pitch_rad > 0.0 ? o.max_pitch_rad : 1.5 * even};
}

// The largest ΔP whose angles stay within [lo, hi]: the extreme angles are 2π/N ± s·ΔP with
// s = ½ (Alternating) or (N − 1)/2 (Linear).
double max_variation(PitchPattern pattern, int teeth, double lo, double hi) {
  const double even = 2.0 * kPi / teeth;
  const double s = pattern == PitchPattern::Alternating ? 0.5 : 0.5 * (teeth - 1);
  return std::min(even - lo, hi - even) / s;
}

// The limit at one speed at a fixed discretization (FullDiscretization::boundary).
BoundaryPoint limit_at(const ModalModel& model, const CuttingConditions& cutting, const PitchChoiceOptions& o, int steps,
                       double max_depth_m) {
  return FullDiscretization(model, cutting, steps, o.degree).boundary(o.speed_rpm, max_depth_m, o.depth_steps, 1e-6);
}

// The limit at steps and 2 × steps, Richardson-extrapolated (stability.hpp, BoundaryPoint::depth_m).
BoundaryPoint extrapolated_limit(const ModalModel& model, const CuttingConditions& cutting, const PitchChoiceOptions& o,
                                 int steps, double max_depth_m) {
  const BoundaryPoint coarse = limit_at(model, cutting, o, steps, max_depth_m);
  BoundaryPoint fine = limit_at(model, cutting, o, 2 * steps, max_depth_m);
  fine.steps = 2 * steps;
  if (coarse.kind == BoundaryKind::None || fine.kind == BoundaryKind::None) {
    fine.depth_error_m = kNaN;
    return fine;
  }
  const double factor = std::pow(2.0, o.degree + 1) - 1.0;
  fine.depth_error_m = std::abs(fine.depth_m - coarse.depth_m) / factor;
  fine.depth_m += (fine.depth_m - coarse.depth_m) / factor;
  return fine;
}

}  // namespace

const char* to_string(PitchPattern p) { return p == PitchPattern::Alternating ? "alternating" : "linear"; }

std::vector<double> pitch_pattern(PitchPattern pattern, int teeth, double variation_rad) {
  if (teeth < 2) throw InvalidArgument(fmt::format("a variable pitch needs at least 2 teeth, not {}", teeth));
  if (pattern == PitchPattern::Alternating && teeth % 2 != 0)
    throw InvalidArgument(fmt::format("an alternating pitch needs an even number of teeth, not {}", teeth),
                          "use the linear pattern for an odd number of teeth");
  if (!std::isfinite(variation_rad) || variation_rad < 0.0)
    throw InvalidArgument(fmt::format("pitch variation {} rad must be ≥ 0", variation_rad));
  const double even = 2.0 * kPi / teeth;
  if (!(max_variation(pattern, teeth, 0.0, 2.0 * kPi) > variation_rad))
    throw InvalidArgument(fmt::format("pitch variation {:.6g} rad leaves a pitch angle ≤ 0 with {} teeth ({} pattern)",
                                      variation_rad, teeth, to_string(pattern)));
  std::vector<double> p(static_cast<std::size_t>(teeth));
  for (int j = 0; j < teeth; ++j)
    p[j] = pattern == PitchPattern::Alternating ? even + (j % 2 == 0 ? -0.5 : 0.5) * variation_rad
                                                : even + (j - 0.5 * (teeth - 1)) * variation_rad;
  return p;
}

std::vector<double> budak_variations(PitchPattern pattern, int teeth, double speed_rpm, double chatter_hz, int count) {
  if (!(speed_rpm > 0.0) || !std::isfinite(speed_rpm) || !(chatter_hz > 0.0) || !std::isfinite(chatter_hz))
    throw InvalidArgument(
        fmt::format("Budak's rule needs a speed and a chatter frequency > 0 (got {} rpm, {} Hz)", speed_rpm, chatter_hz));
  const double ratio = rad_s_of_rpm(speed_rpm) / omega_of(chatter_hz);  // Ω/ω_c
  std::vector<double> v;
  for (int k = 0; static_cast<int>(v.size()) < count; ++k) {
    if (pattern == PitchPattern::Alternating) v.push_back((2 * k + 1) * kPi * ratio);
    else if (k > 0 && k % teeth != 0) v.push_back(2.0 * kPi * k * ratio / teeth);
  }
  return v;
}

void PitchChoiceOptions::check() const {
  if (!std::isfinite(speed_rpm) || !(speed_rpm > 0.0))
    throw InvalidArgument(fmt::format("PitchChoiceOptions::speed_rpm {} must be > 0 (the target spindle speed)", speed_rpm));
  for (const auto& [value, name] : {std::pair{min_pitch_rad, "min_pitch_rad"}, std::pair{max_pitch_rad, "max_pitch_rad"}})
    if (!std::isfinite(value) || value < 0.0 || value >= 2.0 * kPi)
      throw InvalidArgument(fmt::format("PitchChoiceOptions::{} {} rad must lie in [0, 2π) (0: automatic)", name, value));
  if (min_pitch_rad > 0.0 && max_pitch_rad > 0.0 && !(min_pitch_rad < max_pitch_rad))
    throw InvalidArgument(
        fmt::format("PitchChoiceOptions::min_pitch_rad {} rad must be below PitchChoiceOptions::max_pitch_rad {} rad",
                    min_pitch_rad, max_pitch_rad));
  if (!std::isfinite(chatter_hz) || chatter_hz < 0.0)
    throw InvalidArgument(fmt::format("PitchChoiceOptions::chatter_hz {} Hz must be ≥ 0 (0: the dominant mode's)", chatter_hz));
  if (!(window > 0.0 && window <= 1.0))
    throw InvalidArgument(fmt::format("PitchChoiceOptions::window {} must lie in (0, 1]", window),
                          "0.5 searches 0.5…1.5 × the closed-form variation");
  if (search_points < 3 || search_points > 201)
    throw InvalidArgument(fmt::format("PitchChoiceOptions::search_points {} must lie in 3…201", search_points));
  if (steps != 0 && (steps < 4 || steps > 2000))
    throw InvalidArgument(fmt::format("PitchChoiceOptions::steps {} must be 0 (automatic) or lie in 4…2000", steps));
  if (degree < 1 || degree > 3) throw InvalidArgument(fmt::format("PitchChoiceOptions::degree {} must be 1, 2 or 3", degree));
  if (!(robustness >= 0.0 && robustness <= 0.2))
    throw InvalidArgument(fmt::format("PitchChoiceOptions::robustness {} must lie in [0, 0.2]", robustness),
                          "0.02 takes the worst limit of ΔP and ΔP ± 2 % (a speed ± 2 %)");
  if (!std::isfinite(max_depth_m) || max_depth_m < 0.0)
    throw InvalidArgument(fmt::format("PitchChoiceOptions::max_depth_m {} m must be ≥ 0 (0: automatic)", max_depth_m));
  if (depth_steps < 4 || depth_steps > 10000)
    throw InvalidArgument(fmt::format("PitchChoiceOptions::depth_steps {} must lie in 4…10000", depth_steps));
  parallel.check();
}

namespace {

// The chosen pattern's extrapolated limit, its gain over the even tool, and a warning where the
// limit collapses next to the chosen variation: a pitch ground a little off, or a speed a little
// off (ΔP scales with Ω), loses the gain. `res.samples` sorted by variation.
void judge_choice(PitchChoice& res, const PitchSample& best, const ModalModel& model, const CuttingConditions& cutting,
                  const PitchChoiceOptions& o) {
  CuttingConditions chosen = cutting;
  chosen.pitch_rad = res.pitch_rad;
  res.chosen = extrapolated_limit(model, chosen, o, res.steps, res.max_depth_m);
  res.evaluations += 2;
  res.gain = res.chosen.depth_m / res.uniform.depth_m;
  const auto at = std::find_if(res.samples.begin(), res.samples.end(),
                               [&](const PitchSample& s) { return s.variation_rad == best.variation_rad; });
  for (const auto side : {at - (at != res.samples.begin() ? 1 : 0), at + (at + 1 != res.samples.end() ? 1 : 0)})
    if (side != at && side->depth_m < 0.7 * best.depth_m) {
      res.warnings.push_back(fmt::format(
          "the limit falls steeply beside the chosen variation: {:.4g} mm at {:.4g}° against {:.4g} mm at {:.4g}° (a pitch or "
          "speed off by {:.2g} % loses it; Budak's closed form {:.4g}° gives {:.4g} mm)",
          side->depth_m * 1e3, degrees_of(side->variation_rad), best.depth_m * 1e3, degrees_of(best.variation_rad),
          100.0 * std::abs(side->variation_rad - best.variation_rad) / best.variation_rad,
          degrees_of(res.closed_form_variation_rad), res.closed_form_depth_m * 1e3));
      break;
    }
}

}  // namespace

PitchChoice choose_pitch(const ModalModel& model, const CuttingConditions& cutting, const PitchChoiceOptions& o) {
  o.check();
  model.check();
  cutting.check();
  if (!cutting.pitch_rad.empty())
    throw InvalidArgument("CuttingConditions::pitch_rad is given: the pitch is what choose_pitch chooses",
                          "leave the pitch angles empty (evenly spaced) and pick the pattern in PitchChoiceOptions::pattern");
  const int n = cutting.teeth;
  if (n < 2) throw InvalidArgument(fmt::format("CuttingConditions::teeth {}: a variable pitch needs at least 2 teeth", n));
  if (o.pattern == PitchPattern::Alternating && n % 2 != 0)
    throw InvalidArgument(fmt::format("PitchChoiceOptions::pattern alternating needs an even number of teeth, not {}", n),
                          "use the linear pattern for an odd number of teeth");
  const double even = 2.0 * kPi / n;
  const auto [lo, hi] = pitch_limits(o, n);
  if (!(lo < even) || !(hi > even))
    throw InvalidArgument(
        fmt::format("PitchChoiceOptions::min_pitch_rad {:.6g} rad ({:.4g}°) and PitchChoiceOptions::max_pitch_rad {:.6g} rad "
                    "({:.4g}°) leave no room around the even pitch 2π/N = {:.6g} rad ({:.4g}°): no variable pitch fits",
                    lo, degrees_of(lo), hi, degrees_of(hi), even, degrees_of(even)),
        "the limits must bracket 2π/N with room on both sides");

  PitchChoice res;
  res.pattern = o.pattern;
  res.teeth = n;
  res.speed_rpm = o.speed_rpm;
  // Angles must stay > 0 (pitch_pattern): keep a hair inside the limit.
  res.max_variation_rad = std::min(max_variation(o.pattern, n, lo, hi),
                                   (1.0 - 1e-9) * max_variation(o.pattern, n, 0.0, 2.0 * kPi));

  // The even tool: its zero-order floor (the default ceiling, and the chatter frequency that sets
  // the steps), then its limit at the target speed, whose chatter the pitch is to cancel.
  CuttingConditions plain = cutting;  // the zero-order floor refuses a helix, runout, process damping
  plain.helix_rad.clear();
  plain.runout_m.clear();
  plain.process_damping_n_per_m = 0.0;
  std::vector<Mode> all = model.x;
  all.insert(all.end(), model.y.begin(), model.y.end());
  double floor_hz = 0.0;
  const double floor = zero_order_floor(modal_milling_frfs(model.x, model.y, modal_frequency_grid(all)), plain, &floor_hz);
  res.max_depth_m = o.max_depth_m > 0.0 ? o.max_depth_m : 20.0 * floor;
  const double tooth_tau = 60.0 / (n * o.speed_rpm);
  const double wave_hz = o.chatter_hz > 0.0 ? o.chatter_hz : floor_hz;
  res.steps = o.steps > 0 ? o.steps : std::clamp(static_cast<int>(std::ceil(12.0 * wave_hz * tooth_tau)), 16, 1000);
  res.uniform = extrapolated_limit(model, cutting, o, res.steps, res.max_depth_m);
  res.evaluations += 2;
  if (o.chatter_hz > 0.0) res.chatter_hz = o.chatter_hz;
  else if (res.uniform.kind != BoundaryKind::None) res.chatter_hz = res.uniform.chatter_hz;
  else {
    res.chatter_hz = floor_hz;
    res.warnings.push_back(fmt::format(
        "the evenly spaced tool is stable up to the ceiling {:.4g} mm at {:.0f} rpm: Budak's rule aims at the zero-order "
        "floor's chatter frequency {:.1f} Hz instead",
        res.max_depth_m * 1e3, o.speed_rpm, floor_hz));
  }

  // The closed form: the smallest ΔP_k within the limits.
  const std::vector<double> budak = budak_variations(o.pattern, n, o.speed_rpm, res.chatter_hz, 1);
  res.closed_form_variation_rad = budak.front();
  double centre = res.closed_form_variation_rad, half = o.window * centre;
  if (res.closed_form_variation_rad > res.max_variation_rad) {
    res.warnings.push_back(fmt::format(
        "Budak's closed-form pitch variation {:.4g}° (chatter at {:.1f} Hz, {:.0f} rpm) exceeds the largest the limits allow, "
        "{:.4g}° (PitchChoiceOptions::min_pitch_rad, max_pitch_rad): the search spans the limits instead",
        degrees_of(res.closed_form_variation_rad), res.chatter_hz, o.speed_rpm, degrees_of(res.max_variation_rad)));
    res.closed_form_variation_rad = res.max_variation_rad;
    centre = 0.5 * res.max_variation_rad;
    half = centre;
  }
  res.closed_form_pitch_rad = pitch_pattern(o.pattern, n, res.closed_form_variation_rad);

  // The limits of a batch of variations, each also at ΔP(1 ± robustness), on the threads (each
  // independent: any count gives the same result).
  const std::vector<double> spread = o.robustness > 0.0 ? std::vector<double>{1.0, 1.0 - o.robustness, 1.0 + o.robustness}
                                                        : std::vector<double>{1.0};
  auto evaluate = [&](const std::vector<double>& variations) {
    std::vector<BoundaryPoint> limits(variations.size() * spread.size());
    parallel_for(limits.size(), o.parallel, [&](std::size_t i) {
      const double v = std::min(variations[i / spread.size()] * spread[i % spread.size()], res.max_variation_rad);
      CuttingConditions c = cutting;
      c.pitch_rad = pitch_pattern(o.pattern, n, v);
      limits[i] = limit_at(model, c, o, res.steps, res.max_depth_m);
    });
    for (std::size_t k = 0; k < variations.size(); ++k) {
      const BoundaryPoint& b = limits[k * spread.size()];
      PitchSample s{variations[k], b.depth_m, b.depth_m, b.chatter_hz, b.kind};
      for (std::size_t q = 1; q < spread.size(); ++q)
        s.robust_depth_m = std::min(s.robust_depth_m, limits[k * spread.size() + q].depth_m);
      res.samples.push_back(s);
    }
    res.evaluations += static_cast<long>(limits.size());
  };
  double v0 = std::max(0.0, centre - half), v1 = std::min(res.max_variation_rad, centre + half);
  std::vector<double> grid;
  for (int i = 0; i < o.search_points; ++i) grid.push_back(v0 + (v1 - v0) * i / (o.search_points - 1));
  grid.push_back(res.closed_form_variation_rad);
  evaluate(grid);
  const auto deepest = [&] {
    return *std::max_element(res.samples.begin(), res.samples.end(), [](const PitchSample& a, const PitchSample& b) {
      return a.robust_depth_m < b.robust_depth_m || (a.robust_depth_m == b.robust_depth_m && a.variation_rad > b.variation_rad);
    });
  };
  res.closed_form_depth_m = res.samples.back().depth_m;
  res.closed_form_robust_depth_m = res.samples.back().robust_depth_m;
  double step = (v1 - v0) / (o.search_points - 1);
  // The best at an edge of the window: extend it there by half as many points, up to 3 times (within the limits).
  for (int extension = 0; extension < 3; ++extension) {
    const double best = deepest().variation_rad;
    const int sign = best >= v1 - 1e-12 && v1 < res.max_variation_rad ? 1 : best <= v0 + 1e-12 && v0 > 0.0 ? -1 : 0;
    if (sign == 0) break;
    std::vector<double> more;
    for (int i = 1; i <= std::max(1, o.search_points / 2); ++i)
      if (const double v = best + sign * i * step; v >= 0.0 && v <= res.max_variation_rad) more.push_back(v);
    if (more.empty()) break;
    evaluate(more);
    (sign > 0 ? v1 : v0) = more.back();
  }
  for (int round = 0; round < 2; ++round) {  // ±1 step around the best in quarter steps (its ends already known)
    const double best = deepest().variation_rad;
    std::vector<double> finer;
    for (int i = -3; i <= 3; ++i)
      if (const double v = best + i * step / 4.0; i != 0 && v >= v0 && v <= v1) finer.push_back(v);
    evaluate(finer);
    step /= 4.0;
  }
  std::sort(res.samples.begin(), res.samples.end(),
            [](const PitchSample& a, const PitchSample& b) { return a.variation_rad < b.variation_rad; });
  const PitchSample best = deepest();
  res.variation_rad = best.variation_rad;
  res.pitch_rad = pitch_pattern(o.pattern, n, res.variation_rad);
  if (best.kind == BoundaryKind::None)
    res.warnings.push_back(
        fmt::format("the chosen pitch is stable up to the ceiling {:.4g} mm (PitchChoiceOptions::max_depth_m): "
                    "its limit is higher, and other variations as deep may be as good",
                    res.max_depth_m * 1e3));
  else if ((res.variation_rad <= v0 + 1e-12 && v0 > 0.0) || (res.variation_rad >= v1 - 1e-12 && v1 < res.max_variation_rad))
    res.warnings.push_back(
        fmt::format("the deepest variation {:.4g}° lies at the edge of the search ({:.4g}…{:.4g}°): widen "
                    "PitchChoiceOptions::window",
                    degrees_of(res.variation_rad), degrees_of(v0), degrees_of(v1)));

  judge_choice(res, best, model, cutting, o);
  return res;
}

}  // namespace toolpoint
