// toolpoint noise: simulated measurement noise as in the seed's Section 3 — every FRF entry at
// every frequency multiplied by its own real random factor of mean 1 and standard deviation σ.
// Units: frequencies in Hz, values in the file's own units; σ dimensionless. --plot overlays the
// clean and the noisy FRF (H of a block).
#include <fmt/format.h>
#include <memory>

#include "cli.hpp"
#include "toolpoint/signal.hpp"

namespace toolpoint::cli {

namespace {

struct NoiseCliOptions {
  std::string input, output, plot;
  std::optional<std::size_t> dataset;
  NoiseOptions noise;
};

void run_noise(const NoiseCliOptions& o, const Globals& g) {
  o.noise.check();
  const std::string comment = fmt::format(
      "simulated measurement noise: each entry times (1 + sigma z), z standard normal (Box-Muller on "
      "mt19937_64), sigma = {}, seed = {}; from {}",
      o.noise.sigma, o.noise.seed, o.input);
  const auto [in, out] = process_frf_file(g, o.input, o.dataset, o.output, o.plot, comment,
                                          [&](const auto& series) { return add_measurement_noise(series, o.noise, o.input); });
  info(g, fmt::format("wrote {} (sigma {}, seed {})", o.output, o.noise.sigma, o.noise.seed));
  if (o.plot.empty()) return;
  plot::FrfFigureOptions fo;
  fo.title = fmt::format("{:g} % multiplicative noise, seed {}: {}", 100.0 * o.noise.sigma, o.noise.seed, plot::literal(o.input));
  fo.mode_labels = 6;
  fo.peak_trace = 1;  // the clean trace, drawn over the noisy points: noise makes spurious peaks
  draw_frf_overlay(g,
                   {{point_frf(out), fmt::format("{:g} % noise", 100.0 * o.noise.sigma), plot::CurveStyle::Points},
                    {point_frf(in), "clean", plot::CurveStyle::Line}},
                   fo, o.plot, o.output);
}

}  // namespace

void add_noise_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<NoiseCliOptions>();
  CLI::App* c = app.add_subcommand(
      "noise", "Simulated measurement noise: multiply every FRF entry by 1 + sigma·z (seed Section 3), reproducibly");
  add_frf_file_arguments(c, g, o->input, o->output, o->dataset, "every entry distorted");
  c->add_option("--sigma", o->noise.sigma, "Standard deviation of the factor [-] (0.05 = 5 %), ≥ 0")
      ->capture_default_str()
      ->check(plausible_value(plausible::kRelativeNoise, "--sigma"));
  c->add_option("--seed", o->noise.seed, "Random seed (mt19937_64); the same seed gives the same noise")->capture_default_str();
  add_plot_option(c, o->plot,
                  "the noisy (points) and the clean FRF (line), |H| [m/N] and phase [deg] against frequency [Hz] (the H "
                  "entry of a block)");
  c->footer(std::string(kFigureFooter) +
            "Entries at every frequency get independent factors (drawn frequency by frequency, H, L, N, P).\n"
            "Example:\n"
            "  toolpoint noise SHT11.csv SHT11_noisy.csv --sigma 0.05 --seed 7 --plot noisy.png");
  c->callback([o, &g] { run_noise(*o, g); });
}

}  // namespace toolpoint::cli
