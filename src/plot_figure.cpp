// toolpoint: the figure model — formats, verbatim text and Figure::check (plot.hpp).
#include "toolpoint/plot.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "plot_detail.hpp"

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

}  // namespace

Format format_for_path(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
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
      require(xs.size() == ys.size(),
              fmt::format("{}: {} has {} x values but {} y values", where, what, xs.size(), ys.size()));
      for (std::size_t k = 0; k < xs.size(); ++k)
        any = any || (plottable(xs[k], x.scale) && plottable(ys[k], p.y.scale));
    };
    for (const Curve& c : p.curves) scan(c.x, c.y, fmt::format("curve '{}'", c.label));
    for (const Fill& f : p.fills) {
      scan(f.x, f.y, fmt::format("fill '{}'", f.label));
      require(plottable(f.base, p.y.scale), fmt::format("{}: fill '{}' base {} is not drawable on this axis", where,
                                                        f.label, f.base));
    }
    require(any, fmt::format("{}: nothing to draw (no finite point{})", where,
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
