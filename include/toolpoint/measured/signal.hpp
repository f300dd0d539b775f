// toolpoint: signal processing for measured FRFs — Savitzky–Golay smoothing, simulated
// measurement noise, and rotational FRFs (L, N, P) by finite differences of translational ones.
//
// Units: frequencies in Hz; FRF values keep the units they come in (H m/N, L 1/N, N rad/N,
// P rad/(N·m)); the finite-difference spacing s in m; Savitzky–Golay windows count frequency
// points. Sign convention as in conventions.hpp: x points from the spindle towards the tool tip,
// θ is positive like dw/dx, a moment m acts in the sense of θ.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

// A processed series and what the caller should know about it (nothing fatal: fatal problems
// throw).
template <class Series>
struct SignalResult {
  Series series;
  std::vector<std::string> warnings;
};

// ---- Savitzky–Golay smoothing ---------------------------------------------------------------
//
// Savitzky & Golay (1964), as in the seed paper's Section 4, and matching
// scipy.signal.savgol_filter(x, window, order, mode='interp'):
//   * interior points (m = window/2 ≤ i < n − m): y_i = Σ_{k=−m..m} c_k x_{i+k}, where c_k are the
//     weights that give the value at 0 of the degree-p least-squares polynomial through
//     x_{i−m..i+m};
//   * the first m outputs: the degree-p polynomial fitted to the first `window` samples,
//     evaluated at positions 0..m−1; the last m likewise with the last `window` samples.
// A complex series is filtered as two real ones (real and imaginary parts separately). The
// samples are assumed evenly spaced in frequency; an uneven grid is filtered as if it were even
// and flagged in the warnings.
struct SavgolOptions {
  int window = 5;  // points in the fitting window: odd, > order (the defaults are the docs/reference.md §6 oracle)
  int order = 2;   // polynomial degree p ≥ 0

  // Throws InvalidArgument naming `SavgolOptions::window` or `SavgolOptions::order`: outside the
  // ranges of savgol_fields(), an even window, an order not below the window.
  void check() const;
};

/// \brief SavgolOptions' fields defined once (option_fields.hpp): check(), the flags of `toolpoint
/// filter` and the attributes of Python's SavgolOptions derive from this table (the window's
/// oddness and order < window are checked beside it).
/// \return the table, in the order of the fields
const std::vector<OptionField<SavgolOptions>>& savgol_fields();

// The interior weights c_{−m..m} (left to right). From the least-squares problem on the
// Vandermonde matrix V_kj = t_k^j, t_k = k/m (centred, scaled abscissa: keeps V well conditioned),
// solved by Householder QR: c = row m of the hat matrix V V⁺ = Q Qᵀ. Their sum is 1 (a constant
// passes unchanged) and Σ c_k² is the factor by which white noise variance is reduced.
// Throws InvalidArgument (see check()) and NumericalError when the order is so high that the
// Vandermonde matrix is too ill-conditioned for accurate weights (condition number > 1e8).
std::vector<double> savgol_coefficients(const SavgolOptions& options);

// Filters real samples. `what` names the data in errors. Throws InvalidArgument when the window
// is longer than the data (scipy's mode='interp' rule), InputError on non-finite samples.
std::vector<double> savgol_filter(std::span<const double> samples, const SavgolOptions& options,
                                  const std::string& what = "samples");

// Filters an FRF (real and imaginary parts separately) or every entry of a 2×2 block series
// (eight real columns). The frequency grid is kept. Validates the series (validate()).
SignalResult<FrfSeries> savgol_filter(const FrfSeries& series, const SavgolOptions& options, const std::string& what = "FRF");
SignalResult<BlockSeries> savgol_filter(const BlockSeries& series, const SavgolOptions& options,
                                        const std::string& what = "block series");

// The rule for smoothing a measured FRF (the filter command, the case study): a window of at most
// a quarter of the `points` — a longer one fits the polynomial to the curve itself, not to its
// noise. Throws InvalidArgument naming SavgolOptions::window, the window and the number of points
// (and as check()). savgol_filter itself only needs the window to fit the data (scipy's rule), for
// the short bands the joint fit smooths internally.
void check_smoothing_window(const SavgolOptions& options, std::size_t points, const std::string& what);

