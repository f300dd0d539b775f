// Tests of rigid and elastic receptance coupling and structural modification (coupling module),
// against the whole-beam solution, closed-form clamped–free and pinned–pinned beams, and the
// alternative algebraic forms of the same equations.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "support/test_util.hpp"
#include "toolpoint/model/assembly.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/model/coupling.hpp"
#include "toolpoint/error.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

// A uniform beam cut into pieces and recoupled rigidly equals the whole beam: all four blocks to
// 1e-9 relative (round-off through a few 2×2 inversions; away from exact resonances by damping).
TEST(Coupling, CutBeamRecoupledRigidlyEqualsWhole) {
  const SectionProperties sp = Segment::tube(1.0, 0.05, 0.02, steel(0.01)).properties();
  for (double f : {3.0, 150.0, 1234.5, 8000.0, 30000.0}) {
    const TwoPort whole = exact_receptance(sp, 0.3, f);
    const TwoPort a = exact_receptance(sp, 0.07, f), b = exact_receptance(sp, 0.11, f), c = exact_receptance(sp, 0.12, f);
    EXPECT_LT(rel_error(couple_rigid(couple_rigid(a, b), c), whole), 1e-9) << f;
    EXPECT_LT(rel_error(couple_rigid(a, couple_rigid(b, c)), whole), 1e-9) << f;
    EXPECT_LT(rel_error(couple_rigid_point(a, couple_rigid(b, c).b11), whole.b11), 1e-9) << f;
  }
}

// Elastic coupling through K·s tends to rigid coupling as s → ∞, with an error ∝ 1/s (the joint
// flexibility K⁻¹/s enters linearly), and K = 0 decouples (G11 = A11).
TEST(Coupling, StiffJointTendsToRigidAndZeroJointDecouples) {
  const SectionProperties sp = Segment::tube(1.0, 0.04, 0.0, steel(0.01)).properties();
  const double f = 900.0;
  const TwoPort a = exact_receptance(sp, 0.2, f), b = exact_receptance(sp, 0.3, f);
  const TwoPort rigid = couple_rigid(a, b);
  const Block K0 = seed_table1_joint().stiffness(f);  // indefinite, as the seed's
  double prev = 0.0;
  for (double s : {1e2, 1e4, 1e6}) {
    const double e = rel_error(couple_elastic(a, b, s * K0), rigid);
    if (prev > 0.0) EXPECT_NEAR(prev / e, 100.0, 5.0) << s;
    prev = e;
  }
  EXPECT_LT(prev, 1e-5);
  const TwoPort free = couple_elastic(a, b, Block::Zero());
  EXPECT_LT(rel_error(free.b11, a.b11), 1e-15);
  EXPECT_LT(free.b12.norm(), 1e-30);
}

// The K(I + S K)⁻¹ form equals the printed (S + K⁻¹)⁻¹ form of Eq. (1)–(5) when K is invertible.
TEST(Coupling, ElasticFormEqualsPrintedEquation) {
  const SectionProperties sp = Segment::tube(1.0, 0.03, 0.0, steel(0.02)).properties();
  const double f = 2100.0;
  const TwoPort a = exact_receptance(sp, 0.08, f), b = exact_receptance(sp, 0.25, f);
  const Block K = seed_table1_joint().stiffness(f);
  const Block X = (a.b22 + K.inverse() + b.b11).inverse();
  EXPECT_LT(rel_error(couple_elastic_point(a, b.b11, K), Block(a.b11 - a.b12 * X * a.b21)), 1e-12);
  const TwoPort g = couple_elastic(a, b, K);
  EXPECT_LT(rel_error(g.b22, Block(b.b22 - b.b21 * X * b.b12)), 1e-12);
  EXPECT_LT(rel_error(g.b12, Block(a.b12 * X * b.b12)), 1e-12);
}

// Structural modification: the forms used equal Özgüven's H − H (D⁻¹ + H)⁻¹ H for invertible D,
// and a stiff ground spring at a point equals rigid coupling to a very stiff "ground" structure.
TEST(Coupling, StructuralModificationForms) {
  const SectionProperties sp = Segment::tube(1.0, 0.05, 0.0, steel(0.01)).properties();
  const double f = 700.0;
  const TwoPort t = exact_receptance(sp, 0.4, f);
  Block D;
  D << Complex(3e7, 1e4), 0.0, 0.0, Complex(2e5, 10.0);
  const Block ref = t.b11 - t.b11 * (D.inverse() + t.b11).inverse() * t.b11;
  EXPECT_LT(rel_error(ground_point(t.b11, D), ref), 1e-12);
  EXPECT_LT(rel_error(ground_end1(t, D).b11, ref), 1e-12);
  const Block ref22 = t.b22 - t.b22 * (D.inverse() + t.b22).inverse() * t.b22;
  EXPECT_LT(rel_error(ground_end2(t, D).b22, ref22), 1e-12);
  const Block ref21 = t.b21 - t.b21 * (D.inverse() + t.b11).inverse() * t.b11;
  EXPECT_LT(rel_error(ground_end1(t, D).b21, ref21), 1e-12);
  // Singular D (no rotational spring) is legal.
  Block Dt = D;
  Dt(1, 1) = 0.0;
  EXPECT_NO_THROW(ground_end2(t, Dt));
}

