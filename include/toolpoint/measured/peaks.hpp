// toolpoint: resonance peaks of an FRF magnitude.
//
// Units: frequencies in Hz; magnitudes in the FRF's own units (m/N for receptance).
#pragma once

#include <functional>
#include <vector>

#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint {

struct Peak {
  std::size_t index = 0;      // grid index of the local maximum
  double frequency_hz = 0.0;  // refined peak frequency
  double magnitude = 0.0;     // refined |FRF| at the peak
  double prominence = 0.0;    // peak height over the higher of the two surrounding minima, relative to the peak
};

struct PeakOptions {
  // A local maximum counts as a peak when it rises at least this fraction of its height above
  // the higher of the minima separating it from its higher neighbours (so ripple and noise on a
  // flank are not modes).
  double min_prominence = 0.02;
  void check() const;  // the range of peak_fields(); InvalidArgument naming `PeakOptions::min_prominence`
};

/// \brief PeakOptions' field defined once (option_fields.hpp): check() and the attribute of Python's
/// PeakOptions derive from this table.
/// \return the table
const std::vector<OptionField<PeakOptions>>& peak_fields();

// Local maxima of a sampled magnitude (≥ 0) with their prominence as defined in Peak, at least
// `min_prominence`, in index order; frequency_hz and magnitude are left at 0 and m[i]. A maximum
// is a point above its left neighbour and above its right one, or a plateau of equal values that
// falls on both sides (counted once, at its middle index); a plateau that rises again is no peak.
// Non-finite values (gaps) are never peaks and are skipped when looking for the valleys. A
// prominence p is a peak-to-valley ratio 1/(1 − p): 20·log10 of it in dB.
std::vector<Peak> find_peaks(const std::vector<double>& magnitude, double min_prominence);

// Local maxima of |values| on the grid, ascending in frequency, each refined by a parabola
// through log|H| at the three grid points around it.
std::vector<Peak> find_peaks(const FrfSeries& frf, const PeakOptions& options = {});

// The same, each peak then refined on the exact magnitude function (e.g. a model evaluated at
// any frequency) between its grid neighbours.
std::vector<Peak> find_peaks(const FrfSeries& frf, const PeakOptions& options, const std::function<double(double)>& magnitude);

// Modes followed through a family of FRFs (an overhang sweep, the seed's Fig. 10): the modes are
// the peaks of member `reference`. `ordered` (members in order of the swept parameter): from the
// reference outwards in both directions, each mode is matched in the next member to the nearest
// peak within `tolerance` (relative) of its frequency in the last member where it was found, so
// modes may move far over a long sweep. Not ordered: every member is matched against the
// reference directly. Either way one peak per mode, closest pairs first; peaks matched to no mode
// (noise, a mode born in the sweep) are left out. Result: [mode][member] frequency in Hz, NaN where
// the mode was not found. Throws InvalidArgument for a reference outside the family or a tolerance
// outside (0, 1).
std::vector<std::vector<double>> track_modes(const std::vector<std::vector<Peak>>& family, std::size_t reference,
                                             double tolerance = 0.15, bool ordered = true);

// Refines a peak of a magnitude function on [lo_hz, hi_hz] (it must be unimodal there) by
// golden-section search to a relative frequency tolerance of 1e-9. Returns (frequency, magnitude).
std::pair<double, double> refine_peak(const std::function<double(double)>& magnitude, double lo_hz, double hi_hz);

}  // namespace toolpoint
