// The joint a result is computed with, and what is said of it. A study given a joint file to sample
// uses the file's joint for its nominal result too (before, the prediction, the coupled FRF, the
// lobes and the plan used the assembly's joint for the nominal and the file's for the samples: 11.36
// against 5.93 mm in one case); a joint file whose identification was judged doubtful or fail says
// so in every result computed with it; and the notes on a joint's definiteness describe the joint
// in use, not the one it replaced. Oracles: the same study run on the assembly with the file's
// joint put in by hand (with_joint), without sampling — bit for bit, the same code on the same
// numbers — and the uncertainty's own nominal (envelope_uncertainty, tool_point_band: computed with
// the file's joint by construction).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <nlohmann/json.hpp>

#include "support/joint_data.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/predict.hpp"

using namespace toolpoint;

namespace {

const std::string kExample = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml";

// A joint file other than the example's Table 1 joint: k_yf and k_θm halved (a clearly different
// tool point), with a 2 % covariance, as identify writes it.
JointFile other_joint(const std::string& verdict = "pass") {
  JointFile f = test::uncertain_joint(0.02);
  f.parameters.k_yf *= 0.5;
  f.parameters.k_tm *= 0.5;
  f.uncertainty->covariance = test::covariance_of(f.parameters, 0.02);
  f.identification = {{"method", "band fit"}, {"verdict", verdict}};
  f.source = "kht.toml";
  return f;
}

// The example on a coarse grid (5 Hz), quick enough for a study with samples.
Assembly coarse_example() {
  Assembly a = test::example_assembly();
  a.grid = FrequencyGrid{200.0, 5000.0, 5.0};
  return a;
}

bool any_contains(const std::vector<std::string>& messages, const std::string& part) {
  return std::any_of(messages.begin(), messages.end(), [&](const std::string& m) { return m.find(part) != std::string::npos; });
}

LobesStudyOptions cutting_options() {
  LobesStudyOptions o;
  o.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.speeds = {5000.0, 20000.0, 150};
  o.uncertainty.samples = 10;
  o.uncertainty.seed = 3;
  return o;
}

}  // namespace

TEST(JointInUse, ASampledJointFileIsTheNominalOfThePrediction) {
  const Assembly a = coarse_example();  // Table 1
  const JointFile j = other_joint();
  PredictOptions o;
  o.uncertain_joint = j;
  o.band.samples = 10;
  const Prediction p = run_prediction_study(a, o);
  const Prediction by_hand = run_prediction_study(with_joint(a, j));
  ASSERT_EQ(p.frf.size(), by_hand.frf.size());
  for (std::size_t i = 0; i < p.frf.size(); ++i) ASSERT_EQ(p.frf.blocks[i], by_hand.frf.blocks[i]) << i;
  ASSERT_EQ(p.modes.size(), by_hand.modes.size());
  for (std::size_t m = 0; m < p.modes.size(); ++m) EXPECT_EQ(p.modes[m].frequency_hz, by_hand.modes[m].frequency_hz);
  ASSERT_TRUE(p.band);
  for (std::size_t i = 0; i < p.frf.size(); ++i) ASSERT_EQ(p.band->nominal.values[i], H_of(p.frf.blocks[i])) << i;
  // The assembly's own joint gives another FRF: the test can tell the two apart.
  EXPECT_NE(H_of(run_prediction_study(a).frf.blocks[500]), H_of(p.frf.blocks[500]));
}

TEST(JointInUse, ASampledJointFileIsTheNominalOfTheCoupledFrf) {
  const Assembly a = coarse_example();
  const JointFile j = other_joint();
  const BlockSeries sh11 = AssemblyModel(a).holder_tip(a.grid.values());
  OverhangStudyOptions o;
  o.overhangs_m = {0.049};
  o.uncertain_joint = j;
  o.band.samples = 10;
  const OverhangStudy s = run_overhang_study(a, sh11, o);
  OverhangStudyOptions plain;
  plain.overhangs_m = {0.049};
  const OverhangStudy by_hand = run_overhang_study(with_joint(a, j), sh11, plain);
  ASSERT_EQ(s.overhangs.size(), 1u);
  for (std::size_t i = 0; i < sh11.size(); ++i) {
    ASSERT_EQ(s.overhangs[0].sht11.blocks[i], by_hand.overhangs[0].sht11.blocks[i]) << i;
    ASSERT_EQ(s.band->nominal.values[i], H_of(s.overhangs[0].sht11.blocks[i])) << i;
  }
}

// The lobes study's nominal envelope against the uncertainty's nominal (envelope_uncertainty runs
// the file's joint), speed by speed: they were 11.36 and 5.93 mm apart at one speed in the issue.
TEST(JointInUse, ASampledJointFileIsTheNominalOfTheLobes) {
  LobesInput in;
  in.assembly = coarse_example();
  in.uncertain_joint = other_joint();
  const LobesStudyResult r = run_lobes_study(in, cutting_options());
  ASSERT_TRUE(r.uncertainty);
  ASSERT_EQ(r.envelope.size(), r.uncertainty->nominal_depth_m.size());
  for (std::size_t i = 0; i < r.envelope.size(); ++i) ASSERT_EQ(r.envelope[i].depth_m, r.uncertainty->nominal_depth_m[i]) << i;
  LobesInput by_hand;
  by_hand.assembly = with_joint(*in.assembly, *in.uncertain_joint);
  LobesStudyOptions plain = cutting_options();
  const LobesStudyResult h = run_lobes_study(by_hand, plain);
  for (std::size_t i = 0; i < r.envelope.size(); ++i) ASSERT_EQ(r.envelope[i].depth_m, h.envelope[i].depth_m) << i;
}

