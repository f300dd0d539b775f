// toolpoint: closed-form identification of joint dynamics (seed Sections 2.2, 2.3, 3).
//
// Every identification in the seed has one shape. A component A (free–free, ends 1 and 2) is
// joined at its end 2 through K to a structure B known by its point receptance B11; G11 is the
// point receptance of the whole at A's end 1. Eq. (5) G11 = A11 − A12 (A22 + K⁻¹ + B11)⁻¹ A21
// rearranges (the printed Eq. 6 misplaces its inverses) to
//     X⁻¹ = A21 (A11 − G11)⁻¹ A12        (= A22 + K⁻¹ + B11)
//     K   = (X⁻¹ − A22 − B11)⁻¹
// which needs one inverse of (A11 − G11) instead of A12⁻¹ and A21⁻¹ — mathematically the same.
//   holder–tool,   Eq. (6):  A = T  (tool outside the holder), B11 = SH11, G11 = SHT11
//   spindle–holder, Eq. (15): A = H  (holder with the shank),   B11 = S11,  G11 = SH11
//   spindle–holder, Eq. (18): A = HT (holder–tool subassembly), B11 = S11,  G11 = SHT11
// k = Re K, c = Im K / ω for all eight parameters (joint.hpp has units and the sign convention).
// The inversions are badly conditioned away from the joint's dominant mode, so the condition
// numbers are reported per frequency and the parameters are read in a band at that mode.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/model/joint.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

// K at one frequency, with the conditioning of each step. Condition numbers are Frobenius ones,
// ‖M‖_F ‖M⁻¹‖_F = ‖M‖²_F / |det M| for a 2×2 (between cond₂ and cond₂ + 1/cond₂): cheap and
// as telling.
struct JointEstimate {
  Block K;
  double cond_difference = 0.0;   // cond(A11 − G11), the inversion that amplifies errors in G11
  double cond_flexibility = 0.0;  // cond(K⁻¹ = X⁻¹ − A22 − B11)
  double cond_A12 = 0.0;          // cond(A12), as the seed's form would invert it
  // Noise gain per parameter (k_yf, c_yf, …, c_θm): the expected relative error of that parameter
  // per unit relative error on each measured entry — the 4 of G11 and the 4 of B11, independent,
  // as the seed's multiplicative noise. First-order propagation: with D = A11 − G11,
  //   δK = −(K A21 D⁻¹) δG (D⁻¹ A12 K) + K δB11 K,
  // a real relative error ε_q on entry q moves K_rc by ε_q coef_q with coef = −(K A21 D⁻¹)_ra
  // (D⁻¹ A12 K)_bc G_ab or K_ra K_bc B_ab; so the RMS error of k = Re K_rc is sqrt(Σ Re(coef)²)
  // and of c = Im K_rc/ω is sqrt(Σ Im(coef)²)/ω, each divided by the parameter for the gain:
  // for 5 % noise expect a relative error of ≈ 0.05 × gain. Unit-free. An off-diagonal parameter
  // is measured against max(|value|, 10 % of sqrt|K_yf K_θm|) of its part (Re or Im): a coupling
  // term that is zero has no relative error, only one against its natural scale. Large away from
  // a well-placed mode (docs/reference.md §1), at low frequency, and always for a damping whose ωc is a small
  // part of |K|.
  std::array<double, 8> noise_gain{};
  // ‖K⁻¹‖ / (‖X⁻¹‖ + ‖A22‖ + ‖B11‖): how much of the terms survives their difference. Small for a
  // stiff joint at low frequency (rounding then limits K); identify_joint refuses below 1e-12.
  double flexibility_share = 0.0;
};

// The closed form above at one frequency. Throws NumericalError when A11 − G11 is singular (G11
// equal to A11: nothing attached, or a hinge joint — a singular K makes A11 − G11 singular too;
// the seed's A12⁻¹ form has the same limit), when K⁻¹ is lost in round-off (flexibility_share
// below 1e-12: a rigid joint) or singular.
// `diagnostics` false skips the condition numbers and noise gains (left 0): K and the round-off
// check only, about twice as fast, for bulk work that does not read them.
JointEstimate identify_joint(const TwoPort& A, const Block& B11, const Block& G11, bool diagnostics = true);

// The three identifications of the seed, each with its joint and the FRF it reads:
//   HolderTool            Eq. (6):  K_ht from SHT11 (SH11 given)
//   SpindleHolderFromSH   Eq. (15): K_sh from SH11  (S11 given)
//   SpindleHolderFromSHT  Eq. (18): K_sh from SHT11 (S11 given, HT from the model's K_ht)
enum class Route { HolderTool, SpindleHolderFromSH, SpindleHolderFromSHT };

// K(ω) over a frequency grid, with k, c per frequency and the conditioning.
struct JointSeries {
  std::vector<double> frequency_hz;
  std::vector<JointEstimate> estimates;
  std::vector<JointParameters> parameters;  // k = Re K, c = Im K / ω
  std::size_t size() const { return frequency_hz.size(); }
};

