// The choice of a variable pitch (pitch.hpp): Budak's closed form, then the full-discretization
// limit over a bounded search around it.
#include "toolpoint/stability/pitch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

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

// ThreeAngle: the offsets of P₀, P₁, P₂ from the even pitch 2π/N (pitch.hpp).
std::array<double, 3> three_angle_offsets(double u, double v) { return {-u, u - v, v}; }

// Ω/ω_c of Budak's rule, checked.
double speed_over_chatter(double speed_rpm, double chatter_hz) {
  if (!(speed_rpm > 0.0) || !std::isfinite(speed_rpm) || !(chatter_hz > 0.0) || !std::isfinite(chatter_hz))
    throw InvalidArgument(
        fmt::format("Budak's rule needs a speed and a chatter frequency > 0 (got {} rpm, {} Hz)", speed_rpm, chatter_hz));
  return rad_s_of_rpm(speed_rpm) / omega_of(chatter_hz);
}

}  // namespace

const char* to_string(PitchPattern p) {
  return p == PitchPattern::Alternating ? "alternating" : p == PitchPattern::Linear ? "linear" : "three-angle";
}

std::vector<double> pitch_pattern(PitchPattern pattern, int teeth, double variation_rad, double second_variation_rad) {
  if (teeth < 2) throw InvalidArgument(fmt::format("a variable pitch needs at least 2 teeth, not {}", teeth));
  if (pattern == PitchPattern::Alternating && teeth % 2 != 0)
    throw InvalidArgument(fmt::format("an alternating pitch needs an even number of teeth, not {}", teeth),
                          "use the linear pattern for an odd number of teeth");
  const double even = 2.0 * kPi / teeth;
  if (pattern == PitchPattern::ThreeAngle) {
    if (teeth % 3 != 0)
      throw InvalidArgument(fmt::format("a three-angle pitch needs a multiple of 3 teeth, not {}", teeth),
                            "use the alternating (even N) or linear pattern");
    if (!std::isfinite(variation_rad) || !std::isfinite(second_variation_rad))
      throw InvalidArgument(fmt::format("three-angle pitch: variation_rad {} and second_variation_rad {} must be finite",
                                        variation_rad, second_variation_rad));
    const std::array<double, 3> off = three_angle_offsets(variation_rad, second_variation_rad);
    for (int k = 0; k < 3; ++k)
      if (!(even + off[k] > 0.0))
        throw InvalidArgument(fmt::format("three-angle pitch: variation_rad {:.6g} and second_variation_rad {:.6g} rad leave "
                                          "P{} = 2π/N{:+.6g} = {:.6g} rad ≤ 0 with {} teeth",
                                          variation_rad, second_variation_rad, k, off[k], even + off[k], teeth),
                              "P₀ = 2π/N − u, P₁ = 2π/N + u − v, P₂ = 2π/N + v must all be > 0");
    std::vector<double> p(static_cast<std::size_t>(teeth));
    for (int j = 0; j < teeth; ++j) p[j] = even + off[j % 3];
    return p;
  }
  if (second_variation_rad != 0.0)
    throw InvalidArgument(fmt::format("second_variation_rad {} must be 0: the {} pattern has one parameter", second_variation_rad,
                                      to_string(pattern)));
  if (!std::isfinite(variation_rad) || variation_rad < 0.0)
    throw InvalidArgument(fmt::format("pitch variation {} rad must be ≥ 0", variation_rad));
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
  const double ratio = speed_over_chatter(speed_rpm, chatter_hz);  // Ω/ω_c
  // ThreeAngle's diagonal u = v is Linear's pattern for three teeth, repeated.
  const int period = pattern == PitchPattern::ThreeAngle ? 3 : teeth;
  std::vector<double> v;
  for (int k = 0; static_cast<int>(v.size()) < count; ++k) {
    if (pattern == PitchPattern::Alternating) v.push_back((2 * k + 1) * kPi * ratio);
    else if (k > 0 && k % period != 0) v.push_back(2.0 * kPi * k * ratio / period);
  }
  return v;
}

