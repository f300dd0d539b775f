// toolpoint: the spindle–holder–tool assembly (seed Section 2.1, after Ertürk et al. 2006).
//
// Components are chains of uniform Timoshenko segments joined by rigid receptance coupling,
// listed from their end 1 (outer, towards the tool tip) inwards:
//   spindle  S: from the spindle nose to the rear, with bearings (springs and dampers to ground,
//               translational and optionally rotational) added by structural modification;
//   holder   H: from the holder tip to its taper end; where the tool shank sits inside the bore
//               the section is composite (holder sleeve + shank: EI, κGA, ρA, ρI add), so H is
//               "the spindle–holder without the part of the cutting tool outside the holder";
//   tool     T: the part of the tool outside the holder, from the tip: fluted part with an
//               equivalent diameter, then shank.
// Elastic coupling through the joints (seed Eq. 1–5):
//   SH11  = H11 − H12 (H22 + K_sh⁻¹ + S11)⁻¹ H21        holder tip, tool outside removed
//   SHT11 = T11 − T12 (T22 + K_ht⁻¹ + SH11)⁻¹ T21       tool point
//   HT    = T coupled to H through K_ht (the holder–tool subassembly of Eq. 17)
// Units: SI (m, kg, N, Pa, s); frequencies in Hz. Sign convention: conventions.hpp.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/model/beam.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/model/joint.hpp"
#include "toolpoint/model/receptance.hpp"

namespace toolpoint {

// One row of a bearing's speed table: its translational stiffness and damping at a spindle speed
// (from the spindle maker or an identification; preload and centrifugal softening change them).
struct BearingSpeedPoint {
  double speed_rpm = 0.0;  // rpm, ≥ 0
  double stiffness = 0.0;  // N/m, ≥ 0
  double damping = 0.0;    // N·s/m, ≥ 0
};

// A bearing: springs and dampers to ground at `position` metres from the spindle nose.
struct Bearing {
  std::string name;                   // for messages ("spindle.bearing[2]")
  double position = 0.0;              // m from the spindle nose, inwards
  double stiffness = 0.0;             // N/m
  double damping = 0.0;               // N·s/m
  double rotational_stiffness = 0.0;  // N·m/rad
  double rotational_damping = 0.0;    // N·m·s/rad
  // The y direction's translational values where they differ from x (anisotropic bearing; x, y as
  // in beam.hpp's spinning segment): N/m, N·s/m; unset: as x. Only the two-plane model
  // (AssemblyModel::tool_point_two_plane) sees them; the rotational values are the same in both.
  std::optional<double> stiffness_y, damping_y;
  // Stiffness and damping against speed (rows by strictly increasing speed; both directions, so
  // not with stiffness_y/damping_y); empty: the constants above at every speed. Read at a speed by
  // at_speed(): linear between rows.
  std::vector<BearingSpeedPoint> speed_table;

  Block dynamic_stiffness(double frequency_hz) const;    // diag(k + iωc, k_θ + iωc_θ), the x plane
  Block dynamic_stiffness_y(double frequency_hz) const;  // the y plane's
  bool isotropic() const;                                // y as x
  void check() const;
};

struct Spindle {
  std::vector<Segment> segments;  // nose → rear
  std::vector<Bearing> bearings;
};

// A solid end mill: fluted part (equivalent diameter) from the tip, then the shank.
struct Tool {
  Material material;
  double length = 0.0;                // total length [m]
  double overhang = 0.0;              // length outside the holder [m]
  double diameter = 0.0;              // nominal (cutting) diameter [m]
  double shank_diameter = 0.0;        // [m]; 0 means `diameter`
  double flute_length = 0.0;          // fluted length from the tip [m]; 0: no flutes modelled
  double flute_diameter_ratio = 0.8;  // equivalent fluted diameter / nominal (default 0.8, after
                                      // Kivanç & Budak 2004 and Schmitz's RCSA papers)
  std::optional<double> shear_coefficient;

