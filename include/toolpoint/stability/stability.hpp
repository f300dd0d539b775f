// toolpoint: milling stability lobes from the tool point dynamics.
//
// Units: SI (m, kg, N, s, rad) in every argument and result, with two named exceptions that are
// the machinist's own: spindle speeds in rpm (fields *_rpm) and, in the CSV the CLI writes, axial
// depths in mm. Frequencies in Hz; cutting coefficients K_t, K_n in N/m² (force per chip area).
//
// Geometry and sign convention (Altintas & Budak, CIRP Annals 44 (1995) 357; Altintas,
// Manufacturing Automation, 2nd ed., ch. 4): x is the feed direction, y the normal direction in the
// plane of the cut; the immersion angle φ of a tooth is measured clockwise from +y, so a tooth cuts
// while φ_st ≤ φ ≤ φ_ex within [0, π]. Up-milling: φ_st = 0, φ_ex = acos(1 − 2a/D); down-milling:
// φ_st = acos(2a/D − 1), φ_ex = π (docs/reference.md §7). x, y are displacements of the tool relative to the
// work; the FRFs G_xx, G_xy, G_yx, G_yy are receptances [m/N] of the tool point in these
// directions (e^{iωt}: Im G_xx ≤ 0). Flutes are straight and teeth evenly spaced unless
// CuttingConditions says otherwise (pitch, helix, runout: the time-domain method only).
//
// Dynamic chip thickness h = Δx sin φ + Δy cos φ, Δ = r(t) − r(t − τ), τ = 60/(N n) the tooth
// period; tooth forces F_t = K_t a h, F_r = K_r F_t with K_r = K_n/K_t. Summed over the teeth in
// cut: F(t) = ½ a K_t A(φ(t)) Δ(t), with per tooth
//     A = [[−sin2φ − K_r(1 − cos2φ),  −(1 + cos2φ) − K_r sin2φ],
//          [ (1 − cos2φ) − K_r sin2φ,    sin2φ − K_r(1 + cos2φ)]],
// whose integral over φ₁…φ₂ is the matrix α of docs/reference.md §7 (directional_integral below).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <functional>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/stability/periodic_delay.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

enum class MillingDirection { Up, Down };

// Entry and exit angles φ_st < φ_ex of the teeth [rad], within [0, π].
struct Engagement {
  double entry_rad = 0.0;
  double exit_rad = 0.0;
  void check() const;  // throws InvalidArgument unless 0 ≤ φ_st < φ_ex ≤ π
};

// From the radial immersion a/D in (0, 1] (docs/reference.md §7). Throws InvalidArgument outside (0, 1].
Engagement engagement_from_immersion(double radial_immersion, MillingDirection direction);
// From angles in degrees (the CLI's --entry/--exit). Throws InvalidArgument outside 0 ≤ entry < exit ≤ 180.
Engagement engagement_from_degrees(double entry_deg, double exit_deg);

// The plausible range of the process-damping (indentation) coefficient C_i [N/m]: published
// values lie around 1e4…1e7 N/m; outside 1e3…1e8 N/m it is most likely in another unit.
inline constexpr double kProcessDampingMin = 1e3, kProcessDampingMax = 1e8;
// The largest helix angle taken [rad] (80°, as simulation.hpp's Cutter::helix_rad).
inline constexpr double kMaxHelixRad = 80.0 * 3.14159265358979323846 / 180.0;

