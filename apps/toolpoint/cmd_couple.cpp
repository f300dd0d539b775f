// toolpoint couple: the semi-analytical tool point FRF — a measured SH11 + the model's tool + the
// holder–tool joint (seed Eq. 5), for one tool overhang or a sweep (the seed's Fig. 10): the
// overhang study (studies/overhang.hpp).
// Units: overhangs in m (mm in file names and figures), receptances in SI (H m/N, …), Hz.
// --plot: one overhang, the tool point FRF; a sweep, the FRFs overlaid in FILE and the natural
// frequencies against overhang in FILE with "_frequencies" before the extension.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/io/uncertainty_io.hpp"
#include "progress.hpp"

namespace toolpoint::cli {

namespace {

struct CoupleArgs {
  std::string sh, assembly, overhang, output, plot, band_output;
  SamplingOptions sampling;
  std::vector<std::string> joints;
  FieldFlags<PeakOptions> peaks;  // --prominence: peak_fields' min_prominence, here by default 0.1
  bool json = false;
};

void print_report(const CoupleArgs& o, const Globals& g, double inside, const std::vector<double>& overhangs,
                  const std::vector<std::vector<double>>& modes, bool sweep);

// plausibility.hpp's rule for an overhang [m]: a 49 m tool is refused, 0.8 m said to be unusual.
void check_overhang(double v) {
  check_plausible(plausible::kOverhang, v, "--overhang", fmt::format("did you mean {:g} (m)?", v / 1000.0));
}

// --overhang: one length or a sweep START:STOP:STEP, in m (empty: none given).
std::vector<double> parse_overhangs(const std::string& text) {
  if (text.empty()) return {};
  if (text.find(':') != std::string::npos) {
    // START:STOP:STEP in metres, in the sweep's own words (not a frequency grid's).
    if (std::count(text.begin(), text.end(), ':') != 2)
      throw InvalidArgument(fmt::format("--overhang '{}' is neither a length nor a sweep START:STOP:STEP [m]", text),
                            "e.g. --overhang 0.050, or --overhang 0.040:0.060:0.002");
    const auto [start, rest] = parse_range(text.substr(0, text.rfind(':')), "--overhang");
    const FrequencyGrid sweep{start, rest, parse_value(text.substr(text.rfind(':') + 1), "--overhang")};
    if (!(sweep.start_hz > 0.0) || !(sweep.stop_hz > sweep.start_hz) || !(sweep.step_hz > 0.0))
      throw InvalidArgument(fmt::format("--overhang {}: a sweep START:STOP:STEP [m] needs 0 < START < STOP and STEP > 0",
                                        text),
                            "e.g. --overhang 0.040:0.060:0.002");
    std::size_t count = 0;
    try {
      count = overhang_sweep_size(sweep.start_hz, sweep.stop_hz, sweep.step_hz);
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(fmt::format("--overhang {}: {}", text, e.what()), e.hint());
    }
    if (count > 1000)
      throw InvalidArgument(fmt::format("--overhang {} gives {} overhangs; at most 1000", text, count), "use a larger STEP");
    const std::vector<double> v = overhang_sweep(sweep.start_hz, sweep.stop_hz, sweep.step_hz);
    for (double x : {v.front(), v.back()}) check_overhang(x);
    return v;
  }
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size())
    throw InvalidArgument(fmt::format("--overhang '{}' is not a length in m or START:STOP:STEP", text),
                          "e.g. --overhang 0.05 or --overhang 0.040:0.060:0.002 (metres)");
  if (!(v > 0.0) || !std::isfinite(v))
    throw InvalidArgument(fmt::format("--overhang {} m must be > 0", v), "give the tool length outside the holder, e.g. 0.05");
  check_overhang(v);
  return {v};
}

void run_couple(const CoupleArgs& o, const Globals& g) {
  check_plot_path(o.plot);
  OverhangStudyOptions options;
  options.overhangs_m = parse_overhangs(o.overhang);
  options.peaks.min_prominence = 0.1;  // SH11 is measured: noise on it must not make modes
  o.peaks.apply(options.peaks);
  options.sh11_name = o.sh;
  {
    ParallelOptions parallel;  // --threads: the overhangs' and the samples' alike
    o.sampling.parallel.apply(parallel);
    options.threads = parallel.threads;
  }
  const bool sweep = options.overhangs_m.size() > 1 || o.overhang.find(':') != std::string::npos;
  if (sweep && o.output.empty())
    throw InvalidArgument("an overhang sweep needs --output DIR for its files", "add --output overhangs");
  {
    std::vector<RunPath> inputs{{o.sh, "--sh"}, {o.assembly, "assembly file"}};
    for (const RunPath& j : joint_paths(o.joints)) inputs.push_back(j);
    std::vector<RunPath> outputs{{sweep ? "" : o.output, "--output"}, {o.plot, "--plot"}, {o.band_output, "--band-output"}};
    if (sweep && !o.plot.empty()) outputs.push_back({with_suffix(o.plot, "_frequencies"), "--plot (frequencies)"});
    check_paths(inputs, outputs);
  }
  if (!sweep) check_output_extension(o.output, "--output", {".csv"}, "the tool point 2×2 block as FRF CSV (.csv)");
  check_output_extension(o.band_output, "--band-output", {".csv"}, "the quantile table as CSV (.csv)");
  const std::vector<JointFile> joints = read_joint_options(g, o.joints);
  if (o.sampling.samples != 0 || !o.band_output.empty()) {
    if (sweep)
      throw InvalidArgument("--samples: the band is computed for one overhang", "give --overhang one length, e.g. 0.048");
    options.band = uncertainty_options(o.sampling);
    options.uncertain_joint = sampled_joint(joints);
  }
  const LoadedAssembly loaded = with_joints(load_assembly(o.assembly), joints);
  report_loaded(g, loaded);
  const BlockSeries sh = read_block_input(g, o.sh).block;

  Progress progress(g, "couple: overhangs");
  const OverhangStudy study = run_overhang_study(loaded.assembly, sh, options, progress.part());
  progress.done();
  warn_all(study.warnings);

  std::vector<double> overhangs;
  for (const OverhangFrf& r : study.overhangs) overhangs.push_back(r.overhang_m);
  const double inside = study.tool_inside_holder_m;
  nlohmann::json j = study;
  j["sh11"] = o.sh;
  j["assembly"] = o.assembly;
  std::vector<std::string> written;
  for (std::size_t i = 0; i < study.overhangs.size(); ++i) {
    const OverhangFrf& r = study.overhangs[i];
    std::string file;
    if (!o.output.empty()) {
      file = sweep ? fmt::format("{}/sht11_overhang_{:.1f}mm.csv", o.output, 1000 * r.overhang_m) : o.output;
      write_frf_csv(file, r.sht11,
                    {fmt::format("tool point SHT11: measured SH11 ({}) + model tool, overhang {} m (tool length {} m), Eq. (5)",
                                 o.sh, r.overhang_m, inside + r.overhang_m)});
      written.push_back(file);
    }
    j["overhangs"][i]["file"] = file;
  }
  if (study.band && !o.band_output.empty()) {
    write_table_csv(o.band_output, band_table(*study.band),
                    {fmt::format("tool point H from {} + model tool at overhang {} m with the joint of {} uncertain: quantiles "
                                 "over {} samples",
                                 o.sh, overhangs.front(), options.uncertain_joint->source, study.band->samples),
                     "frequency Hz, magnitude m/N, phase deg (unwrapped around the nominal)"});
    written.push_back(o.band_output);
    j["band_output"] = o.band_output;
  }
  if (sweep) {
    write_table_csv(o.output + "/natural_frequencies.csv", natural_frequency_table(study),
                    {"modes of the coupled tool point FRF against tool overhang (seed Fig. 10): peaks of |H| followed from "
                     "the overhang nearest the assembly file's to within 15 % per step; an empty cell: not found",
                     "overhang in m, frequencies in Hz"});
    j["natural_frequencies_file"] = o.output + "/natural_frequencies.csv";
    written.push_back(o.output + "/natural_frequencies.csv");
  }
  if (!o.plot.empty()) j["plot"] = sweep ? nlohmann::json{o.plot, with_suffix(o.plot, "_frequencies")} : nlohmann::json(o.plot);
  if (o.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    print_report(o, g, inside, overhangs, study.tracked_modes_hz, sweep);
    if (study.band && !o.band_output.empty()) info(g, fmt::format("wrote {} (quantiles of the tool point FRF)", o.band_output));
  }
  if (o.plot.empty()) return;
  plot::FrfFigureOptions fo;
  fo.symbol = "H^{sht}_{11}";
  if (study.band) {
    fo.title = fmt::format("Tool point FRF from {} + model tool, the joint uncertain ({} samples)", plot::literal(o.sh),
                           study.band->samples);
    fo.mode_labels = 6;
    draw_figures(g, {{plot::frf_figure(band_traces(*study.band), fo), o.plot}}, written);
    return;
  }
  fo.title = fmt::format("Tool point FRF from {} + model tool (Eq. 5)", plot::literal(o.sh));
  fo.mode_labels = sweep ? 0 : 6;  // on an overlay, labels of one trace would be misread as all
  std::vector<FigureFile> figures{{plot::overhang_frf_figure(overhangs, tool_point_frfs(study), fo), o.plot}};
  if (sweep && !study.tracked_modes_hz.empty())
    figures.push_back({plot::natural_frequency_figure(natural_frequency_sweep(study)), with_suffix(o.plot, "_frequencies")});
  draw_figures(g, figures, written);
}

void print_report(const CoupleArgs& o, const Globals& g, double inside, const std::vector<double>& overhangs,
                  const std::vector<std::vector<double>>& modes, bool sweep) {
  std::cout << fmt::format("tool point FRF from {} + model tool ({:.1f} mm inside the holder) + holder–tool joint (Eq. 5)\n",
                           o.sh, 1000 * inside);
  std::cout << "overhang_mm  natural frequencies (peaks of |H|, followed mode by mode) [Hz]\n";
  for (std::size_t i = 0; i < overhangs.size(); ++i) {
    std::cout << fmt::format("{:11.1f} ", 1000 * overhangs[i]);
    for (const auto& mode : modes)
      std::cout << (std::isnan(mode[i]) ? fmt::format(" {:>9}", "-") : fmt::format(" {:9.1f}", mode[i]));
    std::cout << "\n";
  }
  std::cout << std::flush;
  if (!o.output.empty())
    info(g, sweep ? fmt::format("wrote {} FRFs and natural_frequencies.csv to {}/", overhangs.size(), o.output)
                  : fmt::format("wrote {}", o.output));
}

}  // namespace

