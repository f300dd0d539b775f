// Tests of the plan study (studies/plan.hpp), in process. Oracles independent of the plan's code:
//   * the stable depth at each grid speed found by another method (the zero-order characteristic
//     equation solved at fixed speed along the chatter frequency, not lobe by lobe at fixed
//     frequency), the MRR and the limits from closed forms written here, then an exhaustive search;
//   * the mean cutting torque integrated numerically over one revolution, tooth by tooth;
//   * tool tuning: where a pocket must sit (tooth passing = natural frequency / (k + 1)) and which
//     way the overhang must move, with the modes found by peak picking on the model's own FRF;
//   * the uncertainty module's stability_uncertainty for the probability rule (its own sampling
//     loop, FRFs on an even grid, lobes per sample);
//   * the single run for shards merged through part files (bit for bit), and thread counts.
// Units: SI, spindle speeds in rpm, frequencies in Hz.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/plan_io.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

using namespace toolpoint;

namespace {

const std::string kExample = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml";

const Assembly& example() {
  static const Assembly a = load_assembly(kExample).assembly;
  return a;
}

std::vector<double> range(double lo, double hi, double step) {
  std::vector<double> v;
  for (int i = 0; lo + i * step <= hi + 1e-9 * step; ++i) v.push_back(lo + i * step);
  return v;
}

// The example with a passive holder–tool joint. The seed's Table 1 joint has indefinite stiffness
// and damping matrices (k_yf k_θm < ((k_ym + k_θf)/2)², c_yf c_θm < ((c_ym + c_θf)/2)²): from 109 to
// 122 mm overhang the example's tool mode has negative damping, and no depth is stable there
// (Plan.ASetUpThatIsUnstableOnItsOwnHasNoStableDepth). Tool tuning and the plan's search are
// properties of passive structures, tested on this variant: the coupling terms reduced to
// k_ym = k_θf = 1e6 N and c_ym = c_θf = 5 N s, so both matrices are positive definite.
const Assembly& passive_example() {
  static const Assembly a = [] {
    Assembly b = example();
    JointParameters& p = b.holder_tool.parameters;
    p.k_ym = p.k_tf = 1e6;
    p.c_ym = p.c_tf = 5.0;
    return b;
  }();
  return a;
}

PlanCandidate example_candidate(std::vector<double> overhangs, const std::string& name = "example",
                                const Assembly& assembly = example()) {
  PlanCandidate c;
  c.name = name;
  c.assembly = assembly;
  c.overhangs_m = std::move(overhangs);
  return c;
}

// 4 teeth, K_t 6e8 N/m², K_r 0.3, half immersion down-milling, 0.1 mm per tooth.
PlanOptions cut_options(double min_rpm, double max_rpm, int points) {
  PlanOptions o;
  o.lobes.cutting = {4, 6e8, 0.3, engagement_from_immersion(0.5, MillingDirection::Down)};
  o.lobes.speeds = {min_rpm, max_rpm, points};
  o.feed_per_tooth_m = 1e-4;
  return o;
}

// α of docs/reference.md §7 from its printed formula, for the fixed-speed oracle.
Eigen::Matrix2d alpha_of(const CuttingConditions& c) {
  const double kr = c.radial_ratio;
  auto at = [&](double p) {
    Eigen::Matrix2d m;
    m << 0.5 * (std::cos(2 * p) - 2 * kr * p + kr * std::sin(2 * p)), 0.5 * (-std::sin(2 * p) - 2 * p + kr * std::cos(2 * p)),
        0.5 * (-std::sin(2 * p) + 2 * p + kr * std::cos(2 * p)), 0.5 * (-std::cos(2 * p) - 2 * kr * p - kr * std::sin(2 * p));
    return m;
  };
  return at(c.engagement.exit_rad) - at(c.engagement.entry_rad);
}

// The zero-order stable depth at one spindle speed, solved along the chatter frequency: with
// G_yy = G_xx = G and no cross terms, det(I + Λ α G) = 0 needs Λ = −1/(λ G) for an eigenvalue λ
// of α, and Λ = −N a K_t (1 − e^{−iωτ})/(4π) then gives a = 4π/(N K_t λ G (1 − e^{−iωτ})), which
// must be real and positive: a root of Im c = 0 with Re c > 0 for the smooth c = λ G (1 − e^{−iωτ})
// (a itself has poles where c = 0), found between the FRF's points with c linear in between. The
// lowest a = 4π/(N K_t c) over the roots is the limit. No lobe numbers, no speed interpolation: a
// different route to the same envelope.
double fixed_speed_depth(const FrfSeries& g, const CuttingConditions& c, double rpm) {
  const Eigen::EigenSolver<Eigen::Matrix2d> es(alpha_of(c));
  const double tau = 60.0 / (c.teeth * rpm);
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < 2; ++r) {
    const std::complex<double> lambda = es.eigenvalues()(r);
    std::complex<double> prev;
    for (std::size_t i = 0; i < g.size(); ++i) {
      const std::complex<double> e = std::exp(std::complex<double>(0.0, -2.0 * kPi * g.frequency_hz[i] * tau));
      const std::complex<double> z = lambda * g.values[i] * (1.0 - e);
      if (i > 0 && (prev.imag() < 0.0) != (z.imag() < 0.0)) {
        const double t = prev.imag() / (prev.imag() - z.imag());
        const double re = prev.real() + t * (z.real() - prev.real());
        if (re > 0.0) best = std::min(best, 4.0 * kPi / (c.teeth * c.tangential_coefficient * re));
      }
      prev = z;
    }
  }
  return best;
}