// A free–free beam clamped at end 2 (ground springs 1e16 N/m and N·m/rad) is the clamped–free
// beam. Static limit (Timoshenko cantilever, exact): H11 = L³/(3EI) + L/(κGA), L11 = N11 = L²/(2EI),
// P11 = L/EI, at 0.05 Hz where inertia adds (f/f₁)² ≈ 1e-8. Slender limit: peaks of |H11| at
// β_rL = 1.875104069, 4.694091133, 7.854757438 (Euler–Bernoulli), within 2(β_r r_g)².
TEST(Coupling, ClampedFreeBeamByGroundingAnEnd) {
  {
    const double len = 0.2;
    const Segment seg = Segment::tube(len, 0.04, 0.0, steel());
    const SectionProperties sp = seg.properties();
    Chain c({seg}, ReceptanceMethod::Exact, 0);
    c.add_ground(1, Bearing{"clamp", len, 1e16, 0.0, 1e16, 0.0});
    const Block g = c.point(0.05);
    const double EI = sp.EI.real(), kGA = sp.kGA.real();
    EXPECT_NEAR(g(0, 0).real() / (len * len * len / (3 * EI) + len / kGA), 1.0, 1e-6);
    EXPECT_NEAR(g(0, 1).real() / (len * len / (2 * EI)), 1.0, 1e-6);
    EXPECT_NEAR(g(1, 0).real() / (len * len / (2 * EI)), 1.0, 1e-6);
    EXPECT_NEAR(g(1, 1).real() / (len / EI), 1.0, 1e-6);
  }
  {
    const double d = 0.01, len = 1000 * d;
    const Segment seg = Segment::tube(len, d, 0.0, steel(1e-4));
    const SectionProperties sp = seg.properties();
    Chain c({seg}, ReceptanceMethod::Exact, 0);
    c.add_ground(1, Bearing{"clamp", len, 1e16, 0.0, 1e16, 0.0});
    const double beta_ref[] = {1.875104069, 4.694091133, 7.854757438};
    auto hz = [&](double bl) { return bl * bl / (len * len) * std::sqrt(sp.EI.real() / sp.rhoA) / (2 * kPi); };
    const auto peaks = model_peaks([&](double f) { return std::abs(c.point(f)(0, 0)); }, 0.5 * hz(beta_ref[0]),
                                   1.1 * hz(beta_ref[2]), 0.01 * hz(beta_ref[0]));
    ASSERT_EQ(peaks.size(), 3u);
    for (int r = 0; r < 3; ++r) {
      const double beta = std::sqrt(peaks[r] * 2 * kPi / std::sqrt(sp.EI.real() / sp.rhoA)) * len;
      const double brg = beta_ref[r] * d / 4 / len;
      EXPECT_NEAR(beta / beta_ref[r], 1.0, 2 * brg * brg + 1e-7) << "mode " << r + 1;
    }
  }
}

