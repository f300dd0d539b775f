// toolpoint simulate: milling in the time domain — one cut (forces [N], vibration [µm], the wall's
// surface location error [µm], chatter [Hz], power [W]) or a map of stable/unstable and the SLE over
// spindle speed [rpm] × depth [mm], on every core or in shards — by the library's simulation study
// (studies/simulation.hpp). Lengths on the command line in mm, angles in degrees; files in SI with
// the units in the column names.
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/simulation.hpp"
#include "toolpoint/studies/simulation_io.hpp"

namespace toolpoint::cli {

namespace {


struct SimulateArgs {
  DynamicsArgs dyn;
  std::vector<std::string> planar;  // --mode MASS,ZETA,FN,ANGLE_DEG
  bool rigid_tool = false;
  CutArgs cut;
  std::vector<double> pitch_deg, runout_mm, helix_deg;
  FieldFlags<Cutter> cutter;  // --diameter, --flute-length [mm]: cutter_fields
  // --kte, --kre, --exponent, --reference-chip [mm], --process-damping: force_law_fields.
  FieldFlags<ForceLaw> force;
  std::string rpm, depth;
  FieldFlags<MillingCut> feed;  // --feed [mm]: milling_cut_fields
  // --revolutions, --steps, --slices, --memory-revolutions, --analysed: from simulation_fields.
  FieldFlags<SimulationOptions> simulation;
  // The map.
  FieldFlags<SpeedRange> speeds;  // --speeds: speed_range_fields' points (the map's default 200)
  FieldFlags<DepthRange> depths;  // --depths: depth_range_fields' points
  FieldFlags<ParallelOptions> parallel;  // --threads
  std::string shard, part;
  std::vector<std::string> parts;  // merge
  // Outputs.
  std::string output, plot;
  bool json = false;
};

// "MASS,ZETA,FN,ANGLE_DEG" → a mode along the direction at ANGLE from +x towards +y.
PlanarMode parse_planar_mode(const std::string& text) {
  const std::size_t last = text.rfind(',');
  if (last == std::string::npos)
    throw InvalidArgument(fmt::format("--mode '{}' is not MASS_KG,DAMPING_RATIO,FREQUENCY_HZ,ANGLE_DEG", text),
                          "e.g. 0.04,0.011,922,30 (30° from x towards y)");
  const Mode m = parse_mode(text.substr(0, last), "--mode");
  double angle = 0.0;
  try {
    std::size_t used = 0;
    angle = std::stod(text.substr(last + 1), &used);
    if (used != text.size() - last - 1) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    throw InvalidArgument(fmt::format("--mode '{}': the angle '{}' is not a number", text, text.substr(last + 1)),
                          "write MASS_KG,DAMPING_RATIO,FREQUENCY_HZ,ANGLE_DEG, e.g. 0.04,0.011,922,30");
  }
  return planar_mode(m, radians_of(angle));
}

SimulationInput simulation_input(const SimulateArgs& o, const Globals& g) {
  SimulationInput in;
  const std::vector<JointFile> joints = read_joint_options(g, o.dyn.joints);
  fill_dynamics_input(o.dyn, g, joints, in.source);
  for (const std::string& t : o.planar) in.planar_modes.push_back(parse_planar_mode(t));
  in.rigid = o.rigid_tool;
  return in;
}

Cutter cutter_of(const SimulateArgs& o) {
  Cutter c;
  const int teeth = cutting_conditions(o.cut).teeth;  // 0: not given
  if (!o.pitch_deg.empty()) {
    c.pitch_rad = pitch_radians(o.pitch_deg, teeth);
  } else {
    if (teeth < 1) throw InvalidArgument("give the teeth: --teeth N (evenly spaced) or --pitch DEG,DEG,...", "e.g. --teeth 4");
    c.pitch_rad = uniform_cutter(teeth, 1.0).pitch_rad;  // even spacing (the diameter is the flag's)
  }
  o.cutter.apply(c);
  const std::vector<double> helix = helix_radians(o.helix_deg);
  if (helix.size() == 1) c.helix_rad = helix.front();
  else c.tooth_helix_rad = helix;  // one per tooth (Cutter::check counts them)
  for (double r : o.runout_mm) c.runout_m.push_back(1e-3 * r);
  return c;
}

ForceLaw force_of(const SimulateArgs& o) {
  CuttingConditions cc = cutting_conditions(o.cut);
  cc.teeth = std::max(1, cc.teeth);  // the force law is per tooth: the count is the cutter's
  ForceLaw f = linear_force_law(cc);
  o.force.apply(f);
  return f;
}

SimulationOptions simulation_of(const SimulateArgs& o) {
  SimulationOptions s;
  o.simulation.apply(s);
  return s;
}

double feed_of(const SimulateArgs& o) {
  MillingCut cut;
  o.feed.apply(cut);
  return cut.feed_per_tooth_m;
}

// The library's messages name its fields; here they are the flags.
template <class F>
auto with_cli_names(F&& f) {
  try {
    return f();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(with_flags(e.what()), with_flags(e.hint()));
  }
}

// ---- One cut ----------------------------------------------------------------------------------------

std::vector<std::string> cut_outputs(const SimulateArgs& o) {
  std::vector<std::string> out;
  if (!o.output.empty())
    for (const char* f : {"history.csv", "samples.csv", "wall.csv", "simulation.json"})
      out.push_back((std::filesystem::path(o.output) / f).string());
  return out;
}

std::vector<std::string> cut_figures(const std::string& plot) {
  if (plot.empty()) return {};
  return {plot, with_suffix(plot, "_poincare"), with_suffix(plot, "_spectrum"), with_suffix(plot, "_surface")};
}

void print_cut(const SimulationStudyResult& r) {
  const SimulationResult& s = r.simulation;
  for (const ModalFitSummary& f : r.fits)
    std::cout << fmt::format("modal model of {}: {} mode(s), {:.2f} % residual over {:g}–{:g} Hz\n", f.what, f.modes,
                             100.0 * f.residual, f.band_low_hz, f.band_high_hz);
  std::cout << fmt::format(
      "simulated {} revolutions at {:.0f} rpm, depth {:.4g} mm, feed {:.4g} mm/tooth, {} teeth: {} steps per tooth period "
      "({:.3g} µs), {} slice(s), {} mode(s); the last {} revolutions analysed\n",
      s.revolutions, r.cut.speed_rpm, 1e3 * r.cut.depth_m, 1e3 * r.cut.feed_per_tooth_m, r.cutter.teeth(), s.steps_per_tooth,
      1e6 * s.step_s, s.slices, r.dynamics.modes.size(), s.revolutions - s.analysed_from);
  std::cout << fmt::format("  {}: growth {} per revolution, chatter metric {:.3g}{}\n",
                           s.stable ? "stable" : (s.diverged ? "CHATTER (diverged: stopped early)" : "CHATTER"),
                           s.growth == 0.0 ? std::string("0 (decayed below 1e-7)") : fmt::format("{:.4g}", s.growth),
                           s.chatter_metric,
                           std::isfinite(s.chatter_hz) && !s.stable ? fmt::format(", chatter at {:.1f} Hz", s.chatter_hz) : "");
  std::cout << fmt::format("  mean force Fx {:.4g} N, Fy {:.4g} N; peak |F| {:.4g} N; torque {:.4g} N m, power {:.4g} kW\n",
                           s.mean_force_x_n, s.mean_force_y_n, s.peak_force_n, s.mean_torque_nm, 1e-3 * s.power_w);
  for (const Wall& w : s.walls)
    std::cout << fmt::format("  wall at {:.0f}°: surface location error {:.3f} µm (+: material left)\n", degrees_of(w.angle_rad),
                             1e6 * w.mean_sle_m);
}

void run_cut(const SimulateArgs& o, const Globals& g) {
  check_plot_path(o.plot);
  std::vector<RunPath> outs;
  for (const std::string& p : cut_outputs(o)) outs.push_back({p, "--output"});
  for (const std::string& p : cut_figures(o.plot)) outs.push_back({p, "--plot"});
  check_paths(dynamics_paths(o.dyn), outs);
  if (o.rpm.find(':') != std::string::npos || o.depth.find(':') != std::string::npos)
    throw InvalidArgument("--rpm and --depth are ranges (MIN:MAX) only for `toolpoint simulate map`",
                          "give one speed and one depth, e.g. --rpm 10000 --depth 2, or run `toolpoint simulate map`");
  SimulationStudyOptions so;
  so.cutter = cutter_of(o);
  so.force = force_of(o);
  so.cut.engagement = cut_engagement(o.cut);
  so.cut.feed_per_tooth_m = feed_of(o);
  so.cut.speed_rpm = parse_value(o.rpm, "--rpm");
  check_plausible(plausible::kSpindleSpeedRpm, so.cut.speed_rpm, "--rpm", "give the spindle speed in rpm, e.g. --rpm 10000");
  const double depth_mm = parse_value(o.depth, "--depth");
  if (depth_mm != 0.0) check_plausible(kDepthMm, depth_mm, "--depth [mm]", "e.g. --depth 2");
  so.cut.depth_m = 1e-3 * depth_mm;
  so.simulation = simulation_of(o);
  so.fit = dynamics_fit_options(o.dyn);
  so.fit_target = dynamics_fit_target(o.dyn);
  const SimulationInput in = simulation_input(o, g);
  Progress progress(g, "simulate: revolutions");
  const SimulationStudyResult r = with_cli_names([&] { return run_simulation_study(in, so, progress.part()); });
  progress.done();
  std::vector<std::string> written;
  nlohmann::json j = r;
  if (!o.output.empty()) {
    const auto file = [&](const char* f) { return (std::filesystem::path(o.output) / f).string(); };
    const std::vector<std::string> comments{fmt::format("toolpoint simulate: {:.0f} rpm, depth {} m, feed {} m/tooth",
                                                        r.cut.speed_rpm, r.cut.depth_m, r.cut.feed_per_tooth_m)};
    write_table_csv(file("history.csv"), simulation_history_table(r.simulation), comments);
    write_table_csv(file("samples.csv"), simulation_samples_table(r.simulation),
                    {comments[0], "kind 0: once per revolution, 1: once per tooth (as the tooth's tip passes 0°)"});
    write_table_csv(file("wall.csv"), simulation_wall_table(r.simulation),
                    {comments[0], "sle_m: material left on the wall (+: undercut, -: overcut)"});
    write_text_file(file("simulation.json"), j.dump(2) + "\n");
    written = cut_outputs(o);
  }
  warn_all(r.warnings);
  if (o.json) {
    j["files"] = written;
    j["plots"] = cut_figures(o.plot);
    std::cout << j.dump(2) << '\n';
  } else {
    print_cut(r);
    if (!written.empty()) info(g, fmt::format("wrote history.csv, samples.csv, wall.csv and simulation.json to {}/", o.output));
  }
  if (!o.plot.empty()) {
    const std::vector<std::string> paths = cut_figures(o.plot);
    std::vector<FigureFile> figures{{simulation_time_figure(r), paths[0]},
                                    {simulation_poincare_figure(r), paths[1]},
                                    {simulation_spectrum_figure(r), paths[2]}};
    if (!r.simulation.walls.empty() && !r.simulation.walls.front().passes.empty())
      figures.push_back({simulation_surface_figure(r), paths[3]});
    else info(g, fmt::format("no wall is cut (entry 0° or exit 180° makes one): {} is not drawn", paths[3]));
    draw_figures(g, figures, written);
  }
}

// ---- The map ----------------------------------------------------------------------------------------

std::vector<std::string> map_outputs(const SimulateArgs& o) {
  std::vector<std::string> out;
  if (!o.output.empty())
    for (const char* f : {"map.csv", "map.json"}) out.push_back((std::filesystem::path(o.output) / f).string());
  return out;
}

void report_map(const Globals& g, const SimulateArgs& o, const SimulatedMap& m) {
  warn_all(m.warnings);
  std::vector<std::string> written;
  nlohmann::json j = m;
  if (!o.output.empty()) {
    const std::vector<std::string> files = map_outputs(o);
    write_table_csv(files[0], simulated_map_table(m),
                    {fmt::format("toolpoint simulate map: {} speeds x {} depths, {} revolutions per cell; fingerprint {:016x}",
                                 m.header.speeds_rpm.size(), m.header.depths_m.size(), m.header.options.simulation.revolutions,
                                 m.header.fingerprint),
                     "stable: 1 stable, 0 chatter; sle_um: material left on the wall (+: undercut); empty: none"});
    write_text_file(files[1], j.dump(2) + "\n");
    written = files;
  }
  if (o.json) {
    j["files"] = written;
    j["plot"] = o.plot;
    std::cout << j.dump(2) << '\n';
  } else {
    std::size_t cells = 0, stable = 0;
    for (const SimulatedMapRow& r : m.rows)
      for (int s : r.stable) {
        ++cells;
        stable += s != 0;
      }
    std::cout << fmt::format(
        "simulated stability map: {} speeds {:g}-{:g} rpm x {} depths {:.4g}-{:.4g} mm: {} of {} cells stable\n",
        m.header.speeds_rpm.size(), m.header.speeds_rpm.front(), m.header.speeds_rpm.back(), m.header.depths_m.size(),
        1e3 * m.header.depths_m.front(), 1e3 * m.header.depths_m.back(), stable, cells);
    std::cout << "  spindle_speed_rpm  lowest_unstable_depth_mm  chatter_frequency_hz\n";
    const std::size_t every = std::max<std::size_t>(1, m.boundary.size() / 20);
    for (std::size_t i = 0; i < m.boundary.size(); i += every) {
      const EnvelopePoint& e = m.boundary[i];
      std::cout << fmt::format("  {:17.0f}  {:>24}  {:>20}\n", e.speed_rpm,
                               std::isfinite(e.depth_m) ? fmt::format("{:.4g}", 1e3 * e.depth_m) : std::string("-"),
                               std::isfinite(e.chatter_hz) ? fmt::format("{:.1f}", e.chatter_hz) : std::string("-"));
    }
    if (!written.empty()) info(g, fmt::format("wrote map.csv and map.json to {}/", o.output));
  }
  if (!o.plot.empty()) draw_figures(g, {{simulated_map_figure(m), o.plot}}, written);
}

// `study`: the map's options (given_options), kept in a part for the commands that redo a shard.
void run_map(const SimulateArgs& o, const Globals& g, const std::string& study) {
  check_plot_path(o.plot);
  const auto [index, count] = shard_options(o.shard, o.part, !o.output.empty() || !o.plot.empty() || o.json, "map",
                                            "toolpoint simulate merge");
  std::vector<RunPath> outs;
  for (const std::string& p : map_outputs(o)) outs.push_back({p, "--output"});
  outs.push_back({o.plot, "--plot"});
  outs.push_back({o.part, "--part"});
  check_paths(dynamics_paths(o.dyn), outs);
  check_output_extension(o.part, "--part", {".json"}, "a simulated map part as JSON (.json)");
  SimulatedMapOptions mo;
  mo.cutter = cutter_of(o);
  mo.force = force_of(o);
  mo.cut.engagement = cut_engagement(o.cut);
  mo.cut.feed_per_tooth_m = feed_of(o);
  const auto [n0, n1] = parse_range(o.rpm, "--rpm");
  for (double n : {n0, n1})
    check_plausible(plausible::kSpindleSpeedRpm, n, "--rpm", "give spindle speeds in rpm, e.g. --rpm 5000:25000");
  mo.speeds = {n0, n1, mo.speeds.points};
  o.speeds.apply(mo.speeds);
  const auto [d0, d1] = parse_range(o.depth, "--depth");
  for (double d : {d0, d1}) check_plausible(kDepthMm, d, "--depth [mm]", "e.g. --depth 0.1:5");
  mo.depths = {1e-3 * d0, 1e-3 * d1, mo.depths.points};
  o.depths.apply(mo.depths);
  mo.simulation = simulation_of(o);
  o.parallel.apply(mo.parallel);
  std::vector<ModalFitSummary> fits;
  std::vector<std::string> warnings;
  const SimulationInput in = simulation_input(o, g);
  const ToolDynamics dyn = with_cli_names(
      [&] { return simulation_dynamics(in, dynamics_fit_options(o.dyn), dynamics_fit_target(o.dyn), fits, warnings); });
  warn_all(warnings);
  Progress progress(g, o.shard.empty() ? "simulate map: cells" : fmt::format("simulate map: shard {}/{}", index, count));
  if (!o.shard.empty()) {
    SimulatedMapPart part = with_cli_names(
        [&, index = index, count = count] { return run_simulated_map_part(dyn, mo, index, count, progress.part()); });
    progress.done();
    part.study = study;
    write_text_file(o.part, format_simulated_map_part(part));
    info(g, fmt::format("shard {}/{}: {} of {} speeds written to {}", index, count, part.rows.size(),
                        part.header.speeds_rpm.size(), o.part));
    return;
  }
  const SimulatedMap m = with_cli_names([&] { return run_simulated_map(dyn, mo, progress.part()); });
  progress.done();
  report_map(g, o, m);
}

// How a shard of the map is run again: `toolpoint simulate map OPTIONS --shard I/N --part FILE`
// (the options kept in its parts), or in the Slurm array of scripts/slurm/simulate-array.sh.
ShardCommand map_shard_command(const ShardSetCheck& c) {
  const std::string options = c.study.empty() ? "MAP_OPTIONS..." : c.study;
  return {"toolpoint simulate map " + options, [options](const std::string& list, const std::string& dir, int count) {
            return fmt::format("sbatch --array={} scripts/slurm/simulate-array.sh {} {} {}", list, dir, count, options);
          }};
}

void run_merge(const SimulateArgs& o, const Globals& g) {
  check_plot_path(o.plot);
  std::vector<RunPath> in, outs;
  for (const std::string& p : o.parts) in.push_back({p, "part"});
  for (const std::string& p : map_outputs(o)) outs.push_back({p, "--output"});
  outs.push_back({o.plot, "--plot"});
  check_paths(in, outs);
  SimulatedMap m;
  try {
    m = merge_simulated_map_part_files(o.parts);
  } catch (const ShardSetError& e) {
    throw InputError(e.what(), mending_commands(e.check(), map_shard_command(e.check())));
  }
  info(g, fmt::format("merged {} part(s): {} speeds", o.parts.size(), m.rows.size()));
  report_map(g, o, m);
}

// The options of one cut and of the map: the dynamics, the tool, the cut, the scheme.
void add_common(CLI::App* c, SimulateArgs& o, Globals& g, bool map) {
  add_dynamics_options(c, o.dyn, g, "");
  add_joint_option(c, o.dyn.joints)
      ->description(
          "With --assembly: an identified joint instead of the assembly file's (holder-tool=FILE.toml or "
          "spindle-holder=FILE.toml)");
  c->add_option("--mode", o.planar,
                "A mode acting along a direction in the x-y plane, MASS_KG,DAMPING_RATIO,FREQUENCY_HZ,ANGLE_DEG (from x "
                "towards y; 0 an x mode, 90 a y mode, between: x and y coupled); repeatable, added to the others");
  c->add_flag("--rigid-tool", o.rigid_tool, "A rigid tool (no modes): the cut's forces alone");
  add_cut_options(c, o.cut, "evenly spaced; or give --pitch", false, map);
  c->add_option("--pitch", o.pitch_deg,
                "Variable pitch: the angle from each tooth to the next [°], one per tooth, summing to 360 (e.g. 85,95,85,95)")
      ->delimiter(',');
  const auto& cutter = cutter_fields();
  o.cutter.add(c, option_field(cutter, "diameter_m"), true)->required(map);
  c->add_option("--helix", o.helix_deg,
                "Helix angle [°, not rad], 0…80: one for every tooth, or one per tooth (a variable helix, e.g. 35,38,35,38) "
                "(axial slices; default: straight flutes)")
      ->delimiter(',');
  c->add_option("--runout", o.runout_mm,
                "Radial runout per tooth [mm]: each tooth cuts at D/2 + its value (e.g. 0.01,0,0,-0.005; default none)")
      ->delimiter(',');
  o.cutter.add(c, option_field(cutter, "flute_length_m"), true);
  const auto& force = force_law_fields();
  for (const char* name : {"tangential_edge", "radial_edge"}) o.force.add(c, option_field(force, name), true);
  o.force.add(c, option_field(force, "process_damping_n_per_m"));
  o.force.add(c, option_field(force, "exponent"));
  o.force.add(c, option_field(force, "reference_chip_m"));
  o.feed.add(c, option_field(milling_cut_fields(), "feed_per_tooth_m"), true)->required(map);
  c->add_option("--rpm", o.rpm, map ? "Spindle speed range MIN:MAX [rpm] (required)" : "Spindle speed [rpm] (required)")
      ->required(map);
  c->add_option("--depth", o.depth, map ? "Axial depth range MIN:MAX [mm] (required)" : "Axial depth of cut [mm] (required)")
      ->required(map);
  for (const auto& f : simulation_fields())
    if (f.spec.cli_name) o.simulation.add(c, f);
}

}  // namespace

void add_simulate_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<SimulateArgs>();
  CLI::App* c = app.add_subcommand(
      "simulate", "Milling in the time domain: forces, vibration, the wall's surface location error, chatter (and `map`)");
  add_common(c, *o, g, false);
  c->add_option("--output", o->output,
                "Write DIR/history.csv (every step: forces [N], displacements [m], velocities [m/s], torque [N m], each tooth's "
                "force), samples.csv (once per revolution and once per tooth), wall.csv (SLE per slice [m]) and "
                "simulation.json")
      ->option_text("DIR");
  add_plot_option(
      c, o->plot,
      "the forces [N] and displacements [µm] over the last revolutions against time [ms]; in FILE with \"_poincare\", "
      "the tool's path in the x-y plane [µm] with the once-per-revolution and once-per-tooth samples; \"_spectrum\", "
      "the displacement's amplitude spectrum [µm] with the tooth-passing harmonics and the chatter frequency; "
      "\"_surface\", the wall's profile [µm] along the feed [mm]");
  c->add_flag("--json", o->json, "Machine-readable result on stdout");
  c->footer(std::string(kFigureFooter) +
            "The model, the scheme (second order) and its checks: docs/simulation.md. Lengths on the command line in mm, angles\n"
            "in degrees; the files in SI (units in the column names).\n"
            "Examples:\n"
            "  toolpoint simulate --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 \\\n"
            "      --immersion 0.05 --milling down --feed 0.1 --rpm 10000 --depth 2 --output sim --plot sim.png\n"
            "  toolpoint simulate map --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 \\\n"
            "      --immersion 0.05 --milling down --feed 0.1 --rpm 5000:25000 --depth 0.1:10 --output map --plot map.png\n"
            "  toolpoint simulate map ... --shard 3/8 --part parts/part-3.json     (one of 8 batch tasks)\n"
            "  toolpoint simulate merge parts/part-*.json --output map --plot map.png");

