// toolpoint CLI: what every subcommand shares. Each subcommand lives in its own cmd_<name>.cpp
// and is thin: parse options, call the library, report. Only the CLI talks to a person.
//
// House rules every command follows (and states in its --help):
//   * Units: SI (m, kg, N, Pa, s, rad), frequencies in Hz; every option's help gives its unit and
//     default.
//   * Output files are written whole or not at all (write_text_file, plot::render), and a run's files
//     all or none (main's OutputSet); no output may be an input or another output (check_paths,
//     before any work); the format follows the extension or is refused (check_output_extension).
//   * Figures (--plot FILE.png|svg|pdf): the extension is checked before any work; the data
//     (files and the report on stdout) come first, the figure last. If the figure cannot be
//     drawn (gnuplot missing or failing) the data stay written, the error says which files they
//     are, and the exit code is 5 (I/O) — a script never mistakes a missing figure for success.
//   * Progress (progress.hpp) on stderr: a bar on a terminal, a line every few seconds otherwise; never with --quiet.
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "parse.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include <cstddef>
#include <deque>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/plausibility.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/shards.hpp"

namespace toolpoint::cli {

// Exit codes (`toolpoint --help` lists them).
enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,   // a bug: an unexpected exception
  kExitUsage = 2,      // bad command line or option value
  kExitInput = 3,      // bad input file content
  kExitNumerical = 4,  // singular inversion, no convergence
  kExitIo = 5,         // cannot read or write a file (or draw a requested figure)
  kExitVerdict = 6,    // a result judged wrong by its own checks (identify's verdict fail; --accept overrides)
};

// What the user says about the FRF files a command reads (add_frf_read_options): the same
// options, spelt the same, for every command that reads an FRF. As typed; frf_read_options()
// checks them.
struct FrfInputOptions {
  std::string ordinate;              // --ordinate receptance|mobility|accelerance
  std::string units;                 // --units m/N, mm/N, g/N, …
  std::string format;                // --format re-im|mag-phase-deg|mag-phase-rad|db-phase[-rad] (CSV)
  std::vector<std::string> columns;  // --columns F,A,B[,COH] (CSV)
};

// Options every subcommand sees.
struct Globals {
  bool quiet = false;   // --quiet: no progress, no informational messages (warnings still shown)
  FrfInputOptions frf;  // the FRF reading options of the command run (only one runs per call)
};

// Messages on stderr. info() is silenced by --quiet; warn() never is.
void info(const Globals& g, const std::string& message);
void warn(const std::string& message);
void warn_all(const std::vector<std::string>& messages);
// What loading an assembly file found: its warnings, and its notes (info, silenced by --quiet).
void report_loaded(const Globals& g, const LoadedAssembly& loaded);

// An assembly file loaded, its findings reported, and its grid replaced by `frequencies` when
// given (START:STOP:STEP [Hz], named --frequencies in errors): the input of a study.
LoadedAssembly load_assembly_on_grid(const Globals& g, const std::string& path, const std::string& frequencies = {},
                                     const std::vector<JointFile>& joints = {});

// The same, and its model built (warnings reported).
struct LoadedModel {
  LoadedAssembly loaded;
  AssemblyModel model;
};
LoadedModel load_model(const Globals& g, const std::string& path, const std::string& frequencies = {},
                       const std::vector<JointFile>& joints = {});

// ---- Option fields as flags (option_fields.hpp) ------------------------------------------------

// A CLI11 check by plausibility.hpp's rule (the files' rule): a value that cannot be meant in the
// option's unit is refused (exit 2, naming the option, the likely unit slip and the fix), an unusual
// one is a warning; 0 is left to the option's own rule.
CLI::Validator plausible_value(const PlausibleRange& range, const std::string& option);
// The same for a field's flag (field_plausibility on the value in SI: 0, the automatic value and a
// value out of range are the field's own rules), in the flag's unit (a diameter in mm judged as
// mm); an unusual value is warned about only where `warn_unusual` (else the library's result says it).
CLI::Validator field_plausible_value(const FieldSpec& spec, bool warn_unusual);

// A field's --help text: its help, its unit as the CLI takes it, its range in that unit and what
// its automatic value means, e.g. "Best speeds: … [%], [0, 100)".
std::string field_help(const FieldSpec& spec);
// InvalidArgument naming the flag, the value in the CLI's unit and the range in it.
[[noreturn]] void field_flag_refused(const FieldSpec& spec, double typed);

