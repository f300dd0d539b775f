// One definition per option field (option_fields.hpp): the tables are consistent (one accessor per
// field, of its kind; names, flags and plan keys unique; the C++ defaults valid), each accessor
// reaches the member it names (checked against the members read directly, not through the table),
// check() refuses a value just outside each range naming `LobesStudyOptions::field`, and the JSON
// echo holds every field. The plan file's keys: plan_file_test.cpp (PlanStudyFile.OptionFields*);
// the CLI's flags: cli_stability_test.cpp (LobesCommand.OptionFieldsAsFlags); Python's keywords:
// python/tests/test_options.py.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>

#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/identify/forward_check.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/pitch.hpp"
#include "toolpoint/studies/plan.hpp"
#include "support/expected_fields.hpp"

using namespace toolpoint;
using toolpoint::testing::ExpectedField;

namespace {

// A valid value of the field other than `current`: a third of the way into its range (an integer
// rounded down), or the flag flipped. Where the range has no upper end: min + 0.001.
double other_valid_value(const FieldSpec& s, double current) {
  if (s.kind == FieldKind::Flag) return current != 0.0 ? 0.0 : 1.0;
  double v = std::isfinite(s.max) ? s.min + (s.max - s.min) / 3.0 : s.min + 0.001;
  if (s.kind == FieldKind::Integer) v = std::floor(v);
  if (v == current) v += s.kind == FieldKind::Integer ? 1.0 : 0.001;
  return v;
}

// A value just outside the range (above it where it has an upper end, else below).
double invalid_value(const FieldSpec& s) {
  if (s.kind == FieldKind::Integer) return s.max + 1.0;
  if (std::isfinite(s.max)) return s.max_open ? s.max : s.max * 1.5;
  return s.min_open ? s.min : s.min - 1.0;
}

// The members, read directly: the independent reference the table's accessors are compared with.
const std::map<std::string, std::function<double(const LobesStudyOptions&)>> kMembers = {
    {"max_depth_m", [](const LobesStudyOptions& o) { return o.max_depth_m; }},
    {"lobes", [](const LobesStudyOptions& o) { return double(o.lobes); }},
    {"tolerance", [](const LobesStudyOptions& o) { return o.tolerance; }},
    {"steps", [](const LobesStudyOptions& o) { return double(o.steps); }},
    {"degree", [](const LobesStudyOptions& o) { return double(o.degree); }},
    {"max_modes", [](const LobesStudyOptions& o) { return double(o.fit.max_modes); }},
    {"fit_target", [](const LobesStudyOptions& o) { return o.fit_target; }},
    {"pocket_prominence", [](const LobesStudyOptions& o) { return o.pocket_prominence; }},
    {"pockets", [](const LobesStudyOptions& o) { return double(o.pockets); }},
    {"speed_nodes", [](const LobesStudyOptions& o) { return double(o.speed_nodes); }},
    {"extrapolate_bearings", [](const LobesStudyOptions& o) { return o.extrapolate_bearings ? 1.0 : 0.0; }},
};

// Options that check() accepts, apart from the fields of the table.
LobesStudyOptions valid_options() {
  LobesStudyOptions o;
  o.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.speeds = {5000.0, 15000.0, 100};
  return o;
}

}  // namespace

TEST(OptionFields, LobesStudyTableIsConsistent) {
  const auto& fields = lobes_study_fields();
  std::set<std::string> names, flags, keys;
  const LobesStudyOptions defaults;
  for (const auto& f : fields) {
    const FieldSpec& s = f.spec;
    SCOPED_TRACE(s.name);
    EXPECT_TRUE(names.insert(s.name).second);
    if (s.cli_name) EXPECT_TRUE(flags.insert(s.cli_name).second);
    if (s.plan_key) EXPECT_TRUE(keys.insert(s.plan_key).second);
    EXPECT_EQ((f.real != nullptr) + (f.integer != nullptr) + (f.flag != nullptr), 1);
    EXPECT_EQ(f.real != nullptr, s.kind == FieldKind::Real);
    EXPECT_EQ(f.integer != nullptr, s.kind == FieldKind::Integer);
    EXPECT_NE(std::string(s.help), "");
    EXPECT_TRUE(field_value_valid(s, f.get(defaults))) << f.get(defaults);  // the C++ default is valid
    EXPECT_TRUE(field_value_valid(s, other_valid_value(s, f.get(defaults))));
    EXPECT_FALSE(s.kind != FieldKind::Flag && field_value_valid(s, invalid_value(s)));
  }
  // Every field has its direct reference, and every reference a field.
  EXPECT_EQ(names.size(), kMembers.size());
  for (const auto& [name, member] : kMembers) EXPECT_TRUE(names.count(name)) << name;
}

