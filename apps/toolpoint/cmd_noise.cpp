// toolpoint noise: simulated measurement noise as in the seed's Section 3 — every FRF entry at
// every frequency multiplied by its own real random factor of mean 1 and standard deviation σ.
// Units: frequencies in Hz, values in the file's own units; σ dimensionless.
#include <fmt/format.h>
#include <memory>

#include "cli.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/signal.hpp"

namespace toolpoint::cli {

namespace {

struct NoiseCliOptions {
  std::string input, output;
  NoiseOptions noise;
};

void run_noise(const NoiseCliOptions& o, const Globals& g) {
  o.noise.check();
  const FrfTable in = read_frf_csv(o.input);
  const std::vector<std::string> comments = {
      fmt::format("simulated measurement noise: each entry times (1 + sigma z), z standard normal (Box-Muller on "
                  "mt19937_64), sigma = {}, seed = {}; from {}",
                  o.noise.sigma, o.noise.seed, o.input)};
  const auto distort = [&](const auto& series) {
    const auto r = add_measurement_noise(series, o.noise, o.input);
    write_frf_csv(o.output, r.series, comments);
    warn_all(r.warnings);
  };
  in.is_block ? distort(in.block) : distort(in.single);
  info(g, fmt::format("wrote {} (sigma {}, seed {})", o.output, o.noise.sigma, o.noise.seed));
}

}  // namespace

void add_noise_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<NoiseCliOptions>();
  CLI::App* c = app.add_subcommand(
      "noise", "Simulated measurement noise: multiply every FRF entry by 1 + sigma·z (seed Section 3), reproducibly");
  c->add_option("input", o->input, "Input FRF CSV (single FRF or 2×2 block; Hz and FRF units)")->required();
  c->add_option("output", o->output, "Output FRF CSV, same form and units as the input")->required();
  c->add_option("--sigma", o->noise.sigma, "Standard deviation of the factor [-] (0.05 = 5 %), ≥ 0")->capture_default_str();
  c->add_option("--seed", o->noise.seed, "Random seed (mt19937_64); the same seed gives the same noise")
      ->capture_default_str();
  c->footer(
      "Entries at every frequency get independent factors (drawn frequency by frequency, H, L, N, P).\n"
      "Example:\n"
      "  toolpoint noise SHT11.csv SHT11_noisy.csv --sigma 0.05 --seed 7");
  c->callback([o, &g] { run_noise(*o, g); });
}

}  // namespace toolpoint::cli