// The flags of option fields, derived from their table: add() registers a field's flag (its name,
// help and default, in the CLI's unit; a value its unit cannot mean refused where the flag takes
// the field's unit) where the command wants it in its --help; apply() sets the flags given into the library's
// options, converted to SI, range-checked (field_flag_refused).
template <class Options>
class FieldFlags {
 public:
  // `warn_unusual`: the flag warns about an unusual value itself (field_plausible_value), where no
  // library result judges the field.
  CLI::Option* add(CLI::App* c, const OptionField<Options>& f, bool warn_unusual = false) {
    const FieldSpec& s = f.spec;
    Slot& slot = slots_.emplace_back(Slot{&f, f.get(Options{}) * s.cli_per_unit});
    slot.integer = static_cast<int>(slot.real);
    slot.flag = slot.real != 0.0;
    const std::string help = field_help(s);
    if (s.kind == FieldKind::Flag) return slot.option = c->add_flag(field_flag(s), slot.flag, help);
    slot.option = s.kind == FieldKind::Integer ? c->add_option(field_flag(s), slot.integer, help)
                                               : c->add_option(field_flag(s), slot.real, help);
    // A default check() refuses (a speed of 0 rpm, to be given) is not shown as one.
    if (field_value_valid(s, f.get(Options{}))) slot.option->capture_default_str();
    // A value the flag's unit cannot mean is refused at the flag (check() would refuse it naming the
    // field, in its SI unit); an unusual one is the command's or the study's to warn about
    // (BeamStudy::warnings) unless `warn_unusual`. A value out of range is apply()'s to refuse.
    if (s.plausible) slot.option->check(field_plausible_value(s, warn_unusual));
    return slot.option;
  }
  // Whether the field's flag was given (on the command line).
  bool given(std::string_view name) const {
    for (const Slot& slot : slots_)
      if (name == slot.field->spec.name) return slot.option->count() > 0;
    return false;
  }
  // A fraction field's flag taking "2%" or "0.02" alike (parse_fraction); range-checked by apply().
  CLI::Option* add_fraction(CLI::App* c, const OptionField<Options>& f) {
    Slot& slot = slots_.emplace_back(Slot{&f, f.get(Options{})});
    const std::string flag = field_flag(f.spec);
    return slot.option = c->add_option_function<std::string>(
               flag, [&slot, flag](const std::string& v) { slot.real = parse_fraction(v, flag); },
               field_help(f.spec) + ", as 2% or 0.02");
  }
  void apply(Options& o) const {
    for (const Slot& slot : slots_) {
      if (slot.option->count() == 0) continue;
      const FieldSpec& s = slot.field->spec;
      const double typed = s.kind == FieldKind::Flag      ? (slot.flag ? 1.0 : 0.0)
                           : s.kind == FieldKind::Integer ? static_cast<double>(slot.integer)
                                                          : slot.real;
      const double value = typed / s.cli_per_unit;  // 1 mm = 1/1000 m: correctly rounded
      if (!field_value_valid(s, value)) field_flag_refused(s, typed);
      slot.field->set(o, value);
    }
  }

 private:
  struct Slot {
    const OptionField<Options>* field;
    double real = 0.0;
    int integer = 0;
    bool flag = false;
    CLI::Option* option = nullptr;
  };
  std::deque<Slot> slots_;  // a deque: CLI11 keeps the addresses of the values
};

// ---- Joint files -----------------------------------------------------------------------------

// Adds `--joint INTERFACE=FILE.toml` (repeatable; INTERFACE holder-tool or spindle-holder, or just
// FILE.toml): identified joints (`toolpoint identify --joint-output`) in place of the assembly
// file's.
CLI::Option* add_joint_option(CLI::App* command, std::vector<std::string>& target);
// Reads the joint files of --joint options (InvalidArgument when the interface named in the option
// is not the file's, or one interface is given twice) and says which joints are replaced (info).
std::vector<JointFile> read_joint_options(const Globals& g, const std::vector<std::string>& specs);
// The files named by --joint options, for check_paths.
std::vector<RunPath> joint_paths(const std::vector<std::string>& specs);
// The loaded assembly with the files' joints in place (its notes then describe those joints).
LoadedAssembly with_joints(LoadedAssembly loaded, const std::vector<JointFile>& files);

