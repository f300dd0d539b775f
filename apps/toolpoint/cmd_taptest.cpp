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
  // --spacing, --points, --sigma, --floor, --averages, --calibration: from their definitions
  // (tap_test_fields).
  FieldFlags<TapTestOptions> fields;
  std::uint64_t seed = 1;
  FieldFlags<UffWriteOptions> write;  // --binary (uff_write_fields)
};

void run_taptest(const TapTestArgs& o, const Globals& g) {
  {
    std::vector<RunPath> inputs = joint_paths(o.joints);
    inputs.push_back({o.assembly, "assembly file"});
    check_paths(inputs, {{o.output, "--output"}});
  }
  check_output_extension(o.output, "--output", {".uff", ".unv", ".uf"}, "universal file datasets 58 (.uff, .unv or .uf)");
  TapTestOptions options;
  options.side = o.at == "tool" ? TapSide::Tool : TapSide::Holder;
  options.hammer = o.hammer == "tip" ? HammerPlan::Tip : HammerPlan::Roving;
  options.seed = o.seed;
  o.fields.apply(options);  // the flags refused before the assembly is read
  const LoadedAssembly loaded = load_assembly_on_grid(g, o.assembly, o.frequencies, read_joint_options(g, o.joints));
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
                                               options.averages)));
  UffWriteOptions wo;
  o.write.apply(wo);
  const auto w = write_uff(o.output, sets, wo);
  warn_all(t.warnings);
  warn_all(w);
  const std::vector<double> f = loaded.assembly.grid.values();
  std::cout << fmt::format(
      "virtual tap test on the {} of {}: {} FRFs (receptance, m/N), {} frequencies {:g}–{:g} Hz{}\n",
      tool ? "tool (full assembly)" : "holder (tool outside removed)", o.assembly, sets.size(), f.size(), f.front(), f.back(),
      options.sigma > 0.0 || options.floor > 0.0
          ? fmt::format(", {:g} % {}noise{}{}{}", 100 * options.sigma, options.averages ? "hit-to-hit " : "",
                        options.floor > 0.0 ? fmt::format(", a floor at {:g} % of each FRF's peak", 100 * options.floor) : "",
                        options.averages ? fmt::format(", {} averages (coherence written)", options.averages) : "",
                        options.calibration > 0.0 ? fmt::format(", calibration σ {:g} %", 100 * options.calibration) : "")
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
  const auto& fields = tap_test_fields();
  o->fields.add(c, option_field(fields, "spacing_m"))->required()->check(plausible_value(plausible::kPointSpacing, "--spacing"));
  o->fields.add(c, option_field(fields, "points"));
  c->add_option("--hammer", o->hammer,
                "roving: the hammer at every point (all H_ij, for P by cross terms); tip: only at the tip (H_i0)")
      ->check(CLI::IsMember({"roving", "tip"}))
      ->capture_default_str();
  o->fields.add(c, option_field(fields, "sigma"));
  o->fields.add(c, option_field(fields, "floor"))->check(plausible_value(plausible::kRelativeNoise, "--floor"));
  o->fields.add(c, option_field(fields, "averages"));
  o->fields.add_fraction(c, option_field(fields, "calibration"));
  c->add_option("--seed", o->seed, "Random seed of the noise (FRF k uses seed + k)")->capture_default_str();
  c->add_option("--frequencies", o->frequencies, "Override the file's [analysis] grid: START:STOP:STEP [Hz]");
  c->add_option("--output", o->output, "UFF file to write (.uff)")->required();
  o->write.add(c, option_field(uff_write_fields(), "binary"));
  add_joint_option(c, o->joints);
  c->footer(
      "Example:\n"
      "  toolpoint taptest examples/bt40_shrinkfit_16mm.toml --at tool --spacing 0.01 --sigma 0.02 --output tap_tool.uff");
  c->callback([o, &g] { run_taptest(*o, g); });
}

}  // namespace toolpoint::cli
