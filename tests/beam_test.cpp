// Tests of the free–free Timoshenko segment (beam module). Every expectation comes from
// something independent of the code under test: docs/reference.md reference frequencies (exact frequency
// equation confirmed by FE), the Euler–Bernoulli roots β_rL, closed-form rigid-body receptances,
// reciprocity and passivity, and the two independent solution methods against each other.
#include <gtest/gtest.h>

#include <cmath>

#include "support/fe_beam.hpp"
#include "toolpoint/model/beam.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

using namespace toolpoint;

namespace {

Material steel(double eta = 0.0) { return Material{"steel", 200e9, 0.3, 0.0, 7800.0, eta}; }

Complex entry_of(const Block& b, int k) { return b(k / 2, k % 2); }

const Block& block_of(const TwoPort& t, int j) { return j == 0 ? t.b11 : j == 1 ? t.b12 : j == 2 ? t.b21 : t.b22; }

}  // namespace

// docs/reference.md §2: steel stub d = 50 mm, L = 100 mm, Hutchinson κ. Printed to 1e-3 Hz, so the
// tolerance is the rounding, 5e-4 Hz. Modes 3–6 lie above the 38459.6 Hz cut-off.
TEST(Beam, StubFrequenciesMatchReference) {
  const Segment seg = Segment::tube(0.1, 0.05, 0.0, steel());
  const SectionProperties sp = seg.properties();
  EXPECT_NEAR(sp.cutoff_frequency_hz(), 38459.6, 0.05);
  const double ref[] = {15468.385, 28811.957, 42786.488, 44167.081, 58872.552, 61627.834};
  const auto f = free_free_frequencies(sp, 0.1, 6);
  ASSERT_EQ(f.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(f[i], ref[i], 5e-4) << "mode " << i + 1;
}

// The exact method has no root finder: its receptance must blow up at the same frequencies.
// With η = 0, |H11| at f_r (from the frequency equation) exceeds 1e5 × its value 1 % away.
TEST(Beam, ExactReceptanceResonatesAtFrequencyEquationRoots) {
  const SectionProperties sp = Segment::tube(0.1, 0.05, 0.0, steel()).properties();
  for (double fr : free_free_frequencies(sp, 0.1, 6)) {
    const double off = std::abs(H_of(exact_receptance(sp, 0.1, fr * 1.01).b11));
    try {
      const double on = std::abs(H_of(exact_receptance(sp, 0.1, fr).b11));
      EXPECT_GT(on, 1e5 * off) << fr;
    } catch (const NumericalError&) {
      SUCCEED();  // exactly singular: reported, not returned as garbage
    }
  }
}

// Above the cut-off an even and an odd mode can lie 0.02 % apart (a 16 mm bar of L/D = 15 has a
// pair at 149.01 and 149.04 kHz); the frequency equation must give both. Checks independent of
// the root finder: (a) each of the first 40 roots makes the exact, undamped receptance blow up
// (|H11| or |P11| at the root more than 100× its value 1e-4 away; the pair's members are 2.2e-4
// apart); (b) an undamped finite-element model (tests/support, 240 elements) has exactly as many
// eigenfrequencies in 140–152 kHz as there are roots there (4): its error there, well under 1 %,
// cannot move a mode across the window's edges, which are ≥ 1.6 % from the nearest modes.
TEST(Beam, NearDegeneratePairsAboveTheCutoffAreFound) {
  const double len = 0.24, d = 0.016;
  const SectionProperties sp = Segment::tube(len, d, 0.0, steel()).properties();
  const auto roots = free_free_frequencies(sp, len, 40);
  for (std::size_t i = 1; i < roots.size(); ++i) EXPECT_GT(roots[i], roots[i - 1]);
  for (double fr : roots) {
    double on = 0.0;
    try {
      const TwoPort t = exact_receptance(sp, len, fr);
      on = std::max(std::abs(H_of(t.b11)), std::abs(P_of(t.b11)));
    } catch (const NumericalError&) {
      continue;  // exactly singular: a resonance
    }
    for (double side : {1.0 - 1e-4, 1.0 + 1e-4}) {
      const TwoPort t = exact_receptance(sp, len, fr * side);
      EXPECT_GT(on, 100.0 * std::max(std::abs(H_of(t.b11)), std::abs(P_of(t.b11)))) << fr;
    }
  }
  int in_window = 0;
  for (double fr : roots) in_window += fr > 140e3 && fr < 152e3;
  EXPECT_EQ(in_window, 4);
  fe_oracle::FeModel fem;
  fem.add_chain({fe_oracle::FeSegment{len, sp.EI, sp.kGA, sp.rhoA, sp.rhoI, 240}});
  int fe_in_window = 0;
  for (double f : fem.natural_frequencies_hz()) fe_in_window += f > 140e3 && f < 152e3;
  EXPECT_EQ(fe_in_window, in_window);
}

// Euler–Bernoulli limit: β_rL = 4.730040745, 7.853204624, 10.995607838, 14.137165491. Timoshenko
// corrections (shear and rotary inertia) are of relative size (β_r r_g)² with r_g = d/4: at
// L/d = 1000 we allow 2 (β_r r_g)² (≤ 2.5e-5 for mode 4), and going from L/d = 100 to 1000 they
// must shrink like (d/L)², ~100-fold (we require > 50).
TEST(Beam, EulerBernoulliLimitForSlenderBeams) {
  const double beta_ref[] = {4.730040745, 7.853204624, 10.995607838, 14.137165491};
  auto beta_errors = [&](double slenderness) {
    const double d = 0.01, L = slenderness * d;
    const SectionProperties sp = Segment::tube(L, d, 0.0, steel()).properties();
    std::vector<double> err;
    for (int r = 0; double f : free_free_frequencies(sp, L, 4)) {
      const double w = omega_of(f);
      const double beta_l = std::pow(sp.rhoA * w * w / sp.EI.real(), 0.25) * L;
      err.push_back(std::abs(beta_l - beta_ref[r]) / beta_ref[r]);
      ++r;
    }
    return err;
  };
  const auto e100 = beta_errors(100.0), e1000 = beta_errors(1000.0);
  for (int r = 0; r < 4; ++r) {
    const double beta_rg = beta_ref[r] / 1000.0 / 4.0;
    EXPECT_LT(e1000[r], 2.0 * beta_rg * beta_rg) << "mode " << r + 1;
    EXPECT_GT(e100[r] / e1000[r], 50.0) << "mode " << r + 1;
  }
}

// Rigid-body limit (seed Eq. 11–14 rigid terms, generalised with rotary inertia): with
// m = ρAL, J = ρAL³/12 + ρIL about mid-span, end 1 at x = L, end 2 at x = 0,
//   H11 = −(1/m + (L/2)²/J)/Ω², L11 = N11 = −(L/2)/(JΩ²), P11 = −1/(JΩ²),
//   L22 = +(L/2)/(JΩ²), H12 = −(1/m − (L/2)²/J)/Ω², …
// At 1 Hz the elastic part is (f/f1)² ≈ 4e-9 of the total, so 1e-7 relative is ample.
TEST(Beam, RigidBodyLimitAtLowFrequency) {
  const double L = 0.1;
  const SectionProperties sp = Segment::tube(L, 0.05, 0.02, steel(0.01)).properties();
  const double f = 1.0, W2 = omega_of(f) * omega_of(f);
  const double m = sp.rhoA * L, J = sp.rhoA * L * L * L / 12.0 + sp.rhoI * L, h = L / 2.0;
  const TwoPort t = exact_receptance(sp, L, f);
  // Rigid-body mode values (W, Ψ) at end 1 and end 2: translation (1/√m, 0); rotation (±h, 1)/√J.
  const double v1[2][2] = {{1.0 / std::sqrt(m), 0.0}, {h / std::sqrt(J), 1.0 / std::sqrt(J)}};
  const double v2[2][2] = {{1.0 / std::sqrt(m), 0.0}, {-h / std::sqrt(J), 1.0 / std::sqrt(J)}};
  for (int j = 0; j < 4; ++j) {
    const auto& a = (j == 0 || j == 1) ? v1 : v2;  // response end
    const auto& b = (j == 0 || j == 2) ? v1 : v2;  // load end
    for (int k = 0; k < 4; ++k) {
      const int r = k / 2, c = k % 2;
      const double rigid = -(a[0][r] * b[0][c] + a[1][r] * b[1][c]) / W2;
      const Complex got = entry_of(block_of(t, j), k);
      EXPECT_NEAR(got.real(), rigid, 1e-7 * std::abs(rigid) + 1e-300) << "block " << j << " entry " << k;
    }
  }
}

// The seed's printed rigid terms (Eq. 11–14, rotary inertia neglected) at the outer end of a
// slender beam (L/d = 50, so ρI L / (ρA L³/12) = 3e-4): H11 = −4/(ρALΩ²), L11 = N11 = −6/(ρAL²Ω²),
// P11 = −12/(ρAL³Ω²), within 1e-3.
TEST(Beam, SeedRigidTermsAtTheOuterEnd) {
  const double len = 1.0, W2 = omega_of(0.5) * omega_of(0.5);
  const SectionProperties sp = Segment::tube(len, 0.02, 0.0, steel()).properties();
  const TwoPort t = exact_receptance(sp, len, 0.5);
  const double m = sp.rhoA;
  EXPECT_NEAR(H_of(t.b11).real() / (-4.0 / (m * len * W2)), 1.0, 1e-3);
  EXPECT_NEAR(L_of(t.b11).real() / (-6.0 / (m * len * len * W2)), 1.0, 1e-3);
  EXPECT_NEAR(N_of(t.b11).real() / (-6.0 / (m * len * len * W2)), 1.0, 1e-3);
  EXPECT_NEAR(P_of(t.b11).real() / (-12.0 / (m * len * len * len * W2)), 1.0, 1e-3);
  // …and the mirror image at the inner end (x = 0): L22 = +6/(ρAL²Ω²).
  EXPECT_NEAR(L_of(t.b22).real() / (6.0 / (m * len * len * W2)), 1.0, 1e-3);
}

// Maxwell–Betti reciprocity: L11 = N11, L22 = N22, T12 = T21ᵀ (1e-10 relative: round-off only).
TEST(Beam, ReciprocityOfExactReceptances) {
  for (double inner : {0.0, 0.03}) {
    const SectionProperties sp = Segment::tube(0.15, 0.05, inner, steel(0.02)).properties();
    for (double f = 50.0; f < 60000.0; f *= 1.37) {
      const TwoPort t = exact_receptance(sp, 0.15, f);
      const double scale = t.b11.norm() + t.b12.norm();
      EXPECT_LT(std::abs(L_of(t.b11) - N_of(t.b11)), 1e-10 * scale) << f;
      EXPECT_LT(std::abs(L_of(t.b22) - N_of(t.b22)), 1e-10 * scale) << f;
      EXPECT_LT((t.b12 - t.b21.transpose()).norm(), 1e-10 * scale) << f;
    }
  }
}

// Passivity: with η > 0 a point receptance dissipates energy, Im H ≤ 0 and Im P ≤ 0 (e^{iΩt}),
// and peaks are finite with a phase near −90° at the undamped natural frequency.
TEST(Beam, DampedReceptanceIsPassiveAndFinite) {
  const double L = 0.3;
  const SectionProperties sp = Segment::tube(L, 0.04, 0.0, steel(0.02)).properties();
  for (double f = 20.0; f < 50000.0; f *= 1.05) {
    const TwoPort t = exact_receptance(sp, L, f);
    EXPECT_LE(H_of(t.b11).imag(), 0.0) << f;
    EXPECT_LE(P_of(t.b11).imag(), 0.0) << f;
    EXPECT_TRUE(std::isfinite(std::abs(H_of(t.b11))));
  }
  const double f1 = free_free_frequencies(sp, L, 1)[0];
  const Complex h = H_of(exact_receptance(sp, L, f1).b11);
  EXPECT_NEAR(std::arg(h), -kPi / 2.0, 0.05);
}

// Exactly at the cut-off of an undamped section one wavenumber is 0 (C = ρAΩ²(κGA − ρIΩ²) = 0)
// and the shape function sinh(sy)/s takes its limit y. Built so that C is exactly 0 at f: the
// receptances there must be finite and continuous. They are analytic in f there (entire in s²), so
// the mean of f(1 ± 1e-9) differs from them at second order (~1e-18) plus round-off, which is
// ≲ 1e-11 near the cut-off (against extended precision); 1e-8 relative.
TEST(Beam, ExactlyAtTheCutOff) {
  SectionProperties sp = Segment::tube(0.08, 0.05, 0.0, steel()).properties();
  const double f = sp.cutoff_frequency_hz();
  const double w2 = omega_of(f) * omega_of(f);
  sp.kGA = Complex(sp.rhoI * w2, 0.0);  // κGA − ρIΩ² = 0 in floating point at this f
  const TwoPort at = exact_receptance(sp, 0.08, f);
  const TwoPort lo = exact_receptance(sp, 0.08, f * (1.0 - 1e-9)), hi = exact_receptance(sp, 0.08, f * (1.0 + 1e-9));
  for (int j = 0; j < 4; ++j) {
    const Block mean = 0.5 * (block_of(lo, j) + block_of(hi, j));
    EXPECT_TRUE(block_of(at, j).allFinite());
    EXPECT_LT((block_of(at, j) - mean).norm(), 1e-8 * mean.norm()) << j;
  }
}

// The two independent methods. Error of an entry: max over the grid of |modal − exact| divided
// by max over the grid of |exact| (so antiresonances do not inflate it). Timoshenko frequencies
// grow linearly with mode number at high order, so plain sums converge slowly: with 300 modes
// H, P ≲ 1e-2 and L, N ≲ 1e-4 (docs/reference.md §2: P ≈ 0.4 %). With the static residual every entry
// agrees within 1e-6 (what remains is the residual's Ω² dependence).
TEST(Beam, ExactAndModalAgree) {
  for (double inner : {0.0, 0.035}) {
    const double L = 0.25;
    const SectionProperties sp = Segment::tube(L, 0.05, inner, steel(0.01)).properties();
    const ModalBeam plain(sp, L, {300, false}), corrected(sp, L, {300, true});
    double err_plain[4][4] = {}, err_corr[4][4] = {}, peak[4][4] = {};
    for (double f = 25.0; f <= 30000.0; f *= 1.02) {
      const TwoPort e = exact_receptance(sp, L, f), m = plain.receptance(f), c = corrected.receptance(f);
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 4; ++k) {
          const Complex ex = entry_of(block_of(e, j), k);
          peak[j][k] = std::max(peak[j][k], std::abs(ex));
          err_plain[j][k] = std::max(err_plain[j][k], std::abs(entry_of(block_of(m, j), k) - ex));
          err_corr[j][k] = std::max(err_corr[j][k], std::abs(entry_of(block_of(c, j), k) - ex));
        }
    }
    const double tol_plain[4] = {1e-2, 1e-4, 1e-4, 1e-2};
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        EXPECT_LT(err_plain[j][k] / peak[j][k], tol_plain[k]) << "inner " << inner << " block " << j << " entry " << k;
        EXPECT_LT(err_corr[j][k] / peak[j][k], 1e-6) << "inner " << inner << " block " << j << " entry " << k;
      }
  }
}