// Monte Carlo over a joint's uncertainty (--samples N, --seed, --threads), for the commands that
// carry it forward. Adds the options; `sampled` picks the one --joint file with an [uncertainty]
// (InvalidArgument when none or several have one).
struct SamplingOptions {
  int samples = 0;  // 0: none; else UncertaintyOptions::samples (checked by uncertainty_options)
  std::uint64_t seed = 1;
  FieldFlags<ParallelOptions> parallel;  // --threads (parallel_fields), where the command has no other
};
// `threads_option` false: the command has its own --threads (SamplingOptions::parallel unused).
void add_sampling_options(CLI::App* command, SamplingOptions& target, const std::string& what, bool threads_option = true);
const JointFile& sampled_joint(const std::vector<JointFile>& files);
// The Monte Carlo's options from the flags (InvalidArgument naming --samples out of its range).
UncertaintyOptions uncertainty_options(const SamplingOptions& s);
// Adds --threads (parallel_fields()' threads) to `flags`: every command that runs on threads says
// it the same way.
CLI::Option* add_threads_option(CLI::App* command, FieldFlags<ParallelOptions>& flags);

// The example assembly compiled into the binary (examples/bt40_shrinkfit_16mm.toml).
const char* example_assembly_toml();
const char* example_assembly_name();

// ---- Figures ------------------------------------------------------------------------------------

// The paragraph every command with --plot puts in its --help footer.
extern const char* const kFigureFooter;

// Adds `--plot FILE` whose help says what is drawn (`what`, with units) and how.
CLI::Option* add_plot_option(CLI::App* command, std::string& target, const std::string& what);

// Before any work: an empty path passes; otherwise the extension must be .png, .svg or .pdf
// (InvalidArgument naming the option and the path).
void check_plot_path(const std::string& path, const std::string& option = "--plot");

// A figure and where it goes.
struct FigureFile {
  plot::Figure figure;
  std::string path;
};

// Renders the figures in order, saying where each went (info). `written` names the data files
// the command already wrote. When a figure cannot be drawn, throws IoError (PlotUnavailable if
// gnuplot cannot be run) naming that figure, the figures drawn before it and the data written.
// `skip` says how to do without the figures in the fix line.
void draw_figures(const Globals& g, const std::vector<FigureFile>& figures, const std::vector<std::string>& written,
                  const std::string& skip = "drop --plot");

// `path` with `suffix` before its extension: ("lobes.png", "_chatter") → "lobes_chatter.png".
std::string with_suffix(const std::string& path, const std::string& suffix);

// ---- Output paths ---------------------------------------------------------------------------

// Before any work: no output is one of the inputs and no two outputs are the same file
// (check_output_paths in io.hpp; an input's "#N" dataset suffix is dropped, empty paths skipped).
// Every command calls it with all it reads and writes, figures included.
void check_paths(const std::vector<RunPath>& inputs, const std::vector<RunPath>& outputs);

// Before any work: `path` (given as `option`) must end in one of `extensions` (".csv", …; case
// insensitive), else InvalidArgument naming the option, the path and `formats` (what the command
// can write there). An empty path passes.
void check_output_extension(const std::string& path, const std::string& option, std::initializer_list<const char*> extensions,
                            const std::string& formats);
// `formats` for a command that writes a 2×2 block.
extern const char* const kBlockCsvOutput;

// ---- FRF inputs -----------------------------------------------------------------------------

// Help text for an input that takes one FRF file of any supported format: a single FRF only
// (kSingleFrfHelp), or also a 2×2 block CSV whose H entry is used (kPointFrfHelp).
extern const char* const kSingleFrfHelp;
extern const char* const kPointFrfHelp;
// Help text for a block input (SH11, SHT11, S11): FRF CSV only.
extern const char* const kBlockCsvHelp;

// Adds --ordinate, --units, --format and --columns to a command that reads FRF files, bound to
// g.frf, which read_frf_input/read_point_frf/read_block_input then apply to every FRF it reads.
void add_frf_read_options(CLI::App* command, Globals& g);

// The library's reading options from what was typed (InvalidArgument naming the flag).
FrfReadOptions frf_read_options(const FrfInputOptions& typed);

