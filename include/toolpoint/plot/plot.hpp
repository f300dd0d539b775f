// toolpoint: figures rendered by gnuplot (PNG, SVG, PDF).
//
// A Figure is a value: one or more panels stacked vertically and sharing one x axis. Each panel
// holds curves, horizontal reference lines, vertical marker lines, shaded x bands, filled regions
// (between a curve and a constant) and text labels. render() turns it into one gnuplot script
// (data inline as `$name << EOD` blocks, no temporary data files), runs gnuplot with the script on
// stdin, and renames the finished picture over the target: the file is written whole or not at
// all. Ready-made figures below build Figures from toolpoint's results.
//
// Units: the data are plotted as given; every axis label states its unit. The ready-made figures
// take SI inputs (Hz, m, m/N, …) and plot what people in the field read: frequency in Hz, phase in
// degrees, overhang and depth of cut in mm, spindle speed in rpm — each axis label says which.
//
// Text: every label is gnuplot "enhanced text" (k_{yf} is k with subscript yf, 10^{-6} a power);
// pass text that must appear verbatim (file names) through literal(). Strings are UTF-8.
//
// House style, the same in every format: 1000×700 px by default (SVG in px; PDF the same at
// 72 px per inch, so fonts and lines keep their proportions), DejaVu Sans 16 pt, a light grid,
// and curves told apart by dash pattern and marker shape as well as by colour (Okabe–Ito
// palette), so figures read in grayscale.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"

namespace toolpoint::plot {

// gnuplot could not be run at all (not installed, not executable) or lacks every terminal able
// to write the requested format. Callers can catch it apart from other IoErrors, write their
// data anyway and say so.
class PlotUnavailable : public IoError {
 public:
  using IoError::IoError;
};

// ---- Figure description ------------------------------------------------------------------------

enum class Format { Png, Svg, Pdf };

// The format from the file name's extension (.png, .svg, .pdf; any case). Throws
// InvalidArgument naming the path for anything else.
Format format_for_path(const std::string& path);

enum class Scale { Linear, Log };

struct Axis {
  std::string label;  // with its unit, e.g. "Frequency [Hz]"
  Scale scale = Scale::Linear;
  std::optional<double> min, max;  // unset: autoscale
  std::optional<double> tic_step;  // major tic spacing (linear axes), e.g. 90 for phase in degrees
};

// How a curve is drawn. Line: solid for the panel's first series, then dashed, dotted, dash-dot,
// …, with a few markers along the line from the second series on. Dashed: always dashed.
// Points: markers only. LinePoints: the series' line with a marker at every point.
enum class CurveStyle { Line, Dashed, Points, LinePoints };

struct Curve {
  std::vector<double> x, y;  // equal length; a non-finite value (or ≤ 0 on a log axis) breaks the line
  std::string label;         // legend text; empty: not in the legend
  CurveStyle style = CurveStyle::Line;
  int series = -1;  // house style index (colour, dash, marker); −1: next in the panel
};

// A constant y across the panel, drawn and listed in the legend like a curve (its style is the
// next series after the curves).
struct HorizontalLine {
  double y = 0.0;
  std::string label;
};

// A vertical line at x, labelled beside its top end.
struct VerticalLine {
  double x = 0.0;
  std::string label;
};

// An x interval shaded over the panel's full height (an identification band), in the legend.
struct Band {
  double from = 0.0, to = 0.0;
  std::string label;
};

// The region between a curve and y = base, filled (the stable region under a lobe envelope).
// Drawn behind the curves and listed in the legend. base must be > 0 on a log y axis.
struct Fill {
  std::vector<double> x, y;
  double base = 0.0;
  std::string label;
};

// Text at a data point (a mode's frequency at its peak, a lobe number), centred just above the
// point, with a small marker on the point itself when `marker`. Drawn in the panel's order, each
// only where it overlaps no label drawn before it and no legend, inside the frame (an autoscaled
// y axis makes room above for them; at a side edge a label is set against its point).
struct TextLabel {
  double x = 0.0, y = 0.0;
  std::string text;
  bool marker = true;
};

// A colour map (heat map) of z over a regular grid: the cell centred on (x[i], y[j]) is coloured by
// z[j·x.size() + i], drawn behind the panel's other items (curves, labels and lines go on top), with
// a colour bar right of the panel labelled with `colour.label` (its unit included). The palette is
// viridis: perceptually uniform and rising in lightness, so it also reads in greyscale. Cells whose
// z is not finite (or ≤ 0 on a log colour scale) are left blank. Used for a stable depth over
// overhang × spindle speed and a probability of stability over spindle speed × depth.
struct ColourBar {
  std::string label;  // with its unit, e.g. "Stable depth [mm]"
  Scale scale = Scale::Linear;
  // Unset: the finite data's range. Values beyond are drawn in the end colours, and the end's tic
  // label says so ("≥ 3.5", "≤ 0.1").
  std::optional<double> min, max;
};

struct Map {
  std::vector<double> x, y;  // cell centres, increasing and evenly spaced (to 1e-6 of the step); ≥ 1 each
  std::vector<double> z;     // x.size() × y.size() values, x fastest
  ColourBar colour;
};

// Where the legend goes. Inside the panel it has an opaque box; Outside puts it in a column to
// the right of the panels (all panels narrow alike, so their x axes stay aligned), for panels
// whose data fill the whole frame. Auto (the default): the first corner — top right, top left,
// bottom right, bottom left — where the box covers none of the panel's data, lines or labels, as
// drawn; else Outside. A panel without labelled items shows no legend.
enum class Legend { Auto, TopRight, TopLeft, BottomRight, BottomLeft, Outside, Hidden };

struct Panel {
  Axis y;
  std::vector<Curve> curves;
  std::vector<HorizontalLine> horizontal_lines;
  std::vector<VerticalLine> vertical_lines;
  std::vector<Band> bands;
  std::vector<Fill> fills;
  std::vector<TextLabel> labels;
  std::optional<Map> map;  // drawn first, under everything else
  Legend legend = Legend::Auto;
  double height = 1.0;  // share of the plotting height relative to the other panels, > 0
};

struct Figure {
  std::string title;  // above the top panel; may be empty
  Axis x;             // shared by all panels; tic labels and label on the bottom panel only
  std::vector<Panel> panels;
  int width_px = 1000, height_px = 700;

