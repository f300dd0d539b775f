// Tests of the lobes study (studies/lobes.hpp), in process. Oracles: exact modal data (the fit
// must find the modes that made the FRF), the library's lower-level calls run on the true modes
// (an independent path to the same boundary), and the figure's own data.
#include <gtest/gtest.h>

#include <cmath>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "support/joint_data.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/io/uncertainty_io.hpp"

using namespace toolpoint;

namespace {

const Mode kBench{0.03993, 0.011, 922.0};  // docs/reference.md §7
const Mode kSecond{0.2, 0.03, 2100.0};

std::vector<double> grid(double lo, double hi, double step) {
  std::vector<double> f;
  for (int i = 0; lo + i * step <= hi; ++i) f.push_back(lo + i * step);
  return f;
}

LobesStudyOptions options(LobesMethod method, double immersion) {
  LobesStudyOptions o;
  o.method = method;
  o.cutting = {2, 6e8, 1.0 / 3.0, engagement_from_immersion(immersion, MillingDirection::Down)};
  o.speeds = {6000.0, 24000.0, 0};
  return o;
}

}  // namespace

// Exact two-mode data: the fit stops at the two modes that made it (residual ~1e-6, far under the
// 2 % target), recovers them to 1e-4, and the boundary equals stability_boundary on the true modes
// within the two results' error estimates (the fitted modes differ from the true ones by 1e-5).
TEST(LobesStudy, FittedModesAndTheBoundaryFromThem) {
  LobesInput in;
  in.frfs = modal_milling_frfs({kBench, kSecond}, {}, grid(300.0, 3000.0, 0.5));
  in.frf_name = "two.csv";
  LobesStudyOptions o = options(LobesMethod::FullDiscretization, 0.05);
  o.speeds.points = 9;
  const LobesStudyResult r = run_lobes_study(in, o);
  ASSERT_EQ(r.fits.size(), 1u);
  EXPECT_EQ(r.fits[0].what, "two.csv");
  EXPECT_EQ(r.fits[0].modes, 2);
  EXPECT_LT(r.fits[0].residual, 1e-4);
  EXPECT_TRUE(r.fits[0].target_met);
  ASSERT_EQ(r.modes.x.size(), 2u);
  EXPECT_TRUE(r.modes.y.empty());  // rigid in y, as the FRFs say
  EXPECT_NEAR(r.modes.x[0].frequency_hz / kBench.frequency_hz, 1.0, 1e-4);
  EXPECT_NEAR(r.modes.x[1].mass_kg / kSecond.mass_kg, 1.0, 1e-4);
  BoundaryOptions bo;
  bo.speeds = {6000.0, 24000.0, 9};
  const BoundaryResult truth = stability_boundary(ModalModel{{kBench, kSecond}, {}}, o.cutting, bo);
  ASSERT_TRUE(r.boundary);
  for (std::size_t i = 0; i < truth.boundary.size(); ++i) {
    const BoundaryPoint &a = r.boundary->boundary[i], &b = truth.boundary[i];
    ASSERT_EQ(a.kind, b.kind) << i;
    if (a.kind != BoundaryKind::None)
      EXPECT_NEAR(a.depth_m, b.depth_m, a.depth_error_m + b.depth_error_m + 1e-4 * b.depth_m) << a.speed_rpm;
  }
  EXPECT_EQ(r.envelope.size(), 9u);
  EXPECT_FALSE(r.figure.lobes.empty());
  // Each best speed carries the error estimate of the boundary point it is.
  ASSERT_EQ(r.pocket_depth_error_m.size(), r.pockets.size());
  for (std::size_t i = 0; i < r.pockets.size(); ++i)
    for (const BoundaryPoint& b : r.boundary->boundary)
      if (b.speed_rpm == r.pockets[i].speed_rpm && r.pockets[i].lobe >= 0) EXPECT_EQ(r.pocket_depth_error_m[i], b.depth_error_m);
}

