// toolpoint identify: a joint's stiffness and damping from measured FRFs — the band fit with
// intervals (default) or the seed's closed form read at the mode (Eq. 6, 15, 18), with a forward
// check and a verdict. Thin: options → run_identification_study (studies/identification.hpp) → report.
// Units: SI (k in N/m, N, N/rad, N·m/rad; c in N·s/m, N·s, N·s/rad, N·m·s/rad); frequencies in
// Hz; the stated phase noise in degrees (said in its help). --plot draws k(f) and c(f) of the
// closed form (the seed's Fig. 11–12) with the identified values and their intervals.
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/identify_io.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/identification.hpp"

namespace toolpoint::cli {

namespace {

struct IdentifyOptions {
  std::string joint = "holder-tool", method = "fit", assembly, sh, s, band, output, plot, filter, joint_output;
  std::vector<std::string> sht;
  std::optional<double> at;
  // --sigma, --phase-sigma [°], --floor, --calibration, --averages: noise_spec_fields.
  FieldFlags<NoiseSpec> noise;
  bool calibration_shared = false;
  FieldFlags<IdentificationOptions> fields;  // --width (identification_fields)
  int bootstrap = 200, parameters = 6;
  FieldFlags<ParallelOptions> parallel;  // --threads
  std::uint64_t seed = 1;
  std::vector<std::string> overhang_frfs;
  bool json = false, accept = false;
};

// "FILE" or "FILE@OVERHANG" (metres): a set-up at another overhang.
std::pair<std::string, std::optional<double>> split_overhang(const std::string& spec) {
  const std::size_t at = spec.rfind('@');
  if (at == std::string::npos || std::filesystem::exists(spec)) return {spec, std::nullopt};
  const std::string number = spec.substr(at + 1);
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != number.size() || !(v > 0.0) || !std::isfinite(v))
    throw InvalidArgument(fmt::format("--sht {}: '{}' after '@' is not a tool overhang in m", spec, number),
                          "write FILE@OVERHANG with the overhang in metres, e.g. sht11_60mm.csv@0.060");
  if (v > 0.5)
    throw InvalidArgument(fmt::format("--sht {}: an overhang of {} m is implausible (millimetres meant?)", spec, v),
                          fmt::format("the overhang is in metres: {} mm is {:g}", v, v / 1000));
  return {spec.substr(0, at), v};
}

SavgolOptions parse_filter(const std::string& text) {
  int w = 0, p = 0;
  char comma = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d %c %d %c", &w, &comma, &p, &extra) != 3 || comma != ',')
    throw InvalidArgument(fmt::format("--filter '{}' is not WINDOW,ORDER", text),
                          "e.g. --filter 41,2 (41 frequency points, quadratic)");
  SavgolOptions o{w, p};
  try {
    o.check();
  } catch (const InvalidArgument& e) {  // the window and order are the two numbers of --filter here, not --window/--order
    std::string what = e.what();
    for (const auto& [field, name] : {std::pair{"SavgolOptions::window", "WINDOW"}, {"SavgolOptions::order", "ORDER"}})
      for (std::size_t at = what.find(field); at != std::string::npos; at = what.find(field))
        what.replace(at, std::strlen(field), name);
    throw InvalidArgument(fmt::format("--filter {}: {}", text, what), e.hint());
  }
  return o;
}

void print_report(const IdentifyOptions& o, const Identification& id);

void run_identify(const IdentifyOptions& o, const Globals& g) {
  check_plot_path(o.plot);
  const bool ht = o.joint == "holder-tool";
  // Options to the library's fields (errors name the flags).
  IdentificationOptions io;
  io.method = o.method == "seed" ? IdentificationMethod::Seed : IdentificationMethod::Fit;
  o.fields.apply(io);
  if (!o.band.empty()) io.band_hz = parse_range(o.band, "--band");
  io.at_hz = o.at;
  if (!o.filter.empty()) io.filter = parse_filter(o.filter);
  o.noise.apply(io.noise);
  // Any σ or floor given states the noise; what is not stated is zero.
  if (o.noise.given("magnitude_sigma") || o.noise.given("phase_sigma_rad") || o.noise.given("floor"))
    io.noise.source = NoiseSpec::Source::Stated;
  if (o.bootstrap == 0) {
    io.fit.uncertainty = UncertaintyMethod::Linearised;
  } else if (o.bootstrap < 20) {
    throw InvalidArgument(fmt::format("--bootstrap {}: use 0 (linearised intervals) or ≥ 20 replicates", o.bootstrap),
                          "e.g. --bootstrap 200");
  } else {
    io.fit.bootstrap_samples = o.bootstrap;
  }
  io.noise.calibration_shared = o.calibration_shared;
  io.fit.reciprocal = o.parameters == 6;
  io.fit.seed = o.seed;
  o.parallel.apply(io.fit.parallel);
  io.check();  // before any work; its messages name the fields, spelt as the flags by with_flags

  // Inputs, and outputs that must not overwrite them.
  std::vector<IdentificationData> data;
  std::vector<std::string> inputs{o.assembly};
  std::optional<FrfFileData> B;
  auto setup = [&](const std::string& spec) {
    auto [path, overhang] = split_overhang(spec);
    FrfFileData G = read_block_input(g, path);
    IdentificationData d{"", overhang, std::move(G.block), path, std::nullopt, ht ? o.sh : o.s, std::move(G.coherence), {}};
    if (B) {
      d.B11 = B->block;
      d.b_coherence = B->coherence;
    }
    data.push_back(std::move(d));
    inputs.push_back(path);
  };
  if (ht) {
    if (o.sh.empty() || o.sht.empty())
      throw InvalidArgument("--joint holder-tool needs --sh SH11.csv and --sht SHT11.csv",
                            "give both measured blocks, e.g. --sh sh11.csv --sht sht11.csv");
    io.route = Route::HolderTool;
    B = read_block_input(g, o.sh);
    inputs.push_back(o.sh);
    for (const auto& spec : o.sht) setup(spec);
  } else {
    if (o.sh.empty() == o.sht.empty())
      throw InvalidArgument("--joint spindle-holder needs exactly one of --sh SH11.csv (Eq. 15) or --sht SHT11.csv (Eq. 18)",
                            "give --sh for the holder tip FRF or --sht for the tool point FRF, not both");
    if (!o.s.empty()) {
      B = read_block_input(g, o.s);
      inputs.push_back(o.s);
    }
    if (!o.sh.empty()) {
      io.route = Route::SpindleHolderFromSH;
      setup(o.sh);
    } else {
      io.route = Route::SpindleHolderFromSHT;
      for (const auto& spec : o.sht) setup(spec);
    }
  }
  {
    std::vector<RunPath> in;
    for (const std::string& p : inputs) in.push_back({p, "input"});
    for (const std::string& p : o.overhang_frfs) in.push_back({p, "--overhang-frf"});
    check_paths(in, {{o.output, "--output"}, {o.joint_output, "--joint-output"}, {o.plot, "--plot"}});
  }
  check_output_extension(o.output, "--output", {".csv"}, "the joint's K(ω) table as CSV (.csv)");
  if (!o.joint_output.empty() && std::filesystem::path(o.joint_output).extension() != ".toml")
    throw InvalidArgument(fmt::format("--joint-output {}: a joint file is TOML", o.joint_output), "name it FILE.toml");
  for (const auto& p : o.overhang_frfs) io.overhang_frfs.push_back(read_point_frf(g, p));

  Progress progress(g, "identify");
  const LoadedAssembly loaded = load_assembly_on_grid(g, o.assembly);
  const Identification id = run_identification_study(loaded.assembly, data, io, progress.part(0.05, 0.95));
  progress.done();
  warn_all(id.warnings);

  // Results are written unless the verdict is fail (then only with --accept).
  const bool refuse = id.verdict.verdict == Verdict::Fail && !o.accept;
  std::vector<std::string> written;
  if (!refuse && !o.output.empty() && id.closed_form.size() > 0) {
    write_table_csv(o.output, joint_table(id.closed_form),
                    {fmt::format("toolpoint identify: {} joint, {} (closed form per frequency)", o.joint, id.equation),
                     "k = Re K, c = Im K / omega; units in the column names (SI); frequency in Hz"});
    written.push_back(o.output);
  }
  if (!refuse && !o.joint_output.empty()) {
    write_joint_file(o.joint_output, joint_file_of(id, std::vector<std::string>(inputs.begin(), inputs.end())));
    written.push_back(o.joint_output);
  }
  if (o.json) {
    nlohmann::json j = nlohmann::json(id);
    j["joint"] = o.joint;
    if (!o.output.empty()) j["output"] = o.output;
    if (!o.joint_output.empty()) j["joint_output"] = o.joint_output;
    if (!o.plot.empty()) j["plot"] = o.plot;
    std::cout << j.dump(2) << '\n';
  } else {
    print_report(o, id);
  }
  for (const auto& w : written) info(g, "wrote " + w);
  if (!refuse && !o.plot.empty()) draw_figures(g, {{identification_figure(id), o.plot}}, written);
  if (refuse)
    throw VerdictFailure(fmt::format("the identified joint fails its checks: {}", fmt::join(id.verdict.reasons, "; ")),
                         "check the data and the assembly (units, the right files for SH11 and SHT11, the band); --accept writes "
                         "the results anyway");
}

void print_report(const IdentifyOptions& o, const Identification& id) {
  std::cout << fmt::format("{} joint, {}\n", o.joint, id.equation);
  for (std::size_t s = 0; s < id.g_noise.size(); ++s)
    std::cout << fmt::format("noise, set-up {}: G11 {}\n                B11 {}\n", s + 1, id.g_noise[s].summary(),
                             id.b_noise[s].summary());
  const bool seed_ok = id.seed.points > 0;
  if (seed_ok)
    std::cout << fmt::format("seed read-out: {:.1f}–{:.1f} Hz ({} points; {}, centre {:.1f} Hz)\n", id.seed.band_lo_hz,
                             id.seed.band_hi_hz, id.seed.points, id.mode.method, id.mode.center_hz);
  if (id.fit) {
    const JointFit& f = *id.fit;
    std::cout << fmt::format("band fit: {} frequencies, {:g}–{:g} Hz, {} parameters{}; residual ratio {:.3g}\n  intervals: {}\n",
                             f.points, id.fit_band_hz.first, id.fit_band_hz.second, f.reciprocal ? 6 : 8,
                             f.reciprocal ? " (k_tf = k_ym, c_tf = c_ym)" : "", f.residual_ratio, f.method_description);
    std::cout
        << "\nparameter  estimate      95 % interval                  unit        verdict       seed read-out (noise gain)\n";
    for (int k = 0; k < 8; ++k) {
      const ParameterInterval& iv = f.intervals[static_cast<std::size_t>(k)];
      std::cout << fmt::format("{:<9}  {:>11.5g}  [{:>11.5g}, {:>11.5g}]  {:<10}  {:<12}  {}\n", JointParameters::name(k),
                               iv.estimate, iv.lower, iv.upper, JointParameters::unit(k),
                               iv.determined ? "determined" : "UNDETERMINED",
                               seed_ok ? fmt::format("{:.4g} ({:.3g})", id.seed.parameters[static_cast<std::size_t>(k)].median,
                                                     id.seed.noise_gain[static_cast<std::size_t>(k)])
                                       : std::string("-"));
    }
    if (f.setups.size() > 1) {
      std::cout << fmt::format("\nset-ups fitted alone (transfer test χ² = {:.3g}, 99.9 % limit {:.3g}: {})\n",
                               f.transfer_statistic, f.transfer_limit,
                               f.transfers ? "the joint transfers" : "the joint does NOT transfer");
      for (const SetupFit& s : f.setups) {
        const auto se = [&](JointParameter p) { return s.std_error[static_cast<std::size_t>(p)]; };
        std::cout << fmt::format("  {:<22} k_yf {:.5g} ± {:.2g}, k_tm {:.5g} ± {:.2g}, c_tm {:.4g} ± {:.2g}\n", s.label,
                                 s.fitted.k_yf, se(JointParameter::k_yf), s.fitted.k_tm, se(JointParameter::k_tm), s.fitted.c_tm,
                                 se(JointParameter::c_tm));
      }
    }
  } else {
    std::cout << "\nparameter  median         spread       unit        noise gain\n";
    for (int k = 0; k < 8; ++k) {
      const auto& p = id.seed.parameters[static_cast<std::size_t>(k)];
      std::cout << fmt::format("{:<9}  {:>12.5g}  {:>11.3g}  {:<10}  {:>8.3g}\n", JointParameters::name(k), p.median, p.spread,
                               JointParameters::unit(k), id.seed.noise_gain[static_cast<std::size_t>(k)]);
    }
    std::cout << fmt::format(
        "reciprocity: k_ym vs k_tf {:.2g}, c_ym vs c_tf {:.2g} (relative difference); cond(A11 - G11) ≤ {:.3g}\n",
        id.seed.reciprocity_k, id.seed.reciprocity_c, id.seed.max_cond_difference);
  }
  for (const ForwardCheck& fc : id.forward_checks) {
    std::cout << fmt::format(
        "\nforward check{} (identified joint back into the forward model, both sides smoothed alike; {}):\n"
        "  model_hz  measured_hz  predicted_hz  freq_error (noise ± sd)   peak_error (noise ± sd)   agreement\n",
        id.forward_checks.size() > 1 ? ", " + fc.label : "",
        fc.replicates > 0 ? fmt::format("judged against {} noise replicates, false alarm {:g} %, |z| ≤ {:.3g}", fc.replicates,
                                        100 * fc.false_alarm, fc.z)
                          : std::string("exact data: judged by the tolerances"));
    auto pct = [](double x) { return std::isfinite(x) ? fmt::format("{:+.2g} %", 100 * x) : std::string("-"); };
    auto sd = [](double x) { return std::isfinite(x) ? fmt::format("± {:.2g} %", 100 * x) : std::string(""); };
    auto hz = [](double x) { return std::isfinite(x) ? fmt::format("{:.1f}", x) : std::string("-"); };
    // A mode under the noise says how far under.
    auto agreement = [&](const ModeCheck& c) {
      return c.agreement == ModeAgreement::NotResolved && fc.replicates > 0 && c.clearance < kModeClearance
                 ? fmt::format("{} (stands {:.2g} noise σ clear, {:g} needed)", to_string(c.agreement), c.clearance,
                               kModeClearance)
                 : std::string(to_string(c.agreement));
    };
    for (const ModeCheck& c : fc.modes)
      std::cout << fmt::format("  {:8.1f}  {:>11}  {:>12}  {:>10} {:<12}  {:>10} {:<12}  {}\n", c.model_hz, hz(c.measured_hz),
                               hz(c.predicted_hz), pct(c.frequency_error), sd(c.frequency_sd), pct(c.magnitude_error),
                               sd(c.magnitude_sd), agreement(c));
    for (const ExtraPeak& e : fc.extra)
      std::cout << fmt::format("  a peak of the data at {:.1f} Hz (prominence {:.2g}) in no mode's window: {}\n", e.frequency_hz,
                               e.prominence,
                               e.significant ? "not made by the noise"
                                             : fmt::format("the noise makes such peaks (p = {:.2g})", e.p_value));
    for (const auto& n : fc.notes) std::cout << "  note: " << n << "\n";
  }
  std::cout << fmt::format("\nverdict: {}\n", to_string(id.verdict.verdict));
  for (const auto& r : id.verdict.reasons) std::cout << "  - " << r << "\n";
  std::cout << std::flush;
}

}  // namespace