// The mean torque per unit depth [N·m/m] by summing the teeth's tangential forces over one
// revolution (midpoint rule, 360 000 steps: the force jumps at entry and exit, so the rule errs by
// about a step there, 3e-6 of the torque): F_t = K_t c sin φ + K_te per unit depth while a tooth
// is within φ_st…φ_ex, torque F_t D/2.
double integrated_torque_per_depth(const CuttingConditions& c, double d, double feed, double edge) {
  constexpr int kSteps = 360000;
  double sum = 0.0;
  for (int s = 0; s < kSteps; ++s) {
    const double rot = 2.0 * kPi * (s + 0.5) / kSteps;
    for (int j = 0; j < c.teeth; ++j) {
      const double phi = std::fmod(rot + 2.0 * kPi * j / c.teeth, 2.0 * kPi);
      if (phi >= c.engagement.entry_rad && phi <= c.engagement.exit_rad)
        sum += (c.tangential_coefficient * feed * std::sin(phi) + edge) * d / 2.0;
    }
  }
  return sum / kSteps;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// Every number of two results, bit for bit (their JSON, their CSV text and their per-speed series).
void expect_identical(const PlanResult& a, const PlanResult& b) {
  EXPECT_EQ(nlohmann::json(a).dump(), nlohmann::json(b).dump());
  EXPECT_EQ(format_plan_setups_csv(a), format_plan_setups_csv(b));
  EXPECT_EQ(format_plan_tuning_csv(a), format_plan_tuning_csv(b));
  EXPECT_EQ(format_plan_map_csv(a), format_plan_map_csv(b));
  ASSERT_EQ(a.jobs.size(), b.jobs.size());
  for (std::size_t j = 0; j < a.jobs.size(); ++j) {
    EXPECT_TRUE(same_bits(a.jobs[j].stable_depth_m, b.jobs[j].stable_depth_m)) << j;
    EXPECT_TRUE(same_bits(a.jobs[j].safe_depth_m, b.jobs[j].safe_depth_m)) << j;
    EXPECT_TRUE(same_bits(a.jobs[j].depth_m, b.jobs[j].depth_m)) << j;
    EXPECT_TRUE(same_bits(a.jobs[j].mrr_m3_per_s, b.jobs[j].mrr_m3_per_s)) << j;
    EXPECT_TRUE(same_bits(a.jobs[j].probability, b.jobs[j].probability)) << j;
    EXPECT_EQ(a.jobs[j].lobe, b.jobs[j].lobe) << j;
  }
}

PlanResult via_parts(const std::vector<PlanCandidate>& c, const PlanOptions& o, int count) {
  std::vector<PlanPart> parts;
  std::vector<std::string> names;
  for (int i = count - 1; i >= 0; --i) {  // any order
    const std::string text = format_plan_part(run_plan_part(c, o, i, count));
    names.push_back("part-" + std::to_string(i));
    parts.push_back(parse_plan_part(text, names.back()));
  }
  return merge_plan_parts(parts, names);
}

}  // namespace

