// Zero-order lobes with speed-dependent x–y dynamics (zero_order_lobes of SpeedDependentFrfs,
// the lobes study's SpeedModel; docs/spindle-at-speed.md): reductions to the standstill lobes, an
// anisotropic spindle against two independent single-plane models and the Altintas–Budak
// characteristic equation (docs/reference.md §7) evaluated here, and a speed-dependent structure
// against the time-domain simulation. Units SI, frequencies in Hz, speeds in rpm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/lobes.hpp"

using namespace toolpoint;

namespace {

Assembly example() {
  Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  a.grid = {200.0, 5000.0, 4.0};  // coarser than the file's: the tests run many sweeps
  return a;
}

CuttingConditions cut(double immersion = 0.5) {
  return {4, 6e8, 0.3, engagement_from_immersion(immersion, MillingDirection::Down)};
}

LobesStudyOptions options(SpeedModel model, double min_rpm = 5000.0, double max_rpm = 30000.0) {
  LobesStudyOptions o;
  o.cutting = cut();
  o.speeds = {min_rpm, max_rpm, 400};
  o.speed_model = model;
  o.speed_nodes = 6;
  o.parallel.threads = 2;
  return o;
}

LobesStudyResult lobes(const Assembly& a, const LobesStudyOptions& o) {
  LobesInput in;
  in.assembly = a;
  return run_lobes_study(in, o);
}

// The largest relative difference of two envelopes' depths (the same speeds).
double envelope_difference(const std::vector<EnvelopePoint>& a, const std::vector<EnvelopePoint>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t j = 0; j < std::min(a.size(), b.size()); ++j) {
    EXPECT_EQ(a[j].speed_rpm, b[j].speed_rpm);
    EXPECT_EQ(std::isfinite(a[j].depth_m), std::isfinite(b[j].depth_m)) << a[j].speed_rpm << " rpm";
    if (std::isfinite(a[j].depth_m) && std::isfinite(b[j].depth_m))
      worst = std::max(worst, std::abs(a[j].depth_m - b[j].depth_m) / b[j].depth_m);
  }
  return worst;
}

bool says(const std::vector<std::string>& warnings, const std::string& what) {
  return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) { return w.find(what) != std::string::npos; });
}

// |det(I + Λ α G)| / (1 + |Λ tr(αG)| + |Λ² det(αG)|) with Λ = −N a K_t (1 − e^{−iωτ})/(4π),
// τ = 60/(N n) (Altintas & Budak 1995; docs/reference.md §7), for G = [[gxx, gxy], [gyx, gyy]]:
// zero where (n, a, f) is a lobe point.
double characteristic_residual(const CuttingConditions& c, double n, double a, double f, Complex gxx, Complex gxy, Complex gyx,
                               Complex gyy) {
  const Eigen::Matrix2d alpha = directional_factors(c);
  const double tau = 60.0 / (c.teeth * n), w = 2.0 * kPi * f;
  const Complex lam = -static_cast<double>(c.teeth) * a * c.tangential_coefficient * (1.0 - std::exp(Complex(0.0, -w * tau))) /
                      (4.0 * kPi);
  const Complex b00 = alpha(0, 0) * gxx + alpha(0, 1) * gyx, b01 = alpha(0, 0) * gxy + alpha(0, 1) * gyy;
  const Complex b10 = alpha(1, 0) * gxx + alpha(1, 1) * gyx, b11 = alpha(1, 0) * gxy + alpha(1, 1) * gyy;
  const Complex tr = b00 + b11, det = b00 * b11 - b01 * b10;
  const Complex d = 1.0 + lam * tr + lam * lam * det;
  return std::abs(d) / (1.0 + std::abs(lam * tr) + std::abs(lam * lam * det));
}

std::size_t index_of(const std::vector<double>& grid, double f) {
  return static_cast<std::size_t>(std::lower_bound(grid.begin(), grid.end(), f) - grid.begin());
}

}  // namespace

