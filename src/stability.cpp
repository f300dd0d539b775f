// toolpoint: milling stability lobes — zero-order approximation from FRFs and semi-discretization
// of a modal model. Units: SI (m, kg, N, s, rad), frequencies in Hz, spindle speeds in rpm;
// conventions in stability.hpp.
#include "toolpoint/stability/stability.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <memory>
#include <mutex>
#include <unsupported/Eigen/FFT>
#include <optional>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/peaks.hpp"

namespace toolpoint {

namespace {
}  // namespace

// ---- Geometry -------------------------------------------------------------------------------

void Engagement::check() const {
  if (!std::isfinite(entry_rad) || !std::isfinite(exit_rad) || entry_rad < 0.0 || exit_rad > kPi || !(entry_rad < exit_rad))
    throw InvalidArgument(fmt::format("entry/exit angles {:.6g}°/{:.6g}° must satisfy 0 ≤ entry < exit ≤ 180°",
                                      degrees_of(entry_rad), degrees_of(exit_rad)),
                          "angles are measured clockwise from the normal (y) direction; up-milling starts at 0°, "
                          "down-milling ends at 180°");
}

Engagement engagement_from_immersion(double radial_immersion, MillingDirection direction) {
  if (!std::isfinite(radial_immersion) || !(radial_immersion > 0.0) || radial_immersion > 1.0)
    throw InvalidArgument(fmt::format("radial immersion a/D = {} must lie in (0, 1]", radial_immersion),
                          "a/D is the radial depth of cut over the tool diameter: 1 is a slot, 0.05 a light finishing cut");
  if (direction == MillingDirection::Up) return {0.0, std::acos(1.0 - 2.0 * radial_immersion)};
  return {std::acos(2.0 * radial_immersion - 1.0), kPi};
}

Engagement engagement_from_degrees(double entry_deg, double exit_deg) {
  Engagement e{radians_of(entry_deg), radians_of(exit_deg)};
  e.check();
  return e;
}

// CuttingConditions::check's helix part.
static void check_helix(const CuttingConditions& c) {
  if (c.helix_rad.empty()) return;
  if (c.helix_rad.size() != 1 && static_cast<int>(c.helix_rad.size()) != c.teeth)
    throw InvalidArgument(fmt::format("CuttingConditions::helix_rad has {} angles for {} teeth", c.helix_rad.size(), c.teeth),
                          "give one helix angle for every tooth, or one per tooth (a variable helix), or none");
  for (std::size_t j = 0; j < c.helix_rad.size(); ++j)
    if (!std::isfinite(c.helix_rad[j]) || c.helix_rad[j] < 0.0 || c.helix_rad[j] > kMaxHelixRad)
      throw InvalidArgument(fmt::format("CuttingConditions::helix_rad[{}] = {:.6g}° must lie in 0…80°", j,
                                        degrees_of(c.helix_rad[j])),
                            c.helix_rad[j] < 0.0 ? "give the helix angle's size, ≥ 0: the edge lags the tip as the height "
                                                   "grows (a right-hand helix on a clockwise cutter)"
                                                 : "end mills have helix angles of 0…60° (0…1.05 rad): check the unit");
  if (c.helical() && !(c.diameter_m > 0.0))
    throw InvalidArgument("CuttingConditions::diameter_m must be given with a helix (the lag at height z is z·tan β/R)");
}

void CuttingConditions::check() const {
  check_fields(cutting_fields(), *this, "CuttingConditions");
  engagement.check();
  if (process_damping_n_per_m > 0.0 && !(diameter_m > 0.0))
    throw InvalidArgument("CuttingConditions::diameter_m must be given with process damping (the cutting speed is πDn/60)");
  if (!runout_m.empty()) {
    if (static_cast<int>(runout_m.size()) != teeth)
      throw InvalidArgument(fmt::format("CuttingConditions::runout_m has {} offsets for {} teeth", runout_m.size(), teeth),
                            "give one radius offset per tooth, or none");
    for (std::size_t j = 0; j < runout_m.size(); ++j) {
      if (!std::isfinite(runout_m[j]) || (diameter_m > 0.0 && std::abs(runout_m[j]) >= 0.5 * diameter_m))
        throw InvalidArgument(fmt::format("CuttingConditions::runout_m[{}] = {:.6g} mm lies beyond the tool radius {:.6g} mm", j,
                                          runout_m[j] * 1e3, 0.5 * diameter_m * 1e3),
                              "runout is a radius offset of a few µm to tens of µm; check the unit");
      if (std::abs(runout_m[j]) > 1e-3)
        throw InvalidArgument(fmt::format("CuttingConditions::runout_m[{}] = {:.6g} mm is implausibly large (over 1 mm)", j,
                                          runout_m[j] * 1e3),
                              "runout is a radius offset of a few µm to tens of µm; give it in metres");
    }
    if (!(feed_per_tooth_m > 0.0))
      throw InvalidArgument(fmt::format("CuttingConditions::feed_per_tooth_m {} m must be positive with runout",
                                        feed_per_tooth_m),
                            "with runout, which tooth cuts which surface depends on the feed");
  }
  check_helix(*this);
  if (pitch_rad.empty()) return;
  if (static_cast<int>(pitch_rad.size()) != teeth)
    throw InvalidArgument(fmt::format("CuttingConditions::pitch_rad has {} angles for {} teeth", pitch_rad.size(), teeth),
                          "give one pitch angle per tooth (from each tooth to the next), or none for even spacing");
  double sum = 0.0;
  for (std::size_t j = 0; j < pitch_rad.size(); ++j) {
    if (!std::isfinite(pitch_rad[j]) || !(pitch_rad[j] > 0.0))
      throw InvalidArgument(
          fmt::format("CuttingConditions::pitch_rad[{}] = {:.6g}° must be positive", j, degrees_of(pitch_rad[j])));
    sum += pitch_rad[j];
  }
  if (std::abs(sum - 2.0 * kPi) > 1e-6)
    throw InvalidArgument(fmt::format("CuttingConditions::pitch_rad adds up to {:.6g}°, not a revolution (360°)",
                                      degrees_of(sum)),
                          "the pitch angles are the spacings between successive teeth round the tool");
}

bool CuttingConditions::uniform() const {
  for (double p : pitch_rad)
    if (std::abs(p - 2.0 * kPi / teeth) > 1e-12) return false;
  for (double r : runout_m)
    if (r != runout_m.front()) return false;  // the same offset on every tooth changes nothing
  for (double b : helix_rad)
    if (b != helix_rad.front()) return false;
  return true;
}

bool CuttingConditions::helical() const {
  return std::any_of(helix_rad.begin(), helix_rad.end(), [](double b) { return b != 0.0; });
}

double CuttingConditions::helix_of(int tooth) const {
  if (helix_rad.empty()) return 0.0;
  return helix_rad.size() == 1 ? helix_rad.front() : helix_rad[static_cast<std::size_t>(tooth)];
}

Eigen::Matrix2d directional_integral(double kr, double phi1, double phi2) {
  auto antiderivative = [kr](double p) {
    const double s = std::sin(2.0 * p), c = std::cos(2.0 * p);
    Eigen::Matrix2d f;
    f << 0.5 * (c - 2.0 * kr * p + kr * s), 0.5 * (-s - 2.0 * p + kr * c), 0.5 * (-s + 2.0 * p + kr * c),
        0.5 * (-c - 2.0 * kr * p - kr * s);
    return f;
  };
  return antiderivative(phi2) - antiderivative(phi1);
}

Eigen::Matrix2d directional_factors(const CuttingConditions& cutting) {
  return directional_integral(cutting.radial_ratio, cutting.engagement.entry_rad, cutting.engagement.exit_rad);
}

const std::vector<OptionField<CuttingConditions>>& cutting_fields() {
  using O = CuttingConditions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "teeth",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 1000.0,
        .help = "number of teeth N",
        .cli_name = "teeth",
        .plan_key = "teeth"},
       nullptr,
       [](O& o) -> int& { return o.teeth; }},
      {{.name = "tangential_coefficient",
        .kind = FieldKind::Real,
        .unit = "N/m²",
        .min = 0.0,
        .min_open = true,
        .help = "tangential cutting coefficient K_t, a specific cutting pressure (aluminium about 7e8, steel 2e9)",
        .cli_name = "kt",
        .plan_key = "tangential_coefficient",
        .plausible = &plausible::kCuttingCoefficient},
       [](O& o) -> double& { return o.tangential_coefficient; }},
      {{.name = "radial_ratio",
        .kind = FieldKind::Real,
        .min = 0.0,
        .help = "radial cutting coefficient as the ratio K_r = K_n/K_t (typically 0.2…0.6)",
        .cli_name = "kr",
        .plan_key = "radial_ratio",
        .plausible = &plausible::kRadialRatio},
       [](O& o) -> double& { return o.radial_ratio; }},
      // No cutter takes a centimetre per tooth: the top, as PlanOptions::feed_per_tooth_m.
      {{.name = "feed_per_tooth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .max = 0.01,
        .note = "0: not given",
        .help = "feed per tooth c, with runout (which tooth cuts which surface depends on it)",
        .cli_name = "feed",
        .cli_unit = "mm",
        .cli_per_unit = 1e3,
        .plausible = &plausible::kFeedPerTooth},
       [](O& o) -> double& { return o.feed_per_tooth_m; }},
      {{.name = "diameter_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: not given",
        .help = "tool diameter D, needed with process damping and a helix; checks the runout",
        .cli_name = "diameter",
        .cli_unit = "mm",
        .cli_per_unit = 1e3,
        .plausible = &plausible::kToolDiameter},
       [](O& o) -> double& { return o.diameter_m; }},
      // The range is the indentation coefficient's (Budak & Tunç 2009): a value in N/m² or N/mm
      // falls outside it.
      {{.name = "process_damping_n_per_m",
        .kind = FieldKind::Real,
        .unit = "N/m",
        .min = kProcessDampingMin,
        .max = kProcessDampingMax,
        .automatic = 0.0,
        .note = "0: none",
        .help = "process damping (indentation) coefficient C_i, not N/m² or N/mm: the flank adds damping C_i·b/V "
                "(b the depth, V = πDn/60); needs the diameter",
        .cli_name = "process-damping",
        .plan_key = "process_damping"},
       [](O& o) -> double& { return o.process_damping_n_per_m; }},
      {{.name = "helix_slices",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 200.0,
        .automatic = 0.0,
        .note = "0: 8",
        .help = "axial slices of a variable helix, each with its mid-height delays"},
       nullptr,
       [](O& o) -> int& { return o.helix_slices; }}};
  return fields;
}

void SpeedRange::check() const {
  check_fields(speed_range_fields(), *this, "SpeedRange");
  if (!(max_rpm > min_rpm))
    throw InvalidArgument(fmt::format("the spindle speed range {}:{} rpm is empty (SpeedRange::min_rpm and max_rpm must "
                                      "have min < max)",
                                      min_rpm, max_rpm),
                          "give SpeedRange::min_rpm and max_rpm with 0 < min < max, e.g. 5000 and 25000 rpm");
}

const std::vector<OptionField<SpeedRange>>& speed_range_fields() {
  using O = SpeedRange;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "min_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .min_open = true,
        .help = "the lowest spindle speed",
        .plan_key = "speed_min",
        .plausible = &plausible::kSpindleSpeedRpm},
       [](O& o) -> double& { return o.min_rpm; }},
      {{.name = "max_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .min_open = true,
        .help = "the highest spindle speed",
        .plan_key = "speed_max",
        .plausible = &plausible::kSpindleSpeedRpm},
       [](O& o) -> double& { return o.max_rpm; }},
      {{.name = "points",
        .kind = FieldKind::Integer,
        .min = 2.0,
        .max = 1e6,
        .help = "spindle speeds on the grid, both ends included",
        .cli_name = "speeds",
        .plan_key = "speed_points"},
       nullptr,
       [](O& o) -> int& { return o.points; }}};
  return fields;
}

std::vector<double> SpeedRange::values() const {
  check();
  std::vector<double> v(static_cast<std::size_t>(points));
  const double step = (max_rpm - min_rpm) / (points - 1);
  for (int i = 0; i < points; ++i) v[static_cast<std::size_t>(i)] = min_rpm + i * step;
  v.back() = max_rpm;
  return v;
}

// ---- Zero-order approximation ---------------------------------------------------------------

namespace {

// Whether the resonance peak at point k is a mode feeding energy in. Such a mode shows at its peak
// as G ≈ +iA over whatever else responds there, on every point of its half-power band: Im G is a
// large part of |G| — here at least a fifth (arg G beyond 11.5°) — and positive at the points
// beside the peak too. Noise on a raw measured FRF makes peaks of one point (a near-singular
// coupling throws a single value far out, its neighbours' Im G < 0), and peaks of |G| where a
// response dominated by its real part carries a slightly positive Im G (its phase bias: Im G ≈
// +0.01 |G| over a band of a raw SH11 coupled to a tool); neither is dissipation reversed.
bool feeds_energy(const FrfSeries& g, std::size_t k) {
  constexpr double kShare = 0.2;
  const Complex v = g.values[k];
  if (!(v.imag() > kShare * std::abs(v))) return false;
  return (k == 0 || g.values[k - 1].imag() > 0.0) && (k + 1 == g.size() || g.values[k + 1].imag() > 0.0);
}

}  // namespace

std::optional<PassivityViolation> passivity_violation(const FrfSeries& g) {
  double largest = 0.0;
  for (const Complex& v : g.values) largest = std::max(largest, std::abs(v));
  PassivityViolation out;
  std::optional<PassivityViolation> first;
  for (const Peak& p : find_peaks(g, PeakOptions{0.3})) {
    const Complex v = g.values[p.index];
    if (std::abs(v) < 0.01 * largest) continue;
    ++out.peaks;
    if (!feeds_energy(g, p.index)) continue;
    ++out.violating;
    if (!first) first = PassivityViolation{g.frequency_hz[p.index], v, std::abs(v) / largest, 0, 0};
  }
  if (!first) return std::nullopt;
  first->violating = out.violating;
  first->peaks = out.peaks;
  return first;
}

std::string PassivityViolation::describe(const std::string& what) const {
  const std::string where = fmt::format(
      "{}: Im G = {:.4g} > 0 at its resonance peak at {:.6g} Hz (|G| {:.0f} % of the largest; "
      "{} of its {} resonance peaks so): a direct receptance of a passive structure has "
      "Im G < 0 at every frequency in the e^{{iωt}} sign convention",
      what, value.imag(), frequency_hz, 100.0 * share, violating, peaks);
  return violating == peaks ? where +
                                  "; every peak shows it, as data in the conjugate convention e^{−iωt} or of the opposite "
                                  "sign do"
                            : where +
                                  "; the others do not, so the structure feeds energy in at this mode (negative "
                                  "damping, as a joint whose damping matrix is not positive definite gives): it is "
                                  "unstable at any depth of cut";
}