  void check() const;
  // All tool segments from the tip (fluted part, shank).
  std::vector<Segment> segments(ShearModel model) const;
};

enum class ReceptanceMethod { Exact, Modal };

struct Assembly {
  std::string name;
  Spindle spindle;
  std::vector<Segment> holder;  // holder tip → taper end, with its bore
  Tool tool;
  Joint spindle_holder;
  Joint holder_tool;
  ShearModel shear_model = ShearModel::Hutchinson;
  ReceptanceMethod method = ReceptanceMethod::Exact;
  int modal_terms = 100;  // elastic modes per segment for ReceptanceMethod::Modal
  FrequencyGrid grid{10.0, 5000.0, 1.0};

  // Throws InvalidArgument naming the offending item (a bearing outside the spindle, a tool
  // longer than holder + overhang allows, a shank wider than the bore, non-positive sizes, …).
  void check() const;
  // What its parts' sources say against them: its joints' warnings (Joint::warnings), spindle–holder
  // first; then, per bearing, data the standstill single-plane model (AssemblyModel::tool_point,
  // hence the time-domain lobes) does not use: a speed table (read at a stated speed, at_speed: by
  // a prediction at speed and the zero-order lobes and plans at each speed) and y values (read by
  // the two-plane model), so that neither is ignored without a word.
  std::vector<std::string> warnings() const;
};

// A chain of segments from its end 1 inwards, with optional ground springs at the nodes between
// them (node 0 = end 1, node n = end 2). Each segment's end receptances come from the exact
// solution or the modal sum, prepared once.
class Chain {
 public:
  Chain() = default;
  Chain(std::vector<Segment> pieces, ReceptanceMethod method, int modal_terms);
  void add_ground(std::size_t node, const Bearing& b);

  TwoPort piece(std::size_t i, double frequency_hz) const;
  // All four end blocks (rigid coupling of the pieces, ground springs by modification).
  TwoPort two_port(double frequency_hz) const;
  // Only the point receptance at end 1 (a sweep from end 2 outwards: cheaper).
  Block point(double frequency_hz) const;
  // The same for one whirl of the chain spinning at `spin_rad_s` [rad/s] (beam.hpp,
  // whirl_receptance; the ground springs' x values, so for isotropic ones only). At spin 0 the
  // above exactly. Throws InvalidArgument for a spinning chain summed modally (exact pieces only).
  TwoPort two_port(double frequency_hz, double spin_rad_s, Whirl whirl) const;
  Block point(double frequency_hz, double spin_rad_s, Whirl whirl) const;
  // The point receptance at end 1 in both planes (4×4 on w_x, ψ_x, w_y, ψ_y), the pieces
  // spinning at `spin_rad_s` (spinning_receptance), the ground springs with their x and y values.
  Block4 point_two_plane(double frequency_hz, double spin_rad_s) const;
  std::size_t size() const { return pieces_.size(); }
  const std::vector<Segment>& segments() const { return pieces_; }
  const std::vector<SectionProperties>& properties() const { return props_; }  // per piece
  // The ground springs at node k (0 = end 1, size() = end 2).
  const std::vector<Bearing>& grounds(std::size_t node) const { return ground_.at(node); }
  // True when some piece is summed modally (the modal method); false when all are exact.
  bool has_modal_pieces() const;
  double length() const;
  ReceptanceMethod method() const { return method_; }
  int modal_terms() const { return modal_terms_; }
  // What the chain could not do as asked (a composite piece whose layers have different loss
  // factors is computed exactly under the modal method: the modal sum needs one loss factor).
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  // piece(i, f), reusing `waves` when piece i has the section they were made for (consecutive
  // pieces of one cut segment) and refreshing them otherwise.
  TwoPort piece(std::size_t i, double frequency_hz, double spin_rad_s, Whirl whirl, SectionWaves& waves,
                const SectionProperties*& waves_of) const;