// A speed-independent isotropic assembly: at rest in two planes H_xy = H_yx = 0 exactly and
// H_xx = H_yy = the single-plane tool point; the lobes through the speed-dependent route (forced:
// SpeedModel::Bearings) equal today's standstill lobes to 1e-9 (the routes differ: a speed solved
// per lobe point against one division per point), and Automatic keeps today's path (identical).
TEST(LobesAtSpeed, SpeedIndependentIsotropicAssemblyGivesTodaysLobes) {
  const Assembly a = example();
  const std::vector<double> grid = a.grid.values();
  const SpeedDependentFrfs s = milling_frfs_at_speeds(a, grid, {5000.0, 30000.0}, false, false);
  const FrfSeries standstill = entry(AssemblyModel(a).tool_point(grid), 0);
  for (const MillingFrfs& g : s.frfs)
    for (std::size_t i = 0; i < grid.size(); ++i) {
      EXPECT_EQ(g.xy->values[i], Complex(0.0));
      EXPECT_EQ(g.yx->values[i], Complex(0.0));
      EXPECT_NEAR(std::abs(g.xx.values[i] - standstill.values[i]), 0.0, 1e-12 * std::abs(standstill.values[i]));
      EXPECT_EQ(g.yy->values[i], g.xx.values[i]);
    }
  LobesInput in;
  in.frfs = milling_frfs(AssemblyModel(a), grid);
  const LobesStudyResult today = run_lobes_study(in, options(SpeedModel::Standstill));
  const LobesStudyResult automatic = lobes(a, options(SpeedModel::Automatic));
  EXPECT_EQ(automatic.speed_model, SpeedModel::Standstill);
  EXPECT_EQ(envelope_difference(automatic.envelope, today.envelope), 0.0);
  EXPECT_TRUE(automatic.frf_speeds_rpm.empty());
  const LobesStudyResult forced = lobes(a, options(SpeedModel::Bearings));
  EXPECT_EQ(forced.speed_model, SpeedModel::Bearings);
  EXPECT_LE(envelope_difference(forced.envelope, today.envelope), 1e-9);
  EXPECT_NEAR(forced.zero_order->floor_depth_m, today.zero_order->floor_depth_m, 1e-12 * today.zero_order->floor_depth_m);
  EXPECT_EQ(forced.frf_interpolation_error, 0.0);
  EXPECT_EQ(forced.envelope_interpolation_error, 0.0);
  EXPECT_TRUE(says(forced.warnings, "at each spindle speed"));
}

// A stiffness table flat in speed: Automatic uses the speed model (and says so); at rest (Bearings)
// its lobes are the standstill lobes to 1e-9. Spinning differs (gyroscopic moments), the cross FRF
// appears.
TEST(LobesAtSpeed, FlatStiffnessTableGivesTheStandstillLobes) {
  const Assembly a = example();
  Assembly flat = a;
  for (Bearing& b : flat.spindle.bearings) b.speed_table = {{0.0, b.stiffness, b.damping}, {40000.0, b.stiffness, b.damping}};
  LobesInput in;
  in.frfs = milling_frfs(AssemblyModel(a), a.grid.values());
  const LobesStudyResult today = run_lobes_study(in, options(SpeedModel::Standstill));
  const LobesStudyResult at_rest = lobes(flat, options(SpeedModel::Bearings));
  EXPECT_LE(envelope_difference(at_rest.envelope, today.envelope), 1e-9);
  const LobesStudyResult automatic = lobes(flat, options(SpeedModel::Automatic));
  EXPECT_EQ(automatic.speed_model, SpeedModel::Spinning);
  EXPECT_TRUE(says(automatic.warnings, "the spindle spinning"));
  EXPECT_FALSE(says(automatic.warnings, "uses its constant stiffness"));  // the table is read, not ignored
  EXPECT_GT(envelope_difference(automatic.envelope, today.envelope), 1e-4);
  const SpeedDependentFrfs s = milling_frfs_at_speeds(flat, a.grid.values(), {30000.0}, true, false);
  double cross = 0.0;
  for (const Complex& v : s.frfs[0].xy->values) cross = std::max(cross, std::abs(v));
  EXPECT_GT(cross, 0.0);
}

