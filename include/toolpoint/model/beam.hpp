// toolpoint: free–free Timoshenko beam segments and their end receptances (seed Eq. 9–14).
//
// A segment is a uniform length of circular section: one annulus (solid or hollow) or several
// concentric layers of different materials (a holder with the tool shank inside: EI, κGA, ρA and
// ρI add). End 1 is the segment's outer end (larger x, towards the tool tip), end 2 its inner end;
// see conventions.hpp. Units: SI (m, kg, Pa, N); frequencies in Hz.
//
// Damping: structural (hysteretic), as complex moduli E(1+iη) and G(1+iη). This is exactly the
// seed's modal damping (1+iη)ω_r² per mode; note that it damps shear as well as bending.
//
// Two independent ways to the same receptances:
//   * exact: the closed-form solution of the Timoshenko equations, no truncation (the default);
//   * modal: the seed's Eq. (11)–(14) generalised to Timoshenko modes — rigid-body modes plus N
//     elastic free–free modes from the exact frequency equation on both branches (below and
//     above the cut-off frequency), mass-normalised with rotary inertia.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

// An isotropic material. Units: Pa, kg/m³; η dimensionless.
struct Material {
  std::string name;
  double youngs_modulus = 0.0;  // E [Pa]
  double poisson = 0.3;         // ν, in (−1, 0.5)
  double shear_modulus = 0.0;   // G [Pa]; 0 means E/(2(1+ν))
  double density = 0.0;         // ρ [kg/m³]
  double loss_factor = 0.0;     // η ≥ 0, applied to E and G

  double G() const;  // the shear modulus used [Pa]
  // Throws InvalidArgument naming the parameter and value (E ≤ 0, ρ ≤ 0, ν outside (−1, 0.5),
  // η < 0, G ≤ 0, non-finite values).
  void check() const;
};

// How κ is chosen for a circular annulus (outer radius a, inner radius b, m = b/a).
enum class ShearModel {
  Hutchinson,  // Hutchinson (2001): solid 6(1+ν)²/(7+12ν+4ν²); hollow
               // 6(a²+b²)²(1+ν)² / [7a⁴+34a²b²+7b⁴ + ν(12a⁴+48a²b²+12b⁴) + ν²(4a⁴+16a²b²+4b⁴)]
  Cowper,      // Cowper (1966): 6(1+ν)(1+m²)² / [(7+6ν)(1+m²)² + (20+12ν)m²]; solid 6(1+ν)/(7+6ν)
};

double shear_coefficient(ShearModel model, double poisson, double outer_diameter, double inner_diameter);

// One concentric layer of a section. Diameters in m; inner 0 for a solid circle.
struct Annulus {
  double outer_diameter = 0.0;
  double inner_diameter = 0.0;
  Material material;
  std::optional<double> shear_coefficient;  // κ override; default from the section's ShearModel

  double area() const;           // m²
  double second_moment() const;  // I [m⁴]
  void check() const;            // throws InvalidArgument (non-positive outer, inner ≥ outer, …)
};

// Per-unit-length section properties the Timoshenko equations need.
struct SectionProperties {
  Complex EI;   // bending stiffness Σ E(1+iη) I [N·m²]
  Complex kGA;  // shear stiffness Σ κ G(1+iη) A [N]
  double rhoA;  // mass per length Σ ρA [kg/m]
  double rhoI;  // rotary inertia per length Σ ρI [kg·m]

  // Ω_c = sqrt(κGA/ρI) in Hz: above it the second ("shear") spectrum propagates.
  double cutoff_frequency_hz() const;
  // Equal sections have equal wavenumbers (pieces of one cut segment share them).
  bool operator==(const SectionProperties&) const = default;
};

// A uniform segment: length and concentric layers (outermost first or any order). A composite
// section (several layers) takes one shear coefficient for the whole section — that of its outer
// circle with its innermost bore, ν area-weighted — unless a layer overrides κ.
struct Segment {
  std::string name;     // where it came from, for messages ("holder.segment[2]"); may be empty
  double length = 0.0;  // m
  std::vector<Annulus> layers;
  ShearModel shear_model = ShearModel::Hutchinson;