  std::vector<Segment> pieces_;
  std::vector<SectionProperties> props_;
  std::vector<std::shared_ptr<const ModalBeam>> modal_;  // per piece under the modal method; null: exact
  std::vector<std::vector<Bearing>> ground_;             // per node, size n + 1
  ReceptanceMethod method_ = ReceptanceMethod::Exact;
  int modal_terms_ = 0;
  std::vector<std::string> warnings_;
};

// A free piece's conical whirl pole in the assembly (AssemblyModel::whirl_poles): its frequency and
// the relative half-width of the window around it inside which the spinning tool point is taken
// from a stencil (AssemblyModel::tool_point with a whirl). The direct coupling's rounding error
// grows as C/d², d the relative distance to the pole (the pole's rank-one residue, ∝ 1/d, enters
// squared; on the example's fluted piece C ≈ 3e-13 of |H|: 3e-9 at d = 1e-2, 2e-3 at 1e-5, 8 % at
// 1e-6). C is estimated per pole from the rounding jitter of the direct coupling at
// d = 1e-3 (the largest change of the block over one- to three-ulp steps of f at fc(1 + 1e-3),
// relative to the block), and window = sqrt(C / kWhirlPoleTolerance), at most kWhirlPoleMaxWindow.
struct WhirlPole {
  double frequency_hz = 0.0;  // conical_whirl_hz [Hz]
  double window = 0.0;        // relative half-width (0: the direct coupling is precise enough)
};
inline constexpr double kWhirlPoleTolerance = 1e-9;
inline constexpr double kWhirlPoleMaxWindow = 2e-2;
// The stencil about f for a window W: G(f) ≈ Σ_k w_k G(f (1 + x_k W)), x = 2, −2, 4, −4,
// w = 2/3, 2/3, −1/6, −1/6: Richardson's (4 A(δ) − A(2δ))/3 of the symmetric means
// A(h) = (G(f(1+h)) + G(f(1−h)))/2, δ = 2W, which is G(f) + O(δ⁴) for a G smooth on the stencil;
// each point lies at least W from the pole that put f in its window. Where the stencil's
// curvature says an assembly resonance is within its reach, W is halved (src/whirl_pole.hpp).
inline constexpr double kWhirlPoleOffsets[4] = {2.0, -2.0, 4.0, -4.0};
inline constexpr double kWhirlPoleWeights[4] = {2.0 / 3.0, 2.0 / 3.0, -1.0 / 6.0, -1.0 / 6.0};
// The window W of the pole whose window holds `frequency_hz` (the widest if several), else 0.
double whirl_pole_window(double frequency_hz, const std::vector<WhirlPole>& poles);

// Splits a chain listed from end 1 at `distance` from end 1: (outer part, inner part).
std::pair<std::vector<Segment>, std::vector<Segment>> split_segments(const std::vector<Segment>& segments, double distance);

// The assembly's components, built once from an Assembly.
class AssemblyModel {
 public:
  explicit AssemblyModel(const Assembly& assembly);

  // Everything at one frequency.
  struct Receptances {
    Block S11;    // spindle nose, bearings included
    TwoPort H;    // holder with the shank inside, free–free
    TwoPort T;    // tool outside the holder, free–free
    Block SH11;   // holder tip of spindle + holder (Eq. 1)
    Block SHT11;  // tool point (Eq. 5)
  };
  Receptances evaluate(double frequency_hz) const;

