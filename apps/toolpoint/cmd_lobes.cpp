// toolpoint lobes: milling stability lobes — spindle speed [rpm] against limiting axial depth [mm]
// with chatter frequency [Hz] — from the tool point FRF (zero-order approximation) or from a modal
// model (full-discretization in the time domain, modes given or fitted from the FRF), by the
// library's lobes study (studies/lobes.hpp). --plot draws the lobes (or the boundary) with the
// stable region shaded, lobe numbers and the chatter frequency panel.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/io/stability_io.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/io/uncertainty_io.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint::cli {

namespace {

struct LobesOptions {
  DynamicsArgs dyn;       // where the tool point FRFs (or modes) come from
  ToolGeometryArgs tool;  // variable pitch, runout, process damping
  CutArgs cut;
  // Speeds and method.
  std::string rpm, method = "zoa";
  FieldFlags<SpeedRange> speeds;  // --speeds (speed_range_fields' points; not given: the method's)
  int depth_steps = 0;
  FieldFlags<ParallelOptions> parallel;  // --threads
  // --lobes, --tolerance, --intervals, --max-depth, --pocket-prominence, --speed-nodes,
  // --extrapolate-bearings: from their definitions (lobes_study_fields).
  FieldFlags<LobesStudyOptions> fields;
  std::string output, envelope, plot;
  // The joint uncertain (--assembly with a --joint file carrying a covariance).
  SamplingOptions sampling;
  std::string probability_output;
  // The dynamics at speed (--assembly).
  std::string speed_model = "auto";
  bool json = false;
};

// ---- Text ------------------------------------------------------------------------------------

void print_summary(const LobesStudyResult& r) {
  if (r.zero_order) {
    const ZeroOrderResult& z = *r.zero_order;
    std::cout << fmt::format("zero-order stability lobes, k = 0…{}: absolute stability limit {:.4f} mm (chatter at {:.1f} Hz)\n",
                             z.lobes, z.floor_depth_m * 1e3, z.floor_chatter_hz);
    if (!r.frf_speeds_rpm.empty())
      std::cout << fmt::format(
          "  at speed ({}): the x-y tool point FRF at {} speeds, {:g}-{:g} rpm, interpolated between them; estimated "
          "interpolation error {:.2g} % of the FRF, {:.2g} % of the stable depth\n",
          to_string(r.speed_model), r.frf_speeds_rpm.size(), r.frf_speeds_rpm.front(), r.frf_speeds_rpm.back(),
          100.0 * r.frf_interpolation_error, 100.0 * r.envelope_interpolation_error);
    return;
  }
  for (const ModalFitSummary& s : r.fits)
    std::cout << fmt::format("modal model of {}: {} mode(s), {:.2f} % residual over {:g}–{:g} Hz{}\n", s.what, s.modes,
                             100.0 * s.residual, s.band_low_hz, s.band_high_hz, s.target_met ? "" : " (above the target)");
  if (!r.frf_speeds_rpm.empty())
    std::cout << fmt::format(
        "  at speed ({}): a modal model with x-y pole-residue terms fitted at each speed to the x-y tool point FRF at {} "
        "speeds, {:g}-{:g} rpm, interpolated between them; largest fit residual {:.2g} % (real modes), {:.2g} % (the "
        "whole model against the x-y block); "
        "estimated interpolation error {:.2g} % of the FRF, {:.2g} % of the zero-order stable depth\n",
        to_string(r.speed_model), r.frf_speeds_rpm.size(), r.frf_speeds_rpm.front(), r.frf_speeds_rpm.back(),
        100.0 * r.fit_residual, 100.0 * r.block_fit_residual, 100.0 * r.frf_interpolation_error,
        100.0 * r.envelope_interpolation_error);
  const BoundaryResult& b = *r.boundary;
  const auto lowest = std::min_element(b.boundary.begin(), b.boundary.end(),
                                       [](const BoundaryPoint& x, const BoundaryPoint& y) { return x.depth_m < y.depth_m; });
  const auto flips = std::count_if(b.boundary.begin(), b.boundary.end(),
                                   [](const BoundaryPoint& x) { return x.kind == BoundaryKind::Flip; });
  std::cout << fmt::format(
      "stability boundary by full-discretization ({} speeds, depths up to {:.4g} mm; estimated "
      "discretization error at most {:.2g} % of the depth, target {:.3g} %): lowest {} mm at {:.0f} rpm "
      "({}); period-doubling (flip) boundary at {} speed(s)\n",
      b.boundary.size(), b.max_depth_m * 1e3, 100.0 * b.worst_relative_error(), 100.0 * b.tolerance,
      depth_text_mm(lowest->depth_m * 1e3, lowest->depth_error_m * 1e3), lowest->speed_rpm, to_string(lowest->kind), flips);
}

void print_pockets(const LobesStudyResult& r, double prominence) {
  if (r.pockets.empty()) return;
  std::cout << fmt::format(
      "best spindle speeds in {}–{} rpm (envelope maxima rising {:g} % of their depth or more above "
      "the valleys beside them):\n",
      r.speeds.min_rpm, r.speeds.max_rpm, 100.0 * prominence);
  std::cout << "  spindle_speed_rpm  axial_depth_mm  chatter_frequency_hz  lobe\n";
  for (std::size_t i = 0; i < r.pockets.size(); ++i) {
    const EnvelopePoint& p = r.pockets[i];
    // The time domain's depths carry their error estimate: print the digits it supports.
    const double error = r.pocket_depth_error_m[i];
    // lobe −1: no instability up to the ceiling searched there.
    const bool capped = p.lobe < 0;
    const std::string depth = (capped ? ">= " : "") + (r.boundary && !capped ? depth_text_mm(p.depth_m * 1e3, error * 1e3)
                                                                             : fmt::format("{:.4f}", p.depth_m * 1e3));
    std::cout << fmt::format("  {:17.0f}  {:>14}  {:>20}  {:>4}\n", p.speed_rpm, depth,
                             capped ? std::string("-") : fmt::format("{:.1f}", p.chatter_hz),
                             capped ? std::string("-") : std::to_string(p.lobe));
  }
}

// What the joint's uncertainty does to the best speeds: at each, the nominal depth and the depths
// stable with 95 % and 50 % probability (the default levels 0.05, 0.5, 0.95).
void report_uncertain_lobes(const LobesStudyResult& r) {
  std::cout << fmt::format(
      "with the joint of {} uncertain ({} samples): depth stable with probability 95 % / 50 % at the best speeds\n",
      r.uncertain_joint, r.uncertainty->samples);
  std::cout << "  spindle_speed_rpm  nominal_mm  p95_mm  p50_mm\n";
  for (const SpeedQuantiles& q : r.pocket_quantiles)
    std::cout << fmt::format("  {:17.0f}  {:10.4f}  {:6.4f}  {:6.4f}\n", q.speed_rpm, 1e3 * q.nominal_depth_m, 1e3 * q.depth_m[0],
                             1e3 * q.depth_m[1]);
  if (r.worst_speed)
    std::cout << fmt::format("  lowest depth stable with 95 % probability: {:.4f} mm at {:.0f} rpm\n",
                             1e3 * r.worst_speed->depth_m[0], r.worst_speed->speed_rpm);
}

// --method as the library's method (CLI11 has checked the name).
LobesMethod lobes_method(const std::string& method) { return lobes_method_from(method).value_or(LobesMethod::ZeroOrder); }

void run_lobes(const LobesOptions& o, const Globals& g) {
  check_plot_path(o.plot);
  check_paths(dynamics_paths(o.dyn), {{o.output, "--output"},
                                      {o.envelope, "--envelope"},
                                      {o.probability_output, "--probability-output"},
                                      {o.plot, "--plot"},
                                      {o.plot.empty() ? "" : with_suffix(o.plot, "_probability"), "--plot (probability)"}});
  check_output_extension(o.output, "--output", {".csv"}, "the lobe points as CSV (.csv)");
  check_output_extension(o.envelope, "--envelope", {".csv"}, "the stable envelope as CSV (.csv)");
  check_output_extension(o.probability_output, "--probability-output", {".csv"}, "the probability table as CSV (.csv)");
  LobesStudyOptions so;
  so.cutting = cutting_conditions(o.cut);
  apply_tool_geometry(o.tool, so.cutting);
  so.cutting.check();
  const auto [min_rpm, max_rpm] = parse_range(o.rpm, "--rpm");
  for (double n : {min_rpm, max_rpm})
    check_plausible(plausible::kSpindleSpeedRpm, n, "--rpm", "give spindle speeds in rpm, e.g. --rpm 2000:20000");
  so.speeds = {min_rpm, max_rpm, 0};
  o.speeds.apply(so.speeds);
  so.method = lobes_method(o.method);
  so.fit = dynamics_fit_options(o.dyn);
  so.fit_target = dynamics_fit_target(o.dyn);
  o.parallel.apply(so.parallel);
  so.speed_model = speed_model_from(o.speed_model).value_or(SpeedModel::Automatic);  // the option's values are checked
  o.fields.apply(so);
  if (o.dyn.assembly.empty() && (o.speed_model != "auto" || so.speed_nodes != 0 || so.extrapolate_bearings))
    throw InvalidArgument(
        "--speed-model, --speed-nodes and --extrapolate-bearings need --assembly (the model is evaluated at "
        "each speed)",
        "give --assembly FILE.toml, or drop them");

  const bool uncertain = o.sampling.samples != 0 || !o.probability_output.empty();
  if (uncertain) {
    if (o.dyn.assembly.empty())
      throw InvalidArgument("--samples needs --assembly (the joint is sampled inside the model)",
                            "give --assembly FILE.toml --joint holder-tool=kht.toml");
    if (so.method != LobesMethod::ZeroOrder)
      throw InvalidArgument("--samples runs the zero-order method (a time-domain boundary per sample would take minutes)",
                            "drop --method fd, or --samples");
  }
  const std::vector<JointFile> joints = read_joint_options(g, o.dyn.joints);
  LobesInput input;
  if (uncertain) {
    input.uncertain_joint = sampled_joint(joints);
    so.uncertainty = uncertainty_options(o.sampling);
    o.parallel.apply(so.uncertainty.parallel);  // the command's one --threads
  }
  DynamicsArgs dyn = o.dyn;
  dyn.speed_model = !uncertain ? so.speed_model : SpeedModel::Standstill;
  fill_dynamics_input(dyn, g, joints, input);
  const bool has_frf = input.frfs || input.assembly;
  if (so.method == LobesMethod::ZeroOrder && !has_frf)
    throw InvalidArgument("--method zoa needs the tool point FRF: --frf FILE.csv",
                          "add --frf tool_point.csv (or --assembly FILE.toml), or use --method fd with --mode-x");
  if (so.method != LobesMethod::ZeroOrder && input.x_modes.empty() && !has_frf)
    throw InvalidArgument("--method fd needs modes: --mode-x MASS,ZETA,FN (repeatable) or --frf to fit them from",
                          "e.g. --mode-x 0.04,0.011,922, or --frf tool_point.csv");

  Progress progress(g, uncertain ? fmt::format("lobes: zero-order, nominal and {} joint samples", so.uncertainty.samples)
                       : so.method == LobesMethod::ZeroOrder          ? "lobes: zero-order"
                       : so.method == LobesMethod::SemiDiscretization ? "lobes: semi-discretization boundary"
                                                                      : "lobes: full-discretization boundary");
  LobesStudyResult r;
  try {
    r = run_lobes_study(input, so, progress.part());
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(with_flags(e.what()), with_flags(e.hint()));
  }
  progress.done();
  for (std::string& w : r.warnings) w = with_flags(w);
  if (so.method != LobesMethod::ZeroOrder && so.lobes >= 0)
    r.warnings.push_back("--lobes is used by --method zoa only (fd derives lobe numbers)");
  if (const LobesStudyOptions defaults; so.method == LobesMethod::ZeroOrder &&
                                        (so.tolerance != defaults.tolerance || so.steps != defaults.steps))
    r.warnings.push_back("--tolerance and --intervals are used by the time-domain methods only (--method fd or sd): "
                         "the zero-order lobes have no discretization");
  if (o.depth_steps > 0)
    r.warnings.push_back(
        "--depth-steps is no longer used: the boundary is bracketed by a geometric scan from the neighbouring speed's limit");

  const std::optional<StabilityUncertainty>& su = r.uncertainty;
  std::vector<std::string> comments = {fmt::format("teeth {}, K_t {} N/m^2, K_r {}, entry {:.4f} deg, exit {:.4f} deg",
                                                   so.cutting.teeth, so.cutting.tangential_coefficient, so.cutting.radial_ratio,
                                                   degrees_of(so.cutting.engagement.entry_rad),
                                                   degrees_of(so.cutting.engagement.exit_rad)),
                                       has_frf ? fmt::format("tool point FRF {}", input.frf_name)
                                               : std::string("modal model from --mode-x/--mode-y")};
  if (const std::string tool = tool_geometry_text(so.cutting); !tool.empty()) comments.insert(comments.begin() + 1, tool);
  std::vector<std::string> written;
  if (!o.output.empty()) {
    write_text_file(o.output,
                    r.zero_order ? format_lobes_csv(*r.zero_order, comments) : format_boundary_csv(*r.boundary, comments));
    written.push_back(o.output);
  }
  if (!o.envelope.empty()) {
    write_text_file(o.envelope, format_envelope_csv(r.envelope, comments));
    written.push_back(o.envelope);
  }
  if (su && !o.probability_output.empty()) {
    write_table_csv(
        o.probability_output, probability_table(*su),
        {fmt::format(
             "probability that the cut is stable, over {} samples of the joint of {} (zero-order envelope of each sample's "
             "tool point FRF)",
             su->samples, r.uncertain_joint),
         "spindle speed rpm, axial depth mm, probability 0..1"});
    written.push_back(o.probability_output);
    info(g, fmt::format("wrote {} (probability of stability)", o.probability_output));
  }
  if (o.json) {
    nlohmann::json out = r;
    out["units"] = "SI: depths m, speeds rpm, frequencies Hz, angles rad";
    out["output"] = o.output;
    out["envelope"] = o.envelope;
    out["plot"] = o.plot;
    std::cout << out.dump(2) << '\n';
  } else {
    print_summary(r);
    if (!o.output.empty())
      info(g, r.zero_order ? fmt::format("wrote {} (lobe points)", o.output)
                           : fmt::format("wrote {} ({} speeds)", o.output, r.boundary->boundary.size()));
    if (!o.envelope.empty()) info(g, fmt::format("wrote {} (stable envelope)", o.envelope));
    print_pockets(r, so.pocket_prominence);
    if (su) report_uncertain_lobes(r);
    std::cout << std::flush;
    if (o.output.empty() && o.plot.empty())
      info(g,
           "give --output lobes.csv for every lobe point, --envelope env.csv for the stable envelope, --plot lobes.png for "
           "the figure");
  }
  warn_all(r.warnings);
  if (!o.plot.empty()) {
    std::vector<FigureFile> figures{{plot::lobes_figure(r.figure), o.plot}};
    if (r.probability_figure)
      figures.push_back({plot::probability_map_figure(*r.probability_figure), with_suffix(o.plot, "_probability")});
    draw_figures(g, figures, written);
  }
}

}  // namespace