// The best set-up against an exhaustive search over the same overhang × speed grid, with the stable
// depth at every grid point from the fixed-speed oracle on the same (resolved) tool point FRF, the
// safety factor, and the MRR a·b·c·N·n/60 with b = a_e = D/2 (half immersion). The two depth
// routes differ by interpolation only (0.44 % at worst, on the steepest lobe walls); tolerances:
// depths 1 %, the same overhang, the speed within 2 grid steps, the MRR within 1 % (observed: the
// same overhang and speed, MRR equal to 1e-5). The plan's own pick is also checked
// exactly against a search over its per-speed MRR (ties within 1e-9: the largest margin).
TEST(Plan, BestSetUpIsTheBruteForceMaximum) {
  const std::vector<double> overhangs = range(0.080, 0.120, 0.010);
  PlanOptions o = cut_options(8000.0, 12000.0, 201);
  o.safety.factor = 1.25;
  o.parallel.threads = 2;
  const PlanResult r = run_plan({example_candidate(overhangs, "passive", passive_example())}, o);
  ASSERT_EQ(r.best.size(), 1u);
  const double width = 0.5 * example().tool.diameter;  // a_e = D/2
  double best = -1.0;
  std::size_t best_i = 0, best_k = 0;
  double worst_depth_error = 0.0;
  for (std::size_t i = 0; i < overhangs.size(); ++i) {
    const AssemblyModel model(with_overhang(passive_example(), overhangs[i]));
    const FrfSeries g = resolved_tool_point(model, passive_example().grid.values());
    for (std::size_t k = 0; k < r.header.speeds_rpm.size(); ++k) {
      const double n = r.header.speeds_rpm[k];
      const double a = fixed_speed_depth(g, o.lobes.cutting, n);
      worst_depth_error = std::max(worst_depth_error, std::abs(a / r.jobs[i].stable_depth_m[k] - 1.0));
      const double mrr = a / 1.25 * width * 1e-4 * 4 * n / 60.0;
      if (mrr > best) {
        best = mrr;
        best_i = i;
        best_k = k;
      }
    }
  }
  EXPECT_LT(worst_depth_error, 0.01) << "the lobes' envelope against the fixed-speed roots";
  const PlanSetup& s = r.best[0];
  EXPECT_EQ(s.job, best_i);
  EXPECT_NEAR(static_cast<double>(s.speed_index), static_cast<double>(best_k), 2.0);
  EXPECT_NEAR(s.mrr_m3_per_s / best, 1.0, 0.01);
  EXPECT_EQ(s.limit, DepthLimit::Stability);
  EXPECT_NEAR(s.depth_margin, 0.25, 1e-12);

  // The same plan with the spindle's power binding (a plateau of equal MRR = P/K_t): the pick is
  // the largest MRR, and among those within 1e-9 the largest stability margin, then the slowest.
  o.machine.power_w = 1500.0;
  const PlanResult p = run_plan({example_candidate(overhangs, "passive", passive_example())}, o);
  double top = 0.0;
  for (const PlanJob& job : p.jobs)
    for (double m : job.mrr_m3_per_s) top = std::max(top, m);
  double margin = -1.0;
  std::size_t pick_j = 0, pick_k = 0;
  for (std::size_t j = 0; j < p.jobs.size(); ++j)
    for (std::size_t k = 0; k < p.jobs[j].depth_m.size(); ++k) {
      if (!(p.jobs[j].mrr_m3_per_s[k] >= top * (1.0 - 1e-9))) continue;
      const double m = p.jobs[j].stable_depth_m[k] / p.jobs[j].depth_m[k];
      if (m > margin) {
        margin = m;
        pick_j = j;
        pick_k = k;
      }
    }
  EXPECT_EQ(p.best[0].job, pick_j);
  EXPECT_EQ(p.best[0].speed_index, pick_k);
  EXPECT_EQ(p.best[0].limit, DepthLimit::Power);
  // P = K_t · MRR without edge forces: the plateau is P/K_t exactly (to rounding).
  EXPECT_NEAR(p.best[0].mrr_m3_per_s, 1500.0 / 6e8, 1e-12 * 1500.0 / 6e8 * 1e3);
}