  // Throws InvalidArgument: no panels, a size outside 200…20000 px, x and y of different
  // lengths, a panel with nothing to draw, non-finite or inverted ranges, a non-positive limit or
  // fill base on a log axis, a non-positive panel height, a map whose grid is uneven or whose z
  // has the wrong size.
  void check() const;
};

// Escapes gnuplot enhanced-text markup (_ ^ @ & ~ { } \) so `text` prints verbatim.
std::string literal(std::string_view text);

// ---- Rendering ---------------------------------------------------------------------------------

struct PlotOptions {
  std::string gnuplot = "gnuplot";  // program: a path, or a name looked up on PATH
  double timeout_s = 60.0;          // gnuplot is killed after this many seconds, > 0
  void check() const;               // throws InvalidArgument naming `PlotOptions::<field>`
};

/// \brief PlotOptions' scalar field defined once (option_fields.hpp): check() derives from this
/// table (the program, a string, is checked beside it).
/// \return the table
const std::vector<OptionField<PlotOptions>>& plot_fields();

struct RenderResult {
  std::string path;
  Format format = Format::Png;
  std::string terminal;               // the gnuplot terminal used (pngcairo, png, svg, pdfcairo)
  std::vector<std::string> notes;     // e.g. a terminal fallback
  std::vector<std::string> warnings;  // what gnuplot printed on stderr although it succeeded
};

// The gnuplot commands that draw `figure`, data inline; no terminal or output lines.
std::string gnuplot_script(const Figure& figure);

// Renders `figure` to `path` in the format its extension names, through gnuplot.
//   .png: pngcairo; without it the libgd png terminal (noted in the result).
//   .svg: svg (built into every gnuplot).
//   .pdf: pdfcairo; without it PlotUnavailable.
// Missing parent folders are created. gnuplot draws into a hidden temporary file beside `path`
// which is renamed over `path` only when gnuplot succeeded, so `path` is never half-written.
// Throws InvalidArgument (bad figure, bad extension), PlotUnavailable (gnuplot cannot be run or
// lacks a terminal for the format), IoError (gnuplot failed: its message is in what(); timeout;
// the folder is not writable).
RenderResult render(const Figure& figure, const std::string& path, const PlotOptions& options = {});

// The same for a hand-written gnuplot script `body` (no terminal or output lines): the terminal
// for `path`'s format at width×height px is set before it, and the output is closed after it.
RenderResult render_script(const std::string& body, const std::string& path, int width_px, int height_px,
                           const PlotOptions& options = {});

// ---- Ready-made figures -------------------------------------------------------------------------

// Indices of the most prominent local maxima of `values` (at most `max_peaks`, in index order).
// Prominence is measured as a ratio, as read on a log axis: a peak's value divided by the higher
// of the lowest values between it and the nearest higher point on either side (or the end of the
// data). Peaks with a ratio below `min_ratio` (> 1) are dropped; plateaus count once.
std::vector<std::size_t> peak_indices(const std::vector<double>& values, int max_peaks, double min_ratio);

// One FRF drawn in an FRF figure.
struct FrfTrace {
  FrfSeries frf;
  std::string label;  // legend text: "measured", "filtered", "predicted", …
  CurveStyle style = CurveStyle::Line;
};

enum class FrfView {
  MagnitudePhase,  // |X| on a log axis over phase ∠X in degrees, (−180°, 180°]
  RealImaginary,   // Re X over Im X, linear
};

struct FrfFigureOptions {
  FrfView view = FrfView::MagnitudePhase;
  std::string title;
  std::string symbol = "H";  // enhanced text for the FRF in axis labels: "H_{11}", "P^{sht}_{11}"
  std::string unit = "m/N";  // the FRF's unit
  Scale frequency_scale = Scale::Linear;
  std::optional<std::pair<double, double>> frequency_range_hz;
  int mode_labels = 0;  // label up to this many peaks (frequency in Hz) of trace `peak_trace`,
                        // sought within frequency_range_hz when given
  std::size_t peak_trace = 0;
  double min_peak_ratio = 2.0;  // see peak_indices(); 2 = 6 dB above the surrounding valleys
  void check() const;           // throws InvalidArgument naming `FrfFigureOptions::<field>`
};

/// \brief FrfFigureOptions' scalar fields defined once (option_fields.hpp): check() derives from
/// this table (mode_labels, min_peak_ratio; the frequency range, a pair, is checked beside it, and
/// peak_trace, an index, against the traces drawn).
/// \return the table, in the order of the fields
const std::vector<OptionField<FrfFigureOptions>>& frf_figure_fields();

// Two panels (magnitude and phase, or real and imaginary) over frequency [Hz], every trace
// overlaid, the legend in the upper panel. Mode labels: text at the peaks of |X|, or (real and
// imaginary view) labelled vertical lines. Re and Im are plotted with an SI prefix or power of
// ten on the unit (µm/N) so tic labels stay short. Throws InvalidArgument (no traces, bad options) and
// InputError (a trace that fails validate()).
Figure frf_figure(const std::vector<FrfTrace>& traces, const FrfFigureOptions& options = {});

// A receptance block series as four panels: |H| [m/N], ∠H, |P| [rad/(N·m)], ∠P, with the first
// `mode_labels` peaks of |H| labelled. `subscript` (enhanced text, e.g. "11") goes on H and P.
// L and N (equal for a point receptance) are left out: their magnitudes sit between H's and P's.
Figure receptance_figure(const BlockSeries& series, const std::string& title, const std::string& subscript = "",
                         int mode_labels = 6);

// All four entries of a receptance block series (a tip block from finite differences, a converted
// block file): |H| [m/N] with the first `mode_labels` peaks labelled, |L| and |N| overlaid
// [1/N = rad/N] (equal for a point receptance, by reciprocity), |P| [rad/(N·m)], and the four
// phases [deg] overlaid, all on log magnitude axes against frequency [Hz]. `subscript` (enhanced
// text, e.g. "11") goes on every symbol. Throws InputError for an invalid series.
Figure block_figure(const BlockSeries& series, const std::string& title, const std::string& subscript = "", int mode_labels = 6);

// What a filter (Savitzky–Golay smoothing) did: the input's magnitude as points and the filtered
// one as a line over frequency [Hz], one panel per entry — H [m/N] of a single FRF, or H [m/N],
// L [1/N], N [rad/N], P [rad/(N·m)] of a block — with up to 6 peaks of the filtered H labelled,
// and the phase of H [deg] last. Throws InputError for an invalid series.
Figure filter_figure(const FrfSeries& raw, const FrfSeries& filtered, const std::string& title);
Figure filter_figure(const BlockSeries& raw, const BlockSeries& filtered, const std::string& title);

// Tool point FRFs for several tool overhangs overlaid (the seed's Fig. 10): trace i is labelled
// "overhang <overhang_m[i] in mm> mm". `options.mode_labels` applies to options.peak_trace.
Figure overhang_frf_figure(const std::vector<double>& overhang_m, const std::vector<FrfSeries>& frfs,
                           const FrfFigureOptions& options = {});

// Natural frequencies against tool overhang, one curve per mode.
struct OverhangSweep {
  std::vector<double> overhang_m;                 // x, in m (plotted in mm)
  std::vector<std::vector<double>> frequency_hz;  // [mode][overhang index], Hz; NaN: not found
  std::vector<std::string> mode_names;            // legend per mode; empty: "mode 1", "mode 2", …
  std::string title;
};
Figure natural_frequency_figure(const OverhangSweep& sweep);

// Identified joint parameters k(ω), c(ω) (the seed's Fig. 3, 5, 11–13). One parameter is one
// entry of K(ω) = k + iωc; `name` is its subscript, e.g. "yf" → panels "k_{yf}", "c_{yf}".
struct JointParameterCurve {
  std::string name;
  std::string stiffness_unit;                                      // e.g. "N/m"
  std::string damping_unit;                                        // e.g. "N·s/m"
  std::vector<double> stiffness;                                   // per frequency; empty: no stiffness panel
  std::vector<double> damping;                                     // per frequency; empty: no damping panel
  std::optional<double> reference_stiffness, reference_damping;    // drawn as horizontal lines
  std::optional<double> identified_stiffness, identified_damping;  // ditto
  // The identified values' intervals (drawn as two lines when the value is determined) and whether
  // the data leave the value undetermined (then said in its label, and no interval drawn: it
  // would dwarf the curve).
  std::optional<std::pair<double, double>> stiffness_interval, damping_interval;
  bool stiffness_undetermined = false, damping_undetermined = false;
  // A second identified value to compare with (the seed's read-out beside a band fit).
  std::optional<double> other_stiffness, other_damping;
  std::string other_label = "seed read-out";
  std::string identified_label = "identified";
};

struct JointFigureData {
  std::vector<double> frequency_hz;
  std::vector<JointParameterCurve> parameters;
  std::optional<std::pair<double, double>> band_hz;  // the band the values were read from, shaded
  std::string title;
  // Identified k(ω), c(ω) spike by orders of magnitude where the inversion is ill-conditioned;
  // with robust_range the y range spans the 2nd–98th percentile of the values (within the band
  // when given) and the reference lines, widened by half, and spikes run off the panel.
  bool robust_range = true;
};

// Stiffness panels for every parameter, then damping panels, sharing the frequency axis [Hz],
// legends outside on the right. Each panel's values carry an SI prefix or power of ten on the
// unit (MN/m) so tic labels stay short. The figure grows taller beyond two panels. Throws
// InvalidArgument on mismatched lengths.
Figure joint_figure(const JointFigureData& data);

// Stability lobes (zero-order or semi-discretization): depth of cut against spindle speed.
struct Lobe {
  int number = 0;                            // lobe index k, printed at the lobe's lowest point
  std::vector<double> spindle_speed_rpm;     // rpm
  std::vector<double> depth_m;               // axial depth of cut limit, m (plotted in mm)
  std::vector<double> chatter_frequency_hz;  // Hz, same length; empty: not drawn
};

struct LobesFigureData {
  std::vector<Lobe> lobes;
  std::vector<double> envelope_rpm;      // the lower envelope of all lobes: the stability limit
  std::vector<double> envelope_depth_m;  // m
  std::string title;
  std::optional<double> depth_max_m;  // top of the depth axis; default: 5× the envelope's minimum
  // Other envelopes over envelope_rpm (the quantiles of the stable depth when a joint is
  // uncertain), drawn as lines in the house style's next colours, in the legend.
  struct Envelope {
    std::vector<double> depth_m;
    std::string label;
  };
  std::vector<Envelope> other_envelopes;
};

// Two panels: depth [mm] against spindle speed [rpm] with the stable region under the envelope
// shaded and lobe numbers, and chatter frequency [Hz] against spindle speed (when given). The
// speed axis spans the envelope; legends sit outside on the right.
Figure lobes_figure(const LobesFigureData& data);

// The probability that a cut is stable over spindle speed [rpm] × axial depth [mm], as a colour
// map from 0 to 1, with depth curves on top (the nominal envelope, the depth stable with 95 %
// probability). The grid must be regular (Map's rule): the envelope's speeds and the map's depths.
struct ProbabilityMapData {
  std::string title;
  std::vector<double> speed_rpm, depth_mm;  // increasing, evenly spaced
  std::vector<double> probability;          // speed_rpm.size() × depth_mm.size(), speed fastest, in [0, 1]
  struct Envelope {
    std::vector<double> depth_mm;  // per speed
    std::string label;
  };
  std::vector<Envelope> envelopes;
};
Figure probability_map_figure(const ProbabilityMapData& data);

}  // namespace toolpoint::plot
