// toolpoint study: the simulation's figures (studies/simulation.hpp). Plotted units: time ms,
// displacement µm, velocity mm/s, force N, frequency Hz, feed position mm, spindle speed rpm, depth mm.
#include <algorithm>
#include <cmath>
#include <complex>
#include <fmt/format.h>
#include <limits>
#include <unsupported/Eigen/FFT>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/studies/simulation.hpp"

namespace toolpoint {

namespace {


const SimulationResult& recorded(const SimulationStudyResult& r, const char* figure) {
  if (r.simulation.time_s.empty())
    throw InvalidArgument(fmt::format("{} figure: the simulation kept no histories (SimulationOptions::record = false)", figure),
                          "simulate with SimulationOptions::record = true");
  return r.simulation;
}

std::string cut_title(const SimulationStudyResult& r) {
  return fmt::format("{:.0f} rpm, depth {:.3g} mm, {} teeth, feed {:.3g} mm/tooth{}", r.cut.speed_rpm, 1e3 * r.cut.depth_m,
                     r.cutter.teeth(), 1e3 * r.cut.feed_per_tooth_m,
                     r.simulation.stable ? ", stable" : fmt::format(", chatter at {:.0f} Hz", r.simulation.chatter_hz));
}

// Whether the y displacement is identically zero (a tool rigid in y): the figures then use x̂ and v_x.
bool rigid_in_y(const SimulationResult& s) {
  return std::all_of(s.y_m.begin(), s.y_m.end(), [](double v) { return v == 0.0; });
}

// Every k-th index so that at most `most` points remain.
std::size_t stride(std::size_t n, std::size_t most) { return std::max<std::size_t>(1, (n + most - 1) / most); }

}  // namespace

plot::Figure simulation_time_figure(const SimulationStudyResult& r) {
  const SimulationResult& s = recorded(r, "time history");
  const std::size_t per_rev = static_cast<std::size_t>(s.steps_per_revolution);
  const std::size_t revs = std::min<std::size_t>(5, static_cast<std::size_t>(s.revolutions));
  const std::size_t first = s.time_s.size() - 1 - revs * per_rev;
  const std::size_t step = stride(s.time_s.size() - first, 20000);
  plot::Figure fig;
  fig.title = "Time history: " + cut_title(r);
  fig.x.label = "Time [ms]";
  plot::Panel force, disp;
  force.y.label = "Force on the tool [N]";
  disp.y.label = "Displacement [µm]";
  plot::Curve fx, fy, x, y;
  fx.label = "F_x (feed)";
  fy.label = "F_y (normal)";
  x.label = "x (feed)";
  y.label = "y (normal)";
  for (std::size_t k = first; k < s.time_s.size(); k += step) {
    const double t = 1e3 * s.time_s[k];
    fx.x.push_back(t);
    fx.y.push_back(s.force_x_n[k]);
    fy.x.push_back(t);
    fy.y.push_back(s.force_y_n[k]);
    x.x.push_back(t);
    x.y.push_back(1e6 * s.x_m[k]);
    y.x.push_back(t);
    y.y.push_back(1e6 * s.y_m[k]);
  }
  force.curves = {std::move(fx), std::move(fy)};
  disp.curves.push_back(std::move(x));
  if (!rigid_in_y(s)) disp.curves.push_back(std::move(y));
  plot::Curve teeth;
  teeth.label = "once per tooth";
  teeth.style = plot::CurveStyle::Points;
  for (const MotionSample& m : s.per_tooth)
    if (m.time_s >= s.time_s[first]) {
      teeth.x.push_back(1e3 * m.time_s);
      teeth.y.push_back(1e6 * m.x_m);
    }
  if (!teeth.x.empty()) disp.curves.push_back(std::move(teeth));
  force.legend = disp.legend = plot::Legend::Outside;
  fig.panels = {std::move(force), std::move(disp)};
  fig.width_px = 1200;
  return fig;
}

plot::Figure simulation_poincare_figure(const SimulationStudyResult& r) {
  const SimulationResult& s = recorded(r, "Poincaré");
  const bool planar = !rigid_in_y(s);
  // x against y; a tool rigid in y: x against its velocity (the state plane of the one mode).
  auto second = [&](double y, double vx) { return planar ? 1e6 * y : 1e3 * vx; };
  const std::size_t first = static_cast<std::size_t>(s.analysed_from) * static_cast<std::size_t>(s.steps_per_revolution);
  const std::size_t step = stride(s.time_s.size() - first, 20000);
  plot::Figure fig;
  fig.title = "Poincaré section: " + cut_title(r);
  fig.x.label = "x displacement [µm]";
  plot::Panel p;
  p.y.label = planar ? "y displacement [µm]" : "x velocity [mm/s]";
  plot::Curve path, rev, tooth;
  path.label = "path (analysed revolutions)";
  for (std::size_t k = first; k < s.time_s.size(); k += step) {
    path.x.push_back(1e6 * s.x_m[k]);
    path.y.push_back(second(s.y_m[k], s.vx_m_per_s[k]));
  }
  tooth.label = "once per tooth";
  tooth.style = plot::CurveStyle::Points;
  for (const MotionSample& m : s.per_tooth)
    if (m.time_s >= s.time_s[first]) {
      tooth.x.push_back(1e6 * m.x_m);
      tooth.y.push_back(second(m.y_m, m.vx_m_per_s));
    }
  rev.label = "once per revolution";
  rev.style = plot::CurveStyle::Points;
  for (const MotionSample& m : s.per_revolution)
    if (m.time_s >= s.time_s[first]) {
      rev.x.push_back(1e6 * m.x_m);
      rev.y.push_back(second(m.y_m, m.vx_m_per_s));
    }
  p.curves.push_back(std::move(path));
  if (!tooth.x.empty()) p.curves.push_back(std::move(tooth));
  if (!rev.x.empty()) p.curves.push_back(std::move(rev));
  p.legend = plot::Legend::Outside;
  fig.panels.push_back(std::move(p));
  fig.width_px = 1100;
  fig.height_px = 800;
  return fig;
}

plot::Figure simulation_spectrum_figure(const SimulationStudyResult& r) {
  const SimulationResult& s = recorded(r, "spectrum");
  const std::size_t first = static_cast<std::size_t>(s.analysed_from) * static_cast<std::size_t>(s.steps_per_revolution);
  const std::size_t n = s.time_s.size() - 1 - first;
  const double tooth_hz = r.cutter.teeth() * r.cut.speed_rpm / 60.0;
  const double top = std::max(
      {10.5 * tooth_hz, 2.0 * r.dynamics.highest_frequency_hz(), std::isfinite(s.chatter_hz) ? 1.5 * s.chatter_hz : 0.0});
  plot::Figure fig;
  fig.title = "Spectrum of the displacement (analysed revolutions, Hann window): " + cut_title(r);
  fig.x.label = "Frequency [Hz]";
  fig.x.min = 0.0;
  fig.x.max = top;
  plot::Panel p;
  p.y.label = "Amplitude [µm]";
  p.y.scale = plot::Scale::Log;
  const bool planar = !rigid_in_y(s);
  Eigen::FFT<double> fft;
  double wsum = 0.0;
  std::vector<double> w(n);
  for (std::size_t i = 0; i < n; ++i)
    wsum += w[i] = 0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(n));
  for (int axis = 0; axis < (planar ? 2 : 1); ++axis) {
    const std::vector<double>& v = axis == 0 ? s.x_m : s.y_m;
    double mean = 0.0;
    for (std::size_t i = 0; i < n; ++i) mean += v[first + 1 + i] / static_cast<double>(n);
    std::vector<double> b(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = w[i] * (v[first + 1 + i] - mean);
    std::vector<std::complex<double>> spec;
    fft.fwd(spec, b);
    plot::Curve c;
    c.label = axis == 0 ? "x" : "y";
    const double df = 1.0 / (static_cast<double>(n) * s.step_s);
    for (std::size_t i = 1; i < n / 2 && static_cast<double>(i) * df <= top; ++i) {
      c.x.push_back(static_cast<double>(i) * df);
      c.y.push_back(1e6 * 2.0 * std::abs(spec[i]) / wsum);
    }
    p.curves.push_back(std::move(c));
  }
  for (int k = 1; k * tooth_hz <= top; ++k) p.vertical_lines.push_back({k * tooth_hz, k == 1 ? "tooth passing" : ""});
  if (!s.stable && std::isfinite(s.chatter_hz))
    p.vertical_lines.push_back({s.chatter_hz, fmt::format("chatter {:.0f} Hz", s.chatter_hz)});
  fig.panels.push_back(std::move(p));
  fig.width_px = 1200;
  return fig;
}

plot::Figure simulation_surface_figure(const SimulationStudyResult& r) {
  const SimulationResult& s = recorded(r, "surface");
  if (s.walls.empty() || s.walls.front().passes.empty())
    throw InvalidArgument("surface figure: the cut leaves no wall (entry at 0° or exit at 180° makes one)",
                          "cut up or down to a wall (MillingCut::engagement), or leave the surface figure out");
  const Wall& wall = s.walls.front();
  const double feed_rate = r.cutter.teeth() * r.cut.feed_per_tooth_m * r.cut.speed_rpm / 60.0;
  const double t0 = s.time_s[static_cast<std::size_t>(s.analysed_from) * static_cast<std::size_t>(s.steps_per_revolution)];
  const double x0 = feed_rate * t0, x1 = feed_rate * s.time_s.back();
  std::vector<double> xs;
  const int points = std::min(20000, std::max(200, 40 * r.cutter.teeth() * (s.revolutions - s.analysed_from)));
  for (int i = 0; i <= points; ++i) xs.push_back(x0 + (x1 - x0) * i / points);
  plot::Figure fig;
  fig.title = fmt::format("Machined wall at φ = {:.0f}° (material left, +: undercut): {}", degrees_of(wall.angle_rad),
                          cut_title(r));
  fig.x.label = "Position along the feed [mm]";
  plot::Panel p;
  p.y.label = "Surface location error [µm]";
  std::vector<int> slices{0};
  if (s.slices > 2) slices.push_back(s.slices / 2);
  if (s.slices > 1) slices.push_back(s.slices - 1);
  for (int l : slices) {
    const std::vector<double> y = wall_profile(wall, l, 0.5 * r.cutter.diameter_m, r.cutter.runout_m, xs);
    plot::Curve c;
    c.label = fmt::format("z = {:.3g} mm", 1e3 * wall.slice_height_m[static_cast<std::size_t>(l)]);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      c.x.push_back(1e3 * xs[i]);
      c.y.push_back(std::isfinite(y[i]) ? 1e6 * y[i] : kNaN);
    }
    p.curves.push_back(std::move(c));
  }
  if (std::isfinite(wall.mean_sle_m))
    p.horizontal_lines.push_back({1e6 * wall.mean_sle_m, fmt::format("mean SLE {:.3g} µm", 1e6 * wall.mean_sle_m)});
  p.legend = plot::Legend::Outside;
  fig.panels.push_back(std::move(p));
  fig.width_px = 1200;
  return fig;
}