// Each field set through the table changes the member it names and no other; the JSON echo gives
// back every value (exactly: a double is echoed as the double).
TEST(OptionFields, AccessorsReachTheirMembersAndTheJsonEchoesThem) {
  for (const auto& f : lobes_study_fields()) {
    SCOPED_TRACE(f.spec.name);
    const LobesStudyOptions before;
    LobesStudyOptions o;
    const double v = other_valid_value(f.spec, f.get(o));
    f.set(o, v);
    for (const auto& [name, member] : kMembers) {
      if (name == f.spec.name) EXPECT_EQ(member(o), v);
      else EXPECT_EQ(member(o), member(before)) << name << " changed too";
    }
    const nlohmann::json j = fields_json(lobes_study_fields(), o);
    EXPECT_EQ(j.size(), kMembers.size());
    for (const auto& [name, member] : kMembers) {
      ASSERT_TRUE(j.contains(name)) << name;
      EXPECT_EQ(j[name].is_boolean() ? (j[name].get<bool>() ? 1.0 : 0.0) : j[name].get<double>(), member(o)) << name;
    }
  }
}

// check() refuses a value just outside each field's range, naming the field and its range; the
// automatic value (lobes −1, speed_nodes 0, steps 0) passes. max_modes is refused by
// ModalFitOptions::check first (the same range), which names its own field.
TEST(OptionFields, CheckRefusesEachFieldOutOfRangeByName) {
  EXPECT_NO_THROW(valid_options().check());
  for (const auto& f : lobes_study_fields()) {
    const FieldSpec& s = f.spec;
    if (s.kind == FieldKind::Flag) continue;
    SCOPED_TRACE(s.name);
    LobesStudyOptions o = valid_options();
    f.set(o, invalid_value(s));
    try {
      o.check();
      ADD_FAILURE() << "accepted " << invalid_value(s);
    } catch (const InvalidArgument& e) {
      const std::string field = std::string(s.name == std::string("max_modes") ? "ModalFitOptions::" : "LobesStudyOptions::") +
                                s.name;
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(field_range_text(s)), std::string::npos) << e.what();
    }
    if (!std::isnan(s.automatic)) {
      f.set(o, s.automatic);
      EXPECT_NO_THROW(o.check());
    }
  }
}

TEST(OptionFields, RangeTextAndValidity) {
  FieldSpec s;
  s.min = 0.0;
  s.max = 1.0;
  EXPECT_EQ(field_range_text(s), "0…1");
  s.max_open = true;
  EXPECT_EQ(field_range_text(s, 100.0), "[0, 100)");
  EXPECT_TRUE(field_value_valid(s, 0.0));
  EXPECT_FALSE(field_value_valid(s, 1.0));
  EXPECT_FALSE(field_value_valid(s, std::nan("")));
  s.min_open = true;
  EXPECT_EQ(field_range_text(s), "(0, 1)");
  EXPECT_FALSE(field_value_valid(s, 0.0));
  s.max = std::numeric_limits<double>::infinity();
  EXPECT_EQ(field_range_text(s), "> 0");
  EXPECT_FALSE(field_value_valid(s, s.max));  // infinity is not a value
  s.kind = FieldKind::Integer;
  s.min_open = false;
  s.automatic = -1.0;
  EXPECT_TRUE(field_value_valid(s, -1.0));
  EXPECT_FALSE(field_value_valid(s, -2.0));
  EXPECT_FALSE(field_value_valid(s, 2.5));  // not a whole number
  EXPECT_TRUE(field_value_valid(s, 3.0));
}

// ---- PlanOptions, MachineLimits, SafetyRule (plan_fields, machine_limits_fields, safety_rule_fields)

namespace {

// 4 teeth, K_t 6e8 N/m², K_r 0.3, half immersion down-milling, 0.1 mm per tooth: what check() accepts.
PlanOptions valid_plan_options() {
  PlanOptions o;
  o.lobes.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.lobes.speeds = {5000.0, 15000.0, 100};
  o.feed_per_tooth_m = 1e-4;
  return o;
}

PlanOptions& whole(PlanOptions& o) { return o; }
MachineLimits& machine_of(PlanOptions& o) { return o.machine; }
SafetyRule& safety_of(PlanOptions& o) { return o.safety; }

}  // namespace

// The three tables hold exactly the fields the hand-written checks judged, with the plan keys the
// plan file read (docs/planning.md), each accessor reaching its member.
TEST(OptionFields, PlanTablesAreTheExpectedFields) {
  const auto expected = toolpoint::testing::plan_expected_fields();
  toolpoint::testing::expect_table(plan_fields(), expected, "PlanOptions", &whole);
  toolpoint::testing::expect_table(machine_limits_fields(), expected, "MachineLimits", &machine_of);
  toolpoint::testing::expect_table(safety_rule_fields(), expected, "SafetyRule", &safety_of);
}

// PlanOptions::check accepts each field at a closed edge of the range the hand-written checks had,
// and refuses it at an open edge and one double (or one) past either, naming `Type::field`.
TEST(OptionFields, PlanCheckJudgesEachEdgeByName) {
  toolpoint::testing::expect_edges(toolpoint::testing::plan_expected_fields(), valid_plan_options());
}