struct CuttingConditions {
  int teeth = 0;                        // N ≥ 1
  double tangential_coefficient = 0.0;  // K_t > 0 [N/m²]
  double radial_ratio = 0.0;            // K_r = K_n/K_t ≥ 0
  Engagement engagement;
  // Variable pitch: the angle [rad] from each tooth to the one that follows it (tooth j + 1 passes
  // an angle pitch_rad[j]/Ω after tooth j, as simulation.hpp's Cutter::pitch_rad), N entries, each
  // > 0, summing to 2π (within 1e-6 rad). Empty: evenly spaced. Only the time-domain stability
  // (full-discretization) uses it; the zero-order method refuses an uneven pitch.
  std::vector<double> pitch_rad{};
  // Radial runout: tooth j cuts at radius D/2 + runout_m[j] [m] (N entries; empty: none), as
  // simulation.hpp's Cutter::runout_m. Which surface each tooth cuts — and so its delay and its
  // static chip — then depends on the feed (milling_delay_system), given here.
  std::vector<double> runout_m{};
  double feed_per_tooth_m = 0.0;  // c > 0 [m], required with runout (mean feed per tooth)
  double diameter_m = 0.0;        // D [m]: with it, runout is checked against the radius (0: not checked)
  // Process damping (Budak & Tunç, CIRP Annals 58 (2009) 403; Wu's indentation model): the flank's
  // contact adds a damping force −C_i b ṙ_n/V normal to the cut surface per engaged tooth, ṙ_n =
  // u·ṙ, u = (sin φ, cos φ), V = πDn/60 (needs diameter_m): equivalent damping C_i·b/V [N·s/m]
  // that grows as the speed falls. C_i [N/m] within kProcessDampingMin…kProcessDampingMax; 0: none.
  // Teeth are taken as in contact over the engagement (with runout too).
  double process_damping_n_per_m = 0.0;
  // Helix (docs/reference.md §11; Altintas, Manufacturing Automation, 2nd ed., §2.3): the edge of
  // tooth j at height z above the tool tip lags its tip by κ_j z, κ_j = tan β_j / R (R = D/2, needs
  // diameter_m), so the cut is an integral over the axial depth. Empty: straight flutes; one angle
  // [rad]: every tooth; N angles: a variable helix (each tooth its own). Each in [0, 80°]. The
  // time-domain stability integrates the directional matrix exactly over the lagged angles; with a
  // variable helix the delay between teeth changes along z and the depth is cut into
  // `helix_slices` axial slices, each with its own delays. Only the time-domain stability uses it.
  std::vector<double> helix_rad{};
  // Axial slices for a variable helix, 1…200 (0: 8). Each slice's delays are those at its
  // mid-height (a midpoint rule in z: error falling like 1/slices²). A uniform helix needs none:
  // every slice has the same delay, and its integral over z is exact.
  int helix_slices = 0;
  // Throws InvalidArgument naming `CuttingConditions::<field>`: the ranges of cutting_fields() (a
  // K_t in N/mm², a diameter in mm refused as cannot be meant), then what lies between fields (pitch
  // angles of the wrong count or not adding up to a revolution, runout beyond the radius or over
  // 1 mm, runout without a feed, process damping or a helix without the diameter, a helix angle
  // negative or over 80°, …).
  void check() const;
  // Every tooth cuts alike: evenly spaced teeth (pitch_rad empty, or all its angles equal within
  // 1e-12 rad), no runout (or the same on every tooth) and one helix angle. The principal period
  // is then the tooth period, and (straight flutes) the zero-order method applies.
  bool uniform() const;
  // A helix angle > 0 on some tooth: the milling equation's coefficients depend on the depth.
  bool helical() const;
  // Tooth j's helix angle [rad] (0 without helix).
  double helix_of(int tooth) const;
  // The principal period of the milling equation in tooth periods 60/(N n): 1 when uniform(), N (a
  // revolution) otherwise.
  int teeth_per_period() const { return uniform() ? 1 : teeth; }
};
// CuttingConditions' scalar fields (option_fields.hpp): teeth (--teeth; plan [cut] teeth),
// tangential_coefficient (--kt; tangential_coefficient), radial_ratio (--kr; radial_ratio; the CLI's
// --kn and the plan's normal_coefficient are the alternative K_n = K_r·K_t, converted beside the
// table), feed_per_tooth_m (--feed, in mm; the plan's is PlanOptions'), diameter_m (--diameter, in
// mm; the plan's each candidate's tool), process_damping_n_per_m (--process-damping;
// process_damping; 0: none) and helix_slices (0: 8). The engagement and the per-tooth lists are
// checked beside the table.
const std::vector<OptionField<CuttingConditions>>& cutting_fields();

// α(φ₁, φ₂) = ∫_{φ₁}^{φ₂} A(φ) dφ (docs/reference.md §7, Altintas & Budak 1995 Eq. 10), dimensionless:
//   α_xx = ½[cos2φ − 2K_rφ + K_r sin2φ], α_xy = ½[−sin2φ − 2φ + K_r cos2φ],
//   α_yx = ½[−sin2φ + 2φ + K_r cos2φ],  α_yy = ½[−cos2φ − 2K_rφ − K_r sin2φ]   evaluated φ₁…φ₂.
Eigen::Matrix2d directional_integral(double radial_ratio, double phi1, double phi2);
// α over the engagement φ_st…φ_ex: the time average of the summed tooth matrices is (N/2π)·α.
Eigen::Matrix2d directional_factors(const CuttingConditions& cutting);

// An evenly spaced grid of spindle speeds MIN…MAX [rpm], both ends included.
struct SpeedRange {
  double min_rpm = 0.0;
  double max_rpm = 0.0;
  int points = 1000;
  // Throws InvalidArgument naming `SpeedRange::<field>`: the ranges of speed_range_fields() (a
  // speed no spindle turns at refused as cannot be meant), then MIN < MAX.
  void check() const;
  std::vector<double> values() const;
};
// SpeedRange's fields (option_fields.hpp): min_rpm, max_rpm (plan [machine] speed_min, speed_max;
// the CLI's --rpm MIN:MAX is one pair, parsed beside the table) and points (--speeds; speed_points).
const std::vector<OptionField<SpeedRange>>& speed_range_fields();