// Tool tuning on the example (4 teeth, half immersion down-milling, overhangs 80–108 mm every
// millimetre — the example's tool mode has negative damping from 109 to 122 mm, see below — speeds
// 2000 rpm to the top speed): a faster spindle shortens the best overhang, and where the best speed
// sits in a stability pocket at the top speed, the tooth passing N·n*/60 is f_m/(k + 1) for a mode
// f_m of the tuned assembly (here k = 1: the tool mode's second pocket). What the plan finds is in
// docs/planning.md (10 000 rpm: 103 mm, at the top speed on a lobe's flank; 11 000: 92 mm; 11 500: 88 mm
// and 12 000: 83 mm, the tool mode at twice the tooth passing). Tolerances: the pocket within 3 %
// of f_m/(k + 1) (a zero-order pocket peaks a little above the natural frequency; 0.2–3 % seen), n*
// within 5 % of the top speed (MRR ∝ speed: the pocket is used as close to the top as it sits).
TEST(Plan, BestOverhangMovesAsToolTuningPredicts) {
  const std::vector<double> overhangs = range(0.080, 0.108, 0.001);
  std::vector<double> best;
  for (double top : {10000.0, 11000.0, 11500.0, 12000.0}) {
    PlanOptions o = cut_options(2000.0, top, 500);
    o.parallel.threads = 2;
    const PlanResult r = run_plan({example_candidate(overhangs)}, o);
    const PlanSetup& s = r.best[0];
    EXPECT_GT(s.speed_rpm, 0.95 * top) << top;
    best.push_back(s.overhang_m);
    if (top < 11500.0) continue;  // on a flank at the top speed, not in a pocket
    // The modes of the chosen set-up, picked independently on the model's FRF.
    const AssemblyModel model(with_overhang(example(), s.overhang_m));
    const FrfSeries g = entry(model.tool_point(range(500.0, 3000.0, 0.05)), 0);
    const double tooth_passing = 4.0 * s.speed_rpm / 60.0;
    double closest = 1.0;
    for (const Peak& m : find_peaks(g, PeakOptions{0.1}))
      for (int k : {0, 1}) closest = std::min(closest, std::abs(tooth_passing * (k + 1) / m.frequency_hz - 1.0));
    EXPECT_LT(closest, 0.03) << "top " << top << ": no mode has its pocket at " << tooth_passing << " Hz";
  }
  for (std::size_t i = 1; i < best.size(); ++i) EXPECT_GT(best[i - 1], best[i]) << i;
}

// A set-up that is unstable on its own: the example at 110 and 115 mm, where the seed's Table 1
// joint (indefinite damping matrix) gives the tool mode negative damping. Checked independently of
// the plan's peak picking: at the tool mode's peak, found on the exact model by golden-section
// search, Im G > 0 (at 100 mm, < 0). The plan gives those set-ups no stable depth at any speed
// (rather than lobes of a structure that vibrates by itself, or stopping), says why, and picks the
// passive one.
TEST(Plan, ASetUpThatIsUnstableOnItsOwnHasNoStableDepth) {
  for (const auto& [overhang, unstable] : {std::pair{0.100, false}, {0.110, true}, {0.115, true}}) {
    const AssemblyModel model(with_overhang(example(), overhang));
    const auto magnitude = [&](double f) { return std::abs(model.tool_point(f)(0, 0)); };
    const auto [f_peak, h_peak] = refine_peak(magnitude, 1150.0, 1450.0);
    ASSERT_GT(h_peak, 0.0);
    EXPECT_EQ(model.tool_point(f_peak)(0, 0).imag() > 0.0, unstable) << overhang << " m, tool mode at " << f_peak << " Hz";
  }
  PlanOptions o = cut_options(2000.0, 12000.0, 200);
  const PlanResult r = run_plan({example_candidate({0.100, 0.110, 0.115})}, o);
  ASSERT_EQ(r.jobs.size(), 3u);
  for (std::size_t j : {1u, 2u}) {
    for (double d : r.jobs[j].stable_depth_m) EXPECT_EQ(d, 0.0) << j;
    bool said = false;
    for (const std::string& w : r.jobs[j].warnings) said |= w.find("negative damping") != std::string::npos;
    EXPECT_TRUE(said) << j;
  }
  EXPECT_GT(*std::max_element(r.jobs[0].stable_depth_m.begin(), r.jobs[0].stable_depth_m.end()), 1e-3);
  EXPECT_EQ(r.best[0].job, 0u);
}