  SectionProperties properties() const;
  void check() const;  // throws InvalidArgument naming the value
  // A one-layer segment.
  static Segment tube(double length, double outer_diameter, double inner_diameter, const Material& material,
                      std::string name = {});
};

// ---- Exact (truncation-free) receptances -------------------------------------------------------

// Free–free end receptances T11, T12, T21, T22 of a uniform Timoshenko segment at `frequency_hz`
// (> 0), from the closed-form solution of
//     κGA (w'' − ψ') = −ρAΩ² w,     EI ψ'' + κGA (w' − ψ) = −ρIΩ² ψ
// with end loads. Solved in a symmetric/antisymmetric basis about mid-span, scaled by e^{−sL/2}
// so that no term grows with frequency or length (stable for any sL), and entire in the
// wavenumbers so the cut-off frequency (a zero wavenumber) needs no special case.
// Throws NumericalError at an exact undamped natural frequency (η = 0), where the receptance is
// unbounded, or so near one (or near 0 Hz: 1e-10 Hz) that rounding hides the damping;
// InvalidArgument where the terms under- or overflow double precision (1e100 Hz).
TwoPort exact_receptance(const SectionProperties& section, double length, double frequency_hz);
TwoPort exact_receptance(const Segment& segment, double frequency_hz);

// Which end block of a TwoPort: T_jk, the response at end j to loads at end k.
enum class EndBlock { T11, T12, T21, T22 };
const Block& end_block(const TwoPort& ports, EndBlock block);

// One end block over a frequency grid [Hz] (each > 0), as exact_receptance gives it at each.
BlockSeries exact_receptance(const SectionProperties& section, double length, const std::vector<double>& frequency_hz,
                             EndBlock block);

// The length-independent part of the above at one frequency: the two wavenumbers s_j (p_j = s_j²,
// roots of κGA EI p² + (κGA ρI + EI ρA) Ω² p − ρA Ω² (κGA − ρI Ω²) = 0) and the constants the end
// receptances need from them. A segment cut into pieces (at bearings, at the tool's insertion)
// has one section: computing this once per frequency and reusing it for every piece gives what
// exact_receptance(section, length, f) gives for each piece, without repeating the three complex
// square roots. Units: s in 1/m, p in 1/m², e in N/m² (κGA p + ρAΩ²).
struct SectionWaves {
  double frequency_hz = 0.0;
  Complex s[2];      // Re s ≥ 0 (principal root), so e^{−sL} is bounded [1/m]
  Complex inv_s[2];  // 1/s, or 0 where s = 0 (exactly at an undamped cut-off)
  Complex e[2];      // κGA p_j + ρA Ω² [N/m²]
  // Length-independent factors of the closed form (beam.cpp): with a = κGA, b = EI,
  // u = −a ρA Ω² and Δe = e_1 − e_0: a/b, (a/u) Δe, Δe/b.
  Complex a_over_b, f_a, f_d;
  bool undamped = false;  // EI and κGA real: exact resonances exist
};
// Throws InvalidArgument for a frequency that is not > 0.
SectionWaves section_waves(const SectionProperties& section, double frequency_hz);
// End receptances of a piece of `length` m of the section `waves` was made for; throws
// NumericalError at an exact undamped natural frequency, as exact_receptance.
TwoPort exact_receptance(const SectionWaves& waves, double length);

