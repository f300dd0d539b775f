// toolpoint CLI: messages, figures and FRF inputs shared by the subcommands (cli.hpp).
// Units: SI (receptance m/N, joint parameters in their SI units); frequencies in Hz.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <tuple>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>

#include "cli.hpp"
#include "progress.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/pitch.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/precision.hpp"
#include "toolpoint/studies/rotational.hpp"
#include "toolpoint/studies/beam.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/tap_test.hpp"

namespace toolpoint::cli {

void info(const Globals& g, const std::string& message) {
  if (g.quiet) return;
  Progress::clear_line();
  std::cerr << message << '\n';
}

void warn(const std::string& message) {
  Progress::clear_line();
  std::cerr << "warning: " << message << '\n';
}

void warn_all(const std::vector<std::string>& messages) {
  for (const auto& m : messages) warn(with_flags(m));
}

// ---- Figures ------------------------------------------------------------------------------------

const char* const kFigureFooter =
    "Figures (--plot): drawn by gnuplot after the data are written. If gnuplot is missing or fails,\n"
    "the data files stay written, the error names them, and the exit code is 5.\n";

void report_loaded(const Globals& g, const LoadedAssembly& loaded) {
  warn_all(loaded.warnings);
  for (const auto& n : loaded.notes) info(g, "note: " + n);
}

LoadedAssembly load_assembly_on_grid(const Globals& g, const std::string& path, const std::string& frequencies,
                                     const std::vector<JointFile>& joints) {
  LoadedAssembly loaded = with_joints(load_assembly(path), joints);
  report_loaded(g, loaded);
  if (!frequencies.empty()) {
    loaded.assembly.grid = parse_frequency_grid(frequencies, "--frequencies");
    check_plausible(plausible::kTopFrequency, loaded.assembly.grid.stop_hz, "--frequencies: the top frequency [Hz]",
                    "give START:STOP:STEP in Hz, e.g. 10:5000:1");
  }
  return loaded;
}

LoadedModel load_model(const Globals& g, const std::string& path, const std::string& frequencies,
                       const std::vector<JointFile>& joints) {
  LoadedAssembly loaded = load_assembly_on_grid(g, path, frequencies, joints);
  AssemblyModel model(loaded.assembly);
  warn_all(model.warnings());
  return {std::move(loaded), std::move(model)};
}

CLI::Option* add_joint_option(CLI::App* command, std::vector<std::string>& target) {
  return command
      ->add_option("--joint", target,
                   "Use an identified joint instead of the assembly file's: holder-tool=FILE.toml or spindle-holder=FILE.toml "
                   "(as written by `toolpoint identify --joint-output`; repeat for both joints)")
      ->option_text("INTERFACE=FILE");
}

std::vector<JointFile> read_joint_options(const Globals& g, const std::vector<std::string>& specs) {
  std::vector<JointFile> files;
  for (const std::string& spec : specs) {
    const std::size_t eq = spec.find('=');
    std::string path = spec;
    std::optional<JointInterface> named;
    if (eq != std::string::npos) {
      const std::string name = spec.substr(0, eq);
      path = spec.substr(eq + 1);
      if (name == "holder-tool") named = JointInterface::HolderTool;
      else if (name == "spindle-holder") named = JointInterface::SpindleHolder;
      else
        throw InvalidArgument(fmt::format("--joint {}: '{}' names no joint", spec, name),
                              "write holder-tool=FILE.toml or spindle-holder=FILE.toml");
    }
    JointFile f = load_joint_file(path);
    if (named && *named != f.interface)
      throw InvalidArgument(fmt::format("--joint {}: {} holds the {} joint, not the {} joint", spec, path, to_string(f.interface),
                                        to_string(*named)),
                            fmt::format("write --joint {}={}",
                                        f.interface == JointInterface::HolderTool ? "holder-tool" : "spindle-holder", path));
    for (const JointFile& other : files)
      if (other.interface == f.interface)
        throw InvalidArgument(fmt::format("--joint: two files for the {} joint ({} and {})", to_string(f.interface), other.source,
                                          path),
                              "give one file per joint");
    info(g, fmt::format("joints.{}: the identified joint of {}{}", to_string(f.interface), path,
                        f.uncertainty ? " (with its covariance)" : ""));
    files.push_back(std::move(f));
  }
  return files;
}

std::vector<RunPath> joint_paths(const std::vector<std::string>& specs) {
  std::vector<RunPath> paths;
  for (const std::string& spec : specs) paths.push_back({spec.substr(spec.find('=') + 1), "--joint file"});
  return paths;
}

LoadedAssembly with_joints(LoadedAssembly loaded, const std::vector<JointFile>& files) {
  for (const JointFile& f : files) loaded = with_joint(std::move(loaded), f);
  return loaded;
}

void add_sampling_options(CLI::App* command, SamplingOptions& target, const std::string& what, bool threads_option) {
  const FieldSpec& samples = option_field(uncertainty_fields(), "samples").spec;
  command
      ->add_option(field_flag(samples), target.samples,
                   fmt::format("Carry the --joint file's uncertainty forward by Monte Carlo: {} [-], {} (0: none): {}",
                               samples.help, field_range_text(samples), what))
      ->capture_default_str();
  command->add_option("--seed", target.seed, "Random seed of the joint samples")->capture_default_str();
  if (threads_option) add_threads_option(command, target.parallel);
}

CLI::Option* add_threads_option(CLI::App* command, FieldFlags<ParallelOptions>& flags) {
  return flags.add(command, option_field(parallel_fields(), "threads"));
}

const JointFile& sampled_joint(const std::vector<JointFile>& files) {
  const JointFile* found = nullptr;
  for (const JointFile& f : files)
    if (f.uncertainty) {
      if (found)
        throw InvalidArgument(fmt::format("--samples: both {} and {} carry an uncertainty; one joint is sampled at a time",
                                          found->source, f.source),
                              "give the other joint without --samples, or as assembly-file values");
      found = &f;
    }
  if (!found)
    throw InvalidArgument(
        "--samples needs a --joint file with an [uncertainty] (a band fit's covariance)",
        "identify the joint with `toolpoint identify --joint-output FILE.toml` and pass --joint holder-tool=FILE.toml");
  return *found;
}

UncertaintyOptions uncertainty_options(const SamplingOptions& s) {
  UncertaintyOptions o;
  o.samples = s.samples;
  o.seed = s.seed;
  s.parallel.apply(o.parallel);
  o.check();  // main names the flags (with_flags)
  return o;
}

CLI::Option* add_plot_option(CLI::App* command, std::string& target, const std::string& what) {
  return command
      ->add_option("--plot", target,
                   "Draw a figure in FILE (.png, .svg or .pdf by extension, through gnuplot; default: none): " + what)
      ->option_text("FILE");
}

void check_plot_path(const std::string& path, const std::string& option) {
  if (path.empty()) return;
  try {
    plot::format_for_path(path);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("{}: {}", option, e.what()), e.hint());
  }
}