  CLI::App* m = c->add_subcommand("map", "Stable or not, and the SLE, over spindle speed x depth, on every core or in shards");
  add_common(m, *o, g, true);
  o->speeds.add(m, option_field(speed_range_fields(), "points"))->default_str(std::to_string(SimulatedMapOptions{}.speeds.points));
  o->depths.add(m, option_field(depth_range_fields(), "points"));
  add_threads_option(m, o->parallel);
  m->add_option("--shard", o->shard,
                "Compute only shard I of N (I = 0…N-1: the speeds i with i mod N = I) and write it to --part; combine the parts "
                "with `toolpoint simulate merge`")
      ->option_text("I/N");
  m->add_option("--part", o->part, "With --shard: the part file to write (JSON, numbers exact)")->option_text("FILE");
  auto add_map_outputs = [&](CLI::App* x) {
    x->add_option("--output", o->output,
                  "Write DIR/map.csv (per speed [rpm] and depth [mm]: stable, growth per revolution, chatter metric and "
                  "frequency [Hz], SLE [µm], peak force [N]) and map.json")
        ->option_text("DIR");
    add_plot_option(x, o->plot,
                    "the chatter metric over spindle speed [rpm] x depth [mm] with the lowest unstable depth per speed, and "
                    "the SLE [µm] of the stable cuts");
    x->add_flag("--json", o->json, "Machine-readable summary on stdout");
  };
  add_map_outputs(m);
  m->callback([o, c, m, &g] {
    run_map(*o, g, given_options({c, m}, {"--shard", "--part", "--threads", "--output", "--plot", "--json"}));
  });

  CLI::App* mg = c->add_subcommand("merge", "Combine the part files of `simulate map --shard` into the whole map");
  mg->add_option("parts", o->parts, "The part files, every shard once, any order")->required();
  add_map_outputs(mg);
  mg->callback([o, &g] { run_merge(*o, g); });

  c->callback([o, c, m, mg, &g] {
    if (c->got_subcommand(m) || c->got_subcommand(mg)) return;
    // Required for one cut (not on the command itself, which `simulate merge` also passes through).
    for (const char* name : {"--diameter", "--kt", "--feed", "--rpm", "--depth"})
      if (c->count(name) == 0) throw CLI::RequiredError(name);
    run_cut(*o, g);
  });
}

}  // namespace toolpoint::cli