// ---- Zero-order approximation (Altintas & Budak 1995; Budak & Altintas 1998) -------------------

// The tool point FRFs the zero-order method works from, all on one frequency grid [Hz], in m/N.
struct MillingFrfs {
  FrfSeries xx;                 // G_xx
  std::optional<FrfSeries> yy;  // G_yy; absent: G_yy = G_xx (a symmetric tool)
  std::optional<FrfSeries> xy;  // cross FRFs G_xy, G_yx: both or neither; absent: zero
  std::optional<FrfSeries> yx;
  bool rigid_y = false;  // G_yy = G_xy = G_yx = 0: flexible in x only (the 1-DOF model)

  // Throws InputError (data: NaN, grids that differ, one cross FRF without the other, a direct
  // FRF that is not a passive point receptance in the e^{iωt} convention: Im G > 0 at its largest
  // |G|, as the conjugate convention e^{−iωt} or a sign slip gives). `x_name`, `y_name` name G_xx
  // and G_yy in the messages (a file name).
  void check(const std::string& x_name = "G_xx", const std::string& y_name = "G_yy") const;
};

// A direct (point) receptance of a passive structure dissipates: Im G(ω) < 0 at every ω > 0 in the
// e^{iωt} convention (conventions.hpp). Measurement noise can tip the sign where |G| is small, never
// at a resonance peak; there Im G > 0 means the conjugate convention e^{−iωt} or a sign slip
// (every peak shows it), or a structure that feeds energy in at that mode (negative damping: an
// assembly whose joint damping matrix is not positive definite), which chatters at any depth.
// The first resonance peak (prominence ≥ 0.3, ≈ 3 dB; at least 1 % of the largest |G|) with
// Im G > 0 as a mode of negative damping shows it — a fifth of |G| or more (G ≈ +iA at its peak),
// and Im G > 0 at the points beside it too — if any: noise on a raw measured FRF makes one-point
// peaks, and peaks where a slightly positive Im G is its phase bias; neither is dissipation.
struct PassivityViolation {
  double frequency_hz = 0.0;
  Complex value;                                        // G at that peak [m/N]
  double share = 0.0;                                   // |G| there / the largest |G|
  int violating = 0, peaks = 0;                         // how many of the resonance peaks have Im G > 0, of how many
  std::string describe(const std::string& what) const;  // the message, naming `what`
};
std::optional<PassivityViolation> passivity_violation(const FrfSeries& direct_frf);

// The FRFs of a modal model (x and y modes uncoupled, G_xy = G_yx = 0) on a frequency grid.
MillingFrfs modal_milling_frfs(const std::vector<Mode>& x_modes, const std::vector<Mode>& y_modes,
                               const std::vector<double>& frequency_hz);
// A frequency grid [Hz] that resolves every mode's resonance (steps ≤ ζf/20 over f(1 ± 20ζ)) and
// spans 0.3…3 × the mode frequencies: fine enough for the zero-order floor to ~1e-5.
std::vector<double> modal_frequency_grid(const std::vector<Mode>& modes);

struct LobePoint {
  int lobe = 0;             // k: k whole chatter waves plus ε/2π between successive teeth
  int root = 0;             // which eigenvalue of the quadratic (0 or 1), tracked continuously in f
  double speed_rpm = 0.0;   // n = 60 ω_c / (N (ε + 2kπ))
  double depth_m = 0.0;     // a_lim = −2πΛ_R(1 + κ²)/(N K_t) [m]
  double chatter_hz = 0.0;  // ω_c/2π
};

struct EnvelopePoint {
  double speed_rpm = 0.0;
  double depth_m = 0.0;     // minimum over all lobes at this speed [m]; +inf where no lobe reaches
  double chatter_hz = 0.0;  // of the limiting lobe (NaN where none)
  int lobe = -1;            // the limiting lobe k (−1 where none)
};

struct ZeroOrderOptions {
  int lobes = -1;                     // K: lobes k = 0…K; −1 chooses K so the lobes cover speeds.min_rpm
  SpeedRange speeds{0.0, 0.0, 2000};  // where lobe points are kept, and the envelope's grid
  double max_depth_m = 0.0;           // lobe points deeper than this are left out (0: keep all)
  // Throws InvalidArgument naming `ZeroOrderOptions::<field>` (the ranges of zero_order_fields())
  // or the speed range's.
  void check() const;
};
// ZeroOrderOptions' scalar fields (option_fields.hpp): lobes (−1: automatic; flag --lobes),
// max_depth_m (--max-depth, in mm). The lobes study's `lobes` is this field.
const std::vector<OptionField<ZeroOrderOptions>>& zero_order_fields();

