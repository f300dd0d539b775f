// toolpoint study: Savitzky–Golay smoothing with its noise gain and peak changes (studies/filter.hpp).
#include "toolpoint/studies/filter.hpp"

namespace toolpoint {

void FilterStudyOptions::check() const {
  savgol.check();
  peaks.check();
}

double savgol_noise_gain(const SavgolOptions& options) {
  double gain = 0.0;
  for (double c : savgol_coefficients(options)) gain += c * c;
  return gain;
}

namespace {

template <class Series>
FilterStudy<Series> filter_study(const Series& raw, const FilterStudyOptions& options, const std::string& what) {
  options.check();
  check_smoothing_window(options.savgol, raw.size(), what);
  FilterStudy<Series> r;
  SignalResult<Series> f = savgol_filter(raw, options.savgol, what);
  r.filtered = std::move(f.series);
  r.warnings = std::move(f.warnings);
  r.noise_gain = savgol_noise_gain(options.savgol);
  // The filter's window is the search half-width: a filtered peak further than that from a raw one
  // is another peak, not this one moved.
  r.peaks = peak_changes(raw, r.filtered, options.savgol.window, options.peaks, what);
  r.warnings.insert(r.warnings.end(), r.peaks.warnings.begin(), r.peaks.warnings.end());
  return r;
}

}  // namespace

FilterStudy<FrfSeries> run_filter_study(const FrfSeries& raw, const FilterStudyOptions& options, const std::string& what) {
  return filter_study(raw, options, what);
}

FilterStudy<BlockSeries> run_filter_study(const BlockSeries& raw, const FilterStudyOptions& options, const std::string& what) {
  return filter_study(raw, options, what);
}

}  // namespace toolpoint
