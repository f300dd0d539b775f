// toolpoint study: one free–free Timoshenko segment of circular section (solid or hollow) — its
// section, its natural frequencies and, on a frequency grid, one end block of its receptances —
// the procedure behind `toolpoint beam`, as one library call (beam.hpp does the mechanics).
//
// The segment obeys (beam.hpp, seed Eq. 9–14)
//     κGA (w'' − ψ') = −ρAΩ² w,     EI ψ'' + κGA (w' − ψ) = −ρIΩ² ψ
// with E(1+iη), G(1+iη) for a loss factor η. End 1 is x = L (the outer end, towards the tool tip),
// end 2 is x = 0; T_jk is the response at end j to loads at end k, [[H, L], [N, P]] = [[w/f, w/m],
// [θ/f, θ/m]] (conventions.hpp: θ positive like dw/dx, m in the sense of θ).
// Units: SI (m, kg, Pa; H m/N, L 1/N, N rad/N, P rad/(N·m)); frequencies in Hz.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/beam.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/plot/plot.hpp"

namespace toolpoint {

// How the receptance is computed (beam.hpp: two independent routes to the same values).
enum class BeamMethod {
  Exact,  // the closed-form solution, no truncation
  Modal,  // modal summation over BeamStudyOptions::modal's modes (seed Eq. 11–14)
};
// "exact" or "modal".
const char* beam_method_name(BeamMethod method);

struct BeamStudyOptions {
  double length = 0.0;                                       // L [m], > 0 (no default)
  double outer_diameter = 0.0;                               // D [m], > 0 (no default)
  double inner_diameter = 0.0;                               // d [m]; 0: a solid section
  Material material{"beam", 2.0e11, 0.3, 0.0, 7800.0, 0.0};  // steel, undamped (E, ν, G, ρ, η)
  std::optional<double> shear_coefficient;                   // κ [-]; unset: from shear_model, ν and the diameters
  ShearModel shear_model = ShearModel::Hutchinson;
  int modes = 5;                     // free–free natural frequencies listed, ≥ 0
  std::vector<double> frequency_hz;  // the receptance's grid [Hz] (each > 0); empty: no receptance
  EndBlock block = EndBlock::T11;    // which end block
  BeamMethod method = BeamMethod::Exact;
  ModalOptions modal;  // BeamMethod::Modal: elastic modes summed, static residual
  // Spin about the axis [rpm], ≥ 0 (beam.hpp, "A segment spinning about its axis"). > 0: the first
  // `modes` natural frequencies of each whirl (BeamStudy::whirl), and the receptance is the x–x
  // part of the two-plane block (spinning_receptance; y–y is the same, the cross parts skew).
  // The exact method only. Below 1000 rpm a warning: a spin in rad/s is 9.5× too slow in rpm.
  double speed_rpm = 0.0;
  // Speeds [rpm] of the Campbell diagram (each ≥ 0, increasing); empty: none.
  std::vector<double> campbell_rpm;
  // Throws InvalidArgument naming `BeamStudyOptions::<field>`: the ranges and plausibility of
  // beam_study_fields() (a length or diameter that cannot be metres, a speed that cannot be rpm),
  // an inner diameter not below the outer, a non-positive or non-finite frequency,
  // shear_coefficient ≤ 0, modal out of range, a speed with the modal method, Campbell speeds not
  // increasing. The material is checked by Segment::check() when the study builds the segment.
  void check() const;
};

// BeamStudyOptions' scalar fields (option_fields.hpp), with the `toolpoint beam` flags: length
// (--length), outer_diameter (--diameter), inner_diameter (--inner-diameter), modes (--modes),
// speed_rpm (--speed). The material, the shear model, the lists and `modal` (modal_fields()) are
// beside it.
const std::vector<OptionField<BeamStudyOptions>>& beam_study_fields();

// The section's values under the names beam.hpp gives them (Annulus, SectionProperties).
struct BeamSection {
  double area = 0.0;                 // A [m²]
  double second_moment = 0.0;        // I [m⁴]
  double shear_coefficient = 0.0;    // κ [-], as used
  double rhoA = 0.0;                 // ρA [kg/m]
  double rhoI = 0.0;                 // ρI [kg·m]
  double cutoff_frequency_hz = 0.0;  // sqrt(κGA/ρI)/(2π) [Hz]: above it the shear spectrum propagates
};

struct BeamStudy {
  Segment segment;               // the segment built from the options
  SectionProperties properties;  // EI, κGA (complex, with η), ρA, ρI
  BeamSection section;
  std::vector<FreeMode> modes;             // the first options.modes elastic free–free modes, undamped, ascending
  BlockSeries receptance;                  // options.block on options.frequency_hz (empty without a grid)
  double speed_rpm = 0.0;                  // options.speed_rpm
  std::optional<WhirlFrequencies> whirl;   // at options.speed_rpm > 0: each whirl's first options.modes modes
  std::vector<WhirlFrequencies> campbell;  // one per options.campbell_rpm
  // How the receptance was computed: "exact", or "modal (N modes[ + static residual])".
  std::string method;
  std::vector<std::string> warnings;
};

// Runs the study. Throws InvalidArgument (options, the segment: Segment::check()),
// NumericalError (the exact receptance at an undamped natural frequency).
BeamStudy run_beam_study(const BeamStudyOptions& options);

// The Campbell diagram of a study with BeamStudyOptions::campbell_rpm: natural frequency [Hz]
// against speed [rpm], each elastic mode's forward whirl (solid) and backward whirl (dashed) in
// one colour, the conical mode, and the once-per-revolution line f = rpm/60 (where unbalance
// excites a forward whirl). Throws InvalidArgument without at least two speeds.
plot::Figure campbell_figure(const BeamStudy& study, const std::string& title);

}  // namespace toolpoint