// ---- A segment spinning about its axis (docs/reference.md §10) -----------------------------------
//
// Two transverse directions x, y and the axis z (the beam coordinate, from the spindle towards
// the tool tip) form a right-handed frame; each plane (x–z, y–z) has the planar convention above
// (w_x, ψ_x = dw_x/dz; w_y, ψ_y = dw_y/dz). The spin Ω [rad/s] is positive right-handed about +z
// (a standard M3 spindle seen from behind the tool). A slice dz of a circular section has
// diametral inertia ρI dz and polar inertia ρI_p dz = 2ρI dz (every annulus: I_p = 2I); spinning,
// its transverse angular momentum is ρI_p Ω (ψ_x, ψ_y) + ρI (−ψ̇_y, ψ̇_x), so the moments on the
// slopes are ρI ψ̈_x + ρI_p Ω ψ̇_y and ρI ψ̈_y − ρI_p Ω ψ̇_x. In r = w_x + i w_y, ψ = ψ_x + i ψ_y:
//     κGA (r'' − ψ') = ρA r̈,      EI ψ'' + κGA (r' − ψ) = ρI ψ̈ − i ρI_p Ω ψ̇.
// A whirl r ∝ e^{iωt} with ω > 0 turns with the spin (forward), e^{−iωt} against it (backward).
// Each is the standing Timoshenko problem at frequency ω with the rotary inertia replaced by
//     forward:  ρI_f = ρI − ρI_p Ω/ω = ρI (1 − 2Ω/ω),   backward:  ρI_b = ρI (1 + 2Ω/ω),
// (negative for a forward whirl slower than 2Ω: the gyroscopic moment outweighs the inertia),
// and the free–free end receptances stay exact for both. Structural damping E(1+iη), G(1+iη)
// applies to each whirl as written (the backward one is the complex conjugate of the e^{−iωt}
// problem, whose hysteretic damping is E(1−iη)). At Ω = 0 both equal exact_receptance().
enum class Whirl {
  Forward,   // turning with the spin: gyroscopically stiffened, frequencies rise with speed
  Backward,  // turning against it: frequencies fall with speed
};
// "forward" or "backward".
const char* whirl_name(Whirl whirl);

// The rotary inertia per length [kg·m] of the whirl's planar problem at `frequency_hz` (> 0):
// ρI (1 ∓ 2Ω/ω), Ω = `spin_rad_s` [rad/s] (any sign; a negative spin swaps the whirls).
double whirl_rotary_inertia(const SectionProperties& section, double spin_rad_s, Whirl whirl, double frequency_hz);
// section_waves() of the whirl's planar problem (whirl_rotary_inertia in place of ρI). Throws
// InvalidArgument as section_waves().
SectionWaves section_waves(const SectionProperties& section, double frequency_hz, double spin_rad_s, Whirl whirl);
// Free–free end receptances of one whirl in the complex coordinates r = w_x + i w_y,
// ψ = ψ_x + i ψ_y, loads f_x + i f_y, m_x + i m_y (for the forward whirl; the backward whirl's
// block maps w_x − i w_y to f_x − i f_y). Throws as exact_receptance().
TwoPort whirl_receptance(const SectionProperties& section, double length, double frequency_hz, double spin_rad_s, Whirl whirl);
// The segment's two-plane end blocks (receptance.hpp: TwoPort4, DOFs w_x, ψ_x, w_y, ψ_y), both
// whirls combined by two_plane().
TwoPort4 spinning_receptance(const SectionProperties& section, double length, double frequency_hz, double spin_rad_s);

