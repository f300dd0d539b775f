// toolpoint: milling stability lobes — zero-order approximation from FRFs and semi-discretization
// of a modal model. Units: SI (m, kg, N, s, rad), frequencies in Hz, spindle speeds in rpm;
// conventions in stability.hpp.
#include "toolpoint/stability.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <unsupported/Eigen/MatrixFunctions>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

// ---- Geometry -------------------------------------------------------------------------------

void Engagement::check() const {
  if (!std::isfinite(entry_rad) || !std::isfinite(exit_rad) || entry_rad < 0.0 || exit_rad > kPi || !(entry_rad < exit_rad))
    throw InvalidArgument(fmt::format("entry/exit angles {:.6g}°/{:.6g}° must satisfy 0 ≤ entry < exit ≤ 180°",
                                      entry_rad * 180.0 / kPi, exit_rad * 180.0 / kPi),
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
  Engagement e{entry_deg * kPi / 180.0, exit_deg * kPi / 180.0};
  e.check();
  return e;
}

void CuttingConditions::check() const {
  if (teeth < 1 || teeth > 1000) throw InvalidArgument(fmt::format("number of teeth {} must lie in 1…1000", teeth));
  if (!std::isfinite(tangential_coefficient) || !(tangential_coefficient > 0.0))
    throw InvalidArgument(fmt::format("tangential cutting coefficient K_t = {} N/m² must be positive", tangential_coefficient),
                          "K_t is a specific cutting pressure, e.g. 6e8 N/m² for aluminium, 2e9 N/m² for steel");
  if (!std::isfinite(radial_ratio) || radial_ratio < 0.0)
    throw InvalidArgument(fmt::format("radial cutting coefficient ratio K_r = K_n/K_t = {} must be ≥ 0", radial_ratio),
                          "give --kr as a ratio (typically 0.2…0.5) or --kn in N/m²");
  engagement.check();
}

Eigen::Matrix2d directional_integral(double kr, double phi1, double phi2) {
  auto antiderivative = [kr](double p) {
    const double s = std::sin(2.0 * p), c = std::cos(2.0 * p);
    Eigen::Matrix2d f;
    f << 0.5 * (c - 2.0 * kr * p + kr * s), 0.5 * (-s - 2.0 * p + kr * c),
         0.5 * (-s + 2.0 * p + kr * c), 0.5 * (-c - 2.0 * kr * p - kr * s);
    return f;
  };
  return antiderivative(phi2) - antiderivative(phi1);
}

Eigen::Matrix2d directional_factors(const CuttingConditions& cutting) {
  return directional_integral(cutting.radial_ratio, cutting.engagement.entry_rad, cutting.engagement.exit_rad);
}

void SpeedRange::check() const {
  if (!std::isfinite(min_rpm) || !std::isfinite(max_rpm) || !(min_rpm > 0.0) || !(max_rpm > min_rpm))
    throw InvalidArgument(fmt::format("spindle speed range {}:{} rpm is empty or not positive", min_rpm, max_rpm),
                          "give --rpm MIN:MAX with 0 < MIN < MAX, e.g. --rpm 5000:25000");
  if (points < 2 || points > 1000000)
    throw InvalidArgument(fmt::format("{} speed points: need 2…1000000", points));
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

void MillingFrfs::check() const {
  validate(xx, "G_xx", 2);
  if (rigid_y && (yy || xy || yx))
    throw InvalidArgument("a tool rigid in y cannot also have y or cross FRFs", "drop the y/cross FRFs or the rigid-y option");
  if (yy) {
    validate(*yy, "G_yy", 2);
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
  if (y_modes.empty()) frfs.rigid_y = true; else frfs.yy = modal_frf(y_modes, frequency_hz);
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
  if (lobes < -1 || lobes > 5000) throw InvalidArgument(fmt::format("--lobes {} must lie in 0…5000", lobes));
  speeds.check();
  if (!std::isfinite(max_depth_m) || max_depth_m < 0.0)
    throw InvalidArgument(fmt::format("maximum depth {} m must be ≥ 0 (0: no limit)", max_depth_m));
}

namespace {

LobeTable zero_order_roots(const MillingFrfs& frfs, const CuttingConditions& cutting) {
  cutting.check();
  frfs.check();
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
  Complex prev[2] = {0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    const Complex gxx = frfs.xx.values[i];
    const Complex gyy = frfs.rigid_y ? Complex(0.0) : frfs.yy ? frfs.yy->values[i] : gxx;
    const Complex gxy = frfs.xy ? frfs.xy->values[i] : Complex(0.0);
    const Complex gyx = frfs.yx ? frfs.yx->values[i] : Complex(0.0);
    // B = α G; det(I + ΛB) = 0 ⇔ μ = −1/Λ is an eigenvalue of B.
    const Complex b00 = a(0, 0) * gxx + a(0, 1) * gyx, b01 = a(0, 0) * gxy + a(0, 1) * gyy;
    const Complex b10 = a(1, 0) * gxx + a(1, 1) * gyx, b11 = a(1, 0) * gxy + a(1, 1) * gyy;
    const Complex half_tr = 0.5 * (b00 + b11), det = b00 * b11 - b01 * b10;
    const Complex disc = std::sqrt(half_tr * half_tr - det);
    // The larger root directly, the smaller one as det/larger: no cancellation (and exactly 0
    // when det B = 0, the 1-DOF case).
    // (Squared moduli throughout: comparisons need no square roots.)
    const Complex big = std::norm(half_tr + disc) >= std::norm(half_tr - disc) ? half_tr + disc : half_tr - disc;
    Complex mu[2] = {big, big != 0.0 ? det / big : Complex(0.0)};
    if (i > 0 && std::norm(mu[0] - prev[0]) + std::norm(mu[1] - prev[1]) > std::norm(mu[0] - prev[1]) + std::norm(mu[1] - prev[0]))
      std::swap(mu[0], mu[1]);  // keep each root on its own continuous branch
    prev[0] = mu[0];
    prev[1] = mu[1];
    const double scale2 = std::max(std::norm(mu[0]), std::norm(mu[1]));
    for (int r = 0; r < 2; ++r) {
      if (!(std::norm(mu[r]) > 1e-24 * scale2)) continue;  // |μ| ≤ 1e-12 max|μ|: a vanishing root
      const Complex lam = -1.0 / mu[r];
      if (!(lam.real() < 0.0)) continue;  // Λ_R ≥ 0: no positive depth from this root here
      t.depth_m[r][i] = -2.0 * kPi * std::norm(lam) / (lam.real() * nkt);
      t.phase[r][i] = std::atan2(-lam.real(), -lam.imag()) / kPi;  // ε/2π, ε = 2 atan2(−Λ_R, −Λ_I)
    }
  }
  return t;
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

ZeroOrderResult zero_order_lobes(const MillingFrfs& frfs, const CuttingConditions& cutting, const ZeroOrderOptions& options) {
  options.check();
  ZeroOrderResult res;
  res.table = zero_order_roots(frfs, cutting);
  const LobeTable& t = res.table;
  const Floor fl = find_floor(t);
  res.alpha = directional_factors(cutting);
  res.floor_depth_m = fl.depth;
  res.floor_chatter_hz = fl.chatter_hz;
  res.teeth = cutting.teeth;
  res.speeds = options.speeds;
  res.max_depth_m = options.max_depth_m;
  const double n_teeth = cutting.teeth, n_min = options.speeds.min_rpm, n_max = options.speeds.max_rpm;
  const std::size_t nf = t.chatter_hz.size();

  // Lobe k reaches down to 60 f/(N(k + 1)) rpm. Automatic K covers MIN at every chatter frequency
  // whose depth is within 10× the floor (the band that shapes the envelope).
  double f_band = fl.chatter_hz;
  std::size_t near = 0;
  for (int r = 0; r < 2; ++r)
    for (std::size_t i = 0; i < nf; ++i) {
      if (t.depth_m[r][i] <= 10.0 * fl.depth) f_band = std::max(f_band, t.chatter_hz[i]);
      near += t.depth_m[r][i] <= 2.0 * fl.depth;
    }
  const int needed = static_cast<int>(std::ceil(60.0 * f_band / (n_teeth * n_min)));
  if (options.lobes < 0) {
    res.lobes = std::min(needed, 2000);
    if (needed > 2000)
      res.warnings.push_back(fmt::format("{} lobes would be needed to reach {} rpm; computed 2000", needed, n_min));
  } else {
    res.lobes = options.lobes;
    if (res.lobes < needed)
      res.warnings.push_back(fmt::format("lobes 0…{} reach down to about {:.0f} rpm at {:.1f} Hz: slower speeds in the range "
                                         "are not covered (use --lobes {} or more)",
                                         res.lobes, 60.0 * f_band / (n_teeth * (res.lobes + 1)), f_band, needed));
  }
  if (near < 5)
    res.warnings.push_back(fmt::format("only {} FRF point(s) near the critical chatter frequency {:.2f} Hz have a_lim within "
                                       "2× the floor: the FRF grid is too coarse there and the lobes are inaccurate",
                                       near, fl.chatter_hz));

  const std::vector<double> grid = options.speeds.values();
  res.envelope.resize(grid.size());
  for (std::size_t j = 0; j < grid.size(); ++j) res.envelope[j] = {grid[j], kInf, kNaN, -1};
  std::vector<double> speed;
  std::vector<int> cell;
  for (int k = 0; k <= res.lobes; ++k) {
    const auto [i0, i1] = lobe_window(t, cutting.teeth, k, n_min, n_max);
    for (int r = 0; r < 2; ++r) lower_envelope(t, k, r, i0, i1, n_min, grid[1] - grid[0], res.envelope, speed, cell);
  }
  const auto uncovered = std::count_if(res.envelope.begin(), res.envelope.end(), [](const EnvelopePoint& e) { return e.lobe < 0; });
  if (uncovered > 0)
    res.warnings.push_back(fmt::format("{} of {} envelope speeds are reached by no lobe (the FRF's frequency range or the "
                                       "lobe count does not map there); they are left out",
                                       uncovered, res.envelope.size()));
  return res;
}

// ---- Semi-discretization --------------------------------------------------------------------

void ModalModel::check() const {
  if (x.empty()) throw InvalidArgument("the modal model needs at least one mode in x", "give --mode-x MASS,ZETA,FN or an FRF to fit");
  for (std::size_t i = 0; i < x.size() + y.size(); ++i) {
    const bool in_x = i < x.size();
    const Mode& m = in_x ? x[i] : y[i - x.size()];
    const std::string what = fmt::format("{} mode {}", in_x ? "x" : "y", in_x ? i + 1 : i - x.size() + 1);
    m.check(what);
    if (!(m.damping_ratio > 0.0))
      throw InvalidArgument(fmt::format("{}: damping ratio 0 (undamped): every depth is at best marginally stable", what),
                            "give the measured or fitted damping ratio (> 0)");
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

struct SemiDiscretization::SpeedSetup {
  double tau = 0.0, dt = 0.0;
  std::vector<char> cut;                // interval i has a tooth in the cut
  std::vector<Eigen::MatrixXd> mw;      // M⁻¹W_i (n_q × n_q): interval average of M⁻¹ ½K_t Φᵀ A Φ
  Eigen::MatrixXd p0;                   // exp(A₀Δt): an interval with no tooth in the cut
};

struct SemiDiscretization::Propagation {
  Eigen::MatrixXd monodromy;            // reduced: rows/columns of the state and the delayed samples read
  std::vector<Eigen::MatrixXd> states;  // X_i (s × n_u), i = 0…m, the state in terms of the reduced initial vector
};

SemiDiscretization::SemiDiscretization(ModalModel model, CuttingConditions cutting, int intervals)
    : model_(std::move(model)), cutting_(cutting), intervals_(intervals) {
  model_.check();
  cutting_.check();
  if (intervals_ < 4 || intervals_ > 2000)
    throw InvalidArgument(fmt::format("{} semi-discretization intervals per tooth period: need 4…2000", intervals_),
                          "40 is usual; more for chatter frequencies far above the tooth passing frequency");
  modes_ = static_cast<int>(model_.x.size() + model_.y.size());
  const int s = 2 * modes_;
  a0_ = Eigen::MatrixXd::Zero(s, s);
  a0_.topRightCorner(modes_, modes_).setIdentity();
  for (int r = 0; r < modes_; ++r) {
    const Mode& m = r < static_cast<int>(model_.x.size()) ? model_.x[r] : model_.y[r - model_.x.size()];
    const double w = omega_of(m.frequency_hz);
    a0_(modes_ + r, r) = -w * w;
    a0_(modes_ + r, modes_ + r) = -2.0 * m.damping_ratio * w;
  }
}

SemiDiscretization::SpeedSetup SemiDiscretization::prepare(double speed_rpm) const {
  if (!std::isfinite(speed_rpm) || !(speed_rpm > 0.0))
    throw InvalidArgument(fmt::format("spindle speed {} rpm must be positive", speed_rpm));
  const int m = intervals_, nq = modes_, nx = static_cast<int>(model_.x.size()), n_teeth = cutting_.teeth;
  SpeedSetup su;
  su.tau = 60.0 / (n_teeth * speed_rpm);
  su.dt = su.tau / m;
  su.p0 = (a0_ * su.dt).exp();
  su.cut.assign(static_cast<std::size_t>(m), 0);
  su.mw.resize(static_cast<std::size_t>(m));
  const double sweep = 2.0 * kPi / (n_teeth * m), st = cutting_.engagement.entry_rad, ex = cutting_.engagement.exit_rad;
  for (int i = 0; i < m; ++i) {
    Eigen::Matrix2d avg = Eigen::Matrix2d::Zero();
    bool any = false;
    for (int j = 0; j < n_teeth; ++j) {
      const double th0 = std::fmod(2.0 * kPi * j / n_teeth + i * sweep, 2.0 * kPi), th1 = th0 + sweep;
      const double pieces[2][2] = {{th0, std::min(th1, 2.0 * kPi)}, {0.0, th1 - 2.0 * kPi}};
      for (const auto& pc : pieces) {
        const double lo = std::max(pc[0], st), hi = std::min(pc[1], ex);
        if (hi > lo) {
          avg += directional_integral(cutting_.radial_ratio, lo, hi);
          any = true;
        }
      }
    }
    if (!any) continue;
    avg /= sweep;
    Eigen::MatrixXd mw(nq, nq);
    for (int r = 0; r < nq; ++r) {
      const double mass = r < nx ? model_.x[r].mass_kg : model_.y[r - nx].mass_kg;
      for (int c = 0; c < nq; ++c) mw(r, c) = 0.5 * cutting_.tangential_coefficient * avg(r < nx ? 0 : 1, c < nx ? 0 : 1) / mass;
    }
    su.cut[static_cast<std::size_t>(i)] = 1;
    su.mw[static_cast<std::size_t>(i)] = std::move(mw);
  }
  return su;
}

SemiDiscretization::Propagation SemiDiscretization::propagate(const SpeedSetup& su, double depth_m, bool keep_states) const {
  if (!std::isfinite(depth_m) || depth_m < 0.0) throw InvalidArgument(fmt::format("axial depth {} m must be ≥ 0", depth_m));
  const int m = intervals_, nq = modes_, s = 2 * nq;
  // Delayed sample q_{−p} (p = 1…m) is read by interval i when p = m − i or p = m − 1 − i and i is
  // in the cut. p = 0 is the current displacement, part of the state. Unread samples are dropped.
  std::vector<int> col(static_cast<std::size_t>(m + 1), -1);
  for (int i = 0; i < m; ++i)
    if (su.cut[static_cast<std::size_t>(i)]) col[static_cast<std::size_t>(m - i)] = col[static_cast<std::size_t>(m - 1 - i)] = 1;
  col[0] = 0;
  int nu = s;
  std::vector<int> read;  // p ≥ 1 read, in column order
  for (int p = 1; p <= m; ++p)
    if (col[static_cast<std::size_t>(p)] >= 0) {
      col[static_cast<std::size_t>(p)] = nu;
      nu += nq;
      read.push_back(p);
    }
  // Output rows: the new delayed sample at position p is q_{m−p}, the displacement of X_{m−p};
  // its rows sit where its column does.
  std::vector<int> row_of_step(static_cast<std::size_t>(m + 1), -1);
  for (int p : read) row_of_step[static_cast<std::size_t>(m - p)] = col[static_cast<std::size_t>(p)];

  Propagation pr;
  pr.monodromy.resize(nu, nu);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(s, nu), next(s, nu);
  x.leftCols(s).setIdentity();
  auto record = [&](int step) {
    if (keep_states) pr.states.push_back(x);
    if (const int row = row_of_step[static_cast<std::size_t>(step)]; row >= 0) pr.monodromy.middleRows(row, nq) = x.topRows(nq);
  };
  record(0);
  Eigen::MatrixXd aug(s + nq, s + nq), e(s + nq, s + nq);
  for (int i = 0; i < m; ++i) {
    const auto ii = static_cast<std::size_t>(i);
    if (su.cut[ii] && depth_m > 0.0) {
      aug.setZero();
      aug.topLeftCorner(s, s) = a0_;
      aug.block(nq, 0, nq, nq) += depth_m * su.mw[ii];
      aug.block(nq, s, nq, nq) = -depth_m * su.mw[ii];
      e = (aug * su.dt).exp();
      next.noalias() = e.topLeftCorner(s, s) * x;
      const Eigen::MatrixXd r = 0.5 * e.topRightCorner(s, nq);
      for (int p : {m - i, m - 1 - i}) next.middleCols(col[static_cast<std::size_t>(p)], nq) += r;
      x.swap(next);
    } else {
      next.noalias() = su.p0 * x;
      x.swap(next);
    }
    record(i + 1);
  }
  pr.monodromy.topRows(s) = x;
  return pr;
}

namespace {

double largest_modulus(const Eigen::VectorXcd& ev, Eigen::Index* where = nullptr) {
  Eigen::Index k = 0;
  double rho = 0.0;
  for (Eigen::Index i = 0; i < ev.size(); ++i)
    if (std::abs(ev(i)) > rho || (std::abs(ev(i)) == rho && ev(i).imag() > ev(k).imag())) {
      rho = std::abs(ev(i));
      k = i;
    }
  if (!std::isfinite(rho))
    throw NumericalError("the monodromy matrix has non-finite eigenvalues", "reduce the depth range or check the modal model");
  if (where) *where = k;
  return rho;
}

}  // namespace

namespace {

Eigen::EigenSolver<Eigen::MatrixXd> monodromy_eigen(const Eigen::MatrixXd& monodromy, bool vectors, double depth_m) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(monodromy, vectors);
  if (es.info() != Eigen::Success)
    throw NumericalError(fmt::format("the eigenvalues of the monodromy matrix ({}×{}) at depth {} m did not converge",
                                     monodromy.rows(), monodromy.cols(), depth_m));
  return es;
}

}  // namespace

double SemiDiscretization::radius(const SpeedSetup& su, double depth_m) const {
  return largest_modulus(monodromy_eigen(propagate(su, depth_m, false).monodromy, false, depth_m).eigenvalues());
}

double SemiDiscretization::spectral_radius(double speed_rpm, double depth_m) const {
  return radius(prepare(speed_rpm), depth_m);
}

FloquetAnalysis SemiDiscretization::analyse(double speed_rpm, double depth_m) const {
  return analyse(prepare(speed_rpm), depth_m);
}

FloquetAnalysis SemiDiscretization::analyse(const SpeedSetup& su, double depth_m) const {
  const Propagation pr = propagate(su, depth_m, true);
  const auto es = monodromy_eigen(pr.monodromy, true, depth_m);
  FloquetAnalysis fa;
  Eigen::Index k = 0;
  fa.spectral_radius = largest_modulus(es.eigenvalues(), &k);
  const Complex mu = es.eigenvalues()(k);
  fa.critical_multiplier = mu;
  fa.matrix_size = static_cast<int>(pr.monodromy.rows());
  // Real eigenvalues of a real matrix come out of the real Schur form with Im exactly 0.
  fa.kind = std::abs(mu.imag()) > 1e-9 * std::abs(mu) ? BoundaryKind::Hopf : mu.real() < 0.0 ? BoundaryKind::Flip : BoundaryKind::Fold;
  if (std::abs(mu) == 0.0) return fa;

  // The Floquet solution q(t_i) = μ^{i/m} p(t_i), p τ-periodic: the DFT of p over one period gives
  // harmonics at (arg μ + 2πj)/τ; the strongest one (x and y displacement together) is the chatter.
  const int m = intervals_, nq = modes_, nx = static_cast<int>(model_.x.size());
  const Eigen::VectorXcd v = es.eigenvectors().col(k);
  const Complex root = std::exp(std::log(mu) / static_cast<double>(m));
  std::vector<Complex> px(static_cast<std::size_t>(m)), py(static_cast<std::size_t>(m));
  Complex scale = 1.0;
  for (int i = 0; i < m; ++i) {
    const Eigen::VectorXcd q = pr.states[static_cast<std::size_t>(i)].topRows(nq).cast<Complex>() * v;
    px[static_cast<std::size_t>(i)] = q.head(nx).sum() / scale;
    py[static_cast<std::size_t>(i)] = q.tail(nq - nx).sum() / scale;
    scale *= root;
  }
  int best_j = 0;
  double best = -1.0;
  for (int j = -m / 2; j < m - m / 2; ++j) {
    Complex cx = 0.0, cy = 0.0;
    for (int i = 0; i < m; ++i) {
      const Complex w = std::polar(1.0, -2.0 * kPi * j * i / m);
      cx += px[static_cast<std::size_t>(i)] * w;
      cy += py[static_cast<std::size_t>(i)] * w;
    }
    const double power = std::norm(cx) + std::norm(cy);
    if (power > best) {
      best = power;
      best_j = j;
    }
  }
  fa.chatter_hz = std::abs(std::arg(mu) + 2.0 * kPi * best_j) / (2.0 * kPi * su.tau);
  fa.lobe = static_cast<int>(std::floor(fa.chatter_hz * su.tau));
  return fa;
}

Eigen::MatrixXd SemiDiscretization::spectral_radius_map(const std::vector<double>& speeds_rpm, const std::vector<double>& depths_m) const {
  Eigen::MatrixXd rho(static_cast<Eigen::Index>(speeds_rpm.size()), static_cast<Eigen::Index>(depths_m.size()));
  for (std::size_t i = 0; i < speeds_rpm.size(); ++i) {
    const SpeedSetup su = prepare(speeds_rpm[i]);
    for (std::size_t j = 0; j < depths_m.size(); ++j)
      rho(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = radius(su, depths_m[j]);
  }
  return rho;
}

BoundaryPoint SemiDiscretization::boundary(double speed_rpm, double max_depth_m, int depth_steps, double tolerance) const {
  if (!std::isfinite(max_depth_m) || !(max_depth_m > 0.0))
    throw InvalidArgument(fmt::format("maximum depth {} m must be positive", max_depth_m));
  if (depth_steps < 1 || depth_steps > 100000) throw InvalidArgument(fmt::format("{} depth steps: need 1…100000", depth_steps));
  if (!std::isfinite(tolerance) || !(tolerance > 0.0) || tolerance >= 1.0)
    throw InvalidArgument(fmt::format("depth tolerance {} must lie in (0, 1)", tolerance));
  const SpeedSetup su = prepare(speed_rpm);
  BoundaryPoint bp;
  bp.speed_rpm = speed_rpm;
  double lo = 0.0;  // ρ(0) = max e^{−ζω_n τ} < 1: stable
  for (int j = 1; j <= depth_steps; ++j) {
    const double d = max_depth_m * j / depth_steps;
    if (radius(su, d) < 1.0) {
      lo = d;
      continue;
    }
    double hi = d;
    for (int it = 0; it < 200 && hi - lo > tolerance * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      (radius(su, mid) < 1.0 ? lo : hi) = mid;
    }
    const FloquetAnalysis fa = analyse(su, hi);
    bp.depth_m = 0.5 * (lo + hi);
    bp.chatter_hz = fa.chatter_hz;
    bp.lobe = fa.lobe;
    bp.kind = fa.kind;
    bp.multiplier = fa.critical_multiplier;
    return bp;
  }
  bp.depth_m = max_depth_m;
  bp.chatter_hz = kNaN;
  return bp;
}

void SemiDiscretizationOptions::check() const {
  if (intervals < 4 || intervals > 2000) throw InvalidArgument(fmt::format("--intervals {} must lie in 4…2000", intervals));
  speeds.check();
  if (!std::isfinite(max_depth_m) || max_depth_m < 0.0)
    throw InvalidArgument(fmt::format("maximum depth {} m must be ≥ 0 (0: automatic)", max_depth_m));
  if (depth_steps < 1 || depth_steps > 100000) throw InvalidArgument(fmt::format("{} depth steps: need 1…100000", depth_steps));
  if (!std::isfinite(depth_tolerance) || !(depth_tolerance > 0.0) || depth_tolerance >= 1.0)
    throw InvalidArgument(fmt::format("depth tolerance {} must lie in (0, 1)", depth_tolerance));
}

SemiDiscretizationResult semi_discretization_boundary(const ModalModel& model, const CuttingConditions& cutting,
                                                      const SemiDiscretizationOptions& options) {
  options.check();
  const SemiDiscretization sd(model, cutting, options.intervals);
  SemiDiscretizationResult res;
  res.intervals = options.intervals;
  res.max_depth_m = options.max_depth_m;
  if (res.max_depth_m == 0.0) {
    std::vector<Mode> all = model.x;
    all.insert(all.end(), model.y.begin(), model.y.end());
    res.max_depth_m = 10.0 * zero_order_floor(modal_milling_frfs(model.x, model.y, modal_frequency_grid(all)), cutting);
  }
  int none = 0, aliased = 0;
  const std::vector<double> speeds = options.speeds.values();
  for (double n : speeds) {
    res.boundary.push_back(sd.boundary(n, res.max_depth_m, options.depth_steps, options.depth_tolerance));
    if (options.progress) options.progress(static_cast<double>(res.boundary.size()) / static_cast<double>(speeds.size()));
    const BoundaryPoint& b = res.boundary.back();
    none += b.kind == BoundaryKind::None;
    // Fewer than 4 samples per chatter period: the DFT (and the discretization) is at its limit.
    aliased += b.kind != BoundaryKind::None && b.chatter_hz * 60.0 / (cutting.teeth * n) > options.intervals / 4.0;
  }
  if (none > 0)
    res.warnings.push_back(fmt::format("{} of {} speeds are stable up to the maximum depth {:.4g} mm (kind 'none')", none,
                                       res.boundary.size(), res.max_depth_m * 1e3));
  if (aliased > 0)
    res.warnings.push_back(fmt::format("at {} speed(s) the chatter period spans fewer than 4 of the {} intervals: raise "
                                       "--intervals for a trustworthy boundary and chatter frequency",
                                       aliased, options.intervals));
  return res;
}

// ---- Results for people ---------------------------------------------------------------------

std::vector<EnvelopePoint> stability_pockets(const std::vector<EnvelopePoint>& envelope, int count) {
  std::vector<EnvelopePoint> peaks;
  const std::size_t n = envelope.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double d = envelope[i].depth_m;
    if (!std::isfinite(d)) continue;
    const bool left = i == 0 || !std::isfinite(envelope[i - 1].depth_m) || envelope[i - 1].depth_m < d;
    const bool right = i + 1 == n || !std::isfinite(envelope[i + 1].depth_m) || envelope[i + 1].depth_m <= d;
    if (left && right && i > 0 && i + 1 < n) peaks.push_back(envelope[i]);
  }
  std::stable_sort(peaks.begin(), peaks.end(), [](const EnvelopePoint& a, const EnvelopePoint& b) { return a.depth_m > b.depth_m; });
  if (peaks.size() > static_cast<std::size_t>(std::max(count, 0))) peaks.resize(static_cast<std::size_t>(std::max(count, 0)));
  return peaks;
}

namespace {

std::string csv_head(const std::string& what, const std::vector<std::string>& comments, const std::string& columns) {
  std::string s = "# toolpoint " + what + "; units: spindle speed rpm, axial depth mm, chatter frequency Hz\n";
  for (const auto& c : comments) s += "# " + c + "\n";
  return s + columns + "\n";
}

}  // namespace

std::string format_lobes_csv(const ZeroOrderResult& result, const std::vector<std::string>& comments) {
  std::string s = csv_head("stability lobes, zero-order approximation (root: which eigenvalue of the quadratic)", comments,
                           "lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,root");
  result.for_each_point([&](const LobePoint& p) {
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{}\n", p.lobe, p.speed_rpm, p.depth_m * 1e3, p.chatter_hz, p.root);
  });
  return s;
}

std::string format_boundary_csv(const SemiDiscretizationResult& result, const std::vector<std::string>& comments) {
  std::string s = csv_head(fmt::format("stability boundary, semi-discretization with {} intervals per tooth period (kind: "
                                       "hopf, flip = period doubling, none = stable up to {:.6g} mm; lobe −1 where unknown)",
                                       result.intervals, result.max_depth_m * 1e3),
                           comments, "lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,kind");
  for (const BoundaryPoint& b : result.boundary)
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{}\n", b.lobe, b.speed_rpm, b.depth_m * 1e3,
                   std::isfinite(b.chatter_hz) ? fmt::format("{}", b.chatter_hz) : std::string(), to_string(b.kind));
  return s;
}

std::string format_envelope_csv(const std::vector<EnvelopePoint>& envelope, const std::vector<std::string>& comments) {
  std::string s = csv_head("stable envelope (minimum over lobes)", comments,
                           "spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe");
  for (const EnvelopePoint& e : envelope)
    if (std::isfinite(e.depth_m))
      fmt::format_to(std::back_inserter(s), "{},{},{},{}\n", e.speed_rpm, e.depth_m * 1e3,
                     std::isfinite(e.chatter_hz) ? fmt::format("{}", e.chatter_hz) : std::string(), e.lobe);
  return s;
}

std::vector<EnvelopePoint> boundary_envelope(const SemiDiscretizationResult& result) {
  std::vector<EnvelopePoint> env;
  for (const BoundaryPoint& b : result.boundary) env.push_back({b.speed_rpm, b.depth_m, b.chatter_hz, b.lobe});
  return env;
}

}  // namespace toolpoint