// Anisotropic bearings (k_y = 0.5 k_x at the front, at rest): the two-plane FRF against two
// uncoupled single-plane assemblies (the x values, the y values), and every lobe point against the
// characteristic equation det(I + Λ α G) = 0 built here from those two FRFs (residual ≤ 1e-9: the
// solved speeds to 1e-10); the floor against the printed a₀, a₁ quadratic of Altintas & Budak
// (docs/reference.md §7) on the same FRFs, to 1e-9.
TEST(LobesAtSpeed, AnisotropicBearingsAgainstTwoSinglePlaneModels) {
  Assembly aniso = example();
  for (int k : {0, 1}) aniso.spindle.bearings[k].stiffness_y = 0.5 * aniso.spindle.bearings[k].stiffness;
  Assembly ax = aniso, ay = aniso;
  for (Bearing& b : ax.spindle.bearings) b.stiffness_y.reset();
  for (Bearing& b : ay.spindle.bearings) {
    if (b.stiffness_y) b.stiffness = *b.stiffness_y;
    b.stiffness_y.reset();
  }
  const std::vector<double> grid = aniso.grid.values();
  const FrfSeries gx = entry(AssemblyModel(ax).tool_point(grid), 0), gy = entry(AssemblyModel(ay).tool_point(grid), 0);
  const LobesStudyOptions o = options(SpeedModel::Automatic);
  const LobesStudyResult r = lobes(aniso, o);
  EXPECT_EQ(r.speed_model, SpeedModel::Spinning);  // Automatic: x ≠ y bearings
  LobesStudyOptions still = o;
  still.speed_model = SpeedModel::Bearings;
  const LobesStudyResult s = lobes(aniso, still);
  ASSERT_TRUE(s.zero_order);
  const auto pts = s.zero_order->points();
  ASSERT_GT(pts.size(), 100u);
  double worst = 0.0;
  for (std::size_t p = 0; p < pts.size(); p += 7) {
    const std::size_t i = index_of(grid, pts[p].chatter_hz);
    worst = std::max(worst, characteristic_residual(o.cutting, pts[p].speed_rpm, pts[p].depth_m, pts[p].chatter_hz, gx.values[i],
                                                    0.0, 0.0, gy.values[i]));
  }
  EXPECT_LE(worst, 1e-9);
  // The floor from a₀Λ² + a₁Λ + 1 = 0, a₀ = G_xx G_yy (α_xx α_yy − α_xy α_yx), a₁ = α_xx G_xx + α_yy G_yy.
  const Eigen::Matrix2d al = directional_factors(o.cutting);
  double floor = INFINITY;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const Complex a0 = gx.values[i] * gy.values[i] * (al(0, 0) * al(1, 1) - al(0, 1) * al(1, 0));
    const Complex a1 = al(0, 0) * gx.values[i] + al(1, 1) * gy.values[i];
    for (double sign : {1.0, -1.0}) {
      const Complex lam = -(a1 + sign * std::sqrt(a1 * a1 - 4.0 * a0)) / (2.0 * a0);
      if (lam.real() >= 0.0) continue;
      const double kappa = lam.imag() / lam.real();
      floor = std::min(floor,
                       -2.0 * kPi * lam.real() * (1.0 + kappa * kappa) / (o.cutting.teeth * o.cutting.tangential_coefficient));
    }
  }
  EXPECT_NEAR(s.zero_order->floor_depth_m, floor, 1e-9 * floor);
  // The anisotropy matters: the lobes of the x model alone (a round tool on the x bearings) differ.
  LobesInput in;
  in.frfs = milling_frfs(AssemblyModel(ax), grid);
  EXPECT_GT(envelope_difference(s.envelope, run_lobes_study(in, options(SpeedModel::Standstill)).envelope), 0.01);
}