// Convergence of the plain modal sum for P11 away from resonance and antiresonance: roughly 1/N
// (docs/reference.md §2: 10 modes ~11 %, 100 ~1.3 %, 300 ~0.4 %), so tripling N cuts the error by 2–4.5; the
// static residual removes at least 99 % of it at every N.
TEST(Beam, ModalSumConvergenceOfP) {
  const double L = 0.5;
  const SectionProperties sp = Segment::tube(L, 0.05, 0.0, steel(0.0)).properties();
  const double f = 1000.0;
  const Complex exact = P_of(exact_receptance(sp, L, f).b11);
  auto err = [&](int n, bool residual) {
    return std::abs(P_of(ModalBeam(sp, L, {n, residual}).receptance(f).b11) - exact) / std::abs(exact);
  };
  const double e10 = err(10, false), e30 = err(30, false), e100 = err(100, false), e300 = err(300, false);
  EXPECT_GT(e10, 0.05);
  EXPECT_LT(e300, 0.01);
  for (auto [a, b] : {std::pair{e10, e30}, {e100, e300}}) {
    EXPECT_GT(a / b, 2.0);
    EXPECT_LT(a / b, 4.5);
  }
  for (int n : {10, 30, 100}) EXPECT_LT(err(n, true), 0.01 * err(n, false)) << n;
}

