// toolpoint: milling in the time domain — the cut simulated step by step: cutting forces, tool
// vibration, the machined wall and its surface location error (SLE), chatter.
//
// Units: SI (m, kg, N, s, rad, W, N·m) in every argument and result; spindle speeds in rpm (fields
// *_rpm), frequencies in Hz.
//
// Geometry and sign convention: those of stability.hpp (Altintas & Budak 1995; Altintas,
// Manufacturing Automation, 2nd ed., ch. 2–4). x is the feed direction, y the normal direction in
// the plane of the cut; the immersion angle φ of a tooth is measured clockwise from +y (the cutter
// turns clockwise seen from the spindle), so the tooth's edge is at R (sin φ, cos φ) from the tool
// axis and cuts while φ_st ≤ φ ≤ φ_ex. r = (x, y) is the displacement of the tool relative to the
// work; forces are those the work exerts on the tool.
//
// The model (Altintas ch. 2–3; Schmitz & Smith, Machining Dynamics, 2nd ed., §4.5–4.7):
//   * Structure: modes of the tool point in the x–y plane, each q̈_r + 2ζ_rω_r q̇_r + ω_r² q_r = ψ_r·F
//     with a mass-normalised shape ψ_r = (ψ_x, ψ_y) [kg^−½]; r = Σ ψ_r q_r. An x mode of modal mass
//     m is ψ = (1/√m, 0); a mode with both components couples x and y (G_xy = Σ ψ_xψ_y/(ω_r² − ω² +
//     2iζ_rω_rω)). No modes: a rigid tool.
//   * Cutter: N teeth at any angular spacing (pitch), a helix angle β (the cut is split into axial
//     slices of height dz; the slice at height z lags by z tan β/R), or one per tooth (variable
//     helix), a radial runout ρ_j per tooth (tooth j cuts at radius R + ρ_j).
//   * Chip: tooth j of slice z at angle φ removes what lies beyond the surface left by every tooth
//     before it at that angle over the last revolution (not only the previous one: with runout,
//     variable pitch or a tooth that left the cut, an older tooth may have cut deeper). In the frame
//     of the tool centre (the first-order chip of the circular tooth path, Altintas §2.4),
//         h_j(t) = (u·r(t) + R + ρ_j) − max_{q=1…N} [u·r(t − T_q) + R + ρ_{j−q} − C_q sin φ],
//     u = (sin φ, cos φ), T_q the time since tooth j − q passed the same angle (q pitches back) and
//     C_q = N c (its angle)/2π the feed since (c the mean feed per tooth). h ≤ 0: the tooth is out of
//     the cut (no force: the nonlinearity the lobes leave out). Older surfaces lie a feed per
//     revolution or more behind; at the walls (sin φ = 0) the first-order chip would not see that
//     feed and one deep transient pass would mark the wall for ever, so the comparison reaches back
//     SimulationOptions::memory_revolutions (1 by default).
//   * Force law per slice of height dz (Altintas Eq. 2.11–2.12, exponential form of Kline et al.):
//         F_t = dz [K_te + K_t ĥ(h)],   F_r = dz [K_re + K_r K_t ĥ(h)],   ĥ = h₀ (h/h₀)^x,
//     x = 1 the linear law (ĥ = h); on the tool F = F_t (−cos φ, sin φ) + F_r (−sin φ, −cos φ).
//
// Integration (the scheme, stated): m steps of h = τ/m per mean tooth period τ = 60/(N n). Between
// steps each mode is advanced exactly (its 2×2 propagator e^{A_r h} in closed form), with the
// cutting force taken as linear in time between its values at the ends of each piece of the step
// during which a tooth cuts (the pieces split at the teeth's entry and exit angles, exactly, and at
// h = 0, located linearly); the exact response to a linear force is used (a first-order-hold /
// ramp-invariant step). The force at the step's end depends on the displacement there, so the step
// is predicted with the force held and corrected once (Heun's predictor–corrector about the exact
// propagator). Displacements between steps are interpolated linearly for the force and by cubic
// Hermite (with the velocities) for samples; delayed surfaces not on the step grid (variable pitch)
// linearly. Local error O(h³), global O(h²): second order. Measured (tests/simulation_test.cpp,
// docs/simulation.md): the error of a stable cut's periodic motion falls by 4.0× per halving of h.
// Free vibration is exact (the propagator): energy is kept to rounding.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "toolpoint/option_fields.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/stability/stability.hpp"