// The undamped natural frequencies of a free–free spinning segment, per whirl [Hz].
struct WhirlFrequencies {
  double spin_rad_s = 0.0;
  // The first `count` elastic modes of each whirl, ascending; at Ω = 0 both equal
  // free_free_frequencies().
  std::vector<double> forward_hz, backward_hz;
  // The conical (rigid-body tilt) mode, a forward whirl for Ω ≠ 0 at about ρI_pLΩ/J_d
  // (J_d = ρAL³/12 + ρIL, the rigid body's diametral inertia), which stands at 0 Hz without spin;
  // 0 at Ω = 0, NaN if it lies below 1e-7 of the first elastic frequency (too slow to resolve).
  double conical_hz = 0.0;
};
// Roots of the free–free determinants of whirl_receptance()'s symmetric and antisymmetric parts
// (undamped: Re EI, Re κGA), bracketed on a grid finer than 1/32 of the standstill modes' least
// spacing and refined by bisection to 1e-13 relative. `count` ≥ 1. Throws InvalidArgument.
WhirlFrequencies whirl_frequencies(const SectionProperties& section, double length, double spin_rad_s, int count);
// The conical whirl's undamped frequency [Hz] alone (WhirlFrequencies::conical_hz, the same root
// of the same free–free determinant): bisected to 1e-13 relative in [f₀/1.25, 1.25 f₀] around the
// rigid body's f₀ = ρI_p L |Ω| / (2π J_d), J_d = ρAL³/12 + ρIL (the elastic shift is (f₀/f₁)²
// small), else from whirl_frequencies. It lies in the whirl with ρI (1 − 2|Ω|/ω): forward for
// Ω > 0, backward for Ω < 0. Hysteretic damping hardly damps it (it is the rigid tilt, whose
// gyroscopic moment cancels its inertia), so the free–free receptance is nearly unbounded there.
// 0 at Ω = 0. Throws InvalidArgument for a non-finite spin or length ≤ 0.
double conical_whirl_hz(const SectionProperties& section, double length, double spin_rad_s);
// The rigid body's estimate f₀ = ρI_p L |Ω| / (2π J_d) [Hz] of the above (0 at Ω = 0).
double conical_whirl_estimate_hz(const SectionProperties& section, double length, double spin_rad_s);

// ---- Modal summation (seed Eq. 11–14) ---------------------------------------------------------

struct ModalOptions {
  int modes = 100;               // elastic free–free modes kept, N in 1…20000
  bool static_residual = false;  // add the truncated modes' quasi-static part (see below)
  void check() const;            // the range of modal_fields(); InvalidArgument naming `ModalOptions::modes`
};
// ModalOptions' fields (option_fields.hpp): modes (flag --modal-terms), static_residual
// (--static-residual).
const std::vector<OptionField<ModalOptions>>& modal_fields();

// A free–free mode, mass-normalised: ∫(ρA W² + ρI Ψ²) dx = 1. Values at the ends.
struct FreeMode {
  double frequency_hz;  // undamped natural frequency
  double w1, psi1;      // W and Ψ at end 1 (x = L)
  double w2, psi2;      // W and Ψ at end 2 (x = 0)
  bool above_cutoff;    // root from the λ > α branch of the frequency equation
};

// The first `count` elastic free–free natural frequencies [Hz] from the exact frequency equation
// (Han, Benaroya & Wei 1999, both branches), undamped.
std::vector<double> free_free_frequencies(const SectionProperties& section, double length, int count);

// Free–free modes of a segment: roots and mass-normalised end values, computed once.
// The modal method needs one loss factor for the whole section (EI and κGA damped alike);
// throws InvalidArgument otherwise.
class ModalBeam {
 public:
  ModalBeam(const SectionProperties& section, double length, const ModalOptions& options = {});

  // Receptances by modal summation: two rigid-body modes (translation, rotation about the
  // centre of mass) plus the N elastic modes with denominators ω_r²(1+iη) − Ω². With
  // static_residual, the truncated modes' static flexibility Σ_{r>N} φφ/(ω_r²(1+iη)) is added,
  // taken from the exact solution near 0 Hz (so P converges like 1/N³ instead of 1/N).
  TwoPort receptance(double frequency_hz) const;
  // One end block over a frequency grid [Hz] (each > 0).
  BlockSeries receptance(const std::vector<double>& frequency_hz, EndBlock block) const;

  const std::vector<FreeMode>& modes() const { return modes_; }
  double loss_factor() const { return eta_; }

 private:
  SectionProperties props_;
  double length_;
  double eta_;
  std::vector<FreeMode> modes_;
  double w_trans_, w_rot1_, w_rot2_, psi_rot_;  // rigid-body mode values at the ends
  bool has_residual_ = false;
  TwoPort residual_{};
};

}  // namespace toolpoint
