// Tests of the spindle–holder–tool assembly (assembly module): static beam theory for a
// cantilevered stepped assembly with elastic joints, reciprocity, the rigid-joint limit, the
// modal method against the exact one, and station receptances.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "support/test_util.hpp"
#include "toolpoint/assembly.hpp"
#include "toolpoint/assembly_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/coupling.hpp"
#include "toolpoint/error.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

JointParameters joint(double kyf, double kym, double ktm, double cyf = 0.0) {
  JointParameters p;
  p.k_yf = kyf;
  p.k_ym = p.k_tf = kym;
  p.k_tm = ktm;
  p.c_yf = cyf;
  return p;
}

// A cantilevered assembly: the spindle's rear end clamped by a 1e16 bearing (translation and
// rotation); definite symmetric elastic joints.
Assembly cantilevered() {
  Assembly a;
  a.name = "cantilever";
  a.spindle.segments = {Segment::tube(0.2, 0.06, 0.02, steel(), "spindle")};
  a.spindle.bearings = {Bearing{"clamp", 0.2, 1e16, 0.0, 1e16, 0.0}};
  a.holder = {Segment::tube(0.05, 0.04, 0.012, steel(), "holder 1"), Segment::tube(0.03, 0.05, 0.012, steel(), "holder 2")};
  a.tool.material = carbide();
  a.tool.length = 0.08;
  a.tool.overhang = 0.05;
  a.tool.diameter = 0.012;
  a.spindle_holder = Joint::make_elastic(joint(5e8, 1e6, 3e6));
  a.holder_tool = Joint::make_elastic(joint(5e7, 1e6, 1e5));
  return a;
}

double EI_of(const Material& m, double D, double d) { return m.youngs_modulus * kPi / 64.0 * (std::pow(D, 4) - std::pow(d, 4)); }
double kGA_of(const Material& m, double D, double d) {
  return shear_coefficient(ShearModel::Hutchinson, m.poisson, D, d) * m.G() * kPi / 4.0 * (D * D - d * d);
}

}  // namespace

// Static limit against beam theory. Tip load F = 1 on a cantilever of stepped sections, z the
// distance from the tip: w_tip = Σ ∫ z²/EI dz + Σ ∫ 1/κGA dz + Σ_joints [1, ℓ] K⁻¹ [1, ℓ]ᵀ,
// θ_tip = Σ ∫ z/EI dz + Σ [0, 1] K⁻¹ [1, ℓ]ᵀ, and for a tip moment θ = Σ ∫ 1/EI dz + Σ [0,1]K⁻¹[0,1]ᵀ
// (ℓ = distance from the tip to the joint). Where the shank sits in the holder EI and κGA add.
// Free–free components carry rigid-body terms ~1/(mΩ²) that cancel in the coupled result, so the
// static value is taken by Richardson extrapolation in Ω² from 1 Hz and 2 Hz (g ≈ g₀ + a f²:
// g₀ = (4 g(1) − g(2))/3, leaving O((f/f₁)⁴) ≈ 1e-10); tolerance 1e-7.
TEST(Assembly, StaticLimitOfCantileveredAssembly) {
  const Assembly a = cantilevered();
  const AssemblyModel m(a);
  const Material st = steel(), cb = carbide();
  // (length, EI, κGA) from the tip inwards; joints after the tool (ℓ = 0.05) and the holder (ℓ = 0.13).
  struct Piece { double len, EI, kGA; };
  const std::vector<Piece> tool = {{0.05, EI_of(cb, 0.012, 0), kGA_of(cb, 0.012, 0)}};
  const std::vector<Piece> holder = {
      {0.03, EI_of(st, 0.04, 0.012) + EI_of(cb, 0.012, 0), kGA_of(st, 0.04, 0.012) + kGA_of(cb, 0.012, 0)},
      {0.02, EI_of(st, 0.04, 0.012), kGA_of(st, 0.04, 0.012)},
      {0.03, EI_of(st, 0.05, 0.012), kGA_of(st, 0.05, 0.012)}};
  const std::vector<Piece> spindle = {{0.2, EI_of(st, 0.06, 0.02), kGA_of(st, 0.06, 0.02)}};
  double z = 0.0, w = 0.0, th = 0.0, p = 0.0;
  auto add = [&](const std::vector<Piece>& ps) {
    for (const Piece& q : ps) {
      const double z1 = z + q.len;
      w += (z1 * z1 * z1 - z * z * z) / (3 * q.EI) + q.len / q.kGA;
      th += (z1 * z1 - z * z) / (2 * q.EI);
      p += q.len / q.EI;
      z = z1;
    }
  };
  auto add_joint = [&](const JointParameters& jp) {
    const Eigen::Matrix2d C = jp.stiffness(1.0).real().inverse();
    const Eigen::Vector2d u(1.0, z), r(0.0, 1.0);
    w += u.dot(C * u);
    th += r.dot(C * u);
    p += r.dot(C * r);
  };
  add(tool);
  add_joint(a.holder_tool.parameters);
  add(holder);
  add_joint(a.spindle_holder.parameters);
  add(spindle);
  const Block g = (4.0 * m.tool_point(1.0) - m.tool_point(2.0)) / 3.0;
  EXPECT_NEAR(g(0, 0).real() / w, 1.0, 1e-7);
  EXPECT_NEAR(g(1, 0).real() / th, 1.0, 1e-7);
  EXPECT_NEAR(g(0, 1).real() / th, 1.0, 1e-7);
  EXPECT_NEAR(g(1, 1).real() / p, 1.0, 1e-7);
}

