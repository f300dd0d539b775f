// lobes and modes through the command line: the files they write and their headers, exit codes for
// bad input, the modal fit of a two-mode FRF (the Insperger–Stépán mode, docs/reference.md §7, and another),
// and progress lines on a pipe. (Moved here from stability_test.cpp so that the library's tests
// build without the CLI.)
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cctype>
#include <iterator>
#include <map>
#include <cmath>
#include <fmt/format.h>
#include <sstream>
#include <tuple>
#include <vector>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "toolpoint/io/io.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "support/expected_fields.hpp"

using namespace toolpoint;

namespace {

// The Insperger–Stépán (2004) benchmark mode (docs/reference.md §7).
const Mode kBench{0.03993, 0.011, 922.0};

std::vector<double> uniform_grid(double lo, double hi, double step) {
  std::vector<double> f;
  for (int i = 0; lo + i * step <= hi; ++i) f.push_back(lo + i * step);
  return f;
}

}  // namespace

namespace {

struct CliRun {
  int code;
  std::string out;
};

CliRun run_cli(const std::string& args) {
  const std::string cmd = std::string(TOOLPOINT_CLI) + " " + args + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::string temp_dir() {
  const auto dir = std::filesystem::temp_directory_path() / ("toolpoint_stability_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace

TEST(LobesCommand, WritesLobesAndRejectsBadInputWithExitCodes) {
  const std::string dir = temp_dir();
  const std::string frf = dir + "/bench.csv";
  write_frf_csv(frf, modal_frf({kBench}, uniform_grid(600.0, 1400.0, 0.5)));
  const std::string base = "lobes --frf " + frf + " --teeth 2 --kt 6e8 --kn 2e8 --milling down --rpm 5000:25000";

  const CliRun ok = run_cli(base + " --immersion 0.05 --output " + dir + "/z.csv --envelope " + dir + "/e.csv");
  ASSERT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("absolute stability limit"), std::string::npos) << ok.out;
  const std::string csv = read_text_file(dir + "/z.csv");
  EXPECT_NE(csv.find("\nlobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,root\n"), std::string::npos);
  EXPECT_NE(read_text_file(dir + "/e.csv").find("\nspindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,lobe\n"),
            std::string::npos);

  const CliRun sd = run_cli(base + " --immersion 0.05 --method fd --rigid-y --speeds 9 --max-depth 10 --output " + dir +
                            "/s.csv");
  ASSERT_EQ(sd.code, 0) << sd.out;
  EXPECT_NE(read_text_file(dir + "/s.csv")
                .find("\nlobe,spindle_speed_rpm,axial_depth_mm,chatter_frequency_hz,kind,axial_depth_error_mm,steps\n"),
            std::string::npos);
  // The same by semi-discretization (issue 27): the same columns, and depths within 2 % of fd's
  // (each method's estimated error is under its 1 % target).
  const CliRun semi = run_cli(base + " --immersion 0.05 --method sd --rigid-y --speeds 9 --max-depth 10 --output " + dir +
                              "/sd.csv");
  ASSERT_EQ(semi.code, 0) << semi.out;
  auto depths = [](const std::string& text) {
    std::vector<double> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || !(std::isdigit(static_cast<unsigned char>(line[0])) || line[0] == '-')) continue;
      std::istringstream fields(line);
      std::string lobe, speed, depth;
      std::getline(fields, lobe, ',');
      std::getline(fields, speed, ',');
      std::getline(fields, depth, ',');
      out.push_back(std::stod(depth));
    }
    return out;
  };
  const std::vector<double> fd_depth = depths(read_text_file(dir + "/s.csv")), sd_depth = depths(read_text_file(dir + "/sd.csv"));
  ASSERT_EQ(sd_depth.size(), fd_depth.size());
  ASSERT_GE(fd_depth.size(), 9u);
  for (std::size_t i = 0; i < fd_depth.size(); ++i) EXPECT_NEAR(sd_depth[i], fd_depth[i], 0.02 * fd_depth[i]) << i;

  // The JSON names the scheme that made the boundary and its degree (fd: the default interpolation
  // degree 2; sd: its first order, LobesStudyOptions::degree 2 capped at 1, boundary_options), so
  // two runs' boundaries are never confused; independent of the text output.
  for (const auto& [method, scheme, degree] : {std::tuple{"fd", "fd", 2}, std::tuple{"sd", "sd", 1}}) {
    const CliRun js = run_cli(base + " --immersion 0.05 --rigid-y --speeds 3 --max-depth 10 --json --method " + method);
    ASSERT_EQ(js.code, 0) << js.out;
    const std::size_t open = js.out.find("{\n"), close = js.out.rfind("\n}");
    ASSERT_NE(open, std::string::npos) << js.out;
    const nlohmann::json boundary = nlohmann::json::parse(js.out.substr(open, close + 2 - open)).at("boundary");
    ASSERT_TRUE(boundary.contains("scheme")) << boundary.dump();
    EXPECT_EQ(boundary["scheme"], scheme) << method;
    EXPECT_EQ(boundary["degree"], degree) << method;
  }

  // The modal fit's warnings name the FRF they are about (the assembly's tool point FRF), never an
  // empty name; the library's field names reach the user as the options' spellings.
  const CliRun assembly = run_cli(
      "lobes --assembly " + std::string(TOOLPOINT_SOURCE_DIR) +
      "/examples/bt40_shrinkfit_16mm.toml "
      "--method fd --teeth 4 --kt 6e8 --kr 0.3 --immersion 0.5 --milling down --rpm 8000:9000 --speeds 3");
  ASSERT_EQ(assembly.code, 0) << assembly.out;
  EXPECT_EQ(assembly.out.find("warning: :"), std::string::npos) << assembly.out;
  EXPECT_NE(assembly.out.find("warning: the tool point FRF of "), std::string::npos) << assembly.out;
  EXPECT_NE(assembly.out.find("estimated discretization error at most"), std::string::npos) << assembly.out;
  const CliRun few_lobes = run_cli(base + " --immersion 0.5 --lobes 1");
  EXPECT_NE(few_lobes.out.find("--lobes"), std::string::npos) << few_lobes.out;

  // Angles in radians for degrees (90° = 1.5708): refused, the fix in degrees.
  const CliRun radians = run_cli(base + " --entry 0 --exit 1.5708");
  EXPECT_EQ(radians.code, 2) << radians.out;
  EXPECT_NE(radians.out.find("look like radians"), std::string::npos) << radians.out;
  EXPECT_NE(radians.out.find("--entry 0 --exit 90.0002"), std::string::npos) << radians.out;
  EXPECT_EQ(run_cli(base + " --entry 0 --exit 90").code, 0);
  const CliRun bad_immersion = run_cli(base + " --immersion 1.5");
  EXPECT_EQ(bad_immersion.code, 2) << bad_immersion.out;
  EXPECT_NE(bad_immersion.out.find("immersion"), std::string::npos) << bad_immersion.out;
  const CliRun empty_rpm = run_cli("lobes --frf " + frf +
                                   " --teeth 2 --kt 6e8 --kr 0.3 --immersion 0.5 --milling up --rpm 8000:8000");
  EXPECT_EQ(empty_rpm.code, 2) << empty_rpm.out;
  EXPECT_NE(empty_rpm.out.find("rpm"), std::string::npos) << empty_rpm.out;
  const CliRun negative = run_cli(base + " --immersion 0.5 --kt -6e8");
  EXPECT_EQ(negative.code, 2) << negative.out;
  const CliRun missing = run_cli("lobes --frf " + dir +
                                 "/nope.csv --teeth 2 --kt 6e8 --kr 0.3 --immersion 0.5 --milling up --rpm 1000:2000");
  EXPECT_EQ(missing.code, 5) << missing.out;
  write_text_file(dir + "/broken.csv", "frequency_hz,re,im\n100,1e-6,-1e-7\n200,oops,0\n");
  const CliRun broken = run_cli("lobes --frf " + dir +
                                "/broken.csv --teeth 2 --kt 6e8 --kr 0.3 --immersion 0.5 --milling up --rpm 1000:2000");
  EXPECT_EQ(broken.code, 3) << broken.out;
  EXPECT_NE(broken.out.find("broken.csv:3"), std::string::npos) << broken.out;
  // A failed run leaves no half-written output behind.
  EXPECT_FALSE(std::filesystem::exists(dir + "/never.csv"));
  const CliRun no_output = run_cli(base + " --immersion 2 --output " + dir + "/never.csv");
  EXPECT_EQ(no_output.code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir + "/never.csv"));
  std::filesystem::remove_all(dir);
}

