// toolpoint: figures through gnuplot. See plot.hpp for the figure model and the house style.
#include "toolpoint/plot.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <limits>
#include <map>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/peaks.hpp"

extern char** environ;

namespace toolpoint::plot {

namespace fs = std::filesystem;

// ---- Small helpers ---------------------------------------------------------------------------

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// House style: Okabe–Ito colours ordered so that neighbours also differ in lightness, with a dash
// pattern and an open marker per series so that grayscale prints stay readable.
constexpr const char* kColours[] = {"#000000", "#D55E00", "#0072B2", "#009E73",
                                    "#CC79A7", "#E69F00", "#56B4E9", "#7F7F7F"};
constexpr const char* kDashes[] = {"solid",     "(10,6)",     "(2,4)",     "(10,4,2,4)",
                                   "(20,6)",    "(6,3,2,3,2,3)", "(5,5)", "(2,2)"};
constexpr int kPoints[] = {6, 4, 8, 12, 10, 2, 1, 14};
constexpr std::size_t kSeries = std::size(kColours);
constexpr const char* kFillColours[] = {"#D3EAD3", "#D6E4F2", "#F4E0D0", "#E8E8E8"};
constexpr const char* kBandColour = "#E2E2E2";
constexpr const char* kFont = "DejaVu Sans";
constexpr int kFontPt = 16;

// Layout in pixels, converted to screen fractions per figure so margins do not grow with size.
constexpr double kLeftPx = 130, kRightPx = 30, kTopPx = 25, kTitlePx = 55, kBottomPx = 80, kGapPx = 24;
// Average advance of a DejaVu Sans character, as a fraction of the font size, to size legends.
constexpr double kCharEm = 0.68;
constexpr int kSampleChars = 4;  // legend sample length, in gnuplot character widths
// What an outside legend needs beside its text: the sample (4 of gnuplot's character widths, ~70
// px at 16 pt) and the gaps around it, measured on pngcairo output.
constexpr double kKeyFixedPx = 115;

// A gnuplot double-quoted string.
std::string gp_text(std::string_view text) {
  std::string s = "\"";
  for (char c : text) {
    if (c == '\\' || c == '"') s += '\\';
    if (c == '\n') {
      s += "\\n";
      continue;
    }
    s += c;
  }
  s += '"';
  return s;
}

// A gnuplot single-quoted string (no escapes; '' is a quote): for file names.
std::string gp_path(std::string_view text) {
  std::string s = "'";
  for (char c : text) s += c == '\'' ? std::string("''") : std::string(1, c);
  s += '\'';
  return s;
}

std::string number(double v) { return fmt::format("{}", v); }

std::string title_of(const std::string& label) { return label.empty() ? "notitle" : "title " + gp_text(label); }

bool plottable(double v, Scale scale) { return std::isfinite(v) && (scale == Scale::Linear || v > 0.0); }

void require(bool ok, const std::string& what, const std::string& hint = {}) {
  if (!ok) throw InvalidArgument(what, hint);
}

void check_size(int width_px, int height_px) {
  require(width_px >= 200 && width_px <= 20000 && height_px >= 200 && height_px <= 20000,
          fmt::format("figure size {}×{} px is outside 200…20000 px", width_px, height_px));
}

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

// ---- Script generation -------------------------------------------------------------------------

namespace {

// The shared x range: explicit limits, else the data's extent over every panel, so that the
// stacked panels line up (gnuplot would autoscale each panel on its own).
std::pair<double, double> shared_x_range(const Figure& fig) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  auto take = [&](const std::vector<double>& xs) {
    for (double v : xs)
      if (plottable(v, fig.x.scale)) lo = std::min(lo, v), hi = std::max(hi, v);
  };
  for (const Panel& p : fig.panels) {
    for (const Curve& c : p.curves) take(c.x);
    for (const Fill& f : p.fills) take(f.x);
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
    case CurveStyle::Line:
      return fmt::format("{} lw 2 dt {} {}", sparse, dash, colour);
    case CurveStyle::Dashed:
      return fmt::format("with lines lw 2 dt {} {}", series == 0 ? kDashes[1] : dash, colour);
    case CurveStyle::Points:
      return fmt::format("with points pt {} ps 1.0 lw 1.5 {}", pt, colour);
    case CurveStyle::LinePoints:
      return fmt::format("with linespoints lw 2 dt {} pt {} ps 1.4 pi 1 {}", dash, pt, colour);
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
    if (plottable(v, Scale::Log)) lo = std::min(lo, v), hi = std::max(hi, v);
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

Frame frame_of(const Figure& fig) {
  double right_px = kRightPx;
  for (const Panel& p : fig.panels)
    if (p.legend == Legend::Outside && !legend_texts(p).empty()) right_px = std::max(right_px, legend_width_px(p) + 15.0);
  return {kLeftPx / fig.width_px, 1.0 - right_px / fig.width_px};
}

bool has_points(const std::vector<double>& xs, const std::vector<double>& ys, Scale xs_scale, Scale ys_scale) {
  for (std::size_t k = 0; k < xs.size(); ++k)
    if (plottable(xs[k], xs_scale) && plottable(ys[k], ys_scale)) return true;
  return false;
}

void append_panel(std::string& s, const Figure& fig, std::size_t i, double top, double bottom,
                  std::pair<double, double> xr, Frame frame) {
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
  append_axis(s, 'y', p.y, limit(p.y.min), limit(p.y.max), y_decades(p), true);
  if (p.legend == Legend::Hidden || legend_texts(p).empty()) {
    s += "unset key\n";
  } else if (p.legend == Legend::Outside) {
    // No box: gnuplot sizes boxes from its own, generous estimate of text width.
    s += fmt::format("set key at screen {:.5f}, screen {:.5f} left top Left reverse nobox samplen {} spacing 1.15\n",
                     frame.right + 10.0 / fig.width_px, top, kSampleChars);
  } else {
    s += fmt::format("set key {} opaque box lc rgb \"#A0A0A0\" samplen {} spacing 1.15 width 1\n", key_position(p.legend),
                     kSampleChars);
  }

  std::vector<std::string> items;
  for (std::size_t k = 0; k < p.bands.size(); ++k) {
    const Band& b = p.bands[k];
    s += fmt::format("set object {} rect from first {}, graph 0 to first {}, graph 1 behind fc rgb \"{}\" fs solid 1.0 noborder\n",
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
      s += fmt::format("set label {} at first {}, graph 0.94 left offset 0.4,0 front boxed\n", gp_text(v.label),
                       number(v.x));
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
  }
  // House style shared by every panel.
  s += "set grid xtics ytics back lt 1 lw 1 lc rgb \"#E0E0E0\" dt solid\n"
       "set border lw 1.2\n"
       "set tics scale 1.2, 0.6\n"
       "set samples 2\n"  // horizontal lines are constants: two samples draw them exactly
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

// ---- Running gnuplot -------------------------------------------------------------------------

void PlotOptions::check() const {
  require(!gnuplot.empty(), "PlotOptions::gnuplot is empty", "give the gnuplot program, e.g. \"gnuplot\"");
  require(std::isfinite(timeout_s) && timeout_s > 0.0, fmt::format("PlotOptions::timeout_s {} must be > 0", timeout_s));
}

namespace {

// While a pipe to a child is written, SIGPIPE is blocked in this thread (so a child that exits
// early gives EPIPE, not the death of the caller) and a SIGPIPE raised meanwhile is consumed.
class SigpipeBlock {
 public:
  SigpipeBlock() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
    sigset_t pending;
    sigpending(&pending);
    was_pending_ = sigismember(&pending, SIGPIPE) == 1;
  }
  ~SigpipeBlock() {
    sigset_t pending;
    sigpending(&pending);
    if (!was_pending_ && sigismember(&pending, SIGPIPE) == 1) {
      const timespec zero{0, 0};
      sigtimedwait(&pipe_, nullptr, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeBlock(const SigpipeBlock&) = delete;
  SigpipeBlock& operator=(const SigpipeBlock&) = delete;

 private:
  sigset_t pipe_{}, old_{};
  bool was_pending_ = false;
};

class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { reset(); }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

struct ChildOutcome {
  int status = 0;
  std::string err;
};

// Runs `program -d -` (no init files, script on stdin), feeding `script` and collecting stderr
// concurrently so that neither pipe can fill up and stall the other.
ChildOutcome run_gnuplot(const PlotOptions& o, const std::string& script) {
  int in[2], err[2];
  if (::pipe2(in, O_CLOEXEC) != 0) throw IoError(fmt::format("cannot create a pipe to gnuplot ({})", std::strerror(errno)));
  Fd in_read(in[0]), in_write(in[1]);
  if (::pipe2(err, O_CLOEXEC) != 0) throw IoError(fmt::format("cannot create a pipe from gnuplot ({})", std::strerror(errno)));
  Fd err_read(err[0]), err_write(err[1]);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in_read.get(), 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, err_write.get(), 2);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, pipe_default;
  sigemptyset(&none);
  sigemptyset(&pipe_default);
  sigaddset(&pipe_default, SIGPIPE);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &pipe_default);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::string arg0 = o.gnuplot, arg1 = "-d", arg2 = "-";
  char* argv[] = {arg0.data(), arg1.data(), arg2.data(), nullptr};
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, o.gnuplot.c_str(), &actions, &attr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0)
    throw PlotUnavailable(fmt::format("gnuplot not found: cannot run '{}' ({})", o.gnuplot, std::strerror(rc)),
                          "install gnuplot (Debian: apt-get install gnuplot-nox) and make sure it is on PATH");
  in_read.reset();
  err_write.reset();

  ChildOutcome out;
  SigpipeBlock no_sigpipe;
  ::fcntl(in_write.get(), F_SETFL, ::fcntl(in_write.get(), F_GETFL) | O_NONBLOCK);
  std::size_t written = 0;
  if (script.empty()) in_write.reset();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.timeout_s);
  constexpr std::size_t kMaxErr = 1 << 20;  // a runaway stream of warnings is cut, not buffered whole
  bool err_open = true;
  while (err_open) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
      throw IoError(fmt::format("gnuplot ('{}') did not finish within {} s and was stopped", o.gnuplot, o.timeout_s),
                    "simplify the figure (fewer points) or raise PlotOptions::timeout_s");
    }
    pollfd fds[2] = {{err_read.get(), POLLIN, 0}, {in_write.get(), POLLOUT, 0}};
    const nfds_t n = in_write.get() >= 0 ? 2 : 1;
    if (::poll(fds, n, static_cast<int>(std::min<long long>(left.count(), 1000))) < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
      throw IoError(fmt::format("lost contact with gnuplot ('{}'): poll failed ({})", o.gnuplot, why));
    }
    if (fds[0].revents != 0) {
      char buf[4096];
      const ssize_t got = ::read(err_read.get(), buf, sizeof buf);
      if (got > 0) {
        if (out.err.size() < kMaxErr) out.err.append(buf, static_cast<std::size_t>(got));
      } else if (got == 0 || errno != EINTR) {
        err_open = false;
      }
    }
    if (n == 2 && fds[1].revents != 0) {
      const ssize_t put = ::write(in_write.get(), script.data() + written, script.size() - written);
      if (put > 0) written += static_cast<std::size_t>(put);
      if ((put < 0 && errno != EAGAIN && errno != EINTR) || written == script.size()) in_write.reset();
    }
  }
  in_write.reset();
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  out.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return out;
}

// The terminal, chosen inside gnuplot from what this gnuplot was built with; the choice is
// reported back on stderr through "toolpoint-…:" lines. PDF keeps the PNG's proportions: the
// cairo PNG works at 72 px per inch, and pdfcairo's default font and line scale is one half.
std::string terminal_lines(Format format, int w, int h) {
  const std::string font = fmt::format("font \"{},{}\"", kFont, kFontPt);
  switch (format) {
    case Format::Png:
      return fmt::format(
          "if (strstrt(GPVAL_TERMINALS, \" pngcairo \") > 0) {{\n"
          "  set terminal pngcairo size {0},{1} enhanced {2} linewidth 1 rounded background \"#FFFFFF\"\n"
          "  print \"toolpoint-terminal: pngcairo\"\n"
          "}} else {{\n"
          "  set terminal png size {0},{1} enhanced truecolor font \"DejaVuSans,{3}\"\n"
          "  print \"toolpoint-terminal: png\"\n"
          "  print \"toolpoint-note: gnuplot has no pngcairo terminal; used the libgd png terminal (no anti-aliasing, "
          "plainer dashes)\"\n"
          "}}\n",
          w, h, font, kFontPt - 4);
    case Format::Svg:
      return fmt::format(
          "set terminal svg size {},{} enhanced {} linewidth 1 rounded background \"#FFFFFF\"\n"
          "print \"toolpoint-terminal: svg\"\n",
          w, h, font);
    case Format::Pdf:
      return fmt::format(
          "if (strstrt(GPVAL_TERMINALS, \" pdfcairo \") == 0) {{\n"
          "  print \"toolpoint-unavailable: gnuplot has no pdfcairo terminal, so it cannot write PDF\"\n"
          "  exit status 3\n"
          "}}\n"
          "set terminal pdfcairo size {:.6f},{:.6f} enhanced {} fontscale 1 linewidth 2 rounded background \"#FFFFFF\"\n"
          "print \"toolpoint-terminal: pdfcairo\"\n",
          (w + 0.01) / 72.0, (h + 0.01) / 72.0, font);  // a hair over, or cairo truncates to a point less
  }
  return {};
}

std::string trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

}  // namespace

RenderResult render_script(const std::string& body, const std::string& path, int width_px, int height_px,
                           const PlotOptions& options) {
  options.check();
  const Format format = format_for_path(path);
  check_size(width_px, height_px);
  AtomicOutput tmp(path);
  const std::string script = terminal_lines(format, width_px, height_px) + "set output " + gp_path(tmp.path()) +
                             "\n" + body + "\nunset output\n";
  const ChildOutcome run = run_gnuplot(options, script);

  RenderResult result;
  result.path = path;
  result.format = format;
  std::string unavailable, message;
  std::size_t start = 0;
  while (start < run.err.size()) {
    std::size_t end = run.err.find('\n', start);
    if (end == std::string::npos) end = run.err.size();
    const std::string line = run.err.substr(start, end - start);
    start = end + 1;
    auto tagged = [&](std::string_view tag) { return line.rfind(tag, 0) == 0 ? trimmed(line.substr(tag.size())) : std::string(); };
    if (auto t = tagged("toolpoint-terminal:"); !t.empty()) {
      result.terminal = t;
    } else if (auto n = tagged("toolpoint-note:"); !n.empty()) {
      result.notes.push_back(n);
    } else if (auto u = tagged("toolpoint-unavailable:"); !u.empty()) {
      unavailable = u;
    } else {
      message += line + '\n';
    }
  }
  message = trimmed(message);
  if (!unavailable.empty())
    throw PlotUnavailable(fmt::format("{}: {} ('{}')", path, unavailable, options.gnuplot),
                          "install a gnuplot built with cairo (Debian: gnuplot-nox) or write .png/.svg instead");
  if (run.status != 0) {
    if (message.size() > 4000) message = "…" + message.substr(message.size() - 4000);
    throw IoError(fmt::format("{}: gnuplot failed (exit status {}); nothing was written. gnuplot said:\n{}", path,
                              run.status, message.empty() ? "(nothing)" : message),
                  "the message above names the gnuplot command at fault");
  }
  std::error_code ec;
  const auto size = fs::file_size(tmp.path(), ec);
  if (ec || size == 0)
    throw IoError(fmt::format("{}: gnuplot reported success but wrote nothing; nothing was written", path));
  if (!message.empty()) {
    std::size_t from = 0;
    while (from < message.size()) {
      const std::size_t to = std::min(message.find('\n', from), message.size());
      if (auto w = trimmed(std::string_view(message).substr(from, to - from)); !w.empty()) result.warnings.push_back(w);
      from = to + 1;
    }
  }
  tmp.commit();
  return result;
}

RenderResult render(const Figure& figure, const std::string& path, const PlotOptions& options) {
  format_for_path(path);  // a bad extension is reported before any work
  return render_script(gnuplot_script(figure), path, figure.width_px, figure.height_px, options);
}

// ---- Ready-made figures ------------------------------------------------------------------------

std::vector<std::size_t> peak_indices(const std::vector<double>& v, int max_peaks, double min_ratio) {
  require(max_peaks >= 0, fmt::format("peak_indices: max_peaks {} must be ≥ 0", max_peaks));
  require(min_ratio > 1.0 && std::isfinite(min_ratio), fmt::format("peak_indices: min_ratio {} must be > 1", min_ratio));
  // A ratio r = peak/valley is a prominence 1 − 1/r (peaks.hpp).
  std::vector<Peak> found = find_peaks(v, 1.0 - 1.0 / min_ratio);
  std::stable_sort(found.begin(), found.end(), [](const Peak& a, const Peak& b) { return a.prominence > b.prominence; });
  if (found.size() > static_cast<std::size_t>(max_peaks)) found.resize(static_cast<std::size_t>(max_peaks));
  std::vector<std::size_t> out;
  for (const Peak& p : found) out.push_back(p.index);
  std::sort(out.begin(), out.end());
  return out;
}

void FrfFigureOptions::check() const {
  require(mode_labels >= 0, fmt::format("FrfFigureOptions::mode_labels {} must be ≥ 0", mode_labels));
  require(min_peak_ratio > 1.0 && std::isfinite(min_peak_ratio),
          fmt::format("FrfFigureOptions::min_peak_ratio {} must be > 1", min_peak_ratio));
  if (frequency_range_hz)
    require(std::isfinite(frequency_range_hz->first) && std::isfinite(frequency_range_hz->second) &&
                frequency_range_hz->first < frequency_range_hz->second,
            fmt::format("FrfFigureOptions::frequency_range_hz [{}, {}] must be finite and increasing",
                        frequency_range_hz->first, frequency_range_hz->second));
}

namespace {

// Figure height for n stacked panels: the house 700 px holds two; each further panel adds 170 px.
int height_for_panels(std::size_t n) { return 700 + 170 * static_cast<int>(n > 2 ? n - 2 : 0); }

std::string hz_text(double f) { return f >= 100.0 ? fmt::format("{:.0f} Hz", f) : fmt::format("{:.3g} Hz", f); }

// Phase in degrees with a break (NaN point) wherever it wraps, so no vertical jump is drawn.
void phase_curve(const FrfSeries& s, std::vector<double>& x, std::vector<double>& y) {
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double deg = std::arg(s.values[k]) * 180.0 / kPi;
    if (!y.empty() && std::abs(deg - y.back()) > 180.0) {
      x.push_back(kNaN);
      y.push_back(kNaN);
    }
    x.push_back(s.frequency_hz[k]);
    y.push_back(deg);
  }
}

std::vector<double> scaled(const std::vector<double>& values, double factor) {
  std::vector<double> out;
  out.reserve(values.size());
  for (double v : values) out.push_back(v * factor);
  return out;
}

std::vector<double> mm_of(const std::vector<double>& metres) { return scaled(metres, 1000.0); }

// The power of 1000 that brings the largest |value| into [1, 1000): linear tic labels then need
// at most four digits instead of "1.5×10^{7}", which would crowd the axis label off the figure.
int engineering_exponent(const std::vector<double>& values) {
  double largest = 0.0;
  for (double v : values)
    if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
  if (!(largest > 0.0)) return 0;
  int e = 3 * static_cast<int>(std::floor(std::log10(largest) / 3.0));
  // log10 may land a hair on the wrong side of an exact power of ten (1e-6 → −6.0000000001).
  if (largest / std::pow(10.0, e) >= 1000.0 * (1.0 - 1e-12)) e += 3;
  if (largest / std::pow(10.0, e) < 1.0 - 1e-12) e -= 3;
  return e;
}

// `unit` for values divided by 10^exponent: an SI prefix on a unit that starts with a plain SI
// symbol (m/N → µm/N, N·m/rad → kN·m/rad), otherwise a power of ten in front (10^{6} 1/N).
std::string prefixed_unit(const std::string& unit, int exponent) {
  if (exponent == 0) return unit;
  static const std::pair<int, const char*> kPrefixes[] = {{-12, "p"}, {-9, "n"}, {-6, "µ"}, {-3, "m"},
                                                          {3, "k"},   {6, "M"},  {9, "G"},  {12, "T"}};
  static const std::string_view kSymbols[] = {"N", "m", "rad", "Pa", "s", "Hz"};
  const char* prefix = nullptr;
  for (const auto& [e, p] : kPrefixes)
    if (e == exponent) prefix = p;
  // A symbol followed by a letter is something else ("mm", "kg"…) and gets no second prefix.
  const auto plain = [&](std::string_view sym) {
    return unit.starts_with(sym) && (unit.size() == sym.size() || !std::isalpha(static_cast<unsigned char>(unit[sym.size()])));
  };
  if (prefix != nullptr && std::any_of(std::begin(kSymbols), std::end(kSymbols), plain)) return prefix + unit;
  return fmt::format("10^{{{}}} {}", exponent, unit);
}

}  // namespace