namespace {

// The zero-order lobes of non-passive data look like lobes (4× too deep for the example's
// conjugate), so they are refused.
void require_passive_point_frf(const FrfSeries& g, const std::string& what) {
  require_not_mobility(g, what);
  if (const auto v = passivity_violation(g))
    throw InputError(v->describe(what),
                     v->violating == v->peaks
                         ? "if the data use e^{−iωt} (some analysers), conjugate them (Im → −Im); if the response or force "
                           "direction was reversed, negate them; a cross FRF is not a direct one"
                         : "check the joint's damping (its matrix must be positive definite) and stiffness, or the "
                           "measurement at that frequency");
}

}  // namespace

void MillingFrfs::check(const std::string& x_name, const std::string& y_name) const {
  validate(xx, "G_xx", 2);
  require_passive_point_frf(xx, x_name);
  if (rigid_y && (yy || xy || yx))
    throw InvalidArgument("a tool rigid in y cannot also have y or cross FRFs", "drop the y/cross FRFs or MillingFrfs::rigid_y");
  if (yy) {
    validate(*yy, "G_yy", 2);
    require_passive_point_frf(*yy, y_name);
    require_same_grid(xx.frequency_hz, "G_xx", yy->frequency_hz, "G_yy");
  }
  if (xy.has_value() != yx.has_value())
    throw InputError("only one cross FRF given: G_xy and G_yx go together", "give both cross FRFs or neither");
  if (xy) {
    validate(*xy, "G_xy", 2);
    validate(*yx, "G_yx", 2);
    require_same_grid(xx.frequency_hz, "G_xx", xy->frequency_hz, "G_xy");
    require_same_grid(xx.frequency_hz, "G_xx", yx->frequency_hz, "G_yx");
  }
}

MillingFrfs modal_milling_frfs(const std::vector<Mode>& x_modes, const std::vector<Mode>& y_modes,
                               const std::vector<double>& frequency_hz) {
  MillingFrfs frfs;
  frfs.xx = modal_frf(x_modes, frequency_hz);
  if (y_modes.empty()) frfs.rigid_y = true;
  else frfs.yy = modal_frf(y_modes, frequency_hz);
  return frfs;
}

std::vector<double> modal_frequency_grid(const std::vector<Mode>& modes) {
  if (modes.empty()) throw InvalidArgument("a modal frequency grid needs at least one mode");
  std::vector<double> f;
  double lo = kInf, hi = 0.0;
  for (const Mode& m : modes) {
    m.check();
    const double z = std::max(m.damping_ratio, 1e-4), step = z * m.frequency_hz / 40.0;
    for (int i = -800; i <= 800; ++i) {
      const double v = m.frequency_hz + i * step;
      if (v > 0.0) f.push_back(v);
    }
    lo = std::min(lo, m.frequency_hz);
    hi = std::max(hi, m.frequency_hz);
  }
  const double a = std::log(0.3 * lo), b = std::log(3.0 * hi);
  for (int i = 0; i <= 400; ++i) f.push_back(std::exp(a + (b - a) * i / 400.0));
  std::sort(f.begin(), f.end());
  std::vector<double> out;
  for (double v : f)
    if (out.empty() || v > out.back() * (1.0 + 1e-12)) out.push_back(v);
  return out;
}

void ZeroOrderOptions::check() const {
  check_fields(zero_order_fields(), *this, "ZeroOrderOptions");
  speeds.check();
}

const std::vector<OptionField<ZeroOrderOptions>>& zero_order_fields() {
  using O = ZeroOrderOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "lobes",
        .kind = FieldKind::Integer,
        .min = 0.0,
        .max = 5000.0,
        .automatic = -1.0,
        .note = "−1: enough to cover the lowest speed",
        .help = "lobes k = 0…K",
        .cli_name = "lobes"},
       nullptr,
       [](O& o) -> int& { return o.lobes; }},
      {{.name = "max_depth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: keep all",
        .help = "lobe points deeper than this are left out",
        .cli_name = "max-depth",
        .cli_unit = "mm",
        .cli_per_unit = 1e3},
       [](O& o) -> double& { return o.max_depth_m; }}};
  return fields;
}

namespace {

// The FRFs' largest modulus as a power of two 2^g_exp: dividing by it (ldexp, exact even from
// subnormals) scales them to a largest modulus near 1, so that squared moduli neither overflow nor
// underflow whatever the units (μ scales with G, the depth as 1/G, the phase not).
int frf_scale_exponent(const MillingFrfs& frfs) {
  double g_max = 0.0;
  for (const FrfSeries* f :
       {&frfs.xx, frfs.yy ? &*frfs.yy : nullptr, frfs.xy ? &*frfs.xy : nullptr, frfs.yx ? &*frfs.yx : nullptr})
    if (f)
      for (const Complex& v : f->values) g_max = std::max(g_max, std::abs(v));
  if (!(g_max > 0.0) || !std::isfinite(g_max))
    throw NumericalError(fmt::format("the milling FRFs' largest modulus is {} m/N: no chatter is possible", g_max),
                         "check the FRF: a receptance in m/N that is not zero everywhere");
  return std::ilogb(g_max);
}

// The two eigenvalues μ of B = α G at one frequency (G scaled), ordered to continue `prev` (the
// previous frequency's, when `continue_prev`): det(I + ΛB) = 0 ⇔ μ = −1/Λ.
void milling_eigenvalues(const Eigen::Matrix2d& a, Complex gxx, Complex gyy, Complex gxy, Complex gyx, const Complex* prev,
                         Complex mu[2]) {
  const Complex b00 = a(0, 0) * gxx + a(0, 1) * gyx, b01 = a(0, 0) * gxy + a(0, 1) * gyy;
  const Complex b10 = a(1, 0) * gxx + a(1, 1) * gyx, b11 = a(1, 0) * gxy + a(1, 1) * gyy;
  const Complex half_tr = 0.5 * (b00 + b11), det = b00 * b11 - b01 * b10;
  const Complex disc = std::sqrt(half_tr * half_tr - det);
  // The larger root directly, the smaller one as det/larger: no cancellation (and exactly 0
  // when det B = 0, the 1-DOF case).
  // (Squared moduli throughout: comparisons need no square roots.)
  const Complex big = std::norm(half_tr + disc) >= std::norm(half_tr - disc) ? half_tr + disc : half_tr - disc;
  mu[0] = big;
  mu[1] = big != 0.0 ? det / big : Complex(0.0);
  if (prev && std::norm(mu[0] - prev[0]) + std::norm(mu[1] - prev[1]) > std::norm(mu[0] - prev[1]) + std::norm(mu[1] - prev[0]))
    std::swap(mu[0], mu[1]);  // keep each root on its own continuous branch
}

// The depth a_lim [m] and phase ε/2π of root μ (scaled by 2^−g_exp): false where it gives no
// positive depth (a vanishing root, |μ|² ≤ 1e-24 scale2, or Λ_R ≥ 0); `out_of_range` set where
// the depth does not fit in a double.
bool root_depth(Complex mu, double scale2, double nkt, int g_exp, double& depth, double& phase, bool& out_of_range) {
  if (!(std::norm(mu) > 1e-24 * scale2)) return false;  // |μ| ≤ 1e-12 max|μ|: a vanishing root
  const Complex lam = -1.0 / mu;
  if (!(lam.real() < 0.0)) return false;  // Λ_R ≥ 0: no positive depth from this root here
  depth = std::ldexp(-2.0 * kPi * std::norm(lam) / (lam.real() * nkt), -g_exp);
  if (!std::isfinite(depth)) {
    out_of_range = true;
    return false;
  }
  phase = std::atan2(-lam.real(), -lam.imag()) / kPi;  // ε/2π, ε = 2 atan2(−Λ_R, −Λ_I)
  return true;
}

// The conditions the zero-order method accepts. Throws InvalidArgument.
void check_zero_order_conditions(const CuttingConditions& cutting) {
  cutting.check();
  if (cutting.process_damping_n_per_m > 0.0)
    throw InvalidArgument("CuttingConditions::process_damping_n_per_m: the zero-order method has no process damping",
                          "use the time-domain (full-discretization) method");
  // Its averaged directional matrix is the same with a helix (the lag only shifts A(φ(t)) in
  // time): it would silently leave the helix out.
  if (cutting.helical())
    throw InvalidArgument("CuttingConditions::helix_rad: the zero-order method averages the helix out",
                          "use the time-domain (full-discretization) method for a helix");
  if (!cutting.uniform())
    throw InvalidArgument(
        "CuttingConditions::pitch_rad or CuttingConditions::runout_m: the zero-order method assumes evenly spaced teeth "
        "without runout",
        "use the time-domain (full-discretization) method for a variable pitch or runout");
}

LobeTable zero_order_roots(const MillingFrfs& frfs, const CuttingConditions& cutting, int g_exp) {
  const Eigen::Matrix2d a = directional_factors(cutting);
  const double nkt = cutting.teeth * cutting.tangential_coefficient;
  const std::size_t n = frfs.xx.size();
  LobeTable t;
  t.chatter_hz = frfs.xx.frequency_hz;
  t.speed_factor.resize(n);
  for (std::size_t i = 0; i < n; ++i) t.speed_factor[i] = 60.0 * t.chatter_hz[i] / cutting.teeth;
  for (int r = 0; r < 2; ++r) {
    t.depth_m[r].assign(n, kNaN);
    t.phase[r].assign(n, kNaN);
  }
  bool out_of_range = false;  // a root with Λ_R < 0 whose depth does not fit in a double
  Complex prev[2] = {0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    auto scaled = [g_exp](Complex v) { return Complex(std::ldexp(v.real(), -g_exp), std::ldexp(v.imag(), -g_exp)); };
    const Complex gxx = scaled(frfs.xx.values[i]);
    const Complex gyy = frfs.rigid_y ? Complex(0.0) : frfs.yy ? scaled(frfs.yy->values[i]) : gxx;
    const Complex gxy = frfs.xy ? scaled(frfs.xy->values[i]) : Complex(0.0);
    const Complex gyx = frfs.yx ? scaled(frfs.yx->values[i]) : Complex(0.0);
    Complex mu[2];
    milling_eigenvalues(a, gxx, gyy, gxy, gyx, i > 0 ? prev : nullptr, mu);
    prev[0] = mu[0];
    prev[1] = mu[1];
    const double scale2 = std::max(std::norm(mu[0]), std::norm(mu[1]));
    for (int r = 0; r < 2; ++r) root_depth(mu[r], scale2, nkt, g_exp, t.depth_m[r][i], t.phase[r][i], out_of_range);
  }
  if (out_of_range) {
    bool any = false;
    for (int r = 0; r < 2; ++r)
      for (double d : t.depth_m[r]) any = any || std::isfinite(d);
    if (!any)
      throw NumericalError(fmt::format("the limiting depths lie beyond the range of double precision: the FRF's largest "
                                       "modulus is about {:.3g} m/N (a tool point receptance is typically 1e-8 to 1e-5 m/N)",
                                       std::ldexp(1.0, g_exp)),
                           "check the FRF's units and scale, and the cutting coefficient (N/m²)");
  }
  return t;
}

LobeTable zero_order_roots(const MillingFrfs& frfs, const CuttingConditions& cutting) {
  check_zero_order_conditions(cutting);
  frfs.check();
  return zero_order_roots(frfs, cutting, frf_scale_exponent(frfs));
}

struct Floor {
  double depth = kInf, chatter_hz = kNaN;
};

Floor find_floor(const LobeTable& t) {
  Floor fl;
  for (int r = 0; r < 2; ++r)
    for (std::size_t i = 0; i < t.chatter_hz.size(); ++i)
      if (t.depth_m[r][i] < fl.depth) fl = {t.depth_m[r][i], t.chatter_hz[i]};
  if (!std::isfinite(fl.depth))
    throw NumericalError("no chatter frequency of the FRF gives a positive limiting depth (Λ_R ≥ 0 everywhere)",
                         "check the FRF: a receptance in m/N with Im G ≤ 0 (e^{iωt} convention) around its resonances");
  return fl;
}

// Lowers the envelope with every segment of lobe k, root r: the lobe is a polyline in (speed,
// depth) through neighbouring grid frequencies, interpolated linearly in speed. Most segments are
// short and hold no envelope speed; they are told apart by the grid cell of their ends, computed in
// a branch-free (vectorised) pass.
void lower_envelope(const LobeTable& t, int k, int r, std::size_t i0, std::size_t i1, double n_min, double dn,
                    std::vector<EnvelopePoint>& env, std::vector<double>& speed, std::vector<int>& cell) {
  const double* a = t.speed_factor.data();
  const double* ph = t.phase[r].data();
  const double* d = t.depth_m[r].data();
  const std::size_t n = i1 - i0;
  speed.resize(n);
  cell.resize(n);
  const double inv_dn = 1.0 / dn, last = static_cast<double>(env.size() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    speed[i] = a[i0 + i] / (ph[i0 + i] + k);  // NaN where the root gives no depth
    // floor((speed − n_min)/dn) clamped to −1…last+1 (NaN → −1): truncation of a value ≥ 0.
    // std::max(0.0, NaN) is 0.0 (std::max(NaN, 0.0) would be NaN, and casting NaN to int is UB).
    const double u = std::min(std::max(0.0, (speed[i] - n_min) * inv_dn + 1.0), last + 2.0);
    cell[i] = static_cast<int>(u) - 1;
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (cell[i] == cell[i - 1]) continue;  // no envelope speed strictly inside this segment
    const double s0 = speed[i - 1], s1 = speed[i];
    if (std::isnan(s0) || std::isnan(s1)) continue;
    const auto jl = static_cast<std::size_t>(std::min(cell[i - 1], cell[i]) + 1);
    const auto jh = static_cast<std::size_t>(std::min(std::max(cell[i - 1], cell[i]), static_cast<int>(last)));
    const double d0 = d[i0 + i - 1], d1 = d[i0 + i], slope = 1.0 / (s1 - s0);
    const double f0 = t.chatter_hz[i0 + i - 1], f1 = t.chatter_hz[i0 + i];
    for (std::size_t j = jl; j <= jh; ++j) {
      const double u = (env[j].speed_rpm - s0) * slope, dj = d0 + u * (d1 - d0);
      if (dj < env[j].depth_m) env[j] = {env[j].speed_rpm, dj, f0 + u * (f1 - f0), k};
    }
  }
}

}  // namespace

