// toolpoint: the forward prediction study (studies/predict.hpp).
#include "toolpoint/studies/predict.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <string>
#include <utility>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/plausibility.hpp"
#include "toolpoint/studies/lobes.hpp"

namespace toolpoint {

const char* predicted_frf_name(PredictedFrf frf) { return frf == PredictedFrf::ToolPoint ? "SHT11" : "SH11"; }

void PredictOptions::check() const {
  try {
    peaks.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("PredictOptions::peaks: {}", e.what()), e.hint());
  }
  check_fields(predict_fields(), *this, "PredictOptions");
  if (speed_rpm > 0.0 && (receptance != PredictedFrf::ToolPoint || uncertain_joint))
    throw InvalidArgument("PredictOptions::speed_rpm > 0 is for the tool point without PredictOptions::uncertain_joint",
                          "drop the speed, or predict the tool point without the joint's band");
  if (!uncertain_joint) return;
  if (receptance != PredictedFrf::ToolPoint)
    throw InvalidArgument("PredictOptions::uncertain_joint: the band is computed for the tool point, not the holder tip",
                          "set PredictOptions::receptance to ToolPoint, or leave uncertain_joint empty");
  band.check();
}

const std::vector<OptionField<PredictOptions>>& predict_fields() {
  using O = PredictOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "speed_rpm",
        .kind = FieldKind::Real,
        .unit = "rpm",
        .min = 0.0,
        .note = "0: standing",
        .help = "spindle speed: the spinning assembly in two planes (gyroscopic whirl, docs/spindle-at-speed.md); the "
                "FRF and the modes are then its x–x block",
        .cli_name = "speed",
        .plausible = &plausible::kSpinSpeedRpm},
       [](O& o) -> double& { return o.speed_rpm; }},
      {{.name = "extrapolate_bearings",
        .kind = FieldKind::Flag,
        .help = "bearings with a speed table: extend the end rows' line beyond the table (else a speed outside it is an "
                "error)",
        .cli_name = "extrapolate-bearings"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.extrapolate_bearings; }}};
  return fields;
}

namespace {

Assembly bearings_at_speed(const Assembly& a, const PredictOptions& options) {
  try {
    return at_speed(a, options.speed_rpm, options.extrapolate_bearings);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("PredictOptions::speed_rpm: {}", e.what()),
                          std::string(e.hint()).find("extrapolat") != std::string::npos
                              ? "extend the table, or set PredictOptions::extrapolate_bearings"
                              : e.hint());
  }
}

// The tool point in two planes (PredictOptions::speed_rpm): the 4×4 blocks, their x–x part as
// the FRF, its modes refined on the model's x–x part.
Prediction two_plane_prediction(const AssemblyModel& model, const std::vector<double>& grid, const PredictOptions& options,
                                const ProgressCallback& progress) {
  const double spin = rad_s_of_rpm(options.speed_rpm);
  Prediction p;
  p.receptance = PredictedFrf::ToolPoint;
  p.warnings = model.warnings();
  for (std::string& w : field_plausibility_warnings(predict_fields(), options, "PredictOptions")) p.warnings.push_back(std::move(w));
  p.speed_rpm = options.speed_rpm;
  p.two_plane = model.tool_point_two_plane(grid, spin);
  p.frf.frequency_hz = grid;
  for (const Block4& b : p.two_plane.blocks) p.frf.blocks.push_back(b.topLeftCorner<2, 2>());
  if (progress) progress(1.0);
  const auto magnitude = [&](double f) { return std::abs(model.tool_point_two_plane(f, spin)(0, 0)); };
  p.modes = find_peaks(entry(p.frf, 0), options.peaks, magnitude);
  return p;
}

}  // namespace

plot::Figure speed_frf_figure(const Assembly& assembly, const std::vector<double>& speeds_rpm, bool extrapolate_bearings) {
  if (speeds_rpm.empty()) throw InvalidArgument("speed_frf_figure: no speed given", "give one or more speeds [rpm]");
  for (double n : speeds_rpm)
    if (!(std::isfinite(n) && n >= 0.0)) throw InvalidArgument(fmt::format("speed_frf_figure: speed {} rpm must be ≥ 0", n));
  const std::vector<double> grid = assembly.grid.values();
  SpeedDependentFrfs s;
  try {
    s = milling_frfs_at_speeds(assembly, grid, speeds_rpm, true, extrapolate_bearings);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("speed_frf_figure: {}", e.what()), e.hint());
  }
  plot::Figure fig;
  fig.title = fmt::format("Tool point FRF at speed: {}", plot::literal(assembly.name));
  fig.x.label = "Frequency [Hz]";
  plot::Panel xx, xy;
  xx.y.label = "|H_{xx}| [m/N]";
  xy.y.label = "|H_{xy}| [m/N]";
  xx.y.scale = xy.y.scale = plot::Scale::Log;
  xx.legend = plot::Legend::Outside;
  for (std::size_t j = 0; j < speeds_rpm.size(); ++j) {
    std::vector<double> a, c;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      a.push_back(std::abs(s.frfs[j].xx.values[i]));
      c.push_back(std::abs(s.frfs[j].xy->values[i]));  // 0 at rest with isotropic bearings: left out of the log axis
    }
    const std::string label = fmt::format("{:g} rpm", speeds_rpm[j]);
    xx.curves.push_back({grid, a, label, plot::CurveStyle::Line, static_cast<int>(j)});
    xy.curves.push_back({grid, c, "", plot::CurveStyle::Line, static_cast<int>(j)});
  }
  xy.height = 0.7;
  fig.panels = {std::move(xx), std::move(xy)};
  return fig;
}

std::string cross_receptance_csv(const BlockSeries4& s) {
  std::string out = "frequency_hz,Hxx_re,Hxx_im,Hxy_re,Hxy_im,Hyx_re,Hyx_im,Hyy_re,Hyy_im\n";
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Block4& b = s.blocks[i];
    out += fmt::format("{}", s.frequency_hz[i]);
    for (const auto& [r, c] : {std::pair{0, 0}, std::pair{0, 2}, std::pair{2, 0}, std::pair{2, 2}})
      out += fmt::format(",{},{}", b(r, c).real(), b(r, c).imag());
    out += '\n';
  }
  return out;
}

Prediction run_prediction_study(const Assembly& given, const PredictOptions& options, const ProgressCallback& progress) {
  options.check();
  // A sampled joint file's joint is the nominal one, so the prediction and the band describe the
  // same joint (the samples replace the assembly's joint too).
  const Assembly joined = options.uncertain_joint ? with_joint(given, *options.uncertain_joint) : given;
  // The bearings at the speed (their tables read there; PredictOptions::extrapolate_bearings).
  const Assembly assembly = has_speed_tables(joined) ? bearings_at_speed(joined, options) : joined;
  // An option that changes nothing is said, not ignored.
  const auto said = [&](Prediction p) {
    if (options.extrapolate_bearings && !has_speed_tables(joined))
      p.warnings.push_back(
          "PredictOptions::extrapolate_bearings changes nothing: no bearing of the assembly has a speed table");
    return p;
  };
  const AssemblyModel model(assembly);
  const bool tool = options.receptance == PredictedFrf::ToolPoint;
  const std::vector<double> grid = assembly.grid.values();
  if (tool && (options.speed_rpm > 0.0 || !model.isotropic())) return said(two_plane_prediction(model, grid, options, progress));
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
  return said(std::move(p));
}

}  // namespace toolpoint