Figure frf_figure(const std::vector<FrfTrace>& traces, const FrfFigureOptions& o) {
  o.check();
  require(!traces.empty(), "FRF figure: no traces", "pass at least one FRF");
  require(o.mode_labels == 0 || o.peak_trace < traces.size(),
          fmt::format("FRF figure: peak_trace {} but only {} traces", o.peak_trace, traces.size()));
  Figure fig;
  fig.title = o.title;
  fig.x = Axis{"Frequency [Hz]", o.frequency_scale, std::nullopt, std::nullopt, std::nullopt};
  if (o.frequency_range_hz) fig.x.min = o.frequency_range_hz->first, fig.x.max = o.frequency_range_hz->second;
  Panel upper, lower;
  upper.height = 1.6;
  lower.legend = Legend::Hidden;
  const bool polar = o.view == FrfView::MagnitudePhase;
  // Re and Im of every trace share one scale factor, from the largest part of any trace.
  std::vector<double> parts;
  for (std::size_t t = 0; t < traces.size(); ++t) {
    validate(traces[t].frf, traces[t].label.empty() ? fmt::format("FRF trace {}", t + 1) : traces[t].label);
    for (const Complex& v : traces[t].frf.values) parts.push_back(std::max(std::abs(v.real()), std::abs(v.imag())));
  }
  const int exponent = polar ? 0 : engineering_exponent(parts);
  const double factor = std::pow(10.0, -exponent);
  const std::string unit = prefixed_unit(o.unit, exponent);
  upper.y.label = polar ? fmt::format("|{}| [{}]", o.symbol, unit) : fmt::format("Re {} [{}]", o.symbol, unit);
  upper.y.scale = polar ? Scale::Log : Scale::Linear;
  lower.y.label = polar ? fmt::format("∠{} [deg]", o.symbol) : fmt::format("Im {} [{}]", o.symbol, unit);
  // A little beyond ±180° so that a phase lying at −180° is not hidden in the frame.
  if (polar) lower.y.min = -198.0, lower.y.max = 198.0, lower.y.tic_step = 90.0;
  for (const FrfTrace& tr : traces) {
    Curve a{tr.frf.frequency_hz, {}, tr.label, tr.style, -1}, b{{}, {}, tr.label, tr.style, -1};
    for (const Complex& v : tr.frf.values) a.y.push_back(polar ? std::abs(v) : v.real() * factor);
    if (polar) {
      phase_curve(tr.frf, b.x, b.y);
    } else {
      b.x = tr.frf.frequency_hz;
      for (const Complex& v : tr.frf.values) b.y.push_back(v.imag() * factor);
    }
    upper.curves.push_back(std::move(a));
    lower.curves.push_back(std::move(b));
  }
  if (o.mode_labels > 0) {
    const FrfSeries& s = traces[o.peak_trace].frf;
    std::vector<double> magnitude;  // NaN outside the plotted range: no peak is sought there
    for (std::size_t k = 0; k < s.size(); ++k) {
      const double f = s.frequency_hz[k];
      magnitude.push_back(fig.x.min && (f < *fig.x.min || f > *fig.x.max) ? kNaN : std::abs(s.values[k]));
    }
    for (std::size_t k : peak_indices(magnitude, o.mode_labels, o.min_peak_ratio)) {
      const double f = s.frequency_hz[k];
      if (polar) {
        upper.labels.push_back({f, magnitude[k], hz_text(f), true});
      } else {  // Re X swings through zero at a mode: a marker line through both panels reads best
        upper.vertical_lines.push_back({f, hz_text(f)});
        lower.vertical_lines.push_back({f, ""});
      }
    }
  }
  fig.panels = {std::move(upper), std::move(lower)};
  return fig;
}