// The plan's nominal (its stable depths) with the candidate's sampled joint is the plan of the
// assembly with that joint put in by hand.
TEST(JointInUse, ASampledJointFileIsTheNominalOfThePlan) {
  PlanOptions o;
  o.lobes = cutting_options();
  o.lobes.speeds = {5000.0, 15000.0, 60};
  o.feed_per_tooth_m = 1e-4;
  o.safety.kind = SafetyRule::Kind::Probability;
  o.safety.probability = 0.9;
  o.safety.samples = 20;
  PlanCandidate c;
  c.name = "c";
  c.assembly = coarse_example();
  c.uncertain_joint = other_joint();
  c.overhangs_m = {0.049};
  PlanCandidate by_hand = c;
  by_hand.assembly = with_joint(c.assembly, *c.uncertain_joint);
  const PlanResult r = run_plan({c}, o), h = run_plan({by_hand}, o);
  ASSERT_EQ(r.jobs.size(), 1u);
  EXPECT_EQ(r.jobs[0].stable_depth_m, h.jobs[0].stable_depth_m);
  EXPECT_EQ(r.jobs[0].safe_depth_m, h.jobs[0].safe_depth_m);
}

// identify writes a joint judged fail only when told to accept it, and one judged doubtful always:
// either way the file's verdict follows the joint into every result (text and JSON), naming the
// file; a joint judged pass says nothing.
TEST(JointInUse, AJointFileJudgedDoubtfulOrFailSaysSoInEveryResult) {
  const std::string text = format_joint_file(other_joint("doubtful"));
  const JointFile doubtful = parse_joint_file(text, "kht_doubtful.toml");
  const auto w = joint_file_warnings(doubtful);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("kht_doubtful.toml"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("judged 'doubtful'"), std::string::npos) << w[0];
  EXPECT_TRUE(joint_file_warnings(other_joint("pass")).empty());
  EXPECT_NE(joint_file_warnings(other_joint("fail")).at(0).find("written all the same"), std::string::npos);

  const Assembly a = with_joint(coarse_example(), doubtful);
  EXPECT_EQ(a.holder_tool.warnings, w);
  EXPECT_TRUE(any_contains(AssemblyModel(a).warnings(), "judged 'doubtful'"));
  EXPECT_TRUE(any_contains(run_prediction_study(a).warnings, "judged 'doubtful'"));
  LobesInput in;
  in.assembly = a;
  const LobesStudyResult lobes = run_lobes_study(in, cutting_options());
  EXPECT_TRUE(any_contains(lobes.warnings, "judged 'doubtful'"));
  const nlohmann::json j = lobes;
  EXPECT_NE(j["warnings"].dump().find("judged 'doubtful'"), std::string::npos);
  OverhangStudyOptions oo;
  oo.overhangs_m = {0.049};
  EXPECT_TRUE(
      any_contains(run_overhang_study(a, AssemblyModel(a).holder_tip(a.grid.values()), oo).warnings, "judged 'doubtful'"));
  PlanOptions po;
  po.lobes = cutting_options();
  po.lobes.speeds = {5000.0, 15000.0, 40};
  po.feed_per_tooth_m = 1e-4;
  PlanCandidate c;
  c.name = "c";
  c.assembly = a;
  c.overhangs_m = {0.045, 0.049};
  const PlanResult plan = run_plan({c}, po);
  EXPECT_TRUE(any_contains(plan.warnings, "candidate 'c' (every overhang): kht_doubtful.toml: the identification"))
      << (plan.warnings.empty() ? "" : plan.warnings.front());
  // Replaced by a joint without a verdict, the warning goes with the joint it was about.
  EXPECT_TRUE(with_joint(a, test::uncertain_joint(0.0)).warnings().empty());
}

// The example's Table 1 joint is indefinite (two notes name joints.holder_tool). A joint file put in
// its place takes its notes with it: none for a definite joint, and for an indefinite one notes
// naming the file; the spindle–holder joint's are untouched (the example's is definite: none).
TEST(JointInUse, DefinitenessNotesDescribeTheJointInUse) {
  const LoadedAssembly loaded = load_assembly(kExample);
  ASSERT_EQ(loaded.notes.size(), 2u);
  EXPECT_EQ(loaded.source, kExample);
  JointFile definite = other_joint();
  definite.parameters.k_ym = definite.parameters.k_tf = 2.06e5;  // k_yf k_θm − k_ym² > 0
  definite.parameters.c_ym = definite.parameters.c_tf = 2.22;    // c_yf c_θm − c_ym² > 0
  ASSERT_TRUE(joint_warnings(definite.parameters, "x").empty());
  const LoadedAssembly with_definite = with_joint(loaded, definite);
  EXPECT_TRUE(with_definite.notes.empty()) << with_definite.notes.front();
  EXPECT_EQ(with_definite.assembly.holder_tool.parameters.k_ym, 2.06e5);
  JointFile indefinite = other_joint();  // Table 1's off-diagonal terms: still indefinite
  const LoadedAssembly with_indefinite = with_joint(loaded, indefinite);
  ASSERT_EQ(with_indefinite.notes.size(), 2u);
  for (const std::string& n : with_indefinite.notes) {
    EXPECT_EQ(n.rfind("kht.toml (the holder_tool joint in use): ", 0), 0u) << n;
    EXPECT_EQ(n.find("joints.holder_tool"), std::string::npos) << n;
  }
  // A spindle–holder file leaves the holder–tool joint's notes as they were.
  JointFile spindle = definite;
  spindle.interface = JointInterface::SpindleHolder;
  EXPECT_EQ(with_joint(loaded, spindle).notes, loaded.notes);
}
