// toolpoint noise: simulated measurement noise — the seed's Section 3 (every FRF entry at every
// frequency multiplied by its own real random factor of mean 1 and standard deviation σ), and the
// noise real tap tests have: an additive floor relative to each entry's peak, an averaged test with
// its coherence, a calibration factor (signal.hpp's NoiseOptions; noise.hpp states the models).
// Units: frequencies in Hz, values in the file's own units; σ, floor and calibration
// dimensionless. --plot overlays the clean and the noisy FRF (H of a block).
#include <fmt/format.h>
#include <memory>

#include "cli.hpp"
#include "parse.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint::cli {

namespace {

struct NoiseCliOptions {
  std::string input, output, plot;
  std::optional<std::size_t> dataset;
  NoiseOptions noise;
  // --sigma, --floor, --calibration, --averages: from their definitions (noise_fields).
  FieldFlags<NoiseOptions> fields;
};

void run_noise(NoiseCliOptions& o, const Globals& g) {
  o.fields.apply(o.noise);
  o.noise.check();
  const NoiseOptions& n = o.noise;
  std::string model =
      n.averages > 0
          ? fmt::format("{} averaged hits, each entry times (1 + sigma c), c complex circular, sigma = {}", n.averages, n.sigma)
          : fmt::format("each entry times (1 + sigma z), z standard normal (Box-Muller on mt19937_64), sigma = {}", n.sigma);
  if (n.floor > 0.0) model += fmt::format(", plus an additive floor of {} x each entry's peak on each part", n.floor);
  if (n.calibration > 0.0) model += fmt::format(", the whole series times one factor of sigma {}", n.calibration);
  if (n.averages > 0) model += "; coherence column: of the averaged H";
  const std::string comment = fmt::format("simulated measurement noise: {}; seed = {}; from {}", model, n.seed, o.input);
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
      "noise",
      "Simulated measurement noise: every FRF entry times 1 + sigma·z (seed Section 3), or a tap test's: floor, averages "
      "with coherence, calibration; reproducibly");
  add_frf_file_arguments(c, g, o->input, o->output, o->dataset, "every entry distorted");
  const auto& fields = noise_fields();
  o->fields.add(c, option_field(fields, "sigma"))->check(plausible_value(plausible::kRelativeNoise, "--sigma"));
  o->fields.add(c, option_field(fields, "floor"))->check(plausible_value(plausible::kRelativeNoise, "--floor"));
  o->fields.add(c, option_field(fields, "averages"));
  o->fields.add_fraction(c, option_field(fields, "calibration"));
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