// The mean cutting torque of plan.hpp's closed form against the revolution summed tooth by tooth
// (up, down, slot, an edge force; 1e-5 for the quadrature's error at the force's jumps), and the plan's depth used against
// min(a_safe, T_max/T(1), P_max/P(1, n)) at every speed, with T(1) from that integral: 1e-5. The
// limit switches from torque to power at the base speed P/(2π T/60), as the closed form says.
TEST(Plan, PowerAndTorqueCutTheEnvelopeWhereTheClosedFormSays) {
  const double d = example().tool.diameter;
  for (auto [immersion, dir] :
       {std::pair{0.5, MillingDirection::Down}, std::pair{0.3, MillingDirection::Up}, std::pair{1.0, MillingDirection::Down}}) {
    const CuttingConditions c{3, 8e8, 0.3, engagement_from_immersion(immersion, dir)};
    for (double edge : {0.0, 3e4}) {
      const double numeric = integrated_torque_per_depth(c, d, 1.2e-4, edge);
      EXPECT_NEAR(torque_per_depth(c, d, 1.2e-4, edge) / numeric, 1.0, 1e-5) << immersion << " " << edge;
      EXPECT_NEAR(power_per_depth(c, d, 1.2e-4, edge, 9000.0) / (numeric * 2.0 * kPi * 9000.0 / 60.0), 1.0, 1e-5);
    }
    EXPECT_NEAR(radial_width_m(c, d), immersion * d, 1e-15);
  }

  PlanOptions o = cut_options(2000.0, 12000.0, 500);
  o.edge_coefficient_n_per_m = 2e4;
  o.machine.torque_nm = 0.5;
  o.machine.power_w = 500.0;
  const PlanResult r = run_plan({example_candidate({0.060, 0.090})}, o);
  const double t1 = integrated_torque_per_depth(o.lobes.cutting, d, 1e-4, 2e4);
  const double base_rpm = 500.0 / (2.0 * kPi * 0.5 / 60.0);
  int torque = 0, power = 0;
  for (const PlanJob& job : r.jobs)
    for (std::size_t k = 0; k < r.header.speeds_rpm.size(); ++k) {
      const double n = r.header.speeds_rpm[k];
      const double a_t = 0.5 / t1, a_p = 500.0 / (t1 * 2.0 * kPi * n / 60.0);
      const double expected = std::min({job.safe_depth_m[k], a_t, a_p});
      ASSERT_NEAR(job.depth_m[k] / expected, 1.0, 1e-5) << n;
      if (job.limit[k] == DepthLimit::Torque) {
        ++torque;
        EXPECT_LE(n, base_rpm * (1.0 + 1e-9));
      }
      if (job.limit[k] == DepthLimit::Power) {
        ++power;
        EXPECT_GE(n, base_rpm * (1.0 - 1e-9));
      }
      if (job.limit[k] == DepthLimit::Stability) EXPECT_LE(job.safe_depth_m[k], std::min(a_t, a_p) * (1.0 + 1e-9));
    }
  EXPECT_GT(torque, 0);
  EXPECT_GT(power, 0);
  // The tool's 32 mm flutes cap the depth where nothing else does.
  PlanOptions deep = cut_options(2000.0, 12000.0, 200);
  deep.max_depth_m = 1e-3;
  const PlanResult q = run_plan({example_candidate({0.060})}, deep);
  for (std::size_t k = 0; k < q.jobs[0].depth_m.size(); ++k)
    EXPECT_EQ(q.jobs[0].depth_m[k], std::min(q.jobs[0].safe_depth_m[k], 1e-3));
}