// Identification over a grid: A(f) from the model, B11 and G11 given as series on one grid.
// Throws InputError for mismatched grids, NaN or fewer than 3 points (naming `b_name`, `g_name`).
JointSeries identify_series(const std::function<TwoPort(double)>& A, const BlockSeries& B11, const std::string& b_name,
                            const BlockSeries& G11, const std::string& g_name);

// The eight parameters read in a band: median and a robust spread (1.4826 × median absolute
// deviation, the standard deviation for Gaussian scatter).
struct ParameterReadout {
  double median = 0.0, spread = 0.0, min = 0.0, max = 0.0;
  // Its noise gain (JointReadout::noise_gain) at most ReadoutOptions::gain_warning and its spread
  // at most |median|: what the band's data determine.
  bool determined = false;
};

struct JointReadout {
  double band_lo_hz = 0.0, band_hi_hz = 0.0;
  std::size_t points = 0;
  std::array<ParameterReadout, 8> parameters;  // k_yf, c_yf, k_ym, c_ym, k_θf, c_θf, k_θm, c_θm
  JointParameters medians() const;
  // Reciprocity: |k_ym − k_θf| / max(|k_ym|, |k_θf|), and the same for c (0 when both are 0).
  double reciprocity_k = 0.0, reciprocity_c = 0.0;
  double max_cond_difference = 0.0, max_cond_flexibility = 0.0;
  std::array<double, 8> noise_gain{};  // median over the band of JointEstimate::noise_gain
  std::vector<std::string> warnings;
};

struct ReadoutOptions {
  double cond_warning = 1e6;         // warn when cond(A11 − G11) exceeds this in the band
  double reciprocity_warning = 0.1;  // warn when k_ym and k_θf (or c) differ by more than this
  double gain_warning = 20.0;        // warn when a parameter's noise gain exceeds this (a 5 % FRF
                                     // error then moves it by 100 %)
  // Throws InvalidArgument naming `ReadoutOptions::<field>` outside the ranges of readout_fields()
  // (an infinite level: never warn).
  void check() const;
};

/// \brief ReadoutOptions' fields defined once (option_fields.hpp): check() and the attributes of
/// Python's ReadoutOptions derive from this table.
/// \return the table, in the order of the fields
const std::vector<OptionField<ReadoutOptions>>& readout_fields();

// Reads the parameters from the points with band_lo ≤ f ≤ band_hi. Warns (in the result) about
// poor conditioning, broken reciprocity, any parameter whose noise gain is large or whose spread
// exceeds its value (not identifiable from such data: typical of damping, whose ωc is a few %
// of |K|; filtered data are smooth, so their spread understates the error and the gain is the
// better guide).
// Throws InvalidArgument if the band holds no point.
JointReadout band_readout(const JointSeries& series, double band_lo_hz, double band_hi_hz, const ReadoutOptions& options = {});

// ---- Which mode does the joint control? ---------------------------------------------------------

struct ModeEffect {
  double frequency_hz = 0.0;     // peak of the model FRF
  double magnitude = 0.0;        // m/N
  double stiffness_shift = 0.0;  // relative frequency shift when the joint's k's grow by `step`
  double damping_effect = 0.0;   // relative peak-magnitude change when its c's grow by `step`
};

struct EffectAnalysis {
  std::vector<ModeEffect> modes;
  std::size_t dominant = 0;  // index into modes: the largest |stiffness_shift|
};

// Effect analysis (Ertürk et al. 2007, the seed's basis for choosing the mode): perturb the
// joint's stiffness (then damping) parameters by `step` in the model and see which peak of the
// FRF the joint is identified from (see Route) moves most. Peaks on `frequency_hz`, refined on the
// model. Throws InvalidArgument if the joint is rigid in the model (give it trial values), the
// FRF has no peak, or no mode moves at all (the FRF does not depend on the joint).
EffectAnalysis effect_analysis(const Assembly& assembly, Route route, const std::vector<double>& frequency_hz, double step = 0.1);

// The mode that moves most with the tool overhang (the seed's Fig. 10): the reference FRF's peaks
// found in each FRF (any order; track_modes against the reference within 25 %), the one whose
// frequency varies most (relative range) is dominant. Throws InvalidArgument (fewer than 2 FRFs, bad reference)
// and InputError (no peak in the reference FRF).
struct OverhangModes {
  std::vector<Peak> reference_peaks;
  std::vector<double> relative_variation;  // per reference peak
  std::size_t dominant = 0;
};
OverhangModes overhang_mode(const std::vector<FrfSeries>& frfs, std::size_t reference, const PeakOptions& peaks = {});

// ---- Forward verification -----------------------------------------------------------------------

struct ModeComparison {
  double measured_hz = 0.0, predicted_hz = 0.0, frequency_error = 0.0;      // relative
  double measured_peak = 0.0, predicted_peak = 0.0, magnitude_error = 0.0;  // relative
};

// Peaks of |H| of `measured` matched to those of `predicted` (nearest frequency); errors relative
// to the measured values.
std::vector<ModeComparison> compare_modes(const FrfSeries& measured, const FrfSeries& predicted, const PeakOptions& peaks = {});

}  // namespace toolpoint