plot::Figure simulated_map_figure(const SimulatedMap& m) {
  const SimulatedMapHeader& h = m.header;
  if (m.rows.empty()) throw InvalidArgument("simulated map figure: the map has no speeds");
  plot::Figure fig;
  fig.title = fmt::format("Simulated stability: {} teeth, a/D from φ {:.0f}°–{:.0f}°, {} revolutions per cell",
                          h.options.cutter.teeth(), degrees_of(h.options.cut.engagement.entry_rad),
                          degrees_of(h.options.cut.engagement.exit_rad), h.options.simulation.revolutions);
  fig.x.label = "Spindle speed [rpm]";
  fig.width_px = 1200;
  plot::Panel p;
  p.y.label = "Axial depth [mm]";
  plot::Map map;
  map.x = h.speeds_rpm;
  for (double d : h.depths_m) map.y.push_back(1e3 * d);
  map.z.assign(map.x.size() * map.y.size(), kNaN);
  plot::Map sle = map;
  bool any_sle = false;
  for (const SimulatedMapRow& r : m.rows)
    for (std::size_t d = 0; d < h.depths_m.size(); ++d) {
      const std::size_t at = d * map.x.size() + r.speed_index;
      // The chatter metric: ~0 for a periodic cut, of order 1 for chatter (a diverged run at the top).
      map.z[at] = std::isfinite(r.growth[d]) && std::isfinite(r.chatter_metric[d]) ? std::max(r.chatter_metric[d], 1e-6) : 10.0;
      if (r.stable[d] && std::isfinite(r.sle_m[d])) {
        sle.z[at] = 1e6 * r.sle_m[d];
        // A tool rigid in y leaves no SLE but rounding (1e-20 m): no panel for that.
        any_sle = any_sle || std::abs(r.sle_m[d]) > 1e-12;
      }
    }
  map.colour = {"Chatter metric (once-per-period variation / vibration)", plot::Scale::Log, 1e-6, 10.0};
  p.map = std::move(map);
  plot::Curve b;
  b.label = "lowest unstable depth";
  b.style = plot::CurveStyle::LinePoints;
  for (const EnvelopePoint& e : m.boundary) {
    b.x.push_back(e.speed_rpm);
    b.y.push_back(std::isfinite(e.depth_m) ? 1e3 * e.depth_m : kNaN);
  }
  p.curves.push_back(std::move(b));
  p.legend = plot::Legend::TopLeft;
  fig.panels.push_back(std::move(p));
  if (any_sle) {
    plot::Panel q;
    q.y.label = "Axial depth [mm]";
    // The colour scale spans the 2nd to 98th percentile: cells beside the boundary, whose transient
    // has barely decayed, would otherwise leave the rest one colour.
    std::vector<double> v;
    for (double z : sle.z)
      if (std::isfinite(z)) v.push_back(z);
    std::sort(v.begin(), v.end());
    const auto at = [&](double level) { return v[static_cast<std::size_t>(level * static_cast<double>(v.size() - 1))]; };
    sle.colour = {"SLE of the stable cuts [µm] (+: undercut)", plot::Scale::Linear, at(0.02), at(0.98)};
    if (!(*sle.colour.max > *sle.colour.min)) sle.colour.min = sle.colour.max = std::nullopt;
    q.map = std::move(sle);
    q.legend = plot::Legend::Hidden;
    fig.panels.push_back(std::move(q));
    fig.height_px = 1100;
  }
  return fig;
}

}  // namespace toolpoint