// What every lobe shares, per chatter frequency of the FRF grid and root of the quadratic: lobe k
// has the same depth and chatter frequency at speed n_k = speed_factor / (phase + k), so the lobe
// points are a view of this table (1 division each), not stored.
struct LobeTable {
  std::vector<double> chatter_hz;    // the FRF grid [Hz]
  std::vector<double> speed_factor;  // 60 f/N [rpm]
  std::vector<double> depth_m[2];    // a_lim [m]; NaN where Λ_R ≥ 0 (no positive depth) or no root
  std::vector<double> phase[2];      // ε/2π in (0, 1)
};

struct ZeroOrderResult {
  Eigen::Matrix2d alpha;          // directional factors α over the engagement
  double floor_depth_m = 0.0;     // absolute stability limit: min over ω_c and both roots of a_lim
  double floor_chatter_hz = 0.0;  // … and its chatter frequency
  int lobes = 0;                  // K used
  LobeTable table;
  int teeth = 0;             // N
  SpeedRange speeds;         // the range lobe points are kept in
  double max_depth_m = 0.0;  // lobe points deeper than this are left out (0: none)
  std::vector<EnvelopePoint> envelope;
  std::vector<std::string> warnings;
  // With speed-dependent FRFs (zero_order_lobes of SpeedDependentFrfs): every lobe point solved at
  // its own speed, by lobe, root and chatter frequency (the table then holds the first speed's
  // roots, not the points). Empty otherwise.
  std::vector<LobePoint> solved_points;

  // Calls visit(point) for every lobe point with speed in range (and depth ≤ max_depth_m), by
  // lobe, then root, then chatter frequency.
  template <typename Visit>
  void for_each_point(Visit&& visit) const;
  std::vector<LobePoint> points() const;
};

// Stability lobes by the zero-order approximation, directly from the FRFs (no modal fit). At each
// chatter frequency ω_c of the grid, the two roots of det(I + Λ α G(iω_c)) = 0,
//     a₀Λ² + a₁Λ + 1 = 0,  a₀ = det α · det G,  a₁ = tr(α G)
// (with G_xy = G_yx = 0: a₀ = G_xx G_yy(α_xx α_yy − α_xy α_yx), a₁ = α_xx G_xx + α_yy G_yy), give
// Λ = −N a K_t (1 − e^{−iω_c τ})/(4π). Only Λ_R < 0 gives a positive depth a_lim = −2πΛ_R(1+κ²)/(N K_t),
// κ = Λ_I/Λ_R = cot(ω_c τ/2). The phase ε = ω_c τ − 2kπ = 2·atan2(−Λ_R, −Λ_I) ∈ (0, 2π) (the
// printed ε = π − 2 atan κ on its principal branch), so τ = (ε + 2kπ)/ω_c and n = 60/(Nτ).
// The envelope is the minimum over lobes and roots, each lobe a polyline in (speed, depth)
// interpolated linearly between neighbouring grid frequencies.
// Throws InvalidArgument (bad conditions or options), InputError (bad FRFs), NumericalError when
// no frequency gives a positive depth (no regenerative chatter possible: check the FRF's sign).
ZeroOrderResult zero_order_lobes(const MillingFrfs& frfs, const CuttingConditions& cutting, const ZeroOrderOptions& options);

// Lobe k can only reach speeds in (60f/(N(k+1)), 60f/(Nk)): the index range of the table's
// frequencies that can map into [min_rpm, max_rpm], widened by one point on each side so segments
// crossing the range ends are kept.
std::pair<std::size_t, std::size_t> lobe_window(const LobeTable& table, int teeth, int lobe, double min_rpm, double max_rpm);

template <typename Visit>
void ZeroOrderResult::for_each_point(Visit&& visit) const {
  if (!solved_points.empty()) {
    for (const LobePoint& p : solved_points)
      if (!(max_depth_m > 0.0 && p.depth_m > max_depth_m) && p.speed_rpm >= speeds.min_rpm && p.speed_rpm <= speeds.max_rpm)
        visit(p);
    return;
  }
  for (int k = 0; k <= lobes; ++k) {
    const auto [i0, i1] = lobe_window(table, teeth, k, speeds.min_rpm, speeds.max_rpm);
    for (int r = 0; r < 2; ++r)
      for (std::size_t i = i0; i < i1; ++i) {
        const double d = table.depth_m[r][i];
        if (!(d > 0.0) || (max_depth_m > 0.0 && d > max_depth_m)) continue;
        const double n = table.speed_factor[i] / (table.phase[r][i] + k);
        if (n >= speeds.min_rpm && n <= speeds.max_rpm) visit(LobePoint{k, r, n, d, table.chatter_hz[i]});
      }
  }
}