void add_lobes_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<LobesOptions>();
  CLI::App* c = app.add_subcommand(
      "lobes", "Milling stability lobes from the tool point FRF: zero-order (zoa) or full-discretization (fd)");
  add_dynamics_options(c, o->dyn, g, "fd: ");
  add_cut_options(c, o->cut, "evenly spaced unless --pitch");
  add_tool_geometry_options(c, o->tool);
  c->add_option("--rpm", o->rpm, "Spindle speed range MIN:MAX [rpm] (required)")->required();
  auto* speeds = o->speeds.add(c, option_field(speed_range_fields(), "points"));
  speeds->description(speeds->get_description() + ": the envelope's (zoa) or the boundary's (fd); default 2000 zoa, 200 fd")
      ->default_str("");
  const auto& fields = lobes_study_fields();
  o->fields.add(c, option_field(fields, "lobes"));
  c->add_option("--method", o->method,
                "zoa (zero-order, from the FRF), fd (full-discretization of a modal model in the time domain: flip lobes, "
                "low immersion, several delays) or sd (first-order semi-discretization of the same equation: a cross-check "
                "of fd, slower)")
      ->check(CLI::IsMember({"zoa", "fd", "sd"}))
      ->capture_default_str();
  o->fields.add(c, option_field(fields, "tolerance"));
  o->fields.add(c, option_field(fields, "steps"));
  c->add_option("--depth-steps", o->depth_steps, "No longer used (kept so old scripts run; a warning says so)");
  add_threads_option(c, o->parallel);
  o->fields.add(c, option_field(fields, "max_depth_m"))->check(plausible_value(kDepthMm, "--max-depth"));
  o->fields.add(c, option_field(fields, "pocket_prominence"));
  c->add_option("--output", o->output,
                "Write the lobes (zoa) or the boundary (fd) here: CSV lobe,spindle_speed_rpm,axial_depth_mm,"
                "chatter_frequency_hz,root (zoa) or ...,kind,axial_depth_error_mm,steps (fd) (default: none)");
  c->add_option("--envelope", o->envelope,
                "Write the stable envelope here: CSV spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe (default: none)");
  add_plot_option(c, o->plot,
                  "axial depth [mm] against spindle speed [rpm] with the stable region under the envelope shaded, the "
                  "lobes (zoa) or the boundary (fd) numbered, and their chatter frequency [Hz] in a second panel; with --samples "
                  "also the quantile envelopes, and the probability of stability over speed × depth as a colour map in FILE "
                  "with \"_probability\" before the extension");
  add_joint_option(c, o->dyn.joints)
      ->description(
          "With --assembly: an identified joint instead of the assembly file's (holder-tool=FILE.toml or "
          "spindle-holder=FILE.toml, "
          "from `toolpoint identify --joint-output`)");
  add_sampling_options(c, o->sampling,
                       "zoa with --assembly: the envelope's 5/50/95 % quantiles (drawn in the figure) and the probability of "
                       "stability (--probability-output); --threads applies to them",
                       false);
  c->add_option("--probability-output", o->probability_output,
                "With --samples: the probability that the cut is stable on a spindle speed [rpm] × axial depth [mm] grid "
                "(CSV spindle_speed_rpm,axial_depth_mm,probability_stable)");
  c->add_option("--speed-model", o->speed_model,
                "With --assembly: the tool point dynamics. auto: spinning when the bearings carry speed tables or differ in x "
                "and y, else standstill; standstill: the single-plane FRF at rest (bearing constants, x values); bearings: "
                "at each speed the x-y FRF (H_xx, H_xy, H_yx, H_yy) with the bearings at that speed; spinning: the same with "
                "the spindle spinning (gyroscopic moments). At speed (zoa or fd; fd fits a modal model with x-y pole-residue "
                "terms at each speed): the FRF evaluated at --speed-nodes speeds and midway between them, interpolated in "
                "speed, its error (and fd's fit residuals) estimated and printed")
      ->check(CLI::IsMember({"auto", "standstill", "bearings", "spinning"}))
      ->capture_default_str();
  o->fields.add(c, option_field(fields, "speed_nodes"));
  o->fields.add(c, option_field(fields, "extrapolate_bearings"));
  c->add_flag("--json", o->json, "Machine-readable summary on stdout");
  c->footer(std::string(kFigureFooter) +
            "Examples:\n"
            "  toolpoint lobes --frf tool_point.csv --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.05 --milling down \\\n"
            "      --rpm 5000:25000 --output lobes.csv --envelope envelope.csv --plot lobes.png\n"
            "  toolpoint lobes --method fd --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --kt 6e8 --kn 2e8 \\\n"
            "      --immersion 0.05 --milling down --rpm 5000:25000 --output boundary.csv");
  c->callback([o, &g] { run_lobes(*o, g); });
}

}  // namespace toolpoint::cli
