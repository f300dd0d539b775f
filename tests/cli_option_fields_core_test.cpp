// The flags of ParallelOptions (--threads of every command that runs on threads), UncertaintyOptions
// (--samples), BeamStudyOptions and ModalOptions (`toolpoint beam`) and PredictOptions (`toolpoint
// predict --speed`, `--extrapolate-bearings`), registered from their option tables (option_fields.hpp;
// issue 26), through the command line: each flag is in its command's --help with its unit; a value
// just outside the old range exits non-zero naming the flag, not the library field; a value the
// flag's unit cannot mean (a length in mm, a spin in rad/s) is refused at the flag; the edges pass.
// Flags, units and ranges written out here by hand, not read from the tables. The library's
// check(): option_fields_core_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_help.hpp"
#include "support/scratch.hpp"

using namespace toolpoint::test;

namespace {

const std::string kExample = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml";

// `args` exits non-zero, its message holding `named` and no `Options::` of a library field.
void expect_refused(const std::string& args, const std::string& named) {
  std::string out;
  EXPECT_NE(run_toolpoint(args, &out), 0) << args << ": " << out;
  EXPECT_NE(out.find(named), std::string::npos) << args << ": " << out;
  EXPECT_EQ(out.find("Options::"), std::string::npos) << args << ": " << out;  // the flag, not the field
}

}  // namespace

// Every command that runs on threads takes --threads 0…1024 from the one table.
TEST(CliOptionFieldsCore, ThreadsFlagEverywhere) {
  for (const char* command : {"lobes", "pitch", "plan", "simulate map", "identify", "demo", "predict", "couple"})
    expect_flags_in_help(command, {{"--threads", "-"}});
  const std::string base =
      "lobes --assembly " + kExample + " --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.5 --milling down --rpm 5000:6000 --speeds 3";
  expect_refused(base + " --threads 1025", "--threads");
  expect_refused(base + " --threads -1", "--threads");
  std::string out;
  EXPECT_EQ(run_toolpoint(base + " --threads 1024", &out), 0) << out;
}

// --samples: 0 none, else 10…1000000 (UncertaintyOptions::samples), refused naming the flag.
TEST(CliOptionFieldsCore, SamplesFlag) {
  expect_flags_in_help("predict", {{"--samples", "-"}});
  expect_refused("predict " + kExample + " --samples 9", "--samples");
  expect_refused("predict " + kExample + " --samples 1000001", "--samples");
}

// toolpoint beam: --length, --diameter, --inner-diameter [m], --modes, --speed [rpm], --modal-terms,
// --static-residual from their tables; old ranges: L, D > 0, d ≥ 0, modes ≥ 0 (CLI11's PositiveNumber
// before), speed ≥ 0, modal terms 1…20000.
TEST(CliOptionFieldsCore, BeamFlags) {
  expect_flags_in_help("beam", {{"--length", "m"},
                                {"--diameter", "m"},
                                {"--inner-diameter", "m"},
                                {"--modes", "-"},
                                {"--speed", "rpm"},
                                {"--modal-terms", "-"},
                                {"--static-residual", ""}});
  const std::string base = "beam --length 0.1 --diameter 0.02";
  expect_refused("beam --length 0 --diameter 0.02", "--length");
  expect_refused("beam --length 0.1 --diameter -0.02", "--diameter");
  expect_refused(base + " --inner-diameter -0.01", "--inner-diameter");
  expect_refused(base + " --modes -1", "--modes");
  expect_refused(base + " --modes 20001", "--modes");
  expect_refused(base + " --speed -1", "--speed");
  expect_refused(base + " --method modal --modal-terms 0", "--modal-terms");
  expect_refused(base + " --method modal --modal-terms 20001", "--modal-terms");
  // A unit slip cannot pass: 100 "m" long, a spin of 20 "rpm".
  expect_refused("beam --length 100 --diameter 0.02", "--length");
  expect_refused(base + " --speed 20", "--speed");
  std::string out;
  EXPECT_EQ(run_toolpoint(base + " --modes 3 --inner-diameter 0.01 --speed 30000", &out), 0) << out;
  EXPECT_NE(out.find("forward_hz"), std::string::npos) << out;
  TempDir dir;
  EXPECT_EQ(run_toolpoint(base + " --frequencies 100:1000:100 --output " + std::string(dir / "t.csv") +
                              " --method modal --modal-terms 200 --static-residual",
                          &out),
            0)
      << out;
}

