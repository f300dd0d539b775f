// toolpoint: FRFs put on another frequency grid — cropped to a band, or interpolated onto given
// frequencies — so that measurements from different sessions, analysers or settings can be
// combined (identification and finite differences need one grid).
//
// Units: frequencies in Hz; values in the series' own units (receptance m/N), unchanged.
//
// Interpolation acts on the real and imaginary parts separately, and only inside the measured
// range [f_first, f_last]: a target frequency outside it is an error, never an extrapolation.
// Target frequencies equal to measured ones give the measured values exactly.
//   linear  piecewise linear: error ≤ Δf²/8 · max|H''| (second order), never overshoots;
//   cubic   natural cubic spline through every point: fourth order in the interior (the
//           natural end condition H'' = 0 makes it second order within a few steps of the ends),
//           better across a lightly damped resonance sampled coarsely.
// A coherence (real, 0…1) is interpolated linearly, whatever the method, so it stays in [0, 1].
#pragma once

#include <string>
#include <vector>

#include "toolpoint/model/receptance.hpp"

namespace toolpoint {

enum class Interpolation { Linear, Cubic };

// The points with low ≤ f ≤ high [Hz]. Throws InvalidArgument for an empty or inverted band,
// InputError (naming `what` and the measured range) when no point lies in it.
FrfSeries crop(const FrfSeries& series, double low_hz, double high_hz, const std::string& what);
BlockSeries crop(const BlockSeries& series, double low_hz, double high_hz, const std::string& what);
// The coherence of the points crop keeps (`frequency_hz` the series' grid before cropping).
std::vector<double> crop_values(const std::vector<double>& frequency_hz, const std::vector<double>& values, double low_hz,
                                double high_hz);

// The series at `grid_hz` (strictly increasing). The series needs ≥ 2 points (≥ 3 for cubic).
// Throws InputError naming `what` and the first target frequency outside the measured range,
// InvalidArgument for a target grid that is not strictly increasing and finite.
FrfSeries resample(const FrfSeries& series, const std::vector<double>& grid_hz, Interpolation method, const std::string& what);
BlockSeries resample(const BlockSeries& series, const std::vector<double>& grid_hz, Interpolation method,
                     const std::string& what);
// Real values (a coherence) at `grid_hz`, linearly.
std::vector<double> resample_values(const std::vector<double>& frequency_hz, const std::vector<double>& values,
                                    const std::vector<double>& grid_hz, const std::string& what);

// "linear" or "cubic".
const char* interpolation_name(Interpolation method);

}  // namespace toolpoint