void add_identify_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<IdentifyOptions>();
  CLI::App* c = app.add_subcommand(
      "identify",
      "Joint stiffness and damping from measured FRFs: band fit with intervals, or the seed's closed form (Eq. 6, 15, 18)");
  c->add_option("--joint", o->joint, "holder-tool (Eq. 6) or spindle-holder (Eq. 15 with --sh, Eq. 18 with --sht)")
      ->check(CLI::IsMember({"holder-tool", "spindle-holder"}))
      ->capture_default_str();
  c->add_option("--method", o->method,
                "fit: the joint's constants fitted to every frequency (or --band) with 95 % intervals; seed: the closed form "
                "read at the mode the joint controls (the seed's procedure, no interval)")
      ->check(CLI::IsMember({"fit", "seed"}))
      ->capture_default_str();
  c->add_option("--assembly", o->assembly,
                "Assembly file (TOML, SI units): the model's free–free components; its joint values serve as trial values "
                "(required)")
      ->required();
  c->add_option("--sh", o->sh,
                std::string("SH11, holder tip of spindle + holder with the tool outside removed: ") + kBlockCsvHelp);
  add_frf_read_options(c, g);
  c->add_option("--sht", o->sht,
                std::string("SHT11, tool point of the whole assembly; repeat for other overhangs as FILE@OVERHANG [m] (fitted "
                            "together; the first is the reference): ") +
                    kBlockCsvHelp);
  c->add_option("--s", o->s,
                std::string("S11, spindle nose alone (spindle-holder joint; default: the model's spindle): ") + kBlockCsvHelp);
  c->add_option("--band", o->band,
                "Identify in F1:F2 [Hz]: the seed's read-out band and the fit's band (default: the read-out around "
                "the mode the joint controls, the fit over every frequency)");
  c->add_option(
      "--at", o->at,
      "Read the seed's parameters around this frequency [Hz] (default: the mode chosen by effect analysis or --overhang-frfs)");
  o->fields.add(c, option_field(identification_fields(), "width"));
  c->add_option("--overhang-frfs", o->overhang_frfs,
                std::string("Tool point FRFs at other overhangs, comma-separated: choose the mode that moves most with the "
                            "overhang (seed Fig. 10). Each: ") +
                    kPointFrfHelp)
      ->delimiter(',');
  c->add_option(
      "--filter", o->filter,
      "Savitzky–Golay filter WINDOW,ORDER [frequency points, -] applied to the data (the seed's read-out) and, alike, to "
      "data and model in the fit (default: none; give raw data, the fit needs no filter)");
  const auto& noise = noise_spec_fields();
  const char* stated = "; stating --sigma, --phase-sigma or --floor states the noise, the others then zero (default: "
                       "estimated from the data)";
  for (const char* name : {"magnitude_sigma", "phase_sigma_rad", "floor"}) {
    auto* flag = o->noise.add(c, option_field(noise, name), true);
    flag->description(flag->get_description() + stated)->default_str("");
  }
  o->noise.add_fraction(c, option_field(noise, "calibration"));
  c->add_flag("--calibration-shared", o->calibration_shared,
              "One sensor chain (hammer and response sensor) for every measured FRF: one calibration factor for all of "
              "them (default: one per file)");
  o->noise.add(c, option_field(noise, "averages"));
  c->add_option("--bootstrap", o->bootstrap, "Fit intervals: bootstrap replicates (≥ 20), or 0 for linearised intervals")
      ->capture_default_str();
  c->add_option("--parameters", o->parameters, "6: k_tf = k_ym and c_tf = c_ym (reciprocity); 8: all eight free")
      ->check(CLI::IsMember({6, 8}))
      ->capture_default_str();
  c->add_option("--seed", o->seed, "Random seed of the bootstrap")->capture_default_str();
  add_threads_option(c, o->parallel);
  c->add_option("--output", o->output,
                "Write the closed form's k(f), c(f) (SI units in the column names), condition numbers and noise gains per "
                "frequency [Hz] here (CSV; default: none)");
  c->add_option("--joint-output", o->joint_output,
                "Write the identified joint (constants, covariance, how it was identified) to this TOML file, for "
                "`--joint holder-tool=FILE` of predict, couple, taptest, lobes and demo (default: none)");
  c->add_flag("--accept", o->accept, "Write the results even when the verdict is fail (exit 0 then)");
  add_plot_option(
      c, o->plot,
      "k(f) and c(f) of the four pairs yf, ym, θf, θm by the closed form against frequency [Hz] (SI units on each "
      "axis), the read-out band shaded, the identified values as lines with their 95 % interval (the seed's Fig. 11–12)");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(std::string(kFigureFooter) +
            "Verdict: pass, doubtful or fail (a negative diagonal stiffness, a forward-check error above 5 % in frequency\n"
            "or 50 % in peak height, the same data for SH11 and SHT11, …). On fail nothing is written and the exit\n"
            "code is 6, unless --accept.\n"
            "Example:\n"
            "  toolpoint identify --joint holder-tool --assembly examples/bt40_shrinkfit_16mm.toml \\\n"
            "      --sh sh11.csv --sht sht11.csv --joint-output kht.toml --plot kht.png");
  c->callback([o, &g] { run_identify(*o, g); });
}

}  // namespace toolpoint::cli