namespace toolpoint {

// ---- The structure ----------------------------------------------------------------------------

// One mode of the tool point in the x–y plane (see above).
struct PlanarMode {
  double frequency_hz = 0.0;            // undamped natural frequency f_r > 0 [Hz]
  double damping_ratio = 0.0;           // ζ_r in [0, 1)
  double shape_x = 0.0, shape_y = 0.0;  // ψ_r at the tool point [kg^−½], not both zero
  // Throws InvalidArgument naming `what` and the value.
  void check(const std::string& what = "mode") const;
};

// A 1-DOF mode (modal mass m, as Mode) acting along the direction at `direction_rad` from +x
// towards +y: ψ = (cos θ, sin θ)/√m. θ = 0: an x mode; π/2: a y mode; between: x and y coupled.
PlanarMode planar_mode(const Mode& mode, double direction_rad);

struct ToolDynamics {
  std::vector<PlanarMode> modes;        // empty: a rigid tool
  void check() const;                   // throws InvalidArgument naming `ToolDynamics::modes[i]`
  double highest_frequency_hz() const;  // 0 for a rigid tool
  // The tool point receptance [[G_xx, G_xy], [G_yx, G_yy]] [m/N] at `frequency_hz` (e^{iωt}).
  Eigen::Matrix2cd receptance(double frequency_hz) const;
};

// The modes of a ModalModel (x modes along x, y modes along y, uncoupled).
ToolDynamics tool_dynamics(const ModalModel& model);

// ---- The cutter, the force law, the cut ---------------------------------------------------------

struct Cutter {
  double diameter_m = 0.0;  // D > 0 [m]
  // Angular spacing [rad] from each tooth to the one that follows it (tooth j + 1 passes an angle
  // pitch_rad[j] / Ω after tooth j; the last entry leads back to tooth 0). N = size() ≥ 1, each
  // > 0, summing to 2π (within 1e-6 rad).
  std::vector<double> pitch_rad;
  double helix_rad = 0.0;  // β in [0, 80°] [rad]; > 0 splits the cut into axial slices
  // A variable helix: tooth j's own β_j [rad] (N entries, each in [0, 80°]; empty: helix_rad on
  // every tooth). The slice at height z of tooth j lags by z tan β_j/R, so the angle from the tooth
  // ahead changes along z: p_{j−1} + z (tan β_j − tan β_{j−1})/R.
  std::vector<double> tooth_helix_rad;
  std::vector<double> runout_m;  // ρ_j: radius of tooth j is D/2 + ρ_j [m], |ρ_j| < D/2; empty: none
  double flute_length_m = 0.0;   // the depth of cut may not exceed it [m]; 0: not checked
  int teeth() const { return static_cast<int>(pitch_rad.size()); }
  double helix_of(int tooth) const;  // β_j [rad]
  bool uniform() const;              // even pitch, one helix and no runout: every tooth cuts alike
  // Throws InvalidArgument naming `Cutter::field`: the ranges of cutter_fields() (a diameter in mm
  // refused as cannot be meant), then the per-tooth lists.
  void check() const;
};
// Cutter's scalar fields (option_fields.hpp): diameter_m (simulate --diameter, in mm), helix_rad
// (0…80°; the CLI's --helix list beside), flute_length_m (--flute-length, in mm; 0: not checked).
const std::vector<OptionField<Cutter>>& cutter_fields();

// N evenly spaced straight teeth.
Cutter uniform_cutter(int teeth, double diameter_m);
// Radial runout of an axis offset e at angle λ [rad] (measured like φ): ρ_j = e cos(θ_j − λ),
// θ_j the angular position of tooth j (θ₀ = 0, θ_{j+1} = θ_j − p_j).
std::vector<double> offset_runout(const std::vector<double>& pitch_rad, double offset_m, double angle_rad);

struct ForceLaw {
  double tangential_coefficient = 0.0;  // K_t > 0 [N/m²] (at the reference chip for x ≠ 1)
  double radial_ratio = 0.0;            // K_r = K_n/K_t ≥ 0
  double tangential_edge = 0.0;         // K_te ≥ 0 [N/m]
  double radial_edge = 0.0;             // K_re ≥ 0 [N/m]
  double exponent = 1.0;                // x in (0, 1]: 1 the linear law
  double reference_chip_m = 1e-4;       // h₀ > 0 [m] (used when x ≠ 1)
  // Process damping (Budak & Tunç, CIRP Annals 58 (2009) 403; stability.hpp's CuttingConditions::
  // process_damping_n_per_m): each slice in the cut adds −C_i dz (u·ṙ)/V u, u = (sin φ, cos φ),
  // V = πDn/60. C_i [N/m] within kProcessDampingMin…kProcessDampingMax; 0: none.
  double process_damping_n_per_m = 0.0;
  // Throws InvalidArgument naming `ForceLaw::field`: the ranges of force_law_fields() (a K_t in
  // N/mm² refused as cannot be meant).
  void check() const;
};
// ForceLaw's fields (option_fields.hpp): tangential_coefficient, radial_ratio and
// process_damping_n_per_m are CuttingConditions' (cutting_fields: --kt, --kr, --process-damping);
// tangential_edge (simulate --kte), radial_edge (--kre), exponent (--exponent), reference_chip_m
// (--reference-chip, in mm). The simulated map's part file writes and reads them by their names.
const std::vector<OptionField<ForceLaw>>& force_law_fields();

// The linear law of stability.hpp's cutting conditions (no edge forces; their process damping).
ForceLaw linear_force_law(const CuttingConditions& cutting);

struct MillingCut {
  double speed_rpm = 0.0;         // n > 0 [rpm]
  double depth_m = 0.0;           // axial depth a ≥ 0 [m] (0: nothing is cut, the tool vibrates freely)
  double feed_per_tooth_m = 0.0;  // mean feed per tooth c ≥ 0 [m] (per revolution: N c)
  Engagement engagement;          // φ_st, φ_ex (engagement_from_immersion)
  // Throws InvalidArgument naming `MillingCut::field`: the ranges of milling_cut_fields(), the engagement.
  void check() const;
};
// MillingCut's scalar fields (option_fields.hpp): speed_rpm, depth_m (simulate's --rpm, --depth [mm],
// a value or a map's MIN:MAX, parsed beside), feed_per_tooth_m (--feed [mm]; CuttingConditions').
const std::vector<OptionField<MillingCut>>& milling_cut_fields();

struct SimulationOptions {
  int revolutions = 40;  // simulated revolutions, 2…10^6
  // Steps per mean tooth period m; 0: automatic, max(40, 40 f_max τ) (40 steps per period of the
  // highest mode). Refused when a step exceeds a quarter period of the highest mode.
  int steps_per_tooth = 0;
  int slices = 0;                     // axial slices, 1…1000; 0: 1 without helix, else one per step angle of lag (≤ 200)
  double analysed_fraction = 0.5;     // the last fraction of the revolutions (whole revolutions, ≥ 1) analysed
  bool record = true;                 // keep the time histories (maps: false, only the summary)
  int memory_revolutions = 1;         // the surfaces of the teeth this many revolutions back are compared (1…10)
  std::vector<double> initial_state;  // (q_r, q̇_r) per mode [m·kg^½, m·kg^½/s]; empty: at rest
  double memory_limit_bytes = 0.0;    // refuse runs needing more; 0: the machine's physical memory
  void check() const;                 // throws InvalidArgument naming `SimulationOptions::field`
};

/// \brief SimulationOptions' scalar fields but the memory limit, defined once (option_fields.hpp):
/// their ranges and help, check(), the `toolpoint simulate` flags, the JSON echo and the keywords
/// of Python's simulate_milling derive from it (initial_state and memory_limit_bytes are checked
/// by hand).
/// \return the table, in the order of the fields
const std::vector<OptionField<SimulationOptions>>& simulation_fields();

// A sample of the tool's motion.
struct MotionSample {
  double time_s = 0.0;
  double x_m = 0.0, y_m = 0.0;                // displacement
  double vx_m_per_s = 0.0, vy_m_per_s = 0.0;  // velocity
  int tooth = -1;                             // the tooth that passes φ = 0 at this time (once-per-tooth samples)
};

// Where one tooth, at one slice, passed the wall's angle.
struct WallPass {
  int revolution = 0, tooth = 0, slice = 0;
  double time_s = 0.0;
  double feed_position_m = 0.0;  // the tool centre's nominal x then: v_f t
  double depth_m = 0.0;          // δ = u·r + ρ_j: how far the edge reached beyond its nominal radius (+: into the wall)
};

// A machined wall: the side of the cut at φ = 0 (entry at 0: up milling, slotting) or φ = π (exit
// at π: down milling, slotting).
struct Wall {
  double angle_rad = 0.0;
  std::vector<double> slice_height_m;  // slice centres z above the tool tip
  // Surface location error per slice [m]: the material left beyond the commanded wall (+: undercut,
  // −: overcut) = −(the deepest δ of each analysed revolution, averaged over those revolutions).
  std::vector<double> sle_m;
  double mean_sle_m = 0.0;       // over the slices
  std::vector<WallPass> passes;  // SimulationOptions::record only
};

// The wall's surface profile along the feed at one slice [m]: at each x of `feed_positions_m`, the
// material left (as sle_m) under the envelope of the teeth's circular arcs through their passes,
// y(x) = max_p [δ_p − (x − x_p)²/(2(R + ρ_p))] (the scallops of the feed marks).
std::vector<double> wall_profile(const Wall& wall, int slice, double radius_m, const std::vector<double>& runout_m,
                                 const std::vector<double>& feed_positions_m);

struct SimulationResult {
  // The discretization used.
  double step_s = 0.0;
  int steps_per_tooth = 0, steps_per_revolution = 0, slices = 0, revolutions = 0;
  long steps = 0;
  int analysed_from = 0;  // first analysed revolution
  // Histories at every step k = 0…steps (SimulationOptions::record): force on the tool [N],
  // displacement [m], velocity [m/s], spindle torque [N·m] (ΣF_t(R + ρ_j)).
  std::vector<double> time_s, force_x_n, force_y_n, x_m, y_m, vx_m_per_s, vy_m_per_s, torque_nm;
  std::vector<std::vector<double>> tooth_force_n;  // per tooth: its tangential force ΣF_t over the slices [N]
  std::vector<MotionSample> per_revolution;        // at t = k·60/n (k = 0…revolutions)
  std::vector<MotionSample> per_tooth;             // as each tooth's tip passes φ = 0
  std::vector<Wall> walls;
  // Over the analysed revolutions: the mean forces (time averages of the force, integrated
  // exactly as the scheme represents it), torque, power P = T·2πn/60, the largest |F| at a step.
  double mean_force_x_n = 0.0, mean_force_y_n = 0.0, mean_torque_nm = 0.0, power_w = 0.0, peak_force_n = 0.0;
  double sle_m = 0.0;  // the first wall's mean SLE (NaN without a wall)
  // Chatter. The cut's period is the tooth period for a uniform cutter, else a revolution; X_i the
  // modal state (ω_r q_r, q̇_r) once per cut period. A periodic (chatter-free) cut has X_{i+1} = X_i.
  //   growth: the per-revolution factor by which ‖X_{i+1} − X_i‖ grows (< 1 decays), a least-squares
  //     fit of its logarithm over the analysed periods: the dominant Floquet multiplier's modulus,
  //     per revolution, while the motion stays linear;
  //   chatter_metric: RMS‖r_{i+1} − r_i‖ over the analysed periods / RMS of r about its mean
  //     (0 for a periodic cut, of order 1 for chatter; +inf when the run diverged);
  //   chatter_hz: the strongest spectral line of the displacement left after the average over the
  //     revolutions is removed (the spindle, tooth-passing and runout harmonics go with it).
  double growth = 0.0, chatter_metric = 0.0, chatter_hz = 0.0;
  bool stable = true;  // growth < 1 and chatter_metric below kChatterMetricLimit (or the teeth stay in the cut)
  // The vibration's amplitude (half the range of x or y over a revolution) exceeded 5 % of the
  // tool's radius, beyond the small-vibration chip model: the run
  // stopped at the end of that revolution (`revolutions` says how many were simulated; the
  // histories end there; the means are NaN when it stopped before the analysed revolutions).
  bool diverged = false;
  double out_of_cut_fraction = 0.0;  // of the tooth-slice samples inside the engagement, those with h ≤ 0 (analysed revolutions)
  std::vector<std::string> warnings;
};

// A cut whose once-per-period motion still varies by more than this (chatter_metric) at the end
// is not called stable even if its variation decays.
inline constexpr double kChatterMetricLimit = 0.05;

// Simulates the cut. Throws InvalidArgument (bad dynamics, cutter, law, cut or options: naming the
// field; a step too large for the highest mode; a depth beyond the flute length; a run needing
// more memory than SimulationOptions::memory_limit_bytes), NumericalError (the motion is not finite).
// `progress`, if given, is called once per revolution with the fraction done.
SimulationResult simulate_milling(const ToolDynamics& dynamics, const Cutter& cutter, const ForceLaw& law, const MillingCut& cut,
                                  const SimulationOptions& options = {}, const std::function<void(double)>& progress = {});

// The steps per tooth period the automatic rule gives (SimulationOptions::steps_per_tooth = 0).
int automatic_steps_per_tooth(const ToolDynamics& dynamics, int teeth, double speed_rpm);

}  // namespace toolpoint