std::pair<std::size_t, std::size_t> lobe_window(const LobeTable& t, int teeth, int lobe, double min_rpm, double max_rpm) {
  const double f_lo = min_rpm * teeth * lobe / 60.0, f_hi = max_rpm * teeth * (lobe + 1) / 60.0;
  const auto& f = t.chatter_hz;
  auto i0 = static_cast<std::size_t>(std::lower_bound(f.begin(), f.end(), f_lo) - f.begin());
  auto i1 = static_cast<std::size_t>(std::upper_bound(f.begin(), f.end(), f_hi) - f.begin());
  return {i0 > 0 ? i0 - 1 : 0, std::min(i1 + 1, f.size())};
}

std::vector<LobePoint> ZeroOrderResult::points() const {
  std::vector<LobePoint> v;
  for_each_point([&](const LobePoint& p) { v.push_back(p); });
  return v;
}

double zero_order_floor(const MillingFrfs& frfs, const CuttingConditions& cutting, double* chatter_hz) {
  const Floor fl = find_floor(zero_order_roots(frfs, cutting));
  if (chatter_hz) *chatter_hz = fl.chatter_hz;
  return fl.depth;
}

namespace {

// The result's frame: floor, alpha, options, the lobe count K (automatic: covering speeds.min_rpm
// at every chatter frequency of `tables` whose depth is within 10× the floor), the grid's
// coarseness warning (counted in `floor_table`), and the envelope's speeds with no depth yet.
void frame_zero_order(ZeroOrderResult& res, const std::vector<const LobeTable*>& tables, const LobeTable& floor_table,
                      const Floor& fl, const CuttingConditions& cutting, const ZeroOrderOptions& options) {
  res.alpha = directional_factors(cutting);
  res.floor_depth_m = fl.depth;
  res.floor_chatter_hz = fl.chatter_hz;
  res.teeth = cutting.teeth;
  res.speeds = options.speeds;
  res.max_depth_m = options.max_depth_m;
  const double n_teeth = cutting.teeth, n_min = options.speeds.min_rpm;

  // Lobe k reaches down to 60 f/(N(k + 1)) rpm. Automatic K covers MIN at every chatter frequency
  // whose depth is within 10× the floor (the band that shapes the envelope).
  double f_band = fl.chatter_hz;
  for (const LobeTable* t : tables)
    for (int r = 0; r < 2; ++r)
      for (std::size_t i = 0; i < t->chatter_hz.size(); ++i)
        if (t->depth_m[r][i] <= 10.0 * fl.depth) f_band = std::max(f_band, t->chatter_hz[i]);
  std::size_t near = 0;
  for (int r = 0; r < 2; ++r)
    for (double d : floor_table.depth_m[r]) near += d <= 2.0 * fl.depth;
  const int needed = static_cast<int>(std::ceil(60.0 * f_band / (n_teeth * n_min)));
  if (options.lobes < 0) {
    res.lobes = std::min(needed, 2000);
    if (needed > 2000)
      res.warnings.push_back(fmt::format("{} lobes would be needed to reach {} rpm; computed 2000", needed, n_min));
  } else {
    res.lobes = options.lobes;
    if (res.lobes < needed)
      res.warnings.push_back(
          fmt::format("lobes 0…{} reach down to about {:.0f} rpm at {:.1f} Hz: slower speeds in the range "
                      "are not covered (ZeroOrderOptions::lobes {} or more)",
                      res.lobes, 60.0 * f_band / (n_teeth * (res.lobes + 1)), f_band, needed));
  }
  if (near < 5)
    res.warnings.push_back(
        fmt::format("only {} FRF point(s) near the critical chatter frequency {:.2f} Hz have a_lim within "
                    "2× the floor: the FRF grid is too coarse there and the lobes are inaccurate",
                    near, fl.chatter_hz));
  const std::vector<double> grid = options.speeds.values();
  res.envelope.resize(grid.size());
  for (std::size_t j = 0; j < grid.size(); ++j) res.envelope[j] = {grid[j], kInf, kNaN, -1};
}

void warn_uncovered(ZeroOrderResult& res) {
  const auto uncovered = std::count_if(res.envelope.begin(), res.envelope.end(),
                                       [](const EnvelopePoint& e) { return e.lobe < 0; });
  if (uncovered > 0)
    res.warnings.push_back(
        fmt::format("{} of {} envelope speeds are reached by no lobe (the FRF's frequency range or the "
                    "lobe count does not map there); they are left out",
                    uncovered, res.envelope.size()));
}

}  // namespace

ZeroOrderResult zero_order_lobes(const MillingFrfs& frfs, const CuttingConditions& cutting, const ZeroOrderOptions& options) {
  options.check();
  ZeroOrderResult res;
  res.table = zero_order_roots(frfs, cutting);
  const LobeTable& t = res.table;
  frame_zero_order(res, {&t}, t, find_floor(t), cutting, options);
  const double n_min = options.speeds.min_rpm, n_max = options.speeds.max_rpm;
  const double dn = res.envelope[1].speed_rpm - res.envelope[0].speed_rpm;
  std::vector<double> speed;
  std::vector<int> cell;
  for (int k = 0; k <= res.lobes; ++k) {
    const auto [i0, i1] = lobe_window(t, cutting.teeth, k, n_min, n_max);
    for (int r = 0; r < 2; ++r) lower_envelope(t, k, r, i0, i1, n_min, dn, res.envelope, speed, cell);
  }
  warn_uncovered(res);
  return res;
}

// ---- Zero-order lobes with speed-dependent dynamics -------------------------------------------

void SpeedDependentFrfs::check(const std::string& name) const {
  if (speed_rpm.empty() || speed_rpm.size() != frfs.size())
    throw InputError(fmt::format("{}: {} speed(s) for {} set(s) of FRFs: one set per speed, at least one", name, speed_rpm.size(),
                                 frfs.size()),
                     "give the FRFs at each speed of SpeedDependentFrfs::speed_rpm");
  for (std::size_t j = 0; j < speed_rpm.size(); ++j) {
    if (!(std::isfinite(speed_rpm[j]) && speed_rpm[j] >= 0.0) || (j > 0 && !(speed_rpm[j] > speed_rpm[j - 1])))
      throw InputError(fmt::format("{}: SpeedDependentFrfs::speed_rpm[{}] = {} rpm: speeds must be ≥ 0 and increase", name, j,
                                   speed_rpm[j]),
                       "list the speeds in increasing order");
    const std::string at = fmt::format("{} at {} rpm", name, speed_rpm[j]);
    frfs[j].check(at, at + " (y)");
    const MillingFrfs& a = frfs.front();
    const MillingFrfs& b = frfs[j];
    if (b.xx.frequency_hz != a.xx.frequency_hz || b.yy.has_value() != a.yy.has_value() || b.xy.has_value() != a.xy.has_value() ||
        b.rigid_y != a.rigid_y)
      throw InputError(
          fmt::format("{}: its frequency grid or the FRFs it holds (y, cross, rigid in y) differ from those at {} rpm", at,
                      speed_rpm.front()),
          "give every speed's FRFs on one grid, with the same entries");
  }
}

MillingFrfs SpeedDependentFrfs::at(double n) const {
  if (speed_rpm.size() == 1 || !(n > speed_rpm.front())) return frfs.front();
  if (n >= speed_rpm.back()) return frfs.back();
  const std::size_t j = static_cast<std::size_t>(std::upper_bound(speed_rpm.begin(), speed_rpm.end(), n) - speed_rpm.begin()) - 1;
  const double t = (n - speed_rpm[j]) / (speed_rpm[j + 1] - speed_rpm[j]);
  const auto lerp = [t](const FrfSeries& a, const FrfSeries& b) {
    FrfSeries c = a;
    for (std::size_t i = 0; i < c.size(); ++i) c.values[i] += t * (b.values[i] - a.values[i]);
    return c;
  };
  MillingFrfs g = frfs[j];
  const MillingFrfs& h = frfs[j + 1];
  g.xx = lerp(frfs[j].xx, h.xx);
  if (g.yy) g.yy = lerp(*frfs[j].yy, *h.yy);
  if (g.xy) g.xy = lerp(*frfs[j].xy, *h.xy);
  if (g.yx) g.yx = lerp(*frfs[j].yx, *h.yx);
  return g;
}

namespace {

// G(f_i; n) of speed-dependent FRFs, scaled by 2^−g_exp, with the interpolation of
// SpeedDependentFrfs::at (a + t(b − a): exactly a where the nodes agree).
struct SpeedFrfPoint {
  const SpeedDependentFrfs& s;
  int g_exp;
  void operator()(std::size_t i, double n, Complex g[4]) const {  // xx, yy, xy, yx
    std::size_t j = 0;
    double t = 0.0;
    if (s.speed_rpm.size() > 1 && n > s.speed_rpm.front()) {
      if (n >= s.speed_rpm.back()) j = s.speed_rpm.size() - 1;
      else {
        j = static_cast<std::size_t>(std::upper_bound(s.speed_rpm.begin(), s.speed_rpm.end(), n) - s.speed_rpm.begin()) - 1;
        t = (n - s.speed_rpm[j]) / (s.speed_rpm[j + 1] - s.speed_rpm[j]);
      }
    }
    const MillingFrfs& a = s.frfs[j];
    const MillingFrfs& b = s.frfs[t > 0.0 ? j + 1 : j];
    const auto value = [&](const FrfSeries& fa, const FrfSeries& fb) {
      Complex v = fa.values[i];
      if (t > 0.0) v += t * (fb.values[i] - fa.values[i]);
      return Complex(std::ldexp(v.real(), -g_exp), std::ldexp(v.imag(), -g_exp));
    };
    g[0] = value(a.xx, b.xx);
    g[1] = a.rigid_y ? Complex(0.0) : a.yy ? value(*a.yy, *b.yy) : g[0];
    g[2] = a.xy ? value(*a.xy, *b.xy) : Complex(0.0);
    g[3] = a.yx ? value(*a.yx, *b.yx) : Complex(0.0);
  }
};

// The floor of speed-dependent FRFs: each node's lobe table (on one scale 2^g_exp for every node,
// so that the points of all speeds are computed alike) and the node whose floor is lowest.
struct NodeTables {
  int g_exp = std::numeric_limits<int>::min();
  std::vector<LobeTable> tables;
  Floor floor;
  std::size_t floor_node = 0;
};

NodeTables node_tables(const SpeedDependentFrfs& frfs, const CuttingConditions& cutting) {
  NodeTables nt;
  for (const MillingFrfs& f : frfs.frfs) nt.g_exp = std::max(nt.g_exp, frf_scale_exponent(f));
  for (std::size_t j = 0; j < frfs.frfs.size(); ++j) {
    nt.tables.push_back(zero_order_roots(frfs.frfs[j], cutting, nt.g_exp));
    bool any = false;
    for (int r = 0; r < 2; ++r)
      for (double d : nt.tables.back().depth_m[r]) any = any || std::isfinite(d);
    if (!any) continue;
    const Floor f = find_floor(nt.tables.back());
    if (f.depth < nt.floor.depth) {
      nt.floor = f;
      nt.floor_node = j;
    }
  }
  if (!std::isfinite(nt.floor.depth)) find_floor(nt.tables.front());  // throws: no positive depth anywhere
  return nt;
}

// The roots at every node and frequency, labelled continuously: along the frequencies at the
// first node (zero_order_lobes' labels), then along the nodes at each frequency; their phases.
// evaluate() gives root r at frequency i and speed n (between nodes j and j + 1, or at j): its
// depth and the speed its phase gives, sf/(φ + k). False where it gives no depth.
struct NodeRoots {
  SpeedFrfPoint frf_at;
  const LobeTable& t0;
  const std::vector<double>& nodes;
  Eigen::Matrix2d a;
  double nkt;
  std::size_t nn, nf;
  std::vector<Complex> mu;
  std::vector<double> phase;

  NodeRoots(const SpeedDependentFrfs& frfs, int g_exp, const LobeTable& table, const Eigen::Matrix2d& alpha, double nkt_)
      : frf_at{frfs, g_exp},
        t0(table),
        nodes(frfs.speed_rpm),
        a(alpha),
        nkt(nkt_),
        nn(nodes.size()),
        nf(t0.chatter_hz.size()),
        mu(nn * nf * 2),
        phase(nn * nf * 2, kNaN) {
    Complex g[4];
    for (std::size_t j = 0; j < nn; ++j)
      for (std::size_t i = 0; i < nf; ++i) {
        frf_at(i, nodes[j], g);
        const Complex* prev = j > 0 ? &mu[((j - 1) * nf + i) * 2] : i > 0 ? &mu[(j * nf + i - 1) * 2] : nullptr;
        Complex* m = &mu[(j * nf + i) * 2];
        milling_eigenvalues(a, g[0], g[1], g[2], g[3], prev, m);
        const double scale2 = std::max(std::norm(m[0]), std::norm(m[1]));
        bool out_of_range = false;
        for (int r = 0; r < 2; ++r) {
          double d = kNaN;
          root_depth(m[r], scale2, nkt, frf_at.g_exp, d, phase[(j * nf + i) * 2 + r], out_of_range);
        }
      }
  }