// Shards in part files, merged, give the single run's result bit for bit (JSON, CSV, every series),
// for 3 shards and for more shards than jobs, in any order; two candidates (the model, and a
// measured SH11 + the model's tool); and the same for 1 and 2 threads.
TEST(Plan, ShardsMergedEqualTheSingleRunBitForBit) {
  PredictOptions holder;
  holder.receptance = PredictedFrf::HolderTip;
  PlanCandidate measured = example_candidate({0.050, 0.060, 0.070}, "measured holder");
  measured.sh11 = run_prediction_study(example(), holder).frf;
  measured.sh11_name = "sh11.csv";
  const std::vector<PlanCandidate> c = {example_candidate({0.045, 0.055, 0.065, 0.075}), measured};
  PlanOptions o = cut_options(5000.0, 15000.0, 300);
  o.machine.power_w = 4000.0;
  o.parallel.threads = 1;
  const PlanResult one = run_plan(c, o);
  EXPECT_EQ(one.jobs.size(), 7u);
  expect_identical(one, via_parts(c, o, 3));
  expect_identical(one, via_parts(c, o, 9));
  o.parallel.threads = 2;
  expect_identical(one, run_plan(c, o));
}

// The probability rule: the allowed depth is the 5 % quantile (type 7) of the sampled joints'
// envelopes, as the uncertainty module computes it (its own sampling, FRFs and lobes on an even
// 0.5 Hz grid over 500–5000 Hz; the plan resolves each sample's grid: 1 % allowed, 0.04 % seen at
// this overhang), the probability at the depth used is ≥ 95 % wherever stability limits it, and
// the plan's sharded run equals its single run.
TEST(Plan, ProbabilityRuleIsTheQuantileOfTheSampledJoints) {
  JointFile joint;
  joint.interface = JointInterface::HolderTool;
  joint.parameters = example().holder_tool.parameters;
  joint.source = "kht.toml";
  JointUncertainty u;
  for (int k = 0; k < 8; ++k) u.covariance(k, k) = std::pow((k % 2 ? 0.10 : 0.05) * joint.parameters[k], 2);
  joint.uncertainty = u;
  PlanCandidate cand = example_candidate({0.049});
  cand.uncertain_joint = joint;
  PlanOptions o = cut_options(9000.0, 12000.0, 31);
  o.safety.kind = SafetyRule::Kind::Probability;
  o.safety.probability = 0.95;
  o.safety.samples = 20;
  o.parallel.threads = 2;
  const PlanResult r = run_plan({cand}, o);

  Assembly a = example();
  a.grid = {500.0, 5000.0, 0.5};
  UncertaintyOptions uo;
  uo.samples = 20;
  uo.seed = 1;
  uo.levels = {0.05};
  ZeroOrderOptions zo;
  zo.speeds = o.lobes.speeds;
  const StabilityUncertainty s = stability_uncertainty(with_overhang(a, 0.049), joint, a.grid.values(), o.lobes.cutting, zo,
                                                       {0.0}, uo);
  const PlanJob& job = r.jobs[0];
  for (std::size_t k = 0; k < job.safe_depth_m.size(); ++k) {
    EXPECT_NEAR(job.safe_depth_m[k] / s.depth_m[0][k], 1.0, 0.01) << r.header.speeds_rpm[k];
    if (job.limit[k] == DepthLimit::Stability) EXPECT_GE(job.probability[k], 0.95);
  }
  EXPECT_GE(r.best[0].probability, 0.95);
  expect_identical(r, via_parts({cand}, o, 2));
}

// What the plan refuses, naming the field.
TEST(Plan, BadOptionsAndCandidatesAreRefusedByName) {
  const auto refuses = [](const std::vector<PlanCandidate>& c, const PlanOptions& o, const std::string& what) {
    try {
      plan_header(c, o);
      ADD_FAILURE() << "accepted; expected " << what;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_FALSE(e.hint().empty());
    }
  };
  const PlanOptions ok = cut_options(2000.0, 12000.0, 100);
  PlanOptions o = ok;
  o.feed_per_tooth_m = 0.1;  // 0.1 mm written as metres
  refuses({example_candidate({0.05})}, o, "feed_per_tooth_m");
  o = ok;
  o.safety.factor = 0.8;
  refuses({example_candidate({0.05})}, o, "SafetyRule::factor");
  o = ok;
  o.safety.kind = SafetyRule::Kind::Probability;
  refuses({example_candidate({0.05})}, o, "uncertain_joint");
  o = ok;
  o.machine.min_overhang_m = 0.08;
  refuses({example_candidate({0.05, 0.06})}, o, "min_overhang_m");
  refuses({example_candidate({49.0})}, ok, "millimetres");
  refuses({example_candidate({0.06, 0.05})}, ok, "strictly increasing");
  refuses({example_candidate({0.05}), example_candidate({0.06})}, ok, "candidates[0]'s");
  EXPECT_THROW(run_plan_part({example_candidate({0.05})}, ok, 3, 3), InvalidArgument);
}

