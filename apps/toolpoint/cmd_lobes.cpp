// toolpoint lobes: milling stability lobes — spindle speed [rpm] against limiting axial depth [mm]
// with chatter frequency [Hz] — from the tool point FRF (zero-order approximation) or from a modal
// model (semi-discretization, modes given or fitted from the FRF). --plot draws the lobes (or the
// sd boundary) with the stable region shaded, lobe numbers and the chatter frequency panel.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/assembly_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/modal_fit.hpp"
#include "toolpoint/plot.hpp"
#include "toolpoint/stability.hpp"
#include "progress.hpp"

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
  std::string output, envelope, plot;
  bool json = false;
};

// The one place the tool point FRFs enter the command: CSV files, or an assembly file whose tool
// point FRF (SHT11's H, seed Eq. 5) serves both directions (a round tool on a round spindle).
// Returns nullopt when no FRF is given (the semi-discretization may run from --mode-x alone).
std::optional<MillingFrfs> tool_point_frfs(const LobesOptions& o, const Globals& g) {
  if (!o.assembly.empty()) {
    if (!o.frf.empty() || !o.frf_y.empty() || !o.frf_xy.empty() || !o.frf_yx.empty())
      throw InvalidArgument("give either --assembly or --frf (with --frf-y, --frf-xy, --frf-yx), not both",
                            "drop --assembly to use measured FRFs, or drop the --frf options");
    const LoadedModel lm = load_model(g, o.assembly);
    MillingFrfs f;
    f.xx = entry(lm.model.tool_point(lm.loaded.assembly.grid.values()), 0);
    f.rigid_y = o.rigid_y;
    f.check();
    info(g, fmt::format("tool point FRF from {} ({} frequencies, {:g}–{:g} Hz), used for x and y", o.assembly, f.xx.size(),
                        f.xx.frequency_hz.front(), f.xx.frequency_hz.back()));
    return f;
  }
  if (o.frf.empty()) {
    if (!o.frf_y.empty() || !o.frf_xy.empty() || !o.frf_yx.empty())
      throw InvalidArgument("--frf-y/--frf-xy/--frf-yx need --frf (the x direct FRF)", "add --frf tool_point_x.csv");
    return std::nullopt;
  }
  MillingFrfs f;
  f.xx = read_point_frf(g, o.frf);
  if (!o.frf_y.empty()) f.yy = read_point_frf(g, o.frf_y);
  if (!o.frf_xy.empty()) f.xy = read_point_frf(g, o.frf_xy);
  if (!o.frf_yx.empty()) f.yx = read_point_frf(g, o.frf_yx);
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
    throw InvalidArgument(fmt::format("--kt {} N/m² must be positive", o.kt), "e.g. --kt 6e8 (N/m², a typical steel value)");
  c.radial_ratio = std::isnan(o.kr) ? o.kn / o.kt : o.kr;
  if (std::isnan(o.entry_deg)) {
    if (std::isnan(o.immersion))
      throw InvalidArgument("give the radial engagement: --immersion a/D with --milling up|down, or --entry/--exit [°]",
                            "e.g. --immersion 0.5 --milling down");
    if (o.milling.empty()) throw InvalidArgument("--immersion needs --milling up or --milling down", "add --milling down");
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
      throw InvalidArgument(fmt::format("{} '{}': '{}' is not a number", option, text, text.substr(start, end - start)),
                            "write MASS_KG,DAMPING_RATIO,FREQUENCY_HZ, e.g. 0.04,0.011,922");
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
    if (!frfs)
      throw InvalidArgument("--method sd needs modes: --mode-x MASS,ZETA,FN (repeatable) or --frf to fit them from",
                            "e.g. --mode-x 0.04,0.011,922, or --frf tool_point.csv");
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

// The top of a lobes figure's depth axis: 5× the shallowest envelope depth (the plot module's own
// default), so lobe points far above it can be left out of the figure's data.
double figure_top_m(const std::vector<EnvelopePoint>& envelope) {
  double floor = std::numeric_limits<double>::infinity();
  for (const EnvelopePoint& e : envelope)
    if (std::isfinite(e.depth_m) && e.depth_m > 0.0) floor = std::min(floor, e.depth_m);
  return 5.0 * floor;
}

void set_envelope(plot::LobesFigureData& d, const std::vector<EnvelopePoint>& envelope) {
  for (const EnvelopePoint& e : envelope) {
    d.envelope_rpm.push_back(e.speed_rpm);
    d.envelope_depth_m.push_back(e.depth_m);
  }
}

// Zero-order lobes for the figure: one polyline per lobe, broken (NaN) between its two roots and
// wherever grid frequencies are skipped (speed out of range, no positive depth, or deeper than
// twice the axis top: such points only thin the data, the visible part stays whole).
plot::LobesFigureData zoa_figure_data(const ZeroOrderResult& r) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  plot::LobesFigureData d;
  set_envelope(d, r.envelope);
  const double keep_below = 2.0 * figure_top_m(r.envelope);
  const std::vector<double>& grid = r.table.chatter_hz;
  std::size_t last_index = grid.size();
  int last_root = -1;
  r.for_each_point([&](const LobePoint& p) {
    if (!(p.depth_m <= keep_below)) return;
    if (d.lobes.empty() || d.lobes.back().number != p.lobe) {
      d.lobes.push_back({p.lobe, {}, {}, {}});
      last_index = grid.size();
    }
    plot::Lobe& l = d.lobes.back();
    const auto index = static_cast<std::size_t>(std::lower_bound(grid.begin(), grid.end(), p.chatter_hz) - grid.begin());
    if (!l.depth_m.empty() && (p.root != last_root || index != last_index + 1)) {
      l.spindle_speed_rpm.push_back(nan);
      l.depth_m.push_back(nan);
      l.chatter_frequency_hz.push_back(nan);
    }
    l.spindle_speed_rpm.push_back(p.speed_rpm);
    l.depth_m.push_back(p.depth_m);
    l.chatter_frequency_hz.push_back(p.chatter_hz);
    last_index = index;
    last_root = p.root;
  });
  return d;
}

// The semi-discretization boundary for the figure: one curve per lobe number over the speed grid
// (NaN at speeds another lobe limits), speeds with no instability left to the envelope alone.
plot::LobesFigureData sd_figure_data(const SemiDiscretizationResult& r) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  plot::LobesFigureData d;
  set_envelope(d, boundary_envelope(r));
  std::vector<int> numbers;
  for (const BoundaryPoint& b : r.boundary)
    if (b.kind != BoundaryKind::None && std::find(numbers.begin(), numbers.end(), b.lobe) == numbers.end()) numbers.push_back(b.lobe);
  std::sort(numbers.begin(), numbers.end());
  for (int k : numbers) {
    plot::Lobe l{k, {}, {}, {}};
    for (const BoundaryPoint& b : r.boundary) {
      const bool mine = b.kind != BoundaryKind::None && b.lobe == k;
      l.spindle_speed_rpm.push_back(b.speed_rpm);
      l.depth_m.push_back(mine ? b.depth_m : nan);
      l.chatter_frequency_hz.push_back(mine ? b.chatter_hz : nan);
    }
    d.lobes.push_back(std::move(l));
  }
  return d;
}

