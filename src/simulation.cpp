// toolpoint: the time-domain milling simulation (simulation.hpp). Units: SI, rpm, Hz.
#include "toolpoint/stability/simulation.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <unsupported/Eigen/FFT>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

using Complex = std::complex<double>;
constexpr double kTwoPi = 2.0 * kPi;

bool finite(double x) { return std::isfinite(x); }

// One mode over one step h: the exact propagator e^{A h} of (q, q̇) and the response to a force
// linear in time over [α, β] ⊂ [0, h]. With λ = −ζω + iω_d, e^{At}(0, 1)ᵀ = (Im e^{λt}, Im λe^{λt})/ω_d,
// so the response to p(s) = p_a + (p_b − p_a)(s − α)/(β − α) is J0 p_a + J1 (p_b − p_a) with
//   K0 = ∫_α^β e^{λ(h−s)} ds = (e^{λU₁} − e^{λU₀})/λ,
//   K1 = ∫_α^β e^{λ(h−s)} (s − α)/L ds = (e^{λU₁} − e^{λU₀})/(λ²L) − e^{λU₀}/λ,
// U₁ = h − α, U₀ = h − β, L = β − α, and J = (Im K, Im λK)/ω_d.
struct ModeStep {
  double sx = 0.0, sy = 0.0, omega = 0.0;  // ψ, ω
  Complex lambda;
  double wd = 0.0;
  double p00 = 0.0, p01 = 0.0, p10 = 0.0, p11 = 0.0;  // e^{Ah}
  double j0q = 0.0, j0v = 0.0, j1q = 0.0, j1v = 0.0;  // the whole step's J0, J1

  void integrals(double h, double alpha, double beta, double& a0q, double& a0v, double& a1q, double& a1v) const {
    const double len = beta - alpha;
    const Complex e1 = std::exp(lambda * (h - alpha)), e0 = std::exp(lambda * (h - beta));
    const Complex k0 = (e1 - e0) / lambda;
    const Complex k1 = (e1 - e0) / (lambda * lambda * len) - e0 / lambda;
    a0q = k0.imag() / wd;
    a0v = (lambda * k0).imag() / wd;
    a1q = k1.imag() / wd;
    a1v = (lambda * k1).imag() / wd;
  }
};

ModeStep mode_step(const PlanarMode& m, double h) {
  ModeStep s;
  s.sx = m.shape_x;
  s.sy = m.shape_y;
  s.omega = omega_of(m.frequency_hz);
  const double z = m.damping_ratio, w = s.omega;
  s.wd = w * std::sqrt(1.0 - z * z);
  s.lambda = Complex(-z * w, s.wd);
  const double e = std::exp(-z * w * h), c = std::cos(s.wd * h), sn = std::sin(s.wd * h);
  s.p00 = e * (c + z * w / s.wd * sn);
  s.p01 = e * sn / s.wd;
  s.p10 = -e * w * w / s.wd * sn;
  s.p11 = e * (c - z * w / s.wd * sn);
  s.integrals(h, 0.0, h, s.j0q, s.j0v, s.j1q, s.j1v);
  return s;
}

// An earlier pass at the same angle and slice: by edge `edge`, whole + part steps ago (part in
// [0, 1)), the tool centre having moved `feed` [m] along x since.
struct Behind {
  int edge = 0;
  long whole = 0;
  double part = 0.0;
  double feed = 0.0;
};

// A tooth at one axial slice.
struct Edge {
  int tooth = 0, slice = 0;
  double offset = 0.0;         // angle at t = 0 in steps: (θ_j − lag)/Δφ (whole for even pitch)
  double radius = 0.0;         // R + ρ_j
  std::vector<Behind> behind;  // the teeth ahead, nearest first, over SimulationOptions::memory_revolutions
};

// During step s, edge e cuts (if h > 0) within [wa, wb] of the step (fractions); sin/cos there.
struct CutEntry {
  int edge = 0;
  double wa = 0.0, wb = 1.0;
  double sa = 0.0, ca = 0.0, sb = 0.0, cb = 0.0;
  double phi0 = 0.0;  // angle at the step's start
};

// At the end of step s, edge e is near or inside the engagement: its surface is updated, and its
// force counted when inside.
struct EndEntry {
  int edge = 0;
  double s = 0.0, c = 0.0;
  bool inside = false;    // within [φ_st, φ_ex]: its force counts
  bool interior = false;  // strictly inside (not at an end, where the static chip may be 0): h ≤ 0 is out of the cut
};

// An edge passing a fixed angle within step s at fraction f (a tooth's tip at φ = 0, or a wall).
struct Pass {
  int edge = 0, wall = 0;
  double f = 0.0;
};

// A real step count modulo the steps per revolution M, in [0, M). Angles are counted in steps, so
// that teeth a whole number of steps apart see the same angles, bit for bit.
double wrap_steps(double k, int steps_per_rev) {
  k = std::fmod(k, static_cast<double>(steps_per_rev));
  return k < 0.0 ? k + steps_per_rev : k;
}

// An angle θ/Δφ in steps, whole when within 1e-9 of a whole number (even pitch: 39.999999999 is 40).
double in_steps(double angle, double dphi) {
  const double d = angle / dphi;
  return std::abs(d - std::round(d)) < 1e-9 ? std::round(d) : d;
}

// The step in which an edge at `offset` (steps) reaches the angle `target` (steps), as (step,
// fraction) with the fraction in (0, 1] (a crossing exactly at a step belongs to the step that ends there).
std::pair<int, double> crossing(double offset, double target, int steps_per_rev) {
  const double k = wrap_steps(target - offset, steps_per_rev);
  int s = static_cast<int>(std::floor(k));
  double f = k - s;
  if (f <= 1e-12) {
    s -= 1;
    f = 1.0;
  }
  s = ((s % steps_per_rev) + steps_per_rev) % steps_per_rev;
  return {s, f};
}

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 0.0;
}

std::string bytes_text(double b) {
  if (b >= 1e9) return fmt::format("{:.1f} GB", b / 1e9);
  if (b >= 1e6) return fmt::format("{:.1f} MB", b / 1e6);
  return fmt::format("{:.0f} kB", b / 1e3);
}

// Hermite cubic on one step: value at fraction f from values and slopes (per step) at both ends.
double hermite(double y0, double d0, double y1, double d1, double f) {
  const double f2 = f * f, f3 = f2 * f;
  return (2 * f3 - 3 * f2 + 1) * y0 + (f3 - 2 * f2 + f) * d0 + (-2 * f3 + 3 * f2) * y1 + (f3 - f2) * d1;
}

}  // namespace

// ---- Value types ----------------------------------------------------------------------------------

void PlanarMode::check(const std::string& what) const {
  if (!finite(frequency_hz) || !(frequency_hz > 0.0))
    throw InvalidArgument(fmt::format("{}: natural frequency {} Hz must be positive", what, frequency_hz));
  if (!finite(damping_ratio) || damping_ratio < 0.0 || damping_ratio >= 0.95)
    throw InvalidArgument(fmt::format("{}: damping ratio {} must lie in [0, 0.95)", what, damping_ratio));
  if (!finite(shape_x) || !finite(shape_y) || (shape_x == 0.0 && shape_y == 0.0))
    throw InvalidArgument(fmt::format("{}: mode shape ({}, {}) kg^-1/2 must be finite and not zero", what, shape_x, shape_y));
}

PlanarMode planar_mode(const Mode& mode, double direction_rad) {
  mode.check();
  if (!finite(direction_rad)) throw InvalidArgument(fmt::format("mode direction {} rad is not finite", direction_rad));
  const double s = 1.0 / std::sqrt(mode.mass_kg);
  // Exact zeros along the axes (cos(π/2) is 6e-17, not 0): an x or y mode stays uncoupled.
  const double c = std::cos(direction_rad), sn = std::sin(direction_rad);
  return {mode.frequency_hz, mode.damping_ratio, std::abs(c) < 1e-15 ? 0.0 : s * c, std::abs(sn) < 1e-15 ? 0.0 : s * sn};
}

void ToolDynamics::check() const {
  for (std::size_t i = 0; i < modes.size(); ++i) modes[i].check(fmt::format("ToolDynamics::modes[{}]", i));
}