TEST(ModesCommand, FitsAnFrfAndRejectsACoarseOne) {
  const std::string dir = temp_dir();
  write_frf_csv(dir + "/two.csv", modal_frf({kBench, Mode{0.2, 0.03, 2100.0}}, uniform_grid(300.0, 3000.0, 1.0)));
  const CliRun ok = run_cli("modes " + dir + "/two.csv --max-modes 2 --json");
  ASSERT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("\"mass_kg\": 0.0399"), std::string::npos) << ok.out;
  const CliRun text = run_cli("modes " + dir + "/two.csv");
  ASSERT_EQ(text.code, 0) << text.out;
  EXPECT_NE(text.out.find("--mode-x 0.03993,0.011,922 --mode-x 0.2,0.03,2100"), std::string::npos) << text.out;
  write_frf_csv(dir + "/coarse.csv", modal_frf({kBench}, uniform_grid(500.0, 1500.0, 25.0)));
  const CliRun coarse = run_cli("modes " + dir + "/coarse.csv");
  EXPECT_EQ(coarse.code, 3) << coarse.out;
  EXPECT_NE(coarse.out.find("half-power band"), std::string::npos) << coarse.out;
  const CliRun bad_band = run_cli("modes " + dir + "/two.csv --band 900");
  EXPECT_EQ(bad_band.code, 2) << bad_band.out;
  // An sd run from explicit modes, and a malformed mode.
  const std::string sd =
      "lobes --method fd --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.05 --milling down --rpm 17000:18000 --speeds 2 --rigid-y";
  const CliRun modes_given = run_cli(sd + " --mode-x 0.03993,0.011,922 --max-depth 10 --json");
  ASSERT_EQ(modes_given.code, 0) << modes_given.out;
  EXPECT_NE(modes_given.out.find("\"kind\": \"flip\""), std::string::npos) << modes_given.out;
  const CliRun malformed = run_cli(sd + " --mode-x 0.03993,0.011");
  EXPECT_EQ(malformed.code, 2) << malformed.out;
  EXPECT_NE(malformed.out.find("--mode-x"), std::string::npos) << malformed.out;
  std::filesystem::remove_all(dir);
}