namespace {

// "_{11}" for subscript "11", nothing for none.
std::string subscript_text(const std::string& subscript) { return subscript.empty() ? "" : "_{" + subscript + "}"; }

// |H| and ∠H of a block series with `mode_labels` peaks of |H| labelled: the top of the
// receptance and block figures. `what` names the series in errors when there is no title.
Figure h_entry_figure(const BlockSeries& series, const std::string& title, const std::string& subscript, int mode_labels,
                      const std::string& what) {
  validate(series, title.empty() ? what : title);
  FrfFigureOptions o;
  o.title = title;
  o.mode_labels = mode_labels;
  o.symbol = "H" + subscript_text(subscript);
  return frf_figure({{entry(series, 0), "", CurveStyle::Line}}, o);
}

}  // namespace

Figure receptance_figure(const BlockSeries& series, const std::string& title, const std::string& subscript,
                         int mode_labels) {
  Figure fig = h_entry_figure(series, title, subscript, mode_labels, "receptance");
  FrfFigureOptions o;
  o.title = title;
  o.symbol = "P" + subscript_text(subscript);
  o.unit = "rad/(N·m)";
  Figure p = frf_figure({{entry(series, 3), "", CurveStyle::Line}}, o);
  for (Panel& panel : p.panels) fig.panels.push_back(std::move(panel));
  fig.height_px = height_for_panels(fig.panels.size());
  return fig;
}

