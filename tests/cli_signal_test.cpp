// filter, noise and rotational through the command line: the docs/reference.md §6 Savitzky–Golay oracle and
// the static cantilever's finite differences (docs/reference.md §5) from files, bad input refused with its exit
// code. (Moved here from signal_test.cpp so that the library's tests build without the CLI.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "toolpoint/io/io.hpp"
#include "toolpoint/measured/signal.hpp"
#include "support/test_util.hpp"

using namespace toolpoint;
using test::cantilever_static;
using test::single;

namespace {

namespace fs = std::filesystem;

// A scratch folder per test, removed afterwards.
class SignalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("toolpoint_signal_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  void write(const std::string& name, const std::string& text) const { write_text_file(path(name), text); }

  // Runs `toolpoint ARGS` in the scratch folder; returns the exit code, stderr in err_.
  int run(const std::string& args) {
    const std::string cmd = "cd '" + dir_.string() + "' && '" TOOLPOINT_CLI "' " + args + " > out.txt 2> err.txt";
    const int status = std::system(cmd.c_str());
    err_ = read_text_file(path("err.txt"));
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  bool err_has(const std::string& s) const { return err_.find(s) != std::string::npos; }

  fs::path dir_;
  std::string err_;
};

// An FRF CSV of the static cantilever flexibility between two points, on two frequencies.
std::string static_frf(double x, double xi, double f0 = 10.0) {
  const double g = cantilever_static(x, xi);
  FrfSeries s = single({{g, 0.0}, {g, -0.01 * g}}, f0, 10.0);
  return format_frf_csv(s);
}

}  // namespace

// The docs/reference.md §6 oracle through the command line, on a complex FRF (imaginary part = −real part)
// and on a 2×2 block: the form is kept and every column is filtered. Written in shortest
// round-trip form, so the file holds the library's numbers: 1e-14 relative as in the library test
// (the values are in µm/N, so 1e-20 m/N).
// The command refuses a window longer than a quarter of the points, so the oracle's nine samples
// are followed by six of 3 and its last five again (20 points): the first seven outputs depend on
// samples 0–8 only and the last two on the last five samples, so they are the oracle's.
TEST_F(SignalCli, FilterReproducesOracle) {
  const double x[] = {2, 2, 5, 2, 1, 0, 1, 4, 9, 3, 3, 3, 3, 3, 3, 1, 0, 1, 4, 9};
  const double want[] = {58 / 35.0, 111 / 35.0, 124 / 35.0, 20 / 7.0, 23 / 35.0, 6 / 35.0, 1, 4, 9};
  const int at[] = {0, 1, 2, 3, 4, 5, 6, 18, 19};  // the outputs that are the oracle's want[0..8]
  std::string single_csv = "frequency_hz,re,im\n", block_csv = "frequency_hz,H_re,H_im,L_re,L_im,N_re,N_im,P_re,P_im\n";
  for (int i = 0; i < 20; ++i) {
    // In µm/N (a plausible receptance; the reader refuses metres per newton of this size).
    const std::string f = std::to_string(100 + 5 * i), v = std::to_string(x[i]) + "e-6", mv = std::to_string(-x[i]) + "e-6";
    single_csv += f + "," + v + "," + mv + "\n";
    block_csv += f + "," + v + "," + mv + "," + v + ",0," + "0," + mv + "," + v + "," + v + "\n";
  }
  write("x.csv", single_csv);
  write("b.csv", block_csv);
  ASSERT_EQ(run("filter x.csv y.csv --window 5 --order 2"), 0) << err_;
  ASSERT_EQ(run("filter b.csv c.csv -w 5 -p 2"), 0) << err_;
  const FrfSeries y = read_single_csv(path("y.csv"));
  const BlockSeries c = read_block_csv(path("c.csv"));
  ASSERT_EQ(y.size(), 20u);
  ASSERT_EQ(c.size(), 20u);
  for (int k = 0; k < 9; ++k) {
    const int i = at[k];
    const double w = want[k] * 1e-6;
    EXPECT_NEAR(y.values[i].real(), w, 1e-20) << i;
    EXPECT_NEAR(y.values[i].imag(), -w, 1e-20) << i;
    EXPECT_NEAR(y.frequency_hz[i], 100 + 5 * i, 0.0);
    const Block& b = c.blocks[i];
    EXPECT_NEAR(b(0, 0).real(), w, 1e-20);
    EXPECT_NEAR(b(0, 0).imag(), -w, 1e-20);
    EXPECT_NEAR(b(0, 1).real(), w, 1e-20);
    EXPECT_NEAR(b(0, 1).imag(), 0.0, 1e-20);
    EXPECT_NEAR(b(1, 0).real(), 0.0, 1e-20);
    EXPECT_NEAR(b(1, 0).imag(), -w, 1e-20);
    EXPECT_NEAR(b(1, 1).real(), w, 1e-20);
    EXPECT_NEAR(b(1, 1).imag(), w, 1e-20);
  }
}

// Bad input: a clear message naming the option or the file and line, the documented exit code,
// and no output file.
TEST_F(SignalCli, FilterRejectsBadInput) {
  write("x.csv", "frequency_hz,re,im\n1,1e-6,0\n2,2e-6,0\n3,3e-6,0\n4,4e-6,0\n5,5e-6,0\n6,6e-6,0\n7,7e-6,0\n");
  write("nan.csv", "# a comment\nfrequency_hz,re,im\n1,1,0\n2,nan,0\n3,3,0\n");
  EXPECT_EQ(run("filter x.csv y.csv --window 4 --order 2"), 2);
  EXPECT_TRUE(err_has("window 4")) << err_;
  EXPECT_EQ(run("filter x.csv y.csv --window 5 --order 5"), 2);
  EXPECT_TRUE(err_has("order 5")) << err_;
  EXPECT_EQ(run("filter x.csv y.csv --window 9 --order 2"), 2);
  EXPECT_TRUE(err_has("longer than x.csv (7 points)")) << err_;
  EXPECT_EQ(run("filter x.csv y.csv --window 3 --order 2"), 2);  // more than a quarter of 7 points
  EXPECT_TRUE(err_has("a quarter of x.csv (7 points, so at most 1)")) << err_;
  EXPECT_TRUE(err_has("error: --window 3 points")) << err_;
  EXPECT_EQ(run("filter x.csv y.csv --window 5"), 2);  // --order is required
  EXPECT_EQ(run("filter nan.csv y.csv --window 3 --order 1"), 3);
  EXPECT_TRUE(err_has("nan.csv:4")) << err_;
  EXPECT_EQ(run("filter missing.csv y.csv --window 3 --order 1"), 5);
  EXPECT_FALSE(fs::exists(path("y.csv")));
}

// Same seed, same file; another seed, another file; a negative sigma is a usage error.
TEST_F(SignalCli, NoiseIsReproducible) {
  write("h.csv", static_frf(1.0, 1.0));
  ASSERT_EQ(run("noise h.csv a.csv --sigma 0.05 --seed 7"), 0) << err_;
  ASSERT_EQ(run("noise h.csv b.csv --sigma 0.05 --seed 7"), 0) << err_;
  ASSERT_EQ(run("noise h.csv c.csv --seed 8"), 0) << err_;
  EXPECT_EQ(read_text_file(path("a.csv")), read_text_file(path("b.csv")));
  EXPECT_NE(read_text_file(path("a.csv")), read_text_file(path("c.csv")));
  EXPECT_EQ(run("noise h.csv d.csv --sigma -0.1"), 2);
  EXPECT_TRUE(err_has("sigma -0.1")) << err_;
}

// docs/reference.md §5 static check through the command line (second order, s = 0.1): N = L = 151/300,
// P = 31/30 (1e-12 as in the library test); with the hammer at the tip only, P ≈ N²/H00 with a
// warning. Errors: negative spacing, a missing point, grids that differ, a block where a
// single FRF belongs.
TEST_F(SignalCli, RotationalStaticCantilever) {
  std::string args = "rotational --spacing 0.1 --order 2 --output tip.csv";
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const std::string name = "h" + std::to_string(i) + std::to_string(j) + ".csv";
      write(name, static_frf(1.0 - 0.1 * i, 1.0 - 0.1 * j));
      args += " --h" + std::to_string(i) + std::to_string(j) + " " + name;
    }
  ASSERT_EQ(run(args), 0) << err_;
  const BlockSeries b = read_block_csv(path("tip.csv"));
  ASSERT_EQ(b.size(), 2u);
  EXPECT_NEAR(N_of(b.blocks[0]).real(), 151.0 / 300, 1e-12);
  EXPECT_NEAR(L_of(b.blocks[0]).real(), 151.0 / 300, 1e-12);
  EXPECT_NEAR(P_of(b.blocks[0]).real(), 31.0 / 30, 1e-12);

