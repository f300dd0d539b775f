// The plan's files, in process: the study file (what it reads, and the errors a user meets: file,
// line, key, what was expected, a fix) and the part files of a sharded run (exact round trip,
// damage and mix-ups refused by name). The CLI's plumbing is in cli_test.cpp (PlanCli).
// Units: SI, spindle speeds in rpm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <initializer_list>
#include <set>
#include <string>
#include <unistd.h>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/plan_io.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "support/expected_fields.hpp"
#include "support/field_values.hpp"

using namespace toolpoint;

namespace {

namespace fs = std::filesystem;

const std::string kExample = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml";

// A small valid study on the example; `replace` swaps one line for another (or adds one after
// `after` when `with` is prefixed by "+").
std::string study(const std::string& find = "", const std::string& with = "") {
  std::string s =
      "[study]\n"          // 1
      "name = \"test\"\n"  // 2
      "[[candidate]]\n"    // 3
      "name = \"a\"\n"     // 4
      "assembly = \"" +
      kExample +
      "\"\n"                            // 5
      "overhang_min = 0.050\n"          // 6
      "overhang_max = 0.060\n"          // 7
      "overhang_step = 0.005\n"         // 8
      "[cut]\n"                         // 9
      "teeth = 4\n"                     // 10
      "tangential_coefficient = 6e8\n"  // 11
      "radial_ratio = 0.3\n"            // 12
      "radial_immersion = 0.5\n"        // 13
      "milling = \"down\"\n"            // 14
      "feed_per_tooth = 1e-4\n"         // 15
      "[machine]\n"                     // 16
      "speed_min = 5000\n"              // 17
      "speed_max = 15000\n"             // 18
      "speed_points = 100\n"            // 19
      "[safety]\n"                      // 20
      "factor = 1.25\n";                // 21
  if (!find.empty()) {
    const std::size_t at = s.find(find);
    EXPECT_NE(at, std::string::npos) << find;
    if (at != std::string::npos) s.replace(at, find.size(), with);
  }
  return s;
}

// parse_plan_study must throw E whose message holds every item of `mentions` and which has a hint.
template <class E>
void expect_refused(const std::string& text, std::initializer_list<std::string> mentions) {
  try {
    parse_plan_study(text, "study.toml", "");
    ADD_FAILURE() << "accepted; expected an error naming " << *mentions.begin();
  } catch (const E& e) {
    const std::string said = std::string(e.what()) + "\n  fix: " + e.hint();
    for (const auto& m : mentions) EXPECT_NE(said.find(m), std::string::npos) << "'" << m << "' not in: " << said;
    EXPECT_FALSE(e.hint().empty()) << e.what();
  }
}

}  // namespace

