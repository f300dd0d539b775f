// Tests of the studies layer (include/toolpoint/studies/): the prediction, the overhang study and
// the virtual tap test, in-process, each against something independent of it — peaks found by a
// separate scan and golden-section search on the model, the full model's own SHT11, a
// finite-element model of the example (tests/support/example_fe.hpp), closed forms, and the
// statistics of the seed's noise model. The CLI tests (cli_test.cpp) only check the plumbing.
// Units: SI (m, N; receptance m/N); frequencies in Hz.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "support/example_fe.hpp"
#include "support/fe_beam.hpp"
#include "support/joint_data.hpp"
#include "support/test_util.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

Assembly example(const FrequencyGrid& grid = {10.0, 5000.0, 1.0}) {
  Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  a.grid = grid;
  return a;
}

// The message and hint of the InvalidArgument `run` throws ("" and a failure if it throws nothing
// else).
template <class F>
std::string invalid_argument_message(F&& run) {
  try {
    run();
  } catch (const InvalidArgument& e) {
    return std::string(e.what()) + " fix: " + e.hint();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InvalidArgument: " << e.what();
    return {};
  }
  ADD_FAILURE() << "nothing thrown";
  return {};
}

// The model's SH11 on the assembly's grid, standing in for a measured one.
BlockSeries model_sh11(const Assembly& a) {
  PredictOptions holder;
  holder.receptance = PredictedFrf::HolderTip;
  return run_prediction_study(a, holder).frf;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The nearest of `peaks` to f.
double nearest(const std::vector<double>& peaks, double f) {
  double best = std::numeric_limits<double>::quiet_NaN();
  for (double p : peaks)
    if (!(std::abs(p - f) >= std::abs(best - f))) best = p;
  return best;
}

}  // namespace

// ---- Prediction ---------------------------------------------------------------------------------

// The modes are the maxima of |H| of the model: found here independently by a 1 Hz scan of the
// per-frequency functions and golden-section search (test_util.hpp), to 1e-6 relative in
// frequency (a maximum is flat: both searches stop at ~1e-8 of f where |H| no longer changes in
// double precision) and 1e-9 in height. The example has five modes below 5 kHz (docs/files.md: 916,
// 1600, 2585, 3629, 4554 Hz at the tool point). The block is the model's sweep, bit for bit,
// though computed in blocks of 4096 frequencies for the progress reports.
TEST(PredictStudy, ModesAreTheModelsPeaksFoundIndependently) {
  const Assembly a = example();
  const AssemblyModel model(a);
  for (PredictedFrf which : {PredictedFrf::ToolPoint, PredictedFrf::HolderTip}) {
    const bool tool = which == PredictedFrf::ToolPoint;
    std::vector<double> fractions;
    PredictOptions o;
    o.receptance = which;
    const Prediction p = run_prediction_study(a, o, [&](double x) { fractions.push_back(x); });
    const auto magnitude = [&](double f) { return std::abs((tool ? model.tool_point(f) : model.holder_tip(f))(0, 0)); };
    const std::vector<double> ref = model_peaks(magnitude, 10.0, 5000.0, 1.0);
    ASSERT_EQ(p.modes.size(), ref.size()) << predicted_frf_name(which);
    for (std::size_t k = 0; k < ref.size(); ++k) {
      EXPECT_NEAR(p.modes[k].frequency_hz, ref[k], 1e-6 * ref[k]) << predicted_frf_name(which) << " mode " << k;
      EXPECT_NEAR(p.modes[k].magnitude, magnitude(ref[k]), 1e-9 * magnitude(ref[k])) << k;
    }
    if (tool) {
      ASSERT_EQ(ref.size(), 5u);
      EXPECT_NEAR(p.modes[2].frequency_hz, 2585.0, 1.0);
    }
    const std::vector<double> grid = a.grid.values();
    ASSERT_EQ(grid.size(), 4991u);  // two blocks: 4096 + 895
    EXPECT_EQ(p.frf.frequency_hz, grid);
    EXPECT_EQ(p.frf.blocks, (tool ? model.tool_point(grid) : model.holder_tip(grid)).blocks);
    EXPECT_EQ(fractions, (std::vector<double>{4096.0 / 4991.0, 1.0}));
  }
  EXPECT_TRUE(contains(invalid_argument_message([&] {
                         PredictOptions o;
                         o.peaks.min_prominence = 1.5;
                         run_prediction_study(a, o);
                       }),
                       "PredictOptions::peaks"));
}

