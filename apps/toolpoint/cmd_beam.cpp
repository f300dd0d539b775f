// toolpoint beam: one free–free Timoshenko segment — natural frequencies and end receptances.
// Units: SI (m, kg, Pa); frequencies in Hz. --plot draws the written block through gnuplot:
// |H| [m/N] and phase of H [deg], |P| [rad/(N·m)] and phase of P [deg], peaks of |H| labelled
// with their frequency [Hz]; L and N are in the CSV only.
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/model/beam.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/studies/beam.hpp"

namespace toolpoint::cli {

namespace {

struct BeamOptions {
  // --length, --diameter, --inner-diameter, --modes, --speed (beam_study_fields); --modal-terms,
  // --static-residual (modal_fields).
  FieldFlags<BeamStudyOptions> fields;
  FieldFlags<ModalOptions> modal;
  double youngs_modulus = 2.0e11, density = 7800.0, poisson = 0.3, loss_factor = 0.0, shear_modulus = 0.0;
  double shear_coefficient = 0.0;
  std::string shear_model = "hutchinson";
  std::string frequencies, output, method = "exact", block = "11", plot;
  bool json = false;
  std::string campbell, campbell_plot;
};

// "START:STOP:STEP" in rpm (START ≥ 0: standstill allowed) → the speeds, at most 1000.
std::vector<double> parse_speed_grid(const std::string& text) {
  const std::size_t a = text.find(':'), b = a == std::string::npos ? a : text.find(':', a + 1);
  if (b == std::string::npos)
    throw InvalidArgument(fmt::format("--campbell '{}' is not START:STOP:STEP (rpm)", text), "e.g. --campbell 0:60000:2000");
  const double start = parse_value(text.substr(0, a), "--campbell"),
               stop = parse_value(text.substr(a + 1, b - a - 1), "--campbell"),
               step = parse_value(text.substr(b + 1), "--campbell");
  if (!(start >= 0.0 && stop > start && step > 0.0) || (stop - start) / step > 1000.0)
    throw InvalidArgument(fmt::format("--campbell {}: need 0 ≤ START < STOP and STEP > 0, at most 1000 speeds", text),
                          "e.g. --campbell 0:60000:2000");
  std::vector<double> v;
  for (int k = 0; start + k * step <= stop * (1.0 + 1e-12); ++k) v.push_back(start + k * step);
  return v;
}

void run_beam(const BeamOptions& o, const Globals& g) {
  check_plot_path(o.plot);  // before any work: a typo in the figure name should not cost a run
  check_plot_path(o.campbell_plot, "--campbell-plot");
  check_paths({}, {{o.output, "--output"}, {o.plot, "--plot"}, {o.campbell_plot, "--campbell-plot"}});
  if (!o.campbell_plot.empty() && o.campbell.empty())
    throw InvalidArgument("--campbell-plot needs --campbell START:STOP:STEP (the speeds, rpm)", "add --campbell 0:60000:2000");
  check_output_extension(o.output, "--output", {".csv"}, "a 2×2 receptance block as FRF CSV (.csv)");
  if (!o.plot.empty() && (o.frequencies.empty() || o.output.empty()))
    throw InvalidArgument("--plot needs --frequencies and --output (the figure draws the receptance written there)",
                          "add --frequencies 10:20000:10 --output tip.csv");
  if (!o.frequencies.empty() && o.output.empty())
    throw InvalidArgument("--frequencies needs --output FILE.csv for the receptance", "add --output tip.csv");
  BeamStudyOptions so;
  if (!o.frequencies.empty()) so.modes = 0;  // the receptance asked for: the modes only when --modes says so
  o.fields.apply(so);
  o.modal.apply(so.modal);
  so.material = {"beam", o.youngs_modulus, o.poisson, o.shear_modulus, o.density, o.loss_factor};
  if (o.shear_coefficient != 0.0) so.shear_coefficient = o.shear_coefficient;
  so.shear_model = o.shear_model == "cowper" ? ShearModel::Cowper : ShearModel::Hutchinson;
  if (!o.frequencies.empty()) so.frequency_hz = parse_frequency_grid(o.frequencies, "--frequencies").values();
  so.block = o.block == "11" ? EndBlock::T11 : o.block == "12" ? EndBlock::T12 : o.block == "21" ? EndBlock::T21 : EndBlock::T22;
  so.method = o.method == "modal" ? BeamMethod::Modal : BeamMethod::Exact;
  if (!o.campbell.empty()) so.campbell_rpm = parse_speed_grid(o.campbell);
  if (so.modes == 0 && so.frequency_hz.empty())
    throw InvalidArgument("--modes 0 without --frequencies: nothing to compute",
                          "give --modes 1 or more, or --frequencies START:STOP:STEP --output FILE.csv for the receptance");
  if (const ModalOptions defaults; so.method == BeamMethod::Exact &&
                                   (so.modal.modes != defaults.modes || so.modal.static_residual != defaults.static_residual))
    warn("--modal-terms and --static-residual are used by --method modal only: the exact receptance has no truncation");
  const BeamStudy r = run_beam_study(so);
  const double kappa = r.section.shear_coefficient;

  // The study's JSON less its warnings (shown on stderr), and the files written.
  const nlohmann::json study = r;
  nlohmann::json out;
  out["units"] = "SI: m, kg, N, Pa; frequencies in Hz";
  out["section"] = study["section"];
  if (!r.modes.empty()) {
    out["modes"] = study["modes"];
    if (!o.json) {
      std::cout << fmt::format("free–free Timoshenko beam: L = {} m, D = {} m, d = {} m, κ = {:.6f}, cut-off {:.3f} Hz\n",
                               so.length, so.outer_diameter, so.inner_diameter, kappa, r.section.cutoff_frequency_hz);
      std::cout << "mode  frequency_hz  branch\n";
      int i = 1;
      for (const FreeMode& m : r.modes)
        std::cout << fmt::format("{:4d}  {:12.3f}  {}\n", i++, m.frequency_hz,
                                 m.above_cutoff ? "above cut-off" : "below cut-off");
    }
  }

  if (r.whirl) {
    out["speed_rpm"] = r.speed_rpm;
    out["whirl"] = study["whirl"];
    if (!o.json) {
      std::cout << fmt::format("spinning at {} rpm: natural frequencies per whirl [Hz]", r.speed_rpm);
      if (std::isfinite(r.whirl->conical_hz))
        std::cout << fmt::format(" (conical mode, forward: {:.3f} Hz)", r.whirl->conical_hz);
      std::cout << "\nmode  forward_hz  backward_hz\n";
      for (std::size_t k = 0; k < r.whirl->forward_hz.size(); ++k)
        std::cout << fmt::format("{:4d}  {:10.3f}  {:11.3f}\n", k + 1, r.whirl->forward_hz[k], r.whirl->backward_hz[k]);
    }
  }
  if (!r.campbell.empty()) {
    out["campbell"] = study["campbell"];
    if (!o.campbell_plot.empty()) out["campbell_plot"] = o.campbell_plot;
  }
  if (!o.frequencies.empty()) {
    write_frf_csv(
        o.output, r.receptance,
        {fmt::format("free-free Timoshenko beam, block T{} (end 1 = x = L, the outer end), method {}", o.block, r.method),
         fmt::format("L = {} m, D = {} m, d = {} m, E = {} Pa, nu = {}, rho = {} kg/m^3, eta = {}, kappa = {}", so.length,
                     so.outer_diameter, so.inner_diameter, o.youngs_modulus, o.poisson, o.density, o.loss_factor, kappa)});
    out["output"] = o.output;
    out["points"] = r.receptance.size();
    info(g, fmt::format("wrote {} ({} frequencies, block T{})", o.output, r.receptance.size(), o.block));
    if (!o.plot.empty()) out["plot"] = o.plot;
  }
  warn_all(r.warnings);
  if (o.json) std::cout << out.dump(2) << '\n';
  if (!o.campbell_plot.empty())
    draw_figures(g,
                 {{campbell_figure(r,
                                   fmt::format("Campbell diagram, free–free segment L = {} m, D = {} m", so.length, so.outer_diameter)),
                   o.campbell_plot}},
                 {});
  if (!o.plot.empty())
    draw_figures(g,
                 {{plot::receptance_figure(r.receptance,
                                           fmt::format("Free–free Timoshenko beam, block T_{{{}}}: L = {} m, D = {} m", o.block,
                                                       so.length, so.outer_diameter),
                                           o.block),
                   o.plot}},
                 {o.output});
}

}  // namespace

void add_beam_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<BeamOptions>();
  CLI::App* c = app.add_subcommand("beam", "Free–free Timoshenko beam: natural frequencies and end receptances (seed Eq. 9–14)");
  const auto& fields = beam_study_fields();
  o->fields.add(c, option_field(fields, "length"))->required();
  o->fields.add(c, option_field(fields, "outer_diameter"))->required();
  o->fields.add(c, option_field(fields, "inner_diameter"));
  c->add_option("--youngs-modulus", o->youngs_modulus, "Young's modulus E [Pa]")
      ->capture_default_str()
      ->check(plausible_value(plausible::kYoungsModulus, "--youngs-modulus"));
  c->add_option("--density", o->density, "Density ρ [kg/m³]")
      ->capture_default_str()
      ->check(plausible_value(plausible::kDensity, "--density"));
  c->add_option("--poisson", o->poisson, "Poisson's ratio ν [-], in (−1, 0.5)")->capture_default_str();
  c->add_option("--shear-modulus", o->shear_modulus, "Shear modulus G [Pa] (default: E/(2(1+ν)))")
      ->check(plausible_value(plausible::kShearModulus, "--shear-modulus"));
  c->add_option("--loss-factor", o->loss_factor, "Structural loss factor η [-], ≥ 0 (complex moduli E(1+iη), G(1+iη))")
      ->capture_default_str()
      ->check(plausible_value(plausible::kLossFactor, "--loss-factor"));
  c->add_option("--shear-coefficient", o->shear_coefficient,
                "Shear coefficient κ [-] (default: from --shear-model, Poisson's ratio and the diameters)")
      ->check(plausible_value(plausible::kShearCoefficient, "--shear-coefficient"));
  c->add_option("--shear-model", o->shear_model, "κ formula for circular sections: hutchinson or cowper")
      ->check(CLI::IsMember({"hutchinson", "cowper"}))
      ->capture_default_str();
  CLI::Option* modes = o->fields.add(c, option_field(fields, "modes"));
  modes->description(modes->get_description() + "; with --frequencies none unless given");
  c->add_option("--frequencies", o->frequencies,
                "Frequency grid START:STOP:STEP [Hz] for the receptance output (needs --output)");
  c->add_option("--output", o->output, "Write the receptance block here (FRF CSV; H m/N, L 1/N, N rad/N, P rad/(N m))");
  add_plot_option(c, o->plot,
                  "the receptance (needs --frequencies and --output): |H| [m/N], phase of H [deg], |P| [rad/(N·m)], "
                  "phase of P [deg] against frequency [Hz], peaks of |H| labelled [Hz]");
  c->add_option("--block", o->block, "Which end block to write: 11 (end 1 = the outer end), 12, 21 or 22")
      ->check(CLI::IsMember({"11", "12", "21", "22"}))
      ->capture_default_str();
  c->add_option("--method", o->method, "Receptance method: exact (closed form) or modal (seed Eq. 11–14 summation)")
      ->check(CLI::IsMember({"exact", "modal"}))
      ->capture_default_str();
  for (const auto& f : modal_fields()) o->modal.add(c, f);
  o->fields.add(c, option_field(fields, "speed_rpm"));
  c->add_option("--campbell", o->campbell,
                "Speeds START:STOP:STEP [rpm] of a Campbell diagram: each whirl's natural frequencies against speed (JSON "
                "campbell)");
  c->add_option("--campbell-plot", o->campbell_plot,
                "Draw the Campbell diagram in FILE (.png, .svg or .pdf; needs --campbell): natural frequency [Hz] against "
                "spindle speed [rpm], forward solid, backward dashed, the once-per-revolution line")
      ->option_text("FILE");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(std::string(kFigureFooter) +
            "Examples:\n"
            "  toolpoint beam --length 0.1 --diameter 0.05 --modes 6\n"
            "  toolpoint beam --length 0.123 --diameter 0.016 --youngs-modulus 5.8e11 --density 14500 \\\n"
            "      --loss-factor 0.002 --frequencies 10:20000:10 --output tool_T11.csv --plot tool_T11.png\n"
            "  toolpoint beam --length 0.15 --diameter 0.04 --speed 30000 --modes 4 \\\n"
            "      --campbell 0:60000:5000 --campbell-plot campbell.png");
  c->callback([o, &g] { run_beam(*o, g); });
}

}  // namespace toolpoint::cli
