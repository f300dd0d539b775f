// toolpoint filter: Savitzky–Golay smoothing of a measured FRF or 2×2 block (seed Section 4).
// Units: frequencies in Hz, values in the file's own units (unchanged; receptance m/N for UFF
// inputs after conversion); the window counts frequency points. --plot overlays the input and
// the filtered FRF (H of a block).
#include <fmt/format.h>
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

void run_filter(const FilterOptions& o, const Globals& g) {
  o.savgol.check();
  const std::string comment =
      fmt::format("Savitzky-Golay filtered (window {} points, order {}, scipy savgol_filter mode='interp'; real and "
                  "imaginary parts separately) from {}",
                  o.savgol.window, o.savgol.order, o.input);
  const auto [in, out] = process_frf_file(g, o.input, o.dataset, o.output, o.plot, comment,
                                          [&](const auto& series) { return savgol_filter(series, o.savgol, o.input); });
  double gain = 0.0;  // Σc²: white noise variance after / before, interior points
  for (double c : savgol_coefficients(o.savgol)) gain += c * c;
  info(g, fmt::format("wrote {} ({}, {} points filtered; interior white-noise variance × {:.4g})", o.output,
                      in.is_block ? "2×2 block" : "single FRF", in.is_block ? in.block.size() : in.single.size(), gain));
  if (o.plot.empty()) return;
  plot::FrfFigureOptions fo;
  fo.title = fmt::format("Savitzky–Golay filter, window {} points, order {}: {}", o.savgol.window, o.savgol.order,
                         plot::literal(o.input));
  fo.mode_labels = 6;
  fo.peak_trace = 1;  // the filtered trace: noise makes spurious peaks on the input
  draw_frf_overlay(g, {{point_frf(in), "input", plot::CurveStyle::Points}, {point_frf(out), "filtered", plot::CurveStyle::Line}},
                   fo, o.plot, o.output);
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
  c->add_option("-p,--order", o->savgol.order, "Polynomial order [-], ≥ 0 and < --window (required, no default)")
      ->required();
  add_plot_option(c, o->plot,
                  "the input (points) and the filtered FRF (line), |H| [m/N] and phase [deg] against frequency [Hz] "
                  "(the H entry of a block)");
  c->footer(std::string(kFigureFooter) +
            "Matches scipy.signal.savgol_filter(x, window, order, mode='interp'): interior points by the\n"
            "least-squares convolution weights, the first/last window/2 points from the polynomial fitted\n"
            "to the first/last window samples. Assumes evenly spaced frequencies (warns otherwise).\n"
            "Example:\n"
            "  toolpoint filter measured_H11.csv smoothed_H11.csv --window 11 --order 3 --plot smoothed.png");
  c->callback([o, &g] { run_filter(*o, g); });
}

}  // namespace toolpoint::cli