// With the joint uncertain, the prediction carries the band tool_point_band gives on its own for
// the same joint, grid and draws (bit for bit), around the prediction's own H (the joint's
// constants in the assembly); the block itself is the one without a band. Progress runs on to 1
// through the samples. The holder tip has no band.
TEST(PredictStudy, TheBandIsToolPointBandOnThePredictionsGrid) {
  const JointFile joint = uncertain_joint(0.02);
  const Assembly a = with_joint(example({2000.0, 3000.0, 5.0}), joint);
  PredictOptions o;
  o.uncertain_joint = joint;
  o.band.samples = 20;
  o.band.seed = 4;
  std::vector<double> fractions;
  const Prediction p = run_prediction_study(a, o, [&](double x) { fractions.push_back(x); });
  ASSERT_TRUE(p.band);
  UncertaintyOptions direct;
  direct.samples = 20;
  direct.seed = 4;
  const FrfBand b = tool_point_band(a, joint, a.grid.values(), direct);
  EXPECT_EQ(p.band->magnitude, b.magnitude);
  EXPECT_EQ(p.band->phase_rad, b.phase_rad);
  EXPECT_EQ(p.band->samples, 20);
  EXPECT_EQ(p.band->nominal.values, entry(p.frf, 0).values);
  EXPECT_EQ(p.frf.blocks, run_prediction_study(a).frf.blocks);
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  EXPECT_LE(fractions.front(), 1.0 / 21.0 + 1e-12);  // the prediction is one of 21 units of work
  EXPECT_TRUE(nlohmann::json(p).contains("band"));
  EXPECT_FALSE(run_prediction_study(a).band);
  o.receptance = PredictedFrf::HolderTip;
  EXPECT_TRUE(contains(invalid_argument_message([&] { run_prediction_study(a, o); }), "PredictOptions::uncertain_joint"));
  o.receptance = PredictedFrf::ToolPoint;
  o.band.samples = 5;
  EXPECT_TRUE(contains(invalid_argument_message([&] { run_prediction_study(a, o); }), "UncertaintyOptions::samples"));
}

// ---- Overhang study -------------------------------------------------------------------------------

// At the assembly file's own overhang, a "measured" SH11 (here the model's) coupled to the
// model's tool (Eq. 5) is the full model's SHT11: both are exact receptance coupling of the same
// beams; 1e-9 relative covers the rounding of the two evaluation orders (the SIMD sweep through
// Eq. 1 and 5, the per-frequency Eq. 5 on the given SH11).
TEST(OverhangStudy, AtTheFilesOverhangItIsThePredictedToolPointFrf) {
  const Assembly a = example({500.0, 3500.0, 2.0});
  const BlockSeries sh = model_sh11(a), sht = run_prediction_study(a).frf;
  const OverhangStudy s = run_overhang_study(a, sh);
  ASSERT_EQ(s.overhangs.size(), 1u);
  EXPECT_EQ(s.overhangs[0].overhang_m, a.tool.overhang);
  EXPECT_NEAR(s.tool_inside_holder_m, 0.074, 1e-15);
  const BlockSeries& got = s.overhangs[0].sht11;
  ASSERT_EQ(got.frequency_hz, sht.frequency_hz);
  for (std::size_t i = 0; i < sht.size(); ++i)
    ASSERT_LE((got.blocks[i] - sht.blocks[i]).norm(), 1e-9 * sht.blocks[i].norm()) << sht.frequency_hz[i];
  EXPECT_TRUE(s.warnings.empty());
}