// Without a terminal (stderr to a pipe here) long work reports progress as lines, the first after
// TOOLPOINT_PROGRESS_DELAY seconds (0 here; 5 by default, so short runs print none), and a closing
// line; --quiet prints none. The data on stdout are untouched.
TEST(LobesCommand, ProgressLinesWhenStderrIsNotATerminal) {
  const std::string args =
      " lobes --method fd --mode-x 0.04,0.011,922 --rigid-y --teeth 2 --kt 6e8 --kn 2e8 --immersion 0.05 "
      "--milling down --rpm 5000:25000 --speeds 24 2>&1 >/dev/null";
  const auto run = [](const std::string& cmd) {
    FILE* p = ::popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    EXPECT_EQ(::pclose(p), 0) << cmd;
    return out;
  };
  const std::string shown = run("TOOLPOINT_PROGRESS_DELAY=0 " + std::string(TOOLPOINT_CLI) + args);
  EXPECT_NE(shown.find("lobes: full-discretization boundary: "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" % after "), std::string::npos) << shown;
  EXPECT_NE(shown.find("lobes: full-discretization boundary: done in "), std::string::npos) << shown;
  EXPECT_EQ(shown.find('\r'), std::string::npos) << "no bar redrawing in a pipe";
  const std::string quiet = run("TOOLPOINT_PROGRESS_DELAY=0 " + std::string(TOOLPOINT_CLI) + " --quiet" + args);
  EXPECT_EQ(quiet.find("full-discretization boundary"), std::string::npos) << quiet;
  const std::string default_delay = run(std::string(TOOLPOINT_CLI) + args);
  EXPECT_EQ(default_delay.find("% after"), std::string::npos) << "a run under 5 s prints no progress line";
}

