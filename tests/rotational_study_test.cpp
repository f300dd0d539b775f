// Tests of the rotational study (studies/rotational.hpp): the tap test's FRFs picked from one
// universal file, and the tip block with and without the model-based correction — against the
// static cantilever's closed form (docs/reference.md §5), against rotational_frfs and the correction called
// directly, and against the model's tip block by the coupling path (not the station path the
// correction differences). The CLI tests (cli_test.cpp) only check the plumbing.
// Units: SI (H m/N, L 1/N, N rad/N, P rad/(N·m)); spacing in m; frequencies in Hz.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/joint_data.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/rotational.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

// Static cantilever flexibility (EI = 1, clamp at x = 0, length 1): deflection at x for a unit
// force at ξ, ξ²(3x − ξ)/6 for ξ ≤ x, symmetric otherwise.
double cantilever(double x, double xi) {
  if (xi > x) std::swap(x, xi);
  return xi * xi * (3.0 * x - xi) / 6.0;
}

// H_ij of the static cantilever at the tip and 0.1, 0.2 inward, on three frequencies (the same
// values at each), with the hammer at the points `hammers`.
PointFrfs cantilever_frfs(int hammers = 3) {
  PointFrfs p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < hammers; ++j) {
      const double h = cantilever(1.0 - 0.1 * i, 1.0 - 0.1 * j);
      p.set(i, j, FrfSeries{{10.0, 20.0, 30.0}, {h, h, h}});
    }
  return p;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

// docs/reference.md §5: EI = 1, L = 1, s = 0.1, second order: H = 1/3, N = L = 151/300, P = 31/30 (1e-12:
// round-off of differences of O(1) numbers over s² = 0.01). Without a model the study's block is
// rotational_frfs' own, and says how it was made.
TEST(RotationalStudy, StaticCantileverWithoutModel) {
  RotationalInput in;
  in.frfs = cantilever_frfs();
  RotationalStudyOptions o;
  o.differences.spacing = 0.1;
  const RotationalStudy r = run_rotational_study(in, o);
  ASSERT_EQ(r.block.size(), 3u);
  for (const Block& b : r.block.blocks) {
    EXPECT_NEAR(H_of(b).real(), 1.0 / 3.0, 1e-15);
    EXPECT_NEAR(N_of(b).real(), 151.0 / 300.0, 1e-12);
    EXPECT_NEAR(L_of(b).real(), 151.0 / 300.0, 1e-12);
    EXPECT_NEAR(P_of(b).real(), 31.0 / 30.0, 1e-12);
  }
  EXPECT_EQ(r.block.blocks, rotational_frfs(in.frfs, o.differences).block.blocks);
  EXPECT_FALSE(r.correction);
  EXPECT_EQ(r.order, 2);
  EXPECT_EQ(r.spacing_m, 0.1);
  EXPECT_TRUE(contains(r.method, "order-2 finite differences")) << r.method;
  EXPECT_TRUE(contains(r.method, "spacing s = 0.1 m")) << r.method;
  EXPECT_TRUE(contains(r.method, "P from cross terms")) << r.method;
  EXPECT_EQ(r.reciprocity, "no measurement filled by reciprocity");
  EXPECT_EQ(r.correction_note, "no finite-difference correction");
  const nlohmann::json j = r;
  EXPECT_TRUE(j["correction"].is_null());
  EXPECT_EQ(j["order"], 2);
  EXPECT_TRUE(j["differences"]["p_from_cross_terms"].get<bool>());
  // The figure draws the block: |H| in its first panel is |H00| = 1/3 m/N at every frequency.
  const plot::Figure fig = rotational_figure(r);
  EXPECT_TRUE(contains(fig.title, "order-2")) << fig.title;
  EXPECT_TRUE(contains(fig.title, "s = 100 mm")) << fig.title;
  ASSERT_FALSE(fig.panels.empty());
  ASSERT_FALSE(fig.panels[0].curves.empty());
  for (double y : fig.panels[0].curves[0].y) EXPECT_NEAR(y, 1.0 / 3.0, 1e-15);
  EXPECT_TRUE(contains(fig.panels[0].y.label, "m/N")) << fig.panels[0].y.label;
}

