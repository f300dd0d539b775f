// toolpoint lobes: milling stability lobes — spindle speed [rpm] against limiting axial depth [mm]
// with chatter frequency [Hz] — from the tool point FRF (zero-order approximation) or from a modal
// model (semi-discretization, modes given or fitted from the FRF).
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/assembly_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/modal_fit.hpp"
#include "toolpoint/stability.hpp"

namespace toolpoint::cli {

namespace {

struct LobesOptions {
  // Where the tool point FRFs come from (see tool_point_frfs).
  std::string frf, frf_y, frf_xy, frf_yx, assembly;
  bool rigid_y = false;
  // Cutting.
  int teeth = 0;
  // NaN: not given (so a negative value reaches the library's check and its message).
  double kt = 0.0, kr = std::nan(""), kn = std::nan("");
  double immersion = std::nan(""), entry_deg = std::nan(""), exit_deg = std::nan("");
  std::string milling;
  // Speeds and method.
  std::string rpm, method = "zoa", band;
  int speeds = 0, lobes = -1, intervals = 40, depth_steps = 50, max_modes = 3;
  double max_depth_mm = 0.0;
  std::vector<std::string> mode_x, mode_y;
  std::string output, envelope;
  bool json = false;
};

FrfSeries read_point_frf(const std::string& path, const Globals& g) {
  FrfTable t = read_frf_csv(path);
  if (!t.is_block) return std::move(t.single);
  info(g, fmt::format("{} holds a 2×2 block: using its H entry (w/f)", path));
  return entry(t.block, 0);
}

// The one place the tool point FRFs enter the command: CSV files, or an assembly file whose tool
// point FRF (SHT11's H, seed Eq. 5) serves both directions (a round tool on a round spindle).
// Returns nullopt when no FRF is given (the semi-discretization may run from --mode-x alone).
std::optional<MillingFrfs> tool_point_frfs(const LobesOptions& o, const Globals& g) {
  if (!o.assembly.empty()) {
    if (!o.frf.empty() || !o.frf_y.empty() || !o.frf_xy.empty() || !o.frf_yx.empty())
      throw InvalidArgument("give either --assembly or --frf (with --frf-y, --frf-xy, --frf-yx), not both");
    const LoadedAssembly loaded = load_assembly(o.assembly);
    warn_all(loaded.warnings);
    const AssemblyModel model(loaded.assembly);
    MillingFrfs f;
    f.xx = entry(block_series(loaded.assembly.grid.values(), [&](double x) { return model.tool_point(x); }), 0);
    f.rigid_y = o.rigid_y;
    f.check();
    info(g, fmt::format("tool point FRF from {} ({} frequencies, {:g}–{:g} Hz), used for x and y", o.assembly, f.xx.size(),
                        f.xx.frequency_hz.front(), f.xx.frequency_hz.back()));
    return f;
  }
  if (o.frf.empty()) {
    if (!o.frf_y.empty() || !o.frf_xy.empty() || !o.frf_yx.empty())
      throw InvalidArgument("--frf-y/--frf-xy/--frf-yx need --frf (the x direct FRF)");
    return std::nullopt;
  }
  MillingFrfs f;
  f.xx = read_point_frf(o.frf, g);
  if (!o.frf_y.empty()) f.yy = read_point_frf(o.frf_y, g);
  if (!o.frf_xy.empty()) f.xy = read_point_frf(o.frf_xy, g);
  if (!o.frf_yx.empty()) f.yx = read_point_frf(o.frf_yx, g);
  f.rigid_y = o.rigid_y;
  f.check();
  return f;
}

CuttingConditions cutting_conditions(const LobesOptions& o) {
  CuttingConditions c;
  c.teeth = o.teeth;
  c.tangential_coefficient = o.kt;
  if (std::isnan(o.kr) && std::isnan(o.kn))
    throw InvalidArgument("give the radial cutting coefficient: --kr K_n/K_t or --kn [N/m²]", "e.g. --kr 0.3");
  if (!std::isnan(o.kn) && !(o.kt > 0.0))
    throw InvalidArgument(fmt::format("--kt {} N/m² must be positive", o.kt));
  c.radial_ratio = std::isnan(o.kr) ? o.kn / o.kt : o.kr;
  if (std::isnan(o.entry_deg)) {
    if (std::isnan(o.immersion))
      throw InvalidArgument("give the radial engagement: --immersion a/D with --milling up|down, or --entry/--exit [°]");
    if (o.milling.empty()) throw InvalidArgument("--immersion needs --milling up or --milling down");
    c.engagement = engagement_from_immersion(o.immersion, o.milling == "up" ? MillingDirection::Up : MillingDirection::Down);
  } else {
    c.engagement = engagement_from_degrees(o.entry_deg, o.exit_deg);
  }
  c.check();
  return c;
}

// "MASS,ZETA,FN" → Mode, naming the option in errors.
Mode parse_mode(const std::string& text, const std::string& option) {
  double v[3];
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = k < 2 ? text.find(',', start) : text.size();
    if (end == std::string::npos || (k == 2 && text.find(',', start) != std::string::npos))
      throw InvalidArgument(fmt::format("{} '{}' is not MASS_KG,DAMPING_RATIO,FREQUENCY_HZ", option, text), "e.g. 0.04,0.011,922");
    const char* first = text.data() + start;
    const auto [ptr, ec] = std::from_chars(first, text.data() + end, v[k]);
    if (ec != std::errc() || ptr != text.data() + end || first == ptr)
      throw InvalidArgument(fmt::format("{} '{}': '{}' is not a number", option, text, text.substr(start, end - start)));
    start = end + 1;
  }
  Mode m{v[0], v[1], v[2]};
  m.check(option);
  return m;
}

// Modes for the semi-discretization: given, or fitted from the direct FRFs (y: the y FRF, the x
// modes for a symmetric tool, none when rigid in y).
ModalModel modal_model(const LobesOptions& o, const std::optional<MillingFrfs>& frfs, nlohmann::json& report,
                       std::vector<std::string>& warnings) {
  ModalModel mm;
  ModalFitOptions fo;
  fo.max_modes = o.max_modes;
  if (!o.band.empty()) fo.band_hz = parse_range(o.band, "--band");
  auto fit = [&](const FrfSeries& s, const std::string& name) {
    const ModalFitResult r = fit_modes(s, fo, name);
    for (const auto& w : r.warnings) warnings.push_back(name + ": " + w);
    report["modal_fit"][name] = {{"normalised_residual", r.normalised_residual}, {"modes", r.modes.size()}};
    return r.modal_model();
  };
  if (o.rigid_y && !o.mode_y.empty()) throw InvalidArgument("--rigid-y and --mode-y contradict each other", "drop one of them");
  for (const auto& t : o.mode_x) mm.x.push_back(parse_mode(t, "--mode-x"));
  for (const auto& t : o.mode_y) mm.y.push_back(parse_mode(t, "--mode-y"));
  if (mm.x.empty()) {
    if (!frfs) throw InvalidArgument("--method sd needs modes: --mode-x MASS,ZETA,FN (repeatable) or --frf to fit them from");
    mm.x = fit(frfs->xx, o.frf);
  }
  if (mm.y.empty() && !o.rigid_y) {
    if (frfs && frfs->yy) mm.y = fit(*frfs->yy, o.frf_y);
    else mm.y = mm.x;  // symmetric tool
  }
  if (frfs && frfs->xy) warnings.push_back("--method sd uses uncoupled x and y modes: the cross FRFs are ignored");
  auto list = [](const std::vector<Mode>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (const Mode& m : v) a.push_back({{"modal_mass_kg", m.mass_kg}, {"damping_ratio", m.damping_ratio}, {"frequency_hz", m.frequency_hz}});
    return a;
  };
  report["modes_x"] = list(mm.x);
  report["modes_y"] = list(mm.y);
  return mm;
}

nlohmann::json pockets_json(const std::vector<EnvelopePoint>& pockets) {
  nlohmann::json a = nlohmann::json::array();
  for (const EnvelopePoint& p : pockets)
    a.push_back({{"spindle_speed_rpm", p.speed_rpm}, {"axial_depth_mm", p.depth_m * 1e3}, {"chatter_frequency_hz", p.chatter_hz}, {"lobe", p.lobe}});
  return a;
}

void print_pockets(const std::vector<EnvelopePoint>& pockets, double min_rpm, double max_rpm) {
  if (pockets.empty()) return;
  std::cout << fmt::format("best spindle speeds in {}–{} rpm (peaks of the stable envelope):\n", min_rpm, max_rpm);
  std::cout << "  spindle_speed_rpm  axial_depth_mm  chatter_frequency_hz  lobe\n";
  for (const EnvelopePoint& p : pockets) {
    // lobe −1: sd found no instability up to the maximum depth there.
    const bool capped = p.lobe < 0;
    std::cout << fmt::format("  {:17.0f}  {:>14}  {:>20}  {:>4}\n", p.speed_rpm,
                             fmt::format("{}{:.4f}", capped ? ">= " : "", p.depth_m * 1e3),
                             capped ? std::string("-") : fmt::format("{:.1f}", p.chatter_hz), capped ? std::string("-") : std::to_string(p.lobe));
  }
}

void run_lobes(const LobesOptions& o, const Globals& g) {
  const CuttingConditions cutting = cutting_conditions(o);
  const auto [min_rpm, max_rpm] = parse_range(o.rpm, "--rpm");
  const std::optional<MillingFrfs> frfs = tool_point_frfs(o, g);
  const double max_depth_m = o.max_depth_mm * 1e-3;
  if (!std::isfinite(max_depth_m) || max_depth_m < 0.0)
    throw InvalidArgument(fmt::format("--max-depth {} mm must be ≥ 0", o.max_depth_mm));
  const std::vector<std::string> comments = {
      fmt::format("teeth {}, K_t {} N/m^2, K_r {}, entry {:.4f} deg, exit {:.4f} deg", cutting.teeth,
                  cutting.tangential_coefficient, cutting.radial_ratio, cutting.engagement.entry_rad * 180.0 / kPi,
                  cutting.engagement.exit_rad * 180.0 / kPi),
      o.frf.empty() ? std::string("modal model from --mode-x/--mode-y") : fmt::format("tool point FRF {}", o.frf)};

  nlohmann::json out;
  out["units"] = "spindle speed rpm, axial depth mm, chatter frequency Hz";
  out["method"] = o.method;
  out["cutting"] = {{"teeth", cutting.teeth},
                    {"tangential_coefficient_n_per_m2", cutting.tangential_coefficient},
                    {"radial_ratio", cutting.radial_ratio},
                    {"entry_deg", cutting.engagement.entry_rad * 180.0 / kPi},
                    {"exit_deg", cutting.engagement.exit_rad * 180.0 / kPi}};
  std::vector<std::string> warnings;
  std::vector<EnvelopePoint> envelope;

  if (o.method == "zoa") {
    if (!frfs) throw InvalidArgument("--method zoa needs the tool point FRF: --frf FILE.csv");
    if (!o.mode_x.empty() || !o.mode_y.empty()) warnings.push_back("--mode-x/--mode-y are used by --method sd only");
    ZeroOrderOptions zo;
    zo.lobes = o.lobes;
    zo.speeds = {min_rpm, max_rpm, o.speeds > 0 ? o.speeds : 2000};
    zo.max_depth_m = max_depth_m;
    const ZeroOrderResult r = zero_order_lobes(*frfs, cutting, zo);
    warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
    envelope = r.envelope;
    if (!o.output.empty()) write_text_file(o.output, format_lobes_csv(r, comments));
    out["floor_depth_mm"] = r.floor_depth_m * 1e3;
    out["floor_chatter_frequency_hz"] = r.floor_chatter_hz;
    std::size_t points = 0;
    r.for_each_point([&](const LobePoint&) { ++points; });
    out["lobes"] = r.lobes;
    out["lobe_points"] = points;
    if (!o.json) {
      std::cout << fmt::format("zero-order stability lobes, k = 0…{}: absolute stability limit {:.4f} mm (chatter at {:.1f} Hz)\n",
                               r.lobes, r.floor_depth_m * 1e3, r.floor_chatter_hz);
      if (!o.output.empty()) info(g, fmt::format("wrote {} ({} lobe points)", o.output, points));
    }
  } else {
    if (o.lobes >= 0) warnings.push_back("--lobes is used by --method zoa only (sd derives lobe numbers)");
    const ModalModel mm = modal_model(o, frfs, out, warnings);
    SemiDiscretizationOptions so;
    so.intervals = o.intervals;
    so.speeds = {min_rpm, max_rpm, o.speeds > 0 ? o.speeds : 200};
    so.max_depth_m = max_depth_m;
    so.depth_steps = o.depth_steps;
    const SemiDiscretizationResult r = semi_discretization_boundary(mm, cutting, so);
    warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
    envelope = boundary_envelope(r);
    if (!o.output.empty()) write_text_file(o.output, format_boundary_csv(r, comments));
    const auto lowest = std::min_element(r.boundary.begin(), r.boundary.end(),
                                         [](const BoundaryPoint& a, const BoundaryPoint& b) { return a.depth_m < b.depth_m; });
    const auto flips = std::count_if(r.boundary.begin(), r.boundary.end(), [](const BoundaryPoint& b) { return b.kind == BoundaryKind::Flip; });
    out["intervals"] = r.intervals;
    out["max_depth_mm"] = r.max_depth_m * 1e3;
    out["lowest_boundary"] = {{"spindle_speed_rpm", lowest->speed_rpm}, {"axial_depth_mm", lowest->depth_m * 1e3},
                              {"kind", to_string(lowest->kind)}};
    out["flip_speeds"] = flips;
    if (!o.json) {
      std::cout << fmt::format("semi-discretization boundary ({} intervals, {} speeds, depths up to {:.4g} mm): lowest {:.4f} mm "
                               "at {:.0f} rpm ({}); period-doubling (flip) boundary at {} speed(s)\n",
                               r.intervals, r.boundary.size(), r.max_depth_m * 1e3, lowest->depth_m * 1e3, lowest->speed_rpm,
                               to_string(lowest->kind), flips);
      if (!o.output.empty()) info(g, fmt::format("wrote {} ({} speeds)", o.output, r.boundary.size()));
    }
  }

  const std::vector<EnvelopePoint> pockets = stability_pockets(envelope, 5);
  if (!o.envelope.empty()) {
    write_text_file(o.envelope, format_envelope_csv(envelope, comments));
    info(g, fmt::format("wrote {} (stable envelope)", o.envelope));
  }
  if (o.json) {
    out["pockets"] = pockets_json(pockets);
    out["output"] = o.output;
    out["envelope"] = o.envelope;
    out["warnings"] = warnings;
    std::cout << out.dump(2) << '\n';
  } else {
    print_pockets(pockets, min_rpm, max_rpm);
    if (o.output.empty()) info(g, "give --output lobes.csv for every lobe point, --envelope env.csv for the stable envelope");
  }
  warn_all(warnings);
}

}  // namespace