TEST(PlanStudyFile, ReadsTheStudy) {
  const PlanStudy s = parse_plan_study(study(), "study.toml", "");
  EXPECT_EQ(s.name, "test");
  ASSERT_EQ(s.candidates.size(), 1u);
  ASSERT_EQ(s.candidates[0].overhangs_m.size(), 3u);
  EXPECT_DOUBLE_EQ(s.candidates[0].overhangs_m[2], 0.060);
  EXPECT_EQ(s.options.lobes.cutting.teeth, 4);
  EXPECT_EQ(s.options.lobes.speeds.points, 100);
  EXPECT_EQ(s.options.safety.kind, SafetyRule::Kind::Factor);
  EXPECT_EQ(s.options.safety.factor, 1.25);
  EXPECT_EQ(s.inputs.size(), 2u);  // the study and the assembly
  // The example study shipped in examples/ reads without warnings.
  const PlanStudy e = load_plan_study(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/plan_bt40.toml");
  EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
  EXPECT_EQ(e.options.machine.power_w, 15e3);
  EXPECT_EQ(e.candidates[0].overhangs_m.size(), 81u);
}

// Every kind of mistake: the file and line, the key, what was expected, a fix.
TEST(PlanStudyFile, MistakesAreNamedWithFileLineAndKey) {
  expect_refused<InputError>(study("teeth = 4", "teth = 4"), {"study.toml:10", "unknown key 'cut.teth'", "did you mean 'teeth'"});
  expect_refused<InputError>(study("[machine]", "[machin]"), {"study.toml", "unknown key 'machin'", "did you mean 'machine'"});
  expect_refused<InputError>(study("overhang_min = 0.050\noverhang_max = 0.060\noverhang_step = 0.005",
                                   "overhang_min = 50\noverhang_max = 60\noverhang_step = 5"),
                             {"study.toml:6", "candidate[1].overhang_min = 50", "cannot be meant", "metres"});
  // Counted before they are made (overhang_sweep_size): a million overhangs are refused, not built.
  expect_refused<InputError>(study("overhang_step = 0.005", "overhang_step = 0.00000001"),
                             {"study.toml:8", "gives 1000001 overhangs; at most 100000", "larger step"});
  expect_refused<InputError>(study("overhang_step = 0.005", "overhang_step = 0.0000000001"),
                             {"study.toml:8", "overhang_step", "below a nanometre"});
  expect_refused<InputError>(study("feed_per_tooth = 1e-4", "feed_per_tooth = 0.1"),
                             {"study.toml:15", "cut.feed_per_tooth", "millimetres?"});
  expect_refused<InputError>(study("factor = 1.25", "probability = 95"),
                             {"study.toml:21", "safety.probability = 95", "[0.5, 1)"});
  expect_refused<InputError>(study("factor = 1.25", "factor = 1.25\nprobability = 0.9"), {"study.toml:22", "choose one"});
  expect_refused<InputError>(study("factor = 1.25", "probability = 0.9"), {"study.toml:3", "candidate[1]", "[uncertainty]"});
  expect_refused<InputError>(study("speed_max = 15000", "speed_max = 1500"), {"study.toml:18", "must exceed machine.speed_min"});
  // 15 kW written as 15 (W expected): no spindle cuts with 15 W, so it is refused at its line.
  expect_refused<InputError>(study("speed_points = 100\n", "speed_points = 100\npower = 15\n"),
                             {"study.toml:20", "machine.power = 15", "cannot be meant", "15 kW = 15e3"});
  expect_refused<InputError>(study("teeth = 4", "teeth = 4.5"), {"study.toml:10", "cut.teeth", "integer"});
  expect_refused<InputError>(study("tangential_coefficient = 6e8", "tangential_coefficient = \"6e8\""),
                             {"study.toml:11", "must be a number"});
  expect_refused<InputError>(study("milling = \"down\"", "milling = \"climb\""), {"study.toml:14", "\"up\" or \"down\""});
  expect_refused<InputError>(study("radial_immersion = 0.5", "radial_immersion = 50"), {"study.toml:13", "(0, 1]"});
  expect_refused<InputError>(study("[machine]\n", "[machine]\nmin_overhang = 0.07\n"),
                             {"study.toml", "shorter than", "min_overhang"});
  expect_refused<InputError>(study("[cut]\n", "[[candidate]]\nname = \"a\"\nassembly = \"" + kExample + "\"\n[cut]\n"),
                             {"both named 'a'"});
  expect_refused<InputError>(study("speed_points = 100\n", "speed_points = 100\n[[bad\n"),
                             {"study.toml:20", "TOML syntax error"});
  EXPECT_EQ(parse_plan_study(study("[safety]\nfactor = 1.25\n", ""), "study.toml", "").options.safety.factor,
            1.0);  // the default
}

TEST(PlanStudyFile, FilesItNamesAreReadWithTheirOwnErrors) {
  // A missing assembly: the study's line and key, and the path.
  expect_refused<IoError>(study(kExample, "/nonexistent/a.toml"),
                          {"study.toml:5", "candidate[1].assembly", "/nonexistent/a.toml"});
  // A broken assembly: its own file and line.
  const fs::path dir = fs::temp_directory_path() / ("toolpoint_plan_file_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string bad = read_text_file(kExample);
  bad.replace(bad.find("density = 7800.0"), 16, "densty = 7800.0");
  write_text_file((dir / "bad.toml").string(), bad);
  expect_refused<InputError>(study(kExample, (dir / "bad.toml").string()), {"bad.toml:", "densty"});
  // Relative paths are the study file's folder's.
  write_text_file((dir / "study.toml").string(), study(kExample, "bad.toml"));
  EXPECT_THROW(load_plan_study((dir / "study.toml").string()), InputError);
  fs::remove_all(dir);
  // A value in another unit that cannot be meant (K_t in MPa) is refused at its line; one that is
  // merely unusual (2e7 N/m^2) is a warning naming the key and line.
  expect_refused<InputError>(study("tangential_coefficient = 6e8", "tangential_coefficient = 600"),
                             {"study.toml:11: cut.tangential_coefficient = 600", "cannot be meant", "N/m^2"});
  const PlanStudy s = parse_plan_study(study("tangential_coefficient = 6e8", "tangential_coefficient = 2e7"), "study.toml", "");
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.front().find("study.toml:11: cut.tangential_coefficient = 2e+07"), std::string::npos)
      << s.warnings.front();
}

// The measured-holder route and identified joints through the study file: `sh11` (a block CSV) and
// `joints` (joint files; the one with [uncertainty] is what safety.probability samples).
TEST(PlanStudyFile, MeasuredHolderAndJointFiles) {
  const fs::path dir = fs::temp_directory_path() / ("toolpoint_plan_route_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Assembly a = load_assembly(kExample).assembly;
  PredictOptions holder;
  holder.receptance = PredictedFrf::HolderTip;
  write_frf_csv((dir / "sh11.csv").string(), run_prediction_study(a, holder).frf);
  JointFile j;
  j.parameters = a.holder_tool.parameters;
  j.parameters.k_yf *= 1.1;
  JointUncertainty u;
  for (int k = 0; k < 8; ++k) u.covariance(k, k) = std::pow(0.05 * j.parameters[k], 2);
  j.uncertainty = u;
  write_joint_file((dir / "kht.toml").string(), j);
  j.uncertainty.reset();
  j.interface = JointInterface::SpindleHolder;
  j.parameters = a.spindle_holder.parameters;
  write_joint_file((dir / "ksh.toml").string(), j);
  const std::string text = study("[cut]\n", "sh11 = \"sh11.csv\"\njoints = [\"kht.toml\", \"ksh.toml\"]\n[cut]\n");
  // With a probability rule: the SH11, both joints in place, the uncertain one sampled.
  std::string prob = text;
  prob.replace(prob.find("factor = 1.25"), 13, "probability = 0.9\nsamples = 20");
  const PlanStudy p = parse_plan_study(prob, (dir / "study.toml").string(), dir.string());
  ASSERT_EQ(p.candidates.size(), 1u);
  const PlanCandidate& c = p.candidates[0];
  ASSERT_TRUE(c.sh11.has_value());
  EXPECT_EQ(c.sh11->size(), a.grid.values().size());
  ASSERT_TRUE(c.uncertain_joint.has_value());
  EXPECT_EQ(c.assembly.holder_tool.parameters.k_yf, 1.1 * a.holder_tool.parameters.k_yf);
  EXPECT_EQ(p.inputs.size(), 5u);  // study, assembly, two joint files, SH11
  EXPECT_EQ(p.options.safety.samples, 20);
  // The measured-holder route runs with the sampled holder–tool joint: the depth used is stable
  // for at least 90 % of the draws wherever stability limits it.
  PlanOptions o = p.options;
  o.lobes.speeds.points = 20;
  const PlanResult r = run_plan(p.candidates, o);
  EXPECT_TRUE(r.header.candidates[0].measured_holder);
  for (const PlanJob& job : r.jobs)
    for (std::size_t k = 0; k < job.depth_m.size(); ++k)
      if (job.limit[k] == DepthLimit::Stability) EXPECT_GE(job.probability[k], 0.9);
  // Two joints with [uncertainty]: only one can be sampled.
  write_joint_file((dir / "ksh.toml").string(), [&] {
    JointFile k = load_joint_file((dir / "ksh.toml").string());
    k.uncertainty = u;
    return k;
  }());
  try {
    parse_plan_study(prob, "study.toml", dir.string());
    ADD_FAILURE() << "two sampled joints accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("only one joint can be sampled"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// Part files: exact round trip; damage, edits and mix-ups refused, naming the part.
TEST(PlanPartFile, RoundTripAndRefusals) {
  PlanStudy s = parse_plan_study(study(), "study.toml", "");
  const PlanPart p0 = run_plan_part(s.candidates, s.options, 0, 2), p1 = run_plan_part(s.candidates, s.options, 1, 2);
  EXPECT_EQ(p0.jobs.size(), 2u);
  EXPECT_EQ(p1.jobs.size(), 1u);
  const std::string t0 = format_plan_part(p0), t1 = format_plan_part(p1);
  EXPECT_EQ(format_plan_part(parse_plan_part(t0, "p0")), t0);
  const auto refused = [](const std::string& text, const std::string& what) {
    try {
      parse_plan_part(text, "p.json");
      ADD_FAILURE() << "accepted; expected " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("p.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused(t0.substr(0, 20), "not a toolpoint plan part file");  // cut before it says which shard it is
  refused("{\"x\": 1}", "not a toolpoint plan part file");
  // One digit of one depth changed: the checksum.
  std::string edited = t0;
  const std::size_t at = edited.find("\"stable_depth_m\":[\"0x1.") + 24;
  edited[at] = edited[at] == '0' ? '1' : '0';
  refused(edited, "checksum");
  // The header edited (the feed): the fingerprint.
  std::string header = t0;
  const std::size_t feed = header.find("\"feed_per_tooth_m\":\"0x1.") + 24;
  header[feed] = header[feed] == '0' ? '1' : '0';
  refused(header, "fingerprint");

  const PlanPart q0 = parse_plan_part(t0, "p0.json"), q1 = parse_plan_part(t1, "p1.json");
  EXPECT_NO_THROW(merge_plan_parts({q1, q0}, {"p1.json", "p0.json"}));
  const auto merge_refused = [](const std::vector<PlanPart>& parts, const std::vector<std::string>& names,
                                const std::string& what) {
    try {
      merge_plan_parts(parts, names);
      ADD_FAILURE() << "merged; expected " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_FALSE(e.hint().empty());
    }
  };
  merge_refused({q0}, {"p0.json"}, "shard(s) 1 of 2 missing");
  merge_refused({q0, q0, q1}, {"p0.json", "again.json", "p1.json"}, "shard 0 of 2 is given 2 times: p0.json and again.json");
  PlanOptions other = s.options;
  other.lobes.speeds.points = 101;
  const PlanPart r1 = run_plan_part(s.candidates, other, 1, 2);
  merge_refused({q0, r1}, {"p0.json", "r1.json"}, "r1.json (shard 1 of 2) belongs to another study");
  const PlanPart w = run_plan_part(s.candidates, s.options, 1, 3);
  merge_refused({q0, w}, {"p0.json", "w.json"}, "w.json is shard 1 of 3, but the other parts split the study into 2");
}

// The batch user's bad input, each refused with the shard and the fix (the shards to run again, the
// parts to leave out), every problem of a set at once: the oracle is the set as built here.
TEST(PlanPartFile, BadSetsNameEveryShardAndTheFix) {
  PlanStudy s = parse_plan_study(study(), "study.toml", "");
  // A shard that does not exist: an index equal to the count is an array numbered from 1.
  const auto shard_refused = [&](int index, int count, const std::string& what) {
    try {
      run_plan_part(s.candidates, s.options, index, count);
      ADD_FAILURE() << index << "/" << count << " accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_FALSE(e.hint().empty());
    }
  };
  shard_refused(3, 3, "an index equal to the count comes from an array numbered from 1");
  shard_refused(4, 3, "shards are numbered 0…2");
  shard_refused(-1, 3, "shards are numbered 0…2");
  shard_refused(0, 0, "shard count 0 must lie in 1…100000");

  const fs::path dir = fs::temp_directory_path() / ("toolpoint_parts_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "parts");
  const auto part = [&](int i) { return (dir / "parts" / ("part-" + std::to_string(i) + ".json")).string(); };
  for (int i = 0; i < 3; ++i) {
    PlanPart p = run_plan_part(s.candidates, s.options, i, 3);
    p.study = "study.toml";
    write_text_file(part(i), format_plan_part(p));
  }
  const std::string whole = format_plan_map_csv(run_plan(s.candidates, s.options));
  EXPECT_EQ(format_plan_map_csv(merge_plan_part_files({part(2), part(0), part(1)})), whole);
  const auto verdict = [&](const std::vector<std::string>& files) {
    try {
      merge_plan_part_files(files);
    } catch (const ShardSetError& e) {
      return e;
    }
    ADD_FAILURE() << "merged";
    return ShardSetError({}, "");
  };
  const auto has = [](const std::string& text, const std::string& what) {
    EXPECT_NE(text.find(what), std::string::npos) << "'" << what << "' not in: " << text;
  };

  // Missing shards: every one named, to be run again into the file named like its siblings.
  ShardSetError e = verdict({part(1)});
  has(e.what(), "shard(s) 0, 2 of 3 missing");
  ASSERT_EQ(e.check().rerun.size(), 2u);
  EXPECT_EQ(e.check().rerun[0].index, 0);
  EXPECT_EQ(e.check().rerun[0].part, part(0));
  EXPECT_EQ(e.check().rerun[1].part, part(2));
  EXPECT_EQ(e.check().study, "study.toml");
  has(e.hint(), "run shard(s) 0, 2 of 3 again (run_plan_part with those indices and count 3)");
  // Only shard 0 missing: said to look like an array numbered from 1.
  has(verdict({part(1), part(2)}).what(), "only shard 0: were the tasks numbered from 1");

  // A part cut short while written or copied (here at every tenth of its length, and one byte short):
  // refused naming its shard, to be run again into the same file; the rest of the set judged too.
  const std::string text = read_text_file(part(1));
  for (std::size_t cut : {text.size() / 10, text.size() / 2, 9 * text.size() / 10, text.size() - 2}) {
    write_text_file((dir / "cut.json").string(), text.substr(0, cut));
    e = verdict({part(0), (dir / "cut.json").string(), part(2)});
    has(e.what(), "cut.json (shard 1 of 3): cut short or damaged");
    ASSERT_EQ(e.check().rerun.size(), 1u) << e.what();
    EXPECT_EQ(e.check().rerun[0].index, 1);
    EXPECT_EQ(e.check().rerun[0].part, (dir / "cut.json").string());
    EXPECT_TRUE(e.check().drop.empty());
  }
  // A cut part whose shard another part holds: left out, nothing to run.
  e = verdict({part(0), (dir / "cut.json").string(), part(1), part(2)});
  EXPECT_TRUE(e.check().rerun.empty()) << e.what();
  EXPECT_EQ(e.check().drop, std::vector<std::string>{(dir / "cut.json").string()});

  // Every problem at once: a second copy, a part of another plan, a missing shard.
  fs::copy_file(part(2), dir / "copy.json");
  PlanOptions other = s.options;
  other.lobes.speeds.points = 101;
  write_text_file((dir / "other.json").string(), format_plan_part(run_plan_part(s.candidates, other, 1, 3)));
  e = verdict({part(0), part(2), (dir / "copy.json").string(), (dir / "other.json").string()});
  has(e.what(), "shard 2 of 3 is given 2 times: " + part(2) + " and " + (dir / "copy.json").string());
  has(e.what(), "other.json (shard 1 of 3) belongs to another study");
  has(e.what(), "shard(s) 1 of 3 missing");
  EXPECT_EQ(e.check().drop, (std::vector<std::string>{(dir / "copy.json").string(), (dir / "other.json").string()}));
  ASSERT_EQ(e.check().rerun.size(), 1u);
  EXPECT_EQ(e.check().rerun[0].part, part(1));
  fs::remove_all(dir);
}

// The tool beyond straight, even teeth in [cut] (issue 27): read into the cutting conditions, the
// diameter each candidate's tool's and the feed the study's (plan_cutting); mistakes named at their
// line and key; the zero-order method refused; the part file keeps them (round trip, and a
// fingerprint of its own).
TEST(PlanStudyFile, ToolGeometryKeys) {
  const auto with = [](const std::string& keys, const std::string& method = "fd") {
    std::string s = study("name = \"test\"\n", "name = \"test\"\nmethod = \"" + method + "\"\n");
    const std::string feed = "feed_per_tooth = 1e-4\n";  // line 16 with the method's line
    s.replace(s.find(feed), feed.size(), feed + keys);
    const std::string points = "speed_points = 100";
    s.replace(s.find(points), points.size(), "speed_points = 12");
    return s;
  };
  const PlanStudy s =
      parse_plan_study(with("pitch = [1.2217304763960306, 1.9198621771937625, 1.2217304763960306, 1.9198621771937625]\n"
                            "helix = 0.5235987755982988\nrunout = [1e-5, 0, -1e-5, 0]\nprocess_damping = 1e5\n"),
                       "study.toml", "");
  const CuttingConditions& c = s.options.lobes.cutting;
  EXPECT_EQ(c.pitch_rad.size(), 4u);
  EXPECT_EQ(c.helix_rad, std::vector<double>{0.5235987755982988});
  EXPECT_EQ(c.runout_m[2], -1e-5);
  EXPECT_EQ(c.process_damping_n_per_m, 1e5);
  const CuttingConditions at = plan_cutting(s.options, 0.016);
  EXPECT_EQ(at.diameter_m, 0.016);
  EXPECT_EQ(at.feed_per_tooth_m, 1e-4);

  expect_refused<InputError>(with("helix = 30\n"), {"study.toml:17", "cut.helix[0]", "must lie in 0…80°", "check the unit"});
  expect_refused<InputError>(with("pitch = [1.5, 1.5, 1.5, 1.5]\n"), {"study.toml:17", "cut.pitch adds up to"});
  expect_refused<InputError>(with("runout = [1e-5]\n"), {"study.toml:17", "cut.runout has 1 offsets for 4 teeth"});
  expect_refused<InputError>(with("process_damping = 2e11\n"), {"study.toml:17", "cut.process_damping", "must lie in 1000…1e+08 N/m"});
  expect_refused<InputError>(with("helix = [0.5, \"x\"]\n"), {"study.toml:17", "cut.helix must be a list of numbers"});
  expect_refused<InputError>(with("helix = 0.5\n", "zoa"), {"study.toml", "zero-order method"});

  // The part file: the same text back, and another fingerprint than the straight tool's.
  const PlanStudy h = parse_plan_study(with("helix = [0.5, 0.6, 0.5, 0.6]\n"), "study.toml", "");
  const PlanStudy plain = parse_plan_study(with(""), "study.toml", "");
  const PlanPart part = run_plan_part(h.candidates, h.options, 0, 3);
  const std::string text = format_plan_part(part);
  const PlanPart back = parse_plan_part(text, "p.json");
  EXPECT_EQ(back.header.options.lobes.cutting.helix_rad, h.options.lobes.cutting.helix_rad);
  EXPECT_EQ(format_plan_part(back), text);
  EXPECT_NE(part.header.fingerprint, run_plan_part(plain.candidates, plain.options, 0, 3).header.fingerprint);
  // The helix reaches the stability: the job's stable depths differ from the straight tool's.
  EXPECT_NE(part.jobs.front().stable_depth_m, run_plan_part(plain.candidates, plain.options, 0, 3).jobs.front().stable_depth_m);
}

// The speed model keys of [lobes], as `lobes --speed-model/--speed-nodes/--extrapolate-bearings`
// (LobesStudyOptions): read into the options, carried through a part file (and into its
// fingerprint: a plan at speed is another study than the default one), mistakes named at their line.
TEST(PlanStudyFile, SpeedModelKeys) {
  const std::string keys = "factor = 1.25\n[lobes]\nspeed_model = \"bearings\"\nspeed_nodes = 9\nextrapolate_bearings = true\n";
  const PlanStudy s = parse_plan_study(study("factor = 1.25\n", keys), "study.toml", "");
  EXPECT_EQ(s.options.lobes.speed_model, SpeedModel::Bearings);
  EXPECT_EQ(s.options.lobes.speed_nodes, 9);
  EXPECT_TRUE(s.options.lobes.extrapolate_bearings);
  const PlanStudy d = parse_plan_study(study(), "study.toml", "");
  EXPECT_EQ(d.options.lobes.speed_model, SpeedModel::Automatic);  // the defaults
  EXPECT_EQ(d.options.lobes.speed_nodes, 0);
  EXPECT_FALSE(d.options.lobes.extrapolate_bearings);
  const PlanHeader h = plan_header(s.candidates, s.options);
  EXPECT_NE(h.fingerprint, plan_header(d.candidates, d.options).fingerprint);
  PlanPart part;
  part.header = h;
  const PlanPart back = parse_plan_part(format_plan_part(part), "p.json");
  EXPECT_EQ(back.header.options.lobes.speed_model, SpeedModel::Bearings);
  EXPECT_EQ(back.header.options.lobes.speed_nodes, 9);
  EXPECT_TRUE(back.header.options.lobes.extrapolate_bearings);
  EXPECT_EQ(back.header.fingerprint, h.fingerprint);

  expect_refused<InputError>(study("factor = 1.25\n", "factor = 1.25\n[lobes]\nspeed_model = \"fast\"\n"),
                             {"study.toml:23", "lobes.speed_model = \"fast\"", "\"spinning\""});
  expect_refused<InputError>(study("factor = 1.25\n", "factor = 1.25\n[lobes]\nspeed_nodes = 1\n"),
                             {"study.toml:23", "lobes.speed_nodes = 1", "2…1000"});
  expect_refused<InputError>(study("factor = 1.25\n", "factor = 1.25\n[lobes]\nextrapolate_bearings = 1\n"),
                             {"study.toml:23", "lobes.extrapolate_bearings", "true or false"});
}

// The [lobes] keys derive from lobes_study_fields (option_fields.hpp): every field with a plan key
// is read into the field its table names (compared with the value written, exactly: 17 digits give
// the double back), and a value just outside its range is refused at its line, naming the key and
// the range. Independent of the table: the keys the plan file documents (examples/plan_bt40.toml).
TEST(PlanStudyFile, OptionFieldsAreItsLobesKeys) {
  std::set<std::string> keys;
  std::string table = "factor = 1.25\n[lobes]\n";
  LobesStudyOptions expected;
  for (const auto& f : lobes_study_fields()) {
    const FieldSpec& s = f.spec;
    if (!s.plan_key) continue;
    keys.insert(s.plan_key);
    double v = s.kind == FieldKind::Flag ? 1.0 - f.get(expected) : s.min + (s.max - s.min) / 3.0;
    if (s.kind == FieldKind::Integer) v = std::floor(v);
    table += s.kind == FieldKind::Flag      ? fmt::format("{} = {}\n", s.plan_key, v != 0.0)
             : s.kind == FieldKind::Integer ? fmt::format("{} = {}\n", s.plan_key, static_cast<int>(v))
                                            : fmt::format("{} = {:.17g}\n", s.plan_key, v);
    f.set(expected, v);
    // Out of range: refused at line 23 (the key's, the only one in [lobes]).
    if (s.kind == FieldKind::Flag) continue;
    const double bad = s.kind == FieldKind::Integer ? s.max + 1.0 : s.max_open ? s.max : s.max * 1.5;
    expect_refused<InputError>(study("factor = 1.25\n", fmt::format("factor = 1.25\n[lobes]\n{} = {}\n", s.plan_key, bad)),
                               {"study.toml:23", fmt::format("lobes.{} = {:g}", s.plan_key, bad), field_range_text(s)});
  }
  EXPECT_EQ(keys, (std::set<std::string>{"lobes", "tolerance", "max_modes", "fit_target", "pocket_prominence", "speed_nodes",
                                         "extrapolate_bearings"}));
  const PlanStudy s = parse_plan_study(study("factor = 1.25\n", table), "study.toml", "");
  for (const auto& f : lobes_study_fields()) EXPECT_EQ(f.get(s.options.lobes), f.get(expected)) << f.spec.name;
  EXPECT_EQ(s.options.lobes.fit.max_modes, 7);  // 1 + 19/3, rounded down: read directly
  EXPECT_TRUE(s.options.lobes.extrapolate_bearings);
}

// The [cut], [machine] and [safety] keys of PlanOptions' fields (plan_fields, machine_limits_fields,
// safety_rule_fields) against the expectation written by hand (support/expected_fields.hpp): each
// key's typical value is read into its member (exactly: 17 digits give the double back), and a
// value outside the expected range is refused at the key's line, naming the key and the value.
// probability and samples are read with a candidate whose joint file has [uncertainty], as the
// probability rule needs.
TEST(PlanStudyFile, OptionFieldsAreItsCutMachineAndSafetyKeys) {
  const fs::path dir = fs::temp_directory_path() / ("toolpoint_plan_keys_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Assembly a = load_assembly(kExample).assembly;
  JointFile j;
  j.parameters = a.holder_tool.parameters;
  JointUncertainty u;
  for (int k = 0; k < 8; ++k) u.covariance(k, k) = std::pow(0.05 * j.parameters[k], 2);
  j.uncertainty = u;
  write_joint_file((dir / "kht.toml").string(), j);
  const std::string with_joint = study("[cut]\n", "joints = [\"kht.toml\"]\n[cut]\n");
  // `key = value` in [section]: the line replaced where the study has it, else added below the header.
  const auto with_key = [](std::string text, const std::string& key, const std::string& value) {
    const std::string section = "[" + key.substr(0, key.find('.')) + "]\n";
    const std::string line = key.substr(key.find('.') + 1) + " = ";
    const std::size_t at = text.find("\n" + line, text.find(section));
    if (at != std::string::npos) text.replace(at + 1, text.find('\n', at + 1) - at - 1, line + value);
    else text.insert(text.find(section) + section.size(), line + value + "\n");
    return text;
  };
  for (const auto& e : toolpoint::testing::plan_expected_fields()) {
    SCOPED_TRACE(e.plan_key);
    const bool sampled = e.plan_key == "safety.probability" || e.plan_key == "safety.samples";
    std::string base = study();
    if (sampled) {
      base = with_joint;
      base.replace(base.find("factor = 1.25"), 13, "probability = 0.9");
    }
    const std::string text = with_key(base, e.plan_key, fmt::format("{:.17g}", e.typical));
    const PlanStudy s = parse_plan_study(text, (dir / "study.toml").string(), dir.string());
    EXPECT_EQ(e.get(s.options), e.typical);
    // Just outside: the next integer, or 0.1 % of the range's scale past the edge.
    const double bad = e.integer             ? e.hi + 1.0
                       : std::isfinite(e.hi) ? (e.hi_open ? e.hi : e.hi * 1.001)
                                             : (e.lo_open ? e.lo : e.lo - 1e-3);
    const std::string refused = with_key(base, e.plan_key, fmt::format("{:.17g}", bad));
    const std::size_t at = refused.find("\n" + e.plan_key.substr(e.plan_key.find('.') + 1) + " = ",
                                        refused.find("[" + e.plan_key.substr(0, e.plan_key.find('.')) + "]"));
    const std::size_t line = static_cast<std::size_t>(std::count(refused.begin(), refused.begin() + at + 1, '\n')) + 1;
    expect_refused<InputError>(refused, {fmt::format("study.toml:{}", line), fmt::format("{} = {:g}", e.plan_key, bad)});
  }
  fs::remove_all(dir);
}

// A plan part file carries every field of the plan's option tables (option_fields.hpp: the lobes,
// their modal fit, the cut, the machine, the safety rule), and each moves the plan's fingerprint: each field in
// turn set to another valid value, written and read back exactly, with a fingerprint unlike the
// defaults'. A field left out of the part file or the fingerprint fails here by name.
TEST(PlanStudyFile, PartFileCarriesEveryTableField) {
  const PlanStudy s = parse_plan_study(study(), "study.toml", "");
  const std::uint64_t plain = plan_header(s.candidates, s.options).fingerprint;
  auto each = [&](const auto& fields, auto member) {
    for (const auto& f : fields) {
      PlanOptions o = s.options;
      const double v = test::other_valid_value(f.spec, f.get(member(o)));
      ASSERT_FALSE(std::isnan(v)) << f.spec.name;
      f.set(member(o), v);
      PlanPart part;
      part.header = plan_header(s.candidates, o);
      EXPECT_NE(part.header.fingerprint, plain) << f.spec.name;
      const PlanPart back = parse_plan_part(format_plan_part(part), "p.json");
      EXPECT_EQ(f.get(member(back.header.options)), v) << f.spec.name;
      EXPECT_EQ(back.header.fingerprint, part.header.fingerprint) << f.spec.name;
    }
  };
  each(lobes_study_fields(), [](auto& o) -> auto& { return o.lobes; });
  each(modal_fit_fields(), [](auto& o) -> auto& { return o.lobes.fit; });
  each(plan_fields(), [](auto& o) -> auto& { return o; });
  each(machine_limits_fields(), [](auto& o) -> auto& { return o.machine; });
  each(safety_rule_fields(), [](auto& o) -> auto& { return o.safety; });
}