// The zero-order absolute stability limit alone [m] (speed independent), and its chatter
// frequency [Hz] through `chatter_hz` when not null. Same errors as zero_order_lobes.
double zero_order_floor(const MillingFrfs& frfs, const CuttingConditions& cutting, double* chatter_hz = nullptr);

// ---- Zero-order lobes with speed-dependent dynamics ---------------------------------------------
//
// The tool point FRFs at several spindle speeds (a spinning spindle's gyroscopic moments, bearings
// whose stiffness changes with speed; docs/spindle-at-speed.md), taken linear in the speed n
// between two neighbouring nodes n_j ≤ n ≤ n_{j+1}:
//     G(ω; n) = G_j(ω) + t (G_{j+1}(ω) − G_j(ω)),  t = (n − n_j)/(n_{j+1} − n_j),
// and equal to the end node's outside them. Each lobe point then sits at its own speed: lobe k at
// chatter frequency f and root r is a solution n of
//     n = 60 f / (N (ε(f; n)/2π + k)),
// ε(f; n) the phase of docs/reference.md §7 from the eigenvalue of α G(f; n) (zero_order_lobes).
// Speed-independent FRFs give zero_order_lobes' points and envelope (up to rounding).
struct SpeedDependentFrfs {
  std::vector<double> speed_rpm;  // the nodes [rpm], ≥ 0, strictly increasing, at least one
  std::vector<MillingFrfs> frfs;  // per node: on one frequency grid, with the same FRFs present
  // Throws InputError naming `name` (sizes, grids or FRFs that differ between nodes, nodes out of
  // order, and what MillingFrfs::check finds at each node).
  void check(const std::string& name = "tool point FRF") const;
  // G(ω; n) on the frequency grid, interpolated as above [m/N].
  MillingFrfs at(double speed_rpm) const;
};

// Zero-order lobes with FRFs that depend on the speed (above). The envelope at each speed n of
// options.speeds is that of the lobes of G(·; n), read at n (zero_order_lobes' envelope of that one
// FRF at n: speeds on `parallel` threads, identical for any count). The lobe points (for figures and
// tables): per lobe k, root r (labelled continuously along the frequencies at the first node, then
// along the nodes) and grid frequency, every zero of sf/(φ(n) + k) − n bracketed between nodes (or
// beyond the end nodes, where G is held) solved by regula falsi to 1e-10 relative; up to 4 per
// frequency where a lobe folds back in speed; what cannot be solved is counted in a warning. The
// floor: the lowest over the nodes' FRFs and those at the envelope's speeds. Same errors as
// zero_order_lobes.
ZeroOrderResult zero_order_lobes(const SpeedDependentFrfs& frfs, const CuttingConditions& cutting,
                                 const ZeroOrderOptions& options, const ParallelOptions& parallel = {});

// ---- Time-domain stability: full-discretization of the milling equation ----------------------
//
// The milling equation in modal coordinates q (each mode a 1-DOF oscillator seen at the tool point):
//     q̈_r + 2ζ_rω_r q̇_r + ω_r² q_r = F_{dir(r)}(t)/m_r,   F(t) = ½ a K_t A(t) (r(t) − r(t − τ)),
// r = (Σ_{x modes} q_r, Σ_{y modes} q_r) the tool-tip displacement, A(t) = Σ_j g_j A(φ_j(t)) over
// the teeth in the cut (Insperger & Stépán, IJNME 61 (2004) 117–141, Eq. 1–6 in this notation).
// It is discretized by periodic_delay.hpp (full-discretization: only the constant part is
// exponentiated, A(t) integrated exactly, r interpolated by a degree-p polynomial; p = 2 by default,
// third order) and its stability read from the dominant Floquet multiplier of the period map.
// Only the tip displacement is delayed: the map acts on the 2n_q modal states and 1 (rigid y) or 2
// tip values per step that the cut reads.

// One pole-residue pair of the tool point receptance block, added to the real modes' block:
//     G_{to,from}(iω) += R/(iω − λ) + R̄/(iω − λ̄).
// A complex residue carries what real modes cannot: the skew (gyroscopic) part of G_xy, whose
// forward and backward whirls enter with opposite signs, and (to = from) the shape of a direct
// FRF whose two whirls lie closer than their damping. In the milling equation it is a state
// z ∈ ℂ (two real states u + iv): ż = λz + F_from, and the tip displacement in `to` gains
// 2 Re(R z) (so its Laplace transform is the term above). Its velocity output is 2 Re(Rλz): the
// direct term 2 Re(R)F is left out, as a receptance has none (relative degree 2; in a fit it is
// the fit's error).
struct ResidueTerm {
  int to = 0;                    // 0: the x displacement, 1: y
  int from = 0;                  // 0: the x force, 1: y
  std::complex<double> pole;     // λ [rad/s], Re λ < 0
  std::complex<double> residue;  // R [m/(N s)]
};

