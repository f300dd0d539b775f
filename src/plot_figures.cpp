// toolpoint: the ready-made figures of toolpoint's results (FRFs, joints, overhangs, lobes) (plot.hpp).
#include "toolpoint/plot/plot.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "plot_detail.hpp"

namespace toolpoint::plot {

using namespace detail;

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
  check_fields(frf_figure_fields(), *this, "FrfFigureOptions");
  if (frequency_range_hz)
    require(std::isfinite(frequency_range_hz->first) && std::isfinite(frequency_range_hz->second) &&
                frequency_range_hz->first < frequency_range_hz->second,
            fmt::format("FrfFigureOptions::frequency_range_hz [{}, {}] must be finite and increasing", frequency_range_hz->first,
                        frequency_range_hz->second));
}

const std::vector<OptionField<FrfFigureOptions>>& frf_figure_fields() {
  using O = FrfFigureOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "mode_labels",
        .kind = FieldKind::Integer,
        .min = 0.0,
        .note = "0: none",
        .help = "label up to this many peaks (frequency in Hz) of trace peak_trace"},
       nullptr,
       [](O& o) -> int& { return o.mode_labels; }},
      {{.name = "min_peak_ratio",
        .kind = FieldKind::Real,
        .min = 1.0,
        .min_open = true,
        .help = "how far a labelled peak stands above its surrounding valleys (2 = 6 dB)"},
       [](O& o) -> double& { return o.min_peak_ratio; }}};
  return fields;
}

