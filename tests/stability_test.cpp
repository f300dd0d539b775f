// Tests of milling stability (stability module). Expectations come from outside the code under
// test: the closed-form SDOF identity and the zero-order slot floor it implies (docs/reference.md §7), the
// Insperger–Stépán benchmark value 0.298054 mm, the characteristic equation det(I + ΛαG) = 0
// evaluated afresh at every lobe point, a numerical quadrature of the per-tooth directional matrix,
// the exact free decay e^{−ζω_nτ}, and a time-invariant case (N = 4, slotting) where zero-order
// and semi-discretization solve the same delay equation and must agree.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <sys/wait.h>
#include <tuple>
#include <unistd.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/io/stability_io.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/studies/rotational.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "support/joint_data.hpp"

using namespace toolpoint;

namespace {

// The Insperger–Stépán (2004) benchmark mode and cutting coefficients (docs/reference.md §7).
const Mode kBench{0.03993, 0.011, 922.0};
constexpr double kKt = 6e8, kKn = 2e8;

CuttingConditions cutting(int teeth, double immersion, MillingDirection dir = MillingDirection::Down) {
  return {teeth, kKt, kKn / kKt, engagement_from_immersion(immersion, dir)};
}

std::vector<double> uniform_grid(double lo, double hi, double step) {
  std::vector<double> f;
  for (int i = 0; lo + i * step <= hi; ++i) f.push_back(lo + i * step);
  return f;
}

// The per-tooth directional matrix, written out from the force model (not from α): chip
// h = Δx sinφ + Δy cosφ, F_x = −F_t cosφ − F_r sinφ, F_y = F_t sinφ − F_r cosφ, F_r = K_r F_t,
// so F = K_t a h [−cosφ − K_r sinφ, sinφ − K_r cosφ]ᵀ and A = 2 [..]·[sinφ, cosφ].
Eigen::Matrix2d tooth_matrix(double kr, double phi) {
  const Eigen::Vector2d force(-std::cos(phi) - kr * std::sin(phi), std::sin(phi) - kr * std::cos(phi));
  const Eigen::Vector2d chip(std::sin(phi), std::cos(phi));
  return 2.0 * force * chip.transpose();
}

// |det(I + ΛαG)| relative to the size of its terms, Λ = −N a K_t (1 − e^{−iωτ})/(4π).
double characteristic_residual(const Eigen::Matrix2d& alpha, const Eigen::Matrix2cd& g, int teeth, double kt, double speed_rpm,
                               double depth_m, double chatter_hz) {
  const double tau = 60.0 / (teeth * speed_rpm), w = omega_of(chatter_hz);
  const Complex lam = -teeth * depth_m * kt * (1.0 - std::exp(Complex(0.0, -w * tau))) / (4.0 * kPi);
  const Eigen::Matrix2cd b = alpha.cast<Complex>() * g;
  const Complex tr = b.trace(), det = b.determinant();
  return std::abs(1.0 + lam * tr + lam * lam * det) / (1.0 + std::abs(lam * tr) + std::abs(lam * lam * det));
}

}  // namespace

// docs/reference.md §7: min Re G = −1/(4kζ(1+ζ)) at ω_n sqrt(1+2ζ) for G = 1/(k − mω² + icω). Checked at the
// point (1e-12: round-off) and as a minimum over a fine grid (nothing below it, 1e-12 slack).
TEST(Stability, SdofRealPartMinimum) {
  for (const Mode m : {kBench, Mode{2.5, 0.05, 310.0}, Mode{0.4, 0.002, 4000.0}}) {
    const double k = m.stiffness(), z = m.damping_ratio, bound = -1.0 / (4.0 * k * z * (1.0 + z));
    const double f_min = m.frequency_hz * std::sqrt(1.0 + 2.0 * z);
    EXPECT_NEAR(modal_receptance({m}, f_min).real() / bound, 1.0, 1e-12);
    for (double f = 0.5 * m.frequency_hz; f < 1.5 * m.frequency_hz; f += 1e-3 * z * m.frequency_hz)
      EXPECT_GE(modal_receptance({m}, f).real(), bound * (1.0 + 1e-12)) << f;
  }
}

// 1-DOF slotting (x flexible only, N = 2): α_xx = −K_rπ, so a_lim = −2/(N K_n Re G) and the floor
// is 8kζ(1+ζ)/(N K_n) (independent of K_t). With f_n sqrt(1+2ζ) on the grid the floor is exact
// to round-off (1e-9); docs/reference.md §7 gives 0.298054 mm, rounded to 6 digits (±5e-7 mm).
TEST(Stability, ZeroOrderSlotFloorOfTheBenchmark) {
  const double f_min = kBench.frequency_hz * std::sqrt(1.0 + 2.0 * kBench.damping_ratio);
  std::vector<double> grid = uniform_grid(700.0, 1200.0, 0.37);
  grid.push_back(f_min);
  std::sort(grid.begin(), grid.end());
  const MillingFrfs frfs = modal_milling_frfs({kBench}, {}, grid);
  const double z = kBench.damping_ratio, exact = 8.0 * kBench.stiffness() * z * (1.0 + z) / (2.0 * kKn);
  double chatter = 0.0;
  const double floor = zero_order_floor(frfs, cutting(2, 1.0), &chatter);
  EXPECT_NEAR(floor / exact, 1.0, 1e-9);
  EXPECT_NEAR(floor * 1e3, 0.298054, 5e-7);
  EXPECT_DOUBLE_EQ(chatter, f_min);
  // K_t does not enter the 1-DOF slot floor (K_n fixed).
  CuttingConditions other = cutting(2, 1.0);
  other.tangential_coefficient = 3e9;
  other.radial_ratio = kKn / 3e9;
  EXPECT_NEAR(zero_order_floor(frfs, other) / exact, 1.0, 1e-9);
  // The modal grid helper resolves the peak well enough for the floor to 1e-4.
  EXPECT_NEAR(zero_order_floor(modal_milling_frfs({kBench}, {}, modal_frequency_grid({kBench})), cutting(2, 1.0)) / exact, 1.0,
              1e-4);
}

