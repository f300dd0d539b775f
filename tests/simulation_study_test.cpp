// Tests of the simulation study (studies/simulation.hpp): the simulated stability map against the
// full-discretization boundary, the same map for any thread count and any sharding (part files
// through their text), refused parts, and the study's dynamics from the lobes study's sources.
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <string>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/studies/simulation.hpp"
#include "toolpoint/studies/simulation_io.hpp"
#include "support/field_values.hpp"

using namespace toolpoint;

namespace {

const Mode kBench{0.03993, 0.011, 922.0};  // docs/reference.md §7

SimulatedMapOptions bench_map(int speeds, int depths) {
  SimulatedMapOptions o;
  o.cutter = uniform_cutter(2, 0.02);
  o.force = {6e8, 1.0 / 3.0};
  o.cut.feed_per_tooth_m = 1e-4;
  o.cut.engagement = engagement_from_immersion(0.05, MillingDirection::Down);
  o.simulation.revolutions = 40;
  o.speeds = {6000.0, 20000.0, speeds};
  o.depths = {0.2e-3, 6e-3, depths};
  return o;
}

ToolDynamics bench_dynamics() {
  ModalModel m;
  m.x = {kBench};
  return tool_dynamics(m);
}

void expect_same(const SimulatedMap& a, const SimulatedMap& b) {
  ASSERT_EQ(a.rows.size(), b.rows.size());
  EXPECT_EQ(a.header.fingerprint, b.header.fingerprint);
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].speed_index, b.rows[i].speed_index);
    EXPECT_EQ(a.rows[i].stable, b.rows[i].stable);
    for (std::size_t d = 0; d < a.rows[i].stable.size(); ++d) {
      // Bit for bit (NaN where no chatter frequency: compare the bits' meaning).
      for (auto m : {&SimulatedMapRow::growth, &SimulatedMapRow::chatter_metric, &SimulatedMapRow::chatter_hz,
                     &SimulatedMapRow::sle_m, &SimulatedMapRow::peak_force_n})
        EXPECT_TRUE(((a.rows[i].*m)[d] == (b.rows[i].*m)[d]) || (std::isnan((a.rows[i].*m)[d]) && std::isnan((b.rows[i].*m)[d])));
    }
  }
  EXPECT_EQ(format_table_csv(simulated_map_table(a)), format_table_csv(simulated_map_table(b)));
}

}  // namespace

// The map's lowest unstable depth per speed brackets full-discretization's converged limit: the
// grid's depth below it is stable and the one at or above unstable, with the simulation's ±3 %
// (Simulation.StableUnstableSwitchBracketsTheFullDiscretizationLimit) added to one depth step.
TEST(SimulatedMap, LowestUnstableDepthIsTheFullDiscretizationLimit) {
  SimulatedMapOptions o = bench_map(8, 30);
  ModalModel model;
  model.x = {kBench};
  const SimulatedMap m = run_simulated_map(bench_dynamics(), o);
  BoundaryOptions bo;
  bo.speeds = o.speeds;
  bo.speeds.points = 8;
  bo.tolerance = 1e-3;
  const BoundaryResult fd = stability_boundary(model, {2, 6e8, 1.0 / 3.0, o.cut.engagement}, bo);
  const double step = (o.depths.max_m - o.depths.min_m) / (o.depths.points - 1);
  for (std::size_t i = 0; i < m.boundary.size(); ++i) {
    const double limit = fd.boundary[i].depth_m;
    if (limit > o.depths.max_m) continue;
    EXPECT_NEAR(m.boundary[i].depth_m, limit, step + 0.03 * limit) << m.boundary[i].speed_rpm << " rpm";
  }
}

// Identical results for any thread count and any sharding; the parts go through their text.
TEST(SimulatedMap, SameForAnyThreadCountAndSharding) {
  SimulatedMapOptions o = bench_map(5, 12);
  o.parallel.threads = 1;
  const SimulatedMap one = run_simulated_map(bench_dynamics(), o);
  o.parallel.threads = 3;
  expect_same(one, run_simulated_map(bench_dynamics(), o));
  std::vector<SimulatedMapPart> parts;
  for (int i : {2, 0, 1}) {
    const std::string text = format_simulated_map_part(run_simulated_map_part(bench_dynamics(), o, i, 3));
    parts.push_back(parse_simulated_map_part(text, fmt::format("part-{}.json", i)));
    EXPECT_EQ(format_simulated_map_part(parts.back()), text);  // exact round trip
  }
  expect_same(one, merge_simulated_map_parts(parts, {"part-2.json", "part-0.json", "part-1.json"}));
}

