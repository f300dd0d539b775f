// toolpoint identify: joint stiffness and damping in closed form from measured (or modelled) FRFs
// (seed Eq. 6, 15, 18), read at the mode the joint controls, verified forward (Eq. 5).
// Units: SI (k in N/m, N, N/rad, N·m/rad; c in N·s/m, N·s, N·s/rad, N·m·s/rad); frequencies in
// Hz. --plot draws k(f) and c(f) of the four pairs (the seed's Fig. 11–12), the read-out band
// shaded and the values read there as lines.
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/assembly_file.hpp"
#include "toolpoint/coupling.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/identify.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/peaks.hpp"
#include "toolpoint/plot.hpp"
#include "progress.hpp"

namespace toolpoint::cli {

namespace {

struct IdentifyOptions {
  std::string joint = "holder-tool", assembly, sh, sht, s, band, output, plot;
  double at = 0.0, width = 0.02;
  std::vector<std::string> overhang_frfs;
  bool json = false;
};

void print_report(const IdentifyOptions& o, const std::string& equation, double center, double lo, double hi,
                  const nlohmann::json& choice, const JointReadout& r, const std::vector<ModeComparison>& cmp);

void run_identify(const IdentifyOptions& o, const Globals& g) {
  if (!(o.width > 0.0 && o.width < 0.5))
    throw InvalidArgument(fmt::format("--width {} must lie in (0, 0.5)", o.width), "e.g. --width 0.02 for ±2 % around the mode");
  check_plot_path(o.plot);
  const bool ht = o.joint == "holder-tool";
  Progress progress(g, "identify: reading");
  const LoadedModel lm = load_model(g, o.assembly);
  const Assembly& a = lm.loaded.assembly;
  const AssemblyModel& model = lm.model;

  // Which equation, which data.
  std::string equation, g_name, b_name;
  BlockSeries G, B;
  std::function<TwoPort(double)> A;
  bool tool_point_frf = true;
  if (ht) {
    if (o.sh.empty() || o.sht.empty())
      throw InvalidArgument("--joint holder-tool needs --sh SH11.csv and --sht SHT11.csv",
                            "give both measured blocks, e.g. --sh sh11.csv --sht sht11.csv");
    equation = "Eq. (6) from Eq. (5): A = T (tool, model), B11 = SH11, G11 = SHT11";
    B = read_block_input(g, b_name = o.sh);
    G = read_block_input(g, g_name = o.sht);
    A = [&](double f) { return model.tool(f); };
  } else {
    if (o.sh.empty() == o.sht.empty())
      throw InvalidArgument("--joint spindle-holder needs exactly one of --sh SH11.csv (Eq. 15) or --sht SHT11.csv (Eq. 18)",
                            "give --sh for the holder tip FRF or --sht for the tool point FRF, not both");
    tool_point_frf = !o.sht.empty();
    G = read_block_input(g, g_name = tool_point_frf ? o.sht : o.sh);
    if (!o.s.empty()) {
      B = read_block_input(g, b_name = o.s);
    } else {
      b_name = "S11 (model spindle)";
      validate(G, g_name, 3);
      B = block_series(G.frequency_hz, [&](double f) { return model.spindle_nose(f); });
    }
    if (tool_point_frf) {
      equation = "Eq. (18): A = HT (holder + tool through the file's K_ht, model), B11 = S11, G11 = SHT11";
      A = [&](double f) { return model.holder_tool(f); };
    } else {
      equation = "Eq. (15): A = H (holder with shank, model), B11 = S11, G11 = SH11";
      A = [&](double f) { return model.holder(f); };
    }
  }
  progress.stage("identify: K(f) at every frequency", 0.2);
  const JointSeries js = identify_series(A, B, b_name, G, g_name);
  const FrfSeries g_h = entry(G, 0);

  // The read-out band.
  nlohmann::json choice;
  double lo = 0.0, hi = 0.0, center = 0.0;
  if (!o.band.empty()) {
    std::tie(lo, hi) = parse_range(o.band, "--band");
    if (!(hi > lo))
      throw InvalidArgument(fmt::format("--band {}: the upper frequency must exceed the lower", o.band), "e.g. --band 2500:2650");
    center = 0.5 * (lo + hi);
    choice = {{"method", "band given"}};
  } else {
    if (o.at > 0.0) {
      center = o.at;
      choice = {{"method", "frequency given"}};
    } else if (!o.overhang_frfs.empty()) {
      std::vector<FrfSeries> frfs{g_h};
      for (const auto& p : o.overhang_frfs) frfs.push_back(read_point_frf(g, p));
      const OverhangModes om = overhang_mode(frfs, 0);
      center = om.reference_peaks[om.dominant].frequency_hz;
      choice = {{"method", "mode that moves most with the overhang"}, {"relative_variation", om.relative_variation}};
    } else {
      progress.stage("identify: effect analysis on the model", 0.4);
      const EffectAnalysis ea =
          effect_analysis(a, ht ? Route::HolderTool : tool_point_frf ? Route::SpindleHolderFromSHT : Route::SpindleHolderFromSH, G.frequency_hz);
      const double model_f = ea.modes[ea.dominant].frequency_hz;
      const auto peaks = find_peaks(g_h);
      if (peaks.empty()) throw InputError(fmt::format("{}: no resonance peak in |H| to read the joint at", g_name), "give --at or --band");
      center = std::min_element(peaks.begin(), peaks.end(), [&](const Peak& x, const Peak& y) {
                 return std::abs(x.frequency_hz - model_f) < std::abs(y.frequency_hz - model_f);
               })->frequency_hz;
      nlohmann::json modes = nlohmann::json::array();
      for (const auto& m : ea.modes)
        modes.push_back({{"model_frequency_hz", m.frequency_hz}, {"relative_shift_per_10pct_k", m.stiffness_shift},
                         {"relative_peak_change_per_10pct_c", m.damping_effect}});
      choice = {{"method", "effect analysis on the model"}, {"model_modes", modes}, {"dominant_model_mode_hz", model_f}};
    }
    lo = center * (1.0 - o.width);
    hi = center * (1.0 + o.width);
  }
  const JointReadout r = read_joint(js, lo, hi);
  warn_all(r.warnings);

  // Forward verification: the constants back into Eq. (5) with the measured B11.
  progress.stage("identify: forward check", 0.8);
  const JointParameters kc = r.medians();
  const Joint joint = Joint::make_elastic(kc);
  BlockSeries pred{G.frequency_hz, {}};
  for (std::size_t i = 0; i < G.size(); ++i) pred.blocks.push_back(couple_point(A(G.frequency_hz[i]), B.blocks[i], joint, G.frequency_hz[i]));
  const auto cmp = compare_modes(g_h, entry(pred, 0));

  progress.done();
  std::vector<std::string> written;
  if (!o.output.empty()) {
    written.push_back(o.output);
    const Table t = joint_table(js);
    write_table_csv(o.output, t,
                    {fmt::format("toolpoint identify: {} joint, {}", o.joint, equation),
                     "k = Re K, c = Im K / omega; units in the column names (SI); frequency in Hz"});
    info(g, fmt::format("wrote {} ({} frequencies)", o.output, js.size()));
  }

  if (o.json) {
    nlohmann::json j;
    j["joint"] = o.joint;
    j["equation"] = equation;
    j["band_hz"] = {lo, hi};
    j["band_center_hz"] = center;
    j["points_in_band"] = r.points;
    j["mode_choice"] = choice;
    for (int k = 0; k < 8; ++k) {
      const auto& p = r.parameters[static_cast<std::size_t>(k)];
      j["parameters"][JointParameters::name(k)] = {
          {"median", p.median}, {"spread", p.spread}, {"min", p.min}, {"max", p.max}, {"unit", JointParameters::unit(k)}};
    }
    j["reciprocity"] = {{"k_ym_vs_k_tf", r.reciprocity_k}, {"c_ym_vs_c_tf", r.reciprocity_c}};
    j["max_condition_numbers_in_band"] = {{"A11_minus_G11", r.max_cond_difference}, {"K_inverse", r.max_cond_flexibility}};
    j["verification"] = nlohmann::json::array();
    for (const auto& c : cmp)
      j["verification"].push_back({{"measured_hz", c.measured_hz}, {"predicted_hz", c.predicted_hz}, {"frequency_error", c.frequency_error},
                                   {"measured_peak_m_per_n", c.measured_peak}, {"predicted_peak_m_per_n", c.predicted_peak},
                                   {"magnitude_error", c.magnitude_error}});
    j["warnings"] = r.warnings;
    if (!o.output.empty()) j["output"] = o.output;
    if (!o.plot.empty()) j["plot"] = o.plot;
    std::cout << j.dump(2) << '\n';
  } else {
    print_report(o, equation, center, lo, hi, choice, r, cmp);
  }
  if (!o.plot.empty()) {
    plot::JointFigureData d;
    d.frequency_hz = js.frequency_hz;
    d.band_hz = std::make_pair(lo, hi);
    d.title = fmt::format("{} joint, {}: k(f), c(f) and the values read in {:.0f}–{:.0f} Hz",
                          ht ? "Holder–tool" : "Spindle–holder", ht ? "Eq. (6)" : tool_point_frf ? "Eq. (18)" : "Eq. (15)", lo, hi);
    for (int pair = 0; pair < 4; ++pair) d.parameters.push_back(joint_curve(js, pair, std::nullopt, kc));
    draw_figures(g, {{plot::joint_figure(d), o.plot}}, written);
  }
}

void print_report(const IdentifyOptions& o, const std::string& equation, double center, double lo, double hi,
                  const nlohmann::json& choice, const JointReadout& r, const std::vector<ModeComparison>& cmp) {
  std::cout << fmt::format("{} joint, {}\n", o.joint, equation);
  std::cout << fmt::format("read at {:.1f} Hz: band {:.1f}–{:.1f} Hz ({} points; {})\n", center, lo, hi, r.points,
                           choice["method"].get<std::string>());
  std::cout << "parameter  median         spread       unit\n";
  for (int k = 0; k < 8; ++k) {
    const auto& p = r.parameters[static_cast<std::size_t>(k)];
    std::cout << fmt::format("{:<9}  {:>12.5g}  {:>11.3g}  {}\n", JointParameters::name(k), p.median, p.spread, JointParameters::unit(k));
  }
  std::cout << fmt::format("reciprocity: k_ym vs k_tf {:.2g}, c_ym vs c_tf {:.2g} (relative difference)\n", r.reciprocity_k,
                           r.reciprocity_c);
  std::cout << fmt::format("conditioning in band: cond(A11 - G11) ≤ {:.3g}, cond(K^-1) ≤ {:.3g}\n", r.max_cond_difference,
                           r.max_cond_flexibility);
  std::cout << "forward check (constants back into Eq. 5): mode  measured_hz  predicted_hz  freq_error  peak_error\n";
  int i = 1;
  for (const auto& c : cmp)
    std::cout << fmt::format("  {:2d}  {:10.1f}  {:12.1f}  {:+10.2e}  {:+10.2e}\n", i++, c.measured_hz, c.predicted_hz, c.frequency_error,
                             c.magnitude_error);
  std::cout << std::flush;
}

}  // namespace

void add_identify_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<IdentifyOptions>();
  CLI::App* c = app.add_subcommand("identify", "Joint stiffness and damping in closed form (seed Eq. 6, 15, 18)");
  c->add_option("--joint", o->joint, "holder-tool (Eq. 6) or spindle-holder (Eq. 15 with --sh, Eq. 18 with --sht)")
      ->check(CLI::IsMember({"holder-tool", "spindle-holder"}))
      ->capture_default_str();
  c->add_option("--assembly", o->assembly,
                "Assembly file (TOML, SI units): the model's free–free components; its joint values serve as trial values "
                "for the effect analysis (required)")
      ->required();
  c->add_option("--sh", o->sh, std::string("SH11, holder tip of spindle + holder with the tool outside removed: ") + kBlockCsvHelp);
  add_frf_read_options(c, g);
  c->add_option("--sht", o->sht, std::string("SHT11, tool point of the whole assembly: ") + kBlockCsvHelp);
  c->add_option("--s", o->s,
                std::string("S11, spindle nose alone (spindle-holder joint; default: the model's spindle): ") + kBlockCsvHelp);
  c->add_option("--band", o->band, "Read the parameters in F1:F2 [Hz] (default: around the mode the joint controls)");
  c->add_option("--at", o->at,
                "Read the parameters around this frequency [Hz] (default: the mode chosen by effect analysis or "
                "--overhang-frfs)");
  c->add_option("--width", o->width, "Half-width of the read-out band around the mode, relative [-] (0.02 = ±2 %), in (0, 0.5)")
      ->capture_default_str();
  c->add_option("--overhang-frfs", o->overhang_frfs,
                std::string("Tool point FRFs at other overhangs, comma-separated: choose the mode that moves most with the "
                            "overhang (seed Fig. 10). Each: ") + kPointFrfHelp)
      ->delimiter(',');
  c->add_option("--output", o->output,
                "Write k(f), c(f) (SI units in the column names), the condition numbers and noise gains per frequency [Hz] "
                "here (CSV; default: none)");
  add_plot_option(c, o->plot,
                  "k(f) and c(f) of the four pairs yf, ym, θf, θm against frequency [Hz] (SI units on each axis), the "
                  "read-out band shaded and the values read there as lines (the seed's Fig. 11–12)");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(std::string(kFigureFooter) +
            "Example:\n"
            "  toolpoint identify --joint holder-tool --assembly examples/bt40_shrinkfit_16mm.toml \\\n"
            "      --sh sh11.csv --sht sht11.csv --output kht.csv --plot kht.png");
  c->callback([o, &g] { run_identify(*o, g); });
}

}  // namespace toolpoint::cli