std::vector<std::pair<double, double>> budak_three_angle_variations(double speed_rpm, double chatter_hz, int count) {
  const double q = 2.0 * kPi * speed_over_chatter(speed_rpm, chatter_hz) / 3.0;
  // (m, n) with P₀ the smallest angle (−m < n < 2m; the equalities have m + n ≡ 0 (mod 3)). The
  // spread is m + max(m − n, n) ≥ 1.5 m, and the first `count` have spread ≤ 3 count: m ≤ 2 count + 1 is enough.
  struct Lattice {
    int m, n, spread;
  };
  std::vector<Lattice> all;
  for (int m = 1; m <= 2 * count + 1; ++m)
    for (int n = -m + 1; n < 2 * m; ++n)
      if (((m + n) % 3 + 3) % 3 != 0) all.push_back({m, n, m + std::max(m - n, n)});
  std::sort(all.begin(), all.end(),
            [](const Lattice& a, const Lattice& b) { return a.spread < b.spread || (a.spread == b.spread && a.n > b.n); });
  std::vector<std::pair<double, double>> out;
  for (int i = 0; i < count && i < static_cast<int>(all.size()); ++i) out.emplace_back(all[i].m * q, all[i].n * q);
  return out;
}

void PitchChoiceOptions::check() const {
  check_fields(pitch_choice_fields(), *this, "PitchChoiceOptions");
  if (min_pitch_rad > 0.0 && max_pitch_rad > 0.0 && !(min_pitch_rad < max_pitch_rad))
    throw InvalidArgument(
        fmt::format("PitchChoiceOptions::min_pitch_rad {} rad must be below PitchChoiceOptions::max_pitch_rad {} rad",
                    min_pitch_rad, max_pitch_rad));
  parallel.check();
}

const std::vector<OptionField<PitchChoiceOptions>>& pitch_choice_fields() {
  using O = PitchChoiceOptions;
  constexpr double kDegreesPerRadian = 180.0 / kPi;  // the CLI's pitch angles are in degrees
  // The boundary's own fields (boundary_fields()) in the pitch search's words: the steps capped as
  // the lobes study's (half the default max_steps), the ceiling's default the even tool's.
  static const FieldSpec steps = study_steps_field("full-discretization: steps per tooth period");
  static const FieldSpec max_depth = [] {
    FieldSpec s = option_field(boundary_fields(), "max_depth_m").spec;
    s.note = "0: 20 × the even tool's zero-order floor";
    return s;
  }();
  static const std::vector<OptionField<O>> fields = {
      {{.name = "speed_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .min_open = true,
        .help = "target spindle speed",
        .cli_name = "rpm",
        .plausible = &plausible::kSpindleSpeedRpm},
       [](O& o) -> double& { return o.speed_rpm; }},
      {{.name = "min_pitch_rad",
        .kind = FieldKind::Real,
        .unit = "rad",
        .min = 0.0,
        .max = 2.0 * kPi,
        .max_open = true,
        .note = "0: half the even pitch",
        .help = "smallest pitch angle allowed",
        .cli_name = "min-pitch",
        .cli_unit = "degrees",
        .cli_per_unit = kDegreesPerRadian},
       [](O& o) -> double& { return o.min_pitch_rad; }},
      {{.name = "max_pitch_rad",
        .kind = FieldKind::Real,
        .unit = "rad",
        .min = 0.0,
        .max = 2.0 * kPi,
        .max_open = true,
        .note = "0: 1.5 × the even pitch",
        .help = "largest pitch angle allowed",
        .cli_name = "max-pitch",
        .cli_unit = "degrees",
        .cli_per_unit = kDegreesPerRadian},
       [](O& o) -> double& { return o.max_pitch_rad; }},
      {{.name = "chatter_hz",
        .kind = FieldKind::Real,
        .unit = "Hz",
        .min = 0.0,
        .note = "0: the evenly spaced tool's at the target speed",
        .help = "chatter frequency Budak's rule aims at",
        .cli_name = "chatter"},
       [](O& o) -> double& { return o.chatter_hz; }},
      {{.name = "window",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .help = "search ΔP over (1 ± window) × the closed form's",
        .cli_name = "window"},
       [](O& o) -> double& { return o.window; }},
      {{.name = "search_points",
        .kind = FieldKind::Integer,
        .min = 3.0,
        .max = 201.0,
        .help = "points of the first search grid (three-angle: per parameter, a square grid)",
        .cli_name = "search-points"},
       nullptr,
       [](O& o) -> int& { return o.search_points; }},
      {{.name = "robustness",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 0.2,
        .help = "maximise the lowest limit of ΔP and ΔP(1 ± robustness), as a speed off by as much",
        .cli_name = "robustness",
        .cli_unit = "% of ΔP",
        .cli_per_unit = 100.0},
       [](O& o) -> double& { return o.robustness; }},
      {steps, nullptr, [](O& o) -> int& { return o.steps; }},
      {{.name = "degree",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 3.0,
        .help = "full-discretization: degree of the polynomial the delayed state is interpolated with"},
       nullptr,
       [](O& o) -> int& { return o.degree; }},
      {max_depth, [](O& o) -> double& { return o.max_depth_m; }},
      {{.name = "depth_steps",
        .kind = FieldKind::Integer,
        .min = 4.0,
        .max = 10000.0,
        .help = "equal depth steps of the search, up to the deepest depth searched",
        .cli_name = "depth-steps"},
       nullptr,
       [](O& o) -> int& { return o.depth_steps; }},
  };
  return fields;
}

