// toolpoint: command-line entry point. Maps library exceptions to messages and exit codes:
// "error: what is wrong and where" on one line, "  fix: how to fix it" on the next.
// Units: SI with frequencies in Hz throughout the commands (each states its own).
#include <exception>
#include <fmt/format.h>
#include <iostream>

#include "cli.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/version.hpp"

namespace {

// `fallback` stands in for errors thrown without a hint, so every error has its fix line.
int report(const toolpoint::Error& e, int code, const std::string& fallback) {
  // The library names its own fields; here they are spelled as the options that set them.
  std::cerr << "error: " << toolpoint::cli::with_flags(e.what()) << '\n';
  std::cerr << "  fix: " << toolpoint::cli::with_flags(e.hint().empty() ? fallback : e.hint()) << '\n';
  return code;
}

// The subcommand named on the command line, for the usage hint ("" if none).
std::string subcommand_named(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    for (const CLI::App* c : app.get_subcommands({}))
      if (c->get_name() == argv[i]) return c->get_name();
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace toolpoint::cli;
  CLI::App app{
      "toolpoint: spindle–holder–tool dynamics for machine tools.\n"
      "Tool point FRFs by receptance coupling of Timoshenko beams, closed-form identification of\n"
      "joint stiffness and damping, measured-FRF handling and chatter stability lobes.\n"
      "Units: SI (m, kg, N, Pa, s, rad) in files and options; frequencies in Hz; where an option takes mm, rpm or "
      "degrees its help says so in brackets ([mm], [rpm], [°]).",
      "toolpoint"};
  app.set_version_flag("--version", std::string("toolpoint ") + TOOLPOINT_VERSION);
  Globals globals;
  app.add_flag("-q,--quiet", globals.quiet,
               "No progress or informational messages (warnings and errors still shown; default: off)");
  app.require_subcommand(1);
  app.fallthrough();  // --quiet may follow the subcommand
  app.footer(
      "Exit codes: 0 success, 1 internal error (a bug), 2 usage (bad option or value), 3 bad input\n"
      "file content, 4 numerical failure (e.g. singular inversion), 5 file I/O failure (including a\n"
      "--plot figure that gnuplot could not draw; the data files are written first), 6 a result that fails its\n"
      "own checks (identify's verdict; --accept overrides).\n"
      "Errors print one line saying what is wrong and where, and one (\"fix:\") saying how to fix it.\n"
      "Progress shows on stderr for long work: a bar on a terminal (after a second), otherwise a line every\n"
      "5 s (TOOLPOINT_PROGRESS_DELAY=SECONDS sets the first delay); nothing with --quiet.\n"
      "Run `toolpoint COMMAND --help` for a command's options, units, defaults and an example.\n"
      "Example:\n"
      "  toolpoint demo --output demo-out");

  add_beam_command(app, globals);
  add_predict_command(app, globals);
  add_identify_command(app, globals);
  add_demo_command(app, globals);
  add_couple_command(app, globals);
  add_taptest_command(app, globals);
  add_filter_command(app, globals);
  add_noise_command(app, globals);
  add_rotational_command(app, globals);
  add_convert_command(app, globals);
  add_lobes_command(app, globals);
  add_pitch_command(app, globals);
  add_modes_command(app, globals);
  add_resample_command(app, globals);
  add_plan_command(app, globals);
  add_simulate_command(app, globals);
  add_precision_command(app, globals);

  const std::string command = subcommand_named(app, argc, argv);
  const std::string help = command.empty() ? "toolpoint --help" : "toolpoint " + command + " --help";
  try {
    // Every file of the run is staged and written at the end, all or none (io.hpp OutputSet);
    // figures are committed separately by draw_figures (the data first, see cli.hpp).
    toolpoint::OutputSet outputs;
    app.parse(argc, argv);
    outputs.commit();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "error: " << e.what() << '\n';  // one form for every error, CLI11's too
    std::cerr << fmt::format("  fix: see `{}` for the options, their units and an example\n", help);
    return kExitUsage;
  } catch (const toolpoint::InvalidArgument& e) {
    return report(e, kExitUsage,
                  fmt::format("correct the value named above; `{}` gives each option's unit, range and default", help));
  } catch (const toolpoint::InputError& e) {
    return report(e, kExitInput, fmt::format("correct the file at the place named above; `{}` describes the formats read", help));
  } catch (const toolpoint::NumericalError& e) {
    return report(e, kExitNumerical, "check the input data (units, signs, frequency range) and the options named above");
  } catch (const toolpoint::VerdictFailure& e) {
    return report(e, kExitVerdict, "check the inputs; the command's --help says how to accept the result anyway");
  } catch (const toolpoint::IoError& e) {
    return report(e, kExitIo, "check the path and the folder's permissions");
  } catch (const toolpoint::Error& e) {
    return report(e, kExitInternal, "this is a bug in toolpoint; please report it with the command line");
  } catch (const std::exception& e) {
    std::cerr << "error: internal: " << e.what()
              << "\n  fix: this is a bug in toolpoint; please report it with the command line\n";
    return kExitInternal;
  }
  return kExitOk;
}