void run_lobes(const LobesOptions& o, const Globals& g) {
  check_plot_path(o.plot);
  const CuttingConditions cutting = cutting_conditions(o);
  const auto [min_rpm, max_rpm] = parse_range(o.rpm, "--rpm");
  const std::optional<MillingFrfs> frfs = tool_point_frfs(o, g);
  const double max_depth_m = o.max_depth_mm * 1e-3;
  if (!std::isfinite(max_depth_m) || max_depth_m < 0.0)
    throw InvalidArgument(fmt::format("--max-depth {} mm must be ≥ 0", o.max_depth_mm), "e.g. --max-depth 10, or 0 for automatic");
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
  std::vector<std::string> written;
  plot::LobesFigureData figure;

  if (o.method == "zoa") {
    if (!frfs)
      throw InvalidArgument("--method zoa needs the tool point FRF: --frf FILE.csv",
                            "add --frf tool_point.csv (or --assembly FILE.toml), or use --method sd with --mode-x");
    if (!o.mode_x.empty() || !o.mode_y.empty()) warnings.push_back("--mode-x/--mode-y are used by --method sd only");
    ZeroOrderOptions zo;
    zo.lobes = o.lobes;
    zo.speeds = {min_rpm, max_rpm, o.speeds > 0 ? o.speeds : 2000};
    zo.max_depth_m = max_depth_m;
    const ZeroOrderResult r = zero_order_lobes(*frfs, cutting, zo);
    warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
    envelope = r.envelope;
    if (!o.output.empty()) write_text_file(o.output, format_lobes_csv(r, comments));
    if (!o.plot.empty()) {
      figure = zoa_figure_data(r);
      figure.title = fmt::format("Zero-order stability lobes, k = 0…{}: limit {:.4g} mm at {:.0f} Hz", r.lobes,
                                 r.floor_depth_m * 1e3, r.floor_chatter_hz);
    }
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
    Progress progress(g, "lobes: semi-discretization boundary");
    so.progress = progress.part();
    const SemiDiscretizationResult r = semi_discretization_boundary(mm, cutting, so);
    progress.done();
    warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
    envelope = boundary_envelope(r);
    if (!o.output.empty()) write_text_file(o.output, format_boundary_csv(r, comments));
    if (!o.plot.empty()) {
      figure = sd_figure_data(r);
      figure.title = fmt::format("Semi-discretization stability boundary ({} intervals per tooth period)", r.intervals);
    }
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

  if (!o.output.empty()) written.push_back(o.output);
  const std::vector<EnvelopePoint> pockets = stability_pockets(envelope, 5);
  if (!o.envelope.empty()) {
    write_text_file(o.envelope, format_envelope_csv(envelope, comments));
    info(g, fmt::format("wrote {} (stable envelope)", o.envelope));
    written.push_back(o.envelope);
  }
  if (o.json) {
    out["pockets"] = pockets_json(pockets);
    out["output"] = o.output;
    out["envelope"] = o.envelope;
    out["plot"] = o.plot;
    out["warnings"] = warnings;
    std::cout << out.dump(2) << '\n';
  } else {
    print_pockets(pockets, min_rpm, max_rpm);
    std::cout << std::flush;
    if (o.output.empty() && o.plot.empty())
      info(g, "give --output lobes.csv for every lobe point, --envelope env.csv for the stable envelope, --plot lobes.png for "
              "the figure");
  }
  warn_all(warnings);
  if (!o.plot.empty()) draw_figures(g, {{plot::lobes_figure(figure), o.plot}}, written);
}

}  // namespace

