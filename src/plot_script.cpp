// toolpoint: a Figure as one gnuplot script, data inline (plot.hpp).
#include "toolpoint/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "plot_detail.hpp"

namespace toolpoint::plot {

using namespace detail;

// ---- Script generation -------------------------------------------------------------------------

namespace {

// The outer edges of a map's cells along one axis (centres ± half a step; ± 0.5 for one cell).
std::pair<double, double> cell_edges(const std::vector<double>& v) {
  const double half = v.size() > 1 ? 0.5 * (v.back() - v.front()) / static_cast<double>(v.size() - 1) : 0.5;
  return {v.front() - half, v.back() + half};
}

// Viridis (matplotlib's), 9 stops: perceptually uniform, lightness rising with the value.
constexpr const char* kViridis =
    "set palette defined (0 '#440154', 1 '#472D7B', 2 '#3B528B', 3 '#2C728E', 4 '#21918C', 5 '#28AE80', 6 '#5EC962', "
    "7 '#ADDC30', 8 '#FDE725')\n";
// Room right of a panel for a colour bar: the box, its tic labels and its rotated label.
constexpr double kColourBarPx = 150, kColourBoxPx = 18, kColourGapPx = 12;

// The shared x range: explicit limits, else the data's extent over every panel, so that the
// stacked panels line up (gnuplot would autoscale each panel on its own).
std::pair<double, double> shared_x_range(const Figure& fig) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  auto take = [&](const std::vector<double>& xs) {
    for (double v : xs)
      if (plottable(v, fig.x.scale)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
  };
  for (const Panel& p : fig.panels) {
    for (const Curve& c : p.curves) take(c.x);
    for (const Fill& f : p.fills) take(f.x);
    if (p.map) take({cell_edges(p.map->x).first, cell_edges(p.map->x).second});
  }
  if (fig.x.min) lo = *fig.x.min;
  if (fig.x.max) hi = *fig.x.max;
  if (!(lo < hi)) {  // a single x value: open a small window around it
    const double mid = lo;
    lo = fig.x.scale == Scale::Log ? mid / 1.1 : mid - std::max(0.5, std::abs(mid) * 0.1);
    hi = fig.x.scale == Scale::Log ? mid * 1.1 : mid + std::max(0.5, std::abs(mid) * 0.1);
  }
  return {lo, hi};
}

// One inline data block. A blank line breaks the line drawn through the points, at non-finite
// values and at values a log axis cannot show.
void append_block(std::string& s, const std::string& name, const std::vector<double>& xs, const std::vector<double>& ys,
                  Scale xs_scale, Scale ys_scale, std::optional<double> third = std::nullopt) {
  s += name + " << EOD\n";
  bool broken = true;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    if (!plottable(xs[k], xs_scale) || !plottable(ys[k], ys_scale)) {
      if (!broken) s += '\n';
      broken = true;
      continue;
    }
    s += number(xs[k]) + ' ' + number(ys[k]);
    if (third) s += ' ' + number(*third);
    s += '\n';
    broken = false;
  }
  s += "EOD\n";
}

// A map's cells as `x y z` rows, one block of x per y (gnuplot's grid order for `with image`); a
// cell that cannot be coloured is NaN, which gnuplot leaves blank.
void append_map(std::string& s, const std::string& name, const Map& m) {
  s += name + " << EOD\n";
  auto out = std::back_inserter(s);
  for (std::size_t j = 0; j < m.y.size(); ++j) {
    for (std::size_t i = 0; i < m.x.size(); ++i) {
      const double z = m.z[j * m.x.size() + i];
      fmt::format_to(out, "{} {} {}\n", m.x[i], m.y[j], plottable(z, m.colour.scale) ? number(z) : std::string("NaN"));
    }
    s += '\n';
  }
  s += "EOD\n";
}

std::string curve_spec(const Curve& c, std::size_t series) {
  const std::string colour = fmt::format("lc rgb \"{}\"", kColours[series % kSeries]);
  const std::string dash = kDashes[series % kSeries];
  const int pt = kPoints[series % kSeries];
  // About a dozen markers along a line: enough to tell series apart, few enough not to hide it.
  // A negative interval blanks a little background around each marker.
  const std::size_t interval = std::max<std::size_t>(1, c.x.size() / 12);
  const std::string sparse = series == 0 ? std::string("with lines")
                                         : fmt::format("with linespoints pt {} ps 1.4 pi -{}", pt, interval);
  switch (c.style) {
    case CurveStyle::Line: return fmt::format("{} lw 2 dt {} {}", sparse, dash, colour);
    case CurveStyle::Dashed: return fmt::format("with lines lw 2 dt {} {}", series == 0 ? kDashes[1] : dash, colour);
    case CurveStyle::Points: return fmt::format("with points pt {} ps 1.0 lw 1.5 {}", pt, colour);
    case CurveStyle::LinePoints: return fmt::format("with linespoints lw 2 dt {} pt {} ps 1.4 pi 1 {}", dash, pt, colour);
  }
  return "with lines";
}

const char* key_position(Legend legend) {
  switch (legend) {
    case Legend::TopRight: return "top right";
    case Legend::TopLeft: return "top left";
    case Legend::BottomRight: return "bottom right";
    case Legend::BottomLeft: return "bottom left";
    case Legend::Outside:
    case Legend::Hidden: break;
  }
  return "";
}

// `lo`, `hi`: the range to set ("*" autoscales); `decades`: the span a log axis will show.
void append_axis(std::string& s, char name, const Axis& a, const std::string& lo, const std::string& hi, double decades,
                 bool show_labels) {
  // The scale before the range: a negative limit is refused while the axis is still logarithmic.
  s += fmt::format(fmt::runtime(a.scale == Scale::Log ? "set logscale {} 10\n" : "unset logscale {}\n"), name);
  // Beyond about six decades the eight minor tics per decade merge into a solid bar.
  s += fmt::format(fmt::runtime(a.scale == Scale::Log && decades > 6.0 ? "unset m{}tics\n" : "set m{}tics default\n"), name);
  s += fmt::format("set {}range [{}:{}]\n", name, lo, hi);
  s += a.tic_step && a.scale == Scale::Linear ? fmt::format("set {}tics {}\n", name, number(*a.tic_step))
                                              : fmt::format("set {}tics autofreq\n", name);
  const char* fmt_text = a.scale == Scale::Log ? (name == 'x' ? "%g" : "10^{%L}") : "%h";
  if (show_labels) {
    s += fmt::format("set format {} {}\nset {}label {}\n", name, gp_text(fmt_text), name, gp_text(a.label));
  } else {
    s += fmt::format("set format {} \"\"\nunset {}label\n", name, name);
  }
}

// Decades spanned by a panel's y data (and limits) on a log axis; 0 on a linear one.
double y_decades(const Panel& p) {
  if (p.y.scale != Scale::Log) return 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  auto take = [&](double v) {
    if (plottable(v, Scale::Log)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  };
  for (const Curve& c : p.curves) std::for_each(c.y.begin(), c.y.end(), take);
  for (const Fill& f : p.fills) std::for_each(f.y.begin(), f.y.end(), take);
  if (p.y.min) lo = *p.y.min;
  if (p.y.max) hi = *p.y.max;
  return hi > lo ? std::log10(hi / lo) : 0.0;
}

// Legend entries of a panel: the labelled items, in drawing order.
std::vector<std::string> legend_texts(const Panel& p) {
  std::vector<std::string> out;
  for (const Band& b : p.bands) out.push_back(b.label);
  for (const Fill& f : p.fills) out.push_back(f.label);
  for (const Curve& c : p.curves) out.push_back(c.label);
  for (const HorizontalLine& h : p.horizontal_lines) out.push_back(h.label);
  std::erase_if(out, [](const std::string& t) { return t.empty(); });
  return out;
}

// Width of an outside legend column in px: the longest entry's visible characters (UTF-8 code
// points less enhanced-text markup) plus the sample and padding.
double legend_width_px(const Panel& p) {
  std::size_t longest = 0;
  for (const std::string& t : legend_texts(p)) {
    std::size_t n = 0;
    for (unsigned char c : t) n += (c & 0xC0) != 0x80 && std::strchr("{}_^\\", c) == nullptr;
    longest = std::max(longest, n);
  }
  return kKeyFixedPx + static_cast<double>(longest) * kCharEm * kFontPt;
}

struct Frame {
  double left, right;  // screen fractions of the panels' left and right edges
};

bool has_map(const Figure& fig) {
  return std::any_of(fig.panels.begin(), fig.panels.end(), [](const Panel& p) { return p.map.has_value(); });
}

Frame frame_of(const Figure& fig) {
  const double bar = has_map(fig) ? kColourBarPx : 0.0;
  double right_px = std::max(kRightPx, bar);
  for (const Panel& p : fig.panels)
    if (p.legend == Legend::Outside && !legend_texts(p).empty()) right_px = std::max(right_px, bar + legend_width_px(p) + 15.0);
  return {kLeftPx / fig.width_px, 1.0 - right_px / fig.width_px};
}

bool has_points(const std::vector<double>& xs, const std::vector<double>& ys, Scale xs_scale, Scale ys_scale) {
  for (std::size_t k = 0; k < xs.size(); ++k)
    if (plottable(xs[k], xs_scale) && plottable(ys[k], ys_scale)) return true;
  return false;
}

void append_panel(std::string& s, const Figure& fig, std::size_t i, double top, double bottom, std::pair<double, double> xr,
                  Frame frame) {
  const Panel& p = fig.panels[i];
  const bool last = i + 1 == fig.panels.size();
  const std::string id = fmt::format("p{}", i);
  s += fmt::format("# ---- panel {}\n", i + 1);  // not the label: a newline in it would end the comment
  s += fmt::format("set lmargin at screen {:.5f}\nset rmargin at screen {:.5f}\n", frame.left, frame.right);
  s += fmt::format("set tmargin at screen {:.5f}\nset bmargin at screen {:.5f}\n", top, bottom);
  s += "unset label\nunset arrow\nunset object\n";
  const auto limit = [](std::optional<double> v) { return v ? number(*v) : std::string("*"); };
  // A linear x axis gets at most one tic label per ~80 px of panel width (gnuplot's autofreq
  // knows the range, not the width, and crowds narrow panels: "5001000"), at a 1-2-5 step.
  Axis x_axis = fig.x;
  if (x_axis.scale == Scale::Linear && !x_axis.tic_step && xr.second > xr.first) {
    const double width_px = (frame.right - frame.left) * fig.width_px;
    const double max_tics = std::max(2.0, std::floor(width_px / 80.0));
    const double raw = (xr.second - xr.first) / max_tics, mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double unit = raw / mag;
    x_axis.tic_step = (unit <= 1.0 ? 1.0 : unit <= 2.0 ? 2.0 : unit <= 5.0 ? 5.0 : 10.0) * mag;
  }
  append_axis(s, 'x', x_axis, number(xr.first), number(xr.second),
              fig.x.scale == Scale::Log ? std::log10(xr.second / xr.first) : 0.0, last);
  Axis y_axis = p.y;
  if (p.map) {  // the cells' outer edges, unless given
    const auto [y0, y1] = cell_edges(p.map->y);
    if (!y_axis.min) y_axis.min = y0;
    if (!y_axis.max) y_axis.max = y1;
  }
  append_axis(s, 'y', y_axis, limit(y_axis.min), limit(y_axis.max), y_decades(p), true);
  const double bar = has_map(fig) ? kColourBarPx / fig.width_px : 0.0;
  if (p.map) {
    const ColourBar& c = p.map->colour;
    s += kViridis;
    s += c.scale == Scale::Log ? "set logscale cb 10\n" : "unset logscale cb\n";
    s += fmt::format("set cbrange [{}:{}]\n", limit(c.min), limit(c.max));
    // The label clear of tic labels of up to five characters.
    s += fmt::format("set format cb {}\nset cbtics autofreq\nset cblabel {} offset 1.5,0\n",
                     gp_text(c.scale == Scale::Log ? "10^{%L}" : "%h"), gp_text(c.label));
    s += fmt::format("set colorbox user origin screen {:.5f}, screen {:.5f} size screen {:.5f}, screen {:.5f} front\n",
                     frame.right + kColourGapPx / fig.width_px, bottom, kColourBoxPx / fig.width_px, top - bottom);
  } else {
    s += "unset colorbox\n";
  }
  if (p.legend == Legend::Hidden || legend_texts(p).empty()) {
    s += "unset key\n";
  } else if (p.legend == Legend::Outside) {
    // No box: gnuplot sizes boxes from its own, generous estimate of text width.
    s += fmt::format("set key at screen {:.5f}, screen {:.5f} left top Left reverse nobox samplen {} spacing 1.15\n",
                     frame.right + bar + 10.0 / fig.width_px, top, kSampleChars);
  } else {
    s += fmt::format("set key {} opaque box lc rgb \"#A0A0A0\" samplen {} spacing 1.15 width 1\n", key_position(p.legend),
                     kSampleChars);
  }

  std::vector<std::string> items;
  if (p.map) items.push_back(fmt::format("${}m using 1:2:3 with image notitle", id));
  for (std::size_t k = 0; k < p.bands.size(); ++k) {
    const Band& b = p.bands[k];
    s +=
        fmt::format("set object {} rect from first {}, graph 0 to first {}, graph 1 behind fc rgb \"{}\" fs solid 1.0 noborder\n",
                    k + 1, number(b.from), number(b.to), kBandColour);
    if (!b.label.empty())
      items.push_back(fmt::format("keyentry with boxes fs solid 1.0 border lc rgb \"#B0B0B0\" fc rgb \"{}\" {}", kBandColour,
                                  title_of(b.label)));
  }
  for (std::size_t k = 0; k < p.fills.size(); ++k)
    if (has_points(p.fills[k].x, p.fills[k].y, fig.x.scale, p.y.scale))
      items.push_back(fmt::format("${}f{} using 1:2:3 with filledcurves fc rgb \"{}\" fs solid 1.0 noborder {}", id, k,
                                  kFillColours[k % std::size(kFillColours)], title_of(p.fills[k].label)));
  std::size_t next_series = 0;
  for (std::size_t k = 0; k < p.curves.size(); ++k) {
    const Curve& c = p.curves[k];
    const std::size_t series = c.series >= 0 ? static_cast<std::size_t>(c.series) : next_series++;
    // An empty data block would only earn a gnuplot warning.
    if (has_points(c.x, c.y, fig.x.scale, p.y.scale))
      items.push_back(fmt::format("${}c{} using 1:2 {} {}", id, k, curve_spec(c, series), title_of(c.label)));
  }
  for (const HorizontalLine& h : p.horizontal_lines) {
    const std::size_t series = next_series++;
    const char* dash = series == 0 ? kDashes[1] : kDashes[series % kSeries];
    items.push_back(fmt::format("{} with lines lw 2 dt {} lc rgb \"{}\" {}", number(h.y), dash, kColours[series % kSeries],
                                title_of(h.label)));
  }
  for (std::size_t k = 0; k < p.vertical_lines.size(); ++k) {
    const VerticalLine& v = p.vertical_lines[k];
    s += fmt::format("set arrow from first {0}, graph 0 to first {0}, graph 1 nohead front lw 1.5 dt (8,6) lc rgb \"#505050\"\n",
                     number(v.x));
    if (!v.label.empty())
      s += fmt::format("set label {} at first {}, graph 0.94 left offset 0.4,0 front boxed\n", gp_text(v.label), number(v.x));
  }
  for (const TextLabel& t : p.labels) {
    s += fmt::format("set label {} at first {}, first {} center offset 0,1.1 front{}\n", gp_text(t.text), number(t.x),
                     number(t.y), t.marker ? " point pt 7 ps 0.8 lc rgb \"#000000\"" : "");
  }
  s += "plot ";
  for (std::size_t k = 0; k < items.size(); ++k) s += (k ? ", \\\n     " : "") + items[k];
  s += '\n';
}

}  // namespace

std::string gnuplot_script(const Figure& fig) {
  fig.check();
  std::string s = "# toolpoint figure: gnuplot commands, data inline\nset encoding utf8\n";
  const auto xr = shared_x_range(fig);
  const Frame frame = frame_of(fig);
  for (std::size_t i = 0; i < fig.panels.size(); ++i) {
    const Panel& p = fig.panels[i];
    for (std::size_t k = 0; k < p.curves.size(); ++k)
      append_block(s, fmt::format("$p{}c{}", i, k), p.curves[k].x, p.curves[k].y, fig.x.scale, p.y.scale);
    for (std::size_t k = 0; k < p.fills.size(); ++k)
      append_block(s, fmt::format("$p{}f{}", i, k), p.fills[k].x, p.fills[k].y, fig.x.scale, p.y.scale, p.fills[k].base);
    if (p.map) append_map(s, fmt::format("$p{}m", i), *p.map);
  }
  // House style shared by every panel.
  s += "set grid xtics ytics back lt 1 lw 1 lc rgb \"#E0E0E0\" dt solid\n"
       "set border lw 1.2\n"
       "set tics scale 1.2, 0.6\n"
       "set samples 2\n"                                   // horizontal lines are constants: two samples draw them exactly
       "set style textbox opaque noborder margins 1,1\n";  // labels on lines stay readable over data
  s += "set multiplot";
  if (!fig.title.empty()) s += fmt::format(" title {} font \",{}\"", gp_text(fig.title), kFontPt + 2);
  s += '\n';
  const double h = fig.height_px;
  const double top = 1.0 - (fig.title.empty() ? kTopPx : kTitlePx) / h, bottom = kBottomPx / h, gap = kGapPx / h;
  double weights = 0.0;
  for (const Panel& p : fig.panels) weights += p.height;
  const double unit = (top - bottom - gap * static_cast<double>(fig.panels.size() - 1)) / weights;
  double y = top;
  for (std::size_t i = 0; i < fig.panels.size(); ++i) {
    const double next = y - unit * fig.panels[i].height;
    append_panel(s, fig, i, y, next, xr, frame);
    y = next - gap;
  }
  s += "unset multiplot\n";
  return s;
}

}  // namespace toolpoint::plot