// Tracked modes against the peaks of a separate full model per overhang (AssemblyModel of the
// assembly with that overhang, scanned and golden-section searched: test_util.hpp). The study
// reads its peaks from the coupled FRF on a 1 Hz grid (a parabola through log|H|), so it is held
// to 2e-5 of the frequency (observed worst 4.5e-6: the parabola's error on a peak tens of Hz
// wide). Every mode of the reference (≥ 3 on 300–4500 Hz) is found at every overhang over
// 35–65 mm, and the tool mode falls as the tool grows (the seed's Fig. 10). Progress is reported
// once per overhang.
TEST(OverhangStudy, TrackedModesAreEachOverhangsModelPeaks) {
  const Assembly a = example({300.0, 4500.0, 1.0});
  const BlockSeries sh = model_sh11(a);
  OverhangStudyOptions o;
  o.overhangs_m = {0.035, 0.040, 0.045, 0.049, 0.055, 0.060, 0.065};
  std::vector<double> fractions;
  const OverhangStudy s = run_overhang_study(a, sh, o, [&](double x) { fractions.push_back(x); });
  ASSERT_EQ(fractions.size(), o.overhangs_m.size());
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_EQ(s.reference, 3u);  // 49 mm, the file's
  ASSERT_GE(s.tracked_modes_hz.size(), 3u);
  double worst = 0.0;
  for (std::size_t i = 0; i < o.overhangs_m.size(); ++i) {
    const AssemblyModel m(with_overhang(a, o.overhangs_m[i]));
    const std::vector<double> ref = model_peaks([&](double f) { return std::abs(m.tool_point(f)(0, 0)); }, 300.0, 4500.0, 1.0);
    for (const auto& mode : s.tracked_modes_hz) {
      ASSERT_FALSE(std::isnan(mode[i])) << "lost at " << o.overhangs_m[i] << ": " << nlohmann::json(s).dump();
      worst = std::max(worst, std::abs(mode[i] - nearest(ref, mode[i])) / mode[i]);
    }
  }
  EXPECT_LT(worst, 2e-5);
  // The tool mode: the one near 2585 Hz at 49 mm.
  const auto& tool_mode = *std::min_element(s.tracked_modes_hz.begin(), s.tracked_modes_hz.end(),
                                            [](const auto& x, const auto& y) {
                                              return std::abs(x[3] - 2585.0) < std::abs(y[3] - 2585.0);
                                            });
  EXPECT_NEAR(tool_mode[3], 2585.0, 5.0);
  for (std::size_t i = 1; i < tool_mode.size(); ++i) EXPECT_LT(tool_mode[i], tool_mode[i - 1]) << o.overhangs_m[i];
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

// Each overhang writes only its own slot (parallel.hpp): 1, 2 and 5 threads give the same bits.
TEST(OverhangStudy, ResultsAreIdenticalForAnyThreadCount) {
  const Assembly a = example({500.0, 3500.0, 5.0});
  const BlockSeries sh = model_sh11(a);
  OverhangStudyOptions o;
  o.overhangs_m = {0.030, 0.036, 0.042, 0.048, 0.054, 0.060};
  o.threads = 1;
  const OverhangStudy one = run_overhang_study(a, sh, o);
  for (int threads : {2, 5}) {
    o.threads = threads;
    const OverhangStudy s = run_overhang_study(a, sh, o);
    ASSERT_EQ(s.overhangs.size(), one.overhangs.size());
    for (std::size_t i = 0; i < s.overhangs.size(); ++i) {
      EXPECT_EQ(s.overhangs[i].sht11.blocks, one.overhangs[i].sht11.blocks) << threads;
      ASSERT_EQ(s.overhangs[i].modes.size(), one.overhangs[i].modes.size());
      for (std::size_t k = 0; k < s.overhangs[i].modes.size(); ++k)
        EXPECT_EQ(s.overhangs[i].modes[k].frequency_hz, one.overhangs[i].modes[k].frequency_hz);
    }
    EXPECT_EQ(nlohmann::json(s).dump(), nlohmann::json(one).dump()) << threads;  // tracked modes, NaN included
  }
}

// A mode that leaves the band is NaN (null in JSON) at that overhang, and the warning names it:
// on 500–3000 Hz the tool mode of a 30 mm overhang (≈ 3008 Hz) is above the band.
TEST(OverhangStudy, ALostModeIsNaNAndWarned) {
  const Assembly a = example({500.0, 3000.0, 2.0});
  OverhangStudyOptions o;
  o.overhangs_m = {0.030, 0.040, 0.049};
  const OverhangStudy s = run_overhang_study(a, model_sh11(a), o);
  ASSERT_EQ(s.reference, 2u);
  std::size_t lost = 0;
  for (const auto& mode : s.tracked_modes_hz)
    if (std::isnan(mode[0])) ++lost;
  EXPECT_EQ(lost, 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_TRUE(contains(s.warnings[0], "30.0 mm")) << s.warnings[0];
  EXPECT_TRUE(contains(nlohmann::json(s).dump(), "null"));
}

// Bad options name the field; with several failing overhangs the first one's error is thrown,
// whatever the thread count; a bad SH11 is an InputError naming it.
TEST(OverhangStudy, BadInputNamesTheField) {
  const Assembly a = example({500.0, 1500.0, 10.0});
  const BlockSeries sh = model_sh11(a);
  const auto message = [&](const OverhangStudyOptions& o) {
    return invalid_argument_message([&] { run_overhang_study(a, sh, o); });
  };
  OverhangStudyOptions o;
  o.overhangs_m = {0.05, 0.04};
  EXPECT_TRUE(contains(message(o), "OverhangStudyOptions::overhangs_m must be strictly increasing"));
  o.overhangs_m = {50.0};
  EXPECT_TRUE(contains(message(o), "millimetres"));
  o.overhangs_m = {-0.05};
  EXPECT_TRUE(contains(message(o), "overhangs_m[0] = -0.05 m must be > 0"));
  o = {};
  o.tracking_tolerance = 1.5;
  EXPECT_TRUE(contains(message(o), "OverhangStudyOptions::tracking_tolerance"));
  o = {};
  o.threads = -1;
  EXPECT_TRUE(contains(message(o), "OverhangStudyOptions::threads"));
  o = {};
  o.peaks.min_prominence = -0.1;
  EXPECT_TRUE(contains(message(o), "OverhangStudyOptions::peaks"));
  // Below the 0.1 mm a tool must stick out (Assembly::check): both fail, the first is reported.
  o = {};
  o.overhangs_m = {2e-5, 5e-5, 0.05};
  for (int threads : {1, 3}) {
    o.threads = threads;
    EXPECT_TRUE(contains(message(o), "OverhangStudyOptions::overhangs_m[0] = 2e-05 m")) << message(o);
  }
  BlockSeries broken = sh;
  broken.blocks[3](0, 0) = Complex(std::nan(""), 0.0);
  o = {};
  o.sh11_name = "sh11.csv";
  try {
    run_overhang_study(a, broken, o);
    ADD_FAILURE() << "NaN in SH11 accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "sh11.csv")) << e.what();
  }
}

// With the holder–tool joint uncertain (one overhang), the study carries the band
// coupled_tool_point_band gives on its own for that overhang, SH11 and draws (bit for bit); a
// sweep has none (refused, naming the field).
TEST(OverhangStudy, TheBandIsCoupledToolPointBandAtTheOverhang) {
  const JointFile joint = uncertain_joint(0.02);
  const Assembly a = with_joint(example({500.0, 3500.0, 5.0}), joint);
  const BlockSeries sh = model_sh11(a);
  OverhangStudyOptions o;
  o.overhangs_m = {0.045};
  o.sh11_name = "sh.csv";
  o.uncertain_joint = joint;
  o.band.samples = 15;
  o.band.seed = 9;
  std::vector<double> fractions;
  const OverhangStudy s = run_overhang_study(a, sh, o, [&](double x) { fractions.push_back(x); });
  ASSERT_TRUE(s.band);
  UncertaintyOptions direct;
  direct.samples = 15;
  direct.seed = 9;
  const FrfBand b = coupled_tool_point_band(with_overhang(a, 0.045), joint, sh, "sh.csv", direct);
  EXPECT_EQ(s.band->magnitude, b.magnitude);
  EXPECT_EQ(s.band->phase_rad, b.phase_rad);
  EXPECT_EQ(s.band->nominal.values, entry(s.overhangs[0].sht11, 0).values);
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_TRUE(nlohmann::json(s).contains("band"));
  o.overhangs_m = {0.045, 0.05};
  EXPECT_TRUE(contains(invalid_argument_message([&] { run_overhang_study(a, sh, o); }), "OverhangStudyOptions::uncertain_joint"));
}

// A sweep's overhangs are the decimal lengths it names: start + i·step to the nanometre, so
// 0.04:0.06:0.002 holds the double 0.052 (0.04 + 6 × 0.002 is 0.052000000000000005), and so does
// the natural-frequency table written from a study on it (its CSV text). The table is the tracked
// modes, column by column; the figure data too.
TEST(OverhangStudy, SweepValuesAreTheDecimalLengthsAndTheTableShowsThem) {
  const std::vector<double> v = overhang_sweep(0.04, 0.06, 0.002);
  ASSERT_EQ(v.size(), 11u);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i], std::stod(fmt::format("0.0{}", 40 + 2 * i))) << i;
  EXPECT_NE(0.04 + 6 * 0.002, 0.052);  // what the rounding removes
  EXPECT_EQ(overhang_sweep(0.05, 0.05, 0.01), std::vector<double>{0.05});
  EXPECT_EQ(overhang_sweep(0.044, 0.054, 0.005), (std::vector<double>{0.044, 0.049, 0.054}));
  EXPECT_THROW(overhang_sweep(0.05, 0.04, 0.001), InvalidArgument);
  EXPECT_THROW(overhang_sweep(0.04, 0.05, 1e-10), InvalidArgument);
  EXPECT_THROW(overhang_sweep(0.0, 0.05, 0.01), InvalidArgument);

  const Assembly a = example({500.0, 3500.0, 5.0});
  OverhangStudyOptions o;
  o.overhangs_m = overhang_sweep(0.048, 0.056, 0.002);
  const OverhangStudy s = run_overhang_study(a, model_sh11(a), o);
  const Table t = natural_frequency_table(s);
  ASSERT_EQ(t.columns.size(), 1 + s.tracked_modes_hz.size());
  EXPECT_EQ(t.columns[0], "overhang_m");
  EXPECT_EQ(t.columns[1], "mode_1_hz");
  ASSERT_EQ(t.rows.size(), 5u);
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    EXPECT_EQ(t.rows[i][0], o.overhangs_m[i]);
    for (std::size_t m = 0; m < s.tracked_modes_hz.size(); ++m) EXPECT_EQ(t.rows[i][m + 1], s.tracked_modes_hz[m][i]);
  }
  const std::string csv = format_table_csv(t);
  EXPECT_TRUE(contains(csv, "\n0.052,")) << csv;
  EXPECT_FALSE(contains(csv, "0.05200000")) << csv;
  const plot::OverhangSweep fig = natural_frequency_sweep(s);
  EXPECT_EQ(fig.overhang_m, o.overhangs_m);
  EXPECT_EQ(nlohmann::json(fig.frequency_hz).dump(), nlohmann::json(s.tracked_modes_hz).dump());
  const std::vector<FrfSeries> h = tool_point_frfs(s);
  ASSERT_EQ(h.size(), 5u);
  EXPECT_EQ(h[2].values, entry(s.overhangs[2].sht11, 0).values);
}

