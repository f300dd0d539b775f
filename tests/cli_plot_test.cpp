// Figures through the command line (plot.hpp's figures drawn by gnuplot): the files written, and
// what happens without gnuplot. (Moved here from plot_test.cpp so that the library's tests build
// without the CLI.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <utility>

#include "toolpoint/io/io.hpp"
#include "support/scratch.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

namespace {

using test::TempDir;

std::string slurp(const std::string& path) { return read_text_file(path); }

}  // namespace

// toolpoint beam --plot: the CSV and a 4-panel PNG (1000 × 1040 px) are written; without
// gnuplot on PATH the CSV is still written, the PNG is not, and the exit code is 5 (I/O) with
// a message saying so.
TEST(PlotCli, BeamPlot) {
  TempDir dir;
  const std::string base = std::string(TOOLPOINT_CLI) +
                           " --quiet beam --length 0.123 --diameter 0.016 --youngs-modulus 5.8e11 --density 14500"
                           " --loss-factor 0.002 --frequencies 10:20000:20";
  const std::string ok = base + " --output " + (dir / "t.csv") + " --plot " + (dir / "t.png");
  ASSERT_EQ(std::system(ok.c_str()), 0) << ok;
  EXPECT_TRUE(fs::exists(dir / "t.csv"));
  EXPECT_EQ(test::png_size(slurp(dir / "t.png")), std::make_pair(1000u, 1040u));

  const std::string missing = "PATH=/nonexistent " + base + " --output " + (dir / "u.csv") + " --plot " + (dir / "u.png") +
                              " 2> " + (dir / "err.txt");
  const int status = std::system(missing.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 5);
  EXPECT_TRUE(fs::exists(dir / "u.csv"));
  EXPECT_FALSE(fs::exists(dir / "u.png"));
  const std::string err = slurp(dir / "err.txt");
  EXPECT_NE(err.find("gnuplot not found"), std::string::npos) << err;
  EXPECT_NE(err.find("u.csv"), std::string::npos) << err;

  const std::string typo = base + " --output " + (dir / "v.csv") + " --plot " + (dir / "v.jpg") + " 2>/dev/null";
  const int bad = std::system(typo.c_str());
  EXPECT_EQ(WEXITSTATUS(bad), 2);
  EXPECT_FALSE(fs::exists(dir / "v.csv"));  // refused before any work
}