// Shear coefficients: Hutchinson's hollow formula tends to his solid one as d → 0 and to the
// thin-walled (1+ν)/(2+ν) as d → D; Cowper's solid value is 6(1+ν)/(7+6ν).
TEST(Beam, ShearCoefficientFormulas) {
  const double nu = 0.3;
  EXPECT_NEAR(shear_coefficient(ShearModel::Hutchinson, nu, 1.0, 0.0), 6 * 1.3 * 1.3 / (7 + 12 * nu + 4 * nu * nu), 1e-15);
  EXPECT_NEAR(shear_coefficient(ShearModel::Hutchinson, nu, 1.0, 1e-6), 6 * 1.3 * 1.3 / (7 + 12 * nu + 4 * nu * nu), 1e-9);
  EXPECT_NEAR(shear_coefficient(ShearModel::Hutchinson, nu, 1.0, 1.0 - 1e-7), 1.3 / 2.3, 1e-6);
  EXPECT_NEAR(shear_coefficient(ShearModel::Cowper, nu, 1.0, 0.0), 6 * 1.3 / (7 + 6 * nu), 1e-15);
  EXPECT_NEAR(shear_coefficient(ShearModel::Cowper, nu, 1.0, 1.0), 2 * 1.3 / (4 + 3 * nu), 1e-15);
}