namespace {

// Figure height for n stacked panels: the house 700 px holds two; each further panel adds 170 px.
int height_for_panels(std::size_t n) { return 700 + 170 * static_cast<int>(n > 2 ? n - 2 : 0); }

std::string hz_text(double f) { return f >= 100.0 ? fmt::format("{:.0f} Hz", f) : fmt::format("{:.3g} Hz", f); }

// Phase in degrees with a break (NaN point) wherever it wraps, so no vertical jump is drawn.
void phase_curve(const FrfSeries& s, std::vector<double>& x, std::vector<double>& y) {
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double deg = degrees_of(std::arg(s.values[k]));
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
  if (o.frequency_range_hz) {
    fig.x.min = o.frequency_range_hz->first;
    fig.x.max = o.frequency_range_hz->second;
  }
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
  if (polar) {
    lower.y.min = -198.0;
    lower.y.max = 198.0;
    lower.y.tic_step = 90.0;
  }
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

Figure receptance_figure(const BlockSeries& series, const std::string& title, const std::string& subscript, int mode_labels) {
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

namespace {

// The input (points) and the filtered series (line) of each entry, one magnitude panel per entry
// (legend in the first), the phase of the first entry last.
Figure filter_entries(const std::vector<FrfSeries>& raw, const std::vector<FrfSeries>& filtered,
                      const std::vector<std::pair<const char*, const char*>>& symbols_units, const std::string& title) {
  Figure fig;
  const std::size_t entries = raw.size();
  for (std::size_t k = 0; k < entries; ++k) {
    FrfFigureOptions fo;
    fo.title = title;
    fo.mode_labels = k == 0 ? 6 : 0;
    fo.peak_trace = 1;  // the filtered trace: noise makes spurious peaks on the input
    fo.symbol = symbols_units[k].first;
    fo.unit = symbols_units[k].second;
    Figure one = frf_figure({{raw[k], "input", CurveStyle::Points}, {filtered[k], "filtered", CurveStyle::Line}}, fo);
    if (k == 0) {
      fig = one;
      if (entries > 1) fig.panels.resize(1);
    } else {
      fig.panels.push_back(one.panels[0]);
      fig.panels.back().legend = Legend::Hidden;  // the first panel's legend says it for all
    }
  }
  if (entries > 1) {  // the phase of the first entry last: the x axis is labelled on the bottom panel
    FrfFigureOptions fo;
    fo.peak_trace = 1;
    const Figure first = frf_figure({{raw[0], "input", CurveStyle::Points}, {filtered[0], "filtered", CurveStyle::Line}}, fo);
    fig.panels.push_back(first.panels[1]);
    fig.panels.back().legend = Legend::Hidden;
  }
  fig.height_px = height_for_panels(fig.panels.size());
  return fig;
}

}  // namespace

Figure filter_figure(const FrfSeries& raw, const FrfSeries& filtered, const std::string& title) {
  return filter_entries({raw}, {filtered}, {{"H", "m/N"}}, title);
}

Figure filter_figure(const BlockSeries& raw, const BlockSeries& filtered, const std::string& title) {
  std::vector<FrfSeries> a, b;
  for (int k = 0; k < 4; ++k) {
    a.push_back(entry(raw, k));
    b.push_back(entry(filtered, k));
  }
  return filter_entries(a, b, {{"H", "m/N"}, {"L", "1/N"}, {"N", "rad/N"}, {"P", "rad/(N·m)"}}, title);
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
    p.curves.push_back({x, sweep.frequency_hz[m], sweep.mode_names.empty() ? fmt::format("mode {}", m + 1) : sweep.mode_names[m],
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
                                       const std::optional<std::pair<double, double>>& band, const std::vector<double>& lines) {
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
  for (double l : lines) {
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  }
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
      require(values.size() == data.frequency_hz.size(), fmt::format("joint figure: {}_{} has {} values for {} frequencies",
                                                                     letter, jp.name, values.size(), data.frequency_hz.size()));
      const auto reference = damping ? jp.reference_damping : jp.reference_stiffness;
      const auto identified = damping ? jp.identified_damping : jp.identified_stiffness;
      const auto interval = damping ? jp.damping_interval : jp.stiffness_interval;
      const bool undetermined = damping ? jp.damping_undetermined : jp.stiffness_undetermined;
      std::vector<double> lines;
      if (reference) lines.push_back(*reference);
      if (identified) lines.push_back(*identified);
      if (interval && !undetermined) {
        lines.push_back(interval->first);
        lines.push_back(interval->second);
      }
      const auto other = damping ? jp.other_damping : jp.other_stiffness;
      if (other) lines.push_back(*other);
      // The scale comes from the values a reader looks at: the robust range, or all values.
      const auto [lo, hi] = robust_range(data.frequency_hz, values, data.band_hz, lines);
      const int exponent = data.robust_range ? engineering_exponent({lo, hi}) : engineering_exponent(values);
      const double factor = std::pow(10.0, -exponent);
      const std::string shown_unit = prefixed_unit(unit, exponent);
      Panel p;
      p.legend = Legend::Outside;
      p.y.label = fmt::format("{}_{{{}}} [{}]", letter, jp.name, shown_unit);
      p.curves.push_back(
          {data.frequency_hz, scaled(values, factor), fmt::format("{}_{{{}}}(f)", letter, jp.name), CurveStyle::Line, -1});
      if (reference)
        p.horizontal_lines.push_back({*reference * factor, fmt::format("reference {:.4g} {}", *reference * factor, shown_unit)});
      if (identified)
        p.horizontal_lines.push_back(
            {*identified * factor, fmt::format("{} {:.4g} {}{}", jp.identified_label, *identified * factor, shown_unit,
                                               undetermined ? ": UNDETERMINED by these data" : "")});
      if (other)
        p.horizontal_lines.push_back({*other * factor, fmt::format("{} {:.4g} {}", jp.other_label, *other * factor, shown_unit)});
      if (interval && !undetermined) {
        p.horizontal_lines.push_back(
            {interval->first * factor, fmt::format("95 %: {:.4g}…{:.4g}", interval->first * factor, interval->second * factor)});
        p.horizontal_lines.push_back({interval->second * factor, ""});
      }
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
    if (std::isfinite(*lo) && std::isfinite(*hi) && *lo < *hi) {
      fig.x.min = *lo;
      fig.x.max = *hi;
    }
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
      if (std::isfinite(r)) {
        rpm_lo = std::min(rpm_lo, r);
        rpm_hi = std::max(rpm_hi, r);
      }
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
  // Lobe numbers, lobe 0 first (the lowest lobes matter most); a number whose box would touch one
  // already placed is left out, so no two overlap: high lobes crowd at low speed, and lobes of
  // different modes can sit side by side at any speed. A box is about 3 % of the speed range per
  // digit wide (a 16 pt digit in a ~850 px wide panel) and 7 % of the depth axis high.
  const double x_range = fig.x.min && fig.x.max ? *fig.x.max - *fig.x.min : rpm_hi - rpm_lo;
  const double digit_width = 0.03 * x_range, line_height = 0.07 * top * 1000.0;
  std::vector<TextLabel> placed;
  for (const auto& entry : lowest) {
    const TextLabel& label = entry.second;  // a reference, not a structured binding: clang 14 cannot capture those
    const double half_width = 0.5 * digit_width * static_cast<double>(label.text.size() + 1);
    const bool overlaps = std::any_of(placed.begin(), placed.end(), [&](const TextLabel& p) {
      const double other_half = 0.5 * digit_width * static_cast<double>(p.text.size() + 1);
      return std::abs(p.x - label.x) < half_width + other_half && std::abs(p.y - label.y) < line_height;
    });
    if (overlaps) continue;
    placed.push_back(label);
  }
  depth.labels = placed;
  // The envelope last, on top of the lobes that form it.
  if (!data.envelope_rpm.empty()) depth.curves.push_back({data.envelope_rpm, env, "stability limit", CurveStyle::Line, 0});
  int series = 3;
  for (const auto& e : data.other_envelopes) {
    require(e.depth_m.size() == data.envelope_rpm.size(), fmt::format("lobes figure: envelope '{}' has {} depths for {} speeds",
                                                                      e.label, e.depth_m.size(), data.envelope_rpm.size()));
    depth.curves.push_back({data.envelope_rpm, mm_of(e.depth_m), e.label, CurveStyle::Line, series++});
  }
  fig.panels.push_back(std::move(depth));
  if (!chatter.curves.empty()) fig.panels.push_back(std::move(chatter));
  return fig;
}

Figure probability_map_figure(const ProbabilityMapData& d) {
  if (d.probability.size() != d.speed_rpm.size() * d.depth_mm.size())
    throw InvalidArgument(fmt::format("probability map: {} values for {} speeds × {} depths", d.probability.size(),
                                      d.speed_rpm.size(), d.depth_mm.size()));
  Figure fig;
  fig.title = d.title;
  fig.x.label = "Spindle speed [rpm]";
  Panel p;
  p.y.label = "Axial depth [mm]";
  Map m;
  m.x = d.speed_rpm;
  m.y = d.depth_mm;
  m.z = d.probability;
  m.colour.label = "Probability of stability";
  m.colour.min = 0.0;
  m.colour.max = 1.0;
  p.map = std::move(m);
  int series = 0;
  for (const auto& e : d.envelopes) p.curves.push_back({d.speed_rpm, e.depth_mm, e.label, CurveStyle::Line, series++});
  p.legend = Legend::TopLeft;
  fig.panels.push_back(std::move(p));
  return fig;
}

}  // namespace toolpoint::plot