void add_lobes_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<LobesOptions>();
  CLI::App* c = app.add_subcommand("lobes", "Milling stability lobes from the tool point FRF: zero-order (zoa) or semi-discretization (sd)");
  c->add_option("--assembly", o->assembly,
                "Assembly file (TOML, SI units): its tool point FRF (SHT11's H, Eq. 5) on its [analysis] grid, for x and y "
                "(instead of --frf)");
  c->add_option("--frf", o->frf, std::string("x direct tool point FRF G_xx: ") + kPointFrfHelp);
  add_frf_read_options(c, g);
  c->add_option("--frf-y", o->frf_y, "y direct FRF G_yy [m/N], any format as --frf (default: the x FRF, a symmetric tool)");
  auto* xy = c->add_option("--frf-xy", o->frf_xy, "Cross FRF G_xy [m/N], any format as --frf (with --frf-yx; default: none)");
  auto* yx = c->add_option("--frf-yx", o->frf_yx, "Cross FRF G_yx [m/N], any format as --frf (with --frf-xy; default: none)");
  xy->needs(yx);
  yx->needs(xy);
  c->add_flag("--rigid-y", o->rigid_y, "The tool is rigid in y: flexible in x only (the 1-DOF model)");
  c->add_option("--teeth", o->teeth, "Number of teeth N [-], ≥ 1 (evenly spaced, straight flutes) (required)")->required();
  c->add_option("--kt", o->kt, "Tangential cutting coefficient K_t [N/m²], > 0 (required)")->required();
  auto* kr = c->add_option("--kr", o->kr, "Radial cutting coefficient as the ratio K_r = K_n/K_t [-], ≥ 0 (this or --kn required)");
  auto* kn = c->add_option("--kn", o->kn, "Radial (normal) cutting coefficient K_n [N/m²], ≥ 0 (this or --kr required)");
  kr->excludes(kn);
  auto* imm = c->add_option("--immersion", o->immersion, "Radial immersion a/D [-] in (0, 1] (1: slotting); needs --milling (this or --entry/--exit required)");
  auto* entry_opt = c->add_option("--entry", o->entry_deg, "Entry angle φ_st [°], clockwise from the normal (y) direction, with --exit");
  auto* exit_opt = c->add_option("--exit", o->exit_deg, "Exit angle φ_ex [°] (0 ≤ entry < exit ≤ 180)");
  entry_opt->needs(exit_opt);
  exit_opt->needs(entry_opt);
  imm->excludes(entry_opt);
  imm->excludes(exit_opt);
  c->add_option("--milling", o->milling, "Milling direction with --immersion: up or down (no default)")->check(CLI::IsMember({"up", "down"}));
  c->add_option("--rpm", o->rpm, "Spindle speed range MIN:MAX [rpm] (required)")->required();
  c->add_option("--speeds", o->speeds, "Points of the speed grid [-] for the envelope (zoa) or the boundary (sd) (default: 2000 zoa, 200 sd)");
  c->add_option("--lobes", o->lobes, "zoa: lobes k = 0…K [-] (default: enough to cover MIN rpm)");
  c->add_option("--method", o->method, "zoa (zero-order, from the FRF) or sd (semi-discretization of a modal model)")
      ->check(CLI::IsMember({"zoa", "sd"}))
      ->capture_default_str();
  c->add_option("--intervals", o->intervals, "sd: intervals per tooth period [-], 4…2000 (more for chatter far above the tooth passing frequency)")
      ->capture_default_str();
  c->add_option("--depth-steps", o->depth_steps, "sd: coarse depth steps [-] before bisection")->capture_default_str();
  c->add_option("--max-depth", o->max_depth_mm, "Largest axial depth [mm]: zoa drops deeper lobe points, sd scans up to it "
                                                "(default: zoa all, sd 10 × the zero-order floor)");
  c->add_option("--mode-x", o->mode_x, "sd: an x mode MASS_KG,DAMPING_RATIO,FREQUENCY_HZ (repeatable; default: fitted from --frf)");
  c->add_option("--mode-y", o->mode_y, "sd: a y mode MASS_KG,DAMPING_RATIO,FREQUENCY_HZ (repeatable; default: from --frf-y, else the x modes)");
  c->add_option("--max-modes", o->max_modes, "sd: at most N modes [-] fitted per FRF, 1…20")->capture_default_str();
  c->add_option("--band", o->band, "sd: fit modes only in F1:F2 [Hz] (default: the whole FRF)");
  c->add_option("--output", o->output,
                "Write the lobes (zoa) or the boundary (sd) here: CSV lobe,spindle_speed_rpm,axial_depth_mm,"
                "chatter_frequency_hz,root|kind (default: none)");
  c->add_option("--envelope", o->envelope,
                "Write the stable envelope here: CSV spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe (default: none)");
  add_plot_option(c, o->plot,
                  "axial depth [mm] against spindle speed [rpm] with the stable region under the envelope shaded, the "
                  "lobes (zoa) or the boundary (sd) numbered, and their chatter frequency [Hz] in a second panel");
  c->add_flag("--json", o->json, "Machine-readable summary on stdout");
  c->footer(std::string(kFigureFooter) +
      "Examples:\n"
      "  toolpoint lobes --frf tool_point.csv --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.05 --milling down \\\n"
      "      --rpm 5000:25000 --output lobes.csv --envelope envelope.csv --plot lobes.png\n"
      "  toolpoint lobes --method sd --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --kt 6e8 --kn 2e8 \\\n"
      "      --immersion 0.05 --milling down --rpm 5000:25000 --output boundary.csv");
  c->callback([o, &g] { run_lobes(*o, g); });
}

}  // namespace toolpoint::cli