// Every assembled point block is reciprocal (L = N) for symmetric joints, including the
// indefinite Table 1 joint: 1e-9 relative to the block norm (round-off).
TEST(Assembly, PointBlocksAreReciprocal) {
  const Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  const AssemblyModel m(a);
  for (double f = 20.0; f < 8000.0; f *= 1.3) {
    const auto r = m.evaluate(f);
    for (const Block* b : {&r.S11, &r.SH11, &r.SHT11}) EXPECT_LT(std::abs((*b)(0, 1) - (*b)(1, 0)), 1e-9 * b->norm()) << f;
    const TwoPort ht = m.holder_tool(f);
    EXPECT_LT((ht.b12 - ht.b21.transpose()).norm(), 1e-9 * ht.b12.norm()) << f;
  }
}

// As both joints stiffen without bound SHT11 tends to the all-rigid assembly, error ∝ 1/s.
TEST(Assembly, StiffJointsTendToRigidAssembly) {
  Assembly a = cantilevered();
  a.spindle.bearings = {Bearing{"b1", 0.05, 3e8, 2e3, 0, 0}, Bearing{"b2", 0.18, 1e8, 1e3, 0, 0}};
  Assembly rigid = a;
  rigid.spindle_holder = rigid.holder_tool = Joint::make_rigid();
  const AssemblyModel mr(rigid);
  double prev = 0.0;
  for (double s : {1e3, 1e5, 1e7}) {
    Assembly b = a;
    for (int i = 0; i < 8; ++i) {
      b.spindle_holder.parameters[i] *= s;
      b.holder_tool.parameters[i] *= s;
    }
    const AssemblyModel mb(b);
    double e = 0.0;
    for (double f : {100.0, 1500.0, 6000.0}) e = std::max(e, rel_error(mb.tool_point(f), mr.tool_point(f)));
    if (prev > 0.0) EXPECT_NEAR(prev / e, 100.0, 10.0);
    prev = e;
  }
  EXPECT_LT(prev, 1e-5);
}