// Found by a newcomer's run: a nested or cross-field refusal names the flags; a flag the chosen
// method does not use is said, not ignored in silence.
TEST(CliOptionFieldsCore, NewcomerFindings) {
  TempDir dir;
  std::string out;
  ASSERT_EQ(run_toolpoint("predict " + kExample + " --at holder --output " + std::string(dir / "sh.csv"), &out), 0) << out;
  expect_refused("couple --sh " + std::string(dir / "sh.csv") + " --assembly " + kExample + " --prominence 5 --output " +
                     std::string(dir / "c.csv"),
                 "--prominence 5 must lie in [0, 1)");
  expect_refused("beam --length 0.1 --diameter 0.05 --inner-diameter 0.06", "--inner-diameter 0.06 m must be below --diameter");
  EXPECT_EQ(run_toolpoint("beam --length 0.1 --diameter 0.02 --modal-terms 50", &out), 0) << out;
  EXPECT_NE(out.find("warning: --modal-terms and --static-residual are used by --method modal only"), std::string::npos)
      << out;
  EXPECT_EQ(run_toolpoint("lobes --assembly " + kExample + " --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.5 --milling down "
                              "--rpm 5000:6000 --speeds 3 --tolerance 5",
                          &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: --tolerance and --intervals are used by the time-domain methods only"), std::string::npos)
      << out;
}

// The cut's flags from cutting_fields and --speeds from speed_range_fields: lobes, pitch and
// simulate take --teeth, --kt [N/m²], --kr; lobes and pitch --feed and --diameter [mm] and
// --process-damping [N/m]; lobes --speeds. Old ranges: teeth 1…1000, K_t > 0, K_r ≥ 0, C_i 1e3…1e8
// (0: none), points 2…1000000; the feed's top 10 mm (PlanOptions'). A unit slip (K_t in MPa, a
// diameter in metres on the mm flag, speeds in thousands of rpm) refused naming the flag and the unit.
TEST(CliOptionFieldsCore, CutFlags) {
  expect_flags_in_help("lobes", {{"--teeth", "-"},
                                 {"--kt", "N/m²"},
                                 {"--kr", "-"},
                                 {"--feed", "mm"},
                                 {"--diameter", "mm"},
                                 {"--process-damping", "N/m"},
                                 {"--speeds", "-"}});
  expect_flags_in_help("pitch", {{"--teeth", "-"}, {"--kt", "N/m²"}, {"--kr", "-"}, {"--diameter", "mm"}});
  expect_flags_in_help("simulate", {{"--teeth", "-"}, {"--kt", "N/m²"}, {"--kr", "-"}});
  const std::string dyn = "lobes --assembly " + kExample + " --immersion 0.5 --milling down ";
  const std::string base = dyn + "--teeth 2 --kt 6e8 --kr 0.3 --rpm 5000:6000 ";
  expect_refused(dyn + "--teeth 0 --kt 6e8 --kr 0.3 --rpm 5000:6000", "--teeth 0 must lie in 1…1000");
  expect_refused(dyn + "--teeth 1001 --kt 6e8 --kr 0.3 --rpm 5000:6000", "--teeth 1001");
  expect_refused(dyn + "--teeth 2 --kt -1 --kr 0.3 --rpm 5000:6000", "--kt -1 N/m² must be > 0");
  expect_refused(dyn + "--teeth 2 --kt 600 --kr 0.3 --rpm 5000:6000", "--kt");
  expect_refused(dyn + "--teeth 2 --kt 6e8 --kr -0.1 --rpm 5000:6000", "--kr -0.1 must be ≥ 0");
  expect_refused(base + "--method fd --diameter 0.016", "--diameter takes mm");
  expect_refused(base + "--method fd --feed 20", "--feed 20 mm must lie in 0…10");
  // Out of range and no feed in metres either: the slip in the flag's unit, not the field's SI hint.
  expect_refused(base + "--method fd --feed 200", "--feed 200 mm must lie in 0…10 (0: not given); --feed takes mm");
  expect_refused(base + "--method fd --diameter 16 --process-damping 10", "--process-damping 10 N/m must lie in 1000…1e+08");
  expect_refused(base + "--speeds 1", "--speeds 1 must lie in 2…1000000");
  expect_refused(dyn + "--teeth 2 --kt 6e8 --kr 0.3 --rpm 0.5:20", "--rpm");
  // An unusual K_t passes with a warning naming the flag; a good cut runs.
  std::string out;
  EXPECT_EQ(run_toolpoint(dyn + "--teeth 2 --kt 2e7 --kr 0.3 --rpm 5000:6000 --speeds 3", &out), 0) << out;
  EXPECT_NE(out.find("warning: --kt = 2e+07 is outside the usual range"), std::string::npos) << out;
  EXPECT_EQ(run_toolpoint(base + "--speeds 3", &out), 0) << out;
  EXPECT_NE(out.find("best spindle speeds in 5000–6000 rpm"), std::string::npos) << out;
}

// A second newcomer's run: predict --speeds below 0 (or without --plot) refused before any file is
// written, naming the flag; --extrapolate-bearings on bearings without a speed table said, not
// ignored; a reversed couple --overhang sweep said in metres, not as a frequency grid; --rpm in
// thousands (15:200) warned about; couple --prominence's help gives its range.
TEST(CliOptionFieldsCore, SecondNewcomerFindings) {
  TempDir dir;
  const std::string csv = std::string(dir / "p.csv");
  expect_refused("predict " + kExample + " --speeds -5 --output " + csv + " --plot " + std::string(dir / "p.png"),
                 "--speeds -5 rpm: spindle speeds must be ≥ 0");
  EXPECT_FALSE(std::filesystem::exists(csv));
  expect_refused("predict " + kExample + " --speeds 0,10000 --output " + csv, "--speeds draws");
  EXPECT_FALSE(std::filesystem::exists(csv));
  std::string out;
  EXPECT_EQ(run_toolpoint("predict " + kExample + " --extrapolate-bearings", &out), 0) << out;
  EXPECT_NE(out.find("warning: --extrapolate-bearings changes nothing: no bearing of the assembly has a speed table"),
            std::string::npos)
      << out;
  ASSERT_EQ(run_toolpoint("predict " + kExample + " --at holder --output " + std::string(dir / "sh.csv"), &out), 0) << out;
  const std::string couple = "couple --sh " + std::string(dir / "sh.csv") + " --assembly " + kExample;
  expect_refused(couple + " --overhang 0.06:0.04:0.002 --output " + std::string(dir / "sweep"),
                 "--overhang 0.06:0.04:0.002: a sweep START:STOP:STEP [m] needs 0 < START < STOP");
  expect_flags_in_help("couple", {{"--prominence", "-"}});
  ASSERT_EQ(run_toolpoint("couple --help", &out), 0);
  EXPECT_NE(flag_help_line(out, "--prominence").find("[0, 1)"), std::string::npos) << out;
  EXPECT_EQ(run_toolpoint("lobes --assembly " + kExample + " --teeth 2 --kt 6e8 --kr 0.3 --immersion 0.5 --milling down "
                              "--rpm 15:200 --speeds 3",
                          &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: --rpm = 15 is outside the usual range [100, 200000]"), std::string::npos) << out;
}

// identify's noise flags from noise_spec_fields: --sigma, --floor [-], --phase-sigma [degrees],
// --calibration (2% or 0.02), --averages; old ranges σ, floor 0…0.5, phase 0…28.6° (0.5 rad),
// calibration 0…10 %, averages 0…100000, each refused naming the flag before any file is read.
TEST(CliOptionFieldsCore, IdentifyNoiseFlags) {
  expect_flags_in_help("identify", {{"--sigma", "-"},
                                    {"--phase-sigma", "degrees"},
                                    {"--floor", "-"},
                                    {"--calibration", "-"},
                                    {"--averages", "-"}});
  const std::string base = "identify --assembly " + kExample + " --sh nope_sh.csv --sht nope_sht.csv";
  expect_refused(base + " --phase-sigma 30", "--phase-sigma 30 degrees must lie in 0…28.6479");
  expect_refused(base + " --sigma 0.6", "--sigma 0.6 must lie in 0…0.5");
  expect_refused(base + " --floor -0.01", "--floor -0.01 must lie in 0…0.5");
  expect_refused(base + " --calibration 11%", "--calibration 0.11 must lie in 0…0.1");
  expect_refused(base + " --averages 100001", "--averages 100001 must lie in 0…100000");
}

// simulate's force law from force_law_fields: --kte, --kre [N/m] ≥ 0, --exponent in (0, 1],
// --reference-chip [mm] > 0, --process-damping 1e3…1e8 N/m (0: none), refused naming the flag.
TEST(CliOptionFieldsCore, SimulateForceLawFlags) {
  expect_flags_in_help("simulate", {{"--kte", "N/m"},
                                    {"--kre", "N/m"},
                                    {"--exponent", "-"},
                                    {"--reference-chip", "mm"},
                                    {"--process-damping", "N/m"}});
  const std::string base = "simulate --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 "
                           "--immersion 0.5 --milling down --feed 0.1 --rpm 10000 --depth 1 --revolutions 4";
  expect_refused(base + " --kte -1", "--kte -1 N/m must be ≥ 0");
  expect_refused(base + " --kre -1", "--kre -1 N/m must be ≥ 0");
  expect_refused(base + " --exponent 1.2", "--exponent 1.2 must lie in (0, 1]");
  expect_refused(base + " --exponent 0", "--exponent 0 must lie in (0, 1]");
  expect_refused(base + " --reference-chip 0", "--reference-chip 0 mm must be > 0");
  expect_refused(base + " --reference-chip 50", "--reference-chip");  // 50 mm: metres' slip the other way
  expect_refused(base + " --process-damping 10", "--process-damping 10 N/m must lie in 1000…1e+08");
  std::string out;
  EXPECT_EQ(run_toolpoint(base + " --kte 2e4 --kre 1e4 --exponent 0.8 --reference-chip 0.05", &out), 0) << out;
  // The cutter and the cut (cutter_fields, milling_cut_fields) and the map's grid (depth_range_fields).
  expect_flags_in_help("simulate", {{"--diameter", "mm"}, {"--flute-length", "mm"}, {"--feed", "mm"}});
  expect_flags_in_help("simulate map", {{"--speeds", "-"}, {"--depths", "-"}});
  const std::string cut = "simulate --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.5 "
                          "--milling down --rpm 10000 --depth 1 --revolutions 4";
  expect_refused(cut + " --feed 0.1 --diameter 0.016", "--diameter takes mm");
  expect_refused(cut + " --feed 0.1 --diameter 0", "--diameter 0 mm must be > 0");
  expect_refused(base + " --flute-length -1", "--flute-length -1 mm must be ≥ 0");
  expect_refused(cut + " --diameter 20 --feed 20", "--feed 20 mm must lie in 0…10");
  const std::string map = "simulate map --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 "
                          "--immersion 0.5 --milling down --feed 0.1 --rpm 8000:12000 --depth 0.5:2 --revolutions 4";
  expect_refused(map + " --depths 1", "--depths 1 must lie in 2…100000");
  expect_refused(map + " --speeds 1", "--speeds 1 must lie in 2…1000000");
}

// toolpoint predict: --speed [rpm] ≥ 0, a spin in rad/s refused; --extrapolate-bearings a switch.
TEST(CliOptionFieldsCore, PredictFlags) {
  expect_flags_in_help("predict", {{"--speed", "rpm"}, {"--extrapolate-bearings", ""}});
  expect_refused("predict " + kExample + " --speed -5", "--speed");
  expect_refused("predict " + kExample + " --speed 15", "--speed");
  std::string out;
  EXPECT_EQ(run_toolpoint("predict " + kExample + " --speed 0", &out), 0) << out;
}