// Two very stiff translational supports (no rotational stiffness) at the ends make the
// pinned–pinned Timoshenko beam, whose modes are exactly sin(nπx/L): Ω_n is the lower root of
//   ρAρI Ω⁴ − [(κGA ρI + EI ρA) k² + κGA ρA] Ω² + EI κGA k⁴ = 0,  k = nπ/L.
// Peaks of |P11| (the end rotates freely) match it to 1e-6: the supports' finite stiffness
// (1e16 N/m against a local shear stiffness κGA/L ≈ 5e8 N/m) shifts them by ~1e-8.
TEST(Coupling, TwoStiffSupportsGivePinnedPinnedBeam) {
  const double len = 0.3;
  const Segment seg = Segment::tube(len, 0.05, 0.02, steel(1e-5));
  const SectionProperties sp = seg.properties();
  Chain c({seg}, ReceptanceMethod::Exact, 0);
  c.add_ground(0, Bearing{"a", 0.0, 1e16, 0.0, 0.0, 0.0});
  c.add_ground(1, Bearing{"b", len, 1e16, 0.0, 0.0, 0.0});
  const double a = sp.kGA.real(), b = sp.EI.real();
  std::vector<double> ref;
  for (int n = 1; n <= 3; ++n) {
    const double k = n * kPi / len;
    const double A = sp.rhoA * sp.rhoI, B = -((a * sp.rhoI + b * sp.rhoA) * k * k + a * sp.rhoA), C = b * a * k * k * k * k;
    const double w2 = (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
    ref.push_back(std::sqrt(w2) / (2 * kPi));
  }
  const auto peaks = model_peaks([&](double f) { return std::abs(c.point(f)(1, 1)); }, 0.5 * ref[0], 1.05 * ref[2],
                                 0.01 * ref[0]);
  ASSERT_EQ(peaks.size(), 3u);
  for (int n = 0; n < 3; ++n) EXPECT_NEAR(peaks[n] / ref[n], 1.0, 1e-6) << "mode " << n + 1;
}

// Junction receptances: reciprocal (G1j = Gj1ᵀ), G11 as the point coupling, and Gjj equal to the
// point receptance of the same beam seen from the other piece (an independent route: couple
// B's free–free receptance with A at B's end 1 in a mirrored chain is equivalent to the
// dynamic stiffnesses adding: Gjj⁻¹ = A22⁻¹ + B11⁻¹).
TEST(Coupling, JunctionReceptances) {
  const SectionProperties sp = Segment::tube(1.0, 0.04, 0.0, steel(0.01)).properties();
  for (double f : {50.0, 1500.0, 9000.0}) {
    const TwoPort a = exact_receptance(sp, 0.13, f);
    const Block b11 = exact_receptance(sp, 0.2, f).b11;
    const Junction j = couple_rigid_junction(a, b11);
    EXPECT_LT((j.g1j - j.gj1.transpose()).norm(), 1e-10 * j.g1j.norm());
    EXPECT_LT(rel_error(j.g11, couple_rigid_point(a, b11)), 1e-14);
    EXPECT_LT(rel_error(j.gjj, Block((a.b22.inverse() + b11.inverse()).inverse())), 1e-9);
  }
}

TEST(Coupling, SingularInterfaceIsReported) {
  Block z = Block::Zero();
  EXPECT_THROW(inverse_checked(z, "test"), NumericalError);
  EXPECT_TRUE(std::isinf(condition_number(z)));
  Block d = Block::Identity();
  d(1, 1) = 1e-3;
  EXPECT_NEAR(condition_number(d), 1e3, 1e-9);
  // Frobenius condition of a 2×2 lies in [cond₂, cond₂ + 1/cond₂] (σ₁/σ₂ + σ₂/σ₁).
  Block m;
  m << Complex(1, 2), Complex(-3, 0.5), Complex(0.2, -1), Complex(4, 4);
  const double c2 = condition_number(m), cf = frobenius_condition(m);
  EXPECT_GE(cf, c2 * (1 - 1e-12));
  EXPECT_NEAR(cf, c2 + 1 / c2, 1e-12 * cf);
}

// Definiteness warnings (joint module): the seed's Table 1 is indefinite in stiffness (det ≈
// −1.5e12) and in damping (54·1 − 22.2² < 0); a diagonal positive joint is not; zero damping is
// not warned about.
TEST(Joint, DefinitenessWarnings) {
  EXPECT_EQ(joint_warnings(seed_table1_joint(), "K_ht").size(), 2u);
  JointParameters p;
  p.k_yf = 1e8;
  p.k_tm = 1e5;
  p.c_yf = 100;
  p.c_tm = 1;
  EXPECT_TRUE(joint_warnings(p, "K").empty());
  p.c_yf = p.c_tm = 0.0;
  EXPECT_TRUE(joint_warnings(p, "K").empty());
  p.k_ym = p.k_tf = 4e6;  // (4e6)² = 1.6e13 > 1e8 · 1e5 = 1e13
  const auto w = joint_warnings(p, "K");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("not positive definite"), std::string::npos);
}

// The index helpers against K itself: Eq. (8) at 1/(2π) Hz (ω = 1) puts k + i c of each entry in
// K, so a parameter set with every value distinct shows which value sits where.
TEST(Joint, IndexHelpersFollowTheLayoutOfK) {
  JointParameters p;
  for (int i = 0; i < 8; ++i) p[i] = 10.0 * (i + 1);
  const Block K = p.stiffness(1.0 / (2.0 * kPi));
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      EXPECT_NEAR(p[JointParameters::stiffness_of(r, c)], K(r, c).real(), 1e-12) << r << c;
      EXPECT_NEAR(p[JointParameters::damping_of(r, c)], K(r, c).imag(), 1e-12) << r << c;
      EXPECT_NEAR(p[JointParameters::transposed(JointParameters::stiffness_of(r, c))], K(c, r).real(), 1e-12) << r << c;
      EXPECT_NEAR(p[JointParameters::transposed(JointParameters::damping_of(r, c))], K(c, r).imag(), 1e-12) << r << c;
    }
  EXPECT_EQ(JointParameters::stiffness_of(0, 1), static_cast<int>(JointParameter::k_ym));
  EXPECT_EQ(JointParameters::damping_of(1, 0), static_cast<int>(JointParameter::c_tf));
  EXPECT_EQ(JointParameters::transposed(static_cast<int>(JointParameter::c_ym)), static_cast<int>(JointParameter::c_tf));
  EXPECT_EQ(JointParameters::transposed(static_cast<int>(JointParameter::k_tm)), static_cast<int>(JointParameter::k_tm));
}
