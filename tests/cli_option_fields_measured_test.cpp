// The flags of SavgolOptions (`toolpoint filter`) and RotationalOptions (`toolpoint rotational`),
// registered from their option tables (option_fields.hpp; issue 26), through the command line: each
// flag is in its command's --help with its unit as the commands had it before the tables; a value
// just outside the old check()'s range exits non-zero naming the flag (not the library field); the
// edges are accepted. Flags, units and ranges written out here by hand, not read from the tables.
// The library's check(): option_fields_measured_test.cpp.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "support/cli_help.hpp"
#include "support/scratch.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/stability/modal_fit.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

// Each `flags` added to `base` exits non-zero naming `named` and no library field of `options`.
void expect_refused(const std::string& base, const std::vector<std::pair<std::string, std::string>>& bad,
                    const std::string& options) {
  for (const auto& [flags, named] : bad) {
    std::string out;
    EXPECT_NE(run_toolpoint(base + " " + flags, &out), 0) << flags << ": " << out;
    EXPECT_NE(out.find(named), std::string::npos) << flags << ": " << out;
    EXPECT_EQ(out.find(options + "::"), std::string::npos) << out;  // the flag, not the field
  }
}

// A one-mode FRF on 41 points (a filter window may be up to a quarter of them: 10).
std::string write_frf(const TempDir& dir) {
  std::vector<double> f;
  for (int i = 0; i <= 40; ++i) f.push_back(800.0 + 5.0 * i);
  write_frf_csv(dir / "h.csv", modal_frf({Mode{0.04, 0.011, 922.0}}, f));
  return dir / "h.csv";
}

}  // namespace

// Old: --window odd, ≥ 1 (SavgolOptions::check), ≤ a quarter of the points; --order ≥ 0, < --window.
TEST(CliOptionFieldsMeasured, FilterFlags) {
  expect_flags_in_help("filter", {{"--window", "frequency points"}, {"--order", "-"}});
  TempDir dir;
  const std::string base = "filter " + write_frf(dir) + " " + dir / "out.csv";
  expect_refused(base,
                 {{"--window 0 --order 0", "--window"},
                  {"--window 4 --order 2", "--window"},
                  {"--window 5 --order -1", "--order"},
                  {"--window 5 --order 5", "--order"}},
                 "SavgolOptions");
  std::string out;
  EXPECT_EQ(run_toolpoint(base + " --window 1 --order 0", &out), 0) << out;
  EXPECT_EQ(run_toolpoint(base + " -w 9 -p 8", &out), 0) << out;
}

// Old: --order 1 or 2 (CLI::IsMember), --spacing > 0 [m]; the switches --symmetrise and
// --assume-reciprocity.
TEST(CliOptionFieldsMeasured, RotationalFlags) {
  expect_flags_in_help("rotational", {{"--order", "-"}, {"--spacing", "m"}, {"--symmetrise", ""}, {"--assume-reciprocity", ""}});
  TempDir dir;
  const std::string h = write_frf(dir);
  const std::string base = "rotational --h00 " + h + " --h10 " + h + " --h20 " + h + " --assume-reciprocity --output " +
                           dir / "r.csv";
  expect_refused(base + " --spacing 0.01", {{"--order 0", "--order"}, {"--order 3", "--order"}}, "RotationalOptions");
  expect_refused(base, {{"--spacing 0", "--spacing"}, {"--spacing -0.01", "--spacing"}}, "RotationalOptions");
  std::string out;
  EXPECT_EQ(run_toolpoint(base + " --spacing 0.01 --order 1 --symmetrise", &out), 0) << out;
  EXPECT_EQ(run_toolpoint(base + " -s 0.01 --order 2", &out), 0) << out;
}
