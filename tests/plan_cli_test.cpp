// `toolpoint plan` as a user meets it (the binary, TOOLPOINT_CLI): a study run whole and the same
// study run as shards in a batch loop then merged (files identical byte for byte), the errors (exit
// code, the file or option named, a fix line, nothing overwritten). The numbers are tested in
// process (plan_test.cpp); a small study keeps this file to about a second.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

#include "toolpoint/io.hpp"

namespace {

namespace fs = std::filesystem;
using toolpoint::read_text_file;
using toolpoint::write_text_file;

const std::string kExamples = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/";

class PlanCli : public ::testing::Test {
 protected:
  struct Run {
    int code = -1;
    std::string out, err;
  };

  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("toolpoint_plan_cli_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The example study, coarser: 7 overhangs (60–120 mm by 10 mm), 300 speeds.
    std::string s = read_text_file(kExamples + "plan_bt40.toml");
    const auto swap = [&](const std::string& a, const std::string& b) {
      const std::size_t at = s.find(a);
      ASSERT_NE(at, std::string::npos) << a;
      s.replace(at, a.size(), b);
    };
    swap("assembly = \"bt40_shrinkfit_16mm.toml\"", "assembly = \"" + kExamples + "bt40_shrinkfit_16mm.toml\"");
    swap("overhang_min = 0.040", "overhang_min = 0.060");
    swap("overhang_step = 0.001", "overhang_step = 0.010");
    swap("speed_points = 2000", "speed_points = 300");
    write_text_file(path("study.toml"), s);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  Run run(const std::string& args) const {
    const std::string cmd = "cd '" + dir_.string() + "' && '" TOOLPOINT_CLI "' " + args + " > .stdout 2> .stderr < /dev/null";
    const int status = std::system(cmd.c_str());
    Run r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text_file(path(".stdout"));
    r.err = read_text_file(path(".stderr"));
    return r;
  }

  void expect_error(const Run& r, int code, std::initializer_list<std::string> mentions) const {
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_NE(r.err.find("error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("\n  fix: "), std::string::npos) << "no fix line:\n" << r.err;
    for (const auto& m : mentions) EXPECT_NE(r.err.find(m), std::string::npos) << "'" << m << "' not named:\n" << r.err;
  }

  fs::path dir_;
};

}  // namespace

// The batch path run locally: shards 0…2 of 3 in a loop (as a Slurm array or an Indexed Job runs
// them), merged in another order, write the same files as the single run, byte for byte; the
// report and --json name the same best set-up.
TEST_F(PlanCli, ShardsInALoopThenMergeEqualTheSingleRun) {
  Run whole = run("plan study.toml --output whole --threads 2");
  ASSERT_EQ(whole.code, 0) << whole.err;
  EXPECT_NE(whole.out.find("best set-ups"), std::string::npos) << whole.out;
  EXPECT_NE(whole.out.find("why: "), std::string::npos) << whole.out;
  for (int i = 0; i < 3; ++i) {
    const Run r = run("plan study.toml --threads 1 --shard " + std::to_string(i) + "/3 --part parts/part-" + std::to_string(i) + ".json");
    ASSERT_EQ(r.code, 0) << r.err;
  }
  const Run merged = run("plan merge parts/part-2.json parts/part-0.json parts/part-1.json --output merged");
  ASSERT_EQ(merged.code, 0) << merged.err;
  EXPECT_EQ(merged.out, whole.out);
  for (const char* f : {"setups.csv", "tuning.csv", "map.csv", "plan.json"})
    EXPECT_EQ(read_text_file(path("merged/") + f), read_text_file(path("whole/") + f)) << f;
  const Run json = run("plan merge parts/part-0.json parts/part-1.json parts/part-2.json --json");
  ASSERT_EQ(json.code, 0) << json.err;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["best"].size(), 1u);
  EXPECT_EQ(j["jobs"], 7);
  EXPECT_EQ(j["best"][0]["limit"], "stability");
}

TEST_F(PlanCli, ErrorsNameTheOptionOrFileAndLeaveNothingBehind) {
  expect_error(run("plan study.toml --shard 3/3 --part p.json"), 2, {"--shard '3/3'", "0 ≤ I < N"});
  expect_error(run("plan study.toml --shard 0/2"), 2, {"--shard needs --part"});
  expect_error(run("plan study.toml --shard 0/2 --part p.json --output out"), 2, {"plan merge"});
  EXPECT_FALSE(fs::exists(path("p.json")));
  // An output over an input: refused, the input untouched.
  const std::string before = read_text_file(path("study.toml"));
  expect_error(run("plan study.toml --shard 0/1 --part study.toml"), 2, {"is the input", "study.toml"});
  EXPECT_EQ(read_text_file(path("study.toml")), before);
  // A bad study file: its line and key.
  std::string bad = before;
  bad.replace(bad.find("teeth = 4"), 9, "teeth = 0");
  write_text_file(path("bad.toml"), bad);
  expect_error(run("plan bad.toml --output out"), 3, {"bad.toml:", "cut.teeth = 0"});
  EXPECT_FALSE(fs::exists(path("out")));
  // Merging: a missing shard, a file that is no part.
  ASSERT_EQ(run("plan study.toml --shard 0/2 --part p0.json").code, 0);
  expect_error(run("plan merge p0.json --output out"), 3, {"shard(s) 1 of 2 missing"});
  expect_error(run("plan merge study.toml --output out"), 3, {"study.toml", "not a plan part file"});
  EXPECT_FALSE(fs::exists(path("out")));
  const Run none = run("plan merge");  // CLI11's own usage error, with the fix line main adds
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("parts is required"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("  fix: "), std::string::npos) << none.err;
}