// --helix (issue 27): degrees, one angle or one per tooth, with --diameter; radians, a negative
// angle, the wrong count and a missing diameter refused with the flag named (the zero-order method:
// Helix.BadHelixNamesTheField); the boundary's CSV
// says which tool it is for.
TEST(LobesCommand, HelixInDegreesWithTheDiameter) {
  const std::string dir = temp_dir();
  const std::string base =
      "lobes --method fd --mode-x 0.03993,0.011,922 --rigid-y --teeth 4 --kt 1.5e8 --kr 0.3 --immersion 0.05 --milling down "
      "--rpm 6000:7000 --speeds 3 --threads 1";
  const CliRun ok = run_cli(base + " --helix 30,40,30,40 --diameter 20 --output " + dir + "/h.csv");
  ASSERT_EQ(ok.code, 0) << ok.out;
  std::ifstream csv(dir + "/h.csv");
  const std::string text((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("# helix 30,40,30,40 deg, 8 axial slices, diameter 20 mm"), std::string::npos) << text;
  const auto refused = [&](const std::string& args, const std::string& said) {
    const CliRun r = run_cli(base + args);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find(said), std::string::npos) << r.out;
  };
  refused(" --helix 0.52 --diameter 20", "look like radians");
  refused(" --helix -5 --diameter 20", "--helix[0] = -5°");
  refused(" --helix 30,40 --diameter 20", "--helix has 2 angles for 4 teeth");
  refused(" --helix 30", "--diameter must be given with a helix");
  std::filesystem::remove_all(dir);
}