std::string with_suffix(const std::string& path, const std::string& suffix) {
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

namespace {

std::string listing(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

void draw_figures(const Globals& g, const std::vector<FigureFile>& figures, const std::vector<std::string>& written,
                  const std::string& skip) {
  // The data of the run are written first (all or none); then the figures, all or none among themselves.
  if (OutputSet* data = OutputSet::active()) data->commit();
  OutputSet staged_figures;
  std::vector<std::string> drawn;
  for (const FigureFile& f : figures) {
    plot::RenderResult r;
    // What stands on disk, for the message if this figure fails.
    const auto what_stands = [&] {
      std::string s;
      if (!written.empty()) s += "; the data were written to " + listing(written);
      if (!drawn.empty()) s += "; figures drawn but not written (all or none): " + listing(drawn);
      return s;
    };
    try {
      r = plot::render(f.figure, f.path);
    } catch (const plot::PlotUnavailable& e) {
      throw plot::PlotUnavailable(fmt::format("figure {} not drawn: {}{}", f.path, e.what(), what_stands()),
                                  (e.hint().empty() ? "install gnuplot" : e.hint()) + ", or " + skip);
    } catch (const IoError& e) {
      throw IoError(fmt::format("figure {} not drawn: {}{}", f.path, e.what(), what_stands()),
                    (e.hint().empty() ? "check that the folder is writable and gnuplot works (`gnuplot --version`)" : e.hint()) +
                        ", or " + skip);
    }
    for (const auto& n : r.notes) info(g, "note: " + n);
    warn_all(r.warnings);
    info(g, fmt::format("wrote {} (gnuplot terminal {})", f.path, r.terminal));
    drawn.push_back(f.path);
  }
  staged_figures.commit();
}

void draw_frf_overlay(const Globals& g, const std::vector<plot::FrfTrace>& traces, const plot::FrfFigureOptions& options,
                      const std::string& plot_path, const std::string& written) {
  draw_figures(g, {{plot::frf_figure(traces, options), plot_path}}, {written});
}

// ---- FRF inputs -----------------------------------------------------------------------------

#define TOOLPOINT_SINGLE_FRF_FORMATS                                                                       \
  "FRF CSV (frequency_hz,re,im), UFF dataset 58/58b (.uff/.unv/.uf; FILE#N picks dataset N, numbered as "  \
  "`toolpoint convert FILE --list` shows; mobility/accelerance converted) or CutPro .frf; receptance m/N " \
  "against frequency Hz"
const char* const kSingleFrfHelp = TOOLPOINT_SINGLE_FRF_FORMATS;
const char* const kPointFrfHelp = TOOLPOINT_SINGLE_FRF_FORMATS ", or a 2×2 block CSV (its H entry, w/f, is used)";
#undef TOOLPOINT_SINGLE_FRF_FORMATS

const char* const kBlockCsvHelp =
    "2×2 block FRF CSV (H m/N, L 1/N, N rad/N, P rad/(N m); CSV only: the one format that carries rotations; ',', ';' "
    "or tab between columns, decimal comma, a coherence column read)";

void add_frf_read_options(CLI::App* command, Globals& g) {
  command->add_option("--ordinate", g.frf.ordinate,
                      "What the input FRF values are: receptance [m/N], mobility [(m/s)/N] or accelerance [(m/s^2)/N]; "
                      "converted to receptance (H = Y/(iω), H = A/(−ω²), ω = 2πf). Default: the file's units (CSV "
                      "header, UFF labels) or UFF record 9/10 codes, else receptance");
  command->add_option("--units", g.frf.units,
                      "Units of the input FRF values, e.g. m/N, mm/N, um/N, m/s/N, mm/s/N, m/s^2/N, g/N (g = 9.80665 "
                      "m/s²), in/lbf; they say the ordinate and are scaled to SI. Default: the file's (CSV header, UFF "
                      "labels or dataset 164), else SI");
  command->add_option("--format", g.frf.format,
                      "CSV input: what the two value columns hold where the header does not say: re-im, mag-phase-deg, "
                      "mag-phase-rad, db-phase (dB of |H| in the units, phase in degrees) or db-phase-rad");
  command
      ->add_option("--columns", g.frf.columns,
                   "CSV input: the frequency column, the two value columns and optionally a coherence column, by "
                   "number from 1 or by header text, comma-separated, e.g. 1,4,5 (default: found by the header's "
                   "names)")
      ->delimiter(',')
      ->expected(3, 4);
}

std::string field_help(const FieldSpec& s) {
  std::string help = s.help;
  if (!help.empty()) help[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(help[0])));
  if (s.kind == FieldKind::Flag) return help;
  const char* unit = s.cli_unit ? s.cli_unit : *s.unit ? s.unit : "-";
  // Where the field has a plausible range, the usual values too, in the flag's unit: a value far
  // outside them is refused although the range admits it (a spin of 15 rpm, a diameter of 0.016 mm).
  const std::string usual = s.plausible ? fmt::format("; usually {:g}…{:g}", s.plausible->low * s.cli_per_unit,
                                                      s.plausible->high * s.cli_per_unit)
                                        : std::string();
  return fmt::format("{} [{}], {}{}{}", help, unit, field_range_text(s, s.cli_per_unit),
                     *s.note ? fmt::format(" ({})", s.note) : std::string(), usual);
}

// The likely slip a flag's implausible value shows: the field's own hint where the flag takes the
// field's unit, else the unit the flag takes (the field's hint speaks of its SI unit: "diameters
// are in metres" is the wrong advice on a flag in mm).
static std::string flag_slip_hint(const FieldSpec& s) {
  return s.cli_per_unit == 1.0 ? std::string(s.plausible->hint) : fmt::format("{} takes {}", field_flag(s), s.cli_unit);
}

void field_flag_refused(const FieldSpec& s, double typed) {
  const char* unit = s.cli_unit ? s.cli_unit : s.unit;
  const std::string in_unit = *unit ? fmt::format(" {}", unit) : "", note = *s.note ? fmt::format(" ({})", s.note) : "";
  // Out of range and, in the field's unit, a value no one can mean: the likely slip too (5 for 5 %).
  const std::string slip = s.plausible && std::isfinite(typed) && typed != 0.0 &&
                                   judge(*s.plausible, typed / s.cli_per_unit) == Plausibility::Impossible
                               ? fmt::format("; {}", flag_slip_hint(s))
                               : std::string();
  throw InvalidArgument(fmt::format("{} {}{} {}{}{}", field_flag(s), field_value_text(s, typed), in_unit,
                                    field_range_phrase(s, s.cli_per_unit), note, slip),
                        fmt::format("give {} a value {}{}{}", field_flag(s), field_range_value(s, s.cli_per_unit), in_unit, note));
}

std::string with_flags(std::string text) {
  // Field → flag, for every command (a field's flag is the same wherever it appears); a library
  // function → the command that does it. In order: a longer name before a name it starts with.
  static const std::pair<std::string_view, std::string_view> kFlags[] = {
      {"FrfReadOptions::format = FrfFormat::Csv", "`toolpoint convert FILE OUT --from csv`"},
      {"UffFile::functions", "`toolpoint convert FILE --list`"},
      {"UffFile::skipped", "`toolpoint convert FILE --list`"},
      {"UffFile::file_warnings", "`toolpoint convert FILE --list`"},
      {"rotational_frfs", "`toolpoint rotational`"},
      {"write_joint_file", "`toolpoint identify --joint-output FILE.toml`"},
      {"run_plan_part", "`toolpoint plan --shard I/N`"},
      {"choose_pitch", "`toolpoint pitch`"},
      {"format_plan_part", "`toolpoint plan --shard I/N --part FILE`"},
      {"run_simulated_map_part", "`toolpoint simulate map --shard I/N`"},
      {"format_simulated_map_part", "`toolpoint simulate map --shard I/N --part FILE`"},
      {"Cutter::pitch_rad", "--pitch"},
      {"Cutter::helix_rad", "--helix"},
      {"Cutter::tooth_helix_rad", "--helix"},
      {"Cutter::runout_m", "--runout"},
      {"MillingCut::speed_rpm", "--rpm"},
      {"MillingCut::depth_m", "--depth"},
      {"MillingCut::engagement", "--immersion or --entry/--exit"},
      {"SimulatedMapOptions::depths", "--depth"},
      {"SimulationInput::rigid", "--rigid-tool"},
      {"(SimulationOptions::record = false)", "(`toolpoint simulate map` keeps none)"},
      {"resample()", "`toolpoint resample IN OUT --onto OTHER`"},
      {"crop()", "`toolpoint resample IN OUT --band F1:F2`"},
      {"MillingFrfs::rigid_y", "--rigid-y"},
      {"PrecisionOptions::tool.spacing_m", "--tool-spacing"},
      {"PrecisionOptions::holder.spacing_m", "--holder-spacing"},
      {"PrecisionOptions::target", "--target"},
      {"OverhangStudyOptions::overhangs_m", "--overhang"},
      {"OverhangStudyOptions::peaks: --prominence", "--prominence"},  // PeakOptions' field mapped first
      {"OverhangStudyOptions::peaks", "--prominence"},
      {"FrfResampleOptions::band_hz", "--band"},
      {"FrfResampleOptions::target_hz", "--onto or --grid"},
      {"BeamStudyOptions::modal.modes", "--modal-terms"},
      {"ModalOptions::modes", "--modal-terms"},
      {"BeamStudyOptions::modes", "--modes"},
      {"BeamStudyOptions::shear_coefficient", "--shear-coefficient"},
      {"BeamStudyOptions::frequency_hz", "--frequencies"},
      {"BeamStudyOptions::speed_rpm", "--speed"},
      {"PredictOptions::extrapolate_bearings", "--extrapolate-bearings"},
      {"PredictOptions::speed_rpm", "--speed"},
      {"BeamStudyOptions::campbell_rpm", "--campbell"},
      {"BeamStudyOptions::method", "--method"},
      {"FrfCsvOptions::columns", "--columns"},
      {"FrfCsvOptions::format", "--format"},
      {"FrfReadOptions::units", "--units"},
      {"FrfReadOptions::ordinate", "--ordinate"},
      {"FrfReadOptions::format", "--from"},
      {"UffSelection::index", "--dataset"},
      {"RotationalOptions::p_method SchmitzSmith", "--p-method n2h"},
      {"TapTestFileOptions::nodes", "--nodes"},
      {"TapTestFileOptions::direction", "--direction"},
      {"PitchChoiceOptions::speed_rpm", "--rpm"},
      {"PitchChoiceOptions::pattern", "--pattern"},
      {"PitchChoiceOptions::min_pitch_rad", "--min-pitch"},
      {"PitchChoiceOptions::max_pitch_rad", "--max-pitch"},
      {"PitchChoiceOptions::chatter_hz", "--chatter"},
      {"PitchChoiceOptions::window", "--window"},
      {"PitchChoiceOptions::search_points", "--search-points"},
      {"PitchChoiceOptions::robustness", "--robustness"},
      {"PitchChoiceOptions::steps", "--intervals"},
      {"PitchChoiceOptions::max_depth_m", "--max-depth"},
      {"PitchChoiceOptions::depth_steps", "--depth-steps"},
      {"BoundaryOptions::max_steps", "--intervals"},
      {"LobesStudyOptions::speed_model", "--speed-model"},
      {"LobesStudyOptions::speeds", "--rpm"},
      {"LobesMethod::ZeroOrder", "--method zoa"},
      {"SpeedModel::Standstill", "--speed-model standstill"},
      {"LobesInput::uncertain_joint", "--samples"},
      {"ModalFitOptions::band_hz", "--band"},
      {"IdentificationOptions::band_hz", "--band"},
      {"IdentificationOptions::at_hz", "--at"},
      {"LobesInput::x_modes", "--mode-x"},
      {"LobesInput::frfs", "--frf"},
      {"LobesInput: rigid_y and y modes", "--rigid-y and --mode-y"},
      {"SpeedRange::min_rpm and max_rpm", "--rpm MIN:MAX"},
      {"SpeedRange::min_rpm", "--rpm MIN"},
      {"SpeedRange::max_rpm", "--rpm MAX"},
      {"CuttingConditions::pitch_rad", "--pitch"},
      {"CuttingConditions::helix_rad", "--helix"},
      {"CuttingConditions::runout_m", "--runout"}};
  const auto replace = [&text](std::string_view field, std::string_view flag) {
    for (std::size_t at = text.find(field); at != std::string::npos; at = text.find(field, at + flag.size()))
      text.replace(at, field.size(), flag);
  };
  // The option fields defined once (option_fields.hpp): Options::name → its flag.
  const auto fields = [&replace](const auto& table, std::string_view options) {
    for (const auto& f : table)
      if (f.spec.cli_name) replace(fmt::format("{}::{}", options, f.spec.name), field_flag(f.spec));
  };
  fields(lobes_study_fields(), "LobesStudyOptions");
  fields(pitch_choice_fields(), "PitchChoiceOptions");
  fields(simulation_fields(), "SimulationOptions");
  fields(identification_fields(), "IdentificationOptions");
  fields(tap_test_fields(), "TapTestOptions");
  fields(noise_fields(), "NoiseOptions");
  fields(tap_noise_fields(), "TapNoise");
  fields(savgol_fields(), "SavgolOptions");
  fields(rotational_fields(), "RotationalOptions");
  fields(tap_test_file_fields(), "TapTestFileOptions");
  fields(uff_write_fields(), "UffWriteOptions");
  fields(modal_fit_fields(), "ModalFitOptions");
  fields(case_study_fields(), "CaseStudyOptions");
  fields(parallel_fields(), "ParallelOptions");
  fields(uncertainty_fields(), "UncertaintyOptions");
  fields(zero_order_fields(), "ZeroOrderOptions");
  fields(boundary_fields(), "BoundaryOptions");
  fields(modal_fields(), "ModalOptions");
  fields(beam_study_fields(), "BeamStudyOptions");
  fields(cutting_fields(), "CuttingConditions");
  fields(peak_fields(), "PeakOptions");
  fields(noise_spec_fields(), "NoiseSpec");
  fields(force_law_fields(), "ForceLaw");
  fields(cutter_fields(), "Cutter");
  fields(milling_cut_fields(), "MillingCut");
  fields(depth_range_fields(), "DepthRange");
  fields(speed_range_fields(), "SpeedRange");
  fields(predict_fields(), "PredictOptions");
  fields(overhang_study_fields(), "OverhangStudyOptions");
  for (const auto& [field, flag] : kFlags) replace(field, flag);
  return text;
}

void check_plausible(const PlausibleRange& range, double value, const std::string& what, const std::string& fix) {
  if (const std::string w = require_plausible(range, value, what, fix); !w.empty()) warn(w);
}

// The number typed, or NaN where it is none (the option's type check says so).
static double typed_number(const std::string& text) {
  try {
    return std::stod(text);
  } catch (const std::exception&) {
    return kNaN;
  }
}

CLI::Validator plausible_value(const PlausibleRange& range, const std::string& option) {
  return CLI::Validator(
      [range, option](std::string& text) -> std::string {
        const double v = typed_number(text);
        if (std::isnan(v) || v == 0.0) return {};
        switch (judge(range, v)) {
          case Plausibility::Usual: return {};
          case Plausibility::Unusual: warn(plausibility_message(range, v, option)); return {};
          case Plausibility::Impossible: break;
        }
        return plausibility_message(range, v, "the value");  // CLI11 puts the option's name first
      },
      "", "plausible");
}

CLI::Validator field_plausible_value(const FieldSpec& spec, bool warn_unusual) {
  const FieldSpec* s = &spec;  // a table's: static
  return CLI::Validator(
      [s, warn_unusual](std::string& text) -> std::string {
        const double v = typed_number(text);
        if (std::isnan(v)) return {};
        const Plausibility verdict = field_plausibility(*s, v / s->cli_per_unit);
        if (verdict == Plausibility::Usual || (verdict == Plausibility::Unusual && !warn_unusual)) return {};
        // In the flag's unit: the range scaled, and the slip said in the flag's words.
        const PlausibleRange& r = *s->plausible;
        const PlausibleRange shown{r.low * s->cli_per_unit, r.high * s->cli_per_unit, r.slack, ""};
        const std::string slip = "; " + flag_slip_hint(*s);
        if (verdict == Plausibility::Unusual) {
          warn(plausibility_message(shown, v, field_flag(*s)) + slip);
          return {};
        }
        return plausibility_message(shown, v, "the value") + slip;  // CLI11 puts the option's name first
      },
      "", "plausible");
}

FrfReadOptions frf_read_options(const FrfInputOptions& t) {
  FrfReadOptions r;
  if (!t.ordinate.empty()) r.ordinate = parse_frf_ordinate(t.ordinate, "--ordinate");
  if (!t.units.empty()) r.units = parse_frf_units_option(t.units, "--units");
  if (!t.format.empty()) r.csv.format = parse_frf_value_format(t.format, "--format");
  r.csv.columns = t.columns;
  try {
    r.check();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(with_flags(e.what()), with_flags(e.hint()));
  }
  return r;
}

FrfFileData read_frf_file_for_cli(const std::string& path, const FrfReadOptions& options) {
  try {
    return read_frf_file(path, options);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(with_flags(e.what()), with_flags(e.hint()));
  } catch (const InputError& e) {
    throw InputError(with_flags(e.what()), with_flags(e.hint()));
  }
}

void add_frf_file_arguments(CLI::App* command, Globals& g, std::string& input, std::string& output,
                            std::optional<std::size_t>& dataset, const std::string& block_note) {
  command
      ->add_option("input", input,
                   std::string("Input FRF (required): ") + kSingleFrfHelp + ", or a 2×2 block CSV (" + block_note + ")")
      ->required();
  command
      ->add_option("output", output,
                   "Output file (required), same form as the input, format by extension: .csv, .uff/.unv/.uf (ASCII UFF 58) "
                   "or .frf for a single FRF; .csv for a block")
      ->required();
  add_dataset_option(command, dataset);
  add_frf_read_options(command, g);
}

CLI::Option* add_dataset_option(CLI::App* command, std::optional<std::size_t>& target) {
  return command->add_option("--dataset", target,
                             "UFF input: the dataset 58 to read, by index from 0 as `toolpoint convert FILE --list` "
                             "shows (default: the file's only dataset 58)");
}

namespace {

// "tap.uff#3" → ("tap.uff", 3) unless a file of that exact name exists.
std::pair<std::string, std::optional<std::size_t>> split_dataset_suffix(const std::string& spec) {
  const std::size_t hash = spec.rfind('#');
  if (hash == std::string::npos || hash + 1 == spec.size() || std::filesystem::exists(spec)) return {spec, std::nullopt};
  const std::string digits = spec.substr(hash + 1);
  if (digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
    return {spec, std::nullopt};
  return {spec.substr(0, hash), std::stoul(digits)};
}

}  // namespace

void check_paths(const std::vector<RunPath>& inputs, const std::vector<RunPath>& outputs) {
  std::vector<RunPath> files;
  for (const RunPath& p : inputs) files.push_back({split_dataset_suffix(p.path).first, p.role});
  check_output_paths(files, outputs);
}

const char* const kBlockCsvOutput = "the 2×2 receptance block as FRF CSV (.csv; the one format that carries rotations)";

void check_output_extension(const std::string& path, const std::string& option, std::initializer_list<const char*> extensions,
                            const std::string& formats) {
  if (path.empty()) return;
  const std::string ext = option_word(std::filesystem::path(path).extension().string());
  std::string listed;
  for (const char* e : extensions) {
    if (ext == e) return;
    listed += (listed.empty() ? "" : ", ") + std::string(e);
  }
  throw InvalidArgument(fmt::format("{} {}: the extension '{}' names a format this command does not write there; it writes {}",
                                    option, path, ext, formats),
                        fmt::format("name the file with {}", listed));
}

FrfFileData read_frf_input(const Globals& g, const std::string& spec, std::optional<std::size_t> dataset) {
  auto [path, suffix] = split_dataset_suffix(spec);
  if (suffix && dataset)
    throw InvalidArgument(fmt::format("{}: dataset {} picked twice (#{} and --dataset {})", spec, *suffix, *suffix, *dataset),
                          "use either FILE#N or --dataset N");
  FrfReadOptions r = frf_read_options(g.frf);
  try {
    r.format = frf_format_of_path(path);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(e.what(),
                          "give an FRF CSV (.csv), a universal file (.uff, .unv, .uf) or a CutPro file (.frf); "
                          "`toolpoint convert --from FORMAT` reads files with other names");
  }
  r.uff.index = suffix ? suffix : dataset;
  if (r.uff.index && r.format != FrfFormat::Uff)
    throw InvalidArgument(fmt::format("{}: dataset {} asked for, but only UFF files have datasets ({} is {})", spec, *r.uff.index,
                                      path, frf_format_name(r.format)),
                          "drop --dataset / #N for CSV and .frf files");
  FrfFileData d = read_frf_file_for_cli(path, r);
  warn_all(d.warnings);
  return d;
}

FrfFileData read_block_input(const Globals& g, const std::string& path) {
  FrfReadOptions r = frf_read_options(g.frf);
  r.format = FrfFormat::Csv;  // the one format that carries rotations
  FrfFileData d = read_frf_file_for_cli(path, r);
  if (!d.is_block)
    throw InputError(fmt::format("{}: holds a single FRF where a 2×2 block is needed", path),
                     "give a block file with columns frequency_hz,H_re,H_im,L_re,L_im,N_re,N_im,P_re,P_im (e.g. from "
                     "`toolpoint rotational`)");
  warn_all(d.warnings);
  return d;
}

FrfSeries read_point_frf(const Globals& g, const std::string& spec, std::optional<std::size_t> dataset) {
  FrfFileData d = read_frf_input(g, spec, dataset);
  if (!d.is_block) return std::move(d.single);
  info(g, fmt::format("{} holds a 2×2 block: using its H entry (w/f)", spec));
  return entry(d.block, 0);
}

FrfSeries point_frf(const FrfFileData& data) { return data.is_block ? entry(data.block, 0) : data.single; }

FrfFormat output_frf_format(const std::string& path) {
  try {
    return frf_format_of_path(path);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(e.what(),
                          "name the output .csv (FRF CSV), .uff/.unv/.uf (ASCII UFF 58) or .frf (CutPro); "
                          "`toolpoint convert --to uffb` writes binary UFF");
  }
}

void check_frf_output(const std::string& path, FrfFormat format, bool is_block) {
  if (is_block && format != FrfFormat::Csv)
    throw InvalidArgument(fmt::format("{}: a 2×2 receptance block can only be written as FRF CSV, not {}", path,
                                      frf_format_name(format)),
                          "name the output .csv");
}

void write_frf_output(const std::string& path, FrfFormat format, const FrfFileData& data, const std::string& comment) {
  check_frf_output(path, format, data.is_block);
  FrfWriteOptions w;
  w.format = format;
  w.dof = data.dof;
  w.description = comment;
  w.coherence = data.coherence;
  warn_all(data.is_block ? write_frf_file(path, data.block, w) : write_frf_file(path, data.single, w));
}

}  // namespace toolpoint::cli

// ---- Milling: the cut and the tool point dynamics -------------------------------------------------

namespace toolpoint::cli {

void add_cut_options(CLI::App* c, CutArgs& o, const std::string& teeth_note, bool teeth_required, bool kt_required) {
  const auto& fields = cutting_fields();
  auto* teeth = o.fields.add(c, option_field(fields, "teeth"));
  teeth->description(teeth->get_description() + " (" + teeth_note + ")");
  teeth->required(teeth_required);
  o.fields.add(c, option_field(fields, "tangential_coefficient"), true)->required(kt_required);
  auto* kr = o.fields.add(c, option_field(fields, "radial_ratio"), true);
  kr->description(kr->get_description() + "; this or --kn required")->default_str("");
  auto* kn = c->add_option("--kn", o.kn,
                           "Radial (normal) cutting coefficient K_n = K_r·K_t [N/m²], ≥ 0 (this or --kr required)");
  kn->check(plausible_value(plausible::kCuttingCoefficient, "--kn"));
  kr->excludes(kn);
  auto* imm =
      c->add_option("--immersion", o.immersion,
                    "Radial immersion a/D [-] in (0, 1] (1: slotting); needs --milling (this or --entry/--exit required)");
  auto* entry_opt = c->add_option("--entry", o.entry_deg,
                                  "Entry angle φ_st [°, not rad], clockwise from the normal (y) direction, with --exit (both "
                                  "within π look like radians: refused)");
  auto* exit_opt = c->add_option("--exit", o.exit_deg, "Exit angle φ_ex [°] (0 ≤ entry < exit ≤ 180)");
  entry_opt->needs(exit_opt);
  exit_opt->needs(entry_opt);
  imm->excludes(entry_opt);
  imm->excludes(exit_opt);
  c->add_option("--milling", o.milling, "Milling direction with --immersion: up or down (no default)")
      ->check(CLI::IsMember({"up", "down"}));
}

Engagement cut_engagement(const CutArgs& o) {
  if (std::isnan(o.entry_deg)) {
    if (std::isnan(o.immersion))
      throw InvalidArgument("give the radial engagement: --immersion a/D with --milling up|down, or --entry/--exit [°]",
                            "e.g. --immersion 0.5 --milling down");
    if (o.milling.empty()) throw InvalidArgument("--immersion needs --milling up or --milling down", "add --milling down");
    return engagement_from_immersion(o.immersion, o.milling == "up" ? MillingDirection::Up : MillingDirection::Down);
  }
  // Both angles within π: radians meant for degrees (1.57, 3.14 for slotting) far more likely than
  // a cut of at most 3°, which gives lobes that look like any others; refused, and such a light
  // cut can still be given as an immersion.
  if (std::abs(o.entry_deg) <= kPi + 1e-3 && std::abs(o.exit_deg) <= kPi + 1e-3)
    throw InvalidArgument(
        fmt::format("--entry {} --exit {}: the angles are in degrees, so this is a cut of only {:g}°; they look like "
                    "radians",
                    o.entry_deg, o.exit_deg, o.exit_deg - o.entry_deg),
        fmt::format("give degrees: --entry {:g} --exit {:g}; for so light a cut, give --immersion a/D with --milling",
                    degrees_of(o.entry_deg), degrees_of(o.exit_deg)));
  return engagement_from_degrees(o.entry_deg, o.exit_deg);
}

CuttingConditions cutting_conditions(const CutArgs& o) {
  CuttingConditions c;
  o.fields.apply(c);
  if (!o.fields.given("radial_ratio") && std::isnan(o.kn))
    throw InvalidArgument("give the radial cutting coefficient: --kr K_n/K_t or --kn [N/m²]", "e.g. --kr 0.3");
  if (!std::isnan(o.kn)) {
    if (!(c.tangential_coefficient > 0.0))
      throw InvalidArgument("--kn needs --kt: the ratio K_r = K_n/K_t is what the model takes",
                            "e.g. --kt 6e8 (N/m², a typical steel value)");
    c.radial_ratio = o.kn / c.tangential_coefficient;
  }
  c.engagement = cut_engagement(o);
  return c;
}

std::vector<double> pitch_radians(const std::vector<double>& pitch_deg, int teeth) {
  if (teeth != 0 && teeth != static_cast<int>(pitch_deg.size()))
    throw InvalidArgument(fmt::format("--teeth {} but --pitch gives {} spacings", teeth, pitch_deg.size()),
                          "give one spacing per tooth, or drop --teeth");
  std::vector<double> rad;
  for (double p : pitch_deg) rad.push_back(radians_of(p));
  return rad;
}

std::vector<double> helix_radians(const std::vector<double>& helix_deg) {
  if (!helix_deg.empty() && std::all_of(helix_deg.begin(), helix_deg.end(), [](double b) { return b > 0.0 && b <= 1.5; }))
    throw InvalidArgument(fmt::format("--helix {}: helix angles are in degrees, and end mills have 10…60°; these look like "
                                      "radians",
                                      fmt::join(helix_deg, ",")),
                          fmt::format("give degrees, e.g. --helix {:g}", helix_deg.front() * 180.0 / kPi));
  std::vector<double> rad;
  for (double b : helix_deg) rad.push_back(radians_of(b));
  return rad;
}

void add_tool_geometry_options(CLI::App* c, ToolGeometryArgs& o, bool feed_and_diameter) {
  c->add_option("--pitch", o.pitch_deg,
                "fd: variable pitch, the angle from each tooth to the next [°, not rad], one per tooth, summing to 360 "
                "(e.g. 70,110,70,110; default: even)")
      ->delimiter(',');
  c->add_option("--helix", o.helix_deg,
                "fd: helix angle [°, not rad], 0…80: one for every tooth, or one per tooth (a variable helix, e.g. "
                "35,38,35,38); needs the tool diameter (default: straight flutes)")
      ->delimiter(',');
  c->add_option("--runout", o.runout_mm,
                "fd: radial runout per tooth [mm, not µm]: each tooth cuts at D/2 + its value (e.g. 0.01,0,-0.01,0; needs "
                "--feed; default none)")
      ->delimiter(',');
  const auto& fields = cutting_fields();
  if (feed_and_diameter) {
    o.fields.add(c, option_field(fields, "feed_per_tooth_m"), true);
    o.fields.add(c, option_field(fields, "diameter_m"), true);
  }
  o.fields.add(c, option_field(fields, "process_damping_n_per_m"));
}

void apply_tool_geometry(const ToolGeometryArgs& o, CuttingConditions& c) {
  if (!o.pitch_deg.empty()) c.pitch_rad = pitch_radians(o.pitch_deg, c.teeth);
  c.helix_rad = helix_radians(o.helix_deg);
  for (double r : o.runout_mm) c.runout_m.push_back(1e-3 * r);
  o.fields.apply(c);
}

void add_dynamics_options(CLI::App* c, DynamicsArgs& o, Globals& g, const std::string& prefix) {
  c->add_option("--assembly", o.assembly,
                "Assembly file (TOML, SI units): its tool point FRF (SHT11's H, Eq. 5) on its [analysis] grid, for x and y "
                "(instead of --frf)");
  c->add_option("--frf", o.frf, std::string("x direct tool point FRF G_xx: ") + kPointFrfHelp);
  add_frf_read_options(c, g);
  c->add_option("--frf-y", o.frf_y, "y direct FRF G_yy [m/N], any format as --frf (default: the x FRF, a symmetric tool)");
  auto* xy = c->add_option("--frf-xy", o.frf_xy, "Cross FRF G_xy [m/N], any format as --frf (with --frf-yx; default: none)");
  auto* yx = c->add_option("--frf-yx", o.frf_yx, "Cross FRF G_yx [m/N], any format as --frf (with --frf-xy; default: none)");
  xy->needs(yx);
  yx->needs(xy);
  c->add_flag("--rigid-y", o.rigid_y, "The tool is rigid in y: flexible in x only (the 1-DOF model)");
  c->add_option("--mode-x", o.mode_x,
                prefix + "an x mode MASS_KG,DAMPING_RATIO,FREQUENCY_HZ (repeatable; default: fitted from --frf)");
  c->add_option("--mode-y", o.mode_y,
                prefix + "a y mode MASS_KG,DAMPING_RATIO,FREQUENCY_HZ (repeatable; default: from --frf-y, else the x modes)");
  // (Their help says which methods use them: "Time domain, modes fitted: …".)
  const auto& lobes = lobes_study_fields();
  for (const char* name : {"max_modes", "fit_target"}) o.fit.add(c, option_field(lobes, name));
  c->add_option("--band", o.band, prefix + "fit modes only in F1:F2 [Hz] (default: the whole FRF)");
}

std::vector<RunPath> dynamics_paths(const DynamicsArgs& o) {
  std::vector<RunPath> inputs = joint_paths(o.joints);
  for (const auto& [p, role] : {std::pair{o.frf, "--frf"},
                                {o.frf_y, "--frf-y"},
                                {o.frf_xy, "--frf-xy"},
                                {o.frf_yx, "--frf-yx"},
                                {o.assembly, "--assembly"}})
    inputs.push_back({p, role});
  return inputs;
}

ModalFitOptions dynamics_fit_options(const DynamicsArgs& o) {
  LobesStudyOptions typed;
  o.fit.apply(typed);
  ModalFitOptions f;
  f.max_modes = typed.fit.max_modes;
  if (!o.band.empty()) f.band_hz = parse_range(o.band, "--band");
  return f;
}

double dynamics_fit_target(const DynamicsArgs& o) {
  LobesStudyOptions typed;
  o.fit.apply(typed);
  return typed.fit_target;
}

Mode parse_mode(const std::string& text, const std::string& option) {
  double v[3];
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = k < 2 ? text.find(',', start) : text.size();
    if (end == std::string::npos || (k == 2 && text.find(',', start) != std::string::npos))
      throw InvalidArgument(fmt::format("{} '{}' is not MASS_KG,DAMPING_RATIO,FREQUENCY_HZ", option, text),
                            "e.g. 0.04,0.011,922");
    const char* first = text.data() + start;
    const auto [ptr, ec] = std::from_chars(first, text.data() + end, v[k]);
    if (ec != std::errc() || ptr != text.data() + end || first == ptr)
      throw InvalidArgument(fmt::format("{} '{}': '{}' is not a number", option, text, text.substr(start, end - start)),
                            "write MASS_KG,DAMPING_RATIO,FREQUENCY_HZ, e.g. 0.04,0.011,922");
    start = end + 1;
  }
  Mode m{v[0], v[1], v[2]};
  m.check(option);
  check_plausible(plausible::kModalMass, m.mass_kg, fmt::format("{} {}: the modal mass [kg]", option, text),
                  "write MASS_KG,DAMPING_RATIO,FREQUENCY_HZ, e.g. 0.04,0.011,922");
  check_plausible(plausible::kNaturalFrequency, m.frequency_hz, fmt::format("{} {}: the natural frequency [Hz]", option, text),
                  "write MASS_KG,DAMPING_RATIO,FREQUENCY_HZ, e.g. 0.04,0.011,922");
  return m;
}

void fill_dynamics_input(const DynamicsArgs& o, const Globals& g, const std::vector<JointFile>& joints, LobesInput& input) {
  // The one place the tool point FRFs enter a command: FRF files, or an assembly file whose tool
  // point FRF (SHT11's H, seed Eq. 5) serves both directions (a round tool on a round spindle).
  if (!o.assembly.empty()) {
    if (!o.frf.empty() || !o.frf_y.empty() || !o.frf_xy.empty() || !o.frf_yx.empty())
      throw InvalidArgument("give either --assembly or --frf (with --frf-y, --frf-xy, --frf-yx), not both",
                            "drop --assembly to use measured FRFs, or drop the --frf options");
    input.assembly = load_assembly_on_grid(g, o.assembly, {}, joints).assembly;
    input.frf_name = "the tool point FRF of " + o.assembly;
    const std::vector<double> f = input.assembly->grid.values();
    info(g, fmt::format("tool point FRF from {} ({} frequencies, {:g}–{:g} Hz), {}", o.assembly, f.size(), f.front(), f.back(),
                        lobes_at_speed(*input.assembly, o.speed_model)
                            ? "in x and y at each spindle speed (lobes at speed, below)"
                            : "used for x and y"));
  } else {
    if (!joints.empty())
      throw InvalidArgument("--joint needs --assembly (the joint goes into the model)", "add --assembly FILE.toml");
    if (o.frf.empty()) {
      if (!o.frf_y.empty() || !o.frf_xy.empty() || !o.frf_yx.empty())
        throw InvalidArgument("--frf-y/--frf-xy/--frf-yx need --frf (the x direct FRF)", "add --frf tool_point_x.csv");
    } else {
      MillingFrfs f;
      f.xx = read_point_frf(g, o.frf);
      if (!o.frf_y.empty()) f.yy = read_point_frf(g, o.frf_y);
      if (!o.frf_xy.empty()) f.xy = read_point_frf(g, o.frf_xy);
      if (!o.frf_yx.empty()) f.yx = read_point_frf(g, o.frf_yx);
      f.rigid_y = o.rigid_y;
      f.check(o.frf, o.frf_y.empty() ? "--frf-y" : o.frf_y);
      input.frfs = std::move(f);
      input.frf_name = o.frf;
      input.frf_y_name = o.frf_y;
    }
  }
  if (o.rigid_y && !o.mode_y.empty()) throw InvalidArgument("--rigid-y and --mode-y contradict each other", "drop one of them");
  for (const auto& [texts, option, modes] :
       {std::tuple{&o.mode_x, "--mode-x", &input.x_modes}, {&o.mode_y, "--mode-y", &input.y_modes}})
    for (std::size_t i = 0; i < texts->size(); ++i) {
      modes->push_back(parse_mode((*texts)[i], option));
      // The same mode twice is twice as flexible: a repeated argument, most likely.
      for (std::size_t j = 0; j < i; ++j)
        if ((*modes)[j].mass_kg == modes->back().mass_kg && (*modes)[j].damping_ratio == modes->back().damping_ratio &&
            (*modes)[j].frequency_hz == modes->back().frequency_hz)
          warn(fmt::format("{} {} is given twice: both are used (a mode of half the mass); drop one if that is not meant", option,
                           (*texts)[i]));
    }
  input.rigid_y = o.rigid_y;
}

}  // namespace toolpoint::cli