// The hammer at the tip only: L is not measured; with assume_reciprocity it is N (first order on
// a static cantilever: (H00 − H10)/s = 299/600) and the fill is said; P ≈ N·L/H00 = 3(299/600)².
TEST(RotationalStudy, ReciprocityFillsAreSaid) {
  RotationalInput in;
  in.frfs = cantilever_frfs(1);
  RotationalStudyOptions o;
  o.differences.order = 1;
  o.differences.spacing = 0.1;
  EXPECT_THROW(run_rotational_study(in, o), InputError);
  o.differences.assume_reciprocity = true;
  const RotationalStudy r = run_rotational_study(in, o);
  EXPECT_NEAR(L_of(r.block.blocks[0]).real(), 299.0 / 600.0, 1e-12);
  EXPECT_NEAR(P_of(r.block.blocks[0]).real(), 3.0 * (299.0 / 600.0) * (299.0 / 600.0), 1e-12);
  EXPECT_TRUE(contains(r.reciprocity, "RotationalOptions::assume_reciprocity")) << r.reciprocity;
  EXPECT_TRUE(contains(r.reciprocity, "H01 := H10")) << r.reciprocity;
  EXPECT_TRUE(contains(r.method, "Schmitz & Smith")) << r.method;
  EXPECT_FALSE(r.warnings.empty());  // the P approximation
  RotationalStudyOptions bad = o;
  bad.differences.spacing = -0.1;
  EXPECT_THROW(run_rotational_study(in, bad), InvalidArgument);
}

// With the model that made the data: the block is rotational_frfs' minus finite_difference_error's
// (called directly: bit for bit), and that is the model's SH11 by the coupling path to 1e-7 of each
// entry's largest value (station and point coupling are different algebra, and differences of FRFs
// 20 mm apart lose ~4 digits), where the uncorrected P is off by more than 1 %.
TEST(RotationalStudy, TheModelsCorrectionIsTheCorrectionCalledDirectly) {
  Assembly a = example_assembly();
  a.grid = FrequencyGrid{200.0, 3000.0, 20.0};
  TapTestOptions t;
  t.side = TapSide::Holder;
  t.spacing_m = 0.02;
  const TapTest tap = run_tap_test_study(a, t);
  RotationalInput in;
  for (const TapTestFrf& h : tap.frfs) in.frfs.set(h.response, h.hammer, h.frf);
  in.model = a;
  in.side = TapSide::Holder;
  in.model_name = "example.toml";
  RotationalStudyOptions o;
  o.differences.spacing = 0.02;
  std::vector<double> fractions;
  const RotationalStudy r = run_rotational_study(in, o, [&](double x) { fractions.push_back(x); });
  ASSERT_FALSE(fractions.empty());
  EXPECT_EQ(fractions.back(), 1.0);

  const RotationalResult raw = rotational_frfs(in.frfs, o.differences);
  const FiniteDifferenceError e = finite_difference_error(a, TapSide::Holder, raw.block.frequency_hz, in.frfs, o.differences);
  EXPECT_EQ(r.block.blocks, remove_finite_difference_error(raw.block, e).blocks);
  EXPECT_EQ(r.differences.block.blocks, raw.block.blocks);
  ASSERT_TRUE(r.correction);
  EXPECT_EQ(r.correction->max_relative, e.max_relative);
  EXPECT_TRUE(contains(r.correction_note, "estimated on the model example.toml (points on the holder)")) << r.correction_note;

  const BlockSeries exact = AssemblyModel(a).holder_tip(a.grid.values());
  for (int q = 1; q < 4; ++q) {
    double scale = 0.0, raw_error = 0.0, corrected_error = 0.0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const Complex x = exact.blocks[i](q / 2, q % 2);
      scale = std::max(scale, std::abs(x));
      raw_error = std::max(raw_error, std::abs(raw.block.blocks[i](q / 2, q % 2) - x));
      corrected_error = std::max(corrected_error, std::abs(r.block.blocks[i](q / 2, q % 2) - x));
    }
    if (q == 3) EXPECT_GT(raw_error, 0.01 * scale) << "P's truncation error, the point of the correction";
    EXPECT_LT(corrected_error, 1e-7 * scale) << "entry " << q;
  }
}