// lobes at speed: an assembly whose bearings carry a speed table gets the x–y FRF at each speed
// (automatically, said in the summary and a note); a speed range beyond the table is an error
// naming --rpm, the bearing's table and the fix (--extrapolate-bearings), exit code non-zero;
// the at-speed options without --assembly are refused.
TEST(LobesCommand, AtSpeedFromABearingTable) {
  const std::string dir = temp_dir();
  std::string text = read_text_file(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml");
  const std::size_t at = text.find("\n[[spindle.bearing]]");
  text.insert(text.find('\n', at + 1) + 1, "speed_rpm = [0, 20000]\nstiffness_at_speed = [6.0e8, 4.0e8]\n");
  text.replace(text.find("frequency_step = 1.0"), 20, "frequency_step = 5.0");
  const std::string file = dir + "/tabled.toml";
  write_text_file(file, text);
  const std::string base = "lobes --assembly " + file +
                           " --teeth 4 --kt 6e8 --kr 0.3 --immersion 0.5 --milling down --speeds 50 --speed-nodes 5";
  const CliRun ok = run_cli(base + " --rpm 5000:20000");
  ASSERT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("at speed (spinning): the x-y tool point FRF at 9 speeds"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("in x and y at each spindle speed"), std::string::npos) << ok.out;
  const CliRun beyond = run_cli(base + " --rpm 5000:25000");
  EXPECT_NE(beyond.code, 0) << beyond.out;
  EXPECT_NE(beyond.out.find("--rpm"), std::string::npos) << beyond.out;
  EXPECT_NE(beyond.out.find("speed_table"), std::string::npos) << beyond.out;
  EXPECT_NE(beyond.out.find("--extrapolate-bearings"), std::string::npos) << beyond.out;
  EXPECT_EQ(run_cli(base + " --rpm 5000:25000 --extrapolate-bearings").code, 0);
  const CliRun standstill = run_cli(base + " --rpm 5000:20000 --speed-model standstill --json");
  ASSERT_EQ(standstill.code, 0) << standstill.out;
  EXPECT_EQ(standstill.out.find("frf_speeds_rpm"), std::string::npos) << standstill.out;
  const CliRun no_assembly = run_cli("lobes --frf " + file +
                                     " --teeth 4 --kt 6e8 --kr 0.3 --immersion 0.5 --milling down "
                                     "--rpm 5000:20000 --speed-model spinning");
  EXPECT_NE(no_assembly.code, 0);
  EXPECT_NE(no_assembly.out.find("need --assembly"), std::string::npos) << no_assembly.out;
}

// toolpoint pitch: degrees on the command line, the library's choice in the report (its numbers are
// tests/pitch_test.cpp's), and bad input — limits that admit no pattern, angles given in radians, an
// alternating pitch on an odd tooth count, a three-angle pitch on 4 teeth — refused with exit code 2,
// naming the flag.
TEST(PitchCommand, ChoosesAPitchAndRefusesBadLimits) {
  const std::string cut = "--mode-x 0.03993,0.011,922 --rigid-y --kt 6e8 --kr 0.3 --immersion 0.5 --milling down --rpm 4130 ";
  const CliRun ok = run_cli("pitch " + cut + "--teeth 4 --min-pitch 60 --max-pitch 120");
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("chosen (searched):"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("8.51× the even tool"), std::string::npos) << ok.out;
  // Three angles: two parameters reported.
  const CliRun three = run_cli("pitch " + cut + "--teeth 3 --pattern three-angle --search-points 5");
  EXPECT_EQ(three.code, 0) << three.out;
  EXPECT_NE(three.out.find("three-angle pattern"), std::string::npos) << three.out;
  EXPECT_NE(three.out.find("chosen (searched):      u "), std::string::npos) << three.out;
  // Refused (exit 2), each naming what to fix: {arguments, what the message must say}.
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"--teeth 4 --min-pitch 95 --max-pitch 120", {"--min-pitch", "no variable pitch fits"}},
           {"--teeth 4 --min-pitch 1.2 --max-pitch 1.9", {"most likely radians"}},
           {"--teeth 3", {"--pattern"}},
           {"--teeth 4 --pitch 80,100,80,100", {"--pitch"}},
           {"--teeth 4 --pattern three-angle", {"--pattern three-angle needs a multiple of 3 teeth"}}}) {
    const CliRun refused = run_cli("pitch " + cut + args);
    EXPECT_EQ(refused.code, 2) << args;
    for (const std::string& text : says) EXPECT_NE(refused.out.find(text), std::string::npos) << args << ": " << refused.out;
  }
}