double ToolDynamics::highest_frequency_hz() const {
  double f = 0.0;
  for (const PlanarMode& m : modes) f = std::max(f, m.frequency_hz);
  return f;
}

Eigen::Matrix2cd ToolDynamics::receptance(double frequency_hz) const {
  Eigen::Matrix2cd g = Eigen::Matrix2cd::Zero();
  const double w = omega_of(frequency_hz);
  for (const PlanarMode& m : modes) {
    const double wr = omega_of(m.frequency_hz);
    const Complex d = 1.0 / Complex(wr * wr - w * w, 2.0 * m.damping_ratio * wr * w);
    g(0, 0) += m.shape_x * m.shape_x * d;
    g(0, 1) += m.shape_x * m.shape_y * d;
    g(1, 0) += m.shape_y * m.shape_x * d;
    g(1, 1) += m.shape_y * m.shape_y * d;
  }
  return g;
}

ToolDynamics tool_dynamics(const ModalModel& model) {
  if (!model.terms.empty())
    throw InvalidArgument("ModalModel::terms: the simulation's modes are real planar modes, which cannot carry complex residues",
                          "give the coupled modes as PlanarMode (ToolDynamics::modes), or drop the terms");
  ToolDynamics d;
  for (const Mode& m : model.x) d.modes.push_back(planar_mode(m, 0.0));
  for (const Mode& m : model.y) d.modes.push_back(planar_mode(m, kPi / 2));
  return d;
}

double Cutter::helix_of(int tooth) const {
  return tooth_helix_rad.empty() ? helix_rad : tooth_helix_rad[static_cast<std::size_t>(tooth)];
}

bool Cutter::uniform() const {
  for (double p : pitch_rad)
    if (std::abs(p - kTwoPi / teeth()) > 1e-12) return false;
  for (double r : runout_m)
    if (r != 0.0) return false;
  for (double b : tooth_helix_rad)
    if (b != tooth_helix_rad.front()) return false;
  return true;
}

void Cutter::check() const {
  check_fields(cutter_fields(), *this, "Cutter");
  if (pitch_rad.empty() || pitch_rad.size() > 100)
    throw InvalidArgument(fmt::format("Cutter::pitch_rad has {} teeth: need 1…100", pitch_rad.size()));
  double sum = 0.0;
  for (std::size_t j = 0; j < pitch_rad.size(); ++j) {
    if (!finite(pitch_rad[j]) || !(pitch_rad[j] > 0.0))
      throw InvalidArgument(fmt::format("Cutter::pitch_rad[{}] = {} rad must be positive", j, pitch_rad[j]));
    sum += pitch_rad[j];
  }
  if (std::abs(sum - kTwoPi) > 1e-6)
    throw InvalidArgument(fmt::format("Cutter::pitch_rad: the teeth's spacings sum to {:.9g} rad ({:.6g}°), not a revolution "
                                      "(2π rad, 360°)",
                                      sum, degrees_of(sum)),
                          "give the angle from each tooth to the next, all of them, summing to 360°");
  if (!tooth_helix_rad.empty() && tooth_helix_rad.size() != pitch_rad.size())
    throw InvalidArgument(fmt::format("Cutter::tooth_helix_rad has {} angles for {} teeth: one per tooth, or none",
                                      tooth_helix_rad.size(), pitch_rad.size()));
  for (std::size_t j = 0; j < tooth_helix_rad.size(); ++j)
    if (!finite(tooth_helix_rad[j]) || tooth_helix_rad[j] < 0.0 || tooth_helix_rad[j] > radians_of(80.0))
      throw InvalidArgument(fmt::format("Cutter::tooth_helix_rad[{}] = {} rad must lie in [0, 80°]", j, tooth_helix_rad[j]));
  if (!runout_m.empty() && runout_m.size() != pitch_rad.size())
    throw InvalidArgument(
        fmt::format("Cutter::runout_m has {} values for {} teeth: one per tooth, or none", runout_m.size(), pitch_rad.size()));
  for (std::size_t j = 0; j < runout_m.size(); ++j)
    if (!finite(runout_m[j]) || std::abs(runout_m[j]) >= 0.5 * diameter_m)
      throw InvalidArgument(fmt::format("Cutter::runout_m[{}] = {} m: a runout must be smaller than the radius {} m", j,
                                        runout_m[j], 0.5 * diameter_m),
                            "give the runout in metres (10 µm = 1e-5)");
}

const std::vector<OptionField<Cutter>>& cutter_fields() {
  using O = Cutter;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "diameter_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "tool diameter D",
        .cli_name = "diameter",
        .cli_unit = "mm",
        .cli_per_unit = 1e3,
        .plausible = &plausible::kToolDiameter},
       [](O& o) -> double& { return o.diameter_m; }},
      {{.name = "helix_rad",
        .kind = FieldKind::Real,
        .unit = "rad",
        .min = 0.0,
        .max = radians_of(80.0),
        .help = "helix angle β of every tooth (> 0 splits the cut into axial slices)"},
       [](O& o) -> double& { return o.helix_rad; }},
      {{.name = "flute_length_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: not checked",
        .help = "flute length: deeper cuts are refused",
        .cli_name = "flute-length",
        .cli_unit = "mm",
        .cli_per_unit = 1e3,
        .plausible = &plausible::kToolLength},
       [](O& o) -> double& { return o.flute_length_m; }}};
  return fields;
}

Cutter uniform_cutter(int teeth, double diameter_m) {
  if (teeth < 1 || teeth > 100) throw InvalidArgument(fmt::format("{} teeth: need 1…100", teeth));
  Cutter c;
  c.diameter_m = diameter_m;
  c.pitch_rad.assign(static_cast<std::size_t>(teeth), kTwoPi / teeth);
  return c;
}

std::vector<double> offset_runout(const std::vector<double>& pitch_rad, double offset_m, double angle_rad) {
  std::vector<double> r;
  double theta = 0.0;
  for (double p : pitch_rad) {
    r.push_back(offset_m * std::cos(theta - angle_rad));
    theta -= p;
  }
  return r;
}

void ForceLaw::check() const { check_fields(force_law_fields(), *this, "ForceLaw"); }

const std::vector<OptionField<ForceLaw>>& force_law_fields() {
  using O = ForceLaw;
  // The cut's own fields, without the plan file's keys (no plan file holds a force law).
  const auto cutting = [](const char* name) {
    FieldSpec s = option_field(cutting_fields(), name).spec;
    s.plan_key = nullptr;
    return s;
  };
  static const std::vector<OptionField<O>> fields = {
      {cutting("tangential_coefficient"), [](O& o) -> double& { return o.tangential_coefficient; }},
      {cutting("radial_ratio"), [](O& o) -> double& { return o.radial_ratio; }},
      {{.name = "tangential_edge",
        .kind = FieldKind::Real,
        .unit = "N/m",
        .min = 0.0,
        .help = "tangential edge coefficient K_te, a force per unit depth whatever the chip",
        .cli_name = "kte",
        .plausible = &plausible::kEdgeCoefficient},
       [](O& o) -> double& { return o.tangential_edge; }},
      {{.name = "radial_edge",
        .kind = FieldKind::Real,
        .unit = "N/m",
        .min = 0.0,
        .help = "radial edge coefficient K_re, a force per unit depth whatever the chip",
        .cli_name = "kre",
        .plausible = &plausible::kEdgeCoefficient},
       [](O& o) -> double& { return o.radial_edge; }},
      {{.name = "exponent",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .help = "the force law F = K h₀ (h/h₀)^x per unit depth: its exponent x (1: the linear law)",
        .cli_name = "exponent"},
       [](O& o) -> double& { return o.exponent; }},
      {{.name = "reference_chip_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "reference chip h₀ of the exponential law, at which K is given",
        .cli_name = "reference-chip",
        .cli_unit = "mm",
        .cli_per_unit = 1e3,
        .plausible = &plausible::kFeedPerTooth},
       [](O& o) -> double& { return o.reference_chip_m; }},
      {cutting("process_damping_n_per_m"), [](O& o) -> double& { return o.process_damping_n_per_m; }}};
  return fields;
}

ForceLaw linear_force_law(const CuttingConditions& cutting) {
  ForceLaw f;
  f.tangential_coefficient = cutting.tangential_coefficient;
  f.radial_ratio = cutting.radial_ratio;
  f.process_damping_n_per_m = cutting.process_damping_n_per_m;
  return f;
}