// A spinning spindle with a bearing table softening 40 % over 0–30 000 rpm: every lobe point solves
// the characteristic equation with the FRF at its own speed (linear between the nodes, evaluated
// here from the nodes' FRFs) to 1e-9; at a node speed the envelope equals the lobes of that node's
// FRF alone (zero_order_lobes of one FRF) read there, to 1e-12; the interpolation error estimate
// is stated, large with 6 nodes (and said), and falls with 17; a speed outside the table is
// refused, naming it.
TEST(LobesAtSpeed, SpinningSpindleWithABearingTable) {
  Assembly a = example();
  for (Bearing& b : a.spindle.bearings)
    b.speed_table = {{0.0, b.stiffness, b.damping}, {30000.0, 0.6 * b.stiffness, 1.2 * b.damping}};
  LobesStudyOptions o = options(SpeedModel::Automatic);
  const LobesStudyResult few = lobes(a, o);
  EXPECT_EQ(few.frf_speeds_rpm.size(), 11u);  // 6 nodes and their 5 midpoints
  EXPECT_GT(few.envelope_interpolation_error, 0.05);
  EXPECT_TRUE(says(few.warnings, "raise LobesStudyOptions::speed_nodes"));
  o.speed_nodes = 0;  // 17 nodes and their midpoints: the estimated errors fall
  const LobesStudyResult r = lobes(a, o);
  ASSERT_TRUE(r.zero_order);
  EXPECT_EQ(r.frf_speeds_rpm.size(), 33u);
  EXPECT_LT(r.frf_interpolation_error, 0.5 * few.frf_interpolation_error);
  EXPECT_LT(r.envelope_interpolation_error, 0.05);
  EXPECT_TRUE(says(r.warnings, "interpolation error estimated"));
  const SpeedDependentFrfs s = milling_frfs_at_speeds(a, a.grid.values(), r.frf_speeds_rpm, true, false, false,
                                                      ParallelOptions{2});
  const std::vector<double>& grid = s.frfs[0].xx.frequency_hz;
  const auto pts = r.zero_order->points();
  double worst = 0.0;
  for (std::size_t p = 0; p < pts.size(); p += 5) {
    const double n = pts[p].speed_rpm;
    const std::size_t i = index_of(grid, pts[p].chatter_hz);
    std::size_t j = static_cast<std::size_t>(std::upper_bound(s.speed_rpm.begin(), s.speed_rpm.end(), n) - s.speed_rpm.begin());
    j = std::clamp<std::size_t>(j, 1, s.speed_rpm.size() - 1) - 1;
    const double t = std::clamp((n - s.speed_rpm[j]) / (s.speed_rpm[j + 1] - s.speed_rpm[j]), 0.0, 1.0);
    const auto g = [&](const std::optional<FrfSeries>& lo, const std::optional<FrfSeries>& hi) {
      return (1.0 - t) * lo->values[i] + t * hi->values[i];
    };
    const MillingFrfs& l = s.frfs[j];
    const MillingFrfs& h = s.frfs[j + 1];
    worst = std::max(worst, characteristic_residual(o.cutting, n, pts[p].depth_m, pts[p].chatter_hz,
                                                    (1.0 - t) * l.xx.values[i] + t * h.xx.values[i], g(l.xy, h.xy), g(l.yx, h.yx),
                                                    g(l.yy, h.yy)));
  }
  EXPECT_LE(worst, 1e-9);
  // At node speeds: the envelope against the frozen lobes of the node's FRF.
  for (std::size_t j : {2u, 6u, 10u}) {
    ZeroOrderOptions zo;
    zo.speeds = o.speeds;
    const ZeroOrderResult frozen = zero_order_lobes(s.frfs[j], o.cutting, zo);
    const double n = s.speed_rpm[j];
    for (std::size_t e = 0; e < r.envelope.size(); ++e) {
      if (std::abs(r.envelope[e].speed_rpm - n) > 1e-6 * n) continue;
      EXPECT_NEAR(r.envelope[e].depth_m, frozen.envelope[e].depth_m, 1e-12 * frozen.envelope[e].depth_m) << n << " rpm";
    }
  }
  LobesStudyOptions beyond = o;
  beyond.speeds.max_rpm = 35000.0;
  try {
    lobes(a, beyond);
    ADD_FAILURE() << "a speed outside the table was accepted";
  } catch (const InvalidArgument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("LobesStudyOptions::speeds"), std::string::npos) << m;
    EXPECT_NE(m.find("speed_table"), std::string::npos) << m;
    EXPECT_NE(std::string(e.hint()).find("LobesStudyOptions::extrapolate_bearings"), std::string::npos) << e.hint();
  }
  beyond.extrapolate_bearings = true;
  EXPECT_NO_THROW(lobes(a, beyond));
}

