// toolpoint: the forward prediction study (studies/predict.hpp).
#include "toolpoint/studies/predict.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

const char* predicted_frf_name(PredictedFrf frf) { return frf == PredictedFrf::ToolPoint ? "SHT11" : "SH11"; }

void PredictOptions::check() const {
  try {
    peaks.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("PredictOptions::peaks: {}", e.what()), e.hint());
  }
  if (!uncertain_joint) return;
  if (receptance != PredictedFrf::ToolPoint)
    throw InvalidArgument("PredictOptions::uncertain_joint: the band is computed for the tool point, not the holder tip",
                          "set PredictOptions::receptance to ToolPoint, or leave uncertain_joint empty");
  band.check();
}

Prediction run_prediction(const Assembly& given, const PredictOptions& options, const ProgressCallback& progress) {
  options.check();
  // A sampled joint file's joint is the nominal one, so the prediction and the band describe the
  // same joint (the samples replace the assembly's joint too).
  const Assembly assembly = options.uncertain_joint ? with_joint(given, *options.uncertain_joint) : given;
  const AssemblyModel model(assembly);
  const bool tool = options.receptance == PredictedFrf::ToolPoint;
  const std::vector<double> grid = assembly.grid.values();
  // With a band, the prediction is one unit of work and each joint sample another.
  const double share = options.uncertain_joint ? 1.0 / (options.band.samples + 1.0) : 1.0;
  Prediction p;
  p.receptance = options.receptance;
  p.warnings = model.warnings();
  p.frf.frequency_hz = grid;
  p.frf.blocks.reserve(grid.size());
  // The sweep in blocks, for progress on long grids. A block length that is a multiple of the
  // four SIMD lanes keeps every frequency in the lane it has in one whole sweep, and no frequency
  // depends on another: the values are those of one sweep, bit for bit.
  constexpr std::size_t kBlock = 4096;
  for (std::size_t start = 0; start < grid.size(); start += kBlock) {
    const std::size_t stop = std::min(grid.size(), start + kBlock);
    const std::vector<double> part(grid.begin() + static_cast<std::ptrdiff_t>(start),
                                   grid.begin() + static_cast<std::ptrdiff_t>(stop));
    const BlockSeries s = tool ? model.tool_point(part) : model.holder_tip(part);
    p.frf.blocks.insert(p.frf.blocks.end(), s.blocks.begin(), s.blocks.end());
    if (progress) progress(share * static_cast<double>(stop) / static_cast<double>(grid.size()));
  }
  const auto magnitude = [&](double f) { return std::abs((tool ? model.tool_point(f) : model.holder_tip(f))(0, 0)); };
  p.modes = find_peaks(entry(p.frf, 0), options.peaks, magnitude);
  if (options.uncertain_joint) {
    UncertaintyOptions band = options.band;
    band.progress = {};
    if (progress) band.progress = [&](double f) { progress(share + (1.0 - share) * f); };
    p.band = tool_point_band(assembly, *options.uncertain_joint, grid, band);
  }
  return p;
}

}  // namespace toolpoint
