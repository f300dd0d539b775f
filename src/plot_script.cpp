// toolpoint: a Figure as one gnuplot script, data inline (plot.hpp).
#include "toolpoint/plot/plot.hpp"

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
    case Legend::Auto:
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

// Width of an outside legend column in px: the longest entry plus the sample and padding.
double legend_width_px(const Panel& p) {
  double longest = 0.0;
  for (const std::string& t : legend_texts(p)) longest = std::max(longest, text_px(t, kFontPt));
  return kKeyFixedPx + longest;
}

// The 1-2-5 step of about five tics over `span` (> 0).
double nice_step(double span) {
  const double raw = span / 5.0, mag = std::pow(10.0, std::floor(std::log10(raw))), unit = raw / mag;
  return (unit <= 1.0 ? 1.0 : unit <= 2.0 ? 2.0 : unit <= 5.0 ? 5.0 : 10.0) * mag;
}

// A colour bar whose range the data exceed (ColourBar::min, max set inside them) draws those cells in
// its end colours: its tics then say so — the end's tic reads "≥ 3.5" (or "≤ …") and the others
// keep clear of it — so that a saturated scale is not read as the data's range. Nothing when the
// data lie within the bar (gnuplot's own tics).
std::string saturation_tics(const Map& m) {
  const ColourBar& c = m.colour;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double z : m.z)
    if (plottable(z, c.scale)) {
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  const bool above = c.max && hi > *c.max, below = c.min && lo < *c.min;
  if (!above && !below) return {};
  const double b0 = c.min.value_or(lo), b1 = c.max.value_or(hi);
  if (!(b1 > b0)) return {};
  const auto text = [](double v) { return fmt::format("{:.3g}", v); };
  std::vector<std::pair<std::string, double>> tics;
  if (c.scale == Scale::Log) {
    for (double d = std::ceil(std::log10(b0) - 1e-9); d <= std::floor(std::log10(b1) + 1e-9); d += 1.0)
      tics.push_back({fmt::format("10^{{{:.0f}}}", d), std::pow(10.0, d)});
  } else {
    const double step = nice_step(b1 - b0);
    for (double v = step * std::ceil(b0 / step - 1e-9); v <= b1 + 1e-9 * step; v += step)
      tics.push_back({text(std::abs(v) < 1e-9 * step ? 0.0 : v), v});
  }
  // Clear of the marked ends: a third of the bar's span per tic would crowd them, a tenth will do.
  const double clear = 0.1 * (c.scale == Scale::Log ? std::log10(b1 / b0) : b1 - b0);
  const auto near = [&](double v, double end) {
    return (c.scale == Scale::Log ? std::abs(std::log10(v / end)) : std::abs(v - end)) < clear;
  };
  std::string list;
  for (const auto& [label, v] : tics) {
    if ((above && near(v, b1)) || (below && near(v, b0))) continue;
    list += fmt::format("{}{} {}", list.empty() ? "" : ", ", gp_text(label), number(v));
  }
  if (above) list += fmt::format("{}{} {}", list.empty() ? "" : ", ", gp_text("≥ " + text(b1)), number(b1));
  if (below) list += fmt::format("{}{} {}", list.empty() ? "" : ", ", gp_text("≤ " + text(b0)), number(b0));
  return fmt::format("set cbtics ({})\n", list);
}

// Room right of the panels for a colour bar: its box, tic labels and rotated label; wider when an
// end's tic reads "≥ …" (saturation_tics).
double colour_bar_px(const Figure& fig) {
  double px = 0.0;
  for (const Panel& p : fig.panels)
    if (p.map) px = std::max(px, kColourBarPx + (saturation_tics(*p.map).empty() ? 0.0 : 30.0));
  return px;
}

struct Frame {
  double left, right;  // screen fractions of the panels' left and right edges
};

// The panels' left and right edges: room right of them for a colour bar and for the legends that
// go outside (`legends`: each panel's, as resolved by layout_of).
Frame frame_of(const Figure& fig, const std::vector<Legend>& legends) {
  const double bar = colour_bar_px(fig);
  double right_px = std::max(kRightPx, bar);
  for (std::size_t i = 0; i < fig.panels.size(); ++i)
    if (legends[i] == Legend::Outside && !legend_texts(fig.panels[i]).empty())
      right_px = std::max(right_px, bar + legend_width_px(fig.panels[i]) + 15.0);
  return {kLeftPx / fig.width_px, 1.0 - right_px / fig.width_px};
}

