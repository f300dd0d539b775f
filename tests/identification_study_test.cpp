// Tests of the identification study (studies/identification.hpp): the procedure end to end on
// model data with the seed's noise, its verdict on data that cannot be right, several set-ups, the
// joint file it writes, and the JSON keys scripts rely on.
#include <gtest/gtest.h>

#include "support/joint_data.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/identify/forward_check.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/identification.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

std::vector<double> grid() { return FrequencyGrid{10.0, 5000.0, 5.0}.values(); }

IdentificationData measured(const RouteData& d, double sigma, std::uint64_t seed) {
  const JointFitData x = noisy_fit_data(d, sigma, seed);
  IdentificationData m;
  m.G11 = x.G11;
  m.g_name = "sht11.csv";
  if (d.b_measured) {
    m.B11 = x.B11;
    m.b_name = "sh11.csv";
  }
  return m;
}

IdentificationOptions quick(Route route) {
  IdentificationOptions o;
  o.route = route;
  o.fit.uncertainty = UncertaintyMethod::Linearised;
  return o;
}

bool covers(const ParameterInterval& iv, double truth) { return iv.lower <= truth && truth <= iv.upper; }

}  // namespace

// The holder–tool joint from 2 % noisy SH11 and SHT11 (noise estimated from the data): a pass,
// every stiffness inside its interval, the forward check within 1 % in frequency and 5 % in peak
// height, the seed's read-out beside it at the tool mode (2584.6 Hz in the model), and the JSON
// keys of issue 11's interface.
TEST(IdentificationStudy, HolderToolEndToEnd) {
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, grid());
  const Identification id = run_identification_study(a, {measured(d, 0.02, 3)}, quick(Route::HolderTool));
  EXPECT_EQ(id.verdict.verdict, Verdict::Pass) << (id.verdict.reasons.empty() ? "" : id.verdict.reasons.front());
  ASSERT_TRUE(id.fit);
  for (int k : {0, 2, 6})
    EXPECT_TRUE(covers(id.fit->intervals[static_cast<std::size_t>(k)], d.truth[k])) << JointParameters::name(k);
  EXPECT_NEAR(id.mode.center_hz, 2584.6, 15.0);
  EXPECT_EQ(id.mode.method, "effect analysis on the model");
  EXPECT_GT(id.seed.points, 10u);
  ASSERT_EQ(id.forward_checks.size(), 1u);
  ASSERT_FALSE(id.forward_checks[0].modes.empty());
  for (const auto& c : id.forward_checks[0].modes) {
    if (c.agreement == ModeAgreement::NotResolved) continue;
    EXPECT_EQ(c.agreement, ModeAgreement::Agrees) << c.model_hz;
    EXPECT_LT(std::abs(c.frequency_error), 0.01) << c.measured_hz;
    EXPECT_LT(std::abs(c.magnitude_error), 0.05) << c.measured_hz;
  }
  const nlohmann::json j = id;
  for (int k = 0; k < 8; ++k)
    for (const char* key : {"estimate", "lower", "upper", "unit", "determined"})
      EXPECT_TRUE(j["parameters"][JointParameters::name(k)].contains(key)) << JointParameters::name(k) << " " << key;
  EXPECT_EQ(j["parameters"], j["fit"]["intervals"]);
  EXPECT_EQ(j["parameters"]["k_yf"]["lower"], id.fit->intervals[0].lower);
  EXPECT_TRUE(j["seed"]["parameters"]["k_yf"].contains("median"));
  EXPECT_EQ(j["verdict"]["verdict"], "pass");
  EXPECT_EQ(j["method"], "fit");
  // Relative errors as the member holds them (a fraction), under the member's name.
  EXPECT_EQ(j["forward_checks"][0]["modes"][0]["frequency_error"], id.forward_checks[0].modes[0].frequency_error);

  // The joint file carries the fit's covariance and says how it was identified.
  const JointFile f = parse_joint_file(format_joint_file(joint_file_of(id, {"sh11.csv", "sht11.csv"})), "kht.toml");
  EXPECT_EQ(f.interface, JointInterface::HolderTool);
  ASSERT_TRUE(f.uncertainty);
  EXPECT_EQ(f.uncertainty->covariance, id.fit->covariance);
  EXPECT_EQ(f.parameters.k_yf, id.identified.k_yf);
  bool inputs = false;
  for (const auto& [k, v] : f.identification) inputs |= k == "input_2" && v == "sht11.csv";
  EXPECT_TRUE(inputs);
}

