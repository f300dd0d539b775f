// toolpoint filter: Savitzky–Golay smoothing of a measured FRF or 2×2 block (seed Section 4).
// Units: frequencies in Hz, values in the file's own units (unchanged; receptance m/N for UFF
// inputs after conversion); the window counts frequency points. --plot overlays the input and
// the filtered FRF (H of a block).
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <type_traits>

#include "cli.hpp"
#include "toolpoint/studies/filter.hpp"

namespace toolpoint::cli {

namespace {

struct FilterOptions {
  std::string input, output, plot;
  std::optional<std::size_t> dataset;
  SavgolOptions savgol;
};

void run_filter(const FilterOptions& o, const Globals& g) {
  const FilterStudyOptions fo{o.savgol, {}};
  fo.check();  // before reading the file
  const std::string comment = fmt::format(
      "Savitzky-Golay filtered (window {} points, order {}, scipy savgol_filter mode='interp'; real and "
      "imaginary parts separately) from {}",
      o.savgol.window, o.savgol.order, o.input);
  double gain = 0.0;
  PeakChangeReport peaks;  // what the filter did to the peaks, against the raw data
  const auto [in, out] = process_frf_file(g, o.input, o.dataset, o.output, o.plot, comment, [&](const auto& series) {
    auto r = run_filter_study(series, fo, o.input);
    gain = r.noise_gain;
    peaks = std::move(r.peaks);
    return SignalResult<std::decay_t<decltype(series)>>{std::move(r.filtered), std::move(r.warnings)};
  });
  info(g, fmt::format("wrote {} ({}, {} points filtered; interior white-noise variance × {:.4g})", o.output,
                      in.is_block ? "2×2 block" : "single FRF", in.is_block ? in.block.size() : in.single.size(), gain));
  std::cout << fmt::format("peaks of {} before and after filtering (window {} points, order {}):\n", o.input, o.savgol.window,
                           o.savgol.order);
  std::cout << "  entry  raw_hz      raw_magnitude  filtered_hz  filtered_magnitude  height_%  frequency_%  noise_%\n";
  for (const PeakChange& c : peaks.peaks) {
    const bool gone = std::isnan(c.filtered_frequency_hz);  // smoothed away: no filtered peak near it
    std::cout << fmt::format("  {:5}  {:10.6g}  {:13.6g}  {:>11}  {:18.6g}  {:+8.2f}  {:>11}  {:7.2f}\n",
                             c.entry.empty() ? "-" : c.entry, c.raw_frequency_hz, c.raw_magnitude,
                             gone ? std::string("gone") : fmt::format("{:.6g}", c.filtered_frequency_hz), c.filtered_magnitude,
                             100.0 * c.height_change,
                             gone ? std::string("-") : fmt::format("{:+.3f}", 100.0 * c.frequency_change), 100.0 * c.noise);
  }
  if (peaks.peaks.empty()) std::cout << "  (no prominent peak)\n";
  std::cout << "  (noise_%: the raw data's magnitude noise σ at the peak, estimated from the data; a peak must rise 8σ above "
               "its valleys to be listed)\n";
  if (o.plot.empty()) return;
  const std::string title = fmt::format("Savitzky–Golay filter, window {} points, order {}: {}", o.savgol.window, o.savgol.order,
                                        plot::literal(o.input));
  draw_figures(g,
               {{in.is_block ? plot::filter_figure(in.block, out.block, title)
                             : plot::filter_figure(in.single, out.single, title),
                 o.plot}},
               {o.output});
}

}  // namespace

void add_filter_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<FilterOptions>();
  CLI::App* c = app.add_subcommand(
      "filter", "Savitzky–Golay smoothing of an FRF (single FRF or 2×2 block, real and imaginary parts separately)");
  add_frf_file_arguments(c, g, o->input, o->output, o->dataset, "every entry filtered");
  // From savgol_fields(), by hand for their short names -w, -p; required, so no default shown.
  const FieldSpec& window = option_field(savgol_fields(), "window").spec;
  const FieldSpec& order = option_field(savgol_fields(), "order").spec;
  c->add_option("-w," + field_flag(window), o->savgol.window,
                field_help(window) + ", ≤ a quarter of the points (required, no default)")
      ->required();
  c->add_option("-p," + field_flag(order), o->savgol.order, field_help(order) + " (required, no default)")->required();
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
