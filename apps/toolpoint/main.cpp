// toolpoint: command-line entry point. Maps library exceptions to messages and exit codes.
#include <exception>
#include <fmt/format.h>
#include <iostream>

#include "cli.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint::cli {

void info(const Globals& g, const std::string& message) {
  if (!g.quiet) std::cerr << message << '\n';
}

void warn(const std::string& message) { std::cerr << "warning: " << message << '\n'; }

void warn_all(const std::vector<std::string>& messages) {
  for (const auto& m : messages) warn(m);
}

}  // namespace toolpoint::cli

namespace {

int report(const char* kind, const toolpoint::Error& e, int code) {
  std::cerr << "error: " << e.what() << '\n';
  if (!e.hint().empty()) std::cerr << "  fix: " << e.hint() << '\n';
  (void)kind;
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace toolpoint::cli;
  CLI::App app{
      "toolpoint: spindle–holder–tool dynamics for machine tools.\n"
      "Tool point FRFs by receptance coupling of Timoshenko beams, closed-form identification of\n"
      "joint stiffness and damping, measured-FRF handling and chatter stability lobes.\n"
      "Units: SI everywhere (m, kg, N, Pa, s, rad); frequencies in Hz.",
      "toolpoint"};
  app.set_version_flag("--version", std::string("toolpoint ") + TOOLPOINT_VERSION);
  Globals globals;
  app.add_flag("-q,--quiet", globals.quiet, "No progress bars or informational messages (warnings and errors still shown)");
  app.require_subcommand(1);
  app.fallthrough();  // --quiet may follow the subcommand
  app.footer(
      "Exit codes: 0 success, 1 internal error, 2 usage (bad option or value), 3 bad input file,\n"
      "4 numerical failure (e.g. singular inversion), 5 file I/O failure.\n"
      "Run `toolpoint COMMAND --help` for a command's options, units, defaults and an example.");

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
  add_modes_command(app, globals);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    std::cerr << "  fix: see `toolpoint --help` or `toolpoint COMMAND --help`\n";
    return kExitUsage;
  } catch (const toolpoint::InvalidArgument& e) {
    return report("usage", e, kExitUsage);
  } catch (const toolpoint::InputError& e) {
    return report("input", e, kExitInput);
  } catch (const toolpoint::NumericalError& e) {
    return report("numerical", e, kExitNumerical);
  } catch (const toolpoint::IoError& e) {
    return report("io", e, kExitIo);
  } catch (const toolpoint::Error& e) {
    return report("error", e, kExitInternal);
  } catch (const std::exception& e) {
    std::cerr << "error: internal: " << e.what() << "\n  fix: this is a bug in toolpoint; please report it with the command line\n";
    return kExitInternal;
  }
  return kExitOk;
}
