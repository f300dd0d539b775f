// toolpoint predict: the tool point FRF (SHT11) or the holder-tip FRF (SH11) of an assembly file
// (the prediction study, studies/predict.hpp).
// Units: SI (H m/N, L 1/N, N rad/N, P rad/(N·m)); frequencies in Hz. --plot draws |H|, ∠H, |P|,
// ∠P with the modes (peaks of |H|) labelled [Hz].
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/io/uncertainty_io.hpp"

namespace toolpoint::cli {

namespace {

struct PredictArgs {
  std::string assembly, at = "tool", output, frequencies, plot, band_output, cross_output;
  FieldFlags<toolpoint::PredictOptions> fields;  // --speed, --extrapolate-bearings (predict_fields)
  std::vector<double> speeds;                    // --speeds: the figure at several speeds
  std::vector<std::string> joints;
  SamplingOptions sampling;
  bool json = false;
};

void run_predict(const PredictArgs& o, const Globals& g) {
  check_plot_path(o.plot);
  {
    std::vector<RunPath> inputs = joint_paths(o.joints);
    inputs.push_back({o.assembly, "assembly file"});
    check_paths(inputs, {{o.output, "--output"},
                         {o.band_output, "--band-output"},
                         {o.plot, "--plot"},
                         {o.cross_output, "--cross-output"}});
  }
  check_output_extension(o.cross_output, "--cross-output", {".csv"}, "H_xx, H_xy, H_yx, H_yy as CSV (.csv)");
  check_output_extension(o.output, "--output", {".csv"}, kBlockCsvOutput);
  check_output_extension(o.band_output, "--band-output", {".csv"}, "the quantile table as CSV (.csv)");
  // --speeds before any work: it draws a figure, and speeds in rad/s or below 0 cannot be drawn.
  if (!o.speeds.empty()) {
    if (o.plot.empty())
      throw InvalidArgument("--speeds draws the tool point FRF at those speeds: it needs --plot FILE", "add --plot FILE.png");
    for (double n : o.speeds) {
      if (!(n >= 0.0))
        throw InvalidArgument(fmt::format("--speeds {:g} rpm: spindle speeds must be ≥ 0 (0: standing)", n),
                              "e.g. --speeds 0,10000,20000,30000");
      if (n > 0.0) check_plausible(plausible::kSpinSpeedRpm, n, "--speeds", "give spindle speeds in rpm, e.g. 0,10000,20000");
    }
  }
  const std::vector<JointFile> joints = read_joint_options(g, o.joints);
  toolpoint::PredictOptions options;
  o.sampling.parallel.apply(options.band.parallel);  // --threads judged with or without --samples
  if (o.sampling.samples != 0 || !o.band_output.empty()) {
    if (o.at != "tool")
      throw InvalidArgument("--samples: the band is computed for the tool point (--at tool)", "drop --at holder");
    options.band = uncertainty_options(o.sampling);
    options.uncertain_joint = sampled_joint(joints);
  }
  const LoadedAssembly loaded = load_assembly_on_grid(g, o.assembly, o.frequencies, joints);
  const bool tool = o.at == "tool";
  options.receptance = tool ? PredictedFrf::ToolPoint : PredictedFrf::HolderTip;
  o.fields.apply(options);
  Progress progress(g, "predict");
  const Prediction p = run_prediction_study(loaded.assembly, options, progress.part());
  progress.done();
  // Before any file is written: the cross receptances exist only in the two-plane model.
  if (!o.cross_output.empty() && p.two_plane.size() == 0)
    throw InvalidArgument("--cross-output needs the two-plane model: --speed RPM > 0 or bearings with stiffness_y/damping_y",
                          "add --speed");
  warn_all(p.warnings);
  const BlockSeries& series = p.frf;
  const std::string what = tool ? "tool point SHT11" : "holder tip SH11 (tool outside the holder removed)";

  std::vector<std::string> written;
  if (!o.output.empty()) {
    write_frf_csv(o.output, series,
                  {fmt::format("{} of {}", what, o.assembly), fmt::format("assembly: {}", loaded.assembly.name)});
    info(g, fmt::format("wrote {} ({} frequencies, {})", o.output, series.size(), what));
    written.push_back(o.output);
  }
  if (!o.cross_output.empty()) {
    write_text_file(o.cross_output,
                    fmt::format("# tool point of {} at {} rpm, both planes: H [m/N] (x, y transverse, spin about +z)\n",
                                o.assembly, p.speed_rpm) +
                        cross_receptance_csv(p.two_plane));
    info(g, fmt::format("wrote {} (H_xx, H_xy, H_yx, H_yy)", o.cross_output));
    written.push_back(o.cross_output);
  }
  if (p.band && !o.band_output.empty()) {
    write_table_csv(o.band_output, band_table(*p.band),
                    {fmt::format("tool point H of {} with the joint of {} uncertain: quantiles over {} samples", o.assembly,
                                 options.uncertain_joint->source, p.band->samples),
                     "magnitude in m/N, phase in degrees, frequency in Hz"});
    info(g, fmt::format("wrote {} (quantiles of the tool point FRF)", o.band_output));
    written.push_back(o.band_output);
  }
  if (o.json) {
    nlohmann::json j = p;
    j["assembly"] = o.assembly;
    j["units"] = "frequency Hz, magnitude m/N";
    j["points"] = series.size();
    if (!o.output.empty()) j["output"] = o.output;
    if (!o.cross_output.empty()) j["cross_output"] = o.cross_output;
    if (!o.plot.empty()) j["plot"] = o.plot;
    // The file's warnings as well as the model's, as before the study.
    std::vector<std::string> warnings = loaded.warnings;
    warnings.insert(warnings.end(), p.warnings.begin(), p.warnings.end());
    j["warnings"] = warnings;
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << fmt::format("{} — {}\n", what, loaded.assembly.name);
    std::cout << fmt::format("{} to {} Hz, {} points; modes (peaks of |H|) below {} Hz:\n", series.frequency_hz.front(),
                             series.frequency_hz.back(), series.size(), series.frequency_hz.back());
    std::cout << "mode  peak_frequency_hz  peak_magnitude_m_per_n\n";
    int i = 1;
    for (const Peak& m : p.modes) std::cout << fmt::format("{:4d}  {:17.2f}  {:22.4e}\n", i++, m.frequency_hz, m.magnitude);
    if (p.modes.empty()) std::cout << "  (no resonance peak in the frequency range)\n";
    std::cout << std::flush;
  }
  if (!o.speeds.empty()) {
    plot::Figure fig;
    try {
      fig = speed_frf_figure(loaded.assembly, o.speeds, options.extrapolate_bearings);
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(with_flags(e.what()), with_flags(e.hint()));
    }
    draw_figures(g, {{fig, o.plot}}, written);
    return;
  }
  if (!o.plot.empty()) {
    const std::string title = fmt::format("{} of {}", tool ? "Tool point FRF SHT_{11}" : "Holder tip FRF SH_{11}",
                                          plot::literal(loaded.assembly.name));
    if (p.band) {
      plot::FrfFigureOptions fo;
      fo.title = fmt::format("Tool point FRF, the joint uncertain ({} samples)", p.band->samples);
      fo.symbol = "H^{sht}_{11}";
      fo.mode_labels = 6;
      draw_figures(g, {{plot::frf_figure(band_traces(*p.band), fo), o.plot}}, written);
    } else {
      draw_figures(g, {{plot::receptance_figure(series, title, "11", 6), o.plot}}, written);
    }
  }
}

}  // namespace

void add_predict_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<PredictArgs>();
  CLI::App* c = app.add_subcommand("predict", "Tool point FRF of an assembly by receptance coupling (seed Eq. 1–5)");
  c->add_option("assembly", o->assembly, "Assembly file (TOML, SI units; see examples/) (required)")->required();
  c->add_option("--at", o->at, "tool: SHT11 at the tool tip; holder: SH11 at the holder tip, tool outside removed")
      ->check(CLI::IsMember({"tool", "holder"}))
      ->capture_default_str();
  c->add_option("--output", o->output,
                "Write the 2×2 block [[H, L], [N, P]] per frequency here (FRF CSV; H m/N, L 1/N, N rad/N, P rad/(N m)); "
                "default: only the table of modes on stdout");
  o->fields.add(c, option_field(predict_fields(), "speed_rpm"));
  c->add_option("--speeds", o->speeds,
                "With --plot: the figure is instead the tool point FRF at these spindle speeds [rpm], comma-separated (e.g. "
                "0,10000,20000,30000): |H_xx| and |H_xy| [m/N] against frequency [Hz], the spindle spinning and the bearings "
                "at each speed")
      ->delimiter(',');
  o->fields.add(c, option_field(predict_fields(), "extrapolate_bearings"));
  c->add_option("--cross-output", o->cross_output,
                "Write the tool point's H_xx, H_xy, H_yx, H_yy [m/N] here (CSV; needs --speed or anisotropic bearings)")
      ->option_text("FILE");
  c->add_option("--frequencies", o->frequencies, "Frequency grid START:STOP:STEP [Hz] (default: the file's [analysis] grid)");
  add_plot_option(c, o->plot,
                  "the block: |H| [m/N] and phase of H [deg], |P| [rad/(N·m)] and phase of P [deg] against frequency "
                  "[Hz], modes (peaks of |H|) labelled [Hz]");
  add_joint_option(c, o->joints);
  add_sampling_options(c, o->sampling, "the 5/50/95 % quantiles of the tool point FRF, in --band-output and the figure");
  c->add_option("--band-output", o->band_output,
                "With --samples: the quantiles of |H| [m/N] and ∠H [deg] per frequency [Hz] (CSV)");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(std::string(kFigureFooter) +
            "Example:\n  toolpoint predict examples/bt40_shrinkfit_16mm.toml --output sht11.csv --plot sht11.png");
  c->callback([o, &g] { run_predict(*o, g); });
}

}  // namespace toolpoint::cli