// A hollow tube's frequencies move the way the section properties say: for a slender tube the
// first frequency scales with sqrt(I/A), i.e. sqrt(D² + d²)/4 (Euler–Bernoulli), to 1e-4
// (L/d = 500: the Timoshenko corrections, ~(β₁ r_g/L)² ≈ 3e-5, differ less than that).
TEST(Beam, HollowSectionScalesLikeRadiusOfGyration) {
  const double L = 10.0;
  const double f_solid = free_free_frequencies(Segment::tube(L, 0.02, 0.0, steel()).properties(), L, 1)[0];
  const double f_tube = free_free_frequencies(Segment::tube(L, 0.02, 0.015, steel()).properties(), L, 1)[0];
  EXPECT_NEAR(f_tube / f_solid, std::sqrt(0.02 * 0.02 + 0.015 * 0.015) / 0.02, 1e-4);
}

// Composite section: two concentric layers of the same material behave exactly as one solid —
// the whole section takes one shear coefficient (found in review: per-layer κ did not).
TEST(Beam, CompositeOfOneMaterialEqualsSolid) {
  Segment solid = Segment::tube(0.12, 0.04, 0.0, steel(0.01));
  Segment layered = solid;
  layered.layers = {Annulus{0.04, 0.016, steel(0.01), std::nullopt}, Annulus{0.016, 0.0, steel(0.01), std::nullopt}};
  const TwoPort a = exact_receptance(solid, 3000.0), b = exact_receptance(layered, 3000.0);
  EXPECT_LT((a.b11 - b.b11).norm(), 1e-12 * a.b11.norm());
}

