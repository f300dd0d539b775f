// toolpoint: the virtual tap test — the translational FRFs an impact test would measure on the
// model, at the tip and at points s, 2s inwards: for planning the spacing of a real test (finite
// differences amplify noise like 1/s² in P), and for trying the measured-data workflow without a
// machine.
//
// H_ij = w_i / f_j, response at point i, hammer at point j, points at x_i = i·s from the tip
// (point 0 the tip), each from the station receptances of the assembly at one frequency
// (AssemblyModel::tool_stations / holder_stations: the component cut at the points and coupled
// rigidly, the rest of the assembly attached through its joint). With noise, every FRF is
// multiplied by its own random factors 1 + σz per frequency (add_measurement_noise, the seed's
// noise model), or measured as n_d averaged hits with a floor (its coherence kept): FRF k (in the
// order of TapTest::frfs) draws from seed + k; a calibration factor scales every FRF alike.
// Units: SI (m, N; receptance m/N); frequencies in Hz.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/studies/study.hpp"

namespace toolpoint {

// Where the points are.
enum class TapSide {
  Tool,    // on the tool of the whole assembly (for SHT11)
  Holder,  // on the holder of the spindle–holder subassembly, the tool outside removed (for SH11)
};
// Where the hammer goes.
enum class HammerPlan {
  Roving,  // at every point: all H_ij (P by cross terms)
  Tip,     // at the tip only: H_i0
};
const char* tap_side_name(TapSide side);        // "tool", "holder"
const char* hammer_plan_name(HammerPlan plan);  // "roving", "tip"

struct TapTestOptions {
  TapSide side = TapSide::Tool;
  double spacing_m = 0.0;  // s > 0 [m]; (points − 1)·s must fit on the tool's overhang / the holder
  int points = 3;          // 2 (first-order differences) or 3 (second order)
  HammerPlan hammer = HammerPlan::Roving;
  double sigma = 0.0;      // σ of the multiplicative noise, [0, 1) (0.02 = 2 %; 0: exact)
  std::uint64_t seed = 1;  // FRF k draws from seed + k
  // Beyond the seed's noise (signal.hpp's NoiseOptions): an additive floor relative to each FRF's
  // peak, n_d averaged hits per FRF (each with variation σ) and their coherence, one calibration
  // factor for the whole test (one hammer and one response sensor: seed's stream 0xCA11B7A7E).
  double floor = 0.0;
  int averages = 0;
  double calibration = 0.0;
  // Throws InvalidArgument naming `TapTestOptions::<field>` and the value (tap_test_fields' ranges).
  void check() const;
};

/// \brief TapTestOptions' scalar fields defined once (option_fields.hpp): check(), the flags of
/// `toolpoint taptest` and Python's TapTestOptions attributes derive from this table (side, hammer
/// and seed have their own definitions; floor, averages and calibration take noise_fields' ranges).
/// \return the table, in the order of the fields
const std::vector<OptionField<TapTestOptions>>& tap_test_fields();

struct TapTestFrf {
  int response = 0;  // point index, 0 = tip (UFF node response + 1)
  int hammer = 0;    // point index of the hammer
  FrfSeries frf;     // H_ij [m/N] on the assembly's grid
  std::vector<double> coherence;  // γ² per frequency with averages, else empty
};

struct TapTest {
  TapSide side = TapSide::Tool;
  std::vector<double> distance_m;  // of each point from the tip [m]: 0, s, 2s
  std::vector<TapTestFrf> frfs;    // hammer by hammer (tip first), responses 0…points−1 within each
  // The smallest shear stiffness κGA [N] of the sections under the points (real part): what
  // finite differences need to turn dw/dx into ψ (rotational_frfs' shear correction).
  double shear_stiffness_n = 0.0;
  bool crosses_step = false;          // the points span more than one section
  std::vector<std::string> warnings;  // the model's and the noise's
};

// The tap test on `assembly` over `assembly.grid`. Throws InvalidArgument (options; points that do
// not fit on the tool's overhang or the holder, naming TapTestOptions::spacing_m), NumericalError
// naming the frequency.
TapTest run_tap_test_study(const Assembly& assembly, const TapTestOptions& options, const ProgressCallback& progress = {});

}  // namespace toolpoint
