// toolpoint pitch: the variable pitch that maximises the stable axial depth at one spindle speed —
// Budak's closed form as the start, the multi-delay full-discretization limit over a bounded search
// to confirm — against the evenly spaced tool, by the library's pitch study (studies/pitch.hpp).
// Angles in degrees here, radians in the library.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/stability_io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/pitch.hpp"

namespace toolpoint::cli {

namespace {

struct PitchOptions {
  DynamicsArgs dyn;
  ToolGeometryArgs tool;
  CutArgs cut;
  // --rpm, --min-pitch, --max-pitch, --chatter, --window, --search-points, --robustness, --intervals,
  // --max-depth, --depth-steps: from pitch_choice_fields.
  FieldFlags<PitchChoiceOptions> fields;
  std::string pattern = "alternating";
  FieldFlags<ParallelOptions> parallel;  // --threads
  bool json = false;
};

std::string angles_text(const std::vector<double>& rad) {
  std::string s;
  for (double p : rad) s += fmt::format("{}{:.2f}", s.empty() ? "" : "/", degrees_of(p));
  return s;
}

// The pattern's parameters: ΔP, or u and v for the three-angle pattern [degrees].
std::string variation_text(PitchPattern pattern, double u, double v) {
  return pattern == PitchPattern::ThreeAngle ? fmt::format("u {:.2f}°, v {:.2f}°", degrees_of(u), degrees_of(v))
                                             : fmt::format("ΔP {:.2f}°", degrees_of(u));
}

void print_choice(const PitchStudyResult& r) {
  for (const ModalFitSummary& s : r.fits)
    std::cout << fmt::format("modal model of {}: {} mode(s), {:.2f} % residual over {:g}–{:g} Hz\n", s.what, s.modes,
                             100.0 * s.residual, s.band_low_hz, s.band_high_hz);
  const PitchChoice& c = r.choice;
  std::cout << fmt::format("pitch choice at {:g} rpm, {} teeth, {} pattern ({} up to {:.2f}° within the limits):\n", c.speed_rpm,
                           c.teeth, to_string(c.pattern), c.pattern == PitchPattern::ThreeAngle ? "closed-form step" : "ΔP",
                           degrees_of(c.max_variation_rad));
  std::cout << fmt::format("  evenly spaced:          limit {} mm, chatter {:.1f} Hz ({})\n",
                           depth_text_mm(c.uniform.depth_m * 1e3, c.uniform.depth_error_m * 1e3), c.uniform.chatter_hz,
                           to_string(c.uniform.kind));
  std::cout << fmt::format("  Budak's closed form:    {} (pitch {}°) for chatter at {:.1f} Hz: limit {:.4f} mm\n",
                           variation_text(c.pattern, c.closed_form_variation_rad, c.closed_form_second_variation_rad),
                           angles_text(c.closed_form_pitch_rad), c.chatter_hz, c.closed_form_depth_m * 1e3);
  std::cout << fmt::format(
      "  chosen (searched):      {} (pitch {}°): limit {} mm, chatter {:.1f} Hz ({}), {:.2f}× the even tool\n",
      variation_text(c.pattern, c.variation_rad, c.second_variation_rad), angles_text(c.pitch_rad),
      depth_text_mm(c.chosen.depth_m * 1e3, c.chosen.depth_error_m * 1e3), c.chosen.chatter_hz, to_string(c.chosen.kind), c.gain);
  std::cout << fmt::format("  ({} limits computed at {} steps per tooth period; depths searched up to {:.4g} mm)\n",
                           c.evaluations, c.steps, c.max_depth_m * 1e3);
}

void run_pitch(const PitchOptions& o, const Globals& g) {
  check_paths(dynamics_paths(o.dyn), {});
  PitchStudyOptions so;
  so.cutting = cutting_conditions(o.cut);
  apply_tool_geometry(o.tool, so.cutting);
  PitchChoiceOptions& c = so.choice;
  o.fields.apply(c);
  check_plausible(plausible::kSpindleSpeedRpm, c.speed_rpm, "--rpm", "give the target spindle speed in rpm, e.g. --rpm 5000");
  // Below 2π degrees: most likely radians (an even pitch that small needs over 57 teeth).
  for (const auto& [rad, flag] : {std::pair{c.min_pitch_rad, "--min-pitch"}, std::pair{c.max_pitch_rad, "--max-pitch"}}) {
    const double deg = degrees_of(rad);
    if (deg > 0.0 && deg < 2.0 * kPi && so.cutting.teeth <= 57)
      throw InvalidArgument(fmt::format("{} {:g}: a pitch angle under 6.3°, most likely radians", flag, deg),
                            "give degrees, e.g. --min-pitch 70 --max-pitch 110 for 4 teeth");
  }
  c.pattern = o.pattern == "linear"        ? PitchPattern::Linear
              : o.pattern == "three-angle" ? PitchPattern::ThreeAngle
                                           : PitchPattern::Alternating;
  o.parallel.apply(c.parallel);
  so.fit = dynamics_fit_options(o.dyn);
  so.fit_target = dynamics_fit_target(o.dyn);
  LobesInput input;
  fill_dynamics_input(o.dyn, g, read_joint_options(g, o.dyn.joints), input);
  if (input.x_modes.empty() && !input.frfs && !input.assembly)
    throw InvalidArgument("pitch needs modes: --mode-x MASS,ZETA,FN (repeatable) or --frf to fit them from",
                          "e.g. --mode-x 0.04,0.011,922 --rigid-y, or --frf tool_point.csv");
  Progress progress(g, "pitch: full-discretization search");
  PitchStudyResult r;
  try {
    r = run_pitch_study(input, so);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(with_flags(e.what()), with_flags(e.hint()));
  }
  progress.done();
  for (std::string& w : r.warnings) w = with_flags(w);
  if (o.json) {
    nlohmann::json out = r;
    out["units"] = "SI: depths m, speeds rpm, frequencies Hz, angles rad";
    std::cout << out.dump(2) << '\n';
  } else {
    print_choice(r);
    std::cout << std::flush;
  }
  warn_all(r.warnings);
}

}  // namespace

void add_pitch_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<PitchOptions>();
  CLI::App* c = app.add_subcommand(
      "pitch", "The variable pitch that maximises the stable depth at one speed: Budak's rule, confirmed by full-discretization");
  add_dynamics_options(c, o->dyn, g, "");
  add_cut_options(c, o->cut, "≥ 2: the pitch is chosen, no --pitch");
  add_tool_geometry_options(c, o->tool);
  const auto& fields = pitch_choice_fields();
  o->fields.add(c, option_field(fields, "speed_rpm"))->required();
  c->add_option(
       "--pattern", o->pattern,
       "alternating (P1/P2/P1/…, an even number of teeth), linear (P, P+ΔP, P+2ΔP, …: N angles, e.g. three for 3 teeth) "
       "or three-angle (P0/P1/P2/P0/…, a multiple of 3 teeth: two parameters, searched in 2-D)")
      ->check(CLI::IsMember({"alternating", "linear", "three-angle"}))
      ->capture_default_str();
  for (const char* name : {"min_pitch_rad", "max_pitch_rad", "chatter_hz", "window", "search_points", "robustness", "steps"})
    o->fields.add(c, option_field(fields, name));
  o->fields.add(c, option_field(fields, "max_depth_m"))->check(plausible_value(kDepthMm, "--max-depth"));
  o->fields.add(c, option_field(fields, "depth_steps"));
  add_threads_option(c, o->parallel);
  c->add_flag("--json", o->json, "Machine-readable result on stdout (angles in radians)");
  c->footer(
      "Example:\n"
      "  toolpoint pitch --mode-x 0.03993,0.011,922 --rigid-y --teeth 4 --kt 6e8 --kr 0.3 --immersion 0.5 \\\n"
      "      --milling down --rpm 5000 --min-pitch 60 --max-pitch 120");
  c->callback([o, &g] { run_pitch(*o, g); });
}

}  // namespace toolpoint::cli