TEST(Beam, BadInputIsRejected) {
  EXPECT_THROW(exact_receptance(Segment::tube(-0.1, 0.05, 0.0, steel()), 100.0), InvalidArgument);
  EXPECT_THROW(exact_receptance(Segment::tube(0.0, 0.05, 0.0, steel()), 100.0), InvalidArgument);
  EXPECT_THROW(exact_receptance(Segment::tube(0.1, 0.05, 0.05, steel()), 100.0), InvalidArgument);
  EXPECT_THROW(exact_receptance(Segment::tube(0.1, 0.05, 0.06, steel()), 100.0), InvalidArgument);
  Material m = steel();
  m.poisson = 0.5;
  EXPECT_THROW(exact_receptance(Segment::tube(0.1, 0.05, 0.0, m), 100.0), InvalidArgument);
  m.poisson = -1.0;
  EXPECT_THROW(m.check(), InvalidArgument);
  m = steel(-0.01);
  EXPECT_THROW(m.check(), InvalidArgument);
  m = steel();
  m.youngs_modulus = std::nan("");
  EXPECT_THROW(m.check(), InvalidArgument);
  EXPECT_THROW(exact_receptance(Segment::tube(0.1, 0.05, 0.0, steel()), 0.0), InvalidArgument);
  EXPECT_THROW(exact_receptance(Segment::tube(0.1, 0.05, 0.0, steel()), -5.0), InvalidArgument);
  // Far outside structural dynamics a damped segment is not at a resonance, and the errors say
  // what is wrong (found in review: 1e-20 and 1e100 Hz were called natural frequencies of an
  // undamped segment): near 0 Hz rounding hides the damping of the rigid-body modes; at 1e100 Hz
  // the terms overflow.
  for (double f : {1e-20, 1e-10}) {
    try {
      exact_receptance(Segment::tube(0.1, 0.05, 0.0, steel(0.01)), f);
      ADD_FAILURE() << f << " Hz was evaluated";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("0 Hz where its rigid-body motion"), std::string::npos) << e.what();
    }
  }
  for (double f : {1e100, 1e300}) {
    try {
      exact_receptance(Segment::tube(0.1, 0.05, 0.0, steel(0.01)), f);
      ADD_FAILURE() << f << " Hz was evaluated";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("overflow double precision"), std::string::npos) << e.what();
    }
  }
  for (double f : {1e-3, 1e7}) EXPECT_TRUE(exact_receptance(Segment::tube(0.1, 0.05, 0.0, steel(0.01)), f).b11.allFinite()) << f;
  EXPECT_THROW(ModalBeam(Segment::tube(0.1, 0.05, 0.0, steel()).properties(), 0.1, {0, false}), InvalidArgument);
  // The raw overload on section properties checks too (found in review: L < 0 gave flipped signs).
  const SectionProperties sp = Segment::tube(0.1, 0.05, 0.0, steel(0.01)).properties();
  EXPECT_THROW(exact_receptance(sp, -0.1, 100.0), InvalidArgument);
  EXPECT_THROW(exact_receptance(sp, 0.0, 100.0), InvalidArgument);
  EXPECT_THROW(exact_receptance(sp, std::nan(""), 100.0), InvalidArgument);
  SectionProperties neg = sp;
  neg.kGA = -neg.kGA;
  EXPECT_THROW(exact_receptance(neg, 0.1, 100.0), InvalidArgument);
  // Layers with different loss factors: the modal method refuses, the exact one works.
  Segment mixed = Segment::tube(0.1, 0.05, 0.02, steel(0.01));
  mixed.layers.push_back(Annulus{0.02, 0.0, steel(0.05), std::nullopt});
  EXPECT_THROW(ModalBeam(mixed.properties(), 0.1, {10, false}), InvalidArgument);
  EXPECT_NO_THROW(exact_receptance(mixed, 100.0));
}

