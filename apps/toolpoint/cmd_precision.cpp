// toolpoint precision: how tight will the joint be, before the tap test — the expected 95 %
// half-width of each joint parameter for this assembly, these tap tests and this noise, and the
// averages a target width needs. Thin: options → run_precision_study (studies/precision.hpp) → report.
// Units: SI (joint parameters as joint.hpp); the spacing in m; σ, floor, calibration and the target
// as fractions or percentages (said in the help).
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "parse.hpp"
#include "progress.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/precision.hpp"

namespace toolpoint::cli {

namespace {

struct PrecisionArgs {
  std::string assembly, joint = "holder-tool", route, frequencies, tool_hammer = "roving", holder_hammer = "roving";
  double tool_spacing = 0.0, holder_spacing = 0.0;
  int tool_points = 3, holder_points = 3;
  PrecisionOptions options;
  // --sigma, --floor, --averages, --calibration, --calibration-shared: from their definitions
  // (tap_noise_fields).
  FieldFlags<TapNoise> noise;
  bool json = false;
};

void run_precision(PrecisionArgs o, const Globals& g) {
  check_paths({{o.assembly, "assembly file"}}, {});
  PrecisionOptions& p = o.options;
  if (o.joint == "holder-tool") {
    if (!o.route.empty() && o.route != "sh")
      throw InvalidArgument("--from applies to --joint spindle-holder", "drop --from for the holder-tool joint (Eq. 6)");
    p.route = Route::HolderTool;
  } else {
    p.route = o.route == "sht" ? Route::SpindleHolderFromSHT : Route::SpindleHolderFromSH;
  }
  p.tool.spacing_m = o.tool_spacing;
  p.tool.points = o.tool_points;
  p.tool.hammer = o.tool_hammer == "tip" ? HammerPlan::Tip : HammerPlan::Roving;
  p.holder.spacing_m = o.holder_spacing;
  p.holder.points = o.holder_points;
  p.holder.hammer = o.holder_hammer == "tip" ? HammerPlan::Tip : HammerPlan::Roving;
  o.noise.apply(p.noise);
  p.check();
  const LoadedAssembly loaded = load_assembly_on_grid(g, o.assembly, o.frequencies);
  Progress progress(g, "precision");
  const PrecisionStudy r = run_precision_study(loaded.assembly, p, progress.part());
  progress.done();
  warn_all(r.warnings);
  if (o.json) {
    nlohmann::json j = r;
    j["joint"] = o.joint;
    std::cout << j.dump(2) << '\n';
    return;
  }
  std::cout << fmt::format("{} joint, {}: the expected precision of its identification before the tap test\n", o.joint,
                           to_string(r.route));
  for (const auto& m : r.measured) std::cout << "  measured: " << m << "\n";
  std::cout << fmt::format("  noise: {:g} % per hit{}, {} average{}{}\n", 100 * p.noise.sigma,
                           p.noise.floor > 0.0 ? fmt::format(", a floor of {:g} % of each FRF's peak", 100 * p.noise.floor) : "",
                           p.noise.averages, p.noise.averages == 1 ? "" : "s",
                           p.noise.calibration > 0.0
                               ? fmt::format(", calibration σ {:g} %{}", 100 * p.noise.calibration,
                                             p.noise.shared_calibration ? " (one factor for both tests)" : "")
                               : "");
  std::cout << fmt::format("  intervals: {}\n\n", r.fit_description);
  std::cout << fmt::format("parameter  value         expected ± ({:g} %)   relative    of which calibration{}\n",
                           100 * r.confidence, r.target ? fmt::format("   averages for ±{:g} %", 100 * *r.target) : "");
  for (int k = 0; k < 8; ++k) {
    const ParameterPrecision& q = r.parameters[static_cast<std::size_t>(k)];
    if (!q.free) continue;
    std::cout << fmt::format("{:<9}  {:<12.5g}  {:<10.3g} {:<10}  {:>9}   {:<19.3g}{}\n", JointParameters::name(k), q.value,
                             q.half_width, JointParameters::unit(k),
                             std::isfinite(q.relative) ? fmt::format("{:.3g} %", 100 * q.relative) : std::string("-"),
                             q.calibration_half_width,
                             !r.target               ? std::string()
                             : q.averages_for_target ? fmt::format("   {}", *q.averages_for_target)
                                                     : std::string("   unreachable (the calibration alone is wider)"));
  }
  std::cout << std::flush;
}

}  // namespace

void add_precision_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<PrecisionArgs>();
  CLI::App* c = app.add_subcommand(
      "precision",
      "How tight will the joint be? The expected 95 % half-width of each joint parameter before the tap test, and the "
      "averages a target width needs");
  c->add_option("assembly", o->assembly, "Assembly file (TOML, SI units): the model, its joints as the expected values")
      ->required();
  c->add_option("--joint", o->joint, "holder-tool (Eq. 6: SH11 and SHT11 measured) or spindle-holder (Eq. 15 or 18, --from)")
      ->check(CLI::IsMember({"holder-tool", "spindle-holder"}))
      ->capture_default_str();
  c->add_option("--from", o->route, "spindle-holder only: sh (Eq. 15, SH11 measured, default) or sht (Eq. 18, SHT11 measured)")
      ->check(CLI::IsMember({"sh", "sht"}));
  c->add_option("--tool-spacing", o->tool_spacing, "Spacing of the tool's tap test points [m] (when SHT11 is measured)")
      ->check(plausible_value(plausible::kPointSpacing, "--tool-spacing"));
  c->add_option("--holder-spacing", o->holder_spacing, "Spacing of the holder's tap test points [m] (when SH11 is measured)")
      ->check(plausible_value(plausible::kPointSpacing, "--holder-spacing"));
  c->add_option("--tool-points", o->tool_points, "Points on the tool: 2 (first-order differences) or 3 (second order)")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  c->add_option("--holder-points", o->holder_points, "Points on the holder: 2 or 3")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  c->add_option("--tool-hammer", o->tool_hammer, "roving (every point) or tip (only the tip; L from N by reciprocity)")
      ->check(CLI::IsMember({"roving", "tip"}))
      ->capture_default_str();
  c->add_option("--holder-hammer", o->holder_hammer, "roving or tip")
      ->check(CLI::IsMember({"roving", "tip"}))
      ->capture_default_str();
  const auto& noise = tap_noise_fields();
  o->noise.add(c, option_field(noise, "sigma"))->check(plausible_value(plausible::kRelativeNoise, "--sigma"));
  o->noise.add(c, option_field(noise, "floor"))->check(plausible_value(plausible::kRelativeNoise, "--floor"));
  o->noise.add(c, option_field(noise, "averages"));
  o->noise.add_fraction(c, option_field(noise, "calibration"));
  o->noise.add(c, option_field(noise, "shared_calibration"));
  c->add_option_function<std::string>(
      "--target", [o](const std::string& v) { o->options.target = parse_fraction(v, "--target"); },
      "A relative half-width wanted for every parameter, as 1% or 0.01: the averages each needs");
  c->add_option("--parameters", o->options.reciprocal, "6 (k_tf = k_ym, c_tf = c_ym) or 8 free parameters")
      ->transform(CLI::Transformer(std::map<std::string, std::string>{{"6", "true"}, {"8", "false"}}))
      ->default_str("6");
  c->add_option("--frequencies", o->frequencies, "Override the file's [analysis] grid: START:STOP:STEP [Hz]");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(
      "The model's own FRFs with the stated noise, through the finite differences of the tap tests and the band fit\n"
      "(linearised): what an identification of such data would report. Checked against Monte Carlo.\n"
      "Example:\n"
      "  toolpoint precision examples/bt40_shrinkfit_16mm.toml --tool-spacing 0.015 --holder-spacing 0.02 \\\n"
      "      --sigma 0.005 --averages 5 --calibration 2% --target 1%");
  c->callback([o, &g] { run_precision(*o, g); });
}

}  // namespace toolpoint::cli
