// toolpoint CLI: what every subcommand shares. Each subcommand lives in its own cmd_<name>.cpp
// and is thin: parse options, call the library, report. Only the CLI talks to a person.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace toolpoint::cli {

// Exit codes (README "Exit codes").
enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,   // a bug: an unexpected exception
  kExitUsage = 2,      // bad command line or option value
  kExitInput = 3,      // bad input file content
  kExitNumerical = 4,  // singular inversion, no convergence
  kExitIo = 5,         // cannot read or write a file
};

// Options every subcommand sees.
struct Globals {
  bool quiet = false;  // --quiet: no progress, no informational messages (warnings still shown)
};

// Messages on stderr. info() is silenced by --quiet; warn() never is.
void info(const Globals& g, const std::string& message);
void warn(const std::string& message);
void warn_all(const std::vector<std::string>& messages);

// The example assembly compiled into the binary (examples/bt40_shrinkfit_16mm.toml).
const char* example_assembly_toml();
const char* example_assembly_name();

// The subcommands. Each adds itself to `app` with its options, help (units, defaults, one
// example) and callback.
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
void add_modes_command(CLI::App& app, Globals& g);

}  // namespace toolpoint::cli