  Block tool_point(double frequency_hz) const;  // SHT11
  Block holder_tip(double frequency_hz) const;  // SH11
  // The same over a grid of frequencies [Hz], as a series (what predict, lobes and the effect
  // analysis need). Under the exact method the frequencies go four at a time through SIMD lanes
  // (sweep.cpp), by the same closed forms and the same coupling order as the per-frequency
  // functions; only the rounding differs. Both lose accuracy at low frequency, where the coupling
  // subtracts free–free receptances (∝ 1/ω²) far larger than the result: on the example, against
  // an 80-digit evaluation, both are within 1e-9 at 10–13 Hz, 2e-7 at 1 Hz and 3e-15 at 10 kHz
  // (tests: Assembly.AccuracyAgainstAnEightyDigitReference).
  // Frequencies the lanes cannot certify (a near-singular inverse, a value outside the fast
  // formulas' range) and the modal method go through the per-frequency functions, which handle
  // them or throw. A NumericalError names the frequency; InvalidArgument for a frequency that is
  // not > 0. `diagnostics`, if given, counts where the frequencies went.
  struct SweepDiagnostics {
    std::size_t simd = 0;           // through the SIMD lanes
    std::size_t per_frequency = 0;  // one at a time: no lanes here, the modal method, or uncertified
  };
  BlockSeries tool_point(const std::vector<double>& frequency_hz, SweepDiagnostics* diagnostics = nullptr) const;
  BlockSeries holder_tip(const std::vector<double>& frequency_hz, SweepDiagnostics* diagnostics = nullptr) const;
  // Two planes at a spin (docs/reference.md §10; x, y, z and the spin's sense as beam.hpp's
  // spinning segment): the tool point's 4×4 block on (w_x, ψ_x, w_y, ψ_y), [[xx, xy], [yx, yy]]
  // of [[H, L], [N, P]] blocks; joints act alike in both planes, bearings with their x and y
  // values. With isotropic bearings the whirls decouple: two_plane(forward, backward) of the
  // single-plane chain per whirl; at spin 0 then xx = yy = tool_point(f) exactly and xy = yx = 0.
  // Anisotropic bearings: the spindle in 4×4 (Chain::point_two_plane). `spin_rad_s` [rad/s].
  // Throws InvalidArgument for a spinning modal assembly (exact only), NumericalError as tool_point.
  Block4 tool_point_two_plane(double frequency_hz, double spin_rad_s) const;
  // Over a grid [Hz], through the SIMD lanes (sweep.cpp): isotropic bearings once per whirl;
  // anisotropic ones with the spindle walked in the whirl basis (forward, backward), where only the
  // bearings couple the whirls, every 4×4 inverse by 2×2 blocks. Same values as the per-frequency
  // function but for rounding; frequencies the lanes cannot certify go through it. `diagnostics`,
  // if given, counts where the frequencies went (for the anisotropic walk).
  BlockSeries4 tool_point_two_plane(const std::vector<double>& frequency_hz, double spin_rad_s,
                                    SweepDiagnostics* diagnostics = nullptr) const;
  // One whirl's single-plane tool point (isotropic bearings; see Chain::point with a whirl).
  // Near a free piece's conical whirl pole (conical_whirl_hz; within its WhirlPole::window) the
  // piece's receptance is nearly unbounded and the coupling cancels most digits, though the
  // assembly is smooth there: this and tool_point_two_plane (one frequency or a grid) then take
  // the value from the symmetric stencil of kWhirlPoleOffsets, combined by Richardson to O(δ⁴)
  // (docs/spindle-at-speed.md).
  Block tool_point(double frequency_hz, double spin_rad_s, Whirl whirl) const;
  // The conical whirl poles of the free pieces of the three chains spinning at `spin_rad_s` whose
  // rigid-body estimate lies within a factor 1.25 of [f_lo, f_hi] (none at spin 0), with their
  // windows (WhirlPole).
  std::vector<WhirlPole> whirl_poles(double spin_rad_s, double f_lo, double f_hi) const;
  // Every bearing isotropic (Bearing::isotropic).
  bool isotropic() const;
  Block spindle_nose(double frequency_hz) const;   // S11
  TwoPort holder(double frequency_hz) const;       // H
  TwoPort tool(double frequency_hz) const;         // T
  TwoPort holder_tool(double frequency_hz) const;  // HT = T ⊕ H through K_ht (Eq. 17's HT)

