// toolpoint: the choice of a variable pitch — the tooth spacing that maximises the stable axial depth
// of a cut at one spindle speed.
//
// Start: Budak's closed-form rule (E. Budak, "An analytical design method for milling cutters with
// nonconstant pitch to increase stability", J. Manuf. Sci. Eng. 125 (2003) 29–38, parts I and II; as
// derived in docs/reference.md §12): with one chatter frequency ω_c in view, the teeth's regenerative
// waves cancel when Σ_j e^{−iω_c τ_j} = 0, τ_j = p_{j−1}/Ω the delays of the pitch angles p_j, Ω the
// spindle speed [rad/s]. Then: confirmed and refined by the multi-delay full-discretization
// stability (stability.hpp's FullDiscretization) in a bounded search around that start, against the
// evenly spaced tool's limit at the same speed.
//
// Units: SI and radians (angles), speeds in rpm, frequencies in Hz (stability.hpp). Pitch angles
// as CuttingConditions::pitch_rad: p_j is the angle from tooth j to tooth j + 1.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "toolpoint/option_fields.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/stability/stability.hpp"

namespace toolpoint {

// Which family of pitch patterns is searched: Alternating and Linear have one parameter, the
// variation ΔP [rad] ≥ 0; ThreeAngle two, the variations u and v [rad] (either sign).
enum class PitchPattern {
  // N even: p = P₁, P₂, P₁, P₂, …, P₁ = 2π/N − ΔP/2, P₂ = 2π/N + ΔP/2 (two angles).
  Alternating,
  // p_j = 2π/N + (j − (N−1)/2) ΔP, j = 0…N−1 (N angles in arithmetic progression; three angles for
  // N = 3). For N = 2 the same as Alternating.
  Linear,
  // N a multiple of 3: p = P₀, P₁, P₂, P₀, P₁, P₂, … with P₀ = 2π/N − u, P₁ = 2π/N + u − v,
  // P₂ = 2π/N + v (three angles adding up to 3 × 2π/N, any three such). u = v = ΔP is Linear's
  // pattern for N = 3 (docs/reference.md §12).
  ThreeAngle,
};
const char* to_string(PitchPattern p);  // "alternating", "linear", "three-angle" (the CLI's --pattern)

// The pitch angles [rad] of `pattern` with variation ΔP = u = `variation_rad` (and, ThreeAngle only,
// v = `second_variation_rad`; the one-parameter patterns take 0) for `teeth` teeth (they sum to 2π).
// Throws InvalidArgument naming the parameter (Alternating with an odd tooth count, ThreeAngle with
// one not a multiple of 3, teeth < 2, ΔP < 0 (one-parameter patterns), a second variation other than 0
// for a one-parameter pattern, variations so large that an angle is ≤ 0).
std::vector<double> pitch_pattern(PitchPattern pattern, int teeth, double variation_rad, double second_variation_rad = 0.0);

// Budak's closed-form variations [rad] for chatter at `chatter_hz` [Hz] and spindle speed
// `speed_rpm` [rpm], Ω = 2πn/60 [rad/s], ω_c = 2πf_c (docs/reference.md §12):
//   Alternating: ω_c ΔP/Ω = (2k + 1)π            →  ΔP_k = (2k + 1)πΩ/ω_c,   k = 0, 1, …
//   Linear:      N ω_c ΔP/Ω = 2πk, k ≢ 0 (mod N)  →  ΔP_k = 2πkΩ/(Nω_c)
//   ThreeAngle:  along its diagonal u = v = ΔP (Linear's N = 3 rule): ΔP_k = 2πkΩ/(3ω_c), k ≢ 0 (mod 3)
// The first `count` of them, smallest first. Throws InvalidArgument (speed or frequency ≤ 0).
std::vector<double> budak_variations(PitchPattern pattern, int teeth, double speed_rpm, double chatter_hz, int count);

// Budak's closed form for the three-angle pattern in both parameters (docs/reference.md §12): the
// three phasors e^{−iω_c P_k/Ω} cancel when they are 120° apart, at
//   (u, v) = (m, n) q,   q = 2πΩ/(3ω_c),   m, n integers with m + n ≢ 0 (mod 3).
// One (u, v) per distinct tool — P₀ the smallest angle (u > 0, −u < v < 2u: the pattern's other
// rotations are the same tool) — ordered by the spread of the angles (largest − smallest, 2q first:
// (q, q) the ascending 2π/N − q, 2π/N, 2π/N + q, and (q, 0) its mirror image), then by v, largest
// first. The first `count` [rad]. Throws InvalidArgument (speed or frequency ≤ 0).
std::vector<std::pair<double, double>> budak_three_angle_variations(double speed_rpm, double chatter_hz, int count);

struct PitchChoiceOptions {
  double speed_rpm = 0.0;  // the target spindle speed [rpm] > 0
  PitchPattern pattern = PitchPattern::Alternating;
  // The limits on every pitch angle [rad]: min_pitch_rad ≤ p_j ≤ max_pitch_rad (chip space, balance,
  // strength). 0: half and 1.5 × the even pitch 2π/N. They must admit the even pitch and some variation.
  double min_pitch_rad = 0.0;
  double max_pitch_rad = 0.0;
  // The chatter frequency Budak's rule aims at [Hz]; 0: the evenly spaced tool's at the target speed
  // (its full-discretization limit's; the zero-order floor's when it is stable to the ceiling).
  double chatter_hz = 0.0;
  // The search: ΔP over (1 ± window) × the closed-form ΔP (within the limits) at `search_points`
  // evenly spaced values (extended by half as many steps beyond an edge where the best lies, up to 3
  // times, within the limits), then twice refined around the best (±1 step in quarter steps). 0 < window ≤ 1.
  // ThreeAngle: a search_points × search_points grid of (u, v) within ± window × q of the better of
  // the two closed forms of spread 2q (budak_three_angle_variations), points outside the limits left
  // out (extended by a block of ±search_points/4 steps around the best while it lies at the edge of
  // what was evaluated, up to 3 times), then a pattern search: the 8 neighbours at half the step,
  // moving to the best while it improves, the step halved when it does not, down to an eighth.
  double window = 0.5;
  int search_points = 11;  // 3…201 (ThreeAngle: per parameter)
  // What is maximised: the lowest of the limits at ΔP and ΔP(1 ± robustness) (ThreeAngle: at (u, v)
  // and (u, v)(1 ± robustness), each scaled back to the limits if it leaves them) (0…0.2). The limit can
  // collapse just past its highest point (where the chatter moves to a frequency the pitch does not
  // cancel), and ΔP scales with the speed: 0.02 keeps the gain for a speed or a pitch 2 % off. 0:
  // the limit at ΔP alone.
  double robustness = 0.02;
  // Full-discretization: steps per tooth period (0: 12 per chatter wave (chatter_hz, or the zero-order
  // floor's), at least 16;
  // 4…2000) and degree (1…3). The final two limits (even and chosen pitch) are also taken at twice the
  // steps, Richardson-extrapolated with their error estimate (stability.hpp, BoundaryPoint).
  int steps = 0;
  int degree = 2;
  // The depth search: up to max_depth_m [m] (0: 20 × the even tool's zero-order floor) in
  // `depth_steps` equal steps (FullDiscretization::boundary: an unstable band narrower than a step
  // can be missed), 4…10000.
  double max_depth_m = 0.0;
  int depth_steps = 60;
  ParallelOptions parallel;  // the search's depths on this many threads (identical for any count)
  // Throws InvalidArgument naming the field: pitch_choice_fields' ranges, then the pitch limits'
  // order (min_pitch_rad < max_pitch_rad where both are given) and parallel.
  void check() const;
};

/// \brief PitchChoiceOptions' numeric fields, defined once (option_fields.hpp): check(), the
/// `toolpoint pitch` flags (the angles in degrees) and `toolpoint._option_fields` derive from it
/// (the pattern and parallel have their own definitions).
/// \return the table, in the order of the fields
const std::vector<OptionField<PitchChoiceOptions>>& pitch_choice_fields();

// One evaluated pattern: its variation and the lowest unstable depth at the target speed.
struct PitchSample {
  double variation_rad = 0.0;         // ΔP, or u (ThreeAngle) [rad]
  double second_variation_rad = 0.0;  // v (ThreeAngle), 0 for the one-parameter patterns [rad]
  double depth_m = 0.0;               // the search ceiling when kind is None
  double robust_depth_m = 0.0;        // the lowest of the limits at ΔP and ΔP(1 ± robustness): what is maximised
  double chatter_hz = 0.0;
  BoundaryKind kind = BoundaryKind::None;
};

struct PitchChoice {
  PitchPattern pattern = PitchPattern::Alternating;
  int teeth = 0;
  double speed_rpm = 0.0;
  double chatter_hz = 0.0;  // the frequency Budak's rule aimed at [Hz]
  // The largest ΔP the limits allow; ThreeAngle: the largest step q of the closed forms (q, q) and
  // (q, 0), min(2π/N − min_pitch, max_pitch − 2π/N) [rad].
  double max_variation_rad = 0.0;
  // Budak's ΔP_0 (alternating) or ΔP_1 (linear) [rad]; the largest allowed when it is over the limits (a warning says so).
  // ThreeAngle: u of the better of (q, q) and (q, 0) (by the robust limit), v its second variation.
  double closed_form_variation_rad = 0.0;
  double closed_form_second_variation_rad = 0.0;
  std::vector<double> closed_form_pitch_rad;
  double closed_form_depth_m = 0.0;         // its limit at the search's discretization [m]
  double closed_form_robust_depth_m = 0.0;  // … and the lowest at ΔP(1 ± robustness) [m]
  double variation_rad = 0.0;               // the chosen ΔP or u (the highest robust_depth_m evaluated)
  double second_variation_rad = 0.0;        // the chosen v (ThreeAngle; else 0)
  std::vector<double> pitch_rad;            // its pitch angles [rad]
  // The chosen pattern's and the even tool's limits at the target speed [m], Richardson-extrapolated
  // from steps and 2 × steps, with their error estimate [m] (NaN where stable to the ceiling).
  BoundaryPoint chosen, uniform;
  double gain = 0.0;                 // chosen.depth_m / uniform.depth_m
  double max_depth_m = 0.0;          // the ceiling searched [m]
  int steps = 0;                     // steps per tooth period of the search
  std::vector<PitchSample> samples;  // every pattern evaluated in the search, by ΔP (or u, then v)
  long evaluations = 0;              // stability limits computed
  std::vector<std::string> warnings;
};

// Chooses the pitch of `pattern` for `model` cutting `cutting` (whose pitch_rad must be empty: that
// is what is chosen; helix, runout and process damping are kept) at options.speed_rpm. Budak's
// closed form gives the start, the full-discretization limit at every ΔP of the bounded search
// decides (ThreeAngle: in (u, v), PitchChoiceOptions::window). Warnings: the closed form outside the limits (the search then
// spans the limits), the chosen pattern stable up to the ceiling, a chosen ΔP at the edge of the search. Throws InvalidArgument
// (bad model, conditions or options, limits that admit no pattern), NumericalError.
PitchChoice choose_pitch(const ModalModel& model, const CuttingConditions& cutting, const PitchChoiceOptions& options);

}  // namespace toolpoint
