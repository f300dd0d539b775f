// toolpoint taptest: a virtual impact test on the model — the translational FRFs at the tip and at
// points s, 2s inwards, written as UFF dataset 58 the way measurement software exports them. For
// planning the spacing of a real test, and for trying the measured-data workflow without a machine.
#include <fmt/format.h>
#include <iostream>
#include <limits>
#include <memory>

#include "cli.hpp"
#include "toolpoint/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/frf_file.hpp"
#include "toolpoint/signal.hpp"
#include "toolpoint/uff.hpp"

namespace toolpoint::cli {

namespace {

struct TapTestOptions {
  std::string assembly, at = "tool", hammer = "roving", frequencies, output;
  std::vector<std::string> joints;
  double spacing = 0.0, sigma = 0.0;
  int points = 3;
  std::uint64_t seed = 1;
  bool binary = false;
};

void run_taptest(const TapTestOptions& o, const Globals& g) {
  if (!(o.spacing > 0.0)) throw InvalidArgument(fmt::format("--spacing {} m must be > 0", o.spacing), "e.g. --spacing 0.01 for 10 mm");
  const LoadedModel lm = load_model(g, o.assembly, o.frequencies, read_joint_options(g, o.joints));
  const LoadedAssembly& loaded = lm.loaded;
  const AssemblyModel& model = lm.model;
  const bool tool = o.at == "tool";
  std::vector<double> x;
  for (int i = 0; i < o.points; ++i) x.push_back(i * o.spacing);
  const std::vector<double> f = loaded.assembly.grid.values();
  // One factorisation per frequency gives every H_ij.
  std::vector<std::vector<FrfSeries>> h(static_cast<std::size_t>(o.points), std::vector<FrfSeries>(static_cast<std::size_t>(o.points)));
  for (auto& row : h)
    for (auto& s : row) s.frequency_hz = f;
  for (double fi : f) {
    const Eigen::MatrixXcd G = tool ? model.tool_stations(fi, x) : model.holder_stations(fi, x);
    for (int i = 0; i < o.points; ++i)
      for (int j = 0; j < o.points; ++j) h[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)].values.push_back(G(2 * i, 2 * j));
  }
  std::vector<UffDataset58> sets;
  std::vector<std::string> warnings;
  int k = 0;
  for (int j = 0; j < o.points; ++j) {  // hammer position
    if (o.hammer == "tip" && j > 0) break;
    for (int i = 0; i < o.points; ++i, ++k) {
      FrfSeries s = h[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      if (o.sigma > 0.0) {
        auto noisy = add_measurement_noise(s, NoiseOptions{o.sigma, o.seed + static_cast<std::uint64_t>(k)}, fmt::format("H{}{}", i, j));
        s = std::move(noisy.series);
        warnings.insert(warnings.end(), noisy.warnings.begin(), noisy.warnings.end());
      }
      sets.push_back(uff_from_receptance(
          s, UffDof{i + 1, 2, j + 1, 2},
          fmt::format("toolpoint taptest H{}{}: {} point {} ({} mm in), hammer at point {}", i, j, tool ? "tool" : "holder", i,
                      1000 * x[static_cast<std::size_t>(i)], j)));
    }
  }
  UffWriteOptions wo;
  wo.binary = o.binary;
  const auto w = write_uff(o.output, sets, wo);
  warn_all(warnings);
  warn_all(w);
  std::cout << fmt::format("virtual tap test on the {} of {}: {} FRFs (receptance, m/N), {} frequencies {:g}–{:g} Hz{}\n",
                           tool ? "tool (full assembly)" : "holder (tool outside removed)", o.assembly, sets.size(), f.size(),
                           f.front(), f.back(), o.sigma > 0.0 ? fmt::format(", {:g} % noise", 100 * o.sigma) : "");
  std::cout << "points: ";
  for (int i = 0; i < o.points; ++i) std::cout << fmt::format("{}node {} at {:g} mm from the tip", i ? "; " : "", i + 1, 1000 * x[static_cast<std::size_t>(i)]);
  std::cout << fmt::format("\nUFF datasets: response node i+1, reference (hammer) node j+1, direction +Y; wrote {}\n", o.output);
  // The section under the points: what `rotational --shear-stiffness` needs to turn dw/dx into ψ.
  const Chain& chain = tool ? model.tool_chain() : model.holder_chain();
  const auto [under, rest] = split_segments(chain.segments(), x.back());
  double kga = std::numeric_limits<double>::infinity();
  for (const Segment& sg : under) kga = std::min(kga, sg.properties().kGA.real());
  std::cout << fmt::format("shear stiffness κGA under the points: {:.4g} N{} (give it to `toolpoint rotational --shear-stiffness`)\n", kga,
                           under.size() > 1 ? " (smallest of the sections spanned: the points cross a step)" : "");
  (void)g;
}

}  // namespace

void add_taptest_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<TapTestOptions>();
  CLI::App* c = app.add_subcommand("taptest", "Virtual impact test on the model: translational FRFs at the tip and s, 2s inwards, as UFF 58");
  c->add_option("assembly", o->assembly, "Assembly file (TOML)")->required()->check(CLI::ExistingFile);
  c->add_option("--at", o->at, "tool: on the tool of the whole assembly (for SHT11); holder: on the holder, tool outside removed (for SH11)")
      ->check(CLI::IsMember({"tool", "holder"}))
      ->capture_default_str();
  c->add_option("--spacing", o->spacing, "Distance s between neighbouring points [m]")->required();
  c->add_option("--points", o->points, "Measurement points: 2 (first-order differences) or 3 (second order)")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  c->add_option("--hammer", o->hammer, "roving: the hammer at every point (all H_ij, for P by cross terms); tip: only at the tip (H_i0)")
      ->check(CLI::IsMember({"roving", "tip"}))
      ->capture_default_str();
  c->add_option("--sigma", o->sigma, "Multiplicative noise on each FRF, standard deviation (0.02 = 2 %; default 0: exact)")->capture_default_str();
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