// `text` with the library's option fields (FrfCsvOptions::format, …) replaced by the flags that
// set them (--format, …): library messages name library fields, the CLI its flags.
std::string with_flags(std::string text);

// The same rule for a value parsed by the command itself (a sweep, a list, a mode): throws
// InvalidArgument naming `what` when it cannot be meant, with `fix`; warns when unusual.
void check_plausible(const PlausibleRange& range, double value, const std::string& what, const std::string& fix);
// Options in the CLI's own units (mm, rpm): their plausible ranges.
inline constexpr PlausibleRange kDepthMm{0.1, 300.0, 10.0, "this depth is in mm (5 mm = 5, not 0.005)"};

// read_frf_file, its errors naming the command's flags where the library names its fields.
FrfFileData read_frf_file_for_cli(const std::string& path, const FrfReadOptions& options);

// Adds the INPUT and OUTPUT arguments, --dataset and the FRF reading options of a command that
// transforms an FRF file into another of the same form (filter, noise); `block_note` says what
// happens to a block, e.g. "every entry filtered".
void add_frf_file_arguments(CLI::App* command, Globals& g, std::string& input, std::string& output,
                            std::optional<std::size_t>& dataset, const std::string& block_note);

// Adds `--dataset N` (UFF inputs: which dataset 58, numbered as `toolpoint convert FILE --list`).
CLI::Option* add_dataset_option(CLI::App* command, std::optional<std::size_t>& target);

// Reads one measured FRF for a command: FRF CSV (single FRF or 2×2 block), UFF 58/58b or CutPro
// .frf, by extension, as receptance [m/N] against frequency [Hz] (ordinates and units converted;
// see frf_file.hpp), with the command's FRF reading options (g.frf). `spec` is a path, optionally
// ending in "#N" to pick dataset N of a UFF file (when no file of that exact name exists);
// `dataset` (a --dataset option) does the same. The file's warnings are shown. Throws
// InvalidArgument (unknown extension, a selection on a non-UFF file, both #N and --dataset, bad
// reading options), InputError, IoError.
FrfFileData read_frf_input(const Globals& g, const std::string& spec, std::optional<std::size_t> dataset = std::nullopt);

// A 2×2 block file (SH11, SHT11, S11: FRF CSV in any dialect) for a command, with its warnings
// shown. InputError if it holds a single FRF.
FrfFileData read_block_input(const Globals& g, const std::string& path);  // a block (its coherence too)

// The same, reduced to one point FRF: a 2×2 block CSV gives its H entry (w/f), said by info().
FrfSeries read_point_frf(const Globals& g, const std::string& spec, std::optional<std::size_t> dataset = std::nullopt);

// The H entry (w/f) of a block, or the single FRF.
FrfSeries point_frf(const FrfFileData& data);

// The format an output FRF file gets from its extension (InvalidArgument naming the path, with
// a hint, for anything else). Call before any work.
FrfFormat output_frf_format(const std::string& path);

// A 2×2 block can only be written as FRF CSV: InvalidArgument naming `path` otherwise.
void check_frf_output(const std::string& path, FrfFormat format, bool is_block);

// Writes `data` (single FRF or block) to `path` in `format` (check_frf_output first): UFF keeps
// the input's DOF labels and takes `comment` as ID line 1; CSV takes it as a comment line and
// keeps a coherence column. Warnings of the writer are shown.
void write_frf_output(const std::string& path, FrfFormat format, const FrfFileData& data, const std::string& comment);

// What filter and noise share: check the figure and output names (before any work), read
// `input` (any format; `dataset` as for read_frf_input), apply `process` — a generic callable
// taking a FrfSeries or a BlockSeries and returning a SignalResult — to its single FRF or block,
// show the result's warnings, and write it to `output` in the input's form (write_frf_output).
// Returns what was read and what was written.
template <class Process>
std::pair<FrfFileData, FrfFileData> process_frf_file(const Globals& g, const std::string& input,
                                                     std::optional<std::size_t> dataset, const std::string& output,
                                                     const std::string& plot_path, const std::string& comment,
                                                     Process&& process) {
  check_plot_path(plot_path);
  const FrfFormat format = output_frf_format(output);
  check_paths({{input, "input"}}, {{output, "output"}, {plot_path, "--plot"}});
  FrfFileData in = read_frf_input(g, input, dataset);
  if (!in.coherence.empty())
    warn(fmt::format("{}: its coherence column is not carried into {}: the values changed", input, output));
  check_frf_output(output, format, in.is_block);
  FrfFileData out;
  out.format = format;
  out.is_block = in.is_block;
  out.dof = in.dof;
  out.description = comment;
  const auto apply = [&](const auto& series) {
    auto r = process(series);
    warn_all(r.warnings);
    if constexpr (requires { r.coherence; }) out.coherence = std::move(r.coherence);  // a measurement made here
    return std::move(r.series);
  };
  if (in.is_block) out.block = apply(in.block);
  else out.single = apply(in.single);
  write_frf_output(output, format, out, comment);
  return {std::move(in), std::move(out)};
}