  // Receptances between stations on the tool outside the holder, at `distances` from the tip
  // (each in [0, overhang]), the rest of the assembly attached: a 2n×2n matrix of blocks,
  // block (i, j) = response at station i to a load at station j. For finite-difference checks.
  Eigen::MatrixXcd tool_stations(double frequency_hz, const std::vector<double>& distances) const;
  // The same on the holder of the spindle–holder subassembly (the tool outside removed), at
  // `distances` from the holder tip inwards: the stations an SH11 tap test uses.
  Eigen::MatrixXcd holder_stations(double frequency_hz, const std::vector<double>& distances) const;

  const Assembly& assembly() const { return assembly_; }
  // The assembly's warnings (Assembly::warnings), then the chains' (see Chain::warnings).
  std::vector<std::string> warnings() const;
  const Chain& spindle_chain() const { return spindle_; }
  const Chain& holder_chain() const { return holder_; }
  const Chain& tool_chain() const { return tool_; }

 private:
  // tool_point_two_plane and tool_point with a whirl at one frequency without the stencil near the
  // whirl poles.
  Block4 tool_point_two_plane_direct(double frequency_hz, double spin_rad_s) const;
  Block whirl_tool_point_direct(double frequency_hz, double spin_rad_s, Whirl whirl) const;

  Assembly assembly_;
  Chain spindle_, holder_, tool_;
};

// The assembly at `speed_rpm`: each bearing with a speed table takes its stiffness and damping
// there, linearly interpolated between the table's rows (the table then left out). A speed outside
// a table is refused (InvalidArgument naming the bearing's speed_table, its range and the speed)
// unless `extrapolate`: then the end rows' line is extended (a negative result still refused).
// Bearings without a table are kept. A table flat in speed gives the constants' assembly.
Assembly at_speed(const Assembly& assembly, double speed_rpm, bool extrapolate = false);
// Some bearing has a speed table.
bool has_speed_tables(const Assembly& assembly);

// The same assembly with the tool sticking out `overhang` m: the length inside the holder is kept
// (tool length = inside + overhang), so a measured SH11 stays valid. Throws InvalidArgument for a
// non-positive overhang (and whatever Assembly::check finds in the result).
Assembly with_overhang(const Assembly& assembly, double overhang);

// Semi-analytical tool point FRF (Schmitz's receptance coupling with the seed's Eq. 5): a measured
// (or finite-differenced) holder-tip block SH11 coupled to the model's free–free tool through the
// assembly's holder–tool joint, SHT11 = T11 − T12 (T22 + K_ht⁻¹ + SH11)⁻¹ T21, on SH11's grid.
// Throws InputError for an invalid SH11 (naming `sh_name`).
BlockSeries couple_tool(const Assembly& assembly, const BlockSeries& sh11, const std::string& sh_name);

// Whether this build and CPU run AssemblyModel's sweeps in SIMD lanes (x86-64 with AVX2 and FMA,
// built with SLEEF); otherwise the sweeps go one frequency at a time, to the same values.
bool simd_sweeps_available();

// Series over a frequency grid (Hz) of any per-frequency block function of the model.
BlockSeries block_series(const std::vector<double>& frequency_hz, const std::function<Block(double)>& at);
// One point of such a series: at(frequency_hz), a NumericalError's message prefixed with the
// frequency ("at 916 Hz: …"), as every series of the model reports it.
Block block_at(const std::function<Block(double)>& at, double frequency_hz);

// The holder segments with the inserted tool part as a core layer; `tool_inside` from the
// holder tip inwards. Throws InvalidArgument if the tool does not fit the bore: wider than it, or
// narrower by more than 1 % (then the two are not one section).
std::vector<Segment> insert_tool(const std::vector<Segment>& holder, const std::vector<Segment>& tool_inside);

}  // namespace toolpoint