  bool evaluate(std::size_t i, int r, std::size_t j, double n, int k, double& depth, double& speed_out) const {
    Complex g[4], m[2];
    frf_at(i, n, g);
    milling_eigenvalues(a, g[0], g[1], g[2], g[3], &mu[(j * nf + i) * 2], m);
    const double scale2 = std::max(std::norm(m[0]), std::norm(m[1]));
    double ph = kNaN;
    bool out_of_range = false;
    if (!root_depth(m[r], scale2, nkt, frf_at.g_exp, depth, ph, out_of_range)) return false;
    speed_out = t0.speed_factor[i] / (ph + k);
    return true;
  }
};

// The points of lobe k, root r at frequency i: the zeros of F(n) = sf/(φ(n) + k) − n; at the
// nodes from their phases, beyond the end nodes linear (the FRF held there). Zeros bracketed by a
// sign change (0 counts as negative) between nodes where the root gives a depth. add(n, depth) takes
// each point, slowest first; `unsettled` counts the brackets whose speed did not settle.
template <class Add>
void lobe_points_at(const NodeRoots& nr, std::size_t i, int r, int k, Add&& add, std::size_t& unsettled) {
  const std::vector<double>& nodes = nr.nodes;
  const std::size_t nn = nr.nn, nf = nr.nf;
  const double sf = nr.t0.speed_factor[i];
  const auto F = [&](std::size_t j) {
    const double ph = nr.phase[(j * nf + i) * 2 + r];
    return sf / (ph + k) - nodes[j];
  };
  const auto evaluate = [&](std::size_t j, double n, double& depth, double& speed_out) {
    return nr.evaluate(i, r, j, n, k, depth, speed_out);
  };
  double d = kNaN, n_out = kNaN;
  const double f0 = F(0);
  if (std::isfinite(f0) && !(f0 > 0.0) && evaluate(0, nodes[0] + f0, d, n_out)) add(n_out, d);
  for (std::size_t j = 0; j + 1 < nn; ++j) {
    double fa = F(j), fb = F(j + 1), lo = nodes[j], hi = nodes[j + 1];
    if (std::isfinite(fa) != std::isfinite(fb)) {
      // The root gains (or loses) its depth between the nodes: the bracket starts where it
      // has one, found by bisection (to 1e-9 of the interval).
      double with = std::isfinite(fa) ? lo : hi, without = std::isfinite(fa) ? hi : lo, fw = std::isfinite(fa) ? fa : fb;
      for (int it = 0; it < 30; ++it) {
        const double mid = 0.5 * (with + without);
        if (evaluate(j, mid, d, n_out)) {
          with = mid;
          fw = n_out - mid;
        } else {
          without = mid;
        }
      }
      if (std::isfinite(fa)) {
        hi = with;
        fb = fw;
      } else {
        lo = with;
        fa = fw;
      }
    }
    if (!std::isfinite(fa) || !std::isfinite(fb) || (fa > 0.0) == (fb > 0.0)) continue;
    // Regula falsi (Illinois) in [lo, hi] on F with the interpolated FRF.
    double flo = fa, fhi = fb;
    bool settled = false;
    int side = 0;
    for (int it = 0; it < 60; ++it) {
      const double n = flo == fhi ? 0.5 * (lo + hi) : lo - flo * (hi - lo) / (fhi - flo);
      if (!evaluate(j, n, d, n_out)) break;  // the root loses its depth inside: no point
      const double fn = n_out - n;
      if (std::abs(fn) <= 1e-10 * n || hi - lo <= 1e-12 * hi) {
        settled = true;
        break;
      }
      if ((fn > 0.0) == (flo > 0.0)) {
        lo = n;
        flo = fn;
        if (side == -1) fhi *= 0.5;
        side = -1;
      } else {
        hi = n;
        fhi = fn;
        if (side == 1) flo *= 0.5;
        side = 1;
      }
    }
    if (settled) add(n_out, d);
    else ++unsettled;
  }
  const double f_last = F(nn - 1);
  if (std::isfinite(f_last) && f_last > 0.0 && evaluate(nn - 1, nodes[nn - 1] + f_last, d, n_out)) add(n_out, d);
}

// Every lobe's points into res.solved_points (by lobe, root, sheet, frequency), with warnings for
// the points that did not settle or fold back in speed more than the sheets hold.
void solve_lobe_points(const NodeRoots& nr, int teeth, double n_min, double n_max, ZeroOrderResult& res) {
  const LobeTable& t0 = nr.t0;
  constexpr int kSheets = 4;  // solutions per lobe, root and frequency kept (a lobe folding back in speed)
  std::size_t unsettled = 0, dropped = 0;
  std::vector<double> speed[2][kSheets], depth[2][kSheets];
  std::vector<int> count[2];
  for (int k = 0; k <= res.lobes; ++k) {
    // Lobe k's window: its speed factor bounds it (phase in (0, 1)) whatever the node.
    // (Not a structured binding: the lambdas below use the bounds, which clang 14 cannot capture.)
    const std::pair<std::size_t, std::size_t> window = lobe_window(t0, teeth, k, n_min, n_max);
    const std::size_t i0 = window.first, i1 = window.second;
    for (int r = 0; r < 2; ++r) {
      for (int q = 0; q < kSheets; ++q) {
        speed[r][q].assign(i1 - i0, kNaN);
        depth[r][q].assign(i1 - i0, kNaN);
      }
      count[r].assign(i1 - i0, 0);
    }
    for (std::size_t i = i0; i < i1; ++i)
      for (int r = 0; r < 2; ++r) {
        auto add = [&](double n, double d) {
          int& c = count[r][i - i0];
          if (c < kSheets) {
            speed[r][c][i - i0] = n;
            depth[r][c][i - i0] = d;
          } else {
            ++dropped;
          }
          ++c;
        };
        lobe_points_at(nr, i, r, k, add, unsettled);
      }
    for (int r = 0; r < 2; ++r)
      for (int q = 0; q < kSheets; ++q)
        for (std::size_t i = i0; i < i1; ++i)
          if (std::isfinite(speed[r][q][i - i0]))
            res.solved_points.push_back(LobePoint{k, r, speed[r][q][i - i0], depth[r][q][i - i0], t0.chatter_hz[i]});
  }
  if (unsettled > 0)
    res.warnings.push_back(fmt::format(
        "{} lobe point(s) left out: the speed of each point (where the FRF at that speed gives its phase) did not settle "
        "in 60 steps between two speeds of the FRFs",
        unsettled));
  if (dropped > 0)
    res.warnings.push_back(
        fmt::format("{} lobe point(s) left out: a lobe folds back in speed more than {} times at one "
                    "chatter frequency (only the {} slowest points are kept)",
                    dropped, kSheets, kSheets));
}

// The envelope at each speed n: the lobes of the FRF at n (interpolated), read at n, as
// zero_order_lobes reads the lobes of its one FRF. The floor: the lowest of those FRFs' and
// the nodes'.
void speed_dependent_envelope(const SpeedDependentFrfs& frfs, const CuttingConditions& cutting, int g_exp,
                              const ParallelOptions& parallel, ZeroOrderResult& res) {
  const double dn = res.envelope[1].speed_rpm - res.envelope[0].speed_rpm;
  std::vector<Floor> floors(res.envelope.size());
  parallel_for(res.envelope.size(), parallel, [&](std::size_t e) {
    const double n = res.envelope[e].speed_rpm;
    const LobeTable t = zero_order_roots(frfs.at(n), cutting, g_exp);
    std::vector<EnvelopePoint> env{res.envelope[e]};
    std::vector<double> sp;
    std::vector<int> cl;
    for (int k = 0; k <= res.lobes; ++k) {
      const auto [i0, i1] = lobe_window(t, cutting.teeth, k, n, n);
      for (int r = 0; r < 2; ++r) lower_envelope(t, k, r, i0, i1, n, dn, env, sp, cl);
    }
    res.envelope[e] = env[0];
    for (int r = 0; r < 2; ++r)
      for (std::size_t i = 0; i < t.chatter_hz.size(); ++i)
        if (t.depth_m[r][i] < floors[e].depth) floors[e] = {t.depth_m[r][i], t.chatter_hz[i]};
  });
  for (const Floor& f : floors)
    if (f.depth < res.floor_depth_m) {
      res.floor_depth_m = f.depth;
      res.floor_chatter_hz = f.chatter_hz;
    }
}

}  // namespace

ZeroOrderResult zero_order_lobes(const SpeedDependentFrfs& frfs, const CuttingConditions& cutting,
                                 const ZeroOrderOptions& options, const ParallelOptions& parallel) {
  options.check();
  check_zero_order_conditions(cutting);
  frfs.check();
  const NodeTables nt = node_tables(frfs, cutting);
  std::vector<const LobeTable*> table_ptrs;
  for (const LobeTable& t : nt.tables) table_ptrs.push_back(&t);
  ZeroOrderResult res;
  frame_zero_order(res, table_ptrs, nt.tables[nt.floor_node], nt.floor, cutting, options);
  res.table = nt.tables.front();
  const NodeRoots roots(frfs, nt.g_exp, res.table, res.alpha, cutting.teeth * cutting.tangential_coefficient);
  solve_lobe_points(roots, cutting.teeth, options.speeds.min_rpm, options.speeds.max_rpm, res);
  speed_dependent_envelope(frfs, cutting, nt.g_exp, parallel, res);
  warn_uncovered(res);
  return res;
}

// ---- Time-domain stability: full-discretization ----------------------------------------------

void ModalModel::check() const {
  if (x.empty())
    throw InvalidArgument("ModalModel::x is empty: the modal model needs at least one mode in x",
                          "give the x modes (mass, damping ratio, natural frequency) or an FRF to fit them from");
  for (std::size_t i = 0; i < x.size() + y.size(); ++i) {
    const bool in_x = i < x.size();
    const Mode& m = in_x ? x[i] : y[i - x.size()];
    const std::string what = fmt::format("{} mode {}", in_x ? "x" : "y", in_x ? i + 1 : i - x.size() + 1);
    m.check(what);
    if (!(m.damping_ratio > 0.0))
      throw InvalidArgument(fmt::format("{}: damping ratio 0 (undamped): every depth is at best marginally stable", what),
                            "give the measured or fitted damping ratio (> 0)");
  }
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const ResidueTerm& c = terms[i];
    const std::string what = fmt::format("ModalModel::terms[{}]", i);
    if (c.to < 0 || c.to > 1 || c.from < 0 || c.from > 1)
      throw InvalidArgument(fmt::format("{}: to {} and from {} must each be 0 (x) or 1 (y)", what, c.to, c.from));
    if (y.empty() && (c.to == 1 || c.from == 1))
      throw InvalidArgument(what + ": the term reads or drives y, but ModalModel::y is empty (rigid in y)",
                            "give the y modes, or drop the term");
    if (!std::isfinite(c.pole.real()) || !std::isfinite(c.pole.imag()) || !(c.pole.real() < 0.0))
      throw InvalidArgument(fmt::format("{}: pole {}{:+}i rad/s must be finite with a negative real part (a damped mode)", what,
                                        c.pole.real(), c.pole.imag()));
    if (!std::isfinite(c.residue.real()) || !std::isfinite(c.residue.imag()))
      throw InvalidArgument(fmt::format("{}: residue must be finite", what));
  }
}

const char* to_string(BoundaryKind kind) {
  switch (kind) {
    case BoundaryKind::Hopf: return "hopf";
    case BoundaryKind::Flip: return "flip";
    case BoundaryKind::Fold: return "fold";
    case BoundaryKind::None: break;
  }
  return "none";
}

namespace {

// ½K_t A(φ) of one tooth at φ (the header's matrix), zero outside the engagement.
Eigen::Matrix2d tooth_matrix(const CuttingConditions& cutting, double phi) {
  phi = std::fmod(phi, 2.0 * kPi);
  if (phi < 0.0) phi += 2.0 * kPi;
  if (phi < cutting.engagement.entry_rad || phi > cutting.engagement.exit_rad) return Eigen::Matrix2d::Zero();
  const double kr = cutting.radial_ratio, s2 = std::sin(2.0 * phi), c2 = std::cos(2.0 * phi);
  Eigen::Matrix2d a;
  a << -s2 - kr * (1.0 - c2), -(1.0 + c2) - kr * s2, (1.0 - c2) - kr * s2, s2 - kr * (1.0 + c2);
  return 0.5 * cutting.tangential_coefficient * a;
}

// Which surface tooth j cuts at angle φ, with runout (simulation.hpp's chip, linearised about
// the static cut): the surface left q pitches back (q = 1…N, angle Θ_q after tooth j − q) lies
// at ρ_{j−q} − C_q sin φ, C_q = N c Θ_q/2π the feed since; tooth j cuts the outermost one, q*, if
// its static chip h = ρ_j − ρ_{j−q*} + C_{q*} sin φ is positive, and then regenerates against
// r(t − Θ_{q*}/Ω). Without runout q* = 1 (the tooth ahead) wherever the tooth is engaged.
struct ToothGeometry {
  int teeth = 0;
  std::vector<double> lag;     // tooth j at φ_j = Ωt − lag_j [rad]
  std::vector<double> back;    // Θ_{j,q} at [j·N + q − 1]: the angle from tooth j − q to tooth j [rad]
  std::vector<double> runout;  // ρ_j [m] (empty: none)
  double per_rev = 0.0;        // N c [m]