// Draws `traces` (FRF figure: |H| and phase, overlaid) in `plot_path` after the data file
// `written` (draw_figures).
void draw_frf_overlay(const Globals& g, const std::vector<plot::FrfTrace>& traces, const plot::FrfFigureOptions& options,
                      const std::string& plot_path, const std::string& written);

// ---- Milling: the cut and the tool point dynamics (lobes, simulate) ---------------------------

// The cut as typed: --teeth, --kt, --kr (cutting_fields) | --kn, --immersion with --milling |
// --entry/--exit. NaN: not given (so a negative value reaches the library's check and its message).
struct CutArgs {
  FieldFlags<CuttingConditions> fields;  // teeth, tangential_coefficient, radial_ratio
  double kn = std::numeric_limits<double>::quiet_NaN();
  double immersion = std::numeric_limits<double>::quiet_NaN(), entry_deg = std::numeric_limits<double>::quiet_NaN(),
         exit_deg = std::numeric_limits<double>::quiet_NaN();
  std::string milling;
};
// Adds the options; `teeth_note` says how the teeth are given (lobes: "straight flutes; evenly
// spaced unless --pitch"); whether --teeth and --kt are required (else the command checks them itself).
void add_cut_options(CLI::App* command, CutArgs& target, const std::string& teeth_note, bool teeth_required = true,
                     bool kt_required = true);
// The library's cutting conditions (InvalidArgument naming the flag: no radial coefficient, no
// engagement, --immersion without --milling); angles both within π refused as radians.
CuttingConditions cutting_conditions(const CutArgs& typed);
// --immersion/--milling or --entry/--exit alone (what cutting_conditions checks for the engagement).
Engagement cut_engagement(const CutArgs& typed);

// The tool beyond evenly spaced straight teeth, for the stability: --pitch, --runout, --helix as
// typed (degrees, mm), and --feed, --diameter, --process-damping from cutting_fields.
struct ToolGeometryArgs {
  std::vector<double> pitch_deg, runout_mm, helix_deg;
  FieldFlags<CuttingConditions> fields;  // feed_per_tooth_m, diameter_m, process_damping_n_per_m
};
// Adds --pitch [°], --helix [°], --runout [mm], --process-damping [N/m] and, unless the command
// has its own (`feed_and_diameter` false: plan's study file), --feed [mm] and --diameter [mm].
void add_tool_geometry_options(CLI::App* command, ToolGeometryArgs& target, bool feed_and_diameter = true);
// Into the cutting conditions, the flags given only (the library checks them: CuttingConditions::
// check, fields mapped to flags).
void apply_tool_geometry(const ToolGeometryArgs& typed, CuttingConditions& cutting);
// --pitch [°] in radians, one per tooth (`teeth` 0: not given; else the count must match).
std::vector<double> pitch_radians(const std::vector<double>& pitch_deg, int teeth);
// --helix [°] in radians: one angle, or one per tooth (a variable helix). An angle whose degrees
// read as radians (all within 0 < β ≤ 1.5, i.e. 86°) is refused: no end mill has a helix under 1.5°.
std::vector<double> helix_radians(const std::vector<double>& helix_deg);

