// toolpoint plan: the set-up (candidate, tool overhang) and spindle speed [rpm] that remove the most
// metal [cm³/min] without chatter, from a study file — the library's plan study (studies/plan.hpp).
// Whole on every core, or one shard of a batch array (--shard I/N --part FILE) and `plan merge`.
// --plot draws the allowed depth [mm] over spindle speed [rpm] × overhang [mm] and the tuning curve.
#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/plan_io.hpp"

namespace toolpoint::cli {

namespace {

struct PlanArgs {
  std::string study, method, output, plot, shard, part;
  ToolGeometryArgs tool;  // overrides of the study's [cut] pitch, helix, runout, process damping
  FieldFlags<ParallelOptions> parallel;  // --threads
  bool json = false;
  std::vector<std::string> parts;  // plan merge
};

// The files a run writes: DIR/setups.csv, tuning.csv, map.csv, plan.json; FILE and FILE_tuning.
std::vector<std::string> outputs_of(const PlanArgs& o) {
  std::vector<std::string> out;
  if (!o.output.empty())
    for (const char* f : {"setups.csv", "tuning.csv", "map.csv", "plan.json"})
      out.push_back((std::filesystem::path(o.output) / f).string());
  if (!o.plot.empty()) out.insert(out.end(), {o.plot, with_suffix(o.plot, "_tuning")});
  if (!o.part.empty()) out.push_back(o.part);
  return out;
}

// No output may overwrite an input (the study, its assemblies, SH11s and joint files, the parts),
// nor another output.
void check_outputs(const PlanArgs& o, const std::vector<std::string>& inputs) {
  std::vector<RunPath> in, out;
  for (const std::string& p : inputs) in.push_back({p, "input"});
  for (const std::string& p : outputs_of(o)) out.push_back({p, "output"});
  check_paths(in, out);
}

void print_report(const PlanResult& r) {
  const std::string& name = r.header.options.name;
  const PlanHeader& h = r.header;
  const PlanOptions& o = h.options;
  std::string limits;
  if (o.machine.power_w > 0.0) limits += fmt::format(", power {:g} kW", 1e-3 * o.machine.power_w);
  if (o.machine.torque_nm > 0.0) limits += fmt::format(", torque {:g} N m", o.machine.torque_nm);
  if (o.machine.min_overhang_m > 0.0) limits += fmt::format(", minimum overhang {:g} mm", 1e3 * o.machine.min_overhang_m);
  if (o.max_depth_m > 0.0) limits += fmt::format(", depth at most {:g} mm", 1e3 * o.max_depth_m);
  std::cout << fmt::format(
      "plan{}: {} candidate(s), {} set-ups (overhangs) x {} spindle speeds {:g}-{:g} rpm, {}; depth used: {}{}\n",
      name.empty() ? "" : " '" + name + "'", h.candidates.size(), h.jobs, h.speeds_rpm.size(), h.speeds_rpm.front(),
      h.speeds_rpm.back(),
      o.lobes.method == LobesMethod::ZeroOrder            ? "zero-order lobes"
      : o.lobes.method == LobesMethod::SemiDiscretization ? "semi-discretization boundary"
                                                          : "full-discretization boundary",
      safety_rule_text(o.safety), limits);
  std::cout << "best set-ups, most metal removed first:\n"
               "  rank  candidate                 overhang_mm  speed_rpm  depth_mm  mrr_cm3_per_min  limit      margin_%  "
               "chatter_hz  lobe  window_rpm\n";
  for (std::size_t i = 0; i < r.best.size(); ++i) {
    const PlanSetup& s = r.best[i];
    std::cout << fmt::format(
        "  {:4}  {:24}  {:11.1f}  {:9.0f}  {:8.3f}  {:15.1f}  {:9}  {:8.1f}  {:10.0f}  {:4}  {:.0f}-{:.0f}\n", i + 1,
        h.candidates[s.candidate].name, 1e3 * s.overhang_m, s.speed_rpm, 1e3 * s.depth_m,
        kCubicCentimetresPerMinute * s.mrr_m3_per_s, to_string(s.limit), 100.0 * s.depth_margin, s.chatter_hz, s.lobe,
        s.window_low_rpm, s.window_high_rpm);
    if (std::isfinite(s.probability))
      std::cout << fmt::format("        probability of stability at this depth: {:.3f}\n", s.probability);
    std::cout << "        why: " << s.reason << "\n";
  }
}

// What a finished plan (whole or merged) writes and says.
void report(const Globals& g, const PlanArgs& o, const PlanResult& r) {
  warn_all(r.warnings);
  std::vector<std::string> written;
  nlohmann::json j = r;
  if (!o.output.empty()) {
    const auto file = [&](const char* f) { return (std::filesystem::path(o.output) / f).string(); };
    write_text_file(file("setups.csv"), format_plan_setups_csv(r));
    write_text_file(file("tuning.csv"), format_plan_tuning_csv(r));
    write_text_file(file("map.csv"), format_plan_map_csv(r));
    write_text_file(file("plan.json"), j.dump(2) + "\n");
    written = {file("setups.csv"), file("tuning.csv"), file("map.csv"), file("plan.json")};
  }
  if (o.json) {
    j["files"] = written;
    if (!o.plot.empty()) j["plots"] = {o.plot, with_suffix(o.plot, "_tuning")};
    std::cout << j.dump(2) << '\n';
  } else {
    print_report(r);
    if (!written.empty()) info(g, fmt::format("wrote setups.csv, tuning.csv, map.csv and plan.json to {}/", o.output));
  }
  if (!o.plot.empty())
    draw_figures(g, {{plan_map_figure(r), o.plot}, {plan_tuning_figure(r), with_suffix(o.plot, "_tuning")}}, written);
}

// The flags given replace the study's [cut] keys (the diameter is each candidate's tool's, the
// feed the study's cut.feed_per_tooth); run_plan checks the result.
void override_tool(const ToolGeometryArgs& t, CuttingConditions& c) {
  if (!t.pitch_deg.empty()) c.pitch_rad = pitch_radians(t.pitch_deg, c.teeth);
  if (!t.helix_deg.empty()) c.helix_rad = helix_radians(t.helix_deg);
  if (!t.runout_mm.empty()) {
    c.runout_m.clear();
    for (double r : t.runout_mm) c.runout_m.push_back(1e-3 * r);
  }
  t.fields.apply(c);  // --process-damping
}

void run_plan_command(const PlanArgs& o, const Globals& g) {
  if (o.study.empty())
    throw InvalidArgument("give the study file: toolpoint plan STUDY.toml", "see `toolpoint plan --help` for its format");
  check_plot_path(o.plot);
  const auto [index, count] = shard_options(o.shard, o.part, !o.output.empty() || !o.plot.empty() || o.json, "plan",
                                            "toolpoint plan merge");
  PlanStudy study = load_plan_study(o.study);
  warn_all(study.warnings);
  for (const std::string& n : study.notes) info(g, "note: " + n);
  check_outputs(o, study.inputs);
  check_output_extension(o.part, "--part", {".json"}, "a plan part as JSON (.json)");
  if (o.method == "zoa") study.options.lobes.method = LobesMethod::ZeroOrder;
  else if (!o.method.empty()) study.options.lobes.method = lobes_method_from(o.method).value_or(LobesMethod::FullDiscretization);
  override_tool(o.tool, study.options.lobes.cutting);
  o.parallel.apply(study.options.parallel);

  Progress progress(g, o.shard.empty() ? "plan: set-ups" : fmt::format("plan: shard {}/{}", index, count));
  if (!o.shard.empty()) {
    PlanPart part = run_plan_part(study.candidates, study.options, index, count, progress.part());
    progress.done();
    part.study = o.study;  // for the commands a merge names when a shard is missing
    write_text_file(o.part, format_plan_part(part));
    info(g, fmt::format("shard {}/{}: {} of {} set-ups written to {}", index, count, part.jobs.size(), part.header.jobs, o.part));
    return;
  }
  const PlanResult r = run_plan(study.candidates, study.options, progress.part());
  progress.done();
  report(g, o, r);
}

// How a shard of the plan is run again: `toolpoint plan STUDY --shard I/N --part FILE`, or in the
// Slurm array of scripts/slurm/plan-array.sh.
ShardCommand plan_shard_command(const ShardSetCheck& c) {
  const std::string study = c.study.empty() ? "STUDY.toml" : c.study;
  return {"toolpoint plan " + study, [study](const std::string& list, const std::string& dir, int count) {
            return fmt::format("sbatch --array={} scripts/slurm/plan-array.sh {} {} {}", list, study, dir, count);
          }};
}

void run_merge_command(const PlanArgs& o, const Globals& g) {
  check_plot_path(o.plot);
  check_outputs(o, o.parts);
  PlanResult r;
  try {
    r = merge_plan_part_files(o.parts);
  } catch (const ShardSetError& e) {
    throw InputError(e.what(), mending_commands(e.check(), plan_shard_command(e.check())));
  }
  info(g, fmt::format("merged {} part(s): {} set-ups", o.parts.size(), r.jobs.size()));
  report(g, o, r);
}

void add_outputs(CLI::App* c, PlanArgs& o) {
  c->add_option(
       "--output", o.output,
       "Write DIR/setups.csv (the best set-up per candidate), tuning.csv (the best per overhang), map.csv (every overhang and "
       "speed: stable, allowed and used depth [mm], limit, MRR [cm^3/min], chatter [Hz], lobe) and plan.json (default: none)")
      ->option_text("DIR");
  add_plot_option(
      c, o.plot,
      "the allowed depth [mm] as a map over spindle speed [rpm] and overhang [mm] with the best speeds marked; the tuning "
      "curve (best MRR [cm^3/min] and its speed [rpm] against overhang [mm]) in FILE with \"_tuning\" before the extension");
  c->add_flag("--json", o.json, "Machine-readable result on stdout");
}

}  // namespace

void add_plan_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<PlanArgs>();
  CLI::App* c = app.add_subcommand(
      "plan", "The set-up (overhang) and spindle speed that remove the most metal without chatter, from a study file");
  c->add_option(
      "study", o->study,
      "Study file (TOML, SI units, spindle speeds in rpm): candidates (assemblies and their overhang ranges, or a measured "
      "SH11 + the model's tool), the cut, the machine's speeds and limits, the safety rule; see examples/plan_bt40.toml");
  c->add_option("--method", o->method,
                "Override the study's method: zoa (zero-order lobes), fd (full-discretization) or sd (semi-discretization)")
      ->check(CLI::IsMember({"zoa", "fd", "sd"}));
  add_tool_geometry_options(c, o->tool, false);
  add_threads_option(c, o->parallel);
  c->add_option("--shard", o->shard,
                "Compute only shard I of N (I = 0…N-1: the set-ups j with j mod N = I) and write it to --part; combine the parts "
                "with `toolpoint plan merge`")
      ->option_text("I/N");
  c->add_option("--part", o->part, "With --shard: the part file to write (JSON, numbers exact)")->option_text("FILE");
  add_outputs(c, *o);
  c->footer(
      std::string(kFigureFooter) +
      "The depth used at each speed is the smallest of: the allowed depth (the stable depth / safety.factor, or the depth\n"
      "stable with probability >= safety.probability for the sampled joint), the spindle's torque and power limits (mean\n"
      "cutting torque from K_t, the feed and the engagement), the tool's flute length and cut.max_depth.\n"
      "MRR = depth x radial width x feed per tooth x teeth x speed. Results are identical for any --threads and any sharding.\n"
      "Spindle at speed: a candidate assembly whose bearings carry speed tables or differ in x and y gets zoa lobes from\n"
      "its x-y tool point FRF at each speed (the spindle spinning, the tables read there; as `toolpoint lobes --speed-model\n"
      "auto`), each job saying so with the interpolation error; fd and a measured SH11 keep the standstill FRF, said.\n"
      "Examples:\n"
      "  toolpoint plan examples/plan_bt40.toml --output plan --plot plan.png\n"
      "  toolpoint plan examples/plan_bt40.toml --shard 3/8 --part parts/part-3.json     (one of 8 batch tasks)\n"
      "  toolpoint plan merge parts/part-*.json --output plan --plot plan.png");
  CLI::App* m = c->add_subcommand("merge",
                                  "Combine the part files of `plan --shard` into the whole plan (identical to an unsharded run)");
  m->add_option("parts", o->parts, "The part files, every shard once, any order")->required();
  add_outputs(m, *o);
  m->callback([o, &g] { run_merge_command(*o, g); });
  c->callback([o, c, m, &g] {
    if (c->got_subcommand(m)) return;
    run_plan_command(*o, g);
  });
}

}  // namespace toolpoint::cli