  // q* (1…N) and the static chip [m] (h ≤ 0: out of the cut, q* = 0).
  std::pair<int, double> reference(int j, double sin_phi) const {
    if (runout.empty()) return {1, per_rev * back[static_cast<std::size_t>(j * teeth)] / (2.0 * kPi) * sin_phi};
    int best = 0;
    double surface = -kInf;
    for (int q = 1; q <= teeth; ++q) {
      const double v = runout[static_cast<std::size_t>((j - q + teeth * 2) % teeth)] -
                       per_rev * back[static_cast<std::size_t>(j * teeth + q - 1)] / (2.0 * kPi) * sin_phi;
      if (v > surface) {
        surface = v;
        best = q;
      }
    }
    const double h = runout[static_cast<std::size_t>(j)] - surface;
    return h > 0.0 ? std::pair<int, double>{best, h} : std::pair<int, double>{0, h};
  }
};

// The teeth of `cutting` (no helix) with a feed per tooth c (the runout's if it has one): tooth j
// lags tooth 0 by the pitches before it, and the angle back to tooth j − q is the q pitches before it.
ToothGeometry tooth_geometry(const CuttingConditions& cutting, double feed_per_tooth_m) {
  const int teeth = cutting.teeth;
  const auto nt = static_cast<std::size_t>(teeth);
  std::vector<double> pitch = cutting.pitch_rad;
  if (pitch.empty()) pitch.assign(nt, 2.0 * kPi / teeth);
  ToothGeometry g;
  g.teeth = teeth;
  g.lag.assign(nt, 0.0);
  for (std::size_t j = 1; j < nt; ++j) g.lag[j] = g.lag[j - 1] + pitch[j - 1];
  g.back.assign(nt * nt, 0.0);
  for (int j = 0; j < teeth; ++j) {
    double angle = 0.0;
    for (int q = 1; q <= teeth; ++q) {
      angle += pitch[static_cast<std::size_t>((j - q + teeth) % teeth)];
      g.back[static_cast<std::size_t>(j * teeth + q - 1)] = q == teeth ? 2.0 * kPi : angle;
    }
  }
  g.runout = cutting.runout_m;
  g.per_rev = teeth * (g.runout.empty() ? feed_per_tooth_m : cutting.feed_per_tooth_m);
  return g;
}

// The angles in [φ_st, φ_ex] where tooth j's cut can change: entry and exit, and with runout
// where q* changes or the static chip reaches zero (sin φ = Δρ/ΔC: both roots φ and π − φ; extra
// angles are harmless).
std::vector<double> cut_changes(const ToothGeometry& g, int j, const Engagement& e) {
  const int teeth = g.teeth;
  std::vector<double> at = {e.entry_rad, e.exit_rad};
  for (int q = 1; q <= (g.runout.empty() ? 0 : teeth); ++q) {
    auto rho = [&](int back) { return g.runout[static_cast<std::size_t>((j - back + 2 * teeth) % teeth)]; };
    auto feed = [&](int back) { return g.per_rev * g.back[static_cast<std::size_t>(j * teeth + back - 1)] / (2.0 * kPi); };
    std::vector<std::pair<double, double>> pairs = {{rho(q) - g.runout[static_cast<std::size_t>(j)], feed(q)}};
    for (int r = q + 1; r <= teeth; ++r) pairs.push_back({rho(q) - rho(r), feed(q) - feed(r)});
    for (const auto& [num, den] : pairs) {
      if (den == 0.0) continue;
      const double sv = num / den;
      if (sv <= 0.0 || sv >= 1.0) continue;
      for (double phi : {std::asin(sv), kPi - std::asin(sv)})
        if (phi > e.entry_rad && phi < e.exit_rad) at.push_back(phi);
    }
  }
  return at;
}

// The revolution-period terms of milling_delay_system (its header comment): P sums the teeth in
// the cut; one delayed term per distinct angle Θ_q, whose coefficient holds the teeth that cut the
// surface q pitches back at that moment.
void add_revolution_terms(PeriodicDelaySystem& sys, const CuttingConditions& cutting, double speed_rpm, double feed_per_tooth_m,
                          int d) {
  const int teeth = cutting.teeth;
  const double spin = rad_s_of_rpm(speed_rpm);
  sys.period = 60.0 / speed_rpm;
  sys.regenerative = false;
  const ToothGeometry g = tooth_geometry(cutting, feed_per_tooth_m);
  // φ in [0, 2π) of tooth j at t, and whether it is engaged.
  auto angle_of = [lag = g.lag, spin](int j, double t) {
    double phi = std::fmod(spin * t - lag[static_cast<std::size_t>(j)], 2.0 * kPi);
    return phi < 0.0 ? phi + 2.0 * kPi : phi;
  };
  const Engagement e = cutting.engagement;
  auto engaged = [e](double phi) { return phi >= e.entry_rad && phi <= e.exit_rad; };
  sys.current = [cutting, g, angle_of, engaged, d](double t, Eigen::MatrixXd& out) {
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    for (int j = 0; j < g.teeth; ++j) {
      const double phi = angle_of(j, t);
      if (engaged(phi) && g.reference(j, std::sin(phi)).first > 0) sum += tooth_matrix(cutting, phi);
    }
    out = sum.topLeftCorner(d, d);
  };
  // Distinct angles Θ (within 1e-12 rad), each with the (j, q) that reach back by it. Without
  // runout only q = 1 is ever cut.
  std::vector<double> angles;
  std::vector<std::vector<std::pair<int, int>>> users;
  for (int j = 0; j < teeth; ++j)
    for (int q = 1; q <= (g.runout.empty() ? 1 : teeth); ++q) {
      const double th = g.back[static_cast<std::size_t>(j * teeth + q - 1)];
      std::size_t k = 0;
      while (k < angles.size() && std::abs(angles[k] - th) > 1e-12) ++k;
      if (k == angles.size()) {
        angles.push_back(th);
        users.emplace_back();
      }
      users[k].push_back({j, q});
    }
  for (std::size_t k = 0; k < angles.size(); ++k)
    sys.delays.push_back({angles[k] / spin, [cutting, g, angle_of, engaged, d, use = users[k]](double t, Eigen::MatrixXd& out) {
                            Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
                            for (const auto& [j, q] : use) {
                              const double phi = angle_of(j, t);
                              if (engaged(phi) && g.reference(j, std::sin(phi)).first == q) sum -= tooth_matrix(cutting, phi);
                            }
                            out = sum.topLeftCorner(d, d);
                          }});
  if (feed_per_tooth_m > 0.0) {
    const double kt = cutting.tangential_coefficient, kr = cutting.radial_ratio;
    sys.forcing = [g, angle_of, engaged, kt, kr, d](double t, Eigen::VectorXd& out) {
      for (int j = 0; j < g.teeth; ++j) {
        const double phi = angle_of(j, t);
        if (!engaged(phi)) continue;
        const double s = std::sin(phi), c = std::cos(phi);
        const auto [q, h] = g.reference(j, s);
        if (q == 0) continue;
        const double ft = kt * h;
        out(0) += ft * (-c - kr * s);
        if (d == 2) out(1) += ft * (s - kr * c);
      }
    };
  }
  // Each tooth enters and leaves once per revolution; with runout also where q* changes or the
  // static chip reaches zero (sin φ = Δρ/ΔC: both roots φ and π − φ; extra breakpoints are harmless).
  for (int j = 0; j < teeth; ++j) {
    for (double angle : cut_changes(g, j, e)) {
      const double t = std::fmod(angle + g.lag[static_cast<std::size_t>(j)], 2.0 * kPi) / spin;
      if (t > 1e-12 * sys.period && t < sys.period * (1.0 - 1e-12)) sys.breakpoints.push_back(t);
    }
  }
}

}  // namespace

// The milling equation without process damping (milling_delay_system's header comment).
// The residue terms of a ModalModel as further blocks of A₀ (after the 2n_q modal states): z = u + iv,
// ż = λz + F_from gives [u̇; v̇] = [[Re λ, −Im λ], [Im λ, Re λ]] [u; v] + [F_from; 0], and the tip
// displacement y_to += 2 Re(R z) = 2 (Re R u − Im R v) (stability.hpp, ResidueTerm).
static void add_residue_terms(PeriodicDelaySystem& sys, const ModalModel& model) {
  if (model.terms.empty()) return;
  const Eigen::Index n0 = sys.input.rows(), n = n0 + 2 * static_cast<Eigen::Index>(model.terms.size());
  sys.input.conservativeResize(n, Eigen::NoChange);
  sys.output.conservativeResize(Eigen::NoChange, n);
  sys.input.bottomRows(n - n0).setZero();
  sys.output.rightCols(n - n0).setZero();
  for (std::size_t i = 0; i < model.terms.size(); ++i) {
    const ResidueTerm& c = model.terms[i];
    const Eigen::Index k = n0 + 2 * static_cast<Eigen::Index>(i);
    Eigen::MatrixXd block(2, 2);
    block << c.pole.real(), -c.pole.imag(), c.pole.imag(), c.pole.real();
    sys.a0_blocks.push_back(block);
    sys.input(k, c.from) = 1.0;
    sys.output(c.to, k) = 2.0 * c.residue.real();
    sys.output(c.to, k + 1) = -2.0 * c.residue.imag();
  }
}

static PeriodicDelaySystem cutting_forces_system(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm,
                                                 double feed_per_tooth_m) {
  if (!std::isfinite(feed_per_tooth_m) || feed_per_tooth_m < 0.0)
    throw InvalidArgument(fmt::format("feed per tooth {} m must be ≥ 0", feed_per_tooth_m));
  model.check();
  cutting.check();
  if (!std::isfinite(speed_rpm) || !(speed_rpm > 0.0))
    throw InvalidArgument(fmt::format("spindle speed {} rpm must be positive", speed_rpm));
  const int nx = static_cast<int>(model.x.size()), nq = nx + static_cast<int>(model.y.size());
  const int d = model.y.empty() ? 1 : 2;
  PeriodicDelaySystem sys;
  sys.input = Eigen::MatrixXd::Zero(2 * nq, d);
  sys.output = Eigen::MatrixXd::Zero(d, 2 * nq);
  for (int r = 0; r < nq; ++r) {
    const Mode& m = r < nx ? model.x[static_cast<std::size_t>(r)] : model.y[static_cast<std::size_t>(r - nx)];
    const double w = omega_of(m.frequency_hz);
    Eigen::MatrixXd block(2, 2);
    block << 0.0, 1.0, -w * w, -2.0 * m.damping_ratio * w;
    sys.a0_blocks.push_back(block);
    sys.input(2 * r + 1, r < nx ? 0 : 1) = 1.0 / m.mass_kg;
    sys.output(r < nx ? 0 : 1, 2 * r) = 1.0;
  }
  add_residue_terms(sys, model);
  if (!cutting.uniform()) {
    if (!cutting.runout_m.empty() && feed_per_tooth_m > 0.0 && std::abs(feed_per_tooth_m - cutting.feed_per_tooth_m) > 1e-12)
      throw InvalidArgument(
          fmt::format("feed per tooth {} m differs from CuttingConditions::feed_per_tooth_m {} m (the runout's)",
                      feed_per_tooth_m, cutting.feed_per_tooth_m));
    add_revolution_terms(sys, cutting, speed_rpm, feed_per_tooth_m, d);
    return sys;
  }
  const int teeth = cutting.teeth;
  const double spin = rad_s_of_rpm(speed_rpm), pitch = 2.0 * kPi / teeth;  // Ω [rad/s], tooth pitch [rad]
  sys.period = 60.0 / (teeth * speed_rpm);
  sys.regenerative = true;
  const double kt = cutting.tangential_coefficient, kr = cutting.radial_ratio;
  const double st = cutting.engagement.entry_rad, ex = cutting.engagement.exit_rad;
  // P(t) = ½K_t Σ_j g_j A(φ_j), φ_j = Ωt + 2πj/N (tooth 0 at φ = 0 when t = 0).
  sys.current = [=](double t, Eigen::MatrixXd& out) {
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    for (int j = 0; j < teeth; ++j) {
      const double phi = std::fmod(spin * t + j * pitch, 2.0 * kPi);
      if (phi < st || phi > ex) continue;
      const double s2 = std::sin(2.0 * phi), c2 = std::cos(2.0 * phi);
      sum(0, 0) += -s2 - kr * (1.0 - c2);
      sum(0, 1) += -(1.0 + c2) - kr * s2;
      sum(1, 0) += (1.0 - c2) - kr * s2;
      sum(1, 1) += s2 - kr * (1.0 + c2);
    }
    out = 0.5 * kt * sum.topLeftCorner(d, d);
  };
  // The static chip c sin φ_j of each tooth in the cut: per unit depth, F_t = K_t c sin φ_j along
  // (−cos φ, sin φ) and F_r = K_r F_t along (−sin φ, −cos φ) (the A(φ) of the header with Δ = (c, 0)).
  if (feed_per_tooth_m > 0.0)
    sys.forcing = [=](double t, Eigen::VectorXd& out) {
      for (int j = 0; j < teeth; ++j) {
        const double phi = std::fmod(spin * t + j * pitch, 2.0 * kPi);
        if (phi < st || phi > ex) continue;
        const double s = std::sin(phi), c = std::cos(phi), ft = kt * feed_per_tooth_m * s;
        out(0) += ft * (-c - kr * s);
        if (d == 2) out(1) += ft * (s - kr * c);
      }
    };
  // Within one tooth period each of the evenly spaced teeth enters and leaves once in turn: the
  // cut changes at Ωt ≡ φ_st and φ_ex (mod the pitch).
  for (double angle : {st, ex}) {
    const double t = std::fmod(angle, pitch) / spin;
    if (t > 1e-12 * sys.period && t < sys.period * (1.0 - 1e-12)) sys.breakpoints.push_back(t);
  }
  return sys;
}

PeriodicDelaySystem milling_delay_system(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm,
                                         double feed_per_tooth_m) {
  if (cutting.helical())
    throw InvalidArgument("CuttingConditions::helix_rad: with a helix the milling equation depends on the depth",
                          "build it at a depth: milling_delay_system_at_depth");
  PeriodicDelaySystem sys = cutting_forces_system(model, cutting, speed_rpm, feed_per_tooth_m);
  const double ci = cutting.process_damping_n_per_m;
  if (!(ci > 0.0)) return sys;
  // Process damping: per engaged tooth −(C_i/V) u uᵀ ṙ per unit depth, u = (sin φ, cos φ) the
  // surface normal, V = πDn/60 the cutting speed.
  const Eigen::MatrixXd velocity = velocity_output(model);
  const int teeth = cutting.teeth, d = static_cast<int>(sys.output.rows());
  std::vector<double> lag(static_cast<std::size_t>(teeth), 0.0);
  for (std::size_t j = 1; j < lag.size(); ++j)
    lag[j] = lag[j - 1] + (cutting.pitch_rad.empty() ? 2.0 * kPi / teeth : cutting.pitch_rad[j - 1]);
  const double spin = rad_s_of_rpm(speed_rpm), speed = cutting_speed(cutting, speed_rpm);
  const Engagement e = cutting.engagement;
  return with_velocity_feedback(sys, velocity, [=](double t, Eigen::MatrixXd& out) {
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    for (double l : lag) {
      double phi = std::fmod(spin * t - l, 2.0 * kPi);
      if (phi < 0.0) phi += 2.0 * kPi;
      if (phi < e.entry_rad || phi > e.exit_rad) continue;
      const Eigen::Vector2d u(std::sin(phi), std::cos(phi));
      sum -= u * u.transpose();
    }
    out = ci / speed * sum.topLeftCorner(d, d);
  });
}

namespace {

// Integrals of 1, sin ψ, cos ψ, sin²ψ, sin ψ cos ψ, cos²ψ over angle pieces, each weighted: the
// closed forms written with the piece's mid-angle and half-width, so that a narrow piece keeps its
// precision (no difference of nearly equal cosines).
struct TrigMoments {
  double one = 0.0, s = 0.0, c = 0.0, ss = 0.0, sc = 0.0, cc = 0.0;
  void add(double lo, double hi, double w) {
    if (hi == lo) {  // a point (a straight flute): the integrand's value
      const double sn = std::sin(lo), cs = std::cos(lo);
      one += w;
      s += w * sn;
      c += w * cs;
      ss += w * sn * sn;
      sc += w * sn * cs;
      cc += w * cs * cs;
      return;
    }
    const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo), sh = std::sin(half), s2h = std::sin(2.0 * half);
    one += w * 2.0 * half;
    s += w * 2.0 * std::sin(mid) * sh;
    c += w * 2.0 * std::cos(mid) * sh;
    ss += w * (half - 0.5 * std::cos(2.0 * mid) * s2h);
    cc += w * (half + 0.5 * std::cos(2.0 * mid) * s2h);
    sc += w * 0.5 * s2h * std::sin(2.0 * mid);
  }
  // ½K_t ∫A(ψ)dψ (sin 2ψ = 2 sin cos, 1 − cos 2ψ = 2 sin², 1 + cos 2ψ = 2 cos²).
  Eigen::Matrix2d tooth(double kt, double kr) const {
    Eigen::Matrix2d a;
    a << -sc - kr * ss, -cc - kr * sc, ss - kr * sc, sc - kr * cc;
    return kt * a;
  }
  Eigen::Matrix2d normal() const {  // ∫ u uᵀ dψ, u = (sin ψ, cos ψ)
    Eigen::Matrix2d a;
    a << ss, sc, sc, cc;
    return a;
  }
};