// Where the tool point dynamics come from, as typed: FRF files or an assembly, modes, the fit.
struct DynamicsArgs {
  std::string frf, frf_y, frf_xy, frf_yx, assembly;
  bool rigid_y = false;
  std::vector<std::string> mode_x, mode_y;
  // --max-modes, --fit-target: from their definitions (lobes_study_fields, its max_modes
  // ModalFitOptions' own), the same for lobes, pitch and simulate.
  FieldFlags<LobesStudyOptions> fit;
  std::string band;
  std::vector<std::string> joints;
  // Set by the command: the lobes at speed (said when the assembly is read).
  SpeedModel speed_model = SpeedModel::Standstill;
};
// Adds --assembly, --frf (and its reading options), --frf-y, --frf-xy, --frf-yx, --rigid-y, --mode-x,
// --mode-y, --max-modes, --fit-target, --band; `prefix` starts the help of the options that only
// some methods use ("fd: "; --max-modes and --fit-target say it in their table's help).
void add_dynamics_options(CLI::App* command, DynamicsArgs& target, Globals& g, const std::string& prefix);
// The inputs and outputs they name, for check_paths (joints included).
std::vector<RunPath> dynamics_paths(const DynamicsArgs& typed);
// The library's input: input.frfs or input.assembly from the files (neither when no FRF is given),
// the modes parsed (a mode given twice warned about), rigid_y. Throws InvalidArgument naming the flags.
void fill_dynamics_input(const DynamicsArgs& typed, const Globals& g, const std::vector<JointFile>& joints, LobesInput& input);
// The modal fit's options from --max-modes, --band (--fit-target separately, as a fraction:
// dynamics_fit_target); a flag out of its range refused naming it.
ModalFitOptions dynamics_fit_options(const DynamicsArgs& typed);
double dynamics_fit_target(const DynamicsArgs& typed);

// "MASS,ZETA,FN" → Mode, naming `option` in errors; plausible mass and frequency checked.
Mode parse_mode(const std::string& text, const std::string& option);

// ---- Sharded studies (plan, simulate map; shard_cli.cpp) -------------------------------------

// --shard I/N and --part FILE of a sharded command: the shard (0 of 1 without --shard). `what`
// names the result ("plan"), `merge` its merge command ("toolpoint plan merge"). Throws
// InvalidArgument for --shard without --part, --part without --shard, and --shard with an output
// of the whole result (`whole_outputs`: --output, --plot or --json given).
ShardId shard_options(const std::string& shard, const std::string& part, bool whole_outputs, const std::string& what,
                      const std::string& merge);

// How a sharded command computes a shard again, for the commands a merge prints.
struct ShardCommand {
  std::string command;  // what comes before " --shard I/N --part FILE", e.g. "toolpoint plan study.toml"
  // The Slurm array's re-run of the shards `list` ("2,5-7") of a split into `count`, their parts in `dir`.
  std::function<std::string(const std::string& list, const std::string& dir, int count)> array;
};

// The commands that mend a set of parts (ShardSetError::check()): the parts to leave out, each
// shard to run again (in a loop when there are many and the parts are named DIR/part-I.json, as
// the scripts in scripts/slurm/ name them; then the Slurm array's re-run too), "then merge again".
std::string mending_commands(const ShardSetCheck& check, const ShardCommand& rerun);

// The options given to `commands` (each one's results, as --name=value, shell-quoted where needed),
// those named in `leave_out` left out: the words that run the same study again.
std::string given_options(const std::vector<const CLI::App*>& commands, std::initializer_list<const char*> leave_out);

// ---- Subcommands ----------------------------------------------------------------------------
// Each adds itself to `app` with its options, help (units, defaults, one example) and callback.
void add_beam_command(CLI::App& app, Globals& g);
void add_predict_command(CLI::App& app, Globals& g);
void add_identify_command(CLI::App& app, Globals& g);
void add_demo_command(CLI::App& app, Globals& g);
void add_couple_command(CLI::App& app, Globals& g);
void add_taptest_command(CLI::App& app, Globals& g);
void add_filter_command(CLI::App& app, Globals& g);
void add_noise_command(CLI::App& app, Globals& g);
void add_rotational_command(CLI::App& app, Globals& g);
void add_convert_command(CLI::App& app, Globals& g);
void add_lobes_command(CLI::App& app, Globals& g);
void add_pitch_command(CLI::App& app, Globals& g);
void add_modes_command(CLI::App& app, Globals& g);
void add_resample_command(CLI::App& app, Globals& g);
void add_plan_command(CLI::App& app, Globals& g);
void add_simulate_command(CLI::App& app, Globals& g);
void add_precision_command(CLI::App& app, Globals& g);

}  // namespace toolpoint::cli
