// toolpoint: stability results as CSV text (stability_io.hpp). Units: rpm, mm, Hz.
#include "toolpoint/io/stability_io.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <iterator>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

std::string csv_head(const std::string& what, const std::vector<std::string>& comments, const std::string& columns) {
  std::string s = "# toolpoint " + what + "; units: spindle speed rpm, axial depth mm, chatter frequency Hz\n";
  for (const auto& c : comments) s += "# " + c + "\n";
  return s + columns + "\n";
}

std::string optional_number(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); }

}  // namespace

std::string tool_geometry_text(const CuttingConditions& c) {
  std::vector<std::string> parts;
  auto list = [](const std::vector<double>& v, double scale) {
    std::string s;
    for (double x : v) s += (s.empty() ? "" : ",") + fmt::format("{:.6g}", x * scale);
    return s;
  };
  if (!c.pitch_rad.empty()) parts.push_back(fmt::format("pitch {} deg", list(c.pitch_rad, 180.0 / kPi)));
  if (c.helical()) {
    parts.push_back(fmt::format("helix {} deg", list(c.helix_rad, 180.0 / kPi)));
    if (!c.uniform() && c.helix_rad.size() > 1)
      parts.push_back(fmt::format("{} axial slices", c.helix_slices > 0 ? c.helix_slices : 8));
  }
  if (!c.runout_m.empty()) parts.push_back(fmt::format("runout {} mm", list(c.runout_m, 1e3)));
  if (!c.runout_m.empty()) parts.push_back(fmt::format("feed {:.6g} mm/tooth", c.feed_per_tooth_m * 1e3));
  if (c.process_damping_n_per_m > 0.0) parts.push_back(fmt::format("process damping C_i {:.6g} N/m", c.process_damping_n_per_m));
  if (parts.empty()) return "";
  if (c.diameter_m > 0.0) parts.push_back(fmt::format("diameter {:.6g} mm", c.diameter_m * 1e3));
  std::string s;
  for (const std::string& p : parts) s += (s.empty() ? "" : ", ") + p;
  return s;
}

std::string depth_text_mm(double depth_mm, double error_mm) {
  if (!std::isfinite(depth_mm))
    throw NumericalError(fmt::format("an axial depth of {} mm cannot be written: a result out of the range of double "
                                     "precision or undefined",
                                     depth_mm),
                         "check the modal model's and the cutting coefficients' magnitudes and units");
  if (!(std::isfinite(error_mm) && error_mm > 0.0) || depth_mm == 0.0) return fmt::format("{}", depth_mm);
  // Decimal places that keep two significant digits of the error, within 3…9 significant digits.
  const int magnitude = static_cast<int>(std::floor(std::log10(std::abs(depth_mm))));
  const int error_place = static_cast<int>(std::floor(std::log10(error_mm))) - 1;
  const int significant = std::clamp(magnitude - error_place + 1, 3, 9);
  // Fixed decimals up to a metre and more; beyond 1e9 mm (a unit slip, said elsewhere) the same
  // significant digits in exponent form rather than a row of meaningless zeros.
  if (magnitude >= 9) return fmt::format("{:.{}e}", depth_mm, significant - 1);
  return fmt::format("{:.{}f}", depth_mm, std::max(0, significant - magnitude - 1));
}

std::string format_lobes_csv(const ZeroOrderResult& result, const std::vector<std::string>& comments) {
  std::string s = csv_head("stability lobes, zero-order approximation (root: which eigenvalue of the quadratic)", comments,
                           "lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,root");
  result.for_each_point([&](const LobePoint& p) {
    if (!std::isfinite(p.speed_rpm) || !std::isfinite(p.depth_m) || !std::isfinite(p.chatter_hz))
      throw NumericalError(fmt::format("lobe {} has a point that is not finite ({} rpm, {} m, {} Hz): a result out of the "
                                       "range of double precision; nothing was written",
                                       p.lobe, p.speed_rpm, p.depth_m, p.chatter_hz),
                           "check the FRF's and the cutting coefficients' magnitudes and units");
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{}\n", p.lobe, p.speed_rpm, p.depth_m * 1e3, p.chatter_hz, p.root);
  });
  return s;
}

std::string format_boundary_csv(const BoundaryResult& result, const std::vector<std::string>& comments) {
  std::string s = csv_head(fmt::format("stability boundary, full-discretization of degree {} (kind: hopf, flip = period "
                                       "doubling, none = stable up to {:.6g} mm; lobe −1 where unknown; axial_depth_error_mm: "
                                       "estimated discretization error, target {:.3g} %; depths to the digits their error "
                                       "supports, chatter frequencies to 0.1 Hz)",
                                       result.degree, result.max_depth_m * 1e3, 100.0 * result.tolerance),
                           comments,
                           "lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,kind,axial_depth_error_mm,steps");
  for (const BoundaryPoint& b : result.boundary)
    fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{}\n", b.lobe, b.speed_rpm,
                   depth_text_mm(b.depth_m * 1e3, b.depth_error_m * 1e3),
                   std::isfinite(b.chatter_hz) ? fmt::format("{:.1f}", b.chatter_hz) : std::string(), to_string(b.kind),
                   std::isfinite(b.depth_error_m) ? fmt::format("{:.2g}", b.depth_error_m * 1e3) : std::string(), b.steps);
  return s;
}

std::string format_envelope_csv(const std::vector<EnvelopePoint>& envelope, const std::vector<std::string>& comments) {
  std::string s = csv_head("stable envelope (minimum over lobes)", comments,
                           "spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe");
  for (const EnvelopePoint& e : envelope)
    if (std::isfinite(e.depth_m))
      fmt::format_to(std::back_inserter(s), "{},{},{},{}\n", e.speed_rpm, e.depth_m * 1e3, optional_number(e.chatter_hz), e.lobe);
  return s;
}

}  // namespace toolpoint