const std::vector<OptionField<MillingCut>>& milling_cut_fields() {
  using O = MillingCut;
  // The cut's feed (cutting_fields), where 0 is a cut without a static chip.
  static const FieldSpec feed = [] {
    FieldSpec s = with_help(option_field(cutting_fields(), "feed_per_tooth_m").spec,
                            "mean feed per tooth c (variable pitch shares it by spacing)");
    s.note = "0: no static chip, the regeneration alone";
    return s;
  }();
  static const std::vector<OptionField<O>> fields = {
      {{.name = "speed_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .min_open = true,
        .help = "spindle speed n",
        .plausible = &plausible::kSpindleSpeedRpm},
       [](O& o) -> double& { return o.speed_rpm; }},
      {{.name = "depth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: nothing is cut, the tool vibrates freely",
        .help = "axial depth of cut a",
        .plausible = &plausible::kDepth},
       [](O& o) -> double& { return o.depth_m; }},
      {feed, [](O& o) -> double& { return o.feed_per_tooth_m; }}};
  return fields;
}

void MillingCut::check() const {
  check_fields(milling_cut_fields(), *this, "MillingCut");
  try {
    engagement.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string("MillingCut::engagement: ") + e.what(), e.hint());
  }
}

void SimulationOptions::check() const {
  // The scalar fields' ranges (simulation_fields); the initial state and the memory limit here.
  check_fields(simulation_fields(), *this, "SimulationOptions");
  for (double v : initial_state)
    if (!finite(v)) throw InvalidArgument("SimulationOptions::initial_state holds a value that is not finite");
  if (!finite(memory_limit_bytes) || memory_limit_bytes < 0.0)
    throw InvalidArgument(fmt::format("SimulationOptions::memory_limit_bytes = {} must be ≥ 0", memory_limit_bytes));
}

const std::vector<OptionField<SimulationOptions>>& simulation_fields() {
  using O = SimulationOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "revolutions",
        .kind = FieldKind::Integer,
        .min = 2.0,
        .max = 1e6,
        .help = "revolutions simulated",
        .cli_name = "revolutions"},
       nullptr,
       [](O& o) -> int& { return o.revolutions; }},
      {{.name = "steps_per_tooth",
        .kind = FieldKind::Integer,
        .min = 4.0,
        .max = 1e6,
        .automatic = 0.0,
        .note = "0: automatic, 40 per period of the highest mode, at least 40",
        .help = "steps per tooth period (refused where a step exceeds a quarter period of the highest mode)",
        .cli_name = "steps"},
       nullptr,
       [](O& o) -> int& { return o.steps_per_tooth; }},
      {{.name = "slices",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 1000.0,
        .automatic = 0.0,
        .note = "0: 1 without helix, else one per step of helix lag, at most 200",
        .help = "axial slices",
        .cli_name = "slices"},
       nullptr,
       [](O& o) -> int& { return o.slices; }},
      {{.name = "analysed_fraction",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .help = "the last fraction of the revolutions analysed (means, chatter, SLE), whole revolutions, at least one",
        .cli_name = "analysed"},
       [](O& o) -> double& { return o.analysed_fraction; }},
      {{.name = "record", .kind = FieldKind::Flag, .help = "keep the time histories (a map keeps only the summary)"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.record; }},
      {{.name = "memory_revolutions",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 10.0,
        .help = "the surfaces of the teeth this many revolutions back are compared for the chip",
        .cli_name = "memory-revolutions"},
       nullptr,
       [](O& o) -> int& { return o.memory_revolutions; }},
  };
  return fields;
}

int automatic_steps_per_tooth(const ToolDynamics& dynamics, int teeth, double speed_rpm) {
  const double tau = 60.0 / (teeth * speed_rpm);
  const double need = 40.0 * dynamics.highest_frequency_hz() * tau;
  return static_cast<int>(std::clamp(std::ceil(need), 40.0, 1e6));
}

std::vector<double> wall_profile(const Wall& wall, int slice, double radius_m, const std::vector<double>& runout_m,
                                 const std::vector<double>& feed_positions_m) {
  std::vector<const WallPass*> passes;
  for (const WallPass& p : wall.passes)
    if (p.slice == slice) passes.push_back(&p);
  std::sort(passes.begin(), passes.end(),
            [](const WallPass* a, const WallPass* b) { return a->feed_position_m < b->feed_position_m; });
  std::vector<double> out;
  for (double x : feed_positions_m) {
    // Arcs more than a few scallops away are far below the nearer ones: look at the neighbours.
    const auto it = std::lower_bound(passes.begin(), passes.end(), x,
                                     [](const WallPass* p, double v) { return p->feed_position_m < v; });
    const std::ptrdiff_t at = it - passes.begin();
    double deepest = -std::numeric_limits<double>::infinity();
    for (std::ptrdiff_t q = std::max<std::ptrdiff_t>(0, at - 16);
         q < std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(passes.size()), at + 16); ++q) {
      const WallPass& p = *passes[static_cast<std::size_t>(q)];
      const double r = radius_m + (runout_m.empty() ? 0.0 : runout_m[static_cast<std::size_t>(p.tooth)]);
      const double dx = x - p.feed_position_m;
      deepest = std::max(deepest, p.depth_m - dx * dx / (2.0 * r));
    }
    out.push_back(std::isfinite(deepest) ? -deepest : kNaN);
  }
  return out;
}

namespace {

// The once-per-period samples of a simulated cut judged: the growth per revolution, exp of the
// log-linear least-squares slope of the state's change from one period to the next (from sample
// p0 on; changes below 1e-7 of the state are rounding, left out), and the chatter metric, the RMS
// change of the displacement from one period to the next over the RMS of the analysed displacement
// (ax, ay) about its mean. `fitted`: how many changes the growth was fitted to (< 3: none, growth 0).
struct PeriodGrowth {
  double growth = 0.0;
  double chatter_metric = 0.0;
  std::size_t fitted = 0;
};

PeriodGrowth period_growth(const std::vector<std::vector<double>>& states, const std::vector<double>& period_x,
                           const std::vector<double>& period_y, std::size_t p0, const std::vector<double>& ax,
                           const std::vector<double>& ay, int M, int period) {
  PeriodGrowth out;
  // Differences below 1e-7 of the state are rounding (and the scheme's O(h³) asymmetries between
  // teeth): the motion has become periodic, and their logarithm is noise (flat), not growth.
  double scale2 = 0.0;
  for (std::size_t i = p0; i < states.size(); ++i) {
    double n2 = 0.0;
    for (double c : states[i]) n2 += c * c;
    scale2 = std::max(scale2, n2);
  }
  std::vector<double> logs, idx;
  double diff2 = 0.0;
  std::size_t ndiff = 0;
  for (std::size_t i = p0; i + 1 < states.size(); ++i) {
    double d = 0.0;
    for (std::size_t c = 0; c < states[i].size(); ++c) d += (states[i + 1][c] - states[i][c]) * (states[i + 1][c] - states[i][c]);
    if (d > 1e-14 * scale2) {
      logs.push_back(0.5 * std::log(d));
      idx.push_back(static_cast<double>(i));
    }
    diff2 += (period_x[i + 1] - period_x[i]) * (period_x[i + 1] - period_x[i]) +
             (period_y[i + 1] - period_y[i]) * (period_y[i + 1] - period_y[i]);
    ++ndiff;
  }
  out.growth = 0.0;
  if (logs.size() >= 3) {
    double mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < logs.size(); ++i) {
      mx += idx[i];
      my += logs[i];
    }
    mx /= static_cast<double>(logs.size());
    my /= static_cast<double>(logs.size());
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t i = 0; i < logs.size(); ++i) {
      sxy += (idx[i] - mx) * (logs[i] - my);
      sxx += (idx[i] - mx) * (idx[i] - mx);
    }
    out.growth = std::exp(sxy / sxx * (static_cast<double>(M) / period));
  }
  double mean_x = 0.0, mean_y = 0.0;
  for (std::size_t i = 0; i < ax.size(); ++i) {
    mean_x += ax[i];
    mean_y += ay[i];
  }
  const double na = static_cast<double>(std::max<std::size_t>(1, ax.size()));
  mean_x /= na;
  mean_y /= na;
  double var = 0.0;
  for (std::size_t i = 0; i < ax.size(); ++i) var += (ax[i] - mean_x) * (ax[i] - mean_x) + (ay[i] - mean_y) * (ay[i] - mean_y);
  var /= na;
  out.chatter_metric = var > 0.0 && ndiff > 0 ? std::sqrt(diff2 / static_cast<double>(ndiff) / var) : 0.0;
  out.fitted = logs.size();
  return out;
}