// What a smoothing filter did to the prominent peaks of an FRF. A Savitzky–Golay window of w
// points fits a degree-p polynomial over w·Δf Hz; a resonance whose half-power width 2ζf_n is not
// much wider than that is flattened (the polynomial cannot follow the peak). Each peak of
// |raw| whose prominence is at least `min_prominence` (and whose height is at least `min_height`
// of the entry's highest peak) is compared with the nearest peak of |filtered| within the
// window's half-width: height change (filtered − raw)/raw and frequency change
// (f_filtered − f_raw)/f_raw. A change beyond `warn_above` (either) is a warning naming the entry,
// the peak, the change and the fix; a peak with no filtered peak near it was smoothed away.
//
// Measured data carry noise, and on noisy data (rotational entries by finite differences carry
// 10 % and more) noise makes local maxima 25 % above their valleys by the hundred. So the raw
// data's noise σ(f) (absolute, E|ε|² = σ²) is estimated from the data themselves — the mean
// squared residual about a local 7-point cubic over the 51 points around f, spikes left out —
// and a peak
// counts only when it also rises `noise_prominence` σ above its higher valley (a noise maximum
// over a noise minimum differs by a Gaussian of deviation √2 σ at most, which exceeds 8σ with
// probability below 1e-8). Its σ, relative to the raw peak, is reported with it: the raw height
// is uncertain by about that much, so a change within 2σ cannot be told from the noise (the
// warning says so). Series too short to estimate the noise from (fewer than 58 points) are taken
// as noise-free.
struct PeakChangeOptions {
  double min_prominence = 0.2;    // a peak at least 25 % above its higher valley (≈ 1.9 dB): noise ripple is not a mode
  double min_height = 0.05;       // fraction of the entry's highest peak below which a peak is not reported
  double warn_above = 0.02;       // |relative change| above which a warning is given (2 %)
  double noise_prominence = 8.0;  // a peak must also rise this many noise σ above its higher valley
  void check() const;             // the ranges of peak_change_fields(); InvalidArgument naming `PeakChangeOptions::<field>`
};

/// \brief PeakChangeOptions' fields defined once (option_fields.hpp): check() derives from this
/// table (fractions in (0, 1), warn_above > 0, noise_prominence ≥ 0), and Python lists it in
/// toolpoint._option_fields.
/// \return the table, in the order of the fields
const std::vector<OptionField<PeakChangeOptions>>& peak_change_fields();

struct PeakChange {
  std::string entry;              // "H", "L", "N", "P" (a block) or "" (a single FRF)
  double raw_frequency_hz = 0.0;  // refined (parabola through log|H| at three points)
  double raw_magnitude = 0.0;     // |raw| at the refined peak, in the FRF's units
  double filtered_frequency_hz = 0.0;
  double filtered_magnitude = 0.0;  // NaN frequency: no filtered peak within the half-window (height read at f_raw)
  double height_change = 0.0;       // (filtered − raw)/raw
  double frequency_change = 0.0;    // (f_filtered − f_raw)/f_raw
  double noise = 0.0;               // the raw data's magnitude noise σ at the peak, relative to raw_magnitude (0: not estimated)
};

struct PeakChangeReport {
  std::vector<PeakChange> peaks;  // per entry, ascending in frequency
  std::vector<std::string> warnings;
};

// `raw` and `filtered` on the same grid; `window` the filter's window in points (the search
// half-width); `what` names the data in the warnings. Throws InvalidArgument for different grids.
PeakChangeReport peak_changes(const FrfSeries& raw, const FrfSeries& filtered, int window, const PeakChangeOptions& options = {},
                              const std::string& what = "FRF");
PeakChangeReport peak_changes(const BlockSeries& raw, const BlockSeries& filtered, int window,
                              const PeakChangeOptions& options = {}, const std::string& what = "block series");

// ---- Simulated measurement noise (seed Section 3, and as tap tests give it) -------------------
//
// The seed's noise (the default): each FRF entry at each frequency is multiplied by its own real
// random factor 1 + σz, z standard normal: mean 1, standard deviation σ, independent across
// entries and frequencies. The complex value is scaled as a whole (magnitude distorted, phase
// kept), as the seed did. Beyond the seed (noise.hpp states the models):
//   * `floor`: an additive floor, each of the real and imaginary parts of every entry gets
//     σ_a z with σ_a = floor × that entry's largest |x| over the series;
//   * `averages` ≥ 2: an averaged impact test instead of one factor: n_d hits, each X_k = x (1 +
//     σ c_k) + σ_a d_k (c_k complex circular with E|c|² = 1: hit-to-hit variation of magnitude
//     and phase alike; d_k with standard normal parts), with a unit force; the H1 estimate is their
//     mean and its coherence γ² = |Σ X_k|² / (n_d Σ |X_k|²) (Bendat & Piersol: the variance of H1
//     is then (1 − γ²)/(2 n_d γ²) |x|² per part, noise.hpp's h1_relative_variance);
//   * `calibration`: the whole series times one factor 1 + σ_c z (a sensor's sensitivity error).
// Reproducible and portable: z comes from std::mt19937_64 raw output (fully specified by the C++
// standard) through the Box–Muller transform written here — not std::normal_distribution, whose
// output differs between standard libraries. Draw order: frequency by frequency, and within one
// frequency the entries H, L, N, P (the seed's factors, or the hits' c_k then the floor's d_k);
// the floor and the calibration draw from streams of their own (stream_seed), so the seed's noise
// is drawn exactly as before whatever else is asked. Results agree bit for bit wherever std::log,
// std::sqrt, std::cos and std::sin round alike (glibc does so on every platform it supports).
struct NoiseOptions {
  double sigma = 0.05;       // the seed's factor's, or each hit's variation's, standard deviation (0.05 = 5 %)
  std::uint64_t seed = 1;    // mt19937_64 seed
  double floor = 0.0;        // additive floor relative to each entry's peak |x| (0.01 = 1 %)
  double calibration = 0.0;  // σ of the series' calibration factor (0.02 = 2 %)
  int averages = 0;          // 0: the seed's single factor; ≥ 2: an averaged test with coherence