// An FRF its resonances alone cannot represent (a large static residual flexibility, 40 % of the
// peak, as an unmodelled stiff mode would add): no modal model meets 2 %, and the warning says so,
// naming the FRF, the residual, the cause (residual terms would carry it) and what to do. A mode
// whose modal constant is complex (the whole FRF turned by 20°, as non-proportional damping does)
// misses the target too, and there the warning says the out-of-band flexibility is not the cause.
TEST(LobesStudy, AFitThatCannotMeetTheTargetSaysWhy) {
  FrfSeries g = modal_frf({kBench}, grid(600.0, 1400.0, 0.5));
  const double peak = 1.0 / (2.0 * kBench.stiffness() * kBench.damping_ratio);
  for (Complex& v : g.values) v += 0.4 * peak;
  ModalFitSummary s;
  std::vector<std::string> warnings;
  const std::vector<Mode> modes = fit_milling_modes(g, "stiff.csv", ModalFitOptions{}, 0.02, s, warnings);
  EXPECT_FALSE(s.target_met);
  EXPECT_GT(s.residual, 0.02);
  EXPECT_EQ(static_cast<int>(modes.size()), s.modes);
  bool said = false;
  for (const std::string& w : warnings)
    said |= w.rfind("stiff.csv: the best modal model", 0) == 0 && w.find("not the 2 %") != std::string::npos &&
            w.find("the rest is the flexibility of modes outside the band") != std::string::npos &&
            w.find("LobesInput::x_modes") != std::string::npos;
  EXPECT_TRUE(said);

  FrfSeries turned = modal_frf({kBench}, grid(600.0, 1400.0, 0.5));
  for (Complex& v : turned.values) v *= std::polar(1.0, 20.0 * M_PI / 180.0);
  warnings.clear();
  fit_milling_modes(turned, "complex.csv", ModalFitOptions{}, 0.02, s, warnings);
  EXPECT_FALSE(s.target_met);
  said = false;
  for (const std::string& w : warnings)
    said |= w.rfind("complex.csv: the best modal model", 0) == 0 &&
            w.find("the flexibility of modes outside the band is not what is missing") != std::string::npos;
  EXPECT_TRUE(said) << (warnings.empty() ? "" : warnings.back());
}

// The zero-order study is zero_order_lobes plus read-outs: the same envelope, pockets from it, and
// a figure whose depth axis covers the pockets it reports.
TEST(LobesStudy, ZeroOrderEnvelopePocketsAndFigureAxis) {
  LobesInput in;
  in.frfs = modal_milling_frfs({kBench}, {kBench}, grid(500.0, 2000.0, 0.25));
  const LobesStudyResult r = run_lobes_study(in, options(LobesMethod::ZeroOrder, 0.05));
  ZeroOrderOptions zo;
  zo.speeds = {6000.0, 24000.0, 2000};
  const ZeroOrderResult z = zero_order_lobes(*in.frfs, options(LobesMethod::ZeroOrder, 0.05).cutting, zo);
  ASSERT_TRUE(r.zero_order);
  ASSERT_EQ(r.envelope.size(), z.envelope.size());
  for (std::size_t i = 0; i < z.envelope.size(); ++i) EXPECT_EQ(r.envelope[i].depth_m, z.envelope[i].depth_m);
  ASSERT_FALSE(r.pockets.empty());
  ASSERT_TRUE(r.figure.depth_max_m);
  const bool clipped = r.figure.title.find("clipped") != std::string::npos;
  for (const EnvelopePoint& p : r.pockets)
    if (!clipped) EXPECT_LE(p.depth_m, *r.figure.depth_max_m);
  // The whole envelope too, or the title says that it is cut (a rise at the range's end is no
  // pocket: process damping's at low speed was cut silently).
  for (const EnvelopePoint& p : r.envelope)
    if (!clipped && std::isfinite(p.depth_m)) EXPECT_LE(p.depth_m, *r.figure.depth_max_m);
}

TEST(LobesStudy, MissingInputsAreRefusedNamingTheField) {
  try {
    run_lobes_study(LobesInput{}, options(LobesMethod::ZeroOrder, 0.5));
    ADD_FAILURE();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("LobesInput::frfs"), std::string::npos) << e.what();
  }
  EXPECT_THROW(run_lobes_study(LobesInput{}, options(LobesMethod::FullDiscretization, 0.5)), InvalidArgument);
  LobesStudyOptions bad = options(LobesMethod::FullDiscretization, 0.5);
  bad.tolerance = 0.0;
  LobesInput modes;
  modes.x_modes = {kBench};
  EXPECT_THROW(run_lobes_study(modes, bad), InvalidArgument);
}