// ---- Virtual tap test -----------------------------------------------------------------------------

// Tool side, 3 points 10 mm apart, roving hammer: nine FRFs, hammer by hammer. Against the
// finite-element model of the example with nodes at the three points (tests/support/example_fe.hpp,
// a different method): every H_ij within 1e-7 of its peak over the band (observed ≤ 7e-9: the FE
// error after Richardson extrapolation on H below 3 kHz; the four entries to 5 kHz, P included,
// need 2e-4 in Assembly.MatchesIndependentFiniteElementModel). H00 is the tool
// point H of the model's point coupling (other algebra: 1e-9 relative, round-off amplified near
// antiresonances, as Assembly.ToolStations), and H_ij = H_ji (Maxwell–Betti) to 1e-9.
TEST(TapTestStudy, ToolStationsMatchTheFiniteElementModel) {
  const Assembly a = example({500.0, 3000.0, 25.0});
  TapTestOptions o;
  o.spacing_m = 0.01;
  std::vector<double> fractions;
  const TapTest t = run_tap_test_study(a, o, [&](double x) { fractions.push_back(x); });
  EXPECT_EQ(fractions.back(), 1.0);
  ASSERT_EQ(t.frfs.size(), 9u);
  EXPECT_EQ(t.distance_m, (std::vector<double>{0.0, 0.01, 0.02}));
  const auto frf = [&](int i, int j) -> const FrfSeries& { return t.frfs[static_cast<std::size_t>(3 * j + i)].frf; };
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(t.frfs[static_cast<std::size_t>(3 * j + i)].response, i);
      EXPECT_EQ(t.frfs[static_cast<std::size_t>(3 * j + i)].hammer, j);
    }
  const AssemblyModel model(a);
  fe_oracle::FeModel fem;
  ExampleFeOptions fo;
  fo.tool_stations_m = t.distance_m;
  const ExampleFe fe = build_example_fe(fem, a, fo);
  fem.set_mesh({1, true});
  double err[3][3] = {}, peak[3][3] = {};
  const std::vector<double> f = a.grid.values();
  for (std::size_t k = 0; k < f.size(); ++k) {
    const Complex h00 = model.tool_point(f[k])(0, 0);
    EXPECT_LT(std::abs(frf(0, 0).values[k] - h00), 1e-9 * std::abs(h00)) << f[k];
    const Eigen::MatrixXcd R = fem.receptance_all(f[k], fe.tool_stations);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Complex got = frf(i, j).values[k], ref = R(2 * i, 2 * j);
        peak[i][j] = std::max(peak[i][j], std::abs(ref));
        err[i][j] = std::max(err[i][j], std::abs(got - ref));
        EXPECT_LT(std::abs(got - frf(j, i).values[k]), 1e-9 * std::abs(got)) << i << j << " at " << f[k];
      }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_LT(err[i][j] / peak[i][j], 1e-7) << "H" << i << j;
}