// The modal method (100 modes per segment with the static residual) reproduces the exact
// assembly FRF: 1e-4 relative over the example's band (the residual's quasi-static
// approximation leaves ~(Ω/ω_N)² of the truncated part). The modal method needs one loss factor
// per section, so the carbide is given the steel's for the composite holder sections.
TEST(Assembly, ModalMethodMatchesExact) {
  Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  a.tool.material.loss_factor = a.holder.front().layers.front().material.loss_factor;
  const AssemblyModel exact(a);
  a.method = ReceptanceMethod::Modal;
  a.modal_terms = 100;
  const AssemblyModel modal(a);
  for (double f = 50.0; f < 5000.0; f *= 1.17) EXPECT_LT(rel_error(modal.tool_point(f), exact.tool_point(f)), 1e-4) << f;
}

// Station receptances: the tip station equals the tool point FRF; the matrix is reciprocal.
TEST(Assembly, ToolStations) {
  const Assembly a = load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
  const AssemblyModel m(a);
  for (double f : {300.0, 2580.0}) {
    const Eigen::MatrixXcd G = m.tool_stations(f, {0.0, 0.01, 0.02});
    EXPECT_LT(rel_error(Block(G.block<2, 2>(0, 0)), m.tool_point(f)), 1e-9);
    EXPECT_LT((G - G.transpose()).norm(), 1e-9 * G.norm());
  }
  EXPECT_THROW(m.tool_stations(100.0, {0.06}), InvalidArgument);
}

// A chain shares the wavenumbers of consecutive pieces of one section (a segment cut at bearings
// or at the tool's insertion). Pieces of two sections alternating in runs: the chain's blocks must
// equal the fold of independent exact_receptance calls with couple_rigid / couple_rigid_point to
// 1e-13 relative (the same arithmetic, so round-off only; reusing the wrong section's
// wavenumbers would be off by O(1)).
TEST(Assembly, SharedWavenumbersEqualIndependentPieces) {
  const Segment a = Segment::tube(1.0, 0.05, 0.02, steel(0.01)), b = Segment::tube(1.0, 0.03, 0.0, carbide(0.002));
  std::vector<Segment> pieces;
  for (auto [seg, len] : {std::pair{&a, 0.03}, {&a, 0.05}, {&b, 0.02}, {&a, 0.04}, {&a, 0.01}, {&b, 0.06}, {&b, 0.015}}) {
    pieces.push_back(*seg);
    pieces.back().length = len;
  }
  const Chain chain(pieces, ReceptanceMethod::Exact, 0);
  for (double f : {20.0, 850.0, 4321.0, 30000.0}) {
    TwoPort g = exact_receptance(pieces.back(), f);
    Block p = g.b11;
    for (std::size_t k = pieces.size() - 1; k-- > 0;) {
      const TwoPort t = exact_receptance(pieces[k].properties(), pieces[k].length, f);
      g = couple_rigid(t, g);
      p = couple_rigid_point(t, p);
    }
    const TwoPort c = chain.two_port(f);
    EXPECT_LT(rel_error(c, g), 1e-13) << f;
    EXPECT_LT(rel_error(chain.point(f), p), 1e-13) << f;
  }
}

TEST(Assembly, InvalidAssembliesAreRejected) {
  Assembly a = cantilevered();
  a.spindle.bearings.push_back(Bearing{"far", 0.3, 1e8, 0, 0, 0});
  EXPECT_THROW(a.check(), InvalidArgument);
  a = cantilevered();
  a.tool.overhang = 0.0;
  EXPECT_THROW(a.check(), InvalidArgument);
  a = cantilevered();
  a.tool.length = 0.2;  // 0.15 m inside a 0.08 m holder
  EXPECT_THROW(a.check(), InvalidArgument);
  a = cantilevered();
  a.tool.diameter = 0.014;  // wider than the 12 mm bore
  EXPECT_THROW(a.check(), InvalidArgument);
  a = cantilevered();
  a.holder[0].layers[0].inner_diameter = 0.0;  // no bore for the shank
  EXPECT_THROW(a.check(), InvalidArgument);
  a = cantilevered();
  a.holder[1].length = -0.01;
  EXPECT_THROW(a.check(), InvalidArgument);
}