void add_lobes_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<LobesOptions>();
  CLI::App* c = app.add_subcommand("lobes", "Milling stability lobes from the tool point FRF: zero-order (zoa) or semi-discretization (sd)");
  c->add_option("--assembly", o->assembly, "Assembly file (TOML): its tool point FRF (SHT11, Eq. 5) on its [analysis] grid, for x and y")
      ->check(CLI::ExistingFile);
  c->add_option("--frf", o->frf, "x direct tool point FRF (receptance m/N, Hz): frequency_hz,re,im CSV or a 2×2 block CSV (H used)");
  c->add_option("--frf-y", o->frf_y, "y direct FRF (default: the x FRF, a symmetric tool)");
  auto* xy = c->add_option("--frf-xy", o->frf_xy, "Cross FRF G_xy [m/N] (with --frf-yx; default: none)");
  auto* yx = c->add_option("--frf-yx", o->frf_yx, "Cross FRF G_yx [m/N] (with --frf-xy)");
  xy->needs(yx);
  yx->needs(xy);
  c->add_flag("--rigid-y", o->rigid_y, "The tool is rigid in y: flexible in x only (the 1-DOF model)");
  c->add_option("--teeth", o->teeth, "Number of teeth N (evenly spaced, straight flutes)")->required();
  c->add_option("--kt", o->kt, "Tangential cutting coefficient K_t [N/m²]")->required();
  auto* kr = c->add_option("--kr", o->kr, "Radial cutting coefficient as the ratio K_r = K_n/K_t (dimensionless)");
  auto* kn = c->add_option("--kn", o->kn, "Radial (normal) cutting coefficient K_n [N/m²]");
  kr->excludes(kn);
  auto* imm = c->add_option("--immersion", o->immersion, "Radial immersion a/D in (0, 1] (1: slotting); needs --milling");
  auto* entry_opt = c->add_option("--entry", o->entry_deg, "Entry angle φ_st [°], clockwise from the normal (y) direction, with --exit");
  auto* exit_opt = c->add_option("--exit", o->exit_deg, "Exit angle φ_ex [°] (0 ≤ entry < exit ≤ 180)");
  entry_opt->needs(exit_opt);
  exit_opt->needs(entry_opt);
  imm->excludes(entry_opt);
  imm->excludes(exit_opt);
  c->add_option("--milling", o->milling, "up or down (with --immersion)")->check(CLI::IsMember({"up", "down"}));
  c->add_option("--rpm", o->rpm, "Spindle speed range MIN:MAX [rpm]")->required();
  c->add_option("--speeds", o->speeds, "Points of the speed grid (envelope / sd boundary) (default: 2000 zoa, 200 sd)");
  c->add_option("--lobes", o->lobes, "zoa: lobes k = 0…K (default: enough to cover MIN rpm)");
  c->add_option("--method", o->method, "zoa (zero-order, from the FRF) or sd (semi-discretization of a modal model)")
      ->check(CLI::IsMember({"zoa", "sd"}))
      ->capture_default_str();
  c->add_option("--intervals", o->intervals, "sd: intervals per tooth period (more for chatter far above the tooth passing frequency)")
      ->capture_default_str();
  c->add_option("--depth-steps", o->depth_steps, "sd: coarse depth steps before bisection")->capture_default_str();
  c->add_option("--max-depth", o->max_depth_mm, "Largest axial depth [mm]: zoa drops deeper lobe points, sd scans up to it "
                                                "(default: zoa all, sd 10 × the zero-order floor)");
  c->add_option("--mode-x", o->mode_x, "sd: an x mode MASS_KG,DAMPING_RATIO,FREQUENCY_HZ (repeatable; default: fitted from --frf)");
  c->add_option("--mode-y", o->mode_y, "sd: a y mode MASS_KG,DAMPING_RATIO,FREQUENCY_HZ (repeatable; default: from --frf-y, else the x modes)");
  c->add_option("--max-modes", o->max_modes, "sd: at most N modes fitted per FRF")->capture_default_str();
  c->add_option("--band", o->band, "sd: fit modes only in F1:F2 [Hz] (default: the whole FRF)");
  c->add_option("--output", o->output, "Write the lobes (zoa) or the boundary (sd) here: CSV lobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,root|kind");
  c->add_option("--envelope", o->envelope, "Write the stable envelope here: CSV spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe");
  c->add_flag("--json", o->json, "Machine-readable summary on stdout");
  c->footer(
      "Example:\n"
      "  toolpoint lobes --frf tool_point.csv --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.05 --milling down \\\n"
      "      --rpm 5000:25000 --output lobes.csv --envelope envelope.csv\n"
      "  toolpoint lobes --method sd --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --kt 6e8 --kn 2e8 \\\n"
      "      --immersion 0.05 --milling down --rpm 5000:25000 --output boundary.csv");
  c->callback([o, &g] { run_lobes(*o, g); });
}

}  // namespace toolpoint::cli
