// toolpoint study: Savitzky–Golay smoothing of a measured FRF or 2×2 block (seed Section 4) with
// what it did — the procedure behind `toolpoint filter`, as one library call: the filter
// (signal.hpp's savgol_filter, real and imaginary parts separately), its white-noise gain and the
// prominent peaks before and after (signal.hpp's peak_changes).
//
// Noise gain: an interior output is y_i = Σ_k c_k x_{i+k}, so white noise of variance σ² comes
// out with variance σ² Σ c_k² (e.g. 17/35 ≈ 0.486 for a window of 5 points, order 2): the
// factor by which the filter reduces the noise's variance (its standard deviation by the root).
// The first and last window/2 points, fitted by one polynomial each, are reduced less.
// Units: frequencies in Hz; values in the series' own units (receptance m/N), unchanged; the
// window counts frequency points.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint {

struct FilterStudyOptions {
  SavgolOptions savgol;     // window [points] and order (the command has no defaults: it asks for both)
  PeakChangeOptions peaks;  // which peaks are compared and when a change is a warning
  // Throws InvalidArgument naming `SavgolOptions::<field>` or `PeakChangeOptions::<field>`.
  void check() const;
};

template <class Series>
struct FilterStudy {
  Series filtered;                    // on the input's grid
  double noise_gain = 0.0;            // Σ c_k² over the interior weights: white-noise variance after / before
  PeakChangeReport peaks;             // the prominent peaks of every entry before and after (its warnings included below)
  std::vector<std::string> warnings;  // the filter's (an uneven grid), then the peaks' (a peak changed > 2 %)
};

// Filters `raw` (a single FRF, or every entry of a block) and compares the peaks. The window may
// be at most a quarter of the points (check_smoothing_window: a longer one follows the curve, not
// its noise). `what` names the data in messages. Throws InvalidArgument (options, the window
// against the points), InputError (non-finite values, an invalid series), NumericalError (an order
// too high for accurate weights).
FilterStudy<FrfSeries> run_filter_study(const FrfSeries& raw, const FilterStudyOptions& options, const std::string& what = "FRF");
FilterStudy<BlockSeries> run_filter_study(const BlockSeries& raw, const FilterStudyOptions& options,
                                          const std::string& what = "block series");

// Σ c_k² of savgol_coefficients(options): the interior white-noise variance gain (see above).
double savgol_noise_gain(const SavgolOptions& options);

}  // namespace toolpoint
