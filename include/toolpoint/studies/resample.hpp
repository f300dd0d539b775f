// toolpoint study: a measured file's FRF on another grid, as `toolpoint resample` does it — the
// FRF (single or block) and its coherence cropped to a band or interpolated onto a target grid,
// in the input's form. The interpolation itself is resample.hpp's (its orders and limits there).
// Units: frequencies in Hz; values in the file's units, unchanged.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/measured/resample.hpp"

namespace toolpoint {

// With a target grid: the target cropped to the band (when one is given), then the FRF (single or
// block) and its coherence interpolated onto it. Without: the FRF and its coherence cropped to the
// band. The result keeps the input's form (single FRF or block, UFF DOF labels).
struct FrfResampleOptions {
  std::optional<std::pair<double, double>> band_hz;  // keep low ≤ f ≤ high [Hz]: of the target, or of the input
  std::optional<std::vector<double>> target_hz;      // interpolate onto these frequencies [Hz], strictly increasing
  std::string target_name = "the target grid";       // names the target in messages and the description
  Interpolation method = Interpolation::Linear;
  // Throws InvalidArgument naming `FrfResampleOptions::<field>`: neither a band nor a target, an
  // inverted or non-finite band, an empty target.
  void check() const;
};

struct FrfResampled {
  FrfFileData data;  // the result in the input's form (format, description and warnings left as defaults)
  // What was done, e.g. "linear interpolation of real and imaginary parts onto the frequencies of
  // a.csv, within 500–3000 Hz" or "cropped to 500–3000 Hz".
  std::string description;
  std::vector<std::string> warnings;  // none yet: refusals throw
};

// `input` (read_frf_file) on the grid `options` asks for; `what` names it in messages. Throws
// InvalidArgument (options), InputError (no target frequency in the band, naming both; a target
// frequency outside the measured range, the hint naming FrfResampleOptions::band_hz; no input
// point in the band).
FrfResampled run_resample_study(const FrfFileData& input, const FrfResampleOptions& options, const std::string& what);

}  // namespace toolpoint
