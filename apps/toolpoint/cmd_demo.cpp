// toolpoint demo: the seed's analytical case study (Section 3) end to end, with its figures.
// Units: SI; frequencies in Hz. The figures follow the CLI's rule (cli.hpp): data first; figures
// gnuplot cannot draw are an error (exit 5) after every data file and summary.json are written.
#include <exception>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/io/identify_io.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/plot/plot.hpp"
#include "progress.hpp"

namespace toolpoint::cli {

namespace {

struct DemoOptions {
  std::string assembly, output = "toolpoint-demo";
  std::vector<std::string> joints;
  // --sigma, --width: from their definitions (case_study_fields).
  FieldFlags<CaseStudyOptions> fields;
  std::uint64_t seed = 1;
  int window = 81, order = 2, bootstrap = 200;
  FieldFlags<ParallelOptions> parallel;  // --threads
  bool no_plots = false, json = false, no_fit = false;
};

std::string pct(double x) { return fmt::format("{:+.2g} %", 100.0 * x); }

void print_report(const DemoOptions& o, const CaseStudyOptions& co, const LoadedAssembly& loaded, const CaseStudy& cs,
                  const std::vector<std::string>& warnings, const std::vector<std::string>& files,
                  const std::vector<std::string>& figures);

void run_demo(const DemoOptions& o, const Globals& g) {
  const LoadedAssembly loaded = with_joints(o.assembly.empty() ? parse_assembly(example_assembly_toml(), example_assembly_name())
                                                               : load_assembly(o.assembly),
                                            read_joint_options(g, o.joints));
  report_loaded(g, loaded);
  CaseStudyOptions co;
  o.fields.apply(co);
  co.seed = o.seed;
  co.filter = SavgolOptions{o.window, o.order};
  co.fit = !o.no_fit;
  if (o.bootstrap == 0) co.fit_options.uncertainty = UncertaintyMethod::Linearised;
  else co.fit_options.bootstrap_samples = o.bootstrap;
  o.parallel.apply(co.fit_options.parallel);
  co.fit_options.seed = o.seed;
  co.check();
  info(g, "toolpoint demo: running the seed's analytical case study (Özşahin et al. 2009, Section 3)…");
  // The stages and the share of the run each takes (the figures dominate).
  Progress progress(g, "demo: case study");
  const CaseStudy cs = run_case_study(loaded.assembly, co, progress.part(0.0, 0.15));
  progress.stage("demo: writing data", 0.15);
  const auto& f = cs.sht_true.frequency_hz;
  const std::string dir = o.output;
  auto path = [&](const std::string& name) { return dir + "/" + name; };

  // Data files.
  const std::vector<std::string> note = {fmt::format("toolpoint demo: {}", loaded.assembly.name)};
  std::vector<std::string> files;
  auto block_file = [&](const std::string& name, const BlockSeries& s, const std::string& what) {
    write_frf_csv(path(name), s, {note[0], what});
    files.push_back(name);
  };
  block_file("sh11_true.csv", cs.sh_true, "SH11, holder tip of spindle + holder (tool outside removed), noise-free model");
  block_file("sht11_true.csv", cs.sht_true, "SHT11, tool point, noise-free model");
  block_file("sh11_noisy.csv", cs.sh_noisy,
             fmt::format("SH11 with {} % multiplicative noise, seed {}", 100 * co.noise_sigma, o.seed));
  block_file("sht11_noisy.csv", cs.sht_noisy,
             fmt::format("SHT11 with {} % multiplicative noise, seed {}", 100 * co.noise_sigma, o.seed + 1));
  block_file("sh11_filtered.csv", cs.sh_filtered,
             fmt::format("SH11 noisy, Savitzky-Golay window {} points, order {}", o.window, o.order));
  block_file("sht11_filtered.csv", cs.sht_filtered,
             fmt::format("SHT11 noisy, Savitzky-Golay window {} points, order {}", o.window, o.order));
  block_file("sht11_identified.csv", cs.sht_verified, "SHT11 from Eq. (5) with the joint read from the filtered data");
  if (cs.fitted) block_file("sht11_fitted.csv", cs.sht_fitted, "SHT11 from Eq. (5) with the joint fitted to the raw noisy data");
  auto joint_file = [&](const std::string& name, const JointSeries& s, const std::string& what) {
    write_table_csv(path(name), joint_table(s),
                    {note[0], "holder-tool joint K(omega) by Eq. (6): " + what, "k = Re K, c = Im K / omega (SI)"});
    files.push_back(name);
  };
  joint_file("kht_noise_free.csv", cs.clean, "noise-free FRFs");
  joint_file("kht_noisy.csv", cs.noisy, "noisy FRFs, unfiltered");
  joint_file("kht_filtered.csv", cs.filtered, "noisy FRFs, Savitzky-Golay filtered");

  // Summary: the case study (json.hpp), and what this run was given and wrote.
  nlohmann::json j = cs;
  j["case_study"] = "Ozsahin, Erturk, Ozguven, Budak (2009), Section 3: holder-tool joint";
  j["assembly"] = o.assembly.empty() ? example_assembly_name() : o.assembly;
  j["units"] = "SI; frequencies in Hz";
  j["frequency_range_hz"] = {f.front(), f.back()};
  j["points"] = f.size();
  j["noise"] = {{"sigma", co.noise_sigma}, {"seed_sh11", o.seed}, {"seed_sht11", o.seed + 1}};
  j["filter"] = {{"method", "Savitzky-Golay"}, {"window_points", o.window}, {"order", o.order}};
  const std::vector<std::string>& warnings = cs.warnings;

  // Figures (the seed's Fig. 2–5). A failure is kept until summary.json and the report are out.
  std::vector<std::string> figures;
  std::exception_ptr figure_failure;
  if (!o.no_plots) {
    const CaseStudyFigures figs = case_study_figures(cs, co);
    const std::vector<FigureFile> todo{{figs.tool_point_frf, path("fig2a_tool_point_frf.png")},
                                       {figs.holder_tip_frf, path("fig2b_holder_tip_frf.png")},
                                       {figs.joint_noise_free, path("fig3_joint_noise_free.png")},
                                       {figs.joint_filtered, path("fig5_joint_filtered.png")},
                                       {figs.verification, path("fig_verification.png")}};
    const std::vector<std::string> written{fmt::format("{}/ ({} data files; summary.json follows)", dir, files.size())};
    for (std::size_t i = 0; i < todo.size(); ++i) {
      progress.stage(fmt::format("demo: figure {} of {}", i + 1, todo.size()),
                     0.2 + 0.8 * static_cast<double>(i) / static_cast<double>(todo.size()));
      try {
        draw_figures(g, {todo[i]}, written, "run with --no-plots");
      } catch (const IoError&) {
        figure_failure = std::current_exception();
        break;
      }
      figures.push_back(std::filesystem::path(todo[i].path).filename().string());
    }
  }
  progress.done();
  j["files"] = files;
  j["figures"] = figures;
  write_text_file(path("summary.json"), j.dump(2) + "\n");
  files.push_back("summary.json");

  if (o.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    print_report(o, co, loaded, cs, warnings, files, figures);
  }
  if (figure_failure) {
    if (OutputSet* data = OutputSet::active()) data->commit();  // the data and summary.json stay (see the footer)
    std::rethrow_exception(figure_failure);
  }
}

void print_report(const DemoOptions& o, const CaseStudyOptions& co, const LoadedAssembly& loaded, const CaseStudy& cs,
                  const std::vector<std::string>& warnings, const std::vector<std::string>& files,
                  const std::vector<std::string>& figures) {
  const auto& f = cs.sht_true.frequency_hz;
  const std::string& dir = o.output;
  std::cout << fmt::format("toolpoint demo: the seed's analytical case study (Özşahin et al. 2009, Section 3)\n");
  std::cout << fmt::format("assembly: {} ({})\n\n", loaded.assembly.name,
                           o.assembly.empty() ? example_assembly_name() : o.assembly);
  std::cout << fmt::format("1. Forward model (Eq. 1–5): SH11 and SHT11 at {} frequencies, {:g}–{:g} Hz.\n", f.size(), f.front(),
                           f.back());
  std::cout << "   tool point modes:";
  for (std::size_t i = 0; i < cs.effect.modes.size(); ++i)
    std::cout << fmt::format(" {:.1f} Hz{}", cs.effect.modes[i].frequency_hz, i == cs.effect.dominant ? " (tool mode)" : "");
  std::cout << "\n";
  const double worst = *std::max_element(cs.clean_max_deviation.begin(), cs.clean_max_deviation.end());
  std::cout << fmt::format(
      "2. Identification from noise-free FRFs (Eq. 6) over the whole band: all 8 parameters equal the\n"
      "   holder-tool joint put in, within {:.1e} relative at every frequency (seed Fig. 3).\n",
      worst);
  std::cout << fmt::format(
      "3. {:g} % noise on every entry of SH11 and SHT11 (seeds {}, {}); Savitzky-Golay filter,\n"
      "   window {} points ({:g} Hz), order {}.\n",
      100 * co.noise_sigma, o.seed, o.seed + 1, o.window, o.window * (f[1] - f[0]), o.order);
  const auto& dm = cs.effect.modes[cs.effect.dominant];
  std::cout << fmt::format(
      "4. Effect analysis: the holder-tool joint controls the {:.1f} Hz mode (+10 % joint stiffness moves it\n"
      "   {}); read in {:.0f}–{:.0f} Hz (±{:g} % around {:.1f} Hz).\n\n",
      dm.frequency_hz, pct(dm.stiffness_shift), cs.filtered_readout.band_lo_hz, cs.filtered_readout.band_hi_hz,
      100 * co.band_width, cs.mode_hz);
  std::cout << "parameter  unit         Table 1      noise-free  error      noisy       error      filtered    error      gain\n";
  for (int k = 0; k < 8; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    const double ref = cs.reference[k];
    auto col = [&](const JointReadout& r) {
      const double v = r.parameters[ks].median;
      return fmt::format("{:>10.4g}  {:>9}", v, ref != 0.0 ? pct(v / ref - 1.0) : std::string("-"));
    };
    std::cout << fmt::format("{:<9}  {:<10}  {:>10.4g}  {}  {}  {}  {:>8.3g}\n", JointParameters::name(k),
                             JointParameters::unit(k), ref, col(cs.clean_readout), col(cs.noisy_readout),
                             col(cs.filtered_readout), cs.clean_readout.noise_gain[ks]);
  }
  std::cout << "gain: relative error of the parameter per unit relative error on every FRF entry, to first order\n"
               "(JointEstimate::noise_gain, median in the band). Damping whose ωc is a few % of |K| has a gain of\n"
               "tens to hundreds: 5 % noise then leaves it unidentifiable by the read-out, whatever the filter.\n";
  std::cout << fmt::format("seed read-out verdict: {}\n", to_string(cs.seed.verdict.verdict));
  if (cs.fitted) {
    const JointFit& fit = *cs.fitted->fit;
    std::cout << fmt::format(
        "\n6. Band fit (beyond the seed): the joint's constants fitted to the raw noisy SH11 and SHT11 at all {} frequencies\n"
        "   (output error on Eq. 5, noise estimated from the data, {} parameters); intervals: {}.\n\n",
        fit.points, fit.reciprocal ? 6 : 8, fit.method_description);
    std::cout << "parameter  unit         Table 1     seed read-out  error      band fit    error       95 % interval            "
                 "  holds Table 1  verdict\n";
    for (int k = 0; k < 8; ++k) {
      const auto ks = static_cast<std::size_t>(k);
      const double ref = cs.reference[k];
      const ParameterInterval& iv = fit.intervals[ks];
      const double seed_v = cs.filtered_readout.parameters[ks].median;
      auto err = [&](double v) { return ref != 0.0 ? pct(v / ref - 1.0) : std::string("-"); };
      std::cout << fmt::format(
          "{:<9}  {:<10}  {:>10.4g}  {:>12.4g}  {:>9}  {:>10.5g}  {:>10}  [{:>10.5g}, {:>10.5g}]  {:<13}  {}\n",
          JointParameters::name(k), JointParameters::unit(k), ref, seed_v, err(seed_v), iv.estimate, err(iv.estimate), iv.lower,
          iv.upper, iv.lower <= ref && ref <= iv.upper ? "yes" : "NO", iv.determined ? "determined" : "undetermined");
    }
    std::cout << fmt::format(
        "band fit verdict: {}; residual ratio {:.3g} (≈ 1: the model and the estimated noise explain the data)\n",
        to_string(cs.fitted->verdict.verdict), fit.residual_ratio);
  }
  std::cout << "\n"
            << (cs.fitted ? "7" : "5")
            << ". Forward check: each identified joint coupled back (Eq. 5) against the true tool point FRF\n"
               "   mode   true_hz   seed: freq_error   peak_error"
            << (cs.fitted ? "     fit: freq_error   peak_error" : "") << "\n";
  for (std::size_t i = 0; i < cs.verification.size(); ++i) {
    const auto& c = cs.verification[i];
    std::cout << fmt::format("   {:4d}  {:8.1f}  {:>17}  {:>11}", i + 1, c.measured_hz, pct(c.frequency_error),
                             pct(c.magnitude_error));
    if (cs.fitted && i < cs.fit_verification.size())
      std::cout << fmt::format("  {:>17}  {:>11}", pct(cs.fit_verification[i].frequency_error),
                               pct(cs.fit_verification[i].magnitude_error));
    std::cout << "\n";
  }
  if (!warnings.empty()) {
    std::cout << "\nnotes:\n";
    for (const auto& w : warnings) std::cout << "  - " << w << "\n";
  }
  std::cout << fmt::format("\nwrote {} data files to {}/", files.size(), dir);
  if (!figures.empty()) {
    std::cout << "\nfigures:";
    for (const auto& fig : figures) std::cout << "\n  " << dir << "/" << fig;
  }
  std::cout << std::endl;
}

}  // namespace

void add_demo_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<DemoOptions>();
  CLI::App* c = app.add_subcommand(
      "demo", "The seed's analytical case study end to end: predict, identify, add noise, filter, identify again, verify");
  c->add_option("--assembly", o->assembly,
                "Assembly file (TOML, SI units; default: the built-in examples/bt40_shrinkfit_16mm.toml)");
  c->add_option("--output", o->output, "Folder for the CSV data, summary.json and figures")->capture_default_str();
  const auto& fields = case_study_fields();
  o->fields.add(c, option_field(fields, "noise_sigma"));
  c->add_option("--seed", o->seed, "Random seed (SH11 uses it, SHT11 seed + 1)")->capture_default_str();
  c->add_option("--window", o->window, "Savitzky-Golay window [frequency points, odd]")->capture_default_str();
  c->add_option("--order", o->order, "Savitzky-Golay polynomial order [-]")->capture_default_str();
  o->fields.add(c, option_field(fields, "band_width"));
  c->add_option("--bootstrap", o->bootstrap, "Band fit intervals: bootstrap replicates (≥ 20), or 0 for linearised intervals")
      ->capture_default_str();
  add_threads_option(c, o->parallel);
  c->add_flag("--no-fit", o->no_fit, "Only the seed's procedure, without the band fit");
  add_joint_option(c, o->joints)
      ->description(
          "The joint(s) the study identifies, from joint files instead of the assembly's (holder-tool=FILE.toml; its "
          "constants are then the reference)");
  c->add_flag("--no-plots", o->no_plots, "Write the data only, no figures (default: draw the five figures, which needs gnuplot)");
  c->add_flag("--json", o->json, "Print summary.json on stdout instead of the table");
  c->footer(
      "Figures: five PNGs (the seed's Fig. 2–5 and the forward check) drawn by gnuplot after the data.\n"
      "If gnuplot is missing or fails, the data files and summary.json stay written, the error names\n"
      "them, and the exit code is 5; --no-plots skips the figures.\n"
      "Examples:\n  toolpoint demo --output demo-out\n  toolpoint demo --sigma 0.02 --seed 7 --window 41 --no-plots");
  c->callback([o, &g] { run_demo(*o, g); });
}

}  // namespace toolpoint::cli