// The seed's procedure alone: the read-out's medians, no interval in the JSON.
TEST(IdentificationStudy, SeedMethod) {
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, grid());
  IdentificationOptions o = quick(Route::HolderTool);
  o.method = IdentificationMethod::Seed;
  o.filter = SavgolOptions{21, 2};
  const Identification id = run_identification_study(a, {measured(d, 0.01, 5)}, o);
  EXPECT_FALSE(id.fit);
  EXPECT_EQ(id.identified.k_yf, id.seed.parameters[0].median);
  const nlohmann::json j = id;
  EXPECT_TRUE(j["parameters"]["k_yf"]["lower"].is_null());
  // "determined" is the read-out's own (ParameterReadout::determined), not a rule applied here.
  for (int k = 0; k < 8; ++k)
    EXPECT_EQ(j["parameters"][JointParameters::name(k)]["determined"], id.seed.parameters[static_cast<std::size_t>(k)].determined)
        << JointParameters::name(k);
  EXPECT_FALSE(joint_file_of(id).uncertainty) << "a read-out has no interval to carry";
}

// Data that cannot identify a joint are judged, not reported as a result: one file given as both
// SH11 and SHT11; the two swapped. Each fails, with a reason a user can act on.
TEST(IdentificationStudy, VerdictFailsWhereTheResultCannotBeRight) {
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, grid());
  const IdentificationData good = measured(d, 0.01, 7);
  IdentificationData same = good;
  same.B11 = good.G11;
  auto reasons = [](const Identification& id) {
    std::string s;
    for (const auto& r : id.verdict.reasons) s += r + "\n";
    return s;
  };
  // Refusing outright (a NumericalError) would do as well as a failed verdict; what may not happen
  // is a pass. Both give a verdict today.
  Identification id = run_identification_study(a, {same}, quick(Route::HolderTool));
  EXPECT_EQ(id.verdict.verdict, Verdict::Fail);
  EXPECT_NE(reasons(id).find("same data"), std::string::npos) << reasons(id);
  IdentificationData swapped = good;
  swapped.G11 = *good.B11;
  swapped.B11 = good.G11;
  id = run_identification_study(a, {swapped}, quick(Route::HolderTool));
  EXPECT_EQ(id.verdict.verdict, Verdict::Fail) << reasons(id);
  std::printf("swapped SH11/SHT11: %s", reasons(id).c_str());
}