// The plan's JSON echoes every field under its name where it echoed them before the tables
// (options.feed_per_tooth_m, options.machine.power_w, options.safety.factor …), the kind and the
// seed beside them.
TEST(OptionFields, PlanJsonEchoesEachField) {
  PlanResult r;
  PlanOptions& o = r.header.options;
  o = valid_plan_options();
  o.safety.seed = 7;
  const auto expected = toolpoint::testing::plan_expected_fields();
  for (const auto& e : expected) e.set(o, e.typical);
  const nlohmann::json j = nlohmann::json(r).at("options");
  for (const auto& e : expected) {
    const nlohmann::json& at = e.type == "PlanOptions" ? j : j.at(e.type == "MachineLimits" ? "machine" : "safety");
    ASSERT_TRUE(at.contains(e.name)) << e.name;
    EXPECT_EQ(at[e.name].get<double>(), e.typical) << e.name;
  }
  EXPECT_EQ(j.at("safety").at("seed"), 7);
  EXPECT_EQ(j.at("safety").at("kind"), "factor");
  EXPECT_EQ(j.at("machine").size(), 3u);
  EXPECT_EQ(j.at("safety").size(), 5u);  // factor, probability, samples, kind, seed
}

// ---- PitchChoiceOptions (pitch_choice_fields), SimulationOptions (simulation_fields) ---------------

using toolpoint::testing::self;

// The pitch table holds the fields PitchChoiceOptions::check judges (written by hand: the table's
// ranges and the check's are held to one expectation here), with the flags `toolpoint pitch` had.
TEST(OptionFields, PitchChoiceTableAndCheckAgreeWithTheExpectation) {
  const auto expected = toolpoint::testing::pitch_expected_fields();
  toolpoint::testing::expect_table(pitch_choice_fields(), expected, "PitchChoiceOptions", &self<PitchChoiceOptions>);
  PitchChoiceOptions valid;
  valid.speed_rpm = 5000.0;
  toolpoint::testing::expect_edges(expected, valid);
  for (const auto& f : pitch_choice_fields()) {
    if (std::isnan(f.spec.automatic)) continue;
    PitchChoiceOptions o = valid;
    f.set(o, f.spec.automatic);
    EXPECT_NO_THROW(o.check()) << f.spec.name;  // steps 0: automatic
  }
}

// The simulation table: check() derived from it judges each edge as the hand-written check did,
// naming SimulationOptions::field; the automatic values (steps_per_tooth, slices 0) pass; the JSON
// echo holds every field.
TEST(OptionFields, SimulationTableCheckAndJson) {
  const auto expected = toolpoint::testing::simulation_expected_fields();
  toolpoint::testing::expect_table(simulation_fields(), expected, "SimulationOptions", &self<SimulationOptions>);
  toolpoint::testing::expect_edges(expected, SimulationOptions{});
  SimulationOptions o;
  o.steps_per_tooth = 0;
  o.slices = 0;
  EXPECT_NO_THROW(o.check());
  for (const auto& e : expected) e.set(o, e.typical);
  const nlohmann::json j = nlohmann::json(o);
  EXPECT_EQ(j.size(), expected.size());
  for (const auto& e : expected) {
    ASSERT_TRUE(j.contains(e.name)) << e.name;
    EXPECT_EQ(j[e.name].is_boolean() ? double(j[e.name].get<bool>()) : j[e.name].get<double>(), e.typical) << e.name;
  }
}

// ---- JointFitOptions, ForwardCheckOptions, IdentificationOptions -----------------------------------

// Each identification table holds the fields its hand-written check judged, and check() derived
// from it judges each edge as that check did, naming `Type::field`. ForwardCheckOptions: on
// options whose false_alarm (0.04) lets 50 replicates meet the rank test's floor 1/(1 + R) ≤
// false_alarm/2, which stays a check of its own. JointFitOptions: bootstrap_samples is judged only
// for the bootstrap (a linearised fit takes any).
TEST(OptionFields, IdentificationTablesAndChecks) {
  const auto fit = toolpoint::testing::joint_fit_expected_fields();
  toolpoint::testing::expect_table(joint_fit_fields(), fit, "JointFitOptions", &self<JointFitOptions>);
  toolpoint::testing::expect_edges(fit, JointFitOptions{});
  JointFitOptions linearised;
  linearised.uncertainty = UncertaintyMethod::Linearised;
  linearised.bootstrap_samples = 5;
  EXPECT_NO_THROW(linearised.check());

  const auto forward = toolpoint::testing::forward_check_expected_fields();
  toolpoint::testing::expect_table(forward_check_fields(), forward, "ForwardCheckOptions", &self<ForwardCheckOptions>);
  ForwardCheckOptions loose;
  loose.false_alarm = 0.04;
  toolpoint::testing::expect_edges(forward, loose);
  ForwardCheckOptions few;
  few.replicates = 50;  // 1/51 > 0.01/2: too few for the default false alarm
  EXPECT_THROW(few.check(), InvalidArgument);

  const auto id = toolpoint::testing::identification_expected_fields();
  toolpoint::testing::expect_table(identification_fields(), id, "IdentificationOptions", &self<IdentificationOptions>);
  toolpoint::testing::expect_edges(id, IdentificationOptions{});
}