  EXPECT_EQ(run("rotational -s 0.1 --order 1 --h00 h00.csv --h10 h10.csv -o tip1.csv"), 3);
  EXPECT_TRUE(err_has("--assume-reciprocity")) << err_;
  ASSERT_EQ(run("rotational -s 0.1 --order 1 --h00 h00.csv --h10 h10.csv --assume-reciprocity -o tip1.csv"), 0) << err_;
  EXPECT_TRUE(err_has("P approximated as N·L/H00")) << err_;
  EXPECT_NEAR(P_of(read_block_csv(path("tip1.csv")).blocks[0]).real(), 3.0 * std::pow(299.0 / 600, 2), 1e-12);

  EXPECT_EQ(run("rotational --spacing -0.1 --h00 h00.csv --h10 h10.csv --h20 h20.csv -o bad.csv"), 2);
  EXPECT_TRUE(err_has("spacing -0.1 m")) << err_;
  EXPECT_EQ(run("rotational --spacing 0.1 --order 2 --h00 h00.csv --h10 h10.csv -o bad.csv"), 3);
  EXPECT_TRUE(err_has("H20")) << err_;
  write("shifted.csv", static_frf(0.9, 1.0, 11.0));
  EXPECT_EQ(run("rotational --spacing 0.1 --order 1 --h00 h00.csv --h10 shifted.csv -o bad.csv"), 3);
  EXPECT_TRUE(err_has("h00.csv") && err_has("shifted.csv")) << err_;
  EXPECT_EQ(run("rotational --spacing 0.1 --order 1 --h00 h00.csv --h10 tip.csv -o bad.csv"), 3);
  EXPECT_TRUE(err_has("tip.csv")) << err_;
  EXPECT_EQ(run("rotational --spacing 0.1 --order 3 --h00 h00.csv --h10 h10.csv -o bad.csv"), 2);
  EXPECT_FALSE(fs::exists(path("bad.csv")));
}