// A weak mode under an additive floor (the second assembly's 2.9 kHz mode, its peak 1.6 % of
// SH11's, under a floor of 1 % of that peak) stands about 2.3 noise σ above its valley: the highest
// peak in its window is as often a noise peak as the mode. Two data sets made from the true joint
// (seeds 1000 + 7·99 and 1000 + 7·27 of IdentificationMonteCarlo's (b) row, two of its false
// alarms) "found" it 8–11 % off, at its window's edge — frequency errors 5 and more standard
// deviations of the replicates' — and failed. Under the clearance (ModeCheck::clearance < 5) the
// mode is not judged; the data pass, as data from the true joint should.
TEST(IdentificationStudy, AModeUnderTheNoiseIsNotJudged) {
  const Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/hsk63_hydraulic_12mm.toml").assembly;
  const RouteData d = route_data(a, Route::SpindleHolderFromSH, a.grid.values());
  for (std::uint64_t seed : {1693u, 1189u}) {
    IdentificationData m;
    m.G11 = draw_block_noise(d.G, stated_block_noise(d.G, StatedNoise{0.01, 0.0, 0.01}), seed);
    m.g_name = "sh11.csv";
    const Identification id = run_identification_study(a, {m}, quick(Route::SpindleHolderFromSH));
    ASSERT_EQ(id.forward_checks.size(), 1u);
    const ForwardCheck& fc = id.forward_checks[0];
    const ModeCheck* weak = nullptr;
    for (const ModeCheck& c : fc.modes)
      if (std::abs(c.model_hz - 2908.0) < 20.0) weak = &c;
    ASSERT_NE(weak, nullptr) << seed;
    EXPECT_GT(std::abs(weak->frequency_error - weak->frequency_mean), 3.0 * weak->frequency_sd) << seed;
    EXPECT_GT(weak->clearance, 1.5) << seed;
    EXPECT_LT(weak->clearance, 4.0) << seed;
    EXPECT_EQ(weak->agreement, ModeAgreement::NotResolved) << seed;
    EXPECT_TRUE(std::isnan(weak->frequency_z)) << seed;
    EXPECT_NE(id.verdict.verdict, Verdict::Fail) << seed;
    // The main mode stands far clear and is judged.
    EXPECT_EQ(fc.modes.front().agreement, ModeAgreement::Agrees) << seed;
    EXPECT_GT(fc.modes.front().clearance, 50.0) << seed;
  }
}