// The teeth of a helical cutter at one depth a, in `slices` slices of height a/slices: tooth j at
// height z is at φ_j(t) − κ_j z, φ_j(t) = Ωt − lag_j, so at slice l it covers the angles
// [φ_j − κ_j z_{l+1}, φ_j − κ_j z_l]. Each slice has the tooth geometry (angles back to the teeth
// ahead, hence delays and, with runout, the surface cut) of its mid-height.
struct HelixCut {
  int teeth = 0, slices = 1;
  double height = 0.0;  // of a slice [m]
  double spin = 0.0;    // Ω [rad/s]
  Engagement e;
  std::vector<double> kappa;                  // κ_j = tan β_j/R [rad/m]
  std::vector<ToothGeometry> slice;           // per slice (lag_j: tooth j at its mid-height, unused here)
  std::vector<double> lag;                    // lag_j at the tool tip [rad]
  std::vector<std::vector<double>> switches;  // [l·N + j]: angles in [0, 2π) where tooth j's cut can change, sorted

  // visit(lo, hi, q, w) for each engaged piece of tooth j's window at slice l at time t: q the
  // surface it cuts (0: out of the cut, q* of ToothGeometry), w = 1/(slices·width), so that Σ w∫
  // is the average over the depth; a window of zero width (κ_j = 0) is the point φ_j (lo = hi,
  // w = 1/slices).
  template <typename Visit>
  void pieces(int l, int j, double t, Visit&& visit) const {
    const auto ju = static_cast<std::size_t>(j);
    const double phi = spin * t - lag[ju];
    const double width = kappa[ju] * height, hi0 = phi - kappa[ju] * height * l, lo0 = hi0 - width;
    const double turn = std::floor(lo0 / (2.0 * kPi)) * 2.0 * kPi;
    const double lo = lo0 - turn, hi = hi0 - turn;  // lo in [0, 2π)
    // Most of the time a tooth is out of the cut (low immersion): no piece to visit.
    if ((hi < e.entry_rad || lo > e.exit_rad) && hi < e.entry_rad + 2.0 * kPi) return;
    const ToothGeometry& g = slice[static_cast<std::size_t>(l)];
    auto cut_at = [&](double psi) {
      psi = std::fmod(psi, 2.0 * kPi);
      if (psi < e.entry_rad || psi > e.exit_rad) return -1;
      return g.reference(j, std::sin(psi)).first;
    };
    if (!(width > 1e-12)) {
      const int q = cut_at(lo);
      if (q >= 0) visit(lo, lo, q, 1.0 / slices);
      return;
    }
    const double w = 1.0 / (slices * (hi - lo));  // the window as represented, so that the average is one of its values
    const std::vector<double>& sw = switches[static_cast<std::size_t>(l * teeth + j)];
    double a = lo;
    for (double shift = 0.0; a < hi; shift += 2.0 * kPi) {
      for (double angle : sw) {
        const double b = std::min(angle + shift, hi);
        if (b <= a) continue;
        const int q = cut_at(0.5 * (a + b));
        if (q >= 0) visit(a, b, q, w);
        a = b;
        if (a >= hi) break;
      }
      if (a < hi && a < shift + 2.0 * kPi) {  // past the last change of this turn
        const double b = std::min(shift + 2.0 * kPi, hi);
        const int q = cut_at(0.5 * (a + b));
        if (q >= 0) visit(a, b, q, w);
        a = b;
      }
    }
  }
};

HelixCut helix_cut(const CuttingConditions& cutting, double speed_rpm, double depth_m, double feed_per_tooth_m) {
  HelixCut h;
  h.teeth = cutting.teeth;
  h.spin = rad_s_of_rpm(speed_rpm);
  h.e = cutting.engagement;
  const double radius = 0.5 * cutting.diameter_m;
  for (int j = 0; j < h.teeth; ++j) h.kappa.push_back(std::tan(cutting.helix_of(j)) / radius);
  const bool variable = std::any_of(h.kappa.begin(), h.kappa.end(), [&](double k) { return k != h.kappa.front(); });
  h.slices = variable ? (cutting.helix_slices > 0 ? cutting.helix_slices : 8) : 1;
  h.height = depth_m / h.slices;
  const ToothGeometry tip = tooth_geometry(cutting, feed_per_tooth_m);
  h.lag = tip.lag;
  for (int l = 0; l < h.slices; ++l) {
    ToothGeometry g = tip;
    const double z = (l + 0.5) * h.height;
    for (int j = 0; j < h.teeth; ++j)
      for (int q = 1; q < h.teeth; ++q) {
        double& back = g.back[static_cast<std::size_t>(j * h.teeth + q - 1)];
        back += z * (h.kappa[static_cast<std::size_t>(j)] - h.kappa[static_cast<std::size_t>((j - q + h.teeth) % h.teeth)]);
        if (!(back > 0.0) || back > 2.0 * kPi)
          throw InvalidArgument(
              fmt::format("CuttingConditions::helix_rad: at {:.4g} mm above the tip tooth {} lies {:.4g}° behind tooth {} "
                          "(outside 0…360°): the helix angles differ too much for this depth",
                          z * 1e3, j, degrees_of(back), (j - q + h.teeth) % h.teeth),
              "give helix angles closer to each other, or a smaller depth");
      }
    std::vector<double> sw;
    for (int j = 0; j < h.teeth; ++j) {
      sw = cut_changes(g, j, h.e);
      std::sort(sw.begin(), sw.end());
      h.switches.push_back(sw);
    }
    h.slice.push_back(std::move(g));
  }
  return h;
}

}  // namespace

PeriodicDelaySystem milling_delay_system_at_depth(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm,
                                                  double depth_m, double feed_per_tooth_m) {
  if (!std::isfinite(depth_m) || depth_m < 0.0) throw InvalidArgument(fmt::format("axial depth {} m must be ≥ 0", depth_m));
  cutting.check();
  if (!cutting.helical()) return milling_delay_system(model, cutting, speed_rpm, feed_per_tooth_m);
  // The modal part (A₀, B, C) of the straight, evenly spaced tool; the cut's terms follow.
  CuttingConditions plain = cutting;
  plain.helix_rad.clear();
  plain.pitch_rad.clear();
  plain.runout_m.clear();
  plain.process_damping_n_per_m = 0.0;
  PeriodicDelaySystem sys = cutting_forces_system(model, plain, speed_rpm, 0.0);
  if (!cutting.runout_m.empty() && feed_per_tooth_m > 0.0 && std::abs(feed_per_tooth_m - cutting.feed_per_tooth_m) > 1e-12)
    throw InvalidArgument(fmt::format("feed per tooth {} m differs from CuttingConditions::feed_per_tooth_m {} m (the runout's)",
                                      feed_per_tooth_m, cutting.feed_per_tooth_m));
  const int d = static_cast<int>(sys.output.rows()), teeth = cutting.teeth;
  const bool tooth_period = cutting.uniform();  // every tooth alike: the map over one tooth period
  sys.period = 60.0 / speed_rpm / (tooth_period ? teeth : 1);
  sys.regenerative = tooth_period;
  sys.forcing = nullptr;
  sys.breakpoints.clear();
  const auto h = std::make_shared<const HelixCut>(helix_cut(cutting, speed_rpm, depth_m, feed_per_tooth_m));
  const double kt = cutting.tangential_coefficient, kr = cutting.radial_ratio;
  sys.current = [h, kt, kr, d](double t, Eigen::MatrixXd& out) {
    TrigMoments m;
    for (int l = 0; l < h->slices; ++l)
      for (int j = 0; j < h->teeth; ++j)
        h->pieces(l, j, t, [&](double lo, double hi, int q, double w) {
          if (q > 0) m.add(lo, hi, w);
        });
    out = m.tooth(kt, kr).topLeftCorner(d, d);
  };
  if (!tooth_period) {
    // One delayed term per distinct angle back (within 1e-12 rad), holding the (slice, tooth, q)
    // that reach back by it; without runout only q = 1 is ever cut.
    struct User {
      int l, j, q;
    };
    std::vector<double> angles;
    std::vector<std::vector<User>> users;
    for (int l = 0; l < h->slices; ++l)
      for (int j = 0; j < teeth; ++j)
        for (int q = 1; q <= (cutting.runout_m.empty() ? 1 : teeth); ++q) {
          const double th = h->slice[static_cast<std::size_t>(l)].back[static_cast<std::size_t>(j * teeth + q - 1)];
          std::size_t k = 0;
          while (k < angles.size() && std::abs(angles[k] - th) > 1e-12) ++k;
          if (k == angles.size()) {
            angles.push_back(th);
            users.emplace_back();
          }
          users[k].push_back({l, j, q});
        }
    for (std::size_t k = 0; k < angles.size(); ++k)
      sys.delays.push_back({angles[k] / h->spin, [h, kt, kr, d, use = users[k]](double t, Eigen::MatrixXd& out) {
                              TrigMoments m;
                              for (const User& u : use)
                                h->pieces(u.l, u.j, t, [&](double lo, double hi, int q, double w) {
                                  if (q == u.q) m.add(lo, hi, w);
                                });
                              out = -m.tooth(kt, kr).topLeftCorner(d, d);
                            }});
  }
  // The static chip h = ρ_j − ρ_{j−q} + C_q sin ψ (C_q = N c Θ_q/2π) of each piece cut: per unit
  // depth F_t = K_t h along (−cos ψ, sin ψ), F_r = K_r F_t along (−sin ψ, −cos ψ).
  const double per_rev = h->slice.front().per_rev;
  if (feed_per_tooth_m > 0.0)
    sys.forcing = [h, kt, kr, d, per_rev](double t, Eigen::VectorXd& out) {
      for (int l = 0; l < h->slices; ++l) {
        const ToothGeometry& g = h->slice[static_cast<std::size_t>(l)];
        for (int j = 0; j < h->teeth; ++j)
          h->pieces(l, j, t, [&](double lo, double hi, int q, double w) {
            if (q <= 0) return;
            const double rho = g.runout.empty() ? 0.0
                                                : g.runout[static_cast<std::size_t>(j)] -
                                                      g.runout[static_cast<std::size_t>((j - q + 2 * h->teeth) % h->teeth)];
            const double c = per_rev * g.back[static_cast<std::size_t>(j * h->teeth + q - 1)] / (2.0 * kPi);
            TrigMoments m;
            m.add(lo, hi, w);
            out(0) += kt * (rho * (-m.c - kr * m.s) + c * (-m.sc - kr * m.ss));
            if (d == 2) out(1) += kt * (rho * (m.s - kr * m.c) + c * (m.ss - kr * m.sc));
          });
      }
    };
  // P changes slope where a window's end crosses an angle where the cut changes.
  for (int l = 0; l < h->slices; ++l)
    for (int j = 0; j < teeth; ++j)
      for (double angle : h->switches[static_cast<std::size_t>(l * teeth + j)])
        for (int end = 0; end <= 1; ++end) {
          const double z = (l + end) * h->height;
          const double t = std::fmod(angle + h->lag[static_cast<std::size_t>(j)] + h->kappa[static_cast<std::size_t>(j)] * z,
                                     2.0 * kPi) /
                           h->spin;
          const double tp = std::fmod(t, sys.period);
          if (tp > 1e-12 * sys.period && tp < sys.period * (1.0 - 1e-12)) sys.breakpoints.push_back(tp);
        }
  std::sort(sys.breakpoints.begin(), sys.breakpoints.end());
  sys.breakpoints.erase(std::unique(sys.breakpoints.begin(), sys.breakpoints.end(),
                                    [&](double a, double b) { return b - a < 1e-12 * sys.period; }),
                        sys.breakpoints.end());
  const double ci = cutting.process_damping_n_per_m;
  if (!(ci > 0.0)) return sys;
  // Process damping, as milling_delay_system: −(C_i/V) u uᵀ ṙ per unit depth over every engaged piece.
  const double speed = cutting_speed(cutting, speed_rpm);
  return with_velocity_feedback(sys, velocity_output(model), [h, ci, speed, d](double t, Eigen::MatrixXd& out) {
    TrigMoments m;
    for (int l = 0; l < h->slices; ++l)
      for (int j = 0; j < h->teeth; ++j) h->pieces(l, j, t, [&](double lo, double hi, int, double w) { m.add(lo, hi, w); });
    out = -ci / speed * m.normal().topLeftCorner(d, d);
  });
}

double cutting_speed(const CuttingConditions& cutting, double speed_rpm) { return kPi * cutting.diameter_m * speed_rpm / 60.0; }

