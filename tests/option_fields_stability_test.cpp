// The option tables of the modal fit and of the studies that fit modes (option_fields.hpp; issue
// 26), against the expectations written by hand in support/expected_fields_stability.hpp (from the
// hand-written checks before the tables): each table holds exactly the expected fields with their
// flag, CLI unit and factor; check() derived from it accepts each closed edge and refuses a value
// one double (or one) past it, naming `Options::field`. The flags through the command line:
// cli_option_fields_stability_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "support/expected_fields_stability.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/pitch.hpp"
#include "toolpoint/studies/lobes.hpp"

using namespace toolpoint;
using namespace toolpoint::testing;

namespace {

// A cut every check accepts: 4 teeth at half immersion (pitch_test.cpp's).
CuttingConditions four_teeth() { return CuttingConditions{4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)}; }

}  // namespace

// ModalFitOptions: the table and check() against the expectation; the band, checked by hand
// beside the table, still refused (F2 ≤ F1) naming ModalFitOptions::band_hz.
TEST(OptionFieldsStability, ModalFitTableAndCheck) {
  const auto expected = modal_fit_expected_fields();
  expect_table(modal_fit_fields(), expected, "ModalFitOptions", &self<ModalFitOptions>);
  expect_edges(expected, ModalFitOptions{});
  ModalFitOptions o;
  o.min_prominence_db = std::nan("");
  EXPECT_THROW(o.check(), InvalidArgument);
  o = {};
  o.band_hz = std::pair{3000.0, 500.0};
  try {
    o.check();
    ADD_FAILURE() << "band 3000:500 accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("ModalFitOptions::band_hz"), std::string::npos) << e.what();
  }
}

// The lobes study's max_modes is ModalFitOptions' field (one range, one flag), with the plan key;
// the pitch and simulation studies' are the lobes study's, without it.
TEST(OptionFieldsStability, FittedModesFieldsAreOneDefinition) {
  const FieldSpec& fit = option_field(modal_fit_fields(), "max_modes").spec;
  const FieldSpec& lobes = option_field(lobes_study_fields(), "max_modes").spec;
  EXPECT_EQ(lobes.min, fit.min);
  EXPECT_EQ(lobes.max, fit.max);
  EXPECT_EQ(field_flag(lobes), field_flag(fit));
  EXPECT_EQ(std::string(lobes.plan_key), "max_modes");
  for (const char* name : {"max_modes", "fit_target"}) {
    const FieldSpec s = fitted_modes_field(name);
    EXPECT_EQ(s.plan_key, nullptr) << name;
    EXPECT_EQ(std::string(s.help), option_field(lobes_study_fields(), name).spec.help) << name;
  }
}

// PitchStudyOptions (no check before the table: an out-of-range fit_target went to the fit
// unjudged) and SimulationStudyOptions: max_modes and fit_target as the lobes study's.
TEST(OptionFieldsStability, PitchAndSimulationStudyTablesAndChecks) {
  const auto pitch = fitted_modes_expected_fields<PitchStudyOptions>("PitchStudyOptions");
  expect_table(pitch_study_fields(), pitch, "PitchStudyOptions", &self<PitchStudyOptions>);
  PitchStudyOptions p;
  p.cutting = four_teeth();
  p.choice.speed_rpm = 5000.0;
  // (max_modes 21 is refused first by the nested ModalFitOptions::check, naming it there.)
  expect_edges(std::vector{pitch[1]}, p);
  PitchStudyOptions many = p;
  many.fit.max_modes = 21;
  EXPECT_THROW(many.check(), InvalidArgument);
  p.choice.speed_rpm = 0.0;
  EXPECT_THROW(p.check(), InvalidArgument);  // the choice's own check comes first

  const auto sim = fitted_modes_expected_fields<SimulationStudyOptions>("SimulationStudyOptions");
  expect_table(simulation_study_fields(), sim, "SimulationStudyOptions", &self<SimulationStudyOptions>);
  SimulationStudyOptions s;
  s.cutter = uniform_cutter(2, 0.02);
  s.force = {6e8, 1.0 / 3.0};
  s.cut = {10000.0, 1e-3, 1e-4, engagement_from_immersion(0.05, MillingDirection::Down)};
  expect_edges(std::vector{sim[1]}, s);
  s.fit.max_modes = 0;
  EXPECT_THROW(s.check(), InvalidArgument);
}

// PitchChoiceOptions::check now derives from pitch_choice_fields (its ranges held to the
// expectation by OptionFields.PitchChoiceTableAndCheckAgreeWithTheExpectation); the limits'
// order, a check between two fields, stays beside the table.
TEST(OptionFieldsStability, PitchChoiceLimitsOrderBesideTheTable) {
  PitchChoiceOptions o;
  o.speed_rpm = 5000.0;
  o.min_pitch_rad = 1.8;
  o.max_pitch_rad = 1.4;
  try {
    o.check();
    ADD_FAILURE() << "min_pitch_rad above max_pitch_rad accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("PitchChoiceOptions::max_pitch_rad"), std::string::npos) << e.what();
  }
  o.max_pitch_rad = 0.0;  // automatic: no order to keep
  EXPECT_NO_THROW(o.check());
}

// CaseStudyOptions and PrecisionOptions: the tables and check() against the expectation; the
// nested options' checks and the precision target (optional, by hand) still refuse.
TEST(OptionFieldsStability, CaseStudyAndPrecisionTablesAndChecks) {
  const auto cases = case_study_expected_fields();
  expect_table(case_study_fields(), cases, "CaseStudyOptions", &self<CaseStudyOptions>);
  expect_edges(cases, CaseStudyOptions{});
  CaseStudyOptions c;
  c.noise_sigma = std::nan("");
  EXPECT_THROW(c.check(), InvalidArgument);
  c = {};
  c.filter.window = 4;  // even: the Savitzky–Golay filter's own check
  EXPECT_THROW(c.check(), InvalidArgument);

  const auto precision = precision_expected_fields();
  expect_table(precision_fields(), precision, "PrecisionOptions", &self<PrecisionOptions>);
  PrecisionOptions p;
  p.tool.spacing_m = 0.015;
  p.holder.spacing_m = 0.02;
  expect_edges(precision, p);
  p.target = 1.0;
  EXPECT_THROW(p.check(), InvalidArgument);
  p.target = 0.01;
  EXPECT_NO_THROW(p.check());
}