// Modes of the tool point in x and in y (uncoupled; each a 1-DOF oscillator seen at the tool
// point, see Mode), and optional pole-residue terms added to them (coupling x and y, or reshaping
// a direct FRF). An empty y list means the tool is rigid in y (the 1-DOF milling model; terms then
// only from x to x).
struct ModalModel {
  std::vector<Mode> x;
  std::vector<Mode> y;
  std::vector<ResidueTerm> terms;  // empty: the real modes alone
  // Throws InvalidArgument: no x mode, a bad mode, or ζ = 0 (undamped: zero depth is already
  // marginal, there is no stable region to bound); a term reading or driving y without y modes,
  // a direction other than 0 or 1, a pole not in the left half-plane or a non-finite residue
  // (naming ModalModel::terms[i]).
  void check() const;
};

enum class BoundaryKind {
  Hopf,  // a complex pair of Floquet multipliers leaves the unit circle: quasi-periodic chatter
  Flip,  // a multiplier leaves at −1: period doubling, chatter at (j + ½) × tooth passing frequency
  Fold,  // a multiplier leaves at +1 (not expected in milling; reported if seen)
  None,  // no instability found up to the maximum depth
};
const char* to_string(BoundaryKind kind);

// What the period map says at one speed and depth.
struct FloquetAnalysis {
  double spectral_radius = 0.0;            // max |μ|; < 1 is asymptotically stable
  Complex critical_multiplier;             // the multiplier of largest modulus (Im ≥ 0 of a pair)
  BoundaryKind kind = BoundaryKind::None;  // Hopf, Flip or Fold from the critical multiplier's phase
  double chatter_hz = 0.0;                 // dominant frequency of the critical Floquet solution
  int lobe = -1;                           // floor(chatter_hz · τ): whole waves per tooth period (−1 if unknown)
  int matrix_size = 0;                     // size of the reduced period map whose multipliers were taken
};

struct BoundaryPoint {
  double speed_rpm = 0.0;
  // The lowest depth where ρ reaches 1 [m] (max_depth_m when kind is None): Richardson's
  // extrapolation a_{2m} + (a_{2m} − a_m)/(2^{p+1} − 1) of the roots at m and 2m steps.
  double depth_m = 0.0;
  // Estimated discretization error [m]: |a_{2m} − a_m|/(2^{p+1} − 1), the error of a_{2m} by
  // Richardson; an upper estimate for depth_m, whose leading error term is removed. NaN for None.
  double depth_error_m = 0.0;
  int steps = 0;            // 2m, the finer level (0 when found at one fixed level)
  double chatter_hz = 0.0;  // NaN when kind is None
  int lobe = -1;
  BoundaryKind kind = BoundaryKind::None;
  Complex multiplier;  // critical multiplier just above the boundary
};

// The milling equation at one speed as a PeriodicDelaySystem. Variable pitch (Altintas, Engin &
// Budak, J. Manuf. Sci. Eng. 121 (1999) 173; Insperger & Stépán 2004 §5): the period is a
// revolution T = 60/n, tooth j at φ_j(t) = Ωt − Σ_{i<j} p_i has its own delay τ_j = p_{j−1}/Ω (the
// time since the tooth before it passed the same angle), and
//     u(t) = σ Σ_j ½K_t g_j A(φ_j) (r(t) − r(t − τ_j)),
// built as P = Σ_j ½K_t g_j A(φ_j) and one PeriodicDelaySystem::delays term per distinct delay;
// with a feed, tooth j's static chip is N c p_{j−1}/(2π) sin φ_j. Runout (Insperger, Mann, Surmann
// & Stépán, IJMTM 48 (2008) 586; the chip of simulation.hpp linearised about the static cut): tooth
// j at φ regenerates against the outermost surface q* pitches back, delay Θ_{q*}/Ω (one
// revolution at most), and is out of the cut where its static chip ρ_j − ρ_{j−q*} + C_{q*} sin φ ≤ 0
// (C_q = N c Θ_q/2π); `feed_per_tooth_m` > 0 must then equal CuttingConditions::feed_per_tooth_m.
// Uniform pitch: per mode the block
// [[0, 1], [−ω_r², −2ζ_rω_r]] on (q_r, q̇_r); B puts the force on q̈_r with 1/m_r; C reads the tip
// displacement; P(t) = ½K_t A(t) [N/m²] with σ the depth a [m], regenerative; breakpoints at the
// teeth's entry and exit. One output (x) when the model has no y mode. With a feed per tooth c > 0
// [m], the forcing w(t) of the static chip c sin φ_j (per unit depth; PeriodMap::periodic_solution
// then gives the forced periodic motion of a stable cut). Throws InvalidArgument.
// With CuttingConditions::process_damping_n_per_m > 0 the system carries the velocity feedback
// −(C_i/V) Σ_j g_j u_j u_jᵀ ṙ per unit depth (with_velocity_feedback: outputs 0…d−1 the tip
// displacement, d…2d−1 its velocity).
// Throws InvalidArgument with a helix (the system depends on the depth: milling_delay_system_at_depth).
PeriodicDelaySystem milling_delay_system(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm,
                                         double feed_per_tooth_m = 0.0);