// The chatter frequency [Hz]: the spectrum of what the average over the whole analysed revolutions
// (M steps of h seconds each) leaves of the displacement (ax, ay) (Hann window), its highest peak
// refined by a parabola through the log power. NaN with fewer than two revolutions or nothing left.
double chatter_frequency(const std::vector<double>& ax, const std::vector<double>& ay, int M, double fmax, double h) {
  const int an_revs = static_cast<int>(ax.size() / static_cast<std::size_t>(M));  // whole analysed revolutions
  if (an_revs < 2) return kNaN;
  const std::size_t n = static_cast<std::size_t>(an_revs) * M;
  std::vector<double> avgx(static_cast<std::size_t>(M), 0.0), avgy(static_cast<std::size_t>(M), 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    avgx[i % M] += ax[i] / an_revs;
    avgy[i % M] += ay[i] / an_revs;
  }
  // Every `every`-th sample (at least 8 per period of the highest mode: the chatter lies near a mode, and
  // little is left above four times it), x + iy as one complex signal (the power at ±f together is
  // |X|² + |Y|²), zero-padded to a power of two: a fraction of the cost of two real transforms
  // of awkward lengths (M = N m need not factor well).
  const std::size_t every = std::max<std::size_t>(1, static_cast<std::size_t>(std::floor(1.0 / (8.0 * fmax * h))));
  const std::size_t nd = n / every;
  std::size_t nfft = 1;
  while (nfft < nd) nfft <<= 1;
  std::vector<Complex> zin(nfft, Complex(0.0, 0.0)), zout;
  double rest = 0.0;
  for (std::size_t i = 0; i < nd; ++i) {
    const std::size_t at = i * every;
    const double w = 0.5 - 0.5 * std::cos(kTwoPi * static_cast<double>(i) / static_cast<double>(nd));
    zin[i] = Complex(w * (ax[at] - avgx[at % M]), w * (ay[at] - avgy[at % M]));
    rest += std::norm(zin[i]);
  }
  if (rest > 0.0) {
    Eigen::FFT<double> fft;
    fft.fwd(zout, zin);
    std::vector<double> power(nfft / 2 + 1);
    for (std::size_t i = 0; i < power.size(); ++i) power[i] = std::norm(zout[i]) + std::norm(zout[(nfft - i) % nfft]);
    std::size_t best = 1;
    for (std::size_t i = 2; i + 1 < power.size(); ++i)
      if (power[i] > power[best]) best = i;
    double shift = 0.0;
    if (best > 0 && best + 1 < power.size() && power[best - 1] > 0.0 && power[best + 1] > 0.0) {
      const double a = std::log(power[best - 1]), b = std::log(power[best]), c = std::log(power[best + 1]);
      const double den = a - 2.0 * b + c;
      if (den < 0.0) shift = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
    }
    return (static_cast<double>(best) + shift) / (static_cast<double>(nfft * every) * h);
  }
  return kNaN;
}

}  // namespace

// ---- The simulation -----------------------------------------------------------------------------

