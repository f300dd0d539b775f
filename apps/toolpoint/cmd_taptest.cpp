// toolpoint taptest: a virtual impact test on the model — the translational FRFs at the tip and at
// points s, 2s inwards, written as UFF dataset 58 the way measurement software exports them. For
// planning the spacing of a real test, and for trying the measured-data workflow without a machine.
// The virtual tap test study (studies/tap_test.hpp).
#include <fmt/format.h>
#include <iostream>
#include <memory>

#include "cli.hpp"
#include "parse.hpp"
#include "progress.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/uff.hpp"

namespace toolpoint::cli {

namespace {

struct TapTestArgs {
  std::string assembly, at = "tool", hammer = "roving", frequencies, output;
  std::vector<std::string> joints;
  double spacing = 0.0, sigma = 0.0, floor = 0.0, calibration = 0.0;
  int points = 3, averages = 0;
  std::uint64_t seed = 1;
  bool binary = false;
};

void run_taptest(const TapTestArgs& o, const Globals& g) {
  {
    std::vector<RunPath> inputs = joint_paths(o.joints);
    inputs.push_back({o.assembly, "assembly file"});
    check_paths(inputs, {{o.output, "--output"}});
  }
  check_output_extension(o.output, "--output", {".uff", ".unv", ".uf"}, "universal file datasets 58 (.uff, .unv or .uf)");
  const LoadedAssembly loaded = load_assembly_on_grid(g, o.assembly, o.frequencies, read_joint_options(g, o.joints));
  TapTestOptions options;
  options.side = o.at == "tool" ? TapSide::Tool : TapSide::Holder;
  options.spacing_m = o.spacing;
  options.points = o.points;
  options.hammer = o.hammer == "tip" ? HammerPlan::Tip : HammerPlan::Roving;
  options.sigma = o.sigma;
  options.seed = o.seed;
  options.floor = o.floor;
  options.averages = o.averages;
  options.calibration = o.calibration;
  Progress progress(g, "taptest");
  TapTest t;
  t = run_tap_test_study(loaded.assembly, options, progress.part());
  progress.done();
  const bool tool = options.side == TapSide::Tool;
  std::vector<UffDataset58> sets;
  for (const TapTestFrf& r : t.frfs)
    sets.push_back(uff_from_receptance(r.frf, UffDof{r.response + 1, 2, r.hammer + 1, 2},
                                       fmt::format("toolpoint taptest H{}{}: {} point {} ({} mm in), hammer at point {}",
                                                   r.response, r.hammer, tool ? "tool" : "holder", r.response,
                                                   1000 * t.distance_m[static_cast<std::size_t>(r.response)], r.hammer)));
  for (const TapTestFrf& r : t.frfs)  // each FRF's coherence beside it, as averaging software exports it
    if (!r.coherence.empty())
      sets.push_back(uff_coherence(r.frf.frequency_hz, r.coherence, UffDof{r.response + 1, 2, r.hammer + 1, 2},
                                   fmt::format("toolpoint taptest coherence of H{}{} ({} averages)", r.response, r.hammer,
                                               o.averages)));
  UffWriteOptions wo;
  wo.binary = o.binary;
  const auto w = write_uff(o.output, sets, wo);
  warn_all(t.warnings);
  warn_all(w);
  const std::vector<double> f = loaded.assembly.grid.values();
  std::cout << fmt::format("virtual tap test on the {} of {}: {} FRFs (receptance, m/N), {} frequencies {:g}–{:g} Hz{}\n",
                           tool ? "tool (full assembly)" : "holder (tool outside removed)", o.assembly, sets.size(), f.size(),
                           f.front(), f.back(),
                           o.sigma > 0.0 || o.floor > 0.0
                               ? fmt::format(", {:g} % {}noise{}{}{}", 100 * o.sigma, o.averages ? "hit-to-hit " : "",
                                             o.floor > 0.0 ? fmt::format(", a floor at {:g} % of each FRF's peak", 100 * o.floor) : "",
                                             o.averages ? fmt::format(", {} averages (coherence written)", o.averages) : "",
                                             o.calibration > 0.0 ? fmt::format(", calibration σ {:g} %", 100 * o.calibration) : "")
                               : "");
  std::cout << "points: ";
  for (std::size_t i = 0; i < t.distance_m.size(); ++i)
    std::cout << fmt::format("{}node {} at {:g} mm from the tip", i ? "; " : "", i + 1, 1000 * t.distance_m[i]);
  std::cout << fmt::format("\nUFF datasets: response node i+1, reference (hammer) node j+1, direction +Y; wrote {}\n", o.output);
  // The section under the points: what `rotational --shear-stiffness` needs to turn dw/dx into ψ.
  std::cout << fmt::format(
      "shear stiffness κGA under the points: {:.4g} N{} (give it to `toolpoint rotational --shear-stiffness`)\n",
      t.shear_stiffness_n, t.crosses_step ? " (smallest of the sections spanned: the points cross a step)" : "");
}

}  // namespace

void add_taptest_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<TapTestArgs>();
  CLI::App* c = app.add_subcommand(
      "taptest", "Virtual impact test on the model: translational FRFs at the tip and s, 2s inwards, as UFF 58");
  c->add_option("assembly", o->assembly, "Assembly file (TOML)")->required();
  c->add_option("--at", o->at,
                "tool: on the tool of the whole assembly (for SHT11); holder: on the holder, tool outside removed (for SH11)")
      ->check(CLI::IsMember({"tool", "holder"}))
      ->capture_default_str();
  c->add_option("--spacing", o->spacing, "Distance s between neighbouring points [m]")
      ->required()
      ->check(plausible_value(plausible::kPointSpacing, "--spacing"));
  c->add_option("--points", o->points, "Measurement points: 2 (first-order differences) or 3 (second order)")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  c->add_option("--hammer", o->hammer,
                "roving: the hammer at every point (all H_ij, for P by cross terms); tip: only at the tip (H_i0)")
      ->check(CLI::IsMember({"roving", "tip"}))
      ->capture_default_str();
  c->add_option("--sigma", o->sigma, "Multiplicative noise on each FRF, standard deviation (0.02 = 2 %; default 0: exact)")
      ->capture_default_str();
  c->add_option("--floor", o->floor,
                "Additive noise floor: σ of the real and imaginary parts relative to each FRF's peak |H| [-] (0.01 = 1 %; "
                "default 0)")
      ->check(plausible_value(plausible::kRelativeNoise, "--floor"));
  c->add_option("--averages", o->averages,
                "Average this many hits per FRF (≥ 2; each hit varies by --sigma in magnitude and phase, with the floor) and "
                "write each FRF's coherence beside it (UFF function type 6); default 0: one noisy copy, no coherence")
      ->check(CLI::Range(0, 10000));
  c->add_option_function<std::string>(
      "--calibration", [o](const std::string& v) { o->calibration = parse_fraction(v, "--calibration"); },
      "σ of one calibration factor scaling every FRF of the test (one hammer, one sensor), as 2% or 0.02 (≤ 10 %)");
  c->add_option("--seed", o->seed, "Random seed of the noise (FRF k uses seed + k)")->capture_default_str();
  c->add_option("--frequencies", o->frequencies, "Override the file's [analysis] grid: START:STOP:STEP [Hz]");
  c->add_option("--output", o->output, "UFF file to write (.uff)")->required();
  c->add_flag("--binary", o->binary, "Write binary dataset 58b instead of ASCII");
  add_joint_option(c, o->joints);
  c->footer(
      "Example:\n"
      "  toolpoint taptest examples/bt40_shrinkfit_16mm.toml --at tool --spacing 0.01 --sigma 0.02 --output tap_tool.uff");
  c->callback([o, &g] { run_taptest(*o, g); });
}

}  // namespace toolpoint::cli