// The flags of LobesStudyOptions' fields derive from lobes_study_fields (option_fields.hpp): every
// field with a flag is a flag of `toolpoint lobes`, typed in its CLI unit (%, mm) and echoed by
// --json in its SI unit under its field name (the value written, to 1e-14 relative: the unit's
// factor and back cost an ulp or two); a value just outside its range is refused (exit 2) naming
// the flag, the value in the CLI's unit and the range in it.
TEST(LobesCommand, OptionFieldsAsFlags) {
  const std::string base = "lobes --assembly " + std::string(TOOLPOINT_SOURCE_DIR) +
                           "/examples/bt40_shrinkfit_16mm.toml --teeth 4 --kt 6e8 --kr 0.3 --immersion 0.5 --milling down "
                           "--rpm 5000:15000 --speeds 50 --speed-model standstill";
  std::string flags;
  std::map<std::string, double> expected;
  for (const auto& f : lobes_study_fields()) {
    const FieldSpec& s = f.spec;
    if (!s.cli_name) continue;
    const std::string flag = field_flag(s);
    double v = std::isfinite(s.max) ? s.min + (s.max - s.min) * 0.001 : s.min + 0.001;
    if (s.kind == FieldKind::Integer) v = std::floor(v);
    if (s.kind == FieldKind::Flag) v = 1.0;
    flags += s.kind == FieldKind::Flag ? fmt::format(" {}", flag) : fmt::format(" {} {:.17g}", flag, v * s.cli_per_unit);
    expected[s.name] = v;
    // (--max-modes and --fit-target are registered by add_dynamics_options, shared with pitch and
    // simulate, from this table too: refused at the flag as the others.)
    if (s.kind == FieldKind::Flag) continue;
    const double bad = s.kind == FieldKind::Integer ? s.max + 1.0 : std::isfinite(s.max) ? s.max * 1.5 : s.min - 1.0;
    const CliRun refused = run_cli(base + fmt::format(" {} {:g}", flag, bad * s.cli_per_unit));
    EXPECT_EQ(refused.code, 2) << refused.out;
    EXPECT_NE(refused.out.find(fmt::format("{} {:g}", flag, bad * s.cli_per_unit)), std::string::npos) << refused.out;
    EXPECT_NE(refused.out.find(field_range_text(s, s.cli_per_unit)), std::string::npos) << refused.out;
  }
  const CliRun ok = run_cli(base + flags + " --json");
  ASSERT_EQ(ok.code, 0) << ok.out;
  const std::size_t open = ok.out.find("{\n"), close = ok.out.rfind("\n}");
  ASSERT_NE(open, std::string::npos) << ok.out;
  const nlohmann::json options = nlohmann::json::parse(ok.out.substr(open, close + 2 - open)).at("options");
  for (const auto& [name, v] : expected) {
    ASSERT_TRUE(options.contains(name)) << name;
    const double echoed = options[name].is_boolean() ? (options[name].get<bool>() ? 1.0 : 0.0) : options[name].get<double>();
    EXPECT_NEAR(echoed, v, 1e-14 * std::abs(v)) << name;
  }
  EXPECT_EQ(expected.size(), 9u);  // every flagged field, --max-modes and --fit-target among them
}

// The flags of PitchChoiceOptions' fields derive from pitch_choice_fields; against the expectation
// written by hand (support/expected_fields.hpp): each flag is in `toolpoint pitch --help` with the
// unit the CLI takes (degrees, %, mm), and a value just outside the expected range, in that unit,
// is refused with exit code 2 naming the flag and the value typed.
TEST(PitchCommand, OptionFieldsAsFlags) {
  const std::string help = run_cli("pitch --help").out;
  const std::string cut = "pitch --mode-x 0.03993,0.011,922 --rigid-y --kt 6e8 --kr 0.3 --immersion 0.5 --milling down --teeth 4";
  int flags = 0;
  for (const auto& e : toolpoint::testing::pitch_expected_fields()) {
    if (e.flag.empty()) continue;
    SCOPED_TRACE(e.flag);
    ++flags;
    const std::string line = toolpoint::testing::help_line(help, e.flag);
    EXPECT_NE(line.find("[" + e.cli_unit + "]"), std::string::npos) << line;
    const std::string bad = toolpoint::testing::cli_text(e, toolpoint::testing::outside(e));
    const CliRun refused = run_cli(cut + (e.flag == "--rpm" ? "" : " --rpm 4130") + " " + e.flag + " " + bad);
    EXPECT_EQ(refused.code, 2) << refused.out;
    EXPECT_NE(refused.out.find(e.flag + " " + bad), std::string::npos) << refused.out;
  }
  EXPECT_EQ(flags, 10);
}