// A tap test as measurement software numbers it (nodes 101…103, +Y) with a +Z copy at twice the
// values: the datasets picked are the ones written; ambiguity and a missing tip are refused,
// naming the datasets and listing the nodes the file holds.
TEST(RotationalStudy, TapTestFrfsPickTheDatasetsByNodeAndDirection) {
  const PointFrfs written = cantilever_frfs();
  std::vector<UffDataset58> sets;
  for (int copy = 0; copy < 2; ++copy)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        FrfSeries h = *written.h[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
        for (Complex& v : h.values) v *= copy == 0 ? 1.0 : 2.0;
        sets.push_back(uff_from_receptance(h, UffDof{101 + i, copy == 0 ? 2 : 3, 101 + j, copy == 0 ? 2 : 3}, "tap"));
      }
  const UffFile file = parse_uff(format_uff(sets, {.binary = true}).bytes, "tap.uff");
  ASSERT_EQ(file.functions.size(), 18u);

  TapTestFileOptions o;
  const std::string missing = [&] {
    try {
      tap_test_frfs(file, o);
    } catch (const InputError& e) {
      return std::string(e.what()) + " fix: " + e.hint();
    }
    return std::string("nothing thrown");
  }();
  EXPECT_TRUE(contains(missing,
                       "tap.uff: no dataset with response and reference node 1 (the tip: the first of "
                       "TapTestFileOptions::nodes 1,2,3)"))
      << missing;
  EXPECT_TRUE(contains(missing, "the file holds response/reference nodes 101/101 +Y, 102/101 +Y")) << missing;
  o.nodes = {101, 102, 103};
  try {
    tap_test_frfs(file, o);
    ADD_FAILURE() << "two datasets per pair of points accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(),
                         "datasets 0 and 9 both have response node 101 and reference node 101 (directions +Y/+Y "
                         "and +Z/+Z)"))
        << e.what();
  }
  o.direction = 3;
  const TapTestFileFrfs z = tap_test_frfs(file, o);
  o.direction = 2;
  const TapTestFileFrfs y = tap_test_frfs(file, o);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      ASSERT_TRUE(y.frfs.h[i][j]) << i << j;
      EXPECT_EQ(y.dataset[i][j], 3 * j + i);
      EXPECT_EQ(z.dataset[i][j], 9 + 3 * j + i);
      for (std::size_t k = 0; k < 3; ++k) {
        const Complex want = written.h[i][j]->values[k];
        EXPECT_NEAR(std::abs(y.frfs.h[i][j]->values[k] - want), 0.0, 1e-15 * std::abs(want));
        EXPECT_NEAR(std::abs(z.frfs.h[i][j]->values[k] - 2.0 * want), 0.0, 2e-15 * std::abs(want));
      }
    }
  EXPECT_TRUE(contains(y.frfs.label(1, 0), "tap.uff dataset 1 (nodes 102/101)")) << y.frfs.label(1, 0);
  // First order reads points 0 and 1 only.
  o.order = 1;
  const TapTestFileFrfs first = tap_test_frfs(file, o);
  EXPECT_FALSE(first.frfs.h[2][0]);
  EXPECT_TRUE(first.frfs.h[1][1]);

  TapTestFileOptions bad;
  bad.nodes = {101, 102};
  EXPECT_THROW(tap_test_frfs(file, bad), InvalidArgument);  // order 2 needs three
  bad.nodes = {101, 102, 101};
  EXPECT_THROW(tap_test_frfs(file, bad), InvalidArgument);
  bad.nodes = {101, 102, 103};
  bad.direction = 7;
  EXPECT_THROW(tap_test_frfs(file, bad), InvalidArgument);
}
