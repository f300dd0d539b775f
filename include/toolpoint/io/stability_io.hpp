// toolpoint: stability results as CSV text — the I/O layer of stability.hpp.
//
// Units (stated in each file's first comment line): spindle speed rpm, axial depth mm, chatter
// frequency Hz. Numbers are written in shortest round-trip form, except where a result carries its
// own accuracy: a boundary depth is then written with the digits its error estimate supports.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/stability/stability.hpp"

namespace toolpoint {

// Zero-order lobes: `lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,root`, every lobe
// point (ZeroOrderResult::for_each_point). `comments` become '#' lines after the units line.
std::string format_lobes_csv(const ZeroOrderResult& result, const std::vector<std::string>& comments = {});

// The time-domain boundary: `lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,kind,
// axial_depth_error_mm,steps` (kind hopf, flip, fold or none; the error is the Richardson estimate,
// empty for none; steps per tooth period of the finer level).
std::string format_boundary_csv(const BoundaryResult& result, const std::vector<std::string>& comments = {});

// The stable envelope: `spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe`; speeds no
// lobe reaches are left out.
std::string format_envelope_csv(const std::vector<EnvelopePoint>& envelope, const std::vector<std::string>& comments = {});

// A depth [mm] with the digits its estimated error [mm] supports: two significant digits of the
// error (at least 3, at most 9 significant digits in all); all digits when the error is unknown.
std::string depth_text_mm(double depth_mm, double error_mm);

// The cutting conditions beyond evenly spaced straight teeth, for a file's comment line (the
// reader's units: degrees, mm, N/m), e.g. "pitch 70,110,70,110 deg, helix 30 deg, diameter 20 mm";
// "" when there are none (the lobes of today's straight, even tool).
std::string tool_geometry_text(const CuttingConditions& cutting);

}  // namespace toolpoint