void add_couple_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<CoupleArgs>();
  CLI::App* c = app.add_subcommand(
      "couple", "Tool point FRF from a measured SH11 and the model's tool, for any overhang (seed Eq. 5, Fig. 10)");
  add_frf_read_options(c, g);
  c->add_option("--sh", o->sh,
                std::string("SH11 at the holder tip, measured (e.g. via `toolpoint rotational`) (required): ") + kBlockCsvHelp)
      ->required();
  c->add_option("--assembly", o->assembly, "Assembly file (TOML, SI units): the tool and the holder–tool joint (required)")
      ->required();
  auto* prominence = o->peaks.add(c, option_field(peak_fields(), "min_prominence"));
  prominence->description(prominence->get_description() + "; 0.1 = 10 % keeps measurement noise in SH11 from making modes")
      ->default_str("0.1");
  c->add_option("--overhang", o->overhang,
                "Tool overhang [m], or a sweep START:STOP:STEP [m] (default: the file's tool.overhang). The length inside "
                "the holder is kept");
  c->add_option("--output", o->output,
                "One overhang: the SHT11 block CSV (H m/N, L 1/N, N rad/N, P rad/(N m)); a sweep (required): a folder for "
                "sht11_overhang_<mm>mm.csv per overhang and natural_frequencies.csv (overhang m, peaks Hz). Default: "
                "the table on stdout only");
  add_joint_option(c, o->joints);
  add_sampling_options(c, o->sampling,
                       "one overhang: the 5/50/95 % quantiles of the tool point FRF, in --band-output and the figure");
  c->add_option("--band-output", o->band_output,
                "With --samples: the quantiles of |H| [m/N] and ∠H [deg] per frequency [Hz] (CSV)");
  add_plot_option(c, o->plot,
                  "|H| [m/N] and phase [deg] of the tool point FRF against frequency [Hz] (one overhang: modes labelled; "
                  "a sweep: every overhang overlaid, and the natural frequencies [Hz] against overhang [mm] in FILE with "
                  "\"_frequencies\" before the extension)");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(std::string(kFigureFooter) +
            "Example:\n"
            "  toolpoint couple --sh sh11.csv --assembly examples/bt40_shrinkfit_16mm.toml \\\n"
            "      --overhang 0.040:0.060:0.002 --output overhangs --plot overhangs.png\n"
            "  (draws overhangs.png and overhangs_frequencies.png)");
  c->callback([o, &g] { run_couple(*o, g); });
}

}  // namespace toolpoint::cli