  // Throws InvalidArgument naming `NoiseOptions::<field>`: σ, floor or calibration negative or not
  // finite, a floor above 0.5 or a calibration above 0.1 (per cent given as a number), averages
  // of 1 or below 0 or above 10000 (the ranges of noise_fields()).
  void check() const;
};

/// \brief NoiseOptions' scalar fields defined once (option_fields.hpp): check(), the flags of
/// `toolpoint noise` and the keywords of Python's add_measurement_noise derive from this table
/// (seed, a 64-bit integer, has its own definition). TapTestOptions' floor, averages and calibration
/// take their ranges from it.
/// \return the table, in the order of the fields
const std::vector<OptionField<NoiseOptions>>& noise_fields();

template <class Series>
struct NoisyMeasurement {
  Series series;
  std::vector<double> coherence;    // γ² per frequency (of H for a block) with averages; else empty
  double calibration_factor = 1.0;  // the factor drawn (1 without calibration)
  std::vector<std::string> warnings;
};

// `count` standard normal numbers from `seed` (Box–Muller on mt19937_64: u1 = (r₁ >> 11 + 1)·2⁻⁵³
// in (0, 1], u2 = (r₂ >> 11)·2⁻⁵³ in [0, 1), z = √(−2 ln u1)·cos 2πu2, then √(−2 ln u1)·sin 2πu2).
std::vector<double> standard_normals(std::size_t count, std::uint64_t seed);

// Noisy copies; `what` names the data in errors (validate()). A warning is given when some factor
// is ≤ 0 (σ so large that a value changes sign).
NoisyMeasurement<FrfSeries> add_measurement_noise(const FrfSeries& series, const NoiseOptions& options,
                                                  const std::string& what = "FRF");
NoisyMeasurement<BlockSeries> add_measurement_noise(const BlockSeries& series, const NoiseOptions& options,
                                                    const std::string& what = "block series");

// ---- Rotational FRFs by finite differences (Duarte & Ewins 2000; docs/reference.md §5) ------------------
//
// Points along the tool: 0 at the tip, 1 at s and 2 at 2s inward (towards the spindle).
// H_ij = w_i/f_j: translational response at point i to a force at point j [m/N].
// With weights d = (1, −1)/s (first order) or (3, −4, 1)/(2s) (second order), one-sided
// differences in the direction of decreasing x:
//     N = Σ_i d_i H_i0      first order (H00 − H10)/s,   second (3H00 − 4H10 + H20)/(2s)
//     L = Σ_j d_j H_0j      first order (H00 − H01)/s,   second (3H00 − 4H01 + H02)/(2s)
//     P = Σ_ij d_i d_j H_ij first order (H00 − H01 − H10 + H11)/s²,
//                           second (9H00 − 12H01 + 3H02 − 12H10 + 16H11 − 4H12 + 3H20 − 4H21 + H22)/(4s²)
// Our x axis points outward (towards the tool tip), the points lie at x_tip − is, so these are
// backward differences of dw/dx and the formulas hold as printed (with an inward axis N and L
// would change sign, P would not). N and L have error O(s) (first order) and O(s²) (second
// order) in general. At a free end loaded by a force — the tool tip — the bending moment w'' is
// zero, so there the first-order N is also O(s²), with half the second-order formula's leading
// error and opposite sign (N₁ − N ≈ s²w'''/6, N₂ − N ≈ −s²w'''/3 for an Euler–Bernoulli tip; L
// likewise). P does not gain an order: the mixed derivative ∂²H/∂x∂ξ has a kink where x = ξ,
// which both stencils straddle, so P's error is O(s) for either order.
//
// Missing data: nothing is invented unless asked for. With assume_reciprocity, a missing
// off-diagonal H_ij is taken from H_ji (Maxwell–Betti reciprocity) and the result lists each fill
// (with the hammer at the tip only, H_i0, that makes L = N); without it, an H_0k or H_k0 that N or
// L needs is an error naming it. P needs every H_ij up to the order (the hammer moved too, in
// particular H11, H22); without them P is approximated as N·L/H00 — N²/H00 when L = N (Schmitz &
// Smith), exact for a single mode, about 25 % low on a static cantilever — and flagged, unless the
// source could not read all it held (PointFrfs::unread: the missing ones may be there, in a
// truncated or damaged file): then the approximation is refused unless asked for (SchmitzSmith).
enum class PMethod {
  Auto,          // cross terms if every H_ij is available (directly or by reciprocity), else N·L/H00
  CrossTerms,    // the finite-difference formula; missing terms are an error
  SchmitzSmith,  // P ≈ N·L/H00 even when cross terms are available
};