Figure block_figure(const BlockSeries& series, const std::string& title, const std::string& subscript, int mode_labels) {
  Figure fig = h_entry_figure(series, title, subscript, mode_labels, "receptance block");
  const std::string sub = subscript_text(subscript);
  fig.panels.resize(1);  // |H| with its mode labels; the phases get a panel of their own
  fig.panels[0].height = 1.3;
  const auto magnitude = [&](int k) {
    Curve c{series.frequency_hz, {}, std::string(1, "HLNP"[k]) + sub, CurveStyle::Line, k};
    for (const Block& b : series.blocks) c.y.push_back(std::abs(b(k / 2, k % 2)));
    return c;
  };
  Panel ln, p, phase;
  // L = w/m [1/N] and N = θ/f [rad/N] share one axis: rad is dimensionless.
  ln.y = Axis{fmt::format("|L{0}|, |N{0}| [1/N]", sub), Scale::Log, std::nullopt, std::nullopt, std::nullopt};
  ln.curves = {magnitude(1), magnitude(2)};
  ln.legend = Legend::Outside;
  p.y = Axis{fmt::format("|P{}| [rad/(N·m)]", sub), Scale::Log, std::nullopt, std::nullopt, std::nullopt};
  p.curves = {magnitude(3)};
  p.legend = Legend::Outside;
  phase.y = Axis{"Phase [deg]", Scale::Linear, -198.0, 198.0, 90.0};  // ±180° kept off the frame
  phase.legend = Legend::Outside;
  for (int k = 0; k < 4; ++k) {
    Curve c{{}, {}, std::string(1, "HLNP"[k]) + sub, CurveStyle::Line, k};
    phase_curve(entry(series, k), c.x, c.y);
    phase.curves.push_back(std::move(c));
  }
  fig.panels.push_back(std::move(ln));
  fig.panels.push_back(std::move(p));
  fig.panels.push_back(std::move(phase));
  fig.height_px = height_for_panels(fig.panels.size());
  return fig;
}