// Parts that cannot be merged, and damaged parts, are refused naming the file and the reason.
TEST(SimulatedMap, PartsAreCheckedBeforeMerging) {
  const SimulatedMapOptions o = bench_map(3, 4);
  const SimulatedMapPart p0 = run_simulated_map_part(bench_dynamics(), o, 0, 2),
                         p1 = run_simulated_map_part(bench_dynamics(), o, 1, 2);
  auto merge_refused = [](const std::vector<SimulatedMapPart>& p, const std::vector<std::string>& names,
                          const std::string& what) {
    try {
      merge_simulated_map_parts(p, names);
      ADD_FAILURE() << "merged; expected " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_FALSE(e.hint().empty());
    }
  };
  // The verdict is the shared one of every sharded study (check_shard_set, tests/shards_test.cpp).
  merge_refused({p0}, {"a.json"}, "shard(s) 1 of 2 missing");
  merge_refused({p0, p0, p1}, {"a.json", "b.json", "c.json"}, "shard 0 of 2 is given 2 times: a.json and b.json");
  SimulatedMapOptions other = o;
  other.cut.feed_per_tooth_m = 2e-4;
  merge_refused({p0, run_simulated_map_part(bench_dynamics(), other, 1, 2)}, {"a.json", "x.json"},
                "x.json (shard 1 of 2) belongs to another study");
  auto parse_refused = [](const std::string& text, const std::string& what) {
    try {
      parse_simulated_map_part(text, "p.json");
      ADD_FAILURE() << "accepted; expected " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("p.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string t = format_simulated_map_part(p0);
  parse_refused("{}", "not a toolpoint simulated map part file");
  std::string edited = t;
  const std::size_t at = edited.find("\"growth\":[\"0x1.") + 15;
  edited[at] = edited[at] == '0' ? '1' : '0';
  parse_refused(edited, "checksum");
  std::string header = t;
  const std::size_t feed = header.find("\"feed_per_tooth_m\":\"0x1.") + 24;
  header[feed] = header[feed] == '0' ? '1' : '0';
  parse_refused(header, "fingerprint");
}

// The study's dynamics: the lobes study's time-domain modes (given or fitted), planar modes, or a
// rigid tool; the cross FRFs' absence of coupling said; nothing given refused.
TEST(SimulationStudy, DynamicsFromModesFitsOrPlanarModes) {
  SimulationStudyOptions o;
  o.cutter = uniform_cutter(2, 0.02);
  o.force = {6e8, 1.0 / 3.0};
  o.cut = {10000.0, 1e-3, 1e-4, engagement_from_immersion(0.05, MillingDirection::Down)};
  o.simulation.revolutions = 10;
  SimulationInput in;
  in.source.x_modes = {kBench};
  in.source.rigid_y = true;
  const SimulationStudyResult given = run_simulation_study(in, o);
  ASSERT_EQ(given.dynamics.modes.size(), 1u);
  EXPECT_DOUBLE_EQ(given.dynamics.modes[0].shape_x, 1.0 / std::sqrt(kBench.mass_kg));
  EXPECT_EQ(given.dynamics.modes[0].shape_y, 0.0);
  // Fitted to the mode's own FRF (on the lobes study's grid): the same mode to 1e-4.
  SimulationInput fitted;
  fitted.source.frfs = modal_milling_frfs({kBench}, {}, modal_frequency_grid({kBench}));
  fitted.source.rigid_y = true;
  const SimulationStudyResult f = run_simulation_study(fitted, o);
  ASSERT_EQ(f.dynamics.modes.size(), 1u);
  EXPECT_NEAR(f.dynamics.modes[0].frequency_hz, 922.0, 0.1);
  EXPECT_NEAR(f.simulation.mean_force_x_n, given.simulation.mean_force_x_n, 1e-3 * std::abs(given.simulation.mean_force_x_n));
  SimulationInput planar;
  planar.planar_modes = {planar_mode(kBench, kPi / 4)};
  EXPECT_GT(std::abs(run_simulation_study(planar, o).dynamics.receptance(900.0)(0, 1)), 0.0);
  SimulationInput rigid;
  rigid.rigid = true;
  EXPECT_TRUE(run_simulation_study(rigid, o).dynamics.modes.empty());
  rigid.planar_modes = planar.planar_modes;
  EXPECT_THROW(run_simulation_study(rigid, o), InvalidArgument);
  EXPECT_THROW(run_simulation_study(SimulationInput{}, o), InvalidArgument);
  // Figures build from a recorded result.
  EXPECT_NO_THROW(simulation_time_figure(given).check());
  EXPECT_NO_THROW(simulation_poincare_figure(given).check());
  EXPECT_NO_THROW(simulation_spectrum_figure(given).check());
  EXPECT_NO_THROW(simulation_surface_figure(given).check());
}

// The FRF block says which modes couple x and y: the receptance of a tool with a mode at 30° from x
// (coupled), an x mode and a y mode, sampled on a grid fine enough for the fit (0.5 Hz), fitted
// direct FRF by direct FRF and coupled through the cross FRFs, gives back the block within 2 % of
// its largest entry at every frequency checked (the fits' residual, the modes' shapes exactly up to
// it), and the same SLE within 2 %; without the cross FRFs the coupling is lost (the cross
// receptance of the fitted model is 0).
TEST(SimulationStudy, CrossFrfsCoupleTheFittedModes) {
  ToolDynamics truth;
  truth.modes = {planar_mode({0.04, 0.02, 900.0}, kPi / 6), planar_mode({0.08, 0.03, 1500.0}, 0.0),
                 planar_mode({0.06, 0.025, 1200.0}, kPi / 2)};
  MillingFrfs f;
  for (double hz = 300.0; hz <= 3000.0; hz += 0.5) {
    f.xx.frequency_hz.push_back(hz);
    f.xx.values.push_back(truth.receptance(hz)(0, 0));
  }
  f.yy = FrfSeries{f.xx.frequency_hz, {}};
  f.xy = FrfSeries{f.xx.frequency_hz, {}};
  f.yx = FrfSeries{f.xx.frequency_hz, {}};
  for (double hz : f.xx.frequency_hz) {
    const Eigen::Matrix2cd g = truth.receptance(hz);
    f.yy->values.push_back(g(1, 1));
    f.xy->values.push_back(g(0, 1));
    f.yx->values.push_back(g(1, 0));
  }
  SimulationInput in;
  in.source.frfs = f;
  std::vector<ModalFitSummary> fits;
  std::vector<std::string> warnings;
  const ToolDynamics d = simulation_dynamics(in, simulation_fit_options(), 0.02, fits, warnings);
  EXPECT_EQ(d.modes.size(), 3u);
  double top = 0.0;
  for (double hz : {600.0, 900.0, 1200.0, 1500.0, 2000.0}) top = std::max(top, truth.receptance(hz).cwiseAbs().maxCoeff());
  for (double hz : {600.0, 880.0, 900.0, 920.0, 1200.0, 1500.0, 2000.0})
    EXPECT_LT((d.receptance(hz) - truth.receptance(hz)).cwiseAbs().maxCoeff(), 0.02 * top) << hz;
  SimulationStudyOptions o;
  o.cutter = uniform_cutter(3, 0.016);
  o.force = {6e8, 0.3};
  o.cut = {9000.0, 2e-4, 1e-4, engagement_from_immersion(0.2, MillingDirection::Down)};
  o.simulation.revolutions = 60;
  SimulationInput given;
  given.planar_modes = truth.modes;
  const double sle = run_simulation_study(given, o).simulation.sle_m;
  EXPECT_NEAR(run_simulation_study(in, o).simulation.sle_m, sle, 0.02 * std::abs(sle));
  SimulationInput uncoupled = in;
  uncoupled.source.frfs->xy.reset();
  uncoupled.source.frfs->yx.reset();
  EXPECT_EQ(std::abs(simulation_dynamics(uncoupled, simulation_fit_options(), 0.02, fits, warnings).receptance(900.0)(0, 1)),
            0.0);
}

// A simulated map's part file carries every field of SimulationOptions' table but `record` (a map
// keeps no histories: its header sets it false), each moving the map's fingerprint: each field in
// turn set to another valid value, written and read back exactly.
TEST(SimulatedMap, PartFileCarriesEveryTableField) {
  const SimulatedMapOptions plain = bench_map(2, 2);
  const std::uint64_t fingerprint = simulated_map_header(bench_dynamics(), plain).fingerprint;
  for (const OptionField<SimulationOptions>& f : simulation_fields()) {
    if (std::string(f.spec.name) == "record") continue;
    SimulatedMapOptions o = plain;
    const double v = test::other_valid_value(f.spec, f.get(o.simulation));
    ASSERT_FALSE(std::isnan(v)) << f.spec.name;
    f.set(o.simulation, v);
    SimulatedMapPart part;
    part.header = simulated_map_header(bench_dynamics(), o);
    EXPECT_NE(part.header.fingerprint, fingerprint) << f.spec.name;
    const SimulatedMapPart back = parse_simulated_map_part(format_simulated_map_part(part), "p.json");
    EXPECT_EQ(f.get(back.header.options.simulation), v) << f.spec.name;
    EXPECT_EQ(back.header.fingerprint, part.header.fingerprint) << f.spec.name;
  }
}