// Holder side (the spindle–holder subassembly, tool outside removed), 20 mm spacing, hammer at
// the tip only: H_i0 against the FE subassembly (1e-7 of the peak as above; observed 2.6e-9), and
// H00 against the model's SH11.
TEST(TapTestStudy, HolderStationsMatchTheFiniteElementSubassembly) {
  const Assembly a = example({500.0, 3000.0, 25.0});
  TapTestOptions o;
  o.side = TapSide::Holder;
  o.spacing_m = 0.02;
  o.hammer = HammerPlan::Tip;
  const TapTest t = run_tap_test_study(a, o);
  ASSERT_EQ(t.frfs.size(), 3u);
  const AssemblyModel model(a);
  fe_oracle::FeModel fem;
  ExampleFeOptions fo;
  fo.with_tool = false;
  fo.holder_stations_m = t.distance_m;
  const ExampleFe fe = build_example_fe(fem, a, fo);
  fem.set_mesh({1, true});
  double err[3] = {}, peak[3] = {};
  const std::vector<double> f = a.grid.values();
  for (std::size_t k = 0; k < f.size(); ++k) {
    const Complex h00 = model.holder_tip(f[k])(0, 0);
    EXPECT_LT(std::abs(t.frfs[0].frf.values[k] - h00), 1e-9 * std::abs(h00)) << f[k];
    const Eigen::MatrixXcd R = fem.receptance_all(f[k], fe.holder_stations);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(t.frfs[static_cast<std::size_t>(i)].hammer, 0);
      peak[i] = std::max(peak[i], std::abs(R(2 * i, 0)));
      err[i] = std::max(err[i], std::abs(t.frfs[static_cast<std::size_t>(i)].frf.values[k] - R(2 * i, 0)));
    }
  }
  for (int i = 0; i < 3; ++i) EXPECT_LT(err[i] / peak[i], 1e-7) << "H" << i << "0";
}