Figure overhang_frf_figure(const std::vector<double>& overhang_m, const std::vector<FrfSeries>& frfs,
                           const FrfFigureOptions& options) {
  require(overhang_m.size() == frfs.size(),
          fmt::format("overhang FRF figure: {} overhangs but {} FRFs", overhang_m.size(), frfs.size()));
  std::vector<FrfTrace> traces;
  for (std::size_t i = 0; i < frfs.size(); ++i)
    traces.push_back({frfs[i], fmt::format("overhang {:g} mm", overhang_m[i] * 1000.0), CurveStyle::Line});
  return frf_figure(traces, options);
}

Figure natural_frequency_figure(const OverhangSweep& sweep) {
  require(!sweep.frequency_hz.empty(), "natural frequency figure: no modes", "pass one frequency list per mode");
  require(sweep.mode_names.empty() || sweep.mode_names.size() == sweep.frequency_hz.size(),
          fmt::format("natural frequency figure: {} mode names for {} modes", sweep.mode_names.size(),
                      sweep.frequency_hz.size()));
  Figure fig;
  fig.title = sweep.title;
  fig.x.label = "Tool overhang [mm]";
  Panel p;
  p.legend = Legend::Outside;
  p.y.label = "Natural frequency [Hz]";
  const std::vector<double> x = mm_of(sweep.overhang_m);
  for (std::size_t m = 0; m < sweep.frequency_hz.size(); ++m) {
    require(sweep.frequency_hz[m].size() == x.size(),
            fmt::format("natural frequency figure: mode {} has {} frequencies for {} overhangs", m + 1,
                        sweep.frequency_hz[m].size(), x.size()));
    p.curves.push_back({x, sweep.frequency_hz[m],
                        sweep.mode_names.empty() ? fmt::format("mode {}", m + 1) : sweep.mode_names[m],
                        CurveStyle::LinePoints, -1});
  }
  fig.panels.push_back(std::move(p));
  return fig;
}

