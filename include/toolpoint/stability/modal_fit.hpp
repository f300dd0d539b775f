// toolpoint: modal models of a tool point and their identification from a measured FRF.
//
// Units: SI (kg, N, m, s); frequencies in Hz at every interface (ω = 2πf inside formulas); damping
// ratios dimensionless; a mode's residue in 1/kg; receptances in m/N.
//
// Model (real modes, viscous modal damping; Ewins, Modal Testing, 2nd ed., Eq. 2.80): a point
// receptance is
//     G(ω) = Σ_r A_r / (ω_r² − ω² + 2iζ_r ω_r ω)  −  L/ω²  +  U          (e^{iωt} convention)
// with A_r = 1/m_r, m_r the modal mass seen at the point (the mass of the equivalent single-
// degree-of-freedom oscillator m_r ẍ + c_r ẋ + k_r x = f, k_r = m_r ω_r², c_r = 2ζ_r m_r ω_r).
// L [1/kg] and U [m/N] are the optional residual terms standing for modes below and above the
// fitted band (Ewins §4.4). Im G ≤ 0 for A_r > 0.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

// One mode of a point receptance as a single-degree-of-freedom oscillator.
struct Mode {
  double mass_kg = 0.0;        // modal mass m_r > 0 [kg]
  double damping_ratio = 0.0;  // ζ_r in [0, 1)
  double frequency_hz = 0.0;   // undamped natural frequency f_r > 0 [Hz]

  double stiffness() const;  // k_r = m_r (2πf_r)² [N/m]
  // Throws InvalidArgument naming `what` and the value (m ≤ 0, ζ outside [0, 1), f ≤ 0, NaN).
  void check(const std::string& what = "mode") const;
};

// G(f) = Σ 1/(m_r(ω_r² − ω² + 2iζ_r ω_r ω)) [m/N] at `frequency_hz` (> 0).
Complex modal_receptance(const std::vector<Mode>& modes, double frequency_hz);
// The same over a grid, as an FRF series.
FrfSeries modal_frf(const std::vector<Mode>& modes, const std::vector<double>& frequency_hz);

struct ModalFitOptions {
  int max_modes = 3;                                 // at most this many modes, 1…20
  std::optional<std::pair<double, double>> band_hz;  // fit only F1 ≤ f ≤ F2 [Hz]; default: all points
  double min_prominence_db = 3.0;                    // a peak of |G| must rise this much [dB] above the valleys on both
                                                     // sides to count as a mode (3 dB: it has a half-power band)
  bool residual_terms = true;                        // fit L and U (out-of-band modes)
  int max_evaluations = 2000;                        // Levenberg–Marquardt function evaluations, ≥ 10
  // Throws InvalidArgument naming `ModalFitOptions::<field>` and the value (modal_fit_fields' ranges;
  // the band by hand).
  void check() const;
};

/// \brief ModalFitOptions' scalar fields defined once (option_fields.hpp): check(), the flags of
/// `toolpoint modes` (`--max-modes`, `--min-prominence`) and Python's ModalFitOptions attributes
/// derive from this table (band_hz has its own definition). The lobes, pitch and simulation
/// studies' max_modes (the shared `--max-modes` of lobes, pitch, simulate) take its range.
/// \return the table, in the order of the fields
const std::vector<OptionField<ModalFitOptions>>& modal_fit_fields();

struct FittedMode {
  Mode mode;                          // modal mass from the residue: m_r = 1/A_r (only meaningful for A_r > 0)
  double residue = 0.0;               // A_r [1/kg]
  double initial_frequency_hz;        // peak-picking estimate
  double initial_damping_ratio;       // half-power estimate
  int points_in_half_power_band = 0;  // measured points within f_r(1 ± ζ_r)
  // ‖G_fit − G‖/‖G‖ over the points within f_r(1 ± 2ζ_r) (at least the 5 nearest points): how well
  // this mode's neighbourhood is reproduced; 0.01 is 1 % of the response there.
  double normalised_residual = 0.0;

  // A resonance a modal model can hold (what a Mode is): a positive residue, so a modal mass
  // 1/A_r > 0, and ζ < 1. A fit can give neither: a non-point FRF or a phase error makes A_r ≤ 0,
  // a mode pushed out of its peak ends overdamped. The one rule for modal_model() and the study's
  // model (what `toolpoint lobes` accepts).
  bool is_resonance() const;
};

struct ModalFitResult {
  std::vector<FittedMode> modes;     // ascending frequency
  double lower_residual = 0.0;       // L [1/kg] (0 when residual_terms is off)
  double upper_residual = 0.0;       // U [m/N]
  double normalised_residual = 0.0;  // ‖G_fit − G‖/‖G‖ over the fitted band
  double band_low_hz = 0.0, band_high_hz = 0.0;
  std::size_t points = 0;  // measured points in the band
  int evaluations = 0;     // Levenberg–Marquardt function evaluations used
  bool converged = false;
  std::vector<std::string> warnings;

  // The fitted modes as a modal model (residual terms dropped). Throws NumericalError when a
  // residue is not positive (no modal mass: not a point FRF, or a phase error in the data).
  std::vector<Mode> modal_model() const;
  // The fitted receptance, residual terms included [m/N].
  Complex receptance(double frequency_hz) const;
  // The same at those of `frequency_hz` (> 0) that lie in the fitted band [band_low_hz,
  // band_high_hz]: on the measured grid, the FRF the fit reproduces.
  FrfSeries fitted_frf(const std::vector<double>& frequency_hz) const;
};

// Identifies up to `max_modes` modes of a point receptance [m/N] (Hz grid):
//  1. peak picking: local maxima of |G| with at least `min_prominence_db` prominence, the most
//     prominent kept; initial ζ from the half-power bandwidth, ζ ≈ (f₂ − f₁)/(2f_r);
//  2. the residues A_r and residual terms by linear least squares with f_r, ζ_r fixed (Eigen QR);
//  3. Levenberg–Marquardt (Eigen's MINPACK port, analytic Jacobian) on all parameters at once,
//     f_r and ζ_r through their logarithms so they stay positive; residuals Re and Im of
//     G_fit − G with equal weights (the fit follows the largest responses, the ones chatter
//     depends on).
// Throws InputError when the band holds fewer than 8 points, when no resonance peak is found, or
// when a peak has fewer than 3 points within its half-power band (the grid is too coarse to see
// that mode's damping). Warnings: a mode that left the band, ζ > 0.3, a non-positive residue,
// a poor fit.
ModalFitResult fit_modes(const FrfSeries& frf, const ModalFitOptions& options = {}, const std::string& what = "FRF");

}  // namespace toolpoint