namespace {

// The step grid of a simulation: the step h (m per tooth period, M per revolution), the axial
// slices, the revolutions analysed, the walls judged; checked against the cut and the memory.
struct StepGrid {
  int teeth = 0, m = 0, M = 0, slices = 0, edges_n = 0, analysed_revs = 0, first_rev = 0;
  double spin = 0.0;  // Ω [rad/s]
  double fmax = 0.0, h = 0.0, dphi = 0.0, radius = 0.0, dz = 0.0;
  long total = 0, first_step = 0;
  std::vector<double> walls_at;  // φ = 0 when the engagement starts there, π when it ends there
};

// The inputs checked against each other, the grid, and the memory the run needs (before any is taken).
StepGrid step_grid(const ToolDynamics& dynamics, const Cutter& cutter, const ForceLaw& law, const MillingCut& cut,
                   const SimulationOptions& options) {
  dynamics.check();
  cutter.check();
  law.check();
  cut.check();
  options.check();
  if (cutter.flute_length_m > 0.0 && cut.depth_m > cutter.flute_length_m)
    throw InvalidArgument(fmt::format("MillingCut::depth_m = {} m is beyond the flute length Cutter::flute_length_m = {} m",
                                      cut.depth_m, cutter.flute_length_m),
                          "cut at most the flute length deep");
  const int nm = static_cast<int>(dynamics.modes.size());
  if (!options.initial_state.empty() && options.initial_state.size() != 2 * dynamics.modes.size())
    throw InvalidArgument(fmt::format("SimulationOptions::initial_state has {} values: need 2 per mode (q, q̇), {} in all",
                                      options.initial_state.size(), 2 * nm));

  StepGrid g;
  const int teeth = g.teeth = cutter.teeth();
  g.spin = rad_s_of_rpm(cut.speed_rpm);
  const double tau = 60.0 / (teeth * cut.speed_rpm);
  const int m = g.m =
      options.steps_per_tooth > 0 ? options.steps_per_tooth : automatic_steps_per_tooth(dynamics, teeth, cut.speed_rpm);
  const double fmax = g.fmax = dynamics.highest_frequency_hz();
  const double h = g.h = tau / m;
  if (fmax > 0.0 && h > 0.25 / fmax)
    throw InvalidArgument(fmt::format("SimulationOptions::steps_per_tooth = {} gives a step of {:.4g} s, more than a quarter "
                                      "period of the highest mode ({:g} Hz)",
                                      m, h, fmax),
                          fmt::format("use at least {} steps per tooth period (or 0: automatic)",
                                      static_cast<int>(std::ceil(4.0 * fmax * tau))));
  if (static_cast<double>(m) * teeth > 2e7)
    throw InvalidArgument(
        fmt::format("SimulationOptions::steps_per_tooth = {} × {} teeth: more than 2e7 steps per revolution", m, teeth));
  const int M = g.M = m * teeth;  // steps per revolution
  const double dphi = g.dphi = kTwoPi / M;
  const double radius = g.radius = 0.5 * cutter.diameter_m;
  // Axial slices: one per step angle of helix lag over the depth (≤ 200), 1 for straight flutes.
  double total_lag = 0.0;
  for (int j = 0; j < teeth; ++j) total_lag = std::max(total_lag, cut.depth_m * std::tan(cutter.helix_of(j)) / radius);
  int slices = options.slices;
  if (slices == 0) slices = total_lag > 0.0 ? static_cast<int>(std::clamp(std::ceil(total_lag / dphi), 1.0, 200.0)) : 1;
  g.slices = slices;
  g.dz = cut.depth_m / slices;
  for (std::size_t j = 0; j < cutter.pitch_rad.size(); ++j)
    if (cutter.pitch_rad[j] < 2.0 * dphi)
      throw InvalidArgument(fmt::format("Cutter::pitch_rad[{}] = {:.4g} rad is less than two steps ({:.4g} rad) of "
                                        "SimulationOptions::steps_per_tooth = {}",
                                        j, cutter.pitch_rad[j], 2.0 * dphi, m),
                            "give more steps per tooth period");
  const long total = g.total = static_cast<long>(options.revolutions) * M;
  const int analysed_revs = g.analysed_revs =
      std::max(1, static_cast<int>(std::lround(options.analysed_fraction * options.revolutions)));
  g.first_rev = options.revolutions - analysed_revs;
  g.first_step = static_cast<long>(g.first_rev) * M;
  const int edges_n = g.edges_n = teeth * slices;
  if (cut.engagement.entry_rad == 0.0) g.walls_at.push_back(0.0);
  if (cut.engagement.exit_rad == kPi) g.walls_at.push_back(kPi);

  // Memory: histories, wall passes, the analysed displacements (and their spectra), the surfaces
  // and the step schedule.
  const double rec = options.record
                         ? static_cast<double>(total + 1) * (8.0 + teeth) * 8.0 +
                               static_cast<double>(g.walls_at.size()) * options.revolutions * edges_n * sizeof(WallPass)
                         : 0.0;
  const double need = rec + static_cast<double>(analysed_revs) * M * 8.0 * 8.0 +
                      static_cast<double>(edges_n) * M * 8.0 * (2.0 + options.memory_revolutions) +
                      static_cast<double>(options.revolutions) * (teeth + 1) * sizeof(MotionSample) * 2.0;
  const double limit = options.memory_limit_bytes > 0.0 ? options.memory_limit_bytes : physical_memory_bytes();
  if (limit > 0.0 && need > limit)
    throw InvalidArgument(fmt::format("the simulation needs about {} of memory ({} revolutions × {} steps × {} edges{}), "
                                      "more than {} ({})",
                                      bytes_text(need), options.revolutions, M, edges_n,
                                      options.record ? ", histories recorded" : "", bytes_text(limit),
                                      options.memory_limit_bytes > 0.0 ? "SimulationOptions::memory_limit_bytes"
                                                                       : "the machine's physical memory"),
                          options.record ? "simulate fewer SimulationOptions::revolutions or fewer steps per tooth, or keep no "
                                           "histories (SimulationOptions::record = false)"
                                         : "simulate fewer SimulationOptions::revolutions or fewer steps per tooth");
  return g;
}

// Edges: tooth j at slice l; θ_{j+1} = θ_j − p_j; the tooth ahead of j is j − 1, pitch p_{j−1}.
// Each with the earlier passes at its angle and slice over `memory` revolutions (a variable helix:
// the earlier tooth lags by its own angle at that height).
std::vector<Edge> cutting_edges(const Cutter& cutter, const MillingCut& cut, const StepGrid& g, int memory) {
  const int teeth = g.teeth, slices = g.slices;
  std::vector<Edge> edges(static_cast<std::size_t>(g.edges_n));
  double theta = 0.0;
  for (int j = 0; j < teeth; ++j) {
    for (int l = 0; l < slices; ++l) {
      Edge& e = edges[static_cast<std::size_t>(j * slices + l)];
      e.tooth = j;
      e.slice = l;
      const double z = (l + 0.5) * g.dz;
      const double lag = z * std::tan(cutter.helix_of(j)) / g.radius;
      e.offset = in_steps(theta - lag, g.dphi);
      e.radius = g.radius + (cutter.runout_m.empty() ? 0.0 : cutter.runout_m[static_cast<std::size_t>(j)]);
      double gap = 0.0;  // the angle back to the earlier tooth, at the tip
      for (int back = 1; back <= memory * teeth; ++back) {
        const int ahead = ((j - back) % teeth + teeth) % teeth;
        gap += cutter.pitch_rad[static_cast<std::size_t>(ahead)];
        // At height z (a variable helix): the earlier tooth lags by its own angle.
        const double at_z = gap + lag - z * std::tan(cutter.helix_of(ahead)) / g.radius;
        if (!(at_z >= 2.0 * g.dphi))
          throw InvalidArgument(fmt::format("Cutter::tooth_helix_rad: at {:.4g} mm above the tip tooth {} is less than two "
                                            "steps behind tooth {}: the helix angles differ too much for this depth",
                                            z * 1e3, j, ahead));
        const double d = in_steps(at_z, g.dphi), whole = std::floor(d);
        e.behind.push_back(
            {ahead * slices + l, static_cast<long>(whole), d - whole, teeth * cut.feed_per_tooth_m * at_z / kTwoPi});
      }
    }
    theta -= cutter.pitch_rad[static_cast<std::size_t>(j)];
  }
  return edges;
}

// The schedule of one revolution, per step: the edges cutting within it, those whose surface is
// updated at its end, the tips passing φ = 0 and the edges passing a wall.
struct Schedule {
  std::vector<std::vector<CutEntry>> cuts;
  std::vector<std::vector<EndEntry>> ends;
  std::vector<std::vector<Pass>> tip_passes, wall_passes;
};

Schedule revolution_schedule(const std::vector<Edge>& edges, const Cutter& cutter, const MillingCut& cut, const StepGrid& g) {
  const int M = g.M;
  const double dphi = g.dphi;
  const double st = cut.engagement.entry_rad, ex = cut.engagement.exit_rad;
  const double margin = 3.0 * dphi;  // surfaces kept this far outside the engagement (interpolation reads them)
  Schedule r;
  r.cuts.resize(static_cast<std::size_t>(M));
  r.ends.resize(static_cast<std::size_t>(M));
  r.tip_passes.resize(static_cast<std::size_t>(M));
  r.wall_passes.resize(static_cast<std::size_t>(M));
  const bool cutting = cut.depth_m > 0.0;
  for (int e = 0; e < g.edges_n && cutting; ++e) {
    const Edge& E = edges[static_cast<std::size_t>(e)];
    for (int s = 0; s < M; ++s) {
      const double p0 = dphi * wrap_steps(E.offset + s, M);
      // The engagement [st, ex] against the step [p0, p0 + dφ] (and one revolution on).
      for (double shift : {0.0, kTwoPi}) {
        const double a = std::max(0.0, (st + shift - p0) / dphi), b = std::min(1.0, (ex + shift - p0) / dphi);
        if (b > a + 1e-12) {
          CutEntry c;
          c.edge = e;
          c.wa = a;
          c.wb = b;
          c.phi0 = p0;
          c.sa = std::sin(p0 + a * dphi);
          c.ca = std::cos(p0 + a * dphi);
          c.sb = std::sin(p0 + b * dphi);
          c.cb = std::cos(p0 + b * dphi);
          r.cuts[static_cast<std::size_t>(s)].push_back(c);
        }
      }
      const double p1 = dphi * wrap_steps(E.offset + s + 1, M);
      const bool near = (p1 >= st - margin && p1 <= ex + margin) || p1 - kTwoPi >= st - margin || p1 + kTwoPi <= ex + margin;
      if (near)
        r.ends[static_cast<std::size_t>(s)].push_back(
            {e, std::sin(p1), std::cos(p1), p1 >= st && p1 <= ex, p1 > st + 1e-9 && p1 < ex - 1e-9});
    }
  }
  for (int j = 0; j < g.teeth; ++j) {
    double theta = 0.0;
    for (int i = 0; i < j; ++i) theta -= cutter.pitch_rad[static_cast<std::size_t>(i)];
    const auto [s, f] = crossing(in_steps(theta, dphi), 0.0, M);
    r.tip_passes[static_cast<std::size_t>(s)].push_back({j, 0, f});
  }
  for (std::size_t w = 0; w < g.walls_at.size() && cutting; ++w)
    for (int e = 0; e < g.edges_n; ++e) {
      const auto [s, f] = crossing(edges[static_cast<std::size_t>(e)].offset, g.walls_at[w] == 0.0 ? 0.0 : 0.5 * M, M);
      r.wall_passes[static_cast<std::size_t>(s)].push_back({e, static_cast<int>(w), f});
    }
  return r;
}

// The time stepping: the modal state, the surfaces every edge left (a ring over the last
// memory_revolutions), the force of each step (predictor, then corrector linear over each cutting
// piece), what is recorded, and the samples the chatter analysis and the surface location error read.
class MillingRun {
 public:
  MillingRun(const ToolDynamics& dynamics, const Cutter& cutter, const ForceLaw& law, const MillingCut& cut,
             const SimulationOptions& options, const StepGrid& grid, SimulationResult& result);
  // Steps until the end or a vibration beyond the chip model (then a warning); progress per revolution.
  void run(const std::function<void(double)>& progress);
  // The summary over the analysed revolutions: mean forces, power, SLE, growth, stability, chatter frequency.
  void summarise();

 private:
  void tip(const std::vector<double>& a, double& x, double& y) const;
  double surface(const Edge& E, long slot1, double f, double sn) const;
  double force(double chip, double s, double c, double vn, double& fx, double& fy) const;
  void close_revolution();
  void push_state();
  void finish(long k1, long slot1, int s);
  void advance(long k, int s);
  void sample_passes(long k, int s, double x0, double y0, double vx0, double vy0);
  bool end_of_step(long k1, const std::function<void(double)>& progress);
  void stopped_early();