Eigen::MatrixXd velocity_output(const ModalModel& model) {
  const int nx = static_cast<int>(model.x.size()), nq = nx + static_cast<int>(model.y.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(model.y.empty() ? 1 : 2, 2 * nq);
  for (int r = 0; r < nq; ++r) c(r < nx ? 0 : 1, 2 * r + 1) = 1.0;
  if (model.terms.empty()) return c;
  // A residue term's velocity 2 Re(Rλ z) (ResidueTerm: without the direct term).
  c.conservativeResize(Eigen::NoChange, 2 * nq + 2 * static_cast<Eigen::Index>(model.terms.size()));
  c.rightCols(2 * static_cast<Eigen::Index>(model.terms.size())).setZero();
  for (std::size_t i = 0; i < model.terms.size(); ++i) {
    const ResidueTerm& t = model.terms[i];
    const Complex rl = t.residue * t.pole;
    const Eigen::Index k = 2 * nq + 2 * static_cast<Eigen::Index>(i);
    c(t.to, k) = 2.0 * rl.real();
    c(t.to, k + 1) = -2.0 * rl.imag();
  }
  return c;
}

namespace {

// Hopf, flip or fold from the critical multiplier; the chatter frequency from the Floquet
// solution q(t_i) = μ^{i/m} p(t_i), p τ-periodic: the DFT of p's tip displacement over one period
// gives harmonics at (arg μ + 2πj)/τ, the strongest is the chatter.
// `tau` the map's period, `tooth_tau` the (mean) tooth period the lobe number counts waves in.
// Only the first `rows` outputs (the tip displacement; velocities follow with process damping) are read.
FloquetAnalysis floquet(const PeriodMap& map, double depth_m, const DominantMultiplier& dm, double tau, double tooth_tau,
                        int rows) {
  FloquetAnalysis fa;
  fa.spectral_radius = dm.spectral_radius;
  fa.critical_multiplier = dm.multiplier;
  fa.matrix_size = map.size();
  const Complex mu = dm.multiplier;
  // Real multipliers come out of the real Schur form with Im exactly 0.
  fa.kind = std::abs(mu.imag()) > 1e-9 * std::abs(mu) ? BoundaryKind::Hopf
            : mu.real() < 0.0                         ? BoundaryKind::Flip
                                                      : BoundaryKind::Fold;
  if (std::abs(mu) == 0.0) return fa;
  const int m = map.steps();
  const Eigen::MatrixXcd r = map.outputs(depth_m, dm.vector);
  const Complex root = std::exp(std::log(mu) / static_cast<double>(m));
  Eigen::MatrixXcd p(rows, m);
  Complex scale = 1.0;
  for (int i = 0; i < m; ++i) {
    p.col(i) = r.col(i).head(rows) / scale;
    scale *= root;
  }
  // The DFT of each output row by FFT (Eigen's kissfft: any m, O(m log m); a direct sum cost m²
  // sines and was a third of a boundary's time). Harmonic j ≥ m − m/2 is j − m.
  Eigen::FFT<double> fft;
  Eigen::VectorXd power = Eigen::VectorXd::Zero(m);
  std::vector<Complex> row(static_cast<std::size_t>(m)), spectrum;
  for (Eigen::Index q = 0; q < p.rows(); ++q) {
    for (int i = 0; i < m; ++i) row[static_cast<std::size_t>(i)] = p(q, i);
    fft.fwd(spectrum, row);
    for (int j = 0; j < m; ++j) power(j) += std::norm(spectrum[static_cast<std::size_t>(j)]);
  }
  int best_j = 0;
  double best = -1.0;
  for (int j = -m / 2; j < m - m / 2; ++j) {
    const double c = power(j < 0 ? j + m : j);
    if (c > best) {
      best = c;
      best_j = j;
    }
  }
  fa.chatter_hz = std::abs(std::arg(mu) + 2.0 * kPi * best_j) / (2.0 * kPi * tau);
  fa.lobe = static_cast<int>(std::floor(fa.chatter_hz * tooth_tau));
  return fa;
}

// A root of ρ(a) = 1.
struct Root {
  double depth_m = 0.0;
  double hi = 0.0;     // where the critical multiplier is read: the bracket's upper end (ρ ≥ 1), or
                       // the evaluated depth nearest the root (within the tolerance)
  double slope = 0.0;  // dρ/da across the last two values [1/m] (secant of the true values)
};

// The period map at a depth: one map for every depth (straight flutes: the depth is only the gain
// σ), or with a helix one built for each depth asked (the last one kept).
class MapAtDepth {
 public:
  MapAtDepth(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm, int steps, int degree,
             Discretization scheme)
      : model_(model), cutting_(cutting), speed_rpm_(speed_rpm), steps_(steps), degree_(degree), scheme_(scheme) {
    if (!cutting.helical()) map_.emplace(milling_delay_system(model, cutting, speed_rpm), steps, degree, scheme);
  }
  const PeriodMap& operator()(double depth_m) const {
    if (cutting_.helical() && (!map_ || depth_m != depth_m_)) {
      map_.reset();
      map_.emplace(milling_delay_system_at_depth(model_, cutting_, speed_rpm_, depth_m), steps_, degree_, scheme_);
      depth_m_ = depth_m;
    }
    return *map_;
  }

 private:
  const ModalModel& model_;
  const CuttingConditions& cutting_;
  double speed_rpm_;
  int steps_, degree_;
  Discretization scheme_;
  mutable std::optional<PeriodMap> map_;
  mutable double depth_m_ = kNaN;
};

struct RadiusCounter {
  const MapAtDepth& map;
  long* evaluations;
  DominantMultiplier operator()(double a) const {
    ++*evaluations;
    return map(a).dominant(a, false);
  }
};

// The root of ρ(a) = 1 in a bracket lo < hi (ρ(lo) < 1 ≤ ρ(hi)) by regula falsi with the
// Anderson–Björck modification (the end kept twice has its value scaled by 1 − f_new/f_old, or
// halved), to a relative width `tolerance`. Returns the bracket's midpoint.
Root narrow_bracket(const RadiusCounter& rho, double lo, double flo, double hi, const DominantMultiplier& at_hi,
                    double tolerance) {
  auto AB = [](double fnew, double fold) {
    const double m = 1.0 - fnew / fold;
    return m > 0.0 ? m : 0.5;
  };
  double fhi = at_hi.spectral_radius - 1.0;
  double true_lo = flo, true_hi = fhi;  // unhalved, for the slope
  int side = 0;                         // which end was kept last time: −1 lo, +1 hi
  for (int it = 0; it < 100 && hi - lo > tolerance * hi; ++it) {
    double x = hi - fhi * (hi - lo) / (fhi - flo);
    // Regula falsi approaches from one side; once an end has moved, aim a little past the estimate
    // so that the other end moves too and the bracket closes within the tolerance.
    if (side != 0) x -= side * 0.4 * tolerance * hi;
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);  // round-off at a tiny bracket
    const double f = rho(x).spectral_radius - 1.0;
    if (f < 0.0) {
      lo = x;
      if (side == -1) fhi *= AB(f, flo);
      flo = true_lo = f;
      side = -1;
    } else {
      hi = x;
      if (side == 1) flo *= AB(f, fhi);
      fhi = true_hi = f;
      side = 1;
    }
  }
  return {0.5 * (lo + hi), hi, (true_hi - true_lo) / (hi - lo)};
}

// The first instability met going up from `start` (or down from it by halving while unstable),
// then narrowed. Going up, the first step jumps to `expected` (the neighbouring speed's limit) when
// that lies above `start`, then steps of ×`growth`. nullopt when ρ < 1 up to max_depth_m.
std::optional<Root> lowest_root(const RadiusCounter& rho, double start, double expected, double growth, double max_depth_m,
                                double tolerance) {
  double a = std::min(start, max_depth_m);
  DominantMultiplier dm = rho(a);
  if (dm.spectral_radius >= 1.0) {
    DominantMultiplier hi_dm = dm;
    double hi = a;
    for (int it = 0; it < 60; ++it) {
      a *= 0.5;
      dm = rho(a);
      if (dm.spectral_radius < 1.0) return narrow_bracket(rho, a, dm.spectral_radius - 1.0, hi, hi_dm, tolerance);
      hi = a;
      hi_dm = dm;
    }
    throw NumericalError(fmt::format("the spectral radius stays ≥ 1 down to depth {:.3g} m, although the free tool decays", a),
                         "check the modal model (damping ratios > 0) and the cutting coefficients");
  }
  bool first = true;
  for (;;) {
    if (a >= max_depth_m) return std::nullopt;
    const double lo = a, flo = dm.spectral_radius - 1.0;
    a = std::min(first && expected > a * 1.05 ? expected : a * growth, max_depth_m);
    first = false;
    dm = rho(a);
    if (dm.spectral_radius >= 1.0) return narrow_bracket(rho, lo, flo, a, dm, tolerance);
  }
}

// The root at a finer level near the coarser level's root `near`, where ρ has slope `slope`: a
// step from ρ(near) along that slope predicts it, and the secant through the two values corrects
// the prediction. The levels' roots differ by the discretization error (well under 1 % at the
// default steps), so the secant's own error, of the order of the product of the two points'
// errors, is far below the tolerance: when the correction is within half the tolerance, that is
// the root, found with two spectral radii. Else the two values are a bracket, or one is grown
// outwards in steps doubling from 0.5 % (at most ±25 %), and narrowed. Failing all that, the
// lowest root at this level by a scan up from 70 % of `near`. nullopt when no instability below
// max_depth_m.
std::optional<Root> root_near(const RadiusCounter& rho, double near, double slope, double max_depth_m, double tolerance) {
  const double a = std::min(near, max_depth_m);
  const DominantMultiplier dm = rho(a);
  const bool unstable = dm.spectral_radius >= 1.0;
  const double fa = dm.spectral_radius - 1.0;
  auto bracket = [&](double b, const DominantMultiplier& db) -> std::optional<Root> {
    const double fb = db.spectral_radius - 1.0;
    if (unstable && fb < 0.0) return narrow_bracket(rho, b, fb, a, dm, tolerance);
    if (!unstable && fb >= 0.0) return narrow_bracket(rho, a, fa, b, db, tolerance);
    return std::nullopt;
  };
  if (std::isfinite(slope) && slope > 0.0) {
    const double step = std::clamp(-fa / slope, -0.25 * a, 0.25 * a);
    const double b = std::min(a + (std::abs(step) > 1e-6 * a ? step : (unstable ? -1e-6 : 1e-6) * a), max_depth_m);
    if (b != a && (b < a) == unstable) {
      const DominantMultiplier db = rho(b);
      const double fb = db.spectral_radius - 1.0;
      const double x = b - fb * (b - a) / (fb - fa);
      if (fb != fa && std::abs(x - b) <= 0.5 * tolerance * b && x > 0.0 && x < max_depth_m)
        return Root{x, b, (fb - fa) / (b - a)};
      if (auto r = bracket(b, db)) return r;
    }
  }
  for (double step = 0.005; step < 0.26; step *= 2.0) {
    const double b = unstable ? a * (1.0 - step) : std::min(a * (1.0 + step), max_depth_m);
    if (auto r = bracket(b, rho(b))) return r;
    if (b >= max_depth_m) break;
  }
  return lowest_root(rho, 0.7 * a, a, 1.2, max_depth_m, tolerance);
}

}  // namespace

int boundary_error_order(Discretization scheme, int degree) { return scheme == Discretization::Semi ? 2 : degree + 1; }

FullDiscretization::FullDiscretization(ModalModel model, CuttingConditions cutting, int steps, int degree, Discretization scheme)
    : model_(std::move(model)), cutting_(cutting), steps_(steps), degree_(degree), scheme_(scheme) {
  model_.check();
  cutting_.check();
  if (steps_ < 4 || steps_ > 20000)
    throw InvalidArgument(fmt::format("{} discretization steps per tooth period: need 4…20000", steps_),
                          "40 is usual; more for chatter frequencies far above the tooth passing frequency");
  if (scheme_ == Discretization::Semi && (degree_ < 0 || degree_ > 1))
    throw InvalidArgument(fmt::format("semi-discretization order {}: need 0 or 1", degree_));
  if (scheme_ == Discretization::Full && (degree_ < 1 || degree_ > 3))
    throw InvalidArgument(fmt::format("interpolation degree {}: need 1, 2 or 3", degree_));
}

PeriodMap FullDiscretization::period_map(double speed_rpm) const {
  return PeriodMap(milling_delay_system(model_, cutting_, speed_rpm), steps_ * cutting_.teeth_per_period(), degree_, scheme_);
}

PeriodMap FullDiscretization::period_map(double speed_rpm, double depth_m) const {
  return PeriodMap(milling_delay_system_at_depth(model_, cutting_, speed_rpm, depth_m), steps_ * cutting_.teeth_per_period(),
                   degree_, scheme_);
}

double FullDiscretization::spectral_radius(double speed_rpm, double depth_m) const {
  if (!std::isfinite(depth_m) || depth_m < 0.0) throw InvalidArgument(fmt::format("axial depth {} m must be ≥ 0", depth_m));
  return period_map(speed_rpm, depth_m).spectral_radius(depth_m);
}

FloquetAnalysis FullDiscretization::analyse(double speed_rpm, double depth_m) const {
  if (!std::isfinite(depth_m) || depth_m < 0.0) throw InvalidArgument(fmt::format("axial depth {} m must be ≥ 0", depth_m));
  const PeriodMap map = period_map(speed_rpm, depth_m);
  const double tooth = 60.0 / (cutting_.teeth * speed_rpm);
  return floquet(map, depth_m, map.dominant(depth_m), tooth * cutting_.teeth_per_period(), tooth, model_.y.empty() ? 1 : 2);
}