namespace {

// The y range of a noisy identified parameter: 2nd–98th percentile of the values (in the band
// when there is one) together with the reference lines, widened by a quarter each side, and never
// narrower than ±5 % around the middle of that range — so a flat (noise-free) result shows flat,
// as in the seed's Fig. 3, rather than its round-off magnified to fill the panel.
std::pair<double, double> robust_range(const std::vector<double>& f, const std::vector<double>& v,
                                       const std::optional<std::pair<double, double>>& band,
                                       const std::vector<double>& lines) {
  std::vector<double> kept;
  for (std::size_t k = 0; k < v.size(); ++k)
    if (std::isfinite(v[k]) && (!band || (f[k] >= band->first && f[k] <= band->second))) kept.push_back(v[k]);
  if (kept.empty())
    for (double x : v)
      if (std::isfinite(x)) kept.push_back(x);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  if (!kept.empty()) {
    std::sort(kept.begin(), kept.end());
    const auto at = [&](double q) { return kept[static_cast<std::size_t>(q * static_cast<double>(kept.size() - 1))]; };
    lo = at(0.02);
    hi = at(0.98);
  }
  for (double l : lines) lo = std::min(lo, l), hi = std::max(hi, l);
  double span = hi - lo;
  if (!(span > 0.0)) span = std::max(std::abs(hi) * 0.2, 1e-300);
  lo -= 0.25 * span;
  hi += 0.25 * span;
  const double mid = 0.5 * (lo + hi), half = 0.05 * std::max(std::abs(lo), std::abs(hi));
  return {std::min(lo, mid - half), std::max(hi, mid + half)};
}

}  // namespace