bool has_points(const std::vector<double>& xs, const std::vector<double>& ys, Scale xs_scale, Scale ys_scale) {
  for (std::size_t k = 0; k < xs.size(); ++k)
    if (plottable(xs[k], xs_scale) && plottable(ys[k], ys_scale)) return true;
  return false;
}

// A title wider than the figure (a long file name in it) broken into lines that fit, at a space
// or after a '/' where one is in the second half of the line, else anywhere; at most three
// lines, the last cut short with "…".
std::vector<std::string> title_lines(const std::string& title, int width_px) {
  if (title.empty()) return {};
  const double room = width_px - 40.0, pt = kFontPt + 2;
  // The longest prefix of `t` (whole code points) at most `px` wide, in bytes.
  const auto fitting = [&](const std::string& t, double px) {
    std::size_t end = 0;
    for (std::size_t i = 1; i <= t.size(); ++i) {
      if (i < t.size() && (static_cast<unsigned char>(t[i]) & 0xC0) == 0x80) continue;  // inside a code point
      if (text_px(std::string_view(t).substr(0, i), pt) > px) break;
      end = i;
    }
    return end;
  };
  std::vector<std::string> lines;
  std::string rest = title;
  while (text_px(rest, pt) > room && lines.size() < 2) {
    const std::size_t limit = std::max<std::size_t>(fitting(rest, room), 1);
    std::size_t cut = rest.find_last_of(" /", limit - 1);
    cut = cut == std::string::npos || cut < limit / 2 ? limit : cut + 1;  // the space or slash ends the line
    std::string head = rest.substr(0, cut);
    while (!head.empty() && head.back() == ' ') head.pop_back();
    lines.push_back(head);
    rest = rest.substr(cut);
  }
  if (text_px(rest, pt) > room) rest = rest.substr(0, fitting(rest, room - text_px("…", pt))) + "…";
  lines.push_back(rest);
  return lines;
}

// ---- Layout: decided in pixels, on the ranges the script sets ------------------------------------
//
// gnuplot places what it is told to, where it is told to: a legend over the data, a label over
// another or through the title, a title wider than the figure. So the y ranges are set here (not
// left to gnuplot's autoscaling), and on them the legend's corner and the labels are chosen.

// One text line of the house font in px (gnuplot's character height for pngcairo at 16 pt, measured);
// a TextLabel is drawn centred 1.1 lines above its point
// (append_panel); a legend inside the frame has 1.15 lines per entry and a little padding.
constexpr double kLinePx = 1.6 * kFontPt, kLabelRise = 1.1, kKeyPadPx = 14.0;

// Width of a legend inside the frame, as gnuplot boxes it: it sizes the box from the longest
// entry's character count (not its glyphs) plus the sample; measured on pngcairo output at the
// house font, about 13.5 px per character and 150 px besides.
double inside_key_width_px(const std::vector<std::string>& entries) {
  std::size_t longest = 0;
  for (const std::string& t : entries) {
    std::size_t n = 0;
    for (unsigned char c : t) n += (c & 0xC0) != 0x80 && c != '{' && c != '}' && c != '_' && c != '^' && c != '\\';
    longest = std::max(longest, n);
  }
  return 150.0 + 13.5 * static_cast<double>(longest);
}

