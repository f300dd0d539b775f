// The flags of the modal fit's option table and of the shared modal-fit flags (option_fields.hpp;
// issue 26) through the command line, against the expectations written by hand in
// support/expected_fields_stability.hpp: `toolpoint modes`' --max-modes and --min-prominence, and
// the --max-modes and --fit-target that lobes, pitch and simulate share (add_dynamics_options),
// each in its command's --help with its unit; a value just outside its range, in the CLI's unit,
// refused with exit code 2 naming the flag and the value typed (and the edges accepted); `toolpoint
// demo`'s --sigma and --width likewise.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/expected_fields_stability.hpp"
#include "support/scratch.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/stability/modal_fit.hpp"

using namespace toolpoint;
using namespace toolpoint::test;
using namespace toolpoint::testing;

namespace {

// Each flagged field of `fields` in `command --help` with its unit; `base` with a value just
// outside the field's range refused (exit 2) naming `flag value`.
template <class Options>
void expect_flags(const std::string& command, const std::string& base, const std::vector<ExpectedField<Options>>& fields) {
  std::string help;
  ASSERT_EQ(run_toolpoint(command + " --help", &help), 0) << help;
  for (const ExpectedField<Options>& e : fields) {
    if (e.flag.empty()) continue;
    SCOPED_TRACE(command + " " + e.flag);
    const std::string line = help_line(help, e.flag);
    EXPECT_NE(line.find("[" + e.cli_unit + "]"), std::string::npos) << line;
    for (const double bad : {outside(e), e.lo_open ? e.lo : beyond(e.lo, -1, e.integer)}) {
      std::string out;
      EXPECT_EQ(run_toolpoint(base + " " + e.flag + " " + cli_text(e, bad), &out), 2) << out;
      EXPECT_NE(out.find(e.flag + " " + cli_text(e, bad)), std::string::npos) << out;
    }
  }
}

}  // namespace

TEST(CliOptionFieldsStability, ModesFlags) {
  TempDir dir;
  std::vector<double> f;
  for (int i = 0; i <= 80; ++i) f.push_back(700.0 + 5.0 * i);
  write_frf_csv(dir / "point.csv", modal_frf({Mode{0.04, 0.011, 922.0}}, f));
  const std::string base = "modes " + dir / "point.csv";
  expect_flags("modes", base, modal_fit_expected_fields());
  std::string out;
  EXPECT_EQ(run_toolpoint(base + " --max-modes 1 --min-prominence 0.5", &out), 0) << out;
  EXPECT_EQ(run_toolpoint(base + " --max-modes 20", &out), 0) << out;
}

TEST(CliOptionFieldsStability, SharedFitFlagsOfPitchAndSimulate) {
  const auto fit = fitted_modes_expected_fields<PitchStudyOptions>("PitchStudyOptions");
  expect_flags("pitch",
               "pitch --mode-x 0.03993,0.011,922 --rigid-y --kt 6e8 --kr 0.3 --immersion 0.5 --milling down --teeth 4 "
               "--rpm 4130",
               fit);
  TempDir dir;
  expect_flags("simulate",
               "simulate --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 --immersion 0.5 "
               "--milling down --feed 0.1 --rpm 8000 --depth 1 --output " +
                   dir / "o.csv",
               fitted_modes_expected_fields<SimulationStudyOptions>("SimulationStudyOptions"));
  std::string lobes;
  ASSERT_EQ(run_toolpoint("lobes --help", &lobes), 0);
  // lobes: the same flags, their help saying which methods use them (LobesCommand.OptionFieldsAsFlags
  // refuses their values).
  EXPECT_NE(help_line(lobes, "--max-modes").find("Time domain"), std::string::npos) << help_line(lobes, "--max-modes");
  EXPECT_NE(help_line(lobes, "--fit-target").find("[%]"), std::string::npos) << help_line(lobes, "--fit-target");
}

// `toolpoint demo --sigma`, `--width` (case_study_fields): in its --help, refused at the flag.
TEST(CliOptionFieldsStability, DemoFlags) {
  TempDir dir;
  expect_flags("demo", "demo --no-plots --no-fit --output " + dir / "out", case_study_expected_fields());
}
