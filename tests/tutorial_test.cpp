// The tutorial (docs/tutorial.md), run exactly as written: every ```sh block of its "## Tutorial" section, in
// order, by /bin/sh -e in a scratch folder that has `build/toolpoint` (the binary under test) and
// `examples/` (the repository's) as the reader's checkout has them; then every promise the section
// makes, checked against something independent of the commands that made it:
//   - the noise the identification finds is the 0.5 % the tap tests were given;
//   - the verdict is pass; every stiffness within 0.1 % and every damping within 1.5 % of Table 1
//     (the joint the virtual tap test was run on), and every Table 1 value inside its interval;
//   - without the finite-difference correction the same fit fails with exit code 6 and writes nothing;
//   - the filter lists H's 974 Hz peak lowered by about 12 % and no peak of P (noise only);
//   - every mode of the coupled predictions within 1 % of the model's own at the same overhang
//     (the model's tool point FRF computed here through the library, not by the CLI), the dominant
//     peak's height within 4 % and the most negative real part within 7 %;
//   - the depth stable with 95 % probability within 0.5 % of the nominal at every best speed;
//   - nothing is written outside the folder the commands run in.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "support/joint_data.hpp"
#include "support/scratch.hpp"
#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/measured/peaks.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

namespace {

// The ```sh blocks between "## Tutorial" and the next "## " heading, joined.
std::string tutorial_script() {
  const std::string doc = read_text_file(std::string(TOOLPOINT_SOURCE_DIR) + "/docs/tutorial.md");
  const std::size_t a = doc.find("\n## Tutorial");
  EXPECT_NE(a, std::string::npos) << "docs/tutorial.md has no Tutorial section";
  const std::size_t b = doc.find("\n## ", a + 5);
  const std::string section = doc.substr(a, b == std::string::npos ? std::string::npos : b - a);
  std::string script;
  const std::regex block("```sh\n([\\s\\S]*?)```");
  for (auto it = std::sregex_iterator(section.begin(), section.end(), block); it != std::sregex_iterator(); ++it)
    script += (*it)[1].str();
  return script;
}

int run_in(const fs::path& dir, const std::string& command) {
  const std::string cmd = "cd '" + dir.string() + "' && " + command;
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(Tutorial, RunsAsWrittenInTheDocs) {
  const std::string script = tutorial_script();
  ASSERT_NE(script.find("build/toolpoint identify"), std::string::npos) << script;
  const fs::path dir = fs::temp_directory_path() / ("toolpoint_tutorial_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "build");
  fs::create_symlink(TOOLPOINT_CLI, dir / "build" / "toolpoint");
  fs::create_directory_symlink(std::string(TOOLPOINT_SOURCE_DIR) + "/examples", dir / "examples");
  { std::ofstream(dir / "tutorial.sh") << script; }
  const auto count_examples = [] {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(std::string(TOOLPOINT_SOURCE_DIR) + "/examples")) n += e.exists();
    return n;
  };
  const std::size_t examples_before = count_examples();

  ASSERT_EQ(run_in(dir, "sh -e tutorial.sh > out.txt 2> err.txt"), 0) << read_text_file((dir / "err.txt").string());
  const std::string out = read_text_file((dir / "out.txt").string());

  // Step 4: the noise found, the verdict, the joint against Table 1 (the example file's joint).
  const std::smatch noise = [&] {
    std::smatch m;
    const std::regex r("G11 magnitude σ ([0-9.]+) % \\(H\\)");
    EXPECT_TRUE(std::regex_search(out, m, r)) << out;
    return m;
  }();
  if (!noise.empty()) EXPECT_NEAR(std::stod(noise[1].str()), 0.5, 0.05);
  EXPECT_NE(out.find("verdict: pass"), std::string::npos) << out;
  const JointFile kht = load_joint_file((dir / "kht.toml").string());
  const JointParameters table1 = test::example_assembly().holder_tool.parameters;
  ASSERT_TRUE(kht.uncertainty.has_value());
  for (int k = 0; k < 8; ++k) {
    const double tolerance = k % 2 == 0 ? 0.001 : 0.015;  // stiffnesses (even indices), dampings
    EXPECT_LT(std::abs(kht.parameters[k] / table1[k] - 1.0), tolerance) << JointParameters::name(k);
    EXPECT_LE(kht.uncertainty->lower[k], table1[k]) << JointParameters::name(k);
    EXPECT_GE(kht.uncertainty->upper[k], table1[k]) << JointParameters::name(k);
    EXPECT_TRUE(kht.uncertainty->determined[k]) << JointParameters::name(k);
  }
  // The same without the correction: refused, exit 6, no joint file.
  ASSERT_EQ(run_in(dir,
                   "build/toolpoint rotational --uff tap_holder.uff --spacing 0.02 --order 2 --shear-stiffness 8.801e7 "
                   "--output sh11_raw.csv 2>/dev/null && build/toolpoint rotational --uff tap_tool.uff --spacing 0.015 "
                   "--order 2 --shear-stiffness 2.778e7 --output sht11_raw.csv 2>/dev/null"),
            0);
  EXPECT_EQ(run_in(dir,
                   "build/toolpoint identify --joint holder-tool --assembly examples/bt40_shrinkfit_16mm.toml --sh "
                   "sh11_raw.csv --sht sht11_raw.csv --bootstrap 0 --joint-output raw.toml > raw.txt 2>&1"),
            6);
  EXPECT_FALSE(fs::exists(dir / "raw.toml"));
  EXPECT_NE(read_text_file((dir / "raw.txt").string()).find("c_yf"), std::string::npos);

  // Step 5: the filter's report (its rows "  H  raw_hz ..."), then the coupled predictions' modes,
  // peak and real part against the model's at each overhang.
  {
    const std::regex h_row("\n  H +9[67][0-9]\\.[0-9]+ +[0-9.e+-]+ +[0-9.]+ +[0-9.e+-]+ +(-1[1-3]\\.[0-9]+) ");
    std::smatch m;
    EXPECT_TRUE(std::regex_search(out, m, h_row)) << out;
    EXPECT_EQ(out.find("\n  P "), std::string::npos) << out;
  }
  const auto table = test::read_csv_table((dir / "overhangs" / "natural_frequencies.csv").string()).rows;
  ASSERT_EQ(table.size(), 6u);
  std::size_t compared = 0;
  for (const auto& row : table) {
    const Assembly model = with_overhang(test::example_assembly(), row[0]);
    FrfSeries h = entry(AssemblyModel(model).tool_point(model.grid.values()), 0);
    const std::vector<Peak> peaks = find_peaks(h, PeakOptions{0.1});
    const FrfTable file = read_frf_csv((dir / "overhangs" / fmt::format("sht11_overhang_{:.1f}mm.csv", row[0] * 1e3)).string());
    ASSERT_TRUE(file.is_block);
    const FrfSeries coupled = entry(file.block, 0);
    ASSERT_EQ(coupled.size(), h.size());
    double peak_model = 0.0, peak_coupled = 0.0, re_model = 0.0, re_coupled = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
      peak_model = std::max(peak_model, std::abs(h.values[i]));
      peak_coupled = std::max(peak_coupled, std::abs(coupled.values[i]));
      re_model = std::min(re_model, h.values[i].real());
      re_coupled = std::min(re_coupled, coupled.values[i].real());
    }
    EXPECT_LT(std::abs(peak_coupled / peak_model - 1.0), 0.04) << "overhang " << row[0];
    EXPECT_LT(std::abs(re_coupled / re_model - 1.0), 0.07) << "overhang " << row[0];
    for (std::size_t m = 1; m < row.size(); ++m) {
      if (std::isnan(row[m])) continue;
      double nearest = 1e300;
      for (const Peak& p : peaks) nearest = std::min(nearest, std::abs(p.frequency_hz / row[m] - 1.0));
      EXPECT_LT(nearest, 0.01) << "overhang " << row[0] << " m, mode at " << row[m] << " Hz";
      ++compared;
    }
  }
  EXPECT_GE(compared, 20u);

  // Step 7: the 95 % depth against the nominal one at every best speed.
  const std::size_t head = out.find("nominal_mm  p95_mm  p50_mm");
  ASSERT_NE(head, std::string::npos) << out;
  std::istringstream rows(out.substr(out.find('\n', head) + 1));
  std::string line;
  std::size_t speeds = 0;
  while (std::getline(rows, line)) {
    double rpm = 0, nominal = 0, p95 = 0, p50 = 0;
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf", &rpm, &nominal, &p95, &p50) != 4) break;
    EXPECT_LT(std::abs(p95 / nominal - 1.0), 0.005) << line;
    ++speeds;
  }
  EXPECT_GE(speeds, 3u);
  for (const char* f : {"sht11_model.png", "lobes.png", "p.png", "p_probability.png", "p.csv", "kht.png", "overhangs.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;

  // Nothing written into the repository's examples through the symlink.
  EXPECT_EQ(count_examples(), examples_before);
  if (!HasFailure()) fs::remove_all(dir);
}
