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
}

Prediction run_prediction(const Assembly& assembly, const PredictOptions& options, const ProgressCallback& progress) {
  options.check();
  const AssemblyModel model(assembly);
  const bool tool = options.receptance == PredictedFrf::ToolPoint;
  const std::vector<double> grid = assembly.grid.values();
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
    if (progress) progress(static_cast<double>(stop) / static_cast<double>(grid.size()));
  }
  const auto magnitude = [&](double f) { return std::abs((tool ? model.tool_point(f) : model.holder_tip(f))(0, 0)); };
  p.modes = find_peaks(entry(p.frf, 0), options.peaks, magnitude);
  return p;
}

}  // namespace toolpoint