  const MillingCut& cut;
  const SimulationOptions& options;
  const StepGrid& g;
  SimulationResult& res;
  const int nm, teeth, slices, M, memory;
  const double h, dphi, radius, dz, fmax;
  const long total, first_step;
  const std::vector<Edge> edges;
  const Schedule schedule;
  std::vector<ModeStep> modes;
  std::vector<double> q, v, qp, qn, vn;

  // Where each edge passed, u·r + R + ρ_j at its own angle, at the steps of the last
  // memory_revolutions (a ring), at rest before t = 0.
  const long ring_n;
  std::vector<double> passed;

  // The force law. Process damping (ForceLaw::process_damping_n_per_m): −C_i dz (u·ṙ)/V u on a
  // slice in the cut, V = πDn/60.
  const double kt, kr, kte, kre, h0, xp, damping;
  const bool linear;

  const bool rec;
  // Per wall and slice: the deepest δ of the current revolution, and the sum of those over the analysed ones.
  std::vector<std::vector<double>> deepest, deepest_sum;
  std::vector<std::vector<int>> deepest_revs;
  int current_rev = 0;

  // The chatter analysis: the modal state once per cut period, the displacement in the analysed revolutions.
  const int period;
  std::vector<std::vector<double>> states;
  std::vector<double> ax, ay;
  std::vector<double> period_x, period_y;  // the displacement at the same samples

  double rx = 0.0, ry = 0.0, vx = 0.0, vy = 0.0;
  double fx_k = 0.0, fy_k = 0.0;  // the force at the current step (final displacement): the record
  // The predictor's force: the previous step's corrector's at its end. Not the recorded one: where a
  // chip is exactly 0 (an edge at φ = 0 or π meets its own surface), rounding decides whether an
  // edge force counts there, and the record's choice would differ from tooth to tooth.
  double px = 0.0, py = 0.0;
  double imp_x = 0.0, imp_y = 0.0, imp_t = 0.0;
  long inside = 0, out_of_cut = 0;
  double peak = 0.0;