// The milling equation at one speed and axial depth `depth_m` [m] ≥ 0 (its gain σ is still the
// depth). Straight flutes: milling_delay_system, whatever the depth. With a helix
// (CuttingConditions::helix_rad, docs/reference.md §11), tooth j at height z is at φ_j(t) − κ_j z,
// κ_j = tan β_j/R, and each coefficient is the average over the depth,
//     P(t) = (1/a) ∫₀ᵃ Σ_j ½K_t g A(φ_j(t) − κ_j z) dz = Σ_j ½K_t/(κ_j a) ∫_{φ_j − κ_j a}^{φ_j} g A(ψ) dψ,
// integrated in closed form between the angles where g (entry, exit; with runout the surface cut)
// changes; process damping's u uᵀ and the static chip's force alike. A uniform helix keeps one
// delay per tooth (the tooth period when uniform()); a variable helix gives tooth j at slice s the
// delay (p_{j−1} + z_s (κ_j − κ_{j−1}))/Ω, z_s the slice's mid-height (slices of equal height, each
// integrated exactly in φ). Throws InvalidArgument (as milling_delay_system; a delay that is not
// positive or exceeds a revolution at this depth).
PeriodicDelaySystem milling_delay_system_at_depth(const ModalModel& model, const CuttingConditions& cutting, double speed_rpm,
                                                  double depth_m, double feed_per_tooth_m = 0.0);
// The cutting speed V = πDn/60 [m/s] of CuttingConditions::diameter_m at `speed_rpm`.
double cutting_speed(const CuttingConditions& cutting, double speed_rpm);
// The tip velocity's C_v (d × 2n_q) of the milling system's state: x (and y) velocities summed over the modes.
Eigen::MatrixXd velocity_output(const ModalModel& model);

// Stability of the milling equation at a fixed number of steps per tooth period.
// Steps per tooth period m: the map is built with m · cutting.teeth_per_period() steps per period.
class FullDiscretization {
 public:
  // Throws InvalidArgument (bad model or conditions, steps outside 4…20000, degree outside 1…3, or
  // with Discretization::Semi the order outside 0…1).
  FullDiscretization(ModalModel model, CuttingConditions cutting, int steps = 40, int degree = 2,
                     Discretization scheme = Discretization::Full);

  // Throws InvalidArgument with a helix (the map depends on the depth: the overload below).
  PeriodMap period_map(double speed_rpm) const;
  // The map at a depth [m] (milling_delay_system_at_depth); with straight flutes any depth gives
  // the same map.
  PeriodMap period_map(double speed_rpm, double depth_m) const;
  double spectral_radius(double speed_rpm, double depth_m) const;
  // The spectral radius with the critical multiplier, its kind, and the chatter frequency: the
  // strongest harmonic (arg μ + 2πj)/(2πτ) of the critical Floquet solution's tip displacement over
  // one tooth period (resolved up to m/(2τ) Hz).
  FloquetAnalysis analyse(double speed_rpm, double depth_m) const;
  // ρ on a grid: result(i, j) at speeds_rpm[i], depths_m[j]; speeds on `parallel` threads
  // (identical results for any thread count).
  Eigen::MatrixXd spectral_radius_map(const std::vector<double>& speeds_rpm, const std::vector<double>& depths_m,
                                      const ParallelOptions& parallel = {}) const;
  // The lowest depth where ρ reaches 1 at this speed, ρ scanned up from 0 in `depth_steps` equal
  // steps to max_depth_m, the first stable → unstable step then narrowed by regula falsi
  // (Anderson–Björck) to a relative width of `tolerance`. Kind None (depth = max_depth_m) when ρ < 1
  // throughout. No error estimate (see stability_boundary).
  BoundaryPoint boundary(double speed_rpm, double max_depth_m, int depth_steps = 50, double tolerance = 1e-7) const;

  const ModalModel& model() const { return model_; }
  const CuttingConditions& cutting() const { return cutting_; }
  int steps() const { return steps_; }
  int degree() const { return degree_; }
  Discretization scheme() const { return scheme_; }

 private:
  ModalModel model_;
  CuttingConditions cutting_;
  int steps_, degree_;
  Discretization scheme_;
};

// The order q of the boundary's discretization error (it falls like m^−q): p + 1 for
// full-discretization of degree p; 2 for semi-discretization of either order, whose averaged
// coefficients (midpoint rule, jumps at entry and exit smeared over a step) limit it — measured in
// tests/semi_discretization_test.cpp. Richardson's extrapolation of stability_boundary uses it.
int boundary_error_order(Discretization scheme, int degree);