// One end block over a grid, by either method, against the rigid-body closed form of
// RigidBodyLimitAtLowFrequency at 0.5, 0.75 and 1 Hz (the elastic part grows like f²: at most
// 4e-8 of the total there, in P; 1e-7 relative): EndBlock T_jk picks the response at end j to loads at end k.
TEST(Beam, EndBlocksOverAGrid) {
  const double L = 0.1;
  const SectionProperties sp = Segment::tube(L, 0.05, 0.02, steel(0.01)).properties();
  const double m = sp.rhoA * L, J = sp.rhoA * L * L * L / 12.0 + sp.rhoI * L, h = L / 2.0;
  const double v1[2][2] = {{1.0 / std::sqrt(m), 0.0}, {h / std::sqrt(J), 1.0 / std::sqrt(J)}};
  const double v2[2][2] = {{1.0 / std::sqrt(m), 0.0}, {-h / std::sqrt(J), 1.0 / std::sqrt(J)}};
  const std::vector<double> f = {0.5, 0.75, 1.0};
  const ModalBeam modal(sp, L, ModalOptions{50, true});
  const EndBlock blocks[4] = {EndBlock::T11, EndBlock::T12, EndBlock::T21, EndBlock::T22};
  for (int j = 0; j < 4; ++j) {
    const auto& a = (j == 0 || j == 1) ? v1 : v2;  // response end
    const auto& b = (j == 0 || j == 2) ? v1 : v2;  // load end
    for (const BlockSeries& s : {exact_receptance(sp, L, f, blocks[j]), modal.receptance(f, blocks[j])}) {
      ASSERT_EQ(s.frequency_hz, f);
      ASSERT_EQ(s.blocks.size(), f.size());
      for (std::size_t i = 0; i < f.size(); ++i) {
        const double W2 = omega_of(f[i]) * omega_of(f[i]);
        for (int k = 0; k < 4; ++k) {
          const int r = k / 2, c = k % 2;
          const double rigid = -(a[0][r] * b[0][c] + a[1][r] * b[1][c]) / W2;
          EXPECT_NEAR(entry_of(s.blocks[i], k).real(), rigid, 1e-7 * std::abs(rigid) + 1e-300)
              << "block " << j << " entry " << k << " at " << f[i] << " Hz";
        }
      }
    }
  }
  EXPECT_THROW(exact_receptance(sp, L, std::vector<double>{0.0}, EndBlock::T11), InvalidArgument);
}
