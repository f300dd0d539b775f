// toolpoint: the figure model — formats, verbatim text and Figure::check (plot.hpp).
#include "toolpoint/plot/plot.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "plot_detail.hpp"
#include "text.hpp"

namespace toolpoint::plot {

using namespace detail;
namespace fs = std::filesystem;

namespace {

std::string panel_name(std::size_t i, const Panel& p) {
  return p.y.label.empty() ? fmt::format("panel {}", i + 1) : fmt::format("panel {} ('{}')", i + 1, p.y.label);
}

void check_axis(const Axis& a, const std::string& where) {
  for (const auto& lim : {a.min, a.max})
    if (lim) {
      require(std::isfinite(*lim), fmt::format("{}: axis limit {} is not finite", where, *lim));
      require(plottable(*lim, a.scale), fmt::format("{}: log axis limit {} must be > 0", where, *lim),
              "use a positive limit or a linear scale");
    }
  if (a.min && a.max)
    require(*a.min < *a.max, fmt::format("{}: axis range [{}, {}] is empty or inverted", where, *a.min, *a.max));
  if (a.tic_step)
    require(std::isfinite(*a.tic_step) && *a.tic_step > 0.0,
            fmt::format("{}: tic step {} must be finite and > 0", where, *a.tic_step));
}

// A map's grid and colour bar (plot.hpp); true when some cell can be drawn.
bool check_map(const Map& m, const Axis& x, const Axis& y, const std::string& where) {
  require(x.scale == Scale::Linear && y.scale == Scale::Linear, fmt::format("{}: a map needs linear x and y axes", where),
          "draw maps on linear axes (the cells are evenly spaced)");
  auto even = [&](const std::vector<double>& v, const char* name) {
    require(!v.empty(), fmt::format("{}: the map's {} has no values", where, name));
    for (double t : v) require(std::isfinite(t), fmt::format("{}: the map's {} holds {}", where, name, t));
    if (v.size() < 2) return;
    const double step = (v.back() - v.front()) / static_cast<double>(v.size() - 1);
    require(step > 0.0, fmt::format("{}: the map's {} must increase", where, name));
    for (std::size_t k = 1; k < v.size(); ++k)
      require(std::abs(v[k] - v[k - 1] - step) <= 1e-6 * step,
              fmt::format("{}: the map's {} is not evenly spaced ({} to {} after {} values)", where, name, v[k - 1], v[k], k),
              "give map cells on an even grid");
  };
  even(m.x, "x");
  even(m.y, "y");
  require(m.z.size() == m.x.size() * m.y.size(),
          fmt::format("{}: the map has {} z values for {} × {} cells", where, m.z.size(), m.x.size(), m.y.size()));
  check_axis(Axis{m.colour.label, m.colour.scale, m.colour.min, m.colour.max, std::nullopt}, where + " colour bar");
  return std::any_of(m.z.begin(), m.z.end(), [&](double v) { return plottable(v, m.colour.scale); });
}

}  // namespace

Format format_for_path(const std::string& path) {
  const std::string ext = text::lower(fs::path(path).extension().string());
  if (ext == ".png") return Format::Png;
  if (ext == ".svg") return Format::Svg;
  if (ext == ".pdf") return Format::Pdf;
  throw InvalidArgument(fmt::format("plot file {}: unknown extension '{}'; expected .png, .svg or .pdf", path, ext),
                        "name the figure file with a .png, .svg or .pdf extension");
}

std::string literal(std::string_view text) {
  std::string s;
  for (char c : text) {
    if (c != '\0' && std::strchr("_^@&~{}\\", c) != nullptr) s += '\\';
    s += c;
  }
  return s;
}

void Figure::check() const {
  require(!panels.empty(), "figure has no panels", "add at least one panel with a curve");
  check_size(width_px, height_px);
  check_axis(x, "x axis");
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const Panel& p = panels[i];
    const std::string where = panel_name(i, p);
    check_axis(p.y, where);
    require(std::isfinite(p.height) && p.height > 0.0, fmt::format("{}: height {} must be > 0", where, p.height));
    bool any = false;
    auto scan = [&](const std::vector<double>& xs, const std::vector<double>& ys, const std::string& what) {
      require(xs.size() == ys.size(), fmt::format("{}: {} has {} x values but {} y values", where, what, xs.size(), ys.size()));
      for (std::size_t k = 0; k < xs.size(); ++k) any = any || (plottable(xs[k], x.scale) && plottable(ys[k], p.y.scale));
    };
    for (const Curve& c : p.curves) scan(c.x, c.y, fmt::format("curve '{}'", c.label));
    if (p.map) any = check_map(*p.map, x, p.y, where) || any;
    for (const Fill& f : p.fills) {
      scan(f.x, f.y, fmt::format("fill '{}'", f.label));
      require(plottable(f.base, p.y.scale),
              fmt::format("{}: fill '{}' base {} is not drawable on this axis", where, f.label, f.base));
    }
    require(any,
            fmt::format("{}: nothing to draw (no finite point{})", where,
                        p.y.scale == Scale::Log || x.scale == Scale::Log ? " with positive values on the log axes" : ""),
            "give the panel a curve or fill with data");
    for (const HorizontalLine& h : p.horizontal_lines)
      require(plottable(h.y, p.y.scale), fmt::format("{}: horizontal line '{}' at {} is not drawable", where, h.label, h.y));
    for (const VerticalLine& v : p.vertical_lines)
      require(plottable(v.x, x.scale), fmt::format("{}: vertical line '{}' at {} is not drawable", where, v.label, v.x));
    for (const Band& b : p.bands)
      require(plottable(b.from, x.scale) && plottable(b.to, x.scale) && b.from < b.to,
              fmt::format("{}: band '{}' [{}, {}] must be finite and increasing", where, b.label, b.from, b.to));
    for (const TextLabel& t : p.labels)
      require(plottable(t.x, x.scale) && plottable(t.y, p.y.scale),
              fmt::format("{}: label '{}' at ({}, {}) is not drawable", where, t.text, t.x, t.y));
  }
}

}  // namespace toolpoint::plot