  // The chip model is that of small vibrations (the tooth's path a circle about the nominal centre,
  // the engagement's angles fixed). A cut whose vibration amplitude grows beyond 5 % of the radius
  // (a strongly unstable cut of a tool flexible in x and y: the cutting force can feed a whirl
  // without bound) has left it: the simulation stops there and says so.
  const double limit;
  double lo_x = 0.0, hi_x = 0.0, lo_y = 0.0, hi_y = 0.0;  // this revolution's range of the displacement
  bool diverged = false;
  double vibration = 0.0;
  long slot = 0;  // k mod ring_n
};

MillingRun::MillingRun(const ToolDynamics& dynamics, const Cutter& cutter, const ForceLaw& law, const MillingCut& cut_,
                       const SimulationOptions& options_, const StepGrid& grid, SimulationResult& result)
    : cut(cut_),
      options(options_),
      g(grid),
      res(result),
      nm(static_cast<int>(dynamics.modes.size())),
      teeth(grid.teeth),
      slices(grid.slices),
      M(grid.M),
      memory(options_.memory_revolutions),
      h(grid.h),
      dphi(grid.dphi),
      radius(grid.radius),
      dz(grid.dz),
      fmax(grid.fmax),
      total(grid.total),
      first_step(grid.first_step),
      edges(cutting_edges(cutter, cut_, grid, options_.memory_revolutions)),
      schedule(revolution_schedule(edges, cutter, cut_, grid)),
      q(static_cast<std::size_t>(nm), 0.0),
      v(static_cast<std::size_t>(nm), 0.0),
      qp(static_cast<std::size_t>(nm)),
      qn(static_cast<std::size_t>(nm)),
      vn(static_cast<std::size_t>(nm)),
      ring_n(static_cast<long>(memory) * M + 2),
      passed(static_cast<std::size_t>(grid.edges_n) * static_cast<std::size_t>(ring_n)),
      kt(law.tangential_coefficient),
      kr(law.radial_ratio * law.tangential_coefficient),
      kte(law.tangential_edge),
      kre(law.radial_edge),
      h0(law.reference_chip_m),
      xp(law.exponent),
      damping(law.process_damping_n_per_m / (kPi * cutter.diameter_m * cut_.speed_rpm / 60.0)),
      linear(law.exponent == 1.0),
      rec(options_.record),
      deepest(grid.walls_at.size(),
              std::vector<double>(static_cast<std::size_t>(slices), -std::numeric_limits<double>::infinity())),
      deepest_sum(grid.walls_at.size(), std::vector<double>(static_cast<std::size_t>(slices), 0.0)),
      deepest_revs(grid.walls_at.size(), std::vector<int>(static_cast<std::size_t>(slices), 0)),
      period(cutter.uniform() ? grid.m : grid.M),
      limit(0.05 * grid.radius) {
  for (const PlanarMode& pm : dynamics.modes) modes.push_back(mode_step(pm, h));
  for (int r = 0; r < nm && !options.initial_state.empty(); ++r) {
    q[static_cast<std::size_t>(r)] = options.initial_state[static_cast<std::size_t>(2 * r)];
    v[static_cast<std::size_t>(r)] = options.initial_state[static_cast<std::size_t>(2 * r + 1)];
  }
  for (int e = 0; e < g.edges_n; ++e)
    std::fill_n(passed.begin() + static_cast<std::ptrdiff_t>(e) * ring_n, ring_n, edges[static_cast<std::size_t>(e)].radius);

  // Records.
  const std::size_t nrec = rec ? static_cast<std::size_t>(total + 1) : 0;
  if (rec) {
    for (auto* v2 :
         {&res.time_s, &res.force_x_n, &res.force_y_n, &res.x_m, &res.y_m, &res.vx_m_per_s, &res.vy_m_per_s, &res.torque_nm})
      v2->resize(nrec);
    res.tooth_force_n.assign(static_cast<std::size_t>(teeth), std::vector<double>(nrec, 0.0));
  }
  res.walls.resize(g.walls_at.size());
  for (std::size_t w = 0; w < g.walls_at.size(); ++w) {
    res.walls[w].angle_rad = g.walls_at[w];
    for (int l = 0; l < slices; ++l) res.walls[w].slice_height_m.push_back((l + 0.5) * dz);
  }
  ax.reserve(static_cast<std::size_t>(g.analysed_revs) * M);
  ay.reserve(static_cast<std::size_t>(g.analysed_revs) * M);
}

void MillingRun::tip(const std::vector<double>& a, double& x, double& y) const {
  x = 0.0;
  y = 0.0;
  for (int r = 0; r < nm; ++r) {
    x += modes[static_cast<std::size_t>(r)].sx * a[static_cast<std::size_t>(r)];
    y += modes[static_cast<std::size_t>(r)].sy * a[static_cast<std::size_t>(r)];
  }
}

// The ring is read at step k + f − delay (f in [0, 1], k's slot `slot1` = k mod ring_n): whole and
// fractional parts of the delay kept apart, so that no division is needed.
double MillingRun::surface(const Edge& E, long slot1, double f, double sn) const {
  double w = -std::numeric_limits<double>::infinity();
  for (const Behind& b : E.behind) {
    double gf = f - b.part;
    long base = slot1 - b.whole;
    if (gf < 0.0) {
      gf += 1.0;
      --base;
    }
    if (base < 0) base += ring_n;
    const double* ring = passed.data() + static_cast<std::ptrdiff_t>(b.edge) * ring_n;
    double p = ring[base];
    if (gf > 0.0) p += gf * (ring[base + 1 == ring_n ? 0 : base + 1] - p);
    w = std::max(w, p - sn * b.feed);
  }
  return w;
}

// The force on one slice (fx, fy) for a chip `chip`, at sin/cos (s, c) of the edge's angle, `vn` = u·ṙ; returns F_t.
double MillingRun::force(double chip, double s, double c, double vn_, double& fx, double& fy) const {
  const double hc = linear ? chip : h0 * std::pow(chip / h0, xp);
  const double ft = dz * (kte + kt * hc), fr = dz * (kre + kr * hc), fd = dz * damping * vn_;
  fx = -ft * c - fr * s - fd * s;
  fy = ft * s - fr * c - fd * c;
  return ft;
}

void MillingRun::close_revolution() {
  for (std::size_t w = 0; w < g.walls_at.size(); ++w)
    for (int l = 0; l < slices; ++l) {
      double& d = deepest[w][static_cast<std::size_t>(l)];
      if (current_rev >= g.first_rev && std::isfinite(d)) {
        deepest_sum[w][static_cast<std::size_t>(l)] += d;
        ++deepest_revs[w][static_cast<std::size_t>(l)];
      }
      d = -std::numeric_limits<double>::infinity();
    }
}

void MillingRun::push_state() {
  std::vector<double> s(2 * static_cast<std::size_t>(nm));
  for (int r = 0; r < nm; ++r) {
    s[2 * static_cast<std::size_t>(r)] = modes[static_cast<std::size_t>(r)].omega * q[static_cast<std::size_t>(r)];
    s[2 * static_cast<std::size_t>(r) + 1] = v[static_cast<std::size_t>(r)];
  }
  states.push_back(std::move(s));
}

// Surfaces and force at the end of step s (time index k1), with the final displacement.
void MillingRun::finish(long k1, long slot1, int s) {
  fx_k = 0.0;
  fy_k = 0.0;
  double torque = 0.0;
  const bool analysed = k1 > first_step;
  for (const EndEntry& en : schedule.ends[static_cast<std::size_t>(s)]) {
    const Edge& E = edges[static_cast<std::size_t>(en.edge)];
    const double ur = en.s * rx + en.c * ry + E.radius;
    const double w = surface(E, slot1, 0.0, en.s);
    passed[static_cast<std::size_t>(en.edge) * static_cast<std::size_t>(ring_n) + static_cast<std::size_t>(slot1)] = ur;
    if (!en.inside) continue;
    const double chip = ur - w;
    if (analysed && en.interior) {
      ++inside;
      out_of_cut += chip <= 0.0;
    }
    if (chip <= 0.0) continue;
    double fx, fy;
    const double ft = force(chip, en.s, en.c, en.s * vx + en.c * vy, fx, fy);
    fx_k += fx;
    fy_k += fy;
    torque += ft * E.radius;
    if (rec) res.tooth_force_n[static_cast<std::size_t>(E.tooth)][static_cast<std::size_t>(k1)] += ft;
  }
  if (analysed) peak = std::max(peak, fx_k * fx_k + fy_k * fy_k);  // squared; the root at the end
  if (rec) {
    const auto i = static_cast<std::size_t>(k1);
    res.time_s[i] = static_cast<double>(k1) * h;
    res.force_x_n[i] = fx_k;
    res.force_y_n[i] = fy_k;
    res.x_m[i] = rx;
    res.y_m[i] = ry;
    res.vx_m_per_s[i] = vx;
    res.vy_m_per_s[i] = vy;
    res.torque_nm[i] = torque;
  }
}

// Step k (step s of its revolution): the predictor (the force of step k held over the step), the
// corrector (the force linear over each cutting piece, at the predicted end), the new state, and
// the surfaces and force at its end.
void MillingRun::advance(long k, int s) {
  double rxp = 0.0, ryp = 0.0, vxp = 0.0, vyp = 0.0;
  for (int r = 0; r < nm; ++r) {
    const ModeStep& md = modes[static_cast<std::size_t>(r)];
    const auto ri = static_cast<std::size_t>(r);
    const double p = md.sx * px + md.sy * py;
    qn[ri] = md.p00 * q[ri] + md.p01 * v[ri];
    vn[ri] = md.p10 * q[ri] + md.p11 * v[ri];
    qp[ri] = qn[ri] + md.j0q * p;
    rxp += md.sx * qp[ri];
    ryp += md.sy * qp[ri];
    if (damping > 0.0) {
      const double vpr = vn[ri] + md.j0v * p;
      vxp += md.sx * vpr;
      vyp += md.sy * vpr;
    }
  }
  // The tip velocity along u at fraction f of the step (linear between the ends, as the displacement).
  auto normal_velocity = [&](double f, double sn, double cs) {
    return damping > 0.0 ? sn * (vx + f * (vxp - vx)) + cs * (vy + f * (vyp - vy)) : 0.0;
  };
  double gax = 0.0, gay = 0.0, gbx = 0.0, gby = 0.0;  // whole-step pieces, summed
  double endx = 0.0, endy = 0.0;                      // every piece's force at the step's end
  const bool analysed = k >= first_step;
  for (const CutEntry& c : schedule.cuts[static_cast<std::size_t>(s)]) {
    const Edge& E = edges[static_cast<std::size_t>(c.edge)];
    auto chip_at = [&](double f, double sn, double cs) {
      const double x = rx + f * (rxp - rx), y = ry + f * (ryp - ry);
      return sn * x + cs * y + E.radius - surface(E, slot, f, sn);
    };
    const double ha = chip_at(c.wa, c.sa, c.ca), hb = chip_at(c.wb, c.sb, c.cb);
    if (ha <= 0.0 && hb <= 0.0) continue;
    double fa = c.wa, fb = c.wb, sa = c.sa, ca = c.ca, sb = c.sb, cb = c.cb, cha = ha, chb = hb;
    if (ha <= 0.0 || hb <= 0.0) {  // the tooth leaves or re-enters the cut within the piece: h = 0 located linearly
      const double fc = c.wa + (c.wb - c.wa) * ha / (ha - hb);
      const double sc = std::sin(c.phi0 + fc * dphi), cc = std::cos(c.phi0 + fc * dphi);
      if (ha > 0.0) {
        fb = fc;
        sb = sc;
        cb = cc;
        chb = 0.0;
      } else {
        fa = fc;
        sa = sc;
        ca = cc;
        cha = 0.0;
      }
      if (!(fb > fa)) continue;
    }
    double fxa, fya, fxb, fyb;
    const double fta = force(cha, sa, ca, normal_velocity(fa, sa, ca), fxa, fya),
                 ftb = force(chb, sb, cb, normal_velocity(fb, sb, cb), fxb, fyb);
    if (analysed) {
      const double len = (fb - fa) * h * 0.5;
      imp_x += len * (fxa + fxb);
      imp_y += len * (fya + fyb);
      imp_t += len * (fta + ftb) * E.radius;
    }
    if (fb == 1.0) {
      endx += fxb;
      endy += fyb;
    }
    if (fa == 0.0 && fb == 1.0) {
      gax += fxa;
      gay += fya;
      gbx += fxb;
      gby += fyb;
      continue;
    }
    for (int r = 0; r < nm; ++r) {
      const ModeStep& md = modes[static_cast<std::size_t>(r)];
      double a0q, a0v, a1q, a1v;
      md.integrals(h, fa * h, fb * h, a0q, a0v, a1q, a1v);
      const double pa = md.sx * fxa + md.sy * fya, pb = md.sx * fxb + md.sy * fyb;
      qn[static_cast<std::size_t>(r)] += a0q * pa + a1q * (pb - pa);
      vn[static_cast<std::size_t>(r)] += a0v * pa + a1v * (pb - pa);
    }
  }
  for (int r = 0; r < nm; ++r) {
    const ModeStep& md = modes[static_cast<std::size_t>(r)];
    const auto ri = static_cast<std::size_t>(r);
    const double pa = md.sx * gax + md.sy * gay, pb = md.sx * gbx + md.sy * gby;
    q[ri] = qn[ri] + md.j0q * pa + md.j1q * (pb - pa);
    v[ri] = vn[ri] + md.j0v * pa + md.j1v * (pb - pa);
  }
  tip(q, rx, ry);
  tip(v, vx, vy);
  px = endx;
  py = endy;
  slot = slot + 1 == ring_n ? 0 : slot + 1;
  finish(k + 1, slot, s);
}

// Samples between the steps k and k + 1 (from (x0, y0) at velocity (vx0, vy0)): cubic Hermite with
// the velocities, at the tips passing φ = 0 and the edges passing a wall.
void MillingRun::sample_passes(long k, int s, double x0, double y0, double vx0, double vy0) {
  for (const Pass& p : schedule.tip_passes[static_cast<std::size_t>(s)]) {
    const double t = (static_cast<double>(k) + p.f) * h;
    // Velocities linearly (their slopes, the accelerations, are not kept).
    res.per_tooth.push_back({t, hermite(x0, vx0 * h, rx, vx * h, p.f), hermite(y0, vy0 * h, ry, vy * h, p.f),
                             vx0 + p.f * (vx - vx0), vy0 + p.f * (vy - vy0), p.edge});
  }
  for (const Pass& p : schedule.wall_passes[static_cast<std::size_t>(s)]) {
    const Edge& E = edges[static_cast<std::size_t>(p.edge)];
    const double phi = g.walls_at[static_cast<std::size_t>(p.wall)];
    const double x = hermite(x0, vx0 * h, rx, vx * h, p.f), y = hermite(y0, vy0 * h, ry, vy * h, p.f);
    const double delta = std::sin(phi) * x + std::cos(phi) * y + (E.radius - radius);
    const double t = (static_cast<double>(k) + p.f) * h;
    double& d = deepest[static_cast<std::size_t>(p.wall)][static_cast<std::size_t>(E.slice)];
    d = std::max(d, delta);
    if (rec)
      res.walls[static_cast<std::size_t>(p.wall)].passes.push_back(
          {current_rev, E.tooth, E.slice, t, teeth * cut.feed_per_tooth_m * cut.speed_rpm / 60.0 * t, delta});
  }
}

// After step k1 − 1: the analysed and once-per-period samples, and at a revolution's end its
// bookkeeping and the divergence check. False: the vibration left the chip model (stop).
bool MillingRun::end_of_step(long k1, const std::function<void(double)>& progress) {
  if (k1 > first_step) {
    ax.push_back(rx);
    ay.push_back(ry);
  }
  if (k1 % period == 0) {
    push_state();
    period_x.push_back(rx);
    period_y.push_back(ry);
  }
  lo_x = std::min(lo_x, rx);
  hi_x = std::max(hi_x, rx);
  lo_y = std::min(lo_y, ry);
  hi_y = std::max(hi_y, ry);
  if (k1 % M != 0) return true;
  close_revolution();
  ++current_rev;
  res.per_revolution.push_back({static_cast<double>(k1) * h, rx, ry, vx, vy, -1});
  if (progress) progress(static_cast<double>(current_rev) / options.revolutions);
  const double amplitude = 0.5 * std::max(hi_x - lo_x, hi_y - lo_y);
  if (!std::isfinite(amplitude))
    throw NumericalError(fmt::format("the simulated tool displacement overflowed at {:.4g} s, revolution {}",
                                     static_cast<double>(k1) * h, current_rev),
                         "check the modes' units (kg, Hz) and the cutting coefficients (N/m²)");
  if (amplitude > limit) {
    diverged = true;
    vibration = amplitude;
    return false;
  }
  lo_x = hi_x = rx;
  lo_y = hi_y = ry;
  return true;
}

void MillingRun::run(const std::function<void(double)>& progress) {
  tip(q, rx, ry);
  tip(v, vx, vy);
  finish(0, 0, M - 1);
  res.per_revolution.push_back({0.0, rx, ry, vx, vy, -1});
  push_state();
  period_x.push_back(rx);
  period_y.push_back(ry);
  lo_x = hi_x = rx;
  lo_y = hi_y = ry;
  for (long k = 0; k < total; ++k) {
    const int s = static_cast<int>(k % M);
    const double x0 = rx, y0 = ry, vx0 = vx, vy0 = vy;
    advance(k, s);
    sample_passes(k, s, x0, y0, vx0, vy0);
    if (!end_of_step(k + 1, progress)) break;
  }
  res.diverged = diverged;
  if (diverged) stopped_early();
}

// The result cut to the revolutions simulated, and why.
void MillingRun::stopped_early() {
  res.revolutions = current_rev;
  res.steps = static_cast<long>(current_rev) * M;
  res.analysed_from = std::min(g.first_rev, current_rev - 1);
  if (rec) {
    for (auto* v2 :
         {&res.time_s, &res.force_x_n, &res.force_y_n, &res.x_m, &res.y_m, &res.vx_m_per_s, &res.vy_m_per_s, &res.torque_nm})
      v2->resize(static_cast<std::size_t>(res.steps + 1));
    for (auto& f : res.tooth_force_n) f.resize(static_cast<std::size_t>(res.steps + 1));
  }
  res.warnings.push_back(fmt::format(
      "the vibration grew beyond 5 % of the tool radius (an amplitude of {:.3g} mm) in revolution {}: the cut chatters "
      "violently, and the simulation stopped there (the chip model holds for small vibrations only); its summary covers "
      "what was simulated",
      1e3 * vibration, current_rev));
}

void MillingRun::summarise() {
  const int done_revs = res.revolutions;
  const int analysed_done = std::max(0, done_revs - g.first_rev);
  const double t_an = analysed_done * 60.0 / cut.speed_rpm;  // 0 when stopped before the analysed revolutions
  res.mean_force_x_n = analysed_done > 0 ? imp_x / t_an : kNaN;
  res.mean_force_y_n = analysed_done > 0 ? imp_y / t_an : kNaN;
  res.mean_torque_nm = analysed_done > 0 ? imp_t / t_an : kNaN;
  res.power_w = res.mean_torque_nm * g.spin;
  res.peak_force_n = std::sqrt(peak);
  res.out_of_cut_fraction = inside > 0 ? static_cast<double>(out_of_cut) / static_cast<double>(inside) : 0.0;
  for (std::size_t w = 0; w < g.walls_at.size(); ++w) {
    Wall& wl = res.walls[w];
    double sum = 0.0;
    for (int l = 0; l < slices; ++l) {
      const int n = deepest_revs[w][static_cast<std::size_t>(l)];
      wl.sle_m.push_back(n > 0 ? -deepest_sum[w][static_cast<std::size_t>(l)] / n : kNaN);
      sum += wl.sle_m.back();
    }
    wl.mean_sle_m = sum / slices;
  }
  res.sle_m = res.walls.empty() ? kNaN : res.walls.front().mean_sle_m;

  // Growth and metric from the once-per-period samples of the analysed revolutions.
  // (Stopped early: the last half of the periods simulated.)
  const std::size_t p0 = analysed_done > 0 ? static_cast<std::size_t>(first_step / period) : states.size() / 2;
  const PeriodGrowth gr = period_growth(states, period_x, period_y, p0, ax, ay, M, period);
  res.growth = gr.growth;
  res.chatter_metric = gr.chatter_metric;
  // Decaying, and either small by now or still linear (the teeth stay in the cut): a saturated
  // chatter (teeth jumping out of the cut) has a flat, noisy growth near 1 that must not pass.
  if (diverged) {
    if (gr.fitted < 3) res.growth = std::numeric_limits<double>::infinity();  // too short to fit: it blew up
    res.chatter_metric = std::numeric_limits<double>::infinity();             // beyond any periodic motion
  }
  res.stable = !diverged && res.growth < 1.0 && (res.chatter_metric < kChatterMetricLimit || res.out_of_cut_fraction < 1e-3);

  // Chatter frequency: the spectrum of what the average over the revolutions leaves (Hann window).
  res.chatter_hz = nm > 0 ? chatter_frequency(ax, ay, M, fmax, h) : kNaN;

  if (!res.stable && res.out_of_cut_fraction > 0.0)
    res.warnings.push_back(
        fmt::format("the cut chatters: the teeth leave the cut in {:.1f} % of the engaged samples (the "
                    "amplitude is bounded by that, not by the linear model)",
                    100.0 * res.out_of_cut_fraction));
  if (nm > 0 && g.analysed_revs < 5)
    res.warnings.push_back(
        fmt::format("only {} revolution(s) analysed: the growth estimate and the chatter decision are "
                    "rough; simulate more revolutions",
                    g.analysed_revs));
}

}  // namespace

SimulationResult simulate_milling(const ToolDynamics& dynamics, const Cutter& cutter, const ForceLaw& law, const MillingCut& cut,
                                  const SimulationOptions& options, const std::function<void(double)>& progress) {
  const StepGrid g = step_grid(dynamics, cutter, law, cut, options);
  SimulationResult res;
  res.step_s = g.h;
  res.steps_per_tooth = g.m;
  res.steps_per_revolution = g.M;
  res.slices = g.slices;
  res.revolutions = options.revolutions;
  res.steps = g.total;
  res.analysed_from = g.first_rev;
  MillingRun run(dynamics, cutter, law, cut, options, g, res);
  run.run(progress);
  run.summarise();
  return res;
}

}  // namespace toolpoint