namespace {

// A sample's parameters for messages: ΔP, or (u, v) for the three-angle pattern [degrees].
std::string parameters_text(PitchPattern pattern, double u, double v) {
  return pattern == PitchPattern::ThreeAngle ? fmt::format("(u, v) = ({:.4g}°, {:.4g}°)", degrees_of(u), degrees_of(v))
                                             : fmt::format("{:.4g}°", degrees_of(u));
}

// The chosen pattern's extrapolated limit, its gain over the even tool, and a warning where the
// limit collapses next to the chosen variation (`neighbours`: the samples beside it): a pitch ground a
// little off, or a speed a little off (the variations scale with Ω), loses the gain.
void judge_choice(PitchChoice& res, const PitchSample& best, const std::vector<PitchSample>& neighbours, const ModalModel& model,
                  const CuttingConditions& cutting, const PitchChoiceOptions& o) {
  CuttingConditions chosen = cutting;
  chosen.pitch_rad = res.pitch_rad;
  res.chosen = extrapolated_limit(model, chosen, o, res.steps, res.max_depth_m);
  res.evaluations += 2;
  res.gain = res.chosen.depth_m / res.uniform.depth_m;
  for (const PitchSample& side : neighbours)
    if (side.depth_m < 0.7 * best.depth_m) {
      const double off = std::hypot(side.variation_rad - best.variation_rad,
                                    side.second_variation_rad - best.second_variation_rad) /
                         std::hypot(best.variation_rad, best.second_variation_rad);
      res.warnings.push_back(
          fmt::format("the limit falls steeply beside the chosen variation: {:.4g} mm at {} against {:.4g} mm at {} (a pitch or "
                      "speed off by {:.2g} % loses it; Budak's closed form {} gives {:.4g} mm)",
                      side.depth_m * 1e3, parameters_text(res.pattern, side.variation_rad, side.second_variation_rad),
                      best.depth_m * 1e3, parameters_text(res.pattern, best.variation_rad, best.second_variation_rad),
                      100.0 * off,
                      parameters_text(res.pattern, res.closed_form_variation_rad, res.closed_form_second_variation_rad),
                      res.closed_form_depth_m * 1e3));
      break;
    }
}

// The even tool: its zero-order floor (the default ceiling, and the chatter frequency that sets
// the steps), then its limit at the target speed, whose chatter the pitch is to cancel.
void judge_even_tool(PitchChoice& res, const ModalModel& model, const CuttingConditions& cutting, const PitchChoiceOptions& o) {
  const int n = cutting.teeth;
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
}

// The limits of a batch of patterns (`params`: (ΔP or u, v)), each also at its parameters scaled by
// 1 ± robustness (`angles(u, v, factor)`: the pitch there, kept within the limits), on the threads
// (each independent: any count gives the same result); appended to res.samples.
void evaluate_patterns(PitchChoice& res, const std::vector<std::pair<double, double>>& params,
                       const std::function<std::vector<double>(double, double, double)>& angles, const ModalModel& model,
                       const CuttingConditions& cutting, const PitchChoiceOptions& o) {
  const std::vector<double> spread = o.robustness > 0.0 ? std::vector<double>{1.0, 1.0 - o.robustness, 1.0 + o.robustness}
                                                        : std::vector<double>{1.0};
  std::vector<BoundaryPoint> limits(params.size() * spread.size());
  parallel_for(limits.size(), o.parallel, [&](std::size_t i) {
    CuttingConditions c = cutting;
    const auto& [u, v] = params[i / spread.size()];
    c.pitch_rad = angles(u, v, spread[i % spread.size()]);
    limits[i] = limit_at(model, c, o, res.steps, res.max_depth_m);
  });
  for (std::size_t k = 0; k < params.size(); ++k) {
    const BoundaryPoint& b = limits[k * spread.size()];
    PitchSample s{params[k].first, params[k].second, b.depth_m, b.depth_m, b.chatter_hz, b.kind};
    for (std::size_t q = 1; q < spread.size(); ++q)
      s.robust_depth_m = std::min(s.robust_depth_m, limits[k * spread.size() + q].depth_m);
    res.samples.push_back(s);
  }
  res.evaluations += static_cast<long>(limits.size());
}

// The one-parameter search (Alternating, Linear): ΔP on a grid around the closed form, extended
// past an edge where the best lies, refined twice (PitchChoiceOptions::window).
void search_one_parameter(PitchChoice& res, const ModalModel& model, const CuttingConditions& cutting,
                          const PitchChoiceOptions& o, double lo, double hi) {
  const int n = cutting.teeth;
  // Angles must stay > 0 (pitch_pattern): keep a hair inside the limit.
  res.max_variation_rad = std::min(max_variation(o.pattern, n, lo, hi),
                                   (1.0 - 1e-9) * max_variation(o.pattern, n, 0.0, 2.0 * kPi));
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

  const auto angles = [&](double v, double, double factor) {
    return pitch_pattern(o.pattern, n, std::min(v * factor, res.max_variation_rad));
  };
  auto evaluate = [&](const std::vector<double>& variations) {
    std::vector<std::pair<double, double>> params;
    for (double v : variations) params.emplace_back(v, 0.0);
    evaluate_patterns(res, params, angles, model, cutting, o);
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

  const auto at = std::find_if(res.samples.begin(), res.samples.end(),
                               [&](const PitchSample& s) { return s.variation_rad == best.variation_rad; });
  std::vector<PitchSample> neighbours;
  for (const auto side : {at - (at != res.samples.begin() ? 1 : 0), at + (at + 1 != res.samples.end() ? 1 : 0)})
    if (side != at) neighbours.push_back(*side);
  judge_choice(res, best, neighbours, model, cutting, o);
}

// The three-angle search in (u, v) (pitch.hpp, PitchChoiceOptions::window): the better of the two
// closed forms of spread 2q as the start, a grid around it within the limits, extended while the
// best lies at its edge, then a pattern search down to an eighth of the grid step.
void search_three_angle(PitchChoice& res, const ModalModel& model, const CuttingConditions& cutting, const PitchChoiceOptions& o,
                        double lo, double hi) {
  const int n = cutting.teeth;
  const double even = 2.0 * kPi / n;
  res.max_variation_rad = std::min(even - lo, hi - even);
  // Within the limits (to rounding: grid points are sums of steps).
  const double slack = 1e-12 * even;
  const auto within = [&](double u, double v) {
    for (double off : three_angle_offsets(u, v))
      if (even + off < lo - slack || even + off > hi + slack) return false;
    return true;
  };
  // (u, v) scaled by `factor`, or as far as the limits allow (the region is convex and holds the even pitch).
  const auto angles = [&](double u, double v, double factor) {
    double t = factor;
    for (double off : three_angle_offsets(u, v))
      if (off > 0.0) t = std::min(t, (hi - even) / off);
      else if (off < 0.0) t = std::min(t, (lo - even) / off);
    return pitch_pattern(PitchPattern::ThreeAngle, n, u * t, v * t);
  };
  std::vector<std::pair<double, double>> start = budak_three_angle_variations(o.speed_rpm, res.chatter_hz, 2);
  const double q = start.front().first;  // (q, q), then (q, 0)
  std::pair<double, double> centre;
  double half = o.window * q;
  if (q > res.max_variation_rad) {
    res.warnings.push_back(fmt::format(
        "Budak's closed-form pitch step {:.4g}° (chatter at {:.1f} Hz, {:.0f} rpm) exceeds the largest the limits allow, "
        "{:.4g}° (PitchChoiceOptions::min_pitch_rad, max_pitch_rad): the search spans the limits instead",
        degrees_of(q), res.chatter_hz, o.speed_rpm, degrees_of(res.max_variation_rad)));
    for (auto& [u, v] : start) u *= res.max_variation_rad / q, v *= res.max_variation_rad / q;
    half = 0.5 * res.max_variation_rad;
  }
  evaluate_patterns(res, start, angles, model, cutting, o);
  const PitchSample& cf = res.samples[1].robust_depth_m > res.samples[0].robust_depth_m ? res.samples[1] : res.samples[0];
  res.closed_form_variation_rad = cf.variation_rad;
  res.closed_form_second_variation_rad = cf.second_variation_rad;
  res.closed_form_depth_m = cf.depth_m;
  res.closed_form_robust_depth_m = cf.robust_depth_m;
  res.closed_form_pitch_rad = pitch_pattern(PitchPattern::ThreeAngle, n, cf.variation_rad, cf.second_variation_rad);
  centre = {cf.variation_rad, cf.second_variation_rad};
  if (q > res.max_variation_rad) centre = {0.5 * centre.first, 0.5 * centre.second};

  // The best: the highest robust limit; on a tie the smaller spread of the angles, then the smaller (u, v).
  const auto spread = [](const PitchSample& s) {
    const std::array<double, 3> off = three_angle_offsets(s.variation_rad, s.second_variation_rad);
    return *std::max_element(off.begin(), off.end()) - *std::min_element(off.begin(), off.end());
  };
  const auto deepest = [&] {
    return *std::max_element(res.samples.begin(), res.samples.end(), [&](const PitchSample& a, const PitchSample& b) {
      if (a.robust_depth_m != b.robust_depth_m) return a.robust_depth_m < b.robust_depth_m;
      if (spread(a) != spread(b)) return spread(a) > spread(b);
      return std::pair{a.variation_rad, a.second_variation_rad} > std::pair{b.variation_rad, b.second_variation_rad};
    });
  };
  // New points within the limits, not evaluated yet (to rounding), then evaluated.
  const auto same = [&](double u, double v, double a, double b) {
    return std::abs(a - u) < 1e-9 * q && std::abs(b - v) < 1e-9 * q;
  };
  const auto evaluated = [&](double u, double v) {
    return std::any_of(res.samples.begin(), res.samples.end(),
                       [&](const PitchSample& s) { return same(u, v, s.variation_rad, s.second_variation_rad); });
  };
  const auto evaluate_new = [&](const std::vector<std::pair<double, double>>& points) {
    std::vector<std::pair<double, double>> fresh;
    for (const auto& [u, v] : points)
      if (within(u, v) && !evaluated(u, v) &&
          std::none_of(fresh.begin(), fresh.end(), [&, u = u, v = v](const auto& p) { return same(u, v, p.first, p.second); }))
        fresh.emplace_back(u, v);
    if (!fresh.empty()) evaluate_patterns(res, fresh, angles, model, cutting, o);
    return fresh.size();
  };
  // The (2k + 1)² points at spacing h around (u, v), the centre left out.
  const auto block = [](double u, double v, double h, int k) {
    std::vector<std::pair<double, double>> b;
    for (int i = -k; i <= k; ++i)
      for (int j = -k; j <= k; ++j)
        if (i != 0 || j != 0) b.emplace_back(u + i * h, v + j * h);
    return b;
  };
  const double step = 2.0 * half / (o.search_points - 1);
  std::vector<std::pair<double, double>> grid;
  for (int i = 0; i < o.search_points; ++i)
    for (int j = 0; j < o.search_points; ++j) grid.emplace_back(centre.first - half + i * step, centre.second - half + j * step);
  evaluate_new(grid);
  // The best at the edge of what was evaluated (a neighbour at the grid step within the limits not
  // evaluated): a block around it, up to 3 times.
  bool at_edge = false;
  for (int extension = 0; extension <= 3; ++extension) {
    const PitchSample best = deepest();
    const std::size_t before = res.samples.size();
    at_edge = false;
    for (const auto& [u, v] : block(best.variation_rad, best.second_variation_rad, step, 1))
      if (within(u, v) && !evaluated(u, v)) at_edge = true;
    if (!at_edge || extension == 3) break;
    evaluate_new(block(best.variation_rad, best.second_variation_rad, step, std::max(1, o.search_points / 4)));
    if (res.samples.size() == before) break;
  }
  // The pattern search: the 8 neighbours at h, moving to the best while it improves, h halved when
  // it does not, down to step/8 (at most 12 rounds).
  double h = 0.5 * step;
  for (int round = 0; round < 12 && h > step / 8.0 * (1.0 - 1e-9); ++round) {
    const PitchSample best = deepest();
    evaluate_new(block(best.variation_rad, best.second_variation_rad, h, 1));
    const PitchSample now = deepest();
    if (now.variation_rad == best.variation_rad && now.second_variation_rad == best.second_variation_rad) h *= 0.5;
  }
  std::sort(res.samples.begin(), res.samples.end(), [](const PitchSample& a, const PitchSample& b) {
    return std::pair{a.variation_rad, a.second_variation_rad} < std::pair{b.variation_rad, b.second_variation_rad};
  });
  const PitchSample best = deepest();
  res.variation_rad = best.variation_rad;
  res.second_variation_rad = best.second_variation_rad;
  res.pitch_rad = pitch_pattern(PitchPattern::ThreeAngle, n, res.variation_rad, res.second_variation_rad);
  if (best.kind == BoundaryKind::None)
    res.warnings.push_back(
        fmt::format("the chosen pitch is stable up to the ceiling {:.4g} mm (PitchChoiceOptions::max_depth_m): "
                    "its limit is higher, and other variations as deep may be as good",
                    res.max_depth_m * 1e3));
  else if (at_edge)
    res.warnings.push_back(fmt::format(
        "the deepest variations {} lie at the edge of the search after 3 extensions: widen PitchChoiceOptions::window",
        parameters_text(PitchPattern::ThreeAngle, res.variation_rad, res.second_variation_rad)));
  // The finest ring around the best: what a pitch ground a little off gets.
  std::vector<PitchSample> neighbours;
  const double ring = 2.0 * h * (1.0 + 1e-6);
  for (const PitchSample& s : res.samples)
    if ((s.variation_rad != best.variation_rad || s.second_variation_rad != best.second_variation_rad) &&
        std::abs(s.variation_rad - best.variation_rad) <= ring &&
        std::abs(s.second_variation_rad - best.second_variation_rad) <= ring)
      neighbours.push_back(s);
  judge_choice(res, best, neighbours, model, cutting, o);
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
  if (o.pattern == PitchPattern::ThreeAngle && n % 3 != 0)
    throw InvalidArgument(fmt::format("PitchChoiceOptions::pattern three-angle needs a multiple of 3 teeth, not {}", n),
                          "use the alternating (even N) or linear pattern");
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
  judge_even_tool(res, model, cutting, o);
  if (o.pattern == PitchPattern::ThreeAngle) search_three_angle(res, model, cutting, o, lo, hi);
  else search_one_parameter(res, model, cutting, o, lo, hi);
  return res;
}

}  // namespace toolpoint
