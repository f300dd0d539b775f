// toolpoint modes: modal parameters (natural frequency Hz, damping ratio, modal mass kg) of a point
// receptance FRF [m/N] by peak picking and a Levenberg–Marquardt fit, with the fit quality.
// --output writes the fitted receptance [m/N] on the measured frequencies [Hz] of the band;
// --plot overlays it on the measured FRF with the fitted modes labelled.
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/modal_fit.hpp"
#include "toolpoint/plot/plot.hpp"

namespace toolpoint::cli {

namespace {

struct ModesOptions {
  std::string file, band, output, plot;
  std::optional<std::size_t> dataset;
  // --max-modes, --min-prominence: from their definitions (modal_fit_fields).
  FieldFlags<ModalFitOptions> fields;
  bool no_residuals = false, json = false;
};

void run_modes(const ModesOptions& o, const Globals& g) {
  ModalFitOptions fo;
  o.fields.apply(fo);
  fo.residual_terms = !o.no_residuals;
  if (!o.band.empty()) fo.band_hz = parse_range(o.band, "--band");
  fo.check();
  check_plot_path(o.plot);
  const FrfFormat out_format = o.output.empty() ? FrfFormat::Csv : output_frf_format(o.output);
  check_paths({{o.file, "input"}}, {{o.output, "--output"}, {o.plot, "--plot"}});
  const FrfSeries frf = read_point_frf(g, o.file, o.dataset);
  const ModalFitStudy study = run_modal_fit_study(frf, fo, o.file);
  const ModalFitResult& r = study.fit;

  if (!o.output.empty()) {
    FrfFileData fitted;
    fitted.single = study.fitted;
    std::string modes;
    for (const FittedMode& m : r.modes)
      modes += fmt::format("{}{:.6g} Hz, zeta {:.4g}, {:.4g} kg", modes.empty() ? "" : "; ", m.mode.frequency_hz,
                           m.mode.damping_ratio, m.mode.mass_kg);
    write_frf_output(o.output, out_format, fitted, fmt::format("modal fit of {}: {}", o.file, modes));
    info(g, fmt::format("wrote {} (fitted receptance, {} frequencies)", o.output, fitted.single.size()));
  }

  if (o.json) {
    nlohmann::json out = r;  // the fit's keys at the top level (its warnings are the study's)
    out["units"] = "SI: frequency Hz, mass kg, residue 1/kg, lower_residual 1/kg, upper_residual m/N";
    out["file"] = o.file;
    if (!o.output.empty()) out["output"] = o.output;
    if (!o.plot.empty()) out["plot"] = o.plot;
    std::cout << out.dump(2) << '\n';
  } else {
    std::cout << fmt::format("modal fit of {}: {} mode(s), {} points in {}–{} Hz, overall residual {:.3g} %{}\n", o.file,
                             r.modes.size(), r.points, r.band_low_hz, r.band_high_hz, 100.0 * r.normalised_residual,
                             r.converged ? "" : " (not converged)");
    std::cout << "mode  frequency_hz  damping_ratio  modal_mass_kg  stiffness_n_per_m  residual_pct  half_power_points\n";
    int i = 1;
    for (const FittedMode& m : r.modes)
      std::cout << fmt::format("{:4d}  {:12.3f}  {:13.6g}  {:13.6g}  {:17.6g}  {:12.3f}  {:17d}\n", i++, m.mode.frequency_hz,
                               m.mode.damping_ratio, m.mode.mass_kg, m.mode.stiffness(), 100.0 * m.normalised_residual,
                               m.points_in_half_power_band);
    if (fo.residual_terms)
      std::cout << fmt::format("residual terms: lower {:.6g} 1/kg (−L/ω²), upper {:.6g} m/N\n", r.lower_residual,
                               r.upper_residual);
    std::string as_options;
    for (const Mode& m : study.model)  // the modes lobes accepts
      as_options += fmt::format(" --mode-x {:.6g},{:.6g},{:.6g}", m.mass_kg, m.damping_ratio, m.frequency_hz);
    if (!as_options.empty()) std::cout << "for `toolpoint lobes --method fd`:" << as_options << '\n';
    std::cout << std::flush;
  }
  warn_all(study.warnings);
  if (o.plot.empty()) return;
  draw_figures(g, {{modal_fit_figure(frf, r, o.file), o.plot}},
               o.output.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.output});
}

}  // namespace

void add_modes_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<ModesOptions>();
  CLI::App* c = app.add_subcommand(
      "modes", "Modal parameters of a point FRF: natural frequency [Hz], damping ratio, modal mass [kg], with fit quality");
  c->add_option("frf", o->file, std::string("The point FRF to fit (required): ") + kPointFrfHelp)->required();
  add_dataset_option(c, o->dataset);
  add_frf_read_options(c, g);
  const auto& fields = modal_fit_fields();
  o->fields.add(c, option_field(fields, "max_modes"));
  c->add_option("--band", o->band, "Fit only F1 ≤ f ≤ F2, as F1:F2 [Hz] (default: the whole FRF)");
  o->fields.add(c, option_field(fields, "min_prominence_db"));
  c->add_flag("--no-residuals", o->no_residuals,
              "Do not fit the residual terms −L/ω² + U for out-of-band modes (default: fit them)");
  c->add_option("--output", o->output,
                "Write the fitted receptance [m/N] (residual terms included) on the measured frequencies [Hz] of the band "
                "here: .csv, .uff/.unv/.uf or .frf by extension (default: none)");
  add_plot_option(c, o->plot,
                  "the measured FRF (points) and the fitted modal FRF (line), |H| [m/N] and phase [deg] against "
                  "frequency [Hz], each fitted mode labelled with its frequency [Hz] and damping ratio");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(std::string(kFigureFooter) +
            "Example:\n"
            "  toolpoint modes tool_point.csv --max-modes 2 --band 500:3000 --plot modes.png");
  c->callback([o, &g] { run_modes(*o, g); });
}

}  // namespace toolpoint::cli
