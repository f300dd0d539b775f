// toolpoint filter: Savitzky–Golay smoothing of a measured FRF or 2×2 block (seed Section 4).
// Units: frequencies in Hz, values in the file's own units (unchanged; receptance m/N for UFF
// inputs after conversion); the window counts frequency points. --plot overlays the input and
// the filtered FRF (H of a block).
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <memory>

#include "cli.hpp"
#include "toolpoint/signal.hpp"

namespace toolpoint::cli {

namespace {

struct FilterOptions {
  std::string input, output, plot;
  std::optional<std::size_t> dataset;
  SavgolOptions savgol;
};

// Every entry of a block (H, L, N, P) or the single FRF: |input| as points, |filtered| as a line,
// one magnitude panel per entry, the phase of the first below.
plot::Figure filter_figure(const FrfFileData& in, const FrfFileData& out, const std::string& title) {
  static const char* symbols[4] = {"H", "L", "N", "P"};
  static const char* units[4] = {"m/N", "1/N", "rad/N", "rad/(N·m)"};
  const int entries = in.is_block ? 4 : 1;
  plot::Figure fig;
  for (int k = 0; k < entries; ++k) {
    plot::FrfFigureOptions fo;
    fo.title = title;
    fo.mode_labels = k == 0 ? 6 : 0;
    fo.peak_trace = 1;  // the filtered trace: noise makes spurious peaks on the input
    fo.symbol = in.is_block ? symbols[k] : "H";
    fo.unit = in.is_block ? units[k] : "m/N";
    const FrfSeries a = in.is_block ? entry(in.block, k) : in.single, b = out.is_block ? entry(out.block, k) : out.single;
    plot::Figure one = plot::frf_figure({{a, "input", plot::CurveStyle::Points}, {b, "filtered", plot::CurveStyle::Line}}, fo);
    if (k == 0) {
      fig = one;
      if (entries > 1) fig.panels.resize(1);
    } else {
      fig.panels.push_back(one.panels[0]);
      fig.panels.back().legend = plot::Legend::Hidden;  // the first panel's legend says it for all
    }
    if (k == entries - 1 && entries > 1) {  // the phase of H last: the x axis is labelled on the bottom panel
      plot::FrfFigureOptions fo0;
      fo0.peak_trace = 1;
      plot::Figure h = plot::frf_figure({{entry(in.block, 0), "input", plot::CurveStyle::Points},
                                         {entry(out.block, 0), "filtered", plot::CurveStyle::Line}},
                                        fo0);
      fig.panels.push_back(h.panels[1]);
      fig.panels.back().legend = plot::Legend::Hidden;
    }
  }
  fig.height_px = 700 + 170 * static_cast<int>(fig.panels.size() - 2);  // the house size: 170 px per panel beyond two
  return fig;
}

void run_filter(const FilterOptions& o, const Globals& g) {
  o.savgol.check();
  const std::string comment = fmt::format(
      "Savitzky-Golay filtered (window {} points, order {}, scipy savgol_filter mode='interp'; real and "
      "imaginary parts separately) from {}",
      o.savgol.window, o.savgol.order, o.input);
  const auto [in, out] = process_frf_file(g, o.input, o.dataset, o.output, o.plot, comment, [&](const auto& series) {
    check_smoothing_window(o.savgol, series.size(), o.input);
    return savgol_filter(series, o.savgol, o.input);
  });
  double gain = 0.0;  // Σc²: white noise variance after / before, interior points
  for (double c : savgol_coefficients(o.savgol)) gain += c * c;
  info(g, fmt::format("wrote {} ({}, {} points filtered; interior white-noise variance × {:.4g})", o.output,
                      in.is_block ? "2×2 block" : "single FRF", in.is_block ? in.block.size() : in.single.size(), gain));
  // What the filter did to the peaks, against the raw data.
  const PeakChangeReport peaks = in.is_block ? peak_changes(in.block, out.block, o.savgol.window, {}, o.input)
                                             : peak_changes(in.single, out.single, o.savgol.window, {}, o.input);
  std::cout << fmt::format("peaks of {} before and after filtering (window {} points, order {}):\n", o.input, o.savgol.window,
                           o.savgol.order);
  std::cout << "  entry  raw_hz      raw_magnitude  filtered_hz  filtered_magnitude  height_%  frequency_%  noise_%\n";
  for (const PeakChange& c : peaks.peaks) {
    const bool gone = std::isnan(c.filtered_frequency_hz);  // smoothed away: no filtered peak near it
    std::cout << fmt::format("  {:5}  {:10.6g}  {:13.6g}  {:>11}  {:18.6g}  {:+8.2f}  {:>11}  {:7.2f}\n",
                             c.entry.empty() ? "-" : c.entry, c.raw_frequency_hz, c.raw_magnitude,
                             gone ? std::string("gone") : fmt::format("{:.6g}", c.filtered_frequency_hz), c.filtered_magnitude,
                             100.0 * c.height_change, gone ? std::string("-") : fmt::format("{:+.3f}", 100.0 * c.frequency_change),
                             100.0 * c.noise);
  }
  if (peaks.peaks.empty()) std::cout << "  (no prominent peak)\n";
  std::cout << "  (noise_%: the raw data's magnitude noise σ at the peak, estimated from the data; a peak must rise 8σ above "
               "its valleys to be listed)\n";
  warn_all(peaks.warnings);
  if (o.plot.empty()) return;
  const std::string title = fmt::format("Savitzky–Golay filter, window {} points, order {}: {}", o.savgol.window, o.savgol.order,
                                        plot::literal(o.input));
  draw_figures(g, {{filter_figure(in, out, title), o.plot}}, {o.output});
}

}  // namespace

void add_filter_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<FilterOptions>();
  CLI::App* c = app.add_subcommand(
      "filter", "Savitzky–Golay smoothing of an FRF (single FRF or 2×2 block, real and imaginary parts separately)");
  add_frf_file_arguments(c, g, o->input, o->output, o->dataset, "every entry filtered");
  c->add_option("-w,--window", o->savgol.window,
                "Window length [frequency points]: odd, > --order, ≤ the number of points (required, no default)")
      ->required();
  c->add_option("-p,--order", o->savgol.order, "Polynomial order [-], ≥ 0 and < --window (required, no default)")->required();
  add_plot_option(c, o->plot,
                  "the input (points) and the filtered FRF (line), |H| [m/N] and phase [deg] against frequency [Hz]; a "
                  "block: |H|, |L|, |N|, |P| and the phase of H");
  c->footer(std::string(kFigureFooter) +
            "Matches scipy.signal.savgol_filter(x, window, order, mode='interp'): interior points by the\n"
            "least-squares convolution weights, the first/last window/2 points from the polynomial fitted\n"
            "to the first/last window samples. Assumes evenly spaced frequencies (warns otherwise).\n"
            "The window may be at most a quarter of the points. Printed: each prominent peak of each entry\n"
            "(H, L, N, P of a block) before and after, its height and frequency change in %; a change above\n"
            "2 % is a warning (the window flattens the peak: shorten it).\n"
            "Example:\n"
            "  toolpoint filter measured_H11.csv smoothed_H11.csv --window 11 --order 3 --plot smoothed.png");
  c->callback([o, &g] { run_filter(*o, g); });
}

}  // namespace toolpoint::cli