// Zero-order lobes of an FRF in any units: the depth scales as 1/G, so the floor of G·2^−990
// (~1e-298 m/N) is the floor of G times 2^990, exactly (scaling by a power of two is exact, and
// every step of the computation is homogeneous in G); a 2-DOF FRF likewise. Where the depths
// themselves leave double precision (G·1e-318: a peak of 3e-323, subnormal), the error says so and does not blame
// the sign of Im G.
TEST(Stability, ZeroOrderLobesAreScaleAware) {
  const std::vector<double> grid = modal_frequency_grid({kBench});
  const Mode other{0.05, 0.02, 1100.0};
  for (const bool two_dof : {false, true}) {
    MillingFrfs frfs = two_dof ? modal_milling_frfs({kBench}, {other}, grid) : modal_milling_frfs({kBench}, {}, grid);
    const double floor = zero_order_floor(frfs, cutting(2, 1.0));
    auto scale = [](FrfSeries& f, double by) {
      for (Complex& v : f.values) v *= by;
    };
    scale(frfs.xx, std::ldexp(1.0, -990));
    if (frfs.yy) scale(*frfs.yy, std::ldexp(1.0, -990));
    EXPECT_EQ(zero_order_floor(frfs, cutting(2, 1.0)), std::ldexp(floor, 990)) << two_dof;
  }
  MillingFrfs tiny = modal_milling_frfs({kBench}, {}, grid);
  for (Complex& v : tiny.xx.values) v *= 1e-318;
  try {
    zero_order_floor(tiny, cutting(2, 1.0));
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond the range of double precision"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("Λ_R ≥ 0"), std::string::npos) << e.what();
  }
}

// Data that are not a passive point receptance in the e^{iωt} convention are refused by the
// zero-order lobes, which would otherwise draw lobes from them (4× too deep for the example's
// conjugate, in review): the benchmark's FRF conjugated (every peak says so: the convention) or
// negated (a sign slip), and a second mode of negative damping beside a passive first (the
// structure feeds energy in: unstable at any depth). The passive FRF itself passes.
TEST(Stability, NonPassiveFrfsAreRefused) {
  const std::vector<double> grid = modal_frequency_grid({kBench, Mode{0.05, 0.02, 2000.0}});
  const MillingFrfs good = modal_milling_frfs({kBench, Mode{0.05, 0.02, 2000.0}}, {}, grid);
  EXPECT_NO_THROW(good.check("g.csv"));
  EXPECT_FALSE(passivity_violation(good.xx).has_value());
  auto message = [](const MillingFrfs& f) {
    try {
      zero_order_floor(f, cutting(2, 1.0));
    } catch (const InputError& e) {
      return std::string(e.what()) + " | " + e.hint();
    }
    return std::string("no error");
  };
  MillingFrfs conjugate = good, negated = good, unstable = good;
  for (Complex& v : conjugate.xx.values) v = std::conj(v);
  for (Complex& v : negated.xx.values) v = -v;
  EXPECT_NE(message(conjugate).find("conjugate"), std::string::npos) << message(conjugate);
  EXPECT_NE(message(conjugate).find("2 of its 2 resonance peaks"), std::string::npos) << message(conjugate);
  EXPECT_NE(message(negated).find("negate"), std::string::npos) << message(negated);
  for (std::size_t i = 0; i < grid.size(); ++i) {  // the 2000 Hz mode with ζ = −0.02
    const Mode m{0.05, 0.02, 2000.0};
    const double r = grid[i] / m.frequency_hz;
    const Complex passive = 1.0 / (m.stiffness() * Complex(1.0 - r * r, 2.0 * m.damping_ratio * r));
    const Complex active = 1.0 / (m.stiffness() * Complex(1.0 - r * r, -2.0 * m.damping_ratio * r));
    unstable.xx.values[i] += active - passive;
  }
  MillingFrfs mobility = good;  // Y = iωG: a file of mobilities read as receptances
  for (std::size_t i = 0; i < grid.size(); ++i) mobility.xx.values[i] *= Complex(0.0, omega_of(grid[i]));
  EXPECT_NE(message(mobility).find("point mobility"), std::string::npos) << message(mobility);
  const std::string u = message(unstable);
  EXPECT_NE(u.find("negative damping"), std::string::npos) << u;
  EXPECT_NE(u.find("1 of its 2 resonance peaks"), std::string::npos) << u;
  const auto v = passivity_violation(unstable.xx);
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(v->frequency_hz, 2000.0, 2.0);
}