// The seed's noise: each FRF value times its own real factor 1 + σz, z standard normal, so the
// ratio noisy/exact is real (phase kept, to rounding) with mean 1 and standard deviation σ, and
// the FRFs' factors are independent. With n = 2501 frequencies: the mean within 4σ/√n, the
// standard deviation within 4σ/√(2n) (its own standard error), the correlation of two FRFs'
// factors within 4/√n (seed 11: means 3.4e-4 and 3.0e-4 against 4.0e-3, standard deviations
// 0.0498 and 0.0481 against 0.05 ± 0.0028, correlation 0.031 against 0.08). FRF k draws from seed + k (add_measurement_noise with
// that seed gives the same bits); the same seed repeats, another differs.
TEST(TapTestStudy, NoiseHasTheSeedsStatistics) {
  const Assembly a = example({500.0, 3000.0, 1.0});
  TapTestOptions o;
  o.spacing_m = 0.015;
  o.points = 2;
  o.hammer = HammerPlan::Tip;
  const TapTest exact = run_tap_test_study(a, o);
  o.sigma = 0.05;
  o.seed = 11;
  const TapTest noisy = run_tap_test_study(a, o);
  ASSERT_EQ(noisy.frfs.size(), 2u);
  const double n = static_cast<double>(a.grid.values().size());
  std::vector<std::vector<double>> z(2);
  for (std::size_t k = 0; k < 2; ++k) {
    const FrfSeries& e = exact.frfs[k].frf;
    const FrfSeries& x = noisy.frfs[k].frf;
    double sum = 0.0, sum2 = 0.0;
    for (std::size_t i = 0; i < e.size(); ++i) {
      const Complex r = x.values[i] / e.values[i];
      EXPECT_LT(std::abs(r.imag()), 1e-12) << i;
      z[k].push_back(r.real() - 1.0);
      sum += r.real() - 1.0;
      sum2 += (r.real() - 1.0) * (r.real() - 1.0);
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_LT(std::abs(mean), 4.0 * 0.05 / std::sqrt(n)) << k;
    EXPECT_LT(std::abs(sd - 0.05), 4.0 * 0.05 / std::sqrt(2.0 * n)) << k;
    const auto again = add_measurement_noise(e, NoiseOptions{0.05, 11 + k}, "H");
    EXPECT_EQ(again.series.values, x.values) << k;
  }
  double c = 0.0;
  for (std::size_t i = 0; i < z[0].size(); ++i) c += z[0][i] * z[1][i];
  EXPECT_LT(std::abs(c / (n * 0.05 * 0.05)), 4.0 / std::sqrt(n));
  EXPECT_EQ(run_tap_test_study(a, o).frfs[1].frf.values, noisy.frfs[1].frf.values);
  o.seed = 12;
  EXPECT_NE(run_tap_test_study(a, o).frfs[0].frf.values, noisy.frfs[0].frf.values);
}

// κGA under the points, the closed form: the fluted part is a solid carbide circle of
// 0.8 × 16 mm, Hutchinson's κ = 6(1+ν)²/(7+12ν+4ν²), G = E/(2(1+ν)), A = πd²/4 (1e-12: the same
// arithmetic in another order). Points reaching past the 32 mm fluted part cross into the shank:
// the smaller, fluted κGA is kept and the step is flagged.
TEST(TapTestStudy, ShearStiffnessUnderThePointsIsTheClosedForm) {
  const Assembly a = example({500.0, 1000.0, 50.0});
  const double E = a.tool.material.youngs_modulus, nu = a.tool.material.poisson, d = 0.8 * 0.016;
  const double kga = 6.0 * (1 + nu) * (1 + nu) / (7 + 12 * nu + 4 * nu * nu) * E / (2 * (1 + nu)) * kPi * d * d / 4;
  TapTestOptions o;
  o.spacing_m = 0.01;
  TapTest t = run_tap_test_study(a, o);
  EXPECT_NEAR(t.shear_stiffness_n, kga, 1e-12 * kga);
  EXPECT_FALSE(t.crosses_step);
  o.spacing_m = 0.02;
  t = run_tap_test_study(a, o);
  EXPECT_NEAR(t.shear_stiffness_n, kga, 1e-12 * kga);
  EXPECT_TRUE(t.crosses_step);
}

TEST(TapTestStudy, BadOptionsNameTheField) {
  const Assembly a = example({500.0, 1000.0, 50.0});
  const auto message = [&](const TapTestOptions& o) { return invalid_argument_message([&] { run_tap_test_study(a, o); }); };
  TapTestOptions o;
  EXPECT_TRUE(contains(message(o), "TapTestOptions::spacing_m 0 m must be > 0"));
  o.spacing_m = 0.03;  // the third point 60 mm from the tip of a 49 mm overhang
  EXPECT_TRUE(contains(message(o), "TapTestOptions::spacing_m = 0.03 m puts point 2 0.06 m from the tool tip")) << message(o);
  o.spacing_m = 10.0;  // 10 mm given as metres
  EXPECT_TRUE(contains(message(o), "10 mm is 0.01"));
  o.spacing_m = 0.01;
  o.points = 4;
  EXPECT_TRUE(contains(message(o), "TapTestOptions::points 4 must lie in 2…3"));
  o.points = 3;
  o.sigma = 1.5;
  EXPECT_TRUE(contains(message(o), "TapTestOptions::sigma"));
}

// ---- JSON -----------------------------------------------------------------------------------------

// One spelling per field: the member's name (json.hpp). Keys checked exactly, enums as strings,
// NaN as null, series left out.
TEST(StudiesJson, KeysAreTheMembersNames) {
  const auto keys = [](const nlohmann::json& j) {
    std::set<std::string> k;
    for (auto it = j.begin(); it != j.end(); ++it) k.insert(it.key());
    return k;
  };
  using Keys = std::set<std::string>;
  const nlohmann::json peak = Peak{7, 916.5, 1.5e-6, 0.9};
  EXPECT_EQ(keys(peak), (Keys{"index", "frequency_hz", "magnitude", "prominence"}));
  EXPECT_EQ(peak["frequency_hz"], 916.5);
  // A forward check's errors as the members hold them (fractions), one unit for every forward check.
  EXPECT_EQ(keys(nlohmann::json(ModeComparison{})),
            (Keys{"measured_hz", "predicted_hz", "frequency_error", "measured_peak", "predicted_peak", "magnitude_error"}));
  EXPECT_EQ(nlohmann::json(ModeComparison{1000.0, 1010.0, 0.01, 1.0, 1.0, 0.0})["frequency_error"], 0.01);

  Prediction p;
  p.receptance = PredictedFrf::HolderTip;
  p.modes = {Peak{}};
  const nlohmann::json jp = p;
  EXPECT_EQ(keys(jp), (Keys{"receptance", "modes", "warnings"}));
  EXPECT_EQ(jp["receptance"], "SH11");
  EXPECT_EQ(keys(jp["modes"][0]), keys(peak));

  OverhangStudy s;
  s.overhangs = {OverhangFrf{0.04, {}, {}}};
  s.tracked_modes_hz = {{std::nan("")}};
  const nlohmann::json js = s;
  EXPECT_EQ(keys(js), (Keys{"tool_inside_holder_m", "overhangs", "reference", "tracked_modes_hz", "warnings"}));
  EXPECT_EQ(keys(js["overhangs"][0]), (Keys{"overhang_m", "modes"}));
  EXPECT_EQ(js["tracked_modes_hz"].dump(), "[[null]]");

  TapTest t;
  t.side = TapSide::Holder;
  t.frfs = {TapTestFrf{1, 0, {}}};
  const nlohmann::json jt = t;
  EXPECT_EQ(keys(jt), (Keys{"side", "distance_m", "frfs", "shear_stiffness_n", "crosses_step", "warnings"}));
  EXPECT_EQ(jt["side"], "holder");
  EXPECT_EQ(keys(jt["frfs"][0]), (Keys{"response", "hammer"}));
}