struct RotationalOptions {
  int order = 2;            // finite-difference order: 1 or 2
  double spacing = 0.0;     // s [m] between neighbouring points, > 0 (no default)
  bool symmetrise = false;  // replace L and N by their mean (reciprocity L = N)
  PMethod p_method = PMethod::Auto;
  // κGA [N] of the section the points lie on. Differences of displacements measure the total
  // slope dw/dx, but the Timoshenko rotation θ = ψ that the coupling equations use differs from it
  // by the shear strain Q/κGA. At a loaded free tip Q equals the tip force, so N and L come out
  // 1/κGA too large; and a force couple across points spaced s apart shears the segment between
  // them, so P comes out c/(s κGA) too large, c = 1 (first order) or 2.5 (second order) — the
  // formulas applied to the shear kernel c₀ − max(x, ξ)/κGA — an error that grows as s shrinks.
  // With the value given, these are subtracted (the points must lie on one uniform section).
  // Unset: the total-slope quantities, as printed in docs/reference.md §5 (fine for slender tools, where
  // 1/κGA is far below N).
  std::optional<double> shear_stiffness;
  bool assume_reciprocity = false;  // fill a missing H_ij with H_ji (default: refuse, see above)

  // Throws InvalidArgument naming `RotationalOptions::<field>`: order, spacing (the ranges of
  // rotational_fields()) or shear_stiffness (> 0 when given).
  void check() const;
};

/// \brief RotationalOptions' scalar fields defined once (option_fields.hpp): check(), the flags of
/// `toolpoint rotational` and the attributes of Python's RotationalOptions derive from this table
/// (p_method, an enum, and shear_stiffness, optional, have their own definitions).
/// \return the table, in the order of the fields
const std::vector<OptionField<RotationalOptions>>& rotational_fields();

// The translational FRFs measured on points 0, 1, 2. Unused slots stay empty.
struct PointFrfs {
  std::array<std::array<std::optional<FrfSeries>, 3>, 3> h;  // h[i][j] = H_ij
  std::array<std::array<std::string, 3>, 3> source;          // where each came from (errors)
  // What their source could not read (a universal file's skipped datasets, UffFile::skipped): a
  // missing H_ij may be among them, so it is not approximated around (rotational_frfs).
  std::vector<std::string> unread;

  // Stores H_{response,force}; `source` (a file name) defaults to "H<response><force>".
  void set(int response, int force, FrfSeries series, std::string source = {});
  // The label used in messages: "H10 (file.csv)" or "H10".
  std::string label(int response, int force) const;
};

struct RotationalResult {
  BlockSeries block;                       // [[H00, L], [N, P]] on H00's frequency grid
  bool p_from_cross_terms = false;         // false: P ≈ N·L/H00 (Schmitz & Smith)
  bool l_equals_n_by_reciprocity = false;  // L or N (or both) built from transposed data
  // max_f |L − N| / max_f max(|L|, |N|) when L and N came from independent data before any
  // symmetrising (a reciprocity and measurement-quality check); empty otherwise.
  std::optional<double> reciprocity_mismatch;
  std::vector<std::string> filled_by_reciprocity;  // "H01 := H10 (tip.csv)", with assume_reciprocity only
  std::vector<std::string> warnings;               // reciprocity fills, the P approximation, unused inputs
};

// Builds the tip block. Throws InvalidArgument (options), InputError (a needed H_ij missing,
// naming it; grids that differ, naming both sources; non-finite values) and NumericalError
// (H00 = 0 where P ≈ N·L/H00 divides by it).
RotationalResult rotational_frfs(const PointFrfs& frfs, const RotationalOptions& options);

}  // namespace toolpoint