// A measured SH11 carries noise — here the tutorial's (docs/tutorial.md): a virtual tap test on the holder with
// 0.5 % noise, differenced (second order, 20 mm, the truncation error removed on the model) — and
// coupling carries it into the tool point FRF, where it makes small peaks with Im G > 0 beside the
// real part that dominates between modes (23 of 117 peaks at 75 mm). They are not negative
// damping: passivity_violation weighs Im G against the local noise and finds none, and a plan on
// that SH11 gives every overhang a stable depth (it gave 50 of 61 none). A real negative-damping
// mode in noise is still found.
TEST(Stability, NoiseOnAMeasuredHolderIsNotNegativeDamping) {
  const Assembly a = test::example_assembly();
  TapTestOptions t;
  t.side = TapSide::Holder;
  t.spacing_m = 0.02;
  t.sigma = 0.005;
  const TapTest tap = run_tap_test_study(a, t);
  RotationalInput in;
  for (const TapTestFrf& x : tap.frfs) in.frfs.set(x.response, x.hammer, x.frf);
  in.model = a;
  in.side = TapSide::Holder;
  RotationalStudyOptions ro;
  ro.differences.spacing = 0.02;
  ro.differences.shear_stiffness = tap.shear_stiffness_n;
  const BlockSeries sh11 = run_rotational_study(in, ro).block;
  std::mt19937 rng(11);
  std::normal_distribution<double> z(0.0, 1.0);
  for (double overhang : {0.060, 0.075, 0.090}) {
    const FrfSeries g = entry(couple_tool(with_overhang(a, overhang), sh11, "SH11"), 0);
    const auto v = passivity_violation(g);
    EXPECT_FALSE(v.has_value()) << overhang << ": " << v->describe("G");
  }
  PlanCandidate c;
  c.name = "measured";
  c.assembly = a;
  c.sh11 = sh11;
  c.overhangs_m = {0.060, 0.075, 0.090};
  PlanOptions o;
  o.lobes.cutting = cutting(4, 0.5);
  o.lobes.speeds = {5000.0, 15000.0, 100};
  o.feed_per_tooth_m = 1e-4;
  const PlanResult r = run_plan({c}, o);
  for (const std::string& w : r.warnings) EXPECT_EQ(w.find("negative damping"), std::string::npos) << w;
  for (const PlanJob& j : r.jobs)
    EXPECT_GT(*std::max_element(j.stable_depth_m.begin(), j.stable_depth_m.end()), 0.0) << j.overhang_m;
  // A mode of negative damping at 2000 Hz in 2 % complex noise: found.
  const Mode m{0.05, 0.02, 2000.0};
  const std::vector<double> grid = modal_frequency_grid({kBench, m});
  FrfSeries unstable = modal_frf({kBench}, grid);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double r2 = grid[i] / m.frequency_hz;
    unstable.values[i] += 1.0 / (m.stiffness() * Complex(1.0 - r2 * r2, -2.0 * m.damping_ratio * r2));
    unstable.values[i] *= 1.0 + 0.02 * Complex(z(rng), z(rng)) / std::sqrt(2.0);
  }
  const auto v = passivity_violation(unstable);
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(v->frequency_hz, 2000.0, 20.0);  // the noisy peak, within 1 %
}