Figure joint_figure(const JointFigureData& data) {
  require(!data.parameters.empty(), "joint figure: no parameters", "pass at least one k(ω) or c(ω) series");
  if (data.band_hz)
    require(data.band_hz->first < data.band_hz->second,
            fmt::format("joint figure: band [{}, {}] Hz is empty or inverted", data.band_hz->first, data.band_hz->second));
  Figure fig;
  fig.title = data.title;
  fig.x.label = "Frequency [Hz]";
  for (int damping = 0; damping < 2; ++damping) {
    for (const JointParameterCurve& jp : data.parameters) {
      const std::vector<double>& values = damping ? jp.damping : jp.stiffness;
      if (values.empty()) continue;
      const char letter = damping ? 'c' : 'k';
      const std::string& unit = damping ? jp.damping_unit : jp.stiffness_unit;
      require(values.size() == data.frequency_hz.size(),
              fmt::format("joint figure: {}_{} has {} values for {} frequencies", letter, jp.name, values.size(),
                          data.frequency_hz.size()));
      const auto reference = damping ? jp.reference_damping : jp.reference_stiffness;
      const auto identified = damping ? jp.identified_damping : jp.identified_stiffness;
      std::vector<double> lines;
      if (reference) lines.push_back(*reference);
      if (identified) lines.push_back(*identified);
      // The scale comes from the values a reader looks at: the robust range, or all values.
      const auto [lo, hi] = robust_range(data.frequency_hz, values, data.band_hz, lines);
      const int exponent = data.robust_range ? engineering_exponent({lo, hi}) : engineering_exponent(values);
      const double factor = std::pow(10.0, -exponent);
      const std::string shown_unit = prefixed_unit(unit, exponent);
      Panel p;
      p.legend = Legend::Outside;
      p.y.label = fmt::format("{}_{{{}}} [{}]", letter, jp.name, shown_unit);
      p.curves.push_back({data.frequency_hz, scaled(values, factor), fmt::format("{}_{{{}}}(f)", letter, jp.name),
                          CurveStyle::Line, -1});
      if (reference)
        p.horizontal_lines.push_back({*reference * factor, fmt::format("reference {:.4g} {}", *reference * factor, shown_unit)});
      if (identified)
        p.horizontal_lines.push_back(
            {*identified * factor, fmt::format("identified {:.4g} {}", *identified * factor, shown_unit)});
      if (data.band_hz)
        p.bands.push_back({data.band_hz->first, data.band_hz->second, fig.panels.empty() ? "identification band" : ""});
      if (data.robust_range) {
        p.y.min = lo * factor;
        p.y.max = hi * factor;
      }
      fig.panels.push_back(std::move(p));
    }
  }
  require(!fig.panels.empty(), "joint figure: every parameter has empty stiffness and damping");
  fig.height_px = height_for_panels(fig.panels.size());
  return fig;
}