// The time-domain method through the plan: in a slot with 4 teeth the milling equation is nearly
// time-invariant, so full-discretization (on modes fitted to the FRF: 2.1 % residual on the
// example) and the zero-order lobes must give about the same envelope and best set-up: 5 % allowed
// for the fit and the error target (1 %); 3.1 % at most seen. The time domain searches up to the
// tool's 32 mm flutes here, so the 3.9 mm pocket is not cut off at its own default ceiling.
TEST(Plan, FullDiscretizationAgreesWithZeroOrderInASlot) {
  PlanOptions o = cut_options(12000.0, 14000.0, 9);
  o.lobes.cutting.engagement = engagement_from_immersion(1.0, MillingDirection::Down);
  o.parallel.threads = 2;
  const PlanResult zoa = run_plan({example_candidate({0.049})}, o);
  o.lobes.method = LobesMethod::FullDiscretization;
  const PlanResult fd = run_plan({example_candidate({0.049})}, o);
  for (std::size_t k = 0; k < 9; ++k)
    EXPECT_NEAR(fd.jobs[0].stable_depth_m[k] / zoa.jobs[0].stable_depth_m[k], 1.0, 0.05) << fd.header.speeds_rpm[k];
  EXPECT_NEAR(fd.best[0].mrr_m3_per_s / zoa.best[0].mrr_m3_per_s, 1.0, 0.05);
}

// Bearings that soften with speed (a table: 30 % over 0–20 000 rpm): the plan's stable depth at
// each speed is the zero-order depth of the tool point FRF at that speed. Oracle: the fixed-speed
// roots above (no lobes, no speed interpolation) on the FRF of the assembly with its bearings at
// that speed (at_speed), within 1 % as in BestSetUpIsTheBruteForceMaximum; the plan's speeds are
// the speeds the FRF was evaluated at (9 nodes and their midpoints), so no interpolation enters.
// At rest (SpeedModel::Bearings: H_xy = 0, H_yy = H_xx, what the oracle assumes); Automatic spins
// the spindle and says so. The standstill depths differ by more than 5 % somewhere: the check
// tells the two apart.
TEST(Plan, BearingSpeedTablesMoveThePlansLobes) {
  Assembly a = passive_example();
  for (Bearing& b : a.spindle.bearings) b.speed_table = {{0.0, b.stiffness, b.damping}, {20000.0, 0.7 * b.stiffness, b.damping}};
  PlanOptions o = cut_options(8000.0, 12000.0, 17);
  o.lobes.speed_model = SpeedModel::Bearings;
  o.lobes.speed_nodes = 9;
  o.parallel.threads = 2;
  const PlanResult r = run_plan({example_candidate({0.060}, "tabled", a)}, o);
  const std::vector<double> grid = a.grid.values();
  const FrfSeries still = entry(AssemblyModel(with_overhang(a, 0.060)).tool_point(grid), 0);
  double worst = 0.0, moved = 0.0;
  for (std::size_t k = 0; k < r.header.speeds_rpm.size(); ++k) {
    const double n = r.header.speeds_rpm[k];
    const FrfSeries g = entry(AssemblyModel(at_speed(with_overhang(a, 0.060), n)).tool_point(grid), 0);
    const double depth = fixed_speed_depth(g, o.lobes.cutting, n);
    worst = std::max(worst, std::abs(depth / r.jobs[0].stable_depth_m[k] - 1.0));
    moved = std::max(moved, std::abs(fixed_speed_depth(still, o.lobes.cutting, n) / depth - 1.0));
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(moved, 0.05);
  const auto said = [](const PlanResult& p, const std::string& what) {
    for (const std::string& w : p.jobs[0].warnings)
      if (w.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(said(r, "at each spindle speed (bearings)"));
  o.lobes.speed_model = SpeedModel::Automatic;
  EXPECT_TRUE(said(run_plan({example_candidate({0.060}, "tabled", a)}, o), "at each spindle speed (spinning)"));
}