// α from the closed-form antiderivatives against Simpson quadrature of the per-tooth matrix
// written from the force model (2000 panels: error ~1e-13), and the slotting values
// α = π[[−K_r, −1], [1, −K_r]].
TEST(Stability, DirectionalFactorsMatchQuadrature) {
  const double kr = 0.3;
  for (auto [a, b] : {std::pair{0.0, kPi}, {0.3, 1.1}, {2.69, kPi}, {0.0, 0.45}}) {
    Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
    const int n = 2000;
    const double h = (b - a) / n;
    for (int i = 0; i <= n; ++i) q += (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * h / 3.0 * tooth_matrix(kr, a + i * h);
    EXPECT_LT((directional_integral(kr, a, b) - q).norm(), 1e-11) << a << " " << b;
  }
  Eigen::Matrix2d slot;
  slot << -kr * kPi, -kPi, kPi, -kr * kPi;
  EXPECT_LT((directional_factors({2, 1e9, kr, {0.0, kPi}}) - slot).norm(), 1e-14);
}

TEST(Stability, EngagementAngles) {
  const auto up = engagement_from_immersion(0.5, MillingDirection::Up),
             down = engagement_from_immersion(0.5, MillingDirection::Down);
  EXPECT_DOUBLE_EQ(up.entry_rad, 0.0);
  EXPECT_NEAR(up.exit_rad, kPi / 2.0, 1e-15);
  EXPECT_NEAR(down.entry_rad, kPi / 2.0, 1e-15);
  EXPECT_DOUBLE_EQ(down.exit_rad, kPi);
  const auto slot = engagement_from_immersion(1.0, MillingDirection::Up);
  EXPECT_DOUBLE_EQ(slot.exit_rad, kPi);
  // a/D = 0.05 down-milling: cos φ_st = 2a/D − 1 = −0.9.
  EXPECT_NEAR(std::cos(engagement_from_immersion(0.05, MillingDirection::Down).entry_rad), -0.9, 1e-15);
  const auto deg = engagement_from_degrees(30.0, 120.0);
  EXPECT_NEAR(deg.entry_rad, kPi / 6.0, 1e-15);
}

// Every lobe point must satisfy the characteristic equation it came from, det(I + ΛαG) = 0, with
// Λ rebuilt from the reported (speed, depth, chatter frequency) alone: this checks the depth, the
// speed mapping and the branch of the phase together (a wrong branch of ψ = atan κ shifts ωτ by
// π and leaves a residual of order 1). Cases: symmetric 2-DOF, asymmetric 2-DOF (both roots),
// with cross FRFs, and 1-DOF. Tolerance 1e-9 relative to the terms: round-off.
TEST(Stability, LobePointsSatisfyTheCharacteristicEquation) {
  const std::vector<double> grid = uniform_grid(600.0, 1500.0, 0.5);
  const Mode other{0.05, 0.02, 1100.0};
  struct Case {
    MillingFrfs frfs;
    double immersion;
    MillingDirection dir;
  };
  std::vector<Case> cases;
  cases.push_back({modal_milling_frfs({kBench}, {kBench}, grid), 0.05, MillingDirection::Down});
  cases.push_back({modal_milling_frfs({kBench}, {other}, grid), 0.5, MillingDirection::Up});
  MillingFrfs coupled = modal_milling_frfs({kBench}, {other}, grid);
  coupled.xy = modal_frf({Mode{0.2, 0.015, 1000.0}}, grid);
  coupled.yx = coupled.xy;
  cases.push_back({coupled, 0.3, MillingDirection::Down});
  cases.push_back({modal_milling_frfs({kBench}, {}, grid), 1.0, MillingDirection::Down});
  int roots_seen[2] = {0, 0};
  for (const Case& c : cases) {
    const CuttingConditions cc{3, kKt, 0.3, engagement_from_immersion(c.immersion, c.dir)};
    ZeroOrderOptions o;
    o.speeds = {3000.0, 30000.0, 500};
    const ZeroOrderResult r = zero_order_lobes(c.frfs, cc, o);
    const std::vector<LobePoint> points = r.points();
    ASSERT_FALSE(points.empty());
    for (const LobePoint& p : points) {
      const auto i = static_cast<std::size_t>(std::lower_bound(grid.begin(), grid.end(), p.chatter_hz - 1e-9) - grid.begin());
      ASSERT_LT(i, grid.size());
      Eigen::Matrix2cd g;
      g << c.frfs.xx.values[i], c.frfs.xy ? c.frfs.xy->values[i] : Complex(0.0), c.frfs.yx ? c.frfs.yx->values[i] : Complex(0.0),
          c.frfs.rigid_y ? Complex(0.0)
          : c.frfs.yy    ? c.frfs.yy->values[i]
                         : c.frfs.xx.values[i];
      ASSERT_LT(characteristic_residual(r.alpha, g, 3, kKt, p.speed_rpm, p.depth_m, p.chatter_hz), 1e-9)
          << "lobe " << p.lobe << " root " << p.root << " at " << p.speed_rpm << " rpm";
      ++roots_seen[p.root];
    }
  }
  EXPECT_GT(roots_seen[0], 0);
  EXPECT_GT(roots_seen[1], 0);  // the second root of the quadratic is used, not only the first
}

// Lobe mapping: speeds positive and inside the range, depths positive; ωτ = 2πk + ε with
// ε ∈ (0, 2π) means floor(f_c τ) = k for every point; at one chatter frequency and root, lobe k's
// speed lies strictly between lobes k+1 and k−1; the lobes' lowest points move to lower speeds as
// k grows; the envelope never drops below the floor and reaches it within 0.5 % on a fine grid.
TEST(Stability, LobeMappingAndEnvelope) {
  const MillingFrfs frfs = modal_milling_frfs({kBench}, {kBench}, uniform_grid(500.0, 2000.0, 0.25));
  const CuttingConditions cc = cutting(2, 0.05);
  ZeroOrderOptions o;
  o.speeds = {4000.0, 30000.0, 4000};
  const ZeroOrderResult r = zero_order_lobes(frfs, cc, o);
  ASSERT_GE(r.lobes, 5);
  // The per-lobe frequency windows only skip work: every (lobe, root, frequency) of the table whose
  // speed falls in the range is a point, counted here without windows.
  const std::vector<LobePoint> points = r.points();
  std::size_t brute = 0;
  for (int k = 0; k <= r.lobes; ++k)
    for (int root = 0; root < 2; ++root)
      for (std::size_t i = 0; i < r.table.chatter_hz.size(); ++i) {
        const double n = r.table.chatter_hz[i] * 60.0 / (cc.teeth * (r.table.phase[root][i] + k));
        brute += r.table.depth_m[root][i] > 0.0 && n >= o.speeds.min_rpm && n <= o.speeds.max_rpm;
      }
  EXPECT_EQ(points.size(), brute);
  std::map<std::tuple<int, double>, std::map<int, double>> by_freq;  // (root, f) → lobe → speed
  std::map<int, LobePoint> lowest;
  for (const LobePoint& p : points) {
    EXPECT_GT(p.depth_m, 0.0);
    EXPECT_GE(p.speed_rpm, o.speeds.min_rpm);
    EXPECT_LE(p.speed_rpm, o.speeds.max_rpm);
    const double waves = p.chatter_hz * 60.0 / (cc.teeth * p.speed_rpm);
    EXPECT_EQ(static_cast<int>(std::floor(waves)), p.lobe) << waves;
    by_freq[{p.root, p.chatter_hz}][p.lobe] = p.speed_rpm;
    if (!lowest.count(p.lobe) || p.depth_m < lowest[p.lobe].depth_m) lowest[p.lobe] = p;
  }
  for (const auto& [key, lobes] : by_freq)
    for (auto it = std::next(lobes.begin()); it != lobes.end(); ++it)
      if (std::prev(it)->first == it->first - 1) EXPECT_LT(it->second, std::prev(it)->second);
  std::erase_if(lowest, [&](const auto& kv) { return kv.second.speed_rpm < 1.01 * o.speeds.min_rpm; });  // cut off by the range
  ASSERT_GE(lowest.size(), 4u);
  for (auto it = std::next(lowest.begin()); it != lowest.end(); ++it)
    EXPECT_LT(it->second.speed_rpm, std::prev(it)->second.speed_rpm) << "lobe " << it->first;
  double env_min = std::numeric_limits<double>::infinity();
  for (const EnvelopePoint& e : r.envelope) {
    ASSERT_GE(e.lobe, 0);
    EXPECT_GE(e.depth_m, r.floor_depth_m * (1.0 - 1e-12));
    env_min = std::min(env_min, e.depth_m);
  }
  EXPECT_LT(env_min / r.floor_depth_m, 1.005);
  // Pockets: local maxima of the envelope, deepest first.
  const auto pockets = stability_pockets(r.envelope, 3);
  ASSERT_EQ(pockets.size(), 3u);
  EXPECT_GE(pockets[0].depth_m, pockets[1].depth_m);
  EXPECT_GT(pockets[2].depth_m, 2.0 * r.floor_depth_m);
}

// Too few lobes for the low end of the speed range: a warning that names the lobe count needed.
TEST(Stability, TooFewLobesAreReported) {
  const MillingFrfs frfs = modal_milling_frfs({kBench}, {kBench}, uniform_grid(500.0, 2000.0, 0.5));
  ZeroOrderOptions o;
  o.speeds = {3000.0, 30000.0, 500};
  o.lobes = 2;
  const ZeroOrderResult r = zero_order_lobes(frfs, cutting(2, 0.5), o);
  bool warned = false;
  for (const auto& w : r.warnings) warned |= w.find("ZeroOrderOptions::lobes") != std::string::npos;
  EXPECT_TRUE(warned);
  for (const LobePoint& p : r.points()) EXPECT_LE(p.lobe, 2);
}

// With no cutting the monodromy matrix is exp(A₀τ): ρ = e^{−ζω_nτ} exactly, and with two modes
// the slower-decaying one. 1e-9: the product of m Padé exponentials (observed ~1e-11).
TEST(Stability, SpectralRadiusAtZeroDepthIsFreeDecay) {
  const Mode second{0.1, 0.05, 400.0};
  for (int m : {10, 40}) {
    const FullDiscretization sd1(ModalModel{{kBench}, {}}, cutting(2, 0.05), m);
    const FullDiscretization sd2(ModalModel{{kBench}, {second}}, cutting(2, 1.0), m);
    for (double rpm : {5000.0, 12345.0, 25000.0}) {
      const double tau = 60.0 / (2.0 * rpm);
      const double decay1 = std::exp(-kBench.damping_ratio * omega_of(kBench.frequency_hz) * tau);
      const double decay2 = std::exp(-second.damping_ratio * omega_of(second.frequency_hz) * tau);
      EXPECT_NEAR(sd1.spectral_radius(rpm, 0.0) / decay1, 1.0, 1e-9);
      EXPECT_NEAR(sd2.spectral_radius(rpm, 0.0) / std::max(decay1, decay2), 1.0, 1e-9);
    }
  }
}

// N = 4 teeth in a slot: two teeth 90° apart always cut and the sin2φ, cos2φ terms of their
// directional matrices cancel, so A(t) = (N/2π)α exactly. The delay equation is then time
// invariant and the zero-order condition is its exact characteristic equation, so
// semi-discretization must converge to it. Reference: zero-order on a 0.02 Hz grid (its own error
// < 1e-5 near lobe bottoms). Compared at the speeds of a 2000 rpm grid where the envelope is below
// twice the floor (near lobe bottoms, away from the cusps where a tiny shift of a lobe changes the
// depth at a fixed speed a lot). The error grows with the chatter waves per tooth period f_c τ
// over m: observed at m = 40 ≤ 1.3 % (lobe 1 at 8000 rpm, f_c τ ≈ 1.9), ≤ 0.34 % on lobe 0; we
// allow 2 %. It falls 4.0–4.1× per doubling of m (second order): we require ≥ 3×.
TEST(Stability, FullDiscretizationConvergesToZeroOrderWhenTimeInvariant) {
  const std::vector<double> grid = uniform_grid(850.0, 1100.0, 0.02);
  const CuttingConditions cc = cutting(4, 1.0);
  for (const bool two_dof : {false, true}) {
    const std::vector<Mode> y = two_dof ? std::vector<Mode>{kBench} : std::vector<Mode>{};
    ZeroOrderOptions zo;
    zo.speeds = {8000.0, 24000.0, 9};
    const ZeroOrderResult z = zero_order_lobes(modal_milling_frfs({kBench}, y, grid), cc, zo);
    std::vector<EnvelopePoint> bottoms;
    for (const EnvelopePoint& e : z.envelope)
      if (e.depth_m < 2.0 * z.floor_depth_m) bottoms.push_back(e);
    ASSERT_GE(bottoms.size(), 3u);
    double prev_err = 0.0;
    for (int m : two_dof ? std::vector<int>{40} : std::vector<int>{20, 40, 80}) {
      const FullDiscretization sd(ModalModel{{kBench}, y}, cc, m);
      double worst = 0.0;
      for (const EnvelopePoint& e : bottoms) {
        const BoundaryPoint b = sd.boundary(e.speed_rpm, 2.0 * e.depth_m, 8, 1e-8);
        ASSERT_EQ(b.kind, BoundaryKind::Hopf) << e.speed_rpm;
        EXPECT_EQ(b.lobe, e.lobe) << e.speed_rpm;
        EXPECT_NEAR(b.chatter_hz / e.chatter_hz, 1.0, 2e-3) << e.speed_rpm;
        worst = std::max(worst, std::abs(b.depth_m / e.depth_m - 1.0));
      }
      if (m == 40) EXPECT_LT(worst, 0.02) << (two_dof ? "2-DOF" : "1-DOF");
      if (prev_err > 0.0) EXPECT_GT(prev_err / worst, 3.0) << "m = " << m;
      prev_err = worst;
    }
  }
}

// The benchmark at a/D = 0.05 down-milling (1-DOF): semi-discretization finds period-doubling
// (flip) lobes that the zero-order method cannot (it has no time-varying directional factors).
// At 17000 rpm the boundary is a flip: multiplier −1 (real), chatter at (j + ½) × the tooth
// passing frequency (to the DFT's resolution: exact here because the multiplier is real), and the
// depth is less than 60 % of the zero-order envelope (observed 43 %). At 22000 rpm, a Hopf lobe
// bottom, the two methods agree within 5 % (observed 2.5 %: the time variation is strong at low
// immersion, so no closer agreement is expected).
TEST(Stability, LowImmersionFlipLobesThatZeroOrderMisses) {
  const CuttingConditions cc = cutting(2, 0.05);
  const FullDiscretization sd(ModalModel{{kBench}, {}}, cc, 40);
  ZeroOrderOptions zo;
  zo.speeds = {17000.0, 22000.0, 2};
  const ZeroOrderResult z = zero_order_lobes(modal_milling_frfs({kBench}, {}, uniform_grid(600.0, 1300.0, 0.05)), cc, zo);
  const BoundaryPoint flip = sd.boundary(17000.0, 0.02, 50, 1e-6);
  EXPECT_EQ(flip.kind, BoundaryKind::Flip);
  EXPECT_LT(flip.multiplier.real(), 0.0);
  EXPECT_EQ(flip.multiplier.imag(), 0.0);
  const double waves = flip.chatter_hz * 60.0 / (2.0 * 17000.0);
  EXPECT_NEAR(waves - std::floor(waves), 0.5, 1e-9);
  EXPECT_LT(flip.depth_m, 0.6 * z.envelope[0].depth_m);
  const BoundaryPoint hopf = sd.boundary(22000.0, 0.02, 50, 1e-6);
  EXPECT_EQ(hopf.kind, BoundaryKind::Hopf);
  EXPECT_NEAR(hopf.depth_m / z.envelope[1].depth_m, 1.0, 0.05);
  // Over the whole benchmark range some speeds have flip boundaries, and the CSV names them.
  BoundaryOptions so;
  so.speeds = {5000.0, 25000.0, 41};
  so.max_depth_m = 0.02;
  const BoundaryResult r = stability_boundary(ModalModel{{kBench}, {}}, cc, so);
  const auto flips = std::count_if(r.boundary.begin(), r.boundary.end(),
                                   [](const BoundaryPoint& b) { return b.kind == BoundaryKind::Flip; });
  EXPECT_GT(flips, 5);
  EXPECT_NE(format_boundary_csv(r).find(",flip,"), std::string::npos);
}

// The boundary is where ρ crosses 1: just below it ρ < 1, just above ρ ≥ 1.
TEST(Stability, BoundaryBracketsTheSpectralRadiusCrossing) {
  const FullDiscretization sd(ModalModel{{kBench}, {kBench}}, cutting(2, 0.5, MillingDirection::Up), 30);
  for (double rpm : {7000.0, 15000.0}) {
    const BoundaryPoint b = sd.boundary(rpm, 0.005, 40, 1e-6);
    ASSERT_NE(b.kind, BoundaryKind::None);
    EXPECT_LT(sd.spectral_radius(rpm, b.depth_m * (1.0 - 1e-5)), 1.0);
    EXPECT_GE(sd.spectral_radius(rpm, b.depth_m * (1.0 + 1e-5)), 1.0);
    const Eigen::MatrixXd map = sd.spectral_radius_map({rpm}, {0.5 * b.depth_m, 2.0 * b.depth_m});
    EXPECT_LT(map(0, 0), 1.0);
    EXPECT_GT(map(0, 1), 1.0);
  }
}

TEST(Stability, BadInputIsRejected) {
  const MillingFrfs frfs = modal_milling_frfs({kBench}, {}, uniform_grid(800.0, 1100.0, 1.0));
  ZeroOrderOptions o;
  o.speeds = {5000.0, 25000.0, 100};
  EXPECT_THROW(engagement_from_immersion(0.0, MillingDirection::Up), InvalidArgument);
  EXPECT_THROW(engagement_from_immersion(1.2, MillingDirection::Down), InvalidArgument);
  EXPECT_THROW(engagement_from_immersion(-0.1, MillingDirection::Down), InvalidArgument);
  EXPECT_THROW(engagement_from_immersion(std::nan(""), MillingDirection::Down), InvalidArgument);
  EXPECT_THROW(engagement_from_degrees(90.0, 30.0), InvalidArgument);
  EXPECT_THROW(engagement_from_degrees(0.0, 200.0), InvalidArgument);
  CuttingConditions bad = cutting(2, 0.5);
  bad.tangential_coefficient = -6e8;
  EXPECT_THROW(zero_order_lobes(frfs, bad, o), InvalidArgument);
  bad = cutting(2, 0.5);
  bad.radial_ratio = -0.3;
  EXPECT_THROW(zero_order_lobes(frfs, bad, o), InvalidArgument);
  bad = cutting(0, 0.5);
  EXPECT_THROW(zero_order_lobes(frfs, bad, o), InvalidArgument);
  for (auto [lo, hi] : {std::pair{5000.0, 5000.0}, {9000.0, 5000.0}, {0.0, 5000.0}, {-100.0, 5000.0}}) {
    ZeroOrderOptions e = o;
    e.speeds = {lo, hi, 100};
    try {
      zero_order_lobes(frfs, cutting(2, 0.5), e);
      ADD_FAILURE() << "accepted " << lo << ":" << hi;
    } catch (const InvalidArgument& ex) {
      EXPECT_NE(std::string(ex.what()).find("rpm"), std::string::npos) << ex.what();
    }
  }
  // FRFs: one cross FRF alone, grids that differ, NaN, a rigid y with a y FRF.
  MillingFrfs half = frfs;
  half.rigid_y = false;
  half.xy = frfs.xx;
  EXPECT_THROW(zero_order_lobes(half, cutting(2, 0.5), o), InputError);
  MillingFrfs shifted = frfs;
  shifted.rigid_y = false;
  shifted.yy = modal_frf({kBench}, uniform_grid(800.5, 1100.5, 1.0));
  EXPECT_THROW(zero_order_lobes(shifted, cutting(2, 0.5), o), InputError);
  MillingFrfs nan = frfs;
  nan.xx.values[10] = Complex(std::nan(""), 0.0);
  EXPECT_THROW(zero_order_lobes(nan, cutting(2, 0.5), o), InputError);
  MillingFrfs contradictory = frfs;
  contradictory.yy = frfs.xx;
  EXPECT_THROW(contradictory.check(), InvalidArgument);
  // An FRF that cannot chatter (positive real: Λ_R > 0 at every frequency).
  MillingFrfs stiff = frfs;
  for (auto& v : stiff.xx.values) v = Complex(1e-7, 0.0);
  EXPECT_THROW(zero_order_lobes(stiff, cutting(2, 1.0), o), NumericalError);
  // Semi-discretization: no x mode, an undamped or massless mode, too few intervals, bad depth.
  EXPECT_THROW(FullDiscretization(ModalModel{{}, {kBench}}, cutting(2, 0.5)), InvalidArgument);
  EXPECT_THROW(FullDiscretization(ModalModel{{Mode{0.04, 0.0, 900.0}}, {}}, cutting(2, 0.5)), InvalidArgument);
  EXPECT_THROW(FullDiscretization(ModalModel{{Mode{-0.04, 0.01, 900.0}}, {}}, cutting(2, 0.5)), InvalidArgument);
  EXPECT_THROW(FullDiscretization(ModalModel{{kBench}, {}}, cutting(2, 0.5), 2), InvalidArgument);
  const FullDiscretization sd(ModalModel{{kBench}, {}}, cutting(2, 0.5), 20);
  EXPECT_THROW(sd.spectral_radius(10000.0, -1e-3), InvalidArgument);
  EXPECT_THROW(sd.spectral_radius(0.0, 1e-3), InvalidArgument);
  EXPECT_THROW(sd.boundary(10000.0, 0.0), InvalidArgument);
}

// ---- The boundary with its error estimate -------------------------------------------------------

namespace {

// The converged limit at one speed, computed here independently of stability_boundary's level
// choice: the lowest root of ρ = 1 at m and 2m steps (fixed-level scans from 0 in 40 steps up to
// `ceiling`, regula falsi to 1e-9), extrapolated a_{2m} + (a_{2m} − a_m)/7 (third order).
double converged_limit(const ModalModel& model, const CuttingConditions& cc, double rpm, double ceiling, int m) {
  const double a1 = FullDiscretization(model, cc, m).boundary(rpm, ceiling, 40, 1e-9).depth_m;
  const double a2 = FullDiscretization(model, cc, 2 * m).boundary(rpm, ceiling, 40, 1e-9).depth_m;
  return a2 + (a2 - a1) / 7.0;
}

}  // namespace

// Issue 16's aim: at default settings the 1-DOF benchmark's depths (a/D = 0.05 and slotting,
// down-milling, 5000–25 000 rpm) lie within 1 % of the converged limit. The limit comes from 320
// and 640 steps extrapolated (its own error below 1e-4 relative: the two levels differ by < 7e-4).
// 21 speeds per case (every 1000 rpm). Observed worst, at 41 speeds: 0.15 % (a/D 0.05), 0.56 %
// (slot). The result's own estimate meets the 1 % target.
TEST(Stability, DefaultBoundaryIsWithinOnePercentOfTheConvergedLimit) {
  for (const double immersion : {0.05, 1.0}) {
    const CuttingConditions cc = cutting(2, immersion);
    BoundaryOptions o;
    o.speeds = {5000.0, 25000.0, 21};
    const BoundaryResult r = stability_boundary(ModalModel{{kBench}, {}}, cc, o);
    EXPECT_LE(r.worst_relative_error(), 0.01);
    for (const BoundaryPoint& b : r.boundary) {
      if (b.kind == BoundaryKind::None) continue;
      const double limit = converged_limit(ModalModel{{kBench}, {}}, cc, b.speed_rpm, 1.05 * b.depth_m, 320);
      EXPECT_NEAR(b.depth_m / limit, 1.0, 0.01) << "a/D " << immersion << " at " << b.speed_rpm << " rpm";
      EXPECT_GT(b.depth_error_m, 0.0);
      EXPECT_GE(b.steps, 32);
    }
  }
}

// Parallel work is split into blocks of speeds whose walk depends on nothing outside them: 1, 2 and
// 4 threads give bit-identical boundaries (2-DOF, 37 speeds: blocks of 8 and a short last one).
TEST(Stability, BoundaryIsIdenticalForAnyThreadCount) {
  const Mode other{0.05, 0.02, 1100.0};
  BoundaryOptions o;
  o.speeds = {6000.0, 24000.0, 37};
  std::vector<BoundaryResult> runs;
  for (int threads : {1, 2, 4}) {
    o.parallel.threads = threads;
    runs.push_back(stability_boundary(ModalModel{{kBench}, {other}}, cutting(3, 0.3), o));
  }
  for (std::size_t t = 1; t < runs.size(); ++t) {
    ASSERT_EQ(runs[t].boundary.size(), runs[0].boundary.size());
    EXPECT_EQ(runs[t].evaluations, runs[0].evaluations);
    for (std::size_t i = 0; i < runs[0].boundary.size(); ++i) {
      const BoundaryPoint &a = runs[0].boundary[i], &b = runs[t].boundary[i];
      EXPECT_EQ(std::memcmp(&a.depth_m, &b.depth_m, sizeof(double)), 0) << i;
      EXPECT_EQ(std::memcmp(&a.depth_error_m, &b.depth_error_m, sizeof(double)), 0) << i;
      EXPECT_EQ(std::memcmp(&a.chatter_hz, &b.chatter_hz, sizeof(double)), 0) << i;
      EXPECT_EQ(a.kind, b.kind);
      EXPECT_EQ(a.steps, b.steps);
    }
  }
  // The spectral-radius map too.
  const FullDiscretization fd(ModalModel{{kBench}, {}}, cutting(2, 0.05), 40);
  const std::vector<double> speeds = {7000.0, 9000.0, 11000.0, 13000.0, 15000.0}, depths = {1e-3, 2e-3};
  const Eigen::MatrixXd one = fd.spectral_radius_map(speeds, depths, ParallelOptions{1});
  const Eigen::MatrixXd four = fd.spectral_radius_map(speeds, depths, ParallelOptions{4});
  EXPECT_EQ(std::memcmp(one.data(), four.data(), sizeof(double) * static_cast<std::size_t>(one.size())), 0);
}

// A tighter target costs more steps and meets it; a loose one fewer. Bad options are refused
// naming the field.
TEST(Stability, ToleranceSetsTheStepsAndBadOptionsAreRefused) {
  BoundaryOptions o;
  o.speeds = {9000.0, 11000.0, 3};
  o.tolerance = 0.05;
  const BoundaryResult loose = stability_boundary(ModalModel{{kBench}, {}}, cutting(2, 1.0), o);
  o.tolerance = 1e-4;
  const BoundaryResult tight = stability_boundary(ModalModel{{kBench}, {}}, cutting(2, 1.0), o);
  EXPECT_LE(tight.worst_relative_error(), 1e-4);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_GE(tight.boundary[i].steps, loose.boundary[i].steps);
  using Edit = std::function<void(BoundaryOptions&)>;
  for (const Edit& bad :
       std::vector<Edit>{[](BoundaryOptions& b) { b.tolerance = 0.0; }, [](BoundaryOptions& b) { b.steps = 3; },
                         [](BoundaryOptions& b) { b.degree = 4; }, [](BoundaryOptions& b) { b.parallel.threads = -1; }}) {
    BoundaryOptions b = o;
    bad(b);
    EXPECT_THROW(b.check(), InvalidArgument);
  }
  try {
    BoundaryOptions b = o;
    b.tolerance = 2.0;
    b.check();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("BoundaryOptions::tolerance"), std::string::npos) << e.what();
  }
}

