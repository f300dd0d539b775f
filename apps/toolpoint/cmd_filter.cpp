// toolpoint filter: Savitzky–Golay smoothing of a measured FRF or 2×2 block (seed Section 4).
// Units: frequencies in Hz, values in the file's own units (unchanged); the window counts
// frequency points.
#include <fmt/format.h>
#include <memory>

#include "cli.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/signal.hpp"

namespace toolpoint::cli {

namespace {

struct FilterOptions {
  std::string input, output;
  SavgolOptions savgol;
};

void run_filter(const FilterOptions& o, const Globals& g) {
  o.savgol.check();
  const FrfTable in = read_frf_csv(o.input);
  const std::vector<std::string> comments = {
      fmt::format("Savitzky-Golay filtered (window {} points, order {}, scipy savgol_filter mode='interp'; real and "
                  "imaginary parts separately) from {}",
                  o.savgol.window, o.savgol.order, o.input)};
  // The same steps for either form of the file.
  const auto filter = [&](const auto& series) {
    const auto r = savgol_filter(series, o.savgol, o.input);
    write_frf_csv(o.output, r.series, comments);
    warn_all(r.warnings);
    return series.size();
  };
  const std::size_t points = in.is_block ? filter(in.block) : filter(in.single);
  double gain = 0.0;  // Σc²: white noise variance after / before, interior points
  for (double c : savgol_coefficients(o.savgol)) gain += c * c;
  info(g, fmt::format("wrote {} ({}, {} points filtered; interior white-noise variance × {:.4g})", o.output,
                      in.is_block ? "2×2 block" : "single FRF", points, gain));
}

}  // namespace

void add_filter_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<FilterOptions>();
  CLI::App* c = app.add_subcommand(
      "filter", "Savitzky–Golay smoothing of an FRF CSV (single FRF or 2×2 block, real and imaginary parts separately)");
  c->add_option("input", o->input, "Input FRF CSV (frequency_hz,re,im or the 9-column block form; Hz and FRF units)")
      ->required();
  c->add_option("output", o->output, "Output FRF CSV, same form and units as the input")->required();
  c->add_option("-w,--window", o->savgol.window,
                "Window length [frequency points]: odd, > --order, ≤ the number of points (required, no default)")
      ->required();
  c->add_option("-p,--order", o->savgol.order, "Polynomial order [-], ≥ 0 and < --window (required, no default)")
      ->required();
  c->footer(
      "Matches scipy.signal.savgol_filter(x, window, order, mode='interp'): interior points by the\n"
      "least-squares convolution weights, the first/last window/2 points from the polynomial fitted\n"
      "to the first/last window samples. Assumes evenly spaced frequencies (warns otherwise).\n"
      "Example:\n"
      "  toolpoint filter measured_H11.csv smoothed_H11.csv --window 11 --order 3");
  c->callback([o, &g] { run_filter(*o, g); });
}

}  // namespace toolpoint::cli