Figure lobes_figure(const LobesFigureData& data) {
  require(!data.lobes.empty() || !data.envelope_rpm.empty(), "lobes figure: no lobes and no envelope",
          "pass the lobes and/or their envelope");
  require(data.envelope_rpm.size() == data.envelope_depth_m.size(),
          fmt::format("lobes figure: envelope has {} speeds but {} depths", data.envelope_rpm.size(),
                      data.envelope_depth_m.size()));
  double floor = std::numeric_limits<double>::infinity();
  for (double d : data.envelope_depth_m)
    if (std::isfinite(d) && d > 0.0) floor = std::min(floor, d);
  for (const Lobe& l : data.lobes) {
    require(l.spindle_speed_rpm.size() == l.depth_m.size() &&
                (l.chatter_frequency_hz.empty() || l.chatter_frequency_hz.size() == l.depth_m.size()),
            fmt::format("lobes figure: lobe {} has {} speeds, {} depths and {} chatter frequencies", l.number,
                        l.spindle_speed_rpm.size(), l.depth_m.size(), l.chatter_frequency_hz.size()));
    if (data.envelope_depth_m.empty())
      for (double d : l.depth_m)
        if (std::isfinite(d) && d > 0.0) floor = std::min(floor, d);
  }
  const double top = data.depth_max_m.value_or(5.0 * floor);
  require(std::isfinite(top) && top > 0.0, fmt::format("lobes figure: depth axis top {} m must be > 0", top),
          "give depth_max_m or lobes with positive depths");

  Figure fig;
  fig.title = data.title;
  fig.x.label = "Spindle speed [rpm]";
  // The envelope spans the speeds of interest; lobes computed beyond it are cut at its ends.
  if (data.envelope_rpm.size() >= 2) {
    const auto [lo, hi] = std::minmax_element(data.envelope_rpm.begin(), data.envelope_rpm.end());
    if (std::isfinite(*lo) && std::isfinite(*hi) && *lo < *hi) fig.x.min = *lo, fig.x.max = *hi;
  }
  Panel depth, chatter;
  depth.height = 1.8;
  depth.y = Axis{"Axial depth of cut [mm]", Scale::Linear, 0.0, top * 1000.0, std::nullopt};
  depth.legend = Legend::Outside;  // lobes rise through every corner of the frame
  chatter.y.label = "Chatter frequency [Hz]";
  chatter.legend = Legend::Outside;
  const std::vector<double> env = mm_of(data.envelope_depth_m);
  if (!data.envelope_rpm.empty()) depth.fills.push_back({data.envelope_rpm, env, 0.0, "stable"});
  bool named = false;
  std::map<int, TextLabel> lowest;  // per lobe number (a lobe may come as several branches)
  double rpm_lo = std::numeric_limits<double>::infinity(), rpm_hi = -rpm_lo;
  for (const Lobe& l : data.lobes) {
    const std::vector<double> mm = mm_of(l.depth_m);
    // The lobe number sits above the lobe's lowest point, in the unstable region; a lobe whose
    // lowest point is an end of its data has its minimum elsewhere, and gets no number.
    std::size_t low = mm.size();
    for (std::size_t k = 0; k < mm.size(); ++k)
      if (std::isfinite(mm[k]) && std::isfinite(l.spindle_speed_rpm[k]) && (low == mm.size() || mm[k] < mm[low])) low = k;
    if (low == mm.size()) continue;  // nothing to draw
    for (double r : l.spindle_speed_rpm)
      if (std::isfinite(r)) rpm_lo = std::min(rpm_lo, r), rpm_hi = std::max(rpm_hi, r);
    if (low > 0 && low + 1 < mm.size() && mm[low] < top * 1000.0) {
      auto it = lowest.find(l.number);
      if (it == lowest.end() || mm[low] < it->second.y)
        lowest[l.number] = {l.spindle_speed_rpm[low], mm[low], fmt::format("{}", l.number), false};
    }
    depth.curves.push_back({l.spindle_speed_rpm, mm, named ? "" : "lobes", CurveStyle::Dashed, 2});
    if (!l.chatter_frequency_hz.empty())
      chatter.curves.push_back({l.spindle_speed_rpm, l.chatter_frequency_hz, named ? "" : "lobes", CurveStyle::Dashed, 2});
    named = true;
  }
  // Lobe numbers from the highest speed down (lobe 0 first); one that would sit within 6 % of the
  // speed range of a number already placed is left out: high lobes crowd at low speed.
  double last = std::numeric_limits<double>::infinity();
  for (const auto& [number, label] : lowest) {
    if (std::abs(last - label.x) < 0.06 * (rpm_hi - rpm_lo)) continue;
    depth.labels.push_back(label);
    last = label.x;
  }
  // The envelope last, on top of the lobes that form it.
  if (!data.envelope_rpm.empty()) depth.curves.push_back({data.envelope_rpm, env, "stability limit", CurveStyle::Line, 0});
  fig.panels.push_back(std::move(depth));
  if (!chatter.curves.empty()) fig.panels.push_back(std::move(chatter));
  return fig;
}

}  // namespace toolpoint::plot