struct BoundaryOptions {
  SpeedRange speeds{0.0, 0.0, 200};
  // Target for the estimated discretization error of each depth, relative to it (0.01: 1 %). The
  // steps per tooth period are doubled until the estimate meets it (or max_steps is reached).
  double tolerance = 0.01;
  int steps = 0;         // steps m of the first level; 0: 12 per chatter wave per tooth period, ≥ 16
  int max_steps = 4000;  // no level finer than this
  int degree = 2;        // interpolation degree p (1…3); the error falls like m^−(p+1)
  // Full-discretization, or semi-discretization with `degree` the order (0 or 1) of its delayed term.
  Discretization scheme = Discretization::Full;
  double max_depth_m = 0.0;  // depths searched up to this [m]; 0: 10 × the zero-order floor of the model
  ParallelOptions parallel;  // speeds on this many threads; results identical for any count
  // Called with the fraction of speeds done (0…1], one call at a time (the library never prints).
  std::function<void(double fraction)> progress;
  // Throws InvalidArgument naming `BoundaryOptions::<field>`: the ranges of boundary_fields(), steps
  // above max_steps/2, a degree outside the scheme's (full 1…3, semi 0…1), the speed range's.
  void check() const;
};
// BoundaryOptions' scalar fields (option_fields.hpp): tolerance (--tolerance, in %), steps
// (0: automatic; --intervals), max_steps, degree (0…3; the scheme's range beside it), max_depth_m
// (--max-depth, in mm), and parallel.threads (parallel_fields()). The lobes study's time-domain
// fields are these.
const std::vector<OptionField<BoundaryOptions>>& boundary_fields();
// BoundaryOptions::steps as a study that leaves max_steps at its default takes it (the lobes
// study's, the pitch search's): the first level at most half the default max_steps (the error
// estimate compares m with 2m steps), described by `help`.
FieldSpec study_steps_field(const char* help);

struct BoundaryResult {
  std::vector<BoundaryPoint> boundary;  // one per speed of the grid
  double max_depth_m = 0.0;             // the ceiling searched
  double tolerance = 0.0;               // the error target (relative)
  int degree = 0;
  Discretization scheme = Discretization::Full;
  long evaluations = 0;  // spectral radii computed
  std::vector<std::string> warnings;
  // The largest depth_error_m/depth_m over the speeds with a boundary (0 if none).
  double worst_relative_error() const;
};

// The stability boundary at every speed of options.speeds, with its error estimate. Per speed:
// the roots of ρ(a) = 1 at m and 2m steps (regula falsi in a bracket found by a geometric scan
// up from below the neighbouring speed's limit, or from a third of the zero-order limit for the
// first speed of each block of 8), m doubled until the estimated error meets the tolerance.
// Stable islands above the first boundary are not reported: the lowest unstable depth is. An
// unstable band below the scan's start (70 % of the neighbour's depth) or narrower than a scan step
// (20 %) can be missed. With a helix the map depends on the depth: each depth the search
// evaluates gets its own map (milling_delay_system_at_depth), built anew (a map costs about as
// much as its spectral radius), so ρ(a) is the same continuous function the root finder expects.
// Throws InvalidArgument (bad model, conditions or options), NumericalError.
BoundaryResult stability_boundary(const ModalModel& model, const CuttingConditions& cutting, const BoundaryOptions& options);

// The boundary with a modal model per speed (a structure that changes with the spindle speed):
// models[i] at options.speeds.values()[i], each speed's limit from its own model exactly as above.
// The starting guesses and the default ceiling (10 × guesses.floor_depth_m) come from `guesses`,
// zero-order lobes on the same speed grid (e.g. of the FRFs the models were fitted to). Throws
// InvalidArgument (a count of models other than the speeds', bad models, conditions or options,
// guesses on another grid), NumericalError.
BoundaryResult stability_boundary(const std::vector<ModalModel>& models, const ZeroOrderResult& guesses,
                                  const CuttingConditions& cutting, const BoundaryOptions& options);

// ---- Results for people ---------------------------------------------------------------------

// The best spindle speeds: local maxima of the envelope depth whose prominence — the depth above
// the higher of the lowest envelope points separating them from a deeper maximum (or the range
// end) — is at least `min_prominence` × their depth (0.02: 2 %). Deepest first, at most `count`.
std::vector<EnvelopePoint> stability_pockets(const std::vector<EnvelopePoint>& envelope, int count, double min_prominence = 0.02);

// The stability boundary as an envelope (kind None rows keep depth = the search ceiling, lobe −1).
std::vector<EnvelopePoint> boundary_envelope(const BoundaryResult& result);

}  // namespace toolpoint