// Best speeds: maxima whose prominence is at least 2 % of their depth. A wiggle of 0.04 % on a
// flank (the 13 787 and 13 841 rpm) is no pocket; the two real pockets are, deepest
// first; the range ends are never pockets.
TEST(Stability, PocketsNeedProminence) {
  std::vector<EnvelopePoint> env;
  for (int i = 0; i <= 100; ++i) {
    const double x = i / 100.0;
    double d = 1.0 + 2.0 * std::exp(-std::pow((x - 0.3) / 0.05, 2)) + 3.0 * std::exp(-std::pow((x - 0.7) / 0.05, 2));
    if (i == 50) d += 0.0004 * d;  // a ripple on the flank between them, from a rising depth
    env.push_back({10000.0 + 100.0 * i, d * 1e-3 + 1e-3 * x, 900.0, 1});
  }
  const std::vector<EnvelopePoint> pockets = stability_pockets(env, 5);
  ASSERT_EQ(pockets.size(), 2u);
  EXPECT_DOUBLE_EQ(pockets[0].speed_rpm, 17000.0);
  EXPECT_DOUBLE_EQ(pockets[1].speed_rpm, 13000.0);
  EXPECT_EQ(stability_pockets(env, 5, 0.0).size(), 2u + (env[50].depth_m > env[49].depth_m && env[50].depth_m > env[51].depth_m));
  EXPECT_THROW(stability_pockets(env, 5, 1.5), InvalidArgument);
}
