// The option tables of ParallelOptions, UncertaintyOptions, ZeroOrderOptions, BoundaryOptions,
// ModalOptions, BeamStudyOptions, PredictOptions and OverhangStudyOptions (option_fields.hpp; issue 26) against the
// expectation written by hand from their old check()s (support/expected_fields_core.hpp): each table
// holds exactly the expected fields with their kind, flag and CLI unit, and reaches its member;
// check() accepts each closed edge and a typical value and refuses an open edge and the next double
// (or integer) past each edge, naming `Options::field`. The checks kept beside the tables (the
// boundary's steps against max_steps and its degree against the scheme, the beam's speed with the
// modal method) and the plausibility every table field with a plausible range now has in check()
// (a length in mm given as m, a spin in rad/s given as rpm, a power in kW given as W, K_t in MPa) are tested
// here too. The flags: cli_option_fields_core_test.cpp; Python: python/tests/test_option_fields_core.py.
#include <gtest/gtest.h>

#include <string>

#include "support/expected_fields_core.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/stability/simulation.hpp"

using namespace toolpoint;
using namespace toolpoint::testing;

namespace {

// check() throws InvalidArgument whose message holds every one of `names`.
template <class O>
void expect_refused(const O& o, std::initializer_list<const char*> names) {
  try {
    o.check();
    ADD_FAILURE() << "accepted; expected a refusal naming " << *names.begin();
  } catch (const InvalidArgument& e) {
    for (const char* name : names) EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

ZeroOrderOptions valid_zero_order() {
  ZeroOrderOptions o;
  o.speeds = {1000.0, 5000.0, 100};
  return o;
}

BoundaryOptions valid_boundary() {
  BoundaryOptions o;
  o.speeds = {1000.0, 5000.0, 10};
  o.max_steps = 20000;  // the steps' edge is max_steps/2
  return o;
}

// With a tool diameter and a feed, so that process damping and the diameter's edges are judged alone.
CuttingConditions valid_cutting() {
  CuttingConditions c{4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  c.diameter_m = 0.02;
  c.feed_per_tooth_m = 1e-4;
  return c;
}

BeamStudyOptions valid_beam() {
  BeamStudyOptions o;
  o.length = 0.1;
  o.outer_diameter = 0.02;
  return o;
}

}  // namespace

TEST(OptionFieldsCore, ParallelTableAndCheck) {
  const auto expected = parallel_expected_fields();
  expect_table(parallel_fields(), expected, "ParallelOptions", &self<ParallelOptions>);
  expect_edges(expected, ParallelOptions{});
}

TEST(OptionFieldsCore, UncertaintyTableAndCheck) {
  const auto expected = uncertainty_expected_fields();
  expect_table(uncertainty_fields(), expected, "UncertaintyOptions", &self<UncertaintyOptions>);
  expect_edges(expected, UncertaintyOptions{});
  UncertaintyOptions o;
  o.levels = {0.5, 0.05};  // not increasing: beside the table
  expect_refused(o, {"UncertaintyOptions::levels"});
}

TEST(OptionFieldsCore, ZeroOrderTableAndCheck) {
  const auto expected = zero_order_expected_fields();
  expect_table(zero_order_fields(), expected, "ZeroOrderOptions", &self<ZeroOrderOptions>);
  expect_edges(expected, valid_zero_order());
}

TEST(OptionFieldsCore, BoundaryTableAndCheck) {
  const auto expected = boundary_expected_fields();
  expect_table(boundary_fields(), expected, "BoundaryOptions", &self<BoundaryOptions>);
  expect_edges(expected, valid_boundary());
  // Beside the table: steps against max_steps, the degree against the scheme.
  BoundaryOptions o = valid_boundary();
  o.max_steps = 100;
  o.steps = 51;
  expect_refused(o, {"BoundaryOptions::steps 51", "max_steps 100"});
  o.steps = 50;
  EXPECT_NO_THROW(o.check());
  o = valid_boundary();
  o.scheme = Discretization::Semi;
  o.degree = 0;
  EXPECT_NO_THROW(o.check());
  o.degree = 2;
  expect_refused(o, {"BoundaryOptions::degree 2"});
}

TEST(OptionFieldsCore, ModalTableAndCheck) {
  const auto expected = modal_expected_fields();
  expect_table(modal_fields(), expected, "ModalOptions", &self<ModalOptions>);
  expect_edges(expected, ModalOptions{});
}

TEST(OptionFieldsCore, BeamStudyTableAndCheck) {
  const auto expected = beam_study_expected_fields();
  expect_table(beam_study_fields(), expected, "BeamStudyOptions", &self<BeamStudyOptions>);
  expect_edges(expected, valid_beam());
  BeamStudyOptions o = valid_beam();
  o.speed_rpm = 20000.0;
  o.method = BeamMethod::Modal;
  expect_refused(o, {"BeamStudyOptions::speed_rpm", "BeamStudyOptions::method"});
  o = valid_beam();
  o.method = BeamMethod::Modal;
  o.modal.modes = 0;  // the nested table, checked with the modal method
  expect_refused(o, {"ModalOptions::modes 0"});
}

TEST(OptionFieldsCore, PredictTableAndCheck) {
  const auto expected = predict_expected_fields();
  expect_table(predict_fields(), expected, "PredictOptions", &self<PredictOptions>);
  expect_edges(expected, PredictOptions{});
}

TEST(OptionFieldsCore, CuttingTableAndCheck) {
  const auto expected = cutting_expected_fields();
  expect_table(cutting_fields(), expected, "CuttingConditions", &self<CuttingConditions>);
  expect_edges(expected, valid_cutting());
  // Beside the table: process damping needs the diameter; 0 means none (the automatic value).
  CuttingConditions c = valid_cutting();
  c.process_damping_n_per_m = 0.0;
  EXPECT_NO_THROW(c.check());
  c.process_damping_n_per_m = 2e5;
  c.diameter_m = 0.0;
  expect_refused(c, {"CuttingConditions::diameter_m", "process damping"});
}

TEST(OptionFieldsCore, SpeedRangeTableAndCheck) {
  const auto expected = speed_range_expected_fields();
  expect_table(speed_range_fields(), expected, "SpeedRange", &self<SpeedRange>);
  expect_edges(expected, SpeedRange{5000.0, 25000.0, 100});
  expect_refused(SpeedRange{15000.0, 5000.0, 100}, {"15000:5000 rpm is empty", "SpeedRange::min_rpm and max_rpm"});
  expect_refused(SpeedRange{5000.0, 5000.0, 100}, {"is empty"});
}

TEST(OptionFieldsCore, NoiseSpecTableAndCheck) {
  const auto expected = noise_spec_expected_fields();
  expect_table(noise_spec_fields(), expected, "NoiseSpec", &self<NoiseSpec>);
  expect_edges(expected, NoiseSpec{});
  // Beside the table: stated noise all zero; a σ in per cent (5) out of range; a tiny σ that
  // cannot be meant as a fraction (1e-6 of a magnitude is no tap test's).
  NoiseSpec n;
  n.source = NoiseSpec::Source::Stated;
  expect_refused(n, {"stated noise is not all zero"});
  n.magnitude_sigma = 5.0;
  expect_refused(n, {"NoiseSpec::magnitude_sigma 5 must lie in 0…0.5"});
  n.magnitude_sigma = 1e-6;
  expect_refused(n, {"NoiseSpec::magnitude_sigma", "cannot be meant"});
  n.magnitude_sigma = 0.02;
  EXPECT_NO_THROW(n.check());
}

TEST(OptionFieldsCore, ForceLawTableAndCheck) {
  const auto expected = force_law_expected_fields();
  expect_table(force_law_fields(), expected, "ForceLaw", &self<ForceLaw>);
  ForceLaw valid;
  valid.tangential_coefficient = 6e8;
  valid.radial_ratio = 0.3;
  expect_edges(expected, valid);
  valid.tangential_coefficient = 600.0;  // MPa
  expect_refused(valid, {"ForceLaw::tangential_coefficient", "cannot be meant"});
}

// The simulation's cutter, cut and depth grid. Depth and speed have no top in range: a depth of
// 3 m or a speed of 3e6 rpm is refused as what cannot be meant, so the edges judged are the lower.
TEST(OptionFieldsCore, SimulationInputTablesAndCheck) {
  expect_table(cutter_fields(), cutter_expected_fields(), "Cutter", &self<Cutter>);
  expect_edges(cutter_expected_fields(), uniform_cutter(4, 0.02));
  MillingCut cut{10000.0, 0.001, 1e-4, engagement_from_immersion(0.5, MillingDirection::Down)};
  expect_table(milling_cut_fields(), milling_cut_expected_fields(), "MillingCut", &self<MillingCut>);
  expect_edges(milling_cut_expected_fields(), cut);
  expect_table(depth_range_fields(), depth_range_expected_fields(), "DepthRange", &self<DepthRange>);
  expect_edges(depth_range_expected_fields(), DepthRange{1e-4, 0.005, 20});
  expect_refused(DepthRange{0.005, 0.001, 20}, {"is empty", "DepthRange::min_m and max_m"});
  Cutter mm = uniform_cutter(4, 16.0);  // 16 mm given as metres
  expect_refused(mm, {"Cutter::diameter_m", "cannot be meant"});
  cut.depth_m = 20.0;  // 20 mm given as metres: no cutting edge is 20 m long
  expect_refused(cut, {"MillingCut::depth_m", "cannot be meant"});
}

TEST(OptionFieldsCore, OverhangStudyTableAndCheck) {
  const auto expected = overhang_study_expected_fields();
  expect_table(overhang_study_fields(), expected, "OverhangStudyOptions", &self<OverhangStudyOptions>);
  expect_edges(expected, OverhangStudyOptions{});
}

// The lobes study's time-domain and zero-order fields are the boundary's and the zero-order
// options' own (one definition): their flags, ranges and notes the same, the steps capped at half
// the default max_steps (4000: 2000, as the lobes study always allowed).
TEST(OptionFieldsCore, LobesStudyTakesTheBoundaryAndZeroOrderFields) {
  const auto same = [](const FieldSpec& a, const FieldSpec& b) {
    SCOPED_TRACE(a.name);
    EXPECT_EQ(field_flag(a), field_flag(b));
    EXPECT_EQ(a.min, b.min);
    EXPECT_STREQ(a.unit, b.unit);
    EXPECT_EQ(a.cli_per_unit, b.cli_per_unit);
  };
  const auto& lobes = lobes_study_fields();
  same(option_field(lobes, "lobes").spec, option_field(zero_order_fields(), "lobes").spec);
  EXPECT_EQ(option_field(lobes, "lobes").spec.max, 5000.0);
  EXPECT_EQ(option_field(lobes, "lobes").spec.automatic, -1.0);
  for (const char* name : {"tolerance", "degree", "max_depth_m", "steps"})
    same(option_field(lobes, name).spec, option_field(boundary_fields(), name).spec);
  EXPECT_EQ(option_field(lobes, "tolerance").spec.max, 0.5);
  EXPECT_EQ(option_field(lobes, "steps").spec.max, 2000.0);
  EXPECT_EQ(option_field(lobes, "steps").spec.automatic, 0.0);
  EXPECT_EQ(option_field(lobes, "degree").spec.max, 3.0);
  LobesStudyOptions o;  // the zero-order method: the steps judged by the lobes table alone
  o.cutting = {2, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.speeds = {5000.0, 15000.0, 100};
  o.steps = 2000;
  EXPECT_NO_THROW(o.check());
  o.steps = 2001;
  expect_refused(o, {"LobesStudyOptions::steps 2001"});
}

// A value in range that cannot be meant in the field's unit is refused by check() (the plan file
// and the flags refused it before; a library or Python caller now meets the same rule), naming the
// field and the likely slip; an unusual one passes (the surfaces warn), and 0 keeps its meaning.
TEST(OptionFieldsCore, CheckRefusesWhatTheUnitCannotMean) {
  BeamStudyOptions beam = valid_beam();
  beam.length = 120.0;  // 120 mm given as metres
  expect_refused(beam, {"BeamStudyOptions::length", "cannot be meant"});
  beam = valid_beam();
  beam.outer_diameter = 16.0;
  expect_refused(beam, {"BeamStudyOptions::outer_diameter", "cannot be meant"});
  beam = valid_beam();
  beam.speed_rpm = 20.0;  // 20 "rpm": below 1000/40 rpm a spin cannot be meant in rpm
  expect_refused(beam, {"BeamStudyOptions::speed_rpm", "rpm"});
  beam.speed_rpm = 500.0;  // unusual (rad/s?) but possible: the surfaces warn
  EXPECT_NO_THROW(beam.check());

  PredictOptions predict;
  predict.speed_rpm = 15.0;
  expect_refused(predict, {"PredictOptions::speed_rpm", "cannot be meant"});
  predict.speed_rpm = 0.0;  // standing
  EXPECT_NO_THROW(predict.check());

  PlanOptions plan;
  plan.lobes.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  plan.lobes.speeds = {5000.0, 15000.0, 100};
  plan.feed_per_tooth_m = 1e-4;
  ASSERT_NO_THROW(plan.check());
  plan.machine.power_w = 15.0;  // 15 kW given as watts: no machining spindle has 15 W
  expect_refused(plan, {"MachineLimits::power_w", "cannot be meant"});
  plan.machine.power_w = 0.0;  // no limit
  EXPECT_NO_THROW(plan.check());
  plan.machine.power_w = 15e3;
  EXPECT_NO_THROW(plan.check());

  // The cut: K_t in MPa (600 for 6e8 N/m²), a diameter in mm (16 for 0.016 m), a feed in mm
  // (0.5 mm given as 0.5 m is over the 1 cm top: the range refuses it); speeds in thousands of rpm.
  CuttingConditions cut = valid_cutting();
  cut.tangential_coefficient = 600.0;
  expect_refused(cut, {"CuttingConditions::tangential_coefficient", "cannot be meant", "N/m^2"});
  cut = valid_cutting();
  cut.diameter_m = 16.0;
  expect_refused(cut, {"CuttingConditions::diameter_m", "cannot be meant", "metres"});
  cut = valid_cutting();
  cut.radial_ratio = 30.0;  // 30 % as 30
  expect_refused(cut, {"CuttingConditions::radial_ratio", "cannot be meant"});
  cut.radial_ratio = 2.0;  // unusual, possible: warned by the surfaces
  EXPECT_NO_THROW(cut.check());
  EXPECT_EQ(field_plausibility_warnings(cutting_fields(), cut, "CuttingConditions").size(), 1u);
  expect_refused(SpeedRange{0.5, 20.0, 100}, {"SpeedRange::min_rpm", "cannot be meant"});
}