// The joint uncertain: the study's quantiles and probability map are those of the zero-order
// stability_uncertainty (uncertainty.hpp: zero_order_lobes on each sample's FRF, a path that does not
// go through the study) on the grid the study documents (201 depths to 1.5 × the nominal's highest
// point), draw for draw; the nominal is the study's own envelope; the figure gains the quantile
// envelopes and a probability map on the same numbers; progress rises to 1; rigid in y carries to
// every sample; an uncertain joint without its assembly is refused naming the field.
TEST(LobesStudy, TheJointUncertainIsTheZeroOrderUncertaintyOnTheDocumentedGrid) {
  const JointFile joint = toolpoint::test::uncertain_joint(0.05);
  Assembly a = with_joint(toolpoint::test::example_assembly(), joint);
  a.grid = FrequencyGrid{200.0, 5000.0, 2.0};
  LobesInput in;
  in.frfs = milling_frfs(AssemblyModel(a), a.grid.values());
  in.assembly = a;
  in.uncertain_joint = joint;
  LobesStudyOptions o = options(LobesMethod::ZeroOrder, 0.5);
  o.cutting.teeth = 4;
  o.speeds = {5000.0, 20000.0, 120};
  o.uncertainty.samples = 30;
  o.uncertainty.seed = 4;
  std::vector<double> fractions;
  const LobesStudyResult r = run_lobes_study(in, o, [&](double x) { fractions.push_back(x); });
  ASSERT_TRUE(r.uncertainty);
  EXPECT_EQ(r.uncertain_joint, "test");

  double top = 0.0;
  for (const EnvelopePoint& p : r.envelope) top = std::max(top, p.depth_m);
  std::vector<double> depths;
  for (int j = 0; j <= 200; ++j) depths.push_back(1.5 * top * j / 200);
  ZeroOrderOptions zo;
  zo.speeds = o.speeds;
  UncertaintyOptions uo;
  uo.samples = 30;
  uo.seed = 4;
  const StabilityUncertainty direct = stability_uncertainty(a, joint, a.grid.values(), o.cutting, zo, depths, uo);
  EXPECT_EQ(r.uncertainty->depth_grid_m, depths);
  EXPECT_EQ(r.uncertainty->speed_rpm, direct.speed_rpm);
  EXPECT_EQ(r.uncertainty->depth_m, direct.depth_m);
  EXPECT_EQ(r.uncertainty->probability, direct.probability);
  for (std::size_t i = 0; i < r.envelope.size(); ++i) ASSERT_EQ(r.uncertainty->nominal_depth_m[i], r.envelope[i].depth_m) << i;

  const auto quantiles = quantile_envelopes(*r.uncertainty);
  ASSERT_GE(r.figure.other_envelopes.size(), quantiles.size());
  EXPECT_EQ(r.figure.other_envelopes.back().depth_m, r.uncertainty->depth_m.back());
  ASSERT_TRUE(r.probability_figure);
  EXPECT_EQ(r.probability_figure->speed_rpm, r.uncertainty->speed_rpm);
  EXPECT_EQ(r.probability_figure->probability.size(), depths.size() * r.envelope.size());
  EXPECT_EQ(r.probability_figure->probability[5 * r.envelope.size() + 7], r.uncertainty->probability(7, 5));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  // The read-outs: each best speed's quantiles at the nearest of the map's speeds (the same grid
  // here), and the speed where the 5 % quantile (95 % sure) is lowest.
  ASSERT_EQ(r.pocket_quantiles.size(), r.pockets.size());
  for (std::size_t i = 0; i < r.pockets.size(); ++i) {
    const auto k = static_cast<std::size_t>(std::find(direct.speed_rpm.begin(), direct.speed_rpm.end(), r.pockets[i].speed_rpm) -
                                            direct.speed_rpm.begin());
    ASSERT_LT(k, direct.speed_rpm.size());
    EXPECT_EQ(r.pocket_quantiles[i].nominal_depth_m, r.pockets[i].depth_m);
    for (std::size_t l = 0; l < direct.levels.size(); ++l) EXPECT_EQ(r.pocket_quantiles[i].depth_m[l], direct.depth_m[l][k]);
  }
  ASSERT_TRUE(r.worst_speed);
  EXPECT_EQ(r.worst_speed->depth_m[0], *std::min_element(direct.depth_m[0].begin(), direct.depth_m[0].end()));
  const nlohmann::json j = r;
  EXPECT_TRUE(j.contains("uncertainty"));
  EXPECT_EQ(j["uncertain_joint"], "test");

  // The assembly alone: its tool point FRF is the one milling_frfs gives (the same study).
  LobesInput model_only;
  model_only.assembly = a;
  LobesStudyOptions plain = options(LobesMethod::ZeroOrder, 0.5);
  plain.cutting.teeth = 4;
  plain.speeds = o.speeds;
  const LobesStudyResult from_model = run_lobes_study(model_only, plain);
  for (std::size_t i = 0; i < r.envelope.size(); ++i) ASSERT_EQ(from_model.envelope[i].depth_m, r.envelope[i].depth_m) << i;

  // Rigid in y: every sample's FRFs are too. With a covariance of zeros every sample is the
  // nominal joint, so each quantile is the rigid study's envelope (a flexible y would lower it).
  in.frfs = milling_frfs(AssemblyModel(a), a.grid.values(), true);
  in.rigid_y = true;
  in.uncertain_joint = toolpoint::test::uncertain_joint(0.0);
  o.uncertainty.samples = 10;
  const LobesStudyResult rigid = run_lobes_study(in, o);
  for (const auto& q : rigid.uncertainty->depth_m)
    for (std::size_t i = 0; i < rigid.envelope.size(); ++i) ASSERT_EQ(q[i], rigid.envelope[i].depth_m) << i;

  in.assembly.reset();
  try {
    run_lobes_study(in, o);
    FAIL() << "no assembly accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("LobesInput::assembly"), std::string::npos) << e.what();
  }
}
