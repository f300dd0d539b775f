// toolpoint study: a file's FRF on another grid (studies/resample.hpp).
#include "toolpoint/studies/resample.hpp"

#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

void FrfResampleOptions::check() const {
  if (!band_hz && !target_hz)
    throw InvalidArgument("FrfResampleOptions needs band_hz (a band to crop to) or target_hz (frequencies to interpolate onto)",
                          "e.g. FrfResampleOptions::band_hz 500:3000");
  if (band_hz && !(std::isfinite(band_hz->first) && std::isfinite(band_hz->second) && band_hz->first <= band_hz->second))
    throw InvalidArgument(fmt::format("FrfResampleOptions::band_hz {}:{}: expected finite LOW ≤ HIGH", band_hz->first,
                                      band_hz->second),
                          "e.g. 500:3000");
  if (target_hz && target_hz->empty())
    throw InvalidArgument(fmt::format("FrfResampleOptions::target_hz ({}) holds no frequency", target_name));
}

FrfResampled run_resample_study(const FrfFileData& in, const FrfResampleOptions& options, const std::string& what) {
  options.check();
  const auto& band = options.band_hz;
  // The target cropped to the band first: a band narrower than the measurement is how a caller
  // keeps interpolation inside the measured range (it never extrapolates).
  std::optional<std::vector<double>> target = options.target_hz;
  if (target && band) {
    std::vector<double> kept;
    for (double f : *target)
      if (f >= band->first && f <= band->second) kept.push_back(f);
    if (kept.empty())
      throw InputError(fmt::format("no target frequency in FrfResampleOptions::band_hz {}:{} ({} spans {}–{} Hz)", band->first,
                                   band->second, options.target_name, target->front(), target->back()),
                       "choose a band that overlaps the target grid");
    target = std::move(kept);
  }
  FrfResampled r;
  FrfFileData& out = r.data;
  out.is_block = in.is_block;
  out.dof = in.dof;
  const std::vector<double>& f_in = in.is_block ? in.block.frequency_hz : in.single.frequency_hz;
  try {
    if (target) {
      if (in.is_block) out.block = resample(in.block, *target, options.method, what);
      else out.single = resample(in.single, *target, options.method, what);
      out.coherence = resample_values(f_in, in.coherence, *target, what);
      r.description = fmt::format("{} interpolation of real and imaginary parts onto {}", interpolation_name(options.method),
                                  options.target_name);
    } else {
      if (in.is_block) out.block = crop(in.block, band->first, band->second, what);
      else out.single = crop(in.single, band->first, band->second, what);
      out.coherence = crop_values(f_in, in.coherence, band->first, band->second);
      r.description = fmt::format("cropped to {}–{} Hz", band->first, band->second);
    }
  } catch (const InputError& e) {
    // A target outside the measured range: the band is what crops the target.
    throw InputError(e.what(), e.hint() + (target ? " (FrfResampleOptions::band_hz)" : ""));
  }
  if (band && target) r.description += fmt::format(", within {}–{} Hz", band->first, band->second);
  return r;
}

}  // namespace toolpoint