struct Rect {
  double x0, y0, x1, y1;  // px from the panel's bottom-left corner
  bool overlaps(const Rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// Where a value sits along an axis drawn from lo to hi, as a fraction of the axis.
double fraction(double v, double lo, double hi, Scale scale) {
  return scale == Scale::Log ? std::log(v / lo) / std::log(hi / lo) : (v - lo) / (hi - lo);
}

// The y values a panel draws (curves, fills with their base, horizontal lines, labels): their
// extent, or nothing.
std::optional<std::pair<double, double>> y_extent(const Panel& p) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const auto take = [&](double v) {
    if (plottable(v, p.y.scale)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  };
  for (const Curve& c : p.curves) std::for_each(c.y.begin(), c.y.end(), take);
  for (const Fill& f : p.fills) {
    std::for_each(f.y.begin(), f.y.end(), take);
    take(f.base);
  }
  for (const HorizontalLine& h : p.horizontal_lines) take(h.y);
  for (const TextLabel& t : p.labels) take(t.y);
  if (!(lo <= hi)) return std::nullopt;
  return std::pair{lo, hi};
}

// A range widened to round values as gnuplot's autoscaling does: whole decades on a log axis, the
// 1-2-5 step of about five tics on a linear one; a single value opens a small window.
std::pair<double, double> rounded_out(double lo, double hi, Scale scale, bool keep_lo, bool keep_hi) {
  if (scale == Scale::Log) {
    if (!(hi > lo)) {
      lo /= 2.0;
      hi *= 2.0;
    }
    return {keep_lo ? lo : std::pow(10.0, std::floor(std::log10(lo) + 1e-9)),
            keep_hi ? hi : std::pow(10.0, std::ceil(std::log10(hi) - 1e-9))};
  }
  if (!(hi > lo)) {
    const double w = std::max(0.5, std::abs(lo) * 0.1);
    return {keep_lo ? lo : lo - w, keep_hi ? hi : hi + w};
  }
  const double step = nice_step(hi - lo);
  return {keep_lo ? lo : step * std::floor(lo / step + 1e-9), keep_hi ? hi : step * std::ceil(hi / step - 1e-9)};
}

// What the layout decided for a panel.
struct PanelLayout {
  std::optional<double> y_lo, y_hi;  // the y range set (unset: gnuplot's; a map's are its cells')
  Legend legend = Legend::Hidden;    // resolved: a corner, Outside or Hidden
  std::vector<TextLabel> labels;     // those that fit, in the panel's order
  std::vector<std::string> justify;  // per kept label: "center", "left" or "right"
};

// The y range of a panel: its axis limits where given; else its data's extent rounded out, the
// top raised until every label (drawn above its point) stays under the frame's top edge. A map
// panel keeps its cells' edges; a panel with no y data is left to gnuplot.
void choose_y_range(const Panel& p, double panel_px, PanelLayout& out) {
  if (p.map) {
    const auto [y0, y1] = cell_edges(p.map->y);
    out.y_lo = p.y.min.value_or(y0);
    out.y_hi = p.y.max.value_or(y1);
    return;
  }
  const auto extent = y_extent(p);
  if (!extent) return;
  auto [lo, hi] = rounded_out(p.y.min.value_or(extent->first), p.y.max.value_or(extent->second), p.y.scale, p.y.min.has_value(),
                              p.y.max.has_value());
  if (!p.y.max && !p.labels.empty() && panel_px > 4.0 * kLinePx) {
    const double room = 1.0 - ((kLabelRise + 0.6) * kLinePx + 4.0) / panel_px;  // the highest a point may sit
    double need = hi;
    for (const TextLabel& t : p.labels) {
      if (!plottable(t.y, p.y.scale) || fraction(t.y, lo, hi, p.y.scale) <= room) continue;
      need = std::max(need, p.y.scale == Scale::Log ? lo * std::pow(t.y / lo, 1.0 / room) : lo + (t.y - lo) / room);
    }
    if (need > hi) hi = rounded_out(lo, need, p.y.scale, true, false).second;
  }
  out.y_lo = lo;
  out.y_hi = hi;
}

// Decides a panel's legend corner (Auto: the first of top right, top left, bottom right, bottom left
// whose box covers none of the panel's data points, lines or labels; else outside) and which labels
// are drawn (in order; one that would overlap one already placed, an inside legend, or the frame's
// top edge is left out; one that would cross a side edge is set against its point instead).
void arrange(const Figure& fig, const Panel& p, std::pair<double, double> xr, double width_px, double height_px,
             PanelLayout& out) {
  const std::vector<std::string> entries = legend_texts(p);
  out.legend = entries.empty() ? Legend::Hidden : p.legend;
  const bool ranged = out.y_lo && out.y_hi && *out.y_hi > *out.y_lo;
  const auto px_x = [&](double v) { return width_px * fraction(v, xr.first, xr.second, fig.x.scale); };
  const auto px_y = [&](double v) { return height_px * fraction(v, *out.y_lo, *out.y_hi, p.y.scale); };
  // The labels' boxes, before any is left out.
  std::vector<Rect> boxes;
  std::vector<bool> drawable;
  for (const TextLabel& t : p.labels) {
    const bool ok = ranged && plottable(t.x, fig.x.scale) && plottable(t.y, p.y.scale);
    drawable.push_back(ok);
    const double cx = ok ? px_x(t.x) : 0.0, cy = ok ? px_y(t.y) + kLabelRise * kLinePx : 0.0;
    const double half = 0.5 * text_px(t.text, kFontPt) + 0.2 * kFontPt;
    boxes.push_back({cx - half, cy - 0.5 * kLinePx, cx + half, cy + 0.5 * kLinePx});
  }
  Rect key{0, 0, 0, 0};
  bool key_inside = false;
  if (out.legend == Legend::Auto) {
    out.legend = Legend::Outside;
    if (ranged && !p.map) {
      const double w = inside_key_width_px(entries), h = static_cast<double>(entries.size()) * 1.15 * kLinePx + kKeyPadPx;
      for (const Legend corner : {Legend::TopRight, Legend::TopLeft, Legend::BottomRight, Legend::BottomLeft}) {
        const bool right = corner == Legend::TopRight || corner == Legend::BottomRight;
        const bool top = corner == Legend::TopRight || corner == Legend::TopLeft;
        const Rect r{right ? width_px - w : 0.0, top ? height_px - h : 0.0, right ? width_px : w, top ? height_px : h};
        const auto inside = [&](double x, double y) { return x >= r.x0 && x <= r.x1 && y >= r.y0 && y <= r.y1; };
        bool covered = false;
        for (const Curve& c : p.curves)
          for (std::size_t k = 0; k < c.x.size() && !covered; ++k)
            covered = plottable(c.x[k], fig.x.scale) && plottable(c.y[k], p.y.scale) && inside(px_x(c.x[k]), px_y(c.y[k]));
        for (const Fill& f : p.fills)  // the filled area: from the base up to the curve
          for (std::size_t k = 0; k < f.x.size() && !covered; ++k) {
            if (!plottable(f.x[k], fig.x.scale) || !plottable(f.y[k], p.y.scale)) continue;
            const double x = px_x(f.x[k]), y0 = px_y(std::max(f.base, *out.y_lo)), y1 = px_y(f.y[k]);
            covered = x >= r.x0 && x <= r.x1 && std::min(y0, y1) <= r.y1 && std::max(y0, y1) >= r.y0;
          }
        for (const HorizontalLine& l : p.horizontal_lines)
          covered = covered || (plottable(l.y, p.y.scale) && px_y(l.y) >= r.y0 && px_y(l.y) <= r.y1);
        for (const VerticalLine& v : p.vertical_lines)  // the line, and its label at the top
          covered = covered || (plottable(v.x, fig.x.scale) &&
                                px_x(v.x) >= r.x0 - (v.label.empty() ? 0.0 : text_px(v.label, kFontPt)) && px_x(v.x) <= r.x1);
        for (std::size_t k = 0; k < boxes.size(); ++k) covered = covered || (drawable[k] && boxes[k].overlaps(r));
        if (!covered) {
          out.legend = corner;
          key = r;
          key_inside = true;
          break;
        }
      }
    }
  } else if (out.legend != Legend::Outside && out.legend != Legend::Hidden && ranged) {
    // A corner given by the figure: its box keeps labels off (placed as above).
    const double w = inside_key_width_px(entries), h = static_cast<double>(entries.size()) * 1.15 * kLinePx + kKeyPadPx;
    const bool right = out.legend == Legend::TopRight || out.legend == Legend::BottomRight;
    const bool top = out.legend == Legend::TopRight || out.legend == Legend::TopLeft;
    key = {right ? width_px - w : 0.0, top ? height_px - h : 0.0, right ? width_px : w, top ? height_px : h};
    key_inside = true;
  }
  std::vector<Rect> placed;
  for (std::size_t k = 0; k < p.labels.size(); ++k) {
    if (!ranged) {  // no range to place them on: drawn as given
      out.labels.push_back(p.labels[k]);
      out.justify.push_back("center");
      continue;
    }
    if (!drawable[k]) continue;
    Rect b = boxes[k];
    std::string justify = "center";
    if (b.x0 < 0.0) {
      justify = "left";
      b = {b.x0 - b.x0 + px_x(p.labels[k].x), b.y0, b.x1 - b.x0 + px_x(p.labels[k].x), b.y1};
    } else if (b.x1 > width_px) {
      justify = "right";
      const double shift = b.x1 - px_x(p.labels[k].x);
      b = {b.x0 - shift, b.y0, b.x1 - shift, b.y1};
    }
    const bool off_top = b.y1 > height_px + 2.0, off_bottom = b.y0 < -2.0;
    const bool on_key = key_inside && b.overlaps(key);
    const bool on_other = std::any_of(placed.begin(), placed.end(), [&](const Rect& o) { return o.overlaps(b); });
    if (off_top || off_bottom || on_key || on_other) continue;
    placed.push_back(b);
    out.labels.push_back(p.labels[k]);
    out.justify.push_back(justify);
  }
}

void append_panel(std::string& s, const Figure& fig, std::size_t i, double top, double bottom, std::pair<double, double> xr,
                  Frame frame, const PanelLayout& layout) {
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
  y_axis.min = layout.y_lo;  // the range the layout chose (choose_y_range)
  y_axis.max = layout.y_hi;
  append_axis(s, 'y', y_axis, limit(y_axis.min), limit(y_axis.max), y_decades(p), true);
  const double bar = colour_bar_px(fig) / fig.width_px;
  if (p.map) {
    const ColourBar& c = p.map->colour;
    s += kViridis;
    s += c.scale == Scale::Log ? "set logscale cb 10\n" : "unset logscale cb\n";
    s += fmt::format("set cbrange [{}:{}]\n", limit(c.min), limit(c.max));
    // The label clear of tic labels of up to five characters.
    s += fmt::format("set format cb {}\nset cbtics autofreq\nset cblabel {} offset 1.5,0\n",
                     gp_text(c.scale == Scale::Log ? "10^{%L}" : "%h"), gp_text(c.label));
    s += saturation_tics(*p.map);
    s += fmt::format("set colorbox user origin screen {:.5f}, screen {:.5f} size screen {:.5f}, screen {:.5f} front\n",
                     frame.right + kColourGapPx / fig.width_px, bottom, kColourBoxPx / fig.width_px, top - bottom);
  } else {
    s += "unset colorbox\n";
  }
  if (layout.legend == Legend::Hidden) {
    s += "unset key\n";
  } else if (layout.legend == Legend::Outside) {
    // No box: gnuplot sizes boxes from its own, generous estimate of text width.
    s += fmt::format("set key at screen {:.5f}, screen {:.5f} left top Left reverse nobox samplen {} spacing 1.15\n",
                     frame.right + bar + 10.0 / fig.width_px, top, kSampleChars);
  } else {
    s += fmt::format("set key {} opaque box lc rgb \"#A0A0A0\" samplen {} spacing 1.15 width 1\n", key_position(layout.legend),
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
  for (std::size_t k = 0; k < layout.labels.size(); ++k) {
    const TextLabel& t = layout.labels[k];
    s += fmt::format("set label {} at first {}, first {} {} offset 0,{} front{}\n", gp_text(t.text), number(t.x), number(t.y),
                     layout.justify[k], kLabelRise, t.marker ? " point pt 7 ps 0.8 lc rgb \"#000000\"" : "");
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
  const std::vector<std::string> title = title_lines(fig.title, fig.width_px);
  s += "set multiplot";
  if (!title.empty()) {
    std::string joined;
    for (const std::string& l : title) joined += (joined.empty() ? "" : "\n") + l;
    s += fmt::format(" title {} font \",{}\"", gp_text(joined), kFontPt + 2);
  }
  s += '\n';
  const double h = fig.height_px;
  const double title_px = title.empty() ? kTopPx : kTitlePx + static_cast<double>(title.size() - 1) * kTitleLinePx;
  const double top = 1.0 - title_px / h, bottom = kBottomPx / h, gap = kGapPx / h;
  double weights = 0.0;
  for (const Panel& p : fig.panels) weights += p.height;
  const double unit = (top - bottom - gap * static_cast<double>(fig.panels.size() - 1)) / weights;
  // Each panel's range, legend and labels on the frame they leave (a legend moved outside narrows
  // every panel: decided again on the narrower frame).
  std::vector<PanelLayout> layouts(fig.panels.size());
  std::vector<Legend> legends;
  for (const Panel& p : fig.panels) legends.push_back(p.legend == Legend::Auto ? Legend::TopRight : p.legend);
  Frame frame = frame_of(fig, legends);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < fig.panels.size(); ++i) {
      const double panel_px = unit * fig.panels[i].height * h, width_px = (frame.right - frame.left) * fig.width_px;
      layouts[i] = PanelLayout{};
      choose_y_range(fig.panels[i], panel_px, layouts[i]);
      arrange(fig, fig.panels[i], xr, width_px, panel_px, layouts[i]);
      legends[i] = layouts[i].legend;
    }
    const Frame next = frame_of(fig, legends);
    if (next.right == frame.right) break;
    frame = next;
  }
  double y = top;
  for (std::size_t i = 0; i < fig.panels.size(); ++i) {
    const double next = y - unit * fig.panels[i].height;
    append_panel(s, fig, i, y, next, xr, frame, layouts[i]);
    y = next - gap;
  }
  s += "unset multiplot\n";
  return s;
}

}  // namespace toolpoint::plot
