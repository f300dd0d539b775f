// The option tables of SavgolOptions, PeakChangeOptions, RotationalOptions, TapTestFileOptions,
// PeakOptions, NoiseEstimateOptions, ReadoutOptions, VerdictOptions, UffWriteOptions, PlotOptions
// and FrfFigureOptions (option_fields.hpp; issue 26)
// against the expectation written by hand from their old check()s (support/expected_fields_measured.hpp):
// each table holds exactly the expected fields with their kind, flag and CLI unit, and reaches its
// member; check() accepts each closed edge and a typical value and refuses an open edge and the
// next double (or integer) past each edge, naming `Options::field`. The checks kept beside the
// tables (odd windows, order < window, doubt ≤ fail, the optional shear stiffness) are tested here
// too. The CLI's flags: cli_option_fields_measured_test.cpp; Python's:
// python/tests/test_option_fields_measured.py.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "support/expected_fields_measured.hpp"

using namespace toolpoint;
using namespace toolpoint::testing;

namespace {

// check() throws InvalidArgument whose message holds `names`.
template <class O>
void expect_refused(const O& o, const std::string& names) {
  try {
    o.check();
    ADD_FAILURE() << "accepted; expected a refusal naming " << names;
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(OptionFieldsMeasured, SavgolTableAndCheck) {
  const auto expected = savgol_expected_fields();
  expect_table(savgol_fields(), expected, "SavgolOptions", &self<SavgolOptions>);
  expect_edges(expected, SavgolOptions{5, 0});                     // order 0: window 1 (its lower edge) valid too
  expect_refused(SavgolOptions{6, 2}, "SavgolOptions::window 6");  // even
  expect_refused(SavgolOptions{5, 5}, "SavgolOptions::order 5");   // order = window
  EXPECT_NO_THROW((SavgolOptions{5, 4}.check()));                  // order = window − 1
}

TEST(OptionFieldsMeasured, PeakChangeTableAndCheck) {
  const auto expected = peak_change_expected_fields();
  expect_table(peak_change_fields(), expected, "PeakChangeOptions", &self<PeakChangeOptions>);
  expect_edges(expected, PeakChangeOptions{});
  PeakChangeOptions o;
  o.warn_above = std::numeric_limits<double>::infinity();  // the old check refused a level not finite
  expect_refused(o, "PeakChangeOptions::warn_above");
}

TEST(OptionFieldsMeasured, RotationalTableAndCheck) {
  const auto expected = rotational_expected_fields();
  expect_table(rotational_fields(), expected, "RotationalOptions", &self<RotationalOptions>);
  RotationalOptions valid;
  valid.spacing = 0.01;
  expect_edges(expected, valid);
  RotationalOptions o = valid;
  o.spacing = std::numeric_limits<double>::infinity();
  expect_refused(o, "RotationalOptions::spacing");
  o = valid;
  o.shear_stiffness = 0.0;
  expect_refused(o, "RotationalOptions::shear_stiffness");
  o.shear_stiffness = 1e7;
  EXPECT_NO_THROW(o.check());
}

TEST(OptionFieldsMeasured, TapTestFileTableAndCheck) {
  const auto expected = tap_test_file_expected_fields();
  expect_table(tap_test_file_fields(), expected, "TapTestFileOptions", &self<TapTestFileOptions>);
  expect_edges(expected, TapTestFileOptions{});
  TapTestFileOptions o;
  o.nodes = {1, 2};  // order 2 needs three
  expect_refused(o, "TapTestFileOptions::nodes");
  o.order = 1;
  EXPECT_NO_THROW(o.check());
}

TEST(OptionFieldsMeasured, PeakTableAndCheck) {
  const auto expected = peak_expected_fields();
  expect_table(peak_fields(), expected, "PeakOptions", &self<PeakOptions>);
  expect_edges(expected, PeakOptions{});
}

TEST(OptionFieldsMeasured, NoiseEstimateTableAndCheck) {
  const auto expected = noise_estimate_expected_fields();
  expect_table(noise_estimate_fields(), expected, "NoiseEstimateOptions", &self<NoiseEstimateOptions>);
  expect_edges(expected, NoiseEstimateOptions{});
  NoiseEstimateOptions o;
  o.window = 22;  // even
  expect_refused(o, "NoiseEstimateOptions::window");
  o = NoiseEstimateOptions{};
  o.local = SavgolOptions{4, 2};
  expect_refused(o, "NoiseEstimateOptions::local: SavgolOptions::window");
}

TEST(OptionFieldsMeasured, ReadoutTableAndCheck) {
  const auto expected = readout_expected_fields();
  expect_table(readout_fields(), expected, "ReadoutOptions", &self<ReadoutOptions>);
  expect_edges(expected, ReadoutOptions{});
  // An infinite level (never warn) was accepted by the old check and still is; NaN refused.
  for (double ReadoutOptions::*level :
       {&ReadoutOptions::cond_warning, &ReadoutOptions::reciprocity_warning, &ReadoutOptions::gain_warning}) {
    ReadoutOptions o;
    o.*level = std::numeric_limits<double>::infinity();
    EXPECT_NO_THROW(o.check());
    o.*level = std::numeric_limits<double>::quiet_NaN();
    expect_refused(o, "ReadoutOptions::");
  }
}

TEST(OptionFieldsMeasured, VerdictTableAndCheck) {
  const auto expected = verdict_expected_fields();
  expect_table(verdict_fields(), expected, "VerdictOptions", &self<VerdictOptions>);
  VerdictOptions valid;
  valid.residual_fail = 5.0;  // above every residual_doubt value tried
  expect_edges(expected, valid);
  VerdictOptions o;
  o.residual_doubt = 2.0;
  o.residual_fail = 1.9;  // doubt > fail
  expect_refused(o, "VerdictOptions::residual_doubt 2 and VerdictOptions::residual_fail 1.9");
  o.residual_fail = 2.0;  // doubt = fail
  EXPECT_NO_THROW(o.check());
  o.residual_fail = std::numeric_limits<double>::infinity();  // refused by the old check (not finite)
  expect_refused(o, "VerdictOptions::residual_fail");
}

TEST(OptionFieldsMeasured, UffWriteTableAndCheck) {
  const auto expected = uff_write_expected_fields();
  expect_table(uff_write_fields(), expected, "UffWriteOptions", &self<UffWriteOptions>);
  expect_edges(expected, UffWriteOptions{});
}

TEST(OptionFieldsMeasured, PlotTablesAndChecks) {
  const auto plot = plot_expected_fields();
  expect_table(plot::plot_fields(), plot, "PlotOptions", &self<plot::PlotOptions>);
  expect_edges(plot, plot::PlotOptions{});
  plot::PlotOptions o;
  o.timeout_s = std::numeric_limits<double>::infinity();  // refused by the old check (not finite)
  expect_refused(o, "PlotOptions::timeout_s");
  o = plot::PlotOptions{};
  o.gnuplot.clear();
  expect_refused(o, "PlotOptions::gnuplot");
  const auto figure = frf_figure_expected_fields();
  expect_table(plot::frf_figure_fields(), figure, "FrfFigureOptions", &self<plot::FrfFigureOptions>);
  expect_edges(figure, plot::FrfFigureOptions{});
  plot::FrfFigureOptions f;
  f.frequency_range_hz = std::pair{200.0, 100.0};  // decreasing: checked beside the table
  expect_refused(f, "FrfFigureOptions::frequency_range_hz");
}