Eigen::MatrixXd FullDiscretization::spectral_radius_map(const std::vector<double>& speeds_rpm,
                                                        const std::vector<double>& depths_m,
                                                        const ParallelOptions& parallel) const {
  for (double a : depths_m)
    if (!std::isfinite(a) || a < 0.0) throw InvalidArgument(fmt::format("axial depth {} m must be ≥ 0", a));
  Eigen::MatrixXd rho(static_cast<Eigen::Index>(speeds_rpm.size()), static_cast<Eigen::Index>(depths_m.size()));
  parallel_for(speeds_rpm.size(), parallel, [&](std::size_t i) {
    const MapAtDepth map(model_, cutting_, speeds_rpm[i], steps_ * cutting_.teeth_per_period(), degree_, scheme_);
    for (std::size_t j = 0; j < depths_m.size(); ++j)
      rho(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = map(depths_m[j]).spectral_radius(depths_m[j]);
  });
  return rho;
}

BoundaryPoint FullDiscretization::boundary(double speed_rpm, double max_depth_m, int depth_steps, double tolerance) const {
  if (!std::isfinite(max_depth_m) || !(max_depth_m > 0.0))
    throw InvalidArgument(fmt::format("maximum depth {} m must be positive", max_depth_m));
  if (depth_steps < 1 || depth_steps > 100000) throw InvalidArgument(fmt::format("{} depth steps: need 1…100000", depth_steps));
  if (!std::isfinite(tolerance) || !(tolerance > 0.0) || tolerance >= 1.0)
    throw InvalidArgument(fmt::format("depth tolerance {} must lie in (0, 1)", tolerance));
  const MapAtDepth map(model_, cutting_, speed_rpm, steps_ * cutting_.teeth_per_period(), degree_, scheme_);
  long evaluations = 0;
  const RadiusCounter rho{map, &evaluations};
  BoundaryPoint bp;
  bp.speed_rpm = speed_rpm;
  double lo = 0.0, flo = map(0.0).spectral_radius(0.0) - 1.0;  // < 0: the free tool decays
  for (int j = 1; j <= depth_steps; ++j) {
    const double a = max_depth_m * j / depth_steps;
    const DominantMultiplier dm = rho(a);
    if (dm.spectral_radius < 1.0) {
      lo = a;
      flo = dm.spectral_radius - 1.0;
      continue;
    }
    const Root root = narrow_bracket(rho, lo, flo, a, dm, tolerance);
    const double tooth = 60.0 / (cutting_.teeth * speed_rpm);
    const PeriodMap& at = map(root.hi);
    const FloquetAnalysis fa = floquet(at, root.hi, at.dominant(root.hi), tooth * cutting_.teeth_per_period(), tooth,
                                       model_.y.empty() ? 1 : 2);
    bp.depth_m = root.depth_m;
    bp.depth_error_m = kNaN;
    bp.chatter_hz = fa.chatter_hz;
    bp.lobe = fa.lobe;
    bp.kind = fa.kind;
    bp.multiplier = fa.critical_multiplier;
    return bp;
  }
  bp.depth_m = max_depth_m;
  bp.depth_error_m = kNaN;
  bp.chatter_hz = kNaN;
  return bp;
}

void BoundaryOptions::check() const {
  speeds.check();
  check_fields(boundary_fields(), *this, "BoundaryOptions");
  if (steps > max_steps / 2)
    throw InvalidArgument(fmt::format("BoundaryOptions::steps {} leaves no room for the finer level below max_steps {}", steps,
                                      max_steps),
                          "the error estimate compares m with 2m steps: keep steps ≤ max_steps/2");
  if (scheme == Discretization::Semi && degree > 1)
    throw InvalidArgument(
        fmt::format("BoundaryOptions::degree {} must be 0 or 1 with Discretization::Semi (the order of "
                    "semi-discretization)",
                    degree));
  if (scheme == Discretization::Full && degree < 1)
    throw InvalidArgument(fmt::format("BoundaryOptions::degree {} must be 1, 2 or 3 with Discretization::Full", degree));
}

FieldSpec study_steps_field(const char* help) {
  FieldSpec s = with_help(option_field(boundary_fields(), "steps").spec, help);
  s.max = BoundaryOptions{}.max_steps / 2;
  return s;
}

const std::vector<OptionField<BoundaryOptions>>& boundary_fields() {
  using O = BoundaryOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "tolerance",
        .kind = FieldKind::Real,
        .min = 1e-6,
        .max = 0.5,
        .help = "target for the estimated discretization error of each depth, relative to the depth (the steps per "
                "tooth period are doubled until it is met)",
        .cli_name = "tolerance",
        .cli_unit = "%",
        .cli_per_unit = 100.0},
       [](O& o) -> double& { return o.tolerance; }},
      {{.name = "steps",  // at most half max_steps' top: the error estimate compares m with 2m steps
        .kind = FieldKind::Integer,
        .min = 4.0,
        .max = 10000.0,
        .automatic = 0.0,
        .note = "0: 12 per chatter wave",
        .help = "steps per tooth period at the first of the two levels compared",
        .cli_name = "intervals"},
       nullptr,
       [](O& o) -> int& { return o.steps; }},
      {{.name = "max_steps", .kind = FieldKind::Integer, .min = 8.0, .max = 20000.0, .help = "no level finer than this"},
       nullptr,
       [](O& o) -> int& { return o.max_steps; }},
      {{.name = "degree",
        .kind = FieldKind::Integer,
        .min = 0.0,
        .max = 3.0,
        .help = "degree of the polynomial the delayed state is interpolated with (full discretization: 1–3; "
                "semi-discretization: 0 its zeroth order, else the first)"},
       nullptr,
       [](O& o) -> int& { return o.degree; }},
      {{.name = "max_depth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .note = "0: 10 × the zero-order floor",
        .help = "depths searched up to this",
        .cli_name = "max-depth",
        .cli_unit = "mm",
        .cli_per_unit = 1e3},
       [](O& o) -> double& { return o.max_depth_m; }},
      {option_field(parallel_fields(), "threads").spec, nullptr, [](O& o) -> int& { return o.parallel.threads; }}};
  return fields;
}

double BoundaryResult::worst_relative_error() const {
  double worst = 0.0;
  for (const BoundaryPoint& b : boundary)
    if (b.kind != BoundaryKind::None && std::isfinite(b.depth_error_m)) worst = std::max(worst, b.depth_error_m / b.depth_m);
  return worst;
}

namespace {

// Where a speed's search starts: the limit and chatter frequency of a neighbouring speed, or of
// the zero-order method (which can be 2.3× too high at low immersion, hence `start` lower).
struct Guess {
  double depth_m, chatter_hz, start;
};

struct SpeedOutcome {
  BoundaryPoint point;
  long evaluations = 0;
  bool unmet = false;    // the tolerance was not met at max_steps
  bool aliased = false;  // the chatter period spans fewer than 4 steps
};

SpeedOutcome boundary_at(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm, const Guess& guess,
                         double max_depth_m, const BoundaryOptions& o) {
  const int per = cutting.teeth_per_period();  // tooth periods per map period
  const double tooth_tau = 60.0 / (cutting.teeth * speed_rpm), tau = tooth_tau * per;
  SpeedOutcome out;
  BoundaryPoint& bp = out.point;
  bp.speed_rpm = speed_rpm;
  // m: 12 steps per chatter wave within a tooth period (at least 16), unless given.
  const double waves = std::isfinite(guess.chatter_hz) ? guess.chatter_hz * tooth_tau : 1.0;
  int m = o.steps > 0 ? o.steps : std::clamp(static_cast<int>(std::ceil(12.0 * waves)), 16, o.max_steps / 2);
  // Roots to brackets of 0.1 (finer level) and 0.3 (coarser) of the error target: the reported
  // a₂ + (a₂ − a₁)/7 then carries at most (0.05·8/7 + 0.15/7) ≈ 0.08 of the target from the roots.
  const double root_tolerance = std::clamp(1e-1 * o.tolerance, 1e-10, 1e-3);
  const MapAtDepth coarse(model, cutting, speed_rpm, m * per, o.degree, o.scheme);
  std::optional<Root> r1 = lowest_root({coarse, &out.evaluations}, guess.start * guess.depth_m, guess.depth_m, 1.15, max_depth_m,
                                       3.0 * root_tolerance);
  if (!r1) {
    bp.depth_m = max_depth_m;
    bp.depth_error_m = kNaN;
    bp.chatter_hz = kNaN;
    return out;
  }
  // Richardson: error of a_{2m} = (a_{2m} − a_m)/(2^q − 1), q = p + 1 for full-discretization.
  const double factor = std::pow(2.0, boundary_error_order(o.scheme, o.degree)) - 1.0;
  double a1 = r1->depth_m, slope = r1->slope;
  for (;;) {
    const MapAtDepth fine(model, cutting, speed_rpm, 2 * m * per, o.degree, o.scheme);
    const std::optional<Root> r2 = root_near({fine, &out.evaluations}, a1, slope, max_depth_m, root_tolerance);
    if (!r2) {  // the finer (more accurate) level is stable up to the ceiling
      bp.depth_m = max_depth_m;
      bp.depth_error_m = kNaN;
      bp.chatter_hz = kNaN;
      bp.steps = 2 * m;
      return out;
    }
    const double a2 = r2->depth_m, error = std::abs(a2 - a1) / factor;
    bp.depth_m = a2 + (a2 - a1) / factor;
    bp.depth_error_m = error;
    bp.steps = 2 * m;
    if (error <= o.tolerance * bp.depth_m || 4 * m > o.max_steps) {
      const PeriodMap& at = fine(r2->hi);
      const FloquetAnalysis fa = floquet(at, r2->hi, at.dominant(r2->hi), tau, tooth_tau, model.y.empty() ? 1 : 2);
      bp.chatter_hz = fa.chatter_hz;
      bp.lobe = fa.lobe;
      bp.kind = fa.kind;
      bp.multiplier = fa.critical_multiplier;
      out.unmet = error > o.tolerance * bp.depth_m;
      // Fewer than 4 steps per chatter period: the discretization (and the DFT) is at its limit.
      out.aliased = fa.chatter_hz * tooth_tau > 2.0 * m / 4.0;
      return out;
    }
    a1 = a2;
    slope = r2->slope;
    m *= 2;
  }
}

}  // namespace

namespace {

// The boundary at every speed of options.speeds, speed i from model_of(i) (a reference valid for the
// call), starting from the zero-order guesses `zero` (on the same grid); res has max_depth_m set.
template <typename ModelOf>
void boundary_over_speeds(const ModelOf& model_of, const ZeroOrderResult& zero, const CuttingConditions& cutting,
                          const BoundaryOptions& options, BoundaryResult& res) {
  const std::vector<double> speeds = options.speeds.values();
  // Blocks of 8 neighbouring speeds, each walked in order from the zero-order guess: the work of
  // one block depends on nothing outside it, so any thread count gives the same result.
  constexpr std::size_t kBlock = 8;
  const std::size_t blocks = (speeds.size() + kBlock - 1) / kBlock;
  std::vector<SpeedOutcome> outcomes(speeds.size());
  std::mutex progress_lock;
  std::size_t done = 0;
  parallel_for(blocks, options.parallel, [&](std::size_t b) {
    Guess guess{kNaN, kNaN, 0.0};
    for (std::size_t i = b * kBlock; i < std::min(speeds.size(), (b + 1) * kBlock); ++i) {
      const EnvelopePoint& z = zero.envelope[i];
      const bool first = i == b * kBlock || outcomes[i - 1].point.kind == BoundaryKind::None;
      if (first)
        guess = std::isfinite(z.depth_m) ? Guess{z.depth_m, z.chatter_hz, 0.35}
                                         : Guess{zero.floor_depth_m, zero.floor_chatter_hz, 0.35};
      else guess = {outcomes[i - 1].point.depth_m, outcomes[i - 1].point.chatter_hz, 0.7};
      outcomes[i] = boundary_at(model_of(i), cutting, speeds[i], guess, res.max_depth_m, options);
      if (options.progress) {
        std::lock_guard<std::mutex> hold(progress_lock);
        options.progress(static_cast<double>(++done) / static_cast<double>(speeds.size()));
      }
    }
  });
  int none = 0, unmet = 0, aliased = 0;
  for (const SpeedOutcome& o : outcomes) {
    res.boundary.push_back(o.point);
    res.evaluations += o.evaluations;
    none += o.point.kind == BoundaryKind::None;
    unmet += o.unmet;
    aliased += o.aliased;
  }
  if (none > 0)
    res.warnings.push_back(fmt::format("{} of {} speeds are stable up to the maximum depth {:.4g} mm (kind 'none')", none,
                                       res.boundary.size(), res.max_depth_m * 1e3));
  if (unmet > 0)
    res.warnings.push_back(
        fmt::format("at {} speed(s) the estimated discretization error stays above {:.3g} % of the depth "
                    "with {} steps per tooth period (BoundaryOptions::max_steps)",
                    unmet, 100.0 * options.tolerance, options.max_steps));
  if (aliased > 0)
    res.warnings.push_back(
        fmt::format("at {} speed(s) the chatter period spans fewer than 4 steps: the boundary and chatter "
                    "frequency there are at the discretization's limit (raise BoundaryOptions::steps)",
                    aliased));
}

}  // namespace

BoundaryResult stability_boundary(const ModalModel& model, const CuttingConditions& cutting, const BoundaryOptions& options) {
  options.check();
  model.check();
  cutting.check();
  BoundaryResult res;
  res.tolerance = options.tolerance;
  res.degree = options.degree;
  res.scheme = options.scheme;
  // The zero-order lobes of the modal model on the same speed grid: starting guesses, and the
  // default ceiling.
  std::vector<Mode> all = model.x;
  all.insert(all.end(), model.y.begin(), model.y.end());
  ZeroOrderOptions zo;
  zo.speeds = options.speeds;
  CuttingConditions even = cutting;  // variable pitch, runout: the even tool's zero-order lobes as the guesses
  even.pitch_rad.clear();
  even.runout_m.clear();
  even.process_damping_n_per_m = 0.0;  // guesses below the damped limit: the search scans up from them
  even.helix_rad.clear();              // the zero-order method averages a helix out
  const ZeroOrderResult zero = zero_order_lobes(modal_milling_frfs(model.x, model.y, modal_frequency_grid(all)), even, zo);
  res.max_depth_m = options.max_depth_m > 0.0 ? options.max_depth_m : 10.0 * zero.floor_depth_m;
  boundary_over_speeds([&](std::size_t) -> const ModalModel& { return model; }, zero, cutting, options, res);
  return res;
}

BoundaryResult stability_boundary(const std::vector<ModalModel>& models, const ZeroOrderResult& guesses,
                                  const CuttingConditions& cutting, const BoundaryOptions& options) {
  options.check();
  cutting.check();
  const std::size_t count = options.speeds.values().size();
  if (models.size() != count)
    throw InvalidArgument(fmt::format("{} modal models for the {} speeds of BoundaryOptions::speeds: one per speed is needed",
                                      models.size(), count));
  if (guesses.envelope.size() != count)
    throw InvalidArgument(
        fmt::format("the zero-order guesses have {} speeds, BoundaryOptions::speeds {}: give them on the same grid",
                    guesses.envelope.size(), count));
  for (const ModalModel& m : models) m.check();
  BoundaryResult res;
  res.tolerance = options.tolerance;
  res.degree = options.degree;
  res.scheme = options.scheme;
  res.max_depth_m = options.max_depth_m > 0.0 ? options.max_depth_m : 10.0 * guesses.floor_depth_m;
  boundary_over_speeds([&](std::size_t i) -> const ModalModel& { return models[i]; }, guesses, cutting, options, res);
  return res;
}

// ---- Results for people ---------------------------------------------------------------------

std::vector<EnvelopePoint> stability_pockets(const std::vector<EnvelopePoint>& envelope, int count, double min_prominence) {
  if (!std::isfinite(min_prominence) || min_prominence < 0.0 || min_prominence >= 1.0)
    throw InvalidArgument(fmt::format("pocket prominence {} must lie in [0, 1) (a fraction of the depth)", min_prominence));
  std::vector<double> depth;
  for (const EnvelopePoint& e : envelope) depth.push_back(std::isfinite(e.depth_m) ? e.depth_m : kNaN);
  std::vector<EnvelopePoint> pockets;
  // find_peaks' prominence is (peak − valley)/peak: the fraction of the depth asked for here. A
  // maximum at either end of the range is only the range's edge, not a pocket.
  for (const Peak& p : find_peaks(depth, min_prominence))
    if (p.index > 0 && p.index + 1 < envelope.size()) pockets.push_back(envelope[p.index]);
  std::stable_sort(pockets.begin(), pockets.end(),
                   [](const EnvelopePoint& a, const EnvelopePoint& b) { return a.depth_m > b.depth_m; });
  if (pockets.size() > static_cast<std::size_t>(std::max(count, 0))) pockets.resize(static_cast<std::size_t>(std::max(count, 0)));
  return pockets;
}

std::vector<EnvelopePoint> boundary_envelope(const BoundaryResult& result) {
  std::vector<EnvelopePoint> env;
  for (const BoundaryPoint& b : result.boundary) env.push_back({b.speed_rpm, b.depth_m, b.chatter_hz, b.lobe});
  return env;
}

}  // namespace toolpoint