// ModeCheck::clearance takes σ from the stated noise through the smoother's weights, the noise
// taken white. Against Monte Carlo: 400 draws of that noise, smoothed as the check smooths (15-point
// cubic), their spread at the weak mode's peak. Tolerance 10 %: 400 draws leave ~3.5 % on σ, and
// the floor's variance changes little over the window.
TEST(IdentificationStudy, AModesClearanceAgainstMonteCarlo) {
  const Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/hsk63_hydraulic_12mm.toml").assembly;
  const RouteData d = route_data(a, Route::SpindleHolderFromSH, a.grid.values());
  JointFitData x;
  x.label = "test";
  x.A = d.A;
  x.B11 = d.B;
  x.b_noise = exact_block_noise();
  x.g_noise = stated_block_noise(d.G, StatedNoise{0.01, 0.0, 0.01});
  x.G11 = draw_block_noise(d.G, x.g_noise, 7);
  const ForwardCheck fc = check_forward(x, d.truth, ForwardCheckOptions{});
  const SavgolOptions smooth{15, 3};
  auto h_of = [](const BlockSeries& g) {
    FrfSeries h;
    h.frequency_hz = g.frequency_hz;
    for (const Block& b : g.blocks) h.values.push_back(b(0, 0));
    return h;
  };
  const FrfSeries ref = savgol_filter(h_of(d.G), smooth, "truth").series;
  std::vector<double> mag;
  for (const Complex& v : ref.values) mag.push_back(std::abs(v));
  int checked = 0;
  for (const ModeCheck& c : fc.modes) {
    const Peak* pk = nullptr;
    const std::vector<Peak> peaks = find_peaks(mag, 0.0);
    for (const Peak& p : peaks)
      if (std::abs(ref.frequency_hz[p.index] - c.model_hz) < 5.0) pk = &p;
    ASSERT_NE(pk, nullptr) << c.model_hz;
    double ms = 0.0;
    constexpr int kDraws = 400;
    for (int r = 0; r < kDraws; ++r) {
      const FrfSeries h = savgol_filter(h_of(draw_block_noise(d.G, x.g_noise, 1000 + r)), smooth, "draw").series;
      ms += std::norm(h.values[pk->index] - ref.values[pk->index]);
    }
    const double sigma = std::sqrt(ms / kDraws / 2.0);
    const double expected = pk->prominence * mag[pk->index] / (std::sqrt(2.0) * sigma);
    EXPECT_NEAR(c.clearance / expected, 1.0, 0.10) << c.model_hz;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

// The spindle–holder joint by Eq. (18), S11 from the model: a pass, stiffnesses covered.
TEST(IdentificationStudy, SpindleHolderFromTheToolPoint) {
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::SpindleHolderFromSHT, grid());
  const Identification id = run_identification_study(a, {measured(d, 0.02, 9)}, quick(Route::SpindleHolderFromSHT));
  EXPECT_NE(id.verdict.verdict, Verdict::Fail);
  for (int k : {0, 6})
    EXPECT_TRUE(covers(id.fit->intervals[static_cast<std::size_t>(k)], d.truth[k])) << JointParameters::name(k);
  EXPECT_EQ(joint_file_of(id).interface, JointInterface::SpindleHolder);
}

// Two overhangs, as the seed measured: fitted together, labelled by overhang, the joint transfers.
TEST(IdentificationStudy, SeveralOverhangs) {
  const Assembly a = example_assembly();
  IdentificationData m49 = measured(route_data(a, Route::HolderTool, grid()), 0.02, 11);
  IdentificationData m60 = measured(route_data(with_overhang(a, 0.060), Route::HolderTool, grid()), 0.02, 13);
  m60.overhang_m = 0.060;
  const Identification id = run_identification_study(a, {m49, m60}, quick(Route::HolderTool));
  ASSERT_EQ(id.fit->setups.size(), 2u);
  EXPECT_EQ(id.fit->setups[1].label, "overhang 60.0 mm");
  EXPECT_TRUE(id.fit->transfers);
  EXPECT_EQ(id.fit->points, 2 * grid().size());
}

TEST(IdentificationStudy, BadInput) {
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, grid());
  IdentificationData no_sh = measured(d, 0.02, 1);
  no_sh.B11.reset();
  EXPECT_THROW(run_identification_study(a, {no_sh}, quick(Route::HolderTool)), InputError);
  IdentificationOptions o = quick(Route::HolderTool);
  o.band_hz = std::make_pair(8000.0, 9000.0);
  EXPECT_THROW(run_identification_study(a, {measured(d, 0.02, 1)}, o), InvalidArgument);
  o = quick(Route::HolderTool);
  o.band_hz = std::make_pair(100.0, 200.0);
  o.at_hz = 150.0;
  EXPECT_THROW(o.check(), InvalidArgument);
  o = quick(Route::HolderTool);
  o.noise.source = NoiseSpec::Source::Stated;
  o.noise.magnitude_sigma = 5.0;  // per cent meant
  EXPECT_THROW(o.check(), InvalidArgument);
  EXPECT_THROW(run_identification_study(a, {}, quick(Route::HolderTool)), InvalidArgument);
}

// The weighted median: values 1, 2, 3 with noise gains 1, 10, 1/√3 (weights 1, 0.01, 3): half the
// total weight (2.005) is first reached at the third value; with equal gains the median is the
// middle value; a band holding the last point alone gives it.
TEST(IdentificationStudy, WeightedMedianOfTheClosedForm) {
  JointSeries s;
  const double gains[3] = {1.0, 10.0, 1.0 / std::sqrt(3.0)};
  for (int i = 0; i < 3; ++i) {
    s.frequency_hz.push_back(100.0 + i);
    JointParameters p;
    for (int k = 0; k < 8; ++k) p[k] = 1.0 + i;
    s.parameters.push_back(p);
    JointEstimate e;
    e.noise_gain.fill(gains[i]);
    s.estimates.push_back(e);
  }
  EXPECT_EQ(weighted_median_parameters(s, 0.0, 1e9).k_yf, 3.0);
  for (auto& e : s.estimates) e.noise_gain.fill(1.0);
  EXPECT_EQ(weighted_median_parameters(s, 0.0, 1e9).k_yf, 2.0);
  EXPECT_EQ(weighted_median_parameters(s, 101.5, 1e9).k_yf, 3.0);
}