// A structure whose mode softens with speed (f_n(n) = 900 Hz (1 − 0.3 n/30 000), the same in x and
// y, modal mass fixed: a spindle whose bearings soften), slotting with 4 teeth. At three speeds
// the speed-dependent zero-order limit a* is checked by the time-domain simulation of the cut with
// that speed's mode (simulation.hpp, independent of the lobes): stable at 0.85 a*, chatter at
// 1.15 a* (the zero-order method against the time domain in slotting: within a few per cent; ±15 %
// leaves room). At each of those speeds the standstill lobes (the 0 rpm mode) give a depth more
// than 20 % away from a*, so the check tells the two apart.
TEST(LobesAtSpeed, SpeedDependentLobesAgainstTheSimulation) {
  const auto mode_at = [](double n) { return Mode{0.05, 0.03, 900.0 * (1.0 - 0.3 * n / 30000.0)}; };
  std::vector<double> f;
  for (double x = 300.0; x <= 1500.0; x += 0.5) f.push_back(x);
  SpeedDependentFrfs s;
  for (double n = 0.0; n <= 30000.0; n += 500.0) {
    s.speed_rpm.push_back(n);
    s.frfs.push_back(modal_milling_frfs({mode_at(n)}, {mode_at(n)}, f));
  }
  const CuttingConditions c = cut(1.0);
  ZeroOrderOptions zo;
  zo.speeds = {6000.0, 30000.0, 49};  // every 500 rpm: the nodes
  const ZeroOrderResult at_speed = zero_order_lobes(s, c, zo);
  const ZeroOrderResult standstill = zero_order_lobes(s.frfs[0], c, zo);
  int checked = 0;
  double last = -1e9;
  for (std::size_t e = 0; e < at_speed.envelope.size() && checked < 3; ++e) {
    const double n = at_speed.envelope[e].speed_rpm, a = at_speed.envelope[e].depth_m;
    if (n < 10000.0 || n - last < 3000.0 || !(std::abs(standstill.envelope[e].depth_m - a) > 0.2 * a)) continue;
    last = n;  // a few spread-out speeds
    ModalModel m;
    m.x = {mode_at(n)};
    m.y = {mode_at(n)};
    SimulationOptions so;
    so.record = false;
    const auto simulate = [&](double depth) {
      return simulate_milling(tool_dynamics(m), uniform_cutter(c.teeth, 0.02), linear_force_law(c),
                              {n, depth, 1e-4, c.engagement}, so);
    };
    EXPECT_TRUE(simulate(0.85 * a).stable) << n << " rpm, a* = " << a;
    EXPECT_FALSE(simulate(1.15 * a).stable) << n << " rpm, a* = " << a;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

// Bad input: FRFs at speeds out of order, or on different grids.
TEST(LobesAtSpeed, SpeedDependentFrfsAreChecked) {
  std::vector<double> f = {100.0, 200.0, 300.0};
  const Mode m{1.0, 0.05, 200.0};
  SpeedDependentFrfs s;
  s.speed_rpm = {1000.0, 500.0};
  s.frfs = {modal_milling_frfs({m}, {m}, f), modal_milling_frfs({m}, {m}, f)};
  EXPECT_THROW(s.check(), InputError);
  s.speed_rpm = {500.0, 1000.0};
  s.frfs[1] = modal_milling_frfs({m}, {m}, {100.0, 200.0, 350.0});
  EXPECT_THROW(s.check(), InputError);
  LobesStudyOptions o = options(SpeedModel::Spinning);
  o.speed_nodes = 1;
  EXPECT_THROW(o.check(), InvalidArgument);
  // The speed model evaluates an assembly: with FRFs alone it is refused, naming the field.
  LobesInput in;
  in.frfs = s.frfs[0];
  try {
    run_lobes_study(in, options(SpeedModel::Spinning));
    ADD_FAILURE() << "a speed model without an assembly was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("LobesStudyOptions::speed_model"), std::string::npos) << e.what();
  }
}
