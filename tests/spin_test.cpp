// The spinning Timoshenko segment (beam.hpp, "A segment spinning about its axis"; docs/reference.md
// §10) against an independent finite-element rotor: consistent-mass Timoshenko elements
// (tests/support/fe_beam.hpp's IIE element, itself proven in fe_oracle_test.cpp) assembled in the
// real coordinates (w_x, ψ_x, w_y, ψ_y) per node with the gyroscopic matrix
//     M q̈ + Ω G q̇ + K q = f,   G on (ψ_x, ψ_y) = +∫ρI_p N_ψᵀN_ψ, on (ψ_y, ψ_x) its negative,
// from the slice's angular momentum written out here in x and y (no complex coordinate, no whirl
// decoupling, no closed form): its natural frequencies come from the state-space eigenproblem,
// whirl directions from the eigenvectors' rotation sense, its FRF from a dense solve of
// (K(1+iη) + iω Ω G − ω²M) q = f. Units SI, frequencies in Hz.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "support/fe_rotor.hpp"
#include "toolpoint/model/beam.hpp"
#include "toolpoint/error.hpp"

namespace {

using toolpoint::Complex;
using toolpoint::SectionProperties;
using toolpoint::Whirl;

constexpr double kPi = std::numbers::pi;

double rpm_to_rad_s(double rpm) { return rpm * 2.0 * kPi / 60.0; }

SectionProperties rod_section(double d, double eta = 0.0) {
  toolpoint::Segment s = toolpoint::Segment::tube(0.15, d, 0.0, toolpoint::Material{"steel", 2.0e11, 0.3, 0.0, 7800.0, eta});
  return s.properties();
}

using fe_oracle::fe_rotor;
using fe_oracle::FeRotor;

struct FeWhirls {
  std::vector<double> forward, backward;  // ascending, Hz
};

// Undamped natural frequencies by whirl: eigenvalues λ = iω (ω > 0) of
// [[0, I], [−M⁻¹K, −M⁻¹ΩG]]; a mode is forward when its w_x + i w_y part (turning with +z)
// outweighs w_x − i w_y. Frequencies below `floor_hz` (the rigid translations' round-off) dropped.
FeWhirls fe_whirls(const SectionProperties& p, double length, int n, double spin, double floor_hz) {
  const FeRotor r = fe_rotor(p, length, n);
  const int N = 4 * r.nodes;
  const Eigen::MatrixXd Kr = r.K.real();
  const Eigen::LDLT<Eigen::MatrixXd> m(r.M);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * N, 2 * N);
  A.topRightCorner(N, N).setIdentity();
  A.bottomLeftCorner(N, N) = -m.solve(Kr);
  A.bottomRightCorner(N, N) = -m.solve(spin * r.G);
  // Shift-invert about σ (real, below the modes of interest): A's norm is set by the highest
  // modes (~ω_max²), which would swamp the low eigenvalues' accuracy; those of (A − σI)⁻¹,
  // 1/(λ − σ), are the largest and come out to round-off relative to them.
  const double sigma = 2.0 * kPi * 100.0;
  const Eigen::MatrixXd inv = (A - sigma * Eigen::MatrixXd::Identity(2 * N, 2 * N)).partialPivLu().inverse();
  const Eigen::EigenSolver<Eigen::MatrixXd> es(inv);
  FeWhirls out;
  for (int i = 0; i < 2 * N; ++i) {
    const Complex lambda = sigma + 1.0 / es.eigenvalues()(i);
    const double f = lambda.imag() / (2.0 * kPi);
    if (f < floor_hz) continue;
    const Eigen::VectorXcd v = es.eigenvectors().col(i);
    double fwd = 0.0, bwd = 0.0;
    for (int k = 0; k < r.nodes; ++k) {
      fwd += std::norm(v(4 * k) + Complex(0, 1) * v(4 * k + 2));
      bwd += std::norm(v(4 * k) - Complex(0, 1) * v(4 * k + 2));
    }
    (fwd > bwd ? out.forward : out.backward).push_back(f);
  }
  std::sort(out.forward.begin(), out.forward.end());
  std::sort(out.backward.begin(), out.backward.end());
  return out;
}

// The FE rotor's natural frequency [Hz] near `guess_hz` and its whirl sense: the real ω > 0 where
// the dynamic stiffness D(ω) = K + iωΩG − ω²M is singular (λ = iω of (λ²M + λΩG + K)v = 0). For
// real ω, D is Hermitian (G is real skew, so iωΩG is Hermitian), its eigenvalues real: Newton on
// the eigenvalue μ(ω) of least modulus, dμ/dω = xᴴD'(ω)x/xᴴx (D' = iΩG − 2ωM; Hellmann–Feynman),
// μ and x by inverse iteration on a sparse LU of D (banded: one factorization costs about what a
// dense eigensolution of the 8-element rotor does). Converged to 1e-14 relative: the dense
// state-space eigensolution cannot reach the finer meshes (its cost grows with the cube of the
// DOFs), this reaches 256 elements in milliseconds per root.
struct FeRoot {
  double hz = 0.0;
  bool forward = false;
};
FeRoot fe_root(const FeRotor& r, double spin, double guess_hz, bool forward) {
  using Sparse = Eigen::SparseMatrix<Complex>;
  const Sparse K = r.K.sparseView(), M = r.M.cast<Complex>().sparseView(), G = r.G.cast<Complex>().sparseView();
  const int N = 4 * r.nodes;
  double w = 2.0 * kPi * guess_hz;
  // The iteration is kept to the whirl asked for (w_y = ∓i w_x, ψ_y = ∓i ψ_x at every node: the
  // rotor is axisymmetric, so D maps each sense to itself), else the forward and backward roots of
  // one mode, 1 % apart, would compete; the sense of the converged root is then read from an
  // unconstrained iterate (below), not assumed.
  const Complex turn = forward ? Complex(0.0, -1.0) : Complex(0.0, 1.0);
  const auto keep_sense = [&](Eigen::VectorXcd& v) {
    for (int k = 0; k < r.nodes; ++k)
      for (int d = 0; d < 2; ++d) {
        const Complex c = 0.5 * (v(4 * k + d) - turn * v(4 * k + 2 + d));
        v(4 * k + d) = c;
        v(4 * k + 2 + d) = turn * c;
      }
    v.normalize();
  };
  Eigen::VectorXcd x = Eigen::VectorXcd::Ones(N);
  keep_sense(x);
  for (int it = 0; it < 30; ++it) {
    const Sparse D = K + Complex(0.0, w * spin) * G - (w * w) * M;
    Eigen::SparseLU<Sparse> lu(D);
    // An exactly zero pivot: w is the root to the last bit (it happens on the finest mesh, where the
    // iteration converges in two steps), so there is nothing left to refine.
    if (lu.info() != Eigen::Success) break;
    for (int k = 0; k < 3; ++k) {
      x = lu.solve(x);
      keep_sense(x);
    }
    const Complex mu = x.dot(D * x), slope = x.dot((Complex(0.0, spin) * G - (2.0 * w) * M) * x);
    const double step = mu.real() / slope.real();
    w -= step;
    if (std::abs(step) < 1e-14 * w) break;
  }
  // At the root the mode's own eigenvalue is the smallest by far: two free steps from a generic
  // vector give its shape, whose sense is the check. The shift sits 1e-10 off the root, where D
  // still factorizes when w is the root to the last bit, and the mode still dominates by far.
  const double shift = w * (1.0 + 1e-10);
  const Sparse D = K + Complex(0.0, shift * spin) * G - (shift * shift) * M;
  Eigen::SparseLU<Sparse> lu(D);
  if (lu.info() != Eigen::Success) {
    ADD_FAILURE() << "the FE rotor's matrix at " << shift / (2.0 * kPi) << " Hz does not factorize: " << lu.lastErrorMessage();
    return {w / (2.0 * kPi), forward};
  }
  x = Eigen::VectorXcd::LinSpaced(N, 1.0, 2.0);
  for (int k = 0; k < 2; ++k) x = lu.solve(x).normalized();
  double fwd = 0.0, bwd = 0.0;
  for (int k = 0; k < r.nodes; ++k) {
    fwd += std::norm(x(4 * k) + Complex(0, 1) * x(4 * k + 2));
    bwd += std::norm(x(4 * k) - Complex(0, 1) * x(4 * k + 2));
  }
  return {w / (2.0 * kPi), fwd > bwd};
}

// Richardson extrapolation of a sequence on meshes n, 2n, 4n, …: errors c₂h² + c₄h⁴ + c₆h⁶ …
// eliminated one power at a time. Returns the last entry and, in `error`, its change from the
// previous column (an estimate of what is left).
double richardson(std::vector<double> v, double* error) {
  double factor = 4.0, previous = v.back();
  while (v.size() > 1) {
    previous = v.back();
    for (std::size_t k = 0; k + 1 < v.size(); ++k) v[k] = (factor * v[k + 1] - v[k]) / (factor - 1.0);
    v.pop_back();
    factor *= 4.0;
  }
  *error = std::abs(v[0] - previous);
  return v[0];
}

}  // namespace

// At Ω = 0 each whirl is today's planar segment, bit for bit (the rotary inertia is ρI − 0), and
// the two-plane block has no cross terms: 1e-12 asked, 0 delivered.
TEST(Spin, StandstillIsTodaysSegment) {
  const SectionProperties p = rod_section(0.04, 0.02);
  for (double f : {50.0, 3000.0, 12000.0, 60000.0}) {
    const toolpoint::TwoPort t = toolpoint::exact_receptance(p, 0.15, f);
    for (Whirl w : {Whirl::Forward, Whirl::Backward}) {
      const toolpoint::TwoPort s = toolpoint::whirl_receptance(p, 0.15, f, 0.0, w);
      EXPECT_LE((s.b11 - t.b11).norm(), 1e-12 * t.b11.norm());
      EXPECT_LE((s.b12 - t.b12).norm(), 1e-12 * t.b12.norm());
    }
    const toolpoint::TwoPort4 b = toolpoint::spinning_receptance(p, 0.15, f, 0.0);
    EXPECT_LE((b.b11.topLeftCorner<2, 2>() - t.b11).norm(), 1e-12 * t.b11.norm());
    EXPECT_LE((b.b11.bottomRightCorner<2, 2>() - t.b11).norm(), 1e-12 * t.b11.norm());
    EXPECT_EQ((b.b11.topRightCorner<2, 2>().norm()), 0.0);
  }
  const toolpoint::WhirlFrequencies w = toolpoint::whirl_frequencies(p, 0.15, 0.0, 5);
  const std::vector<double> today = toolpoint::free_free_frequencies(p, 0.15, 5);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(w.forward_hz[k], today[k], 1e-10 * today[k]);
    EXPECT_NEAR(w.backward_hz[k], today[k], 1e-10 * today[k]);
  }
  EXPECT_EQ(w.conical_hz, 0.0);
}

// The docs/reference.md §2 stub (d = 50 mm, L = 100 mm): the root finder at Ω = 0 returns the
// reference frequencies on both branches of the cut-off (modes 3–6 above it), to their 8 digits.
TEST(Spin, StandstillRootsAreTheReferenceFrequencies) {
  toolpoint::Segment s = toolpoint::Segment::tube(0.1, 0.05, 0.0, toolpoint::Material{"steel", 2.0e11, 0.3, 0.0, 7800.0, 0.0});
  const toolpoint::WhirlFrequencies w = toolpoint::whirl_frequencies(s.properties(), 0.1, 0.0, 6);
  const double reference[6] = {15468.385, 28811.957, 42786.488, 44167.081, 58872.552, 61627.834};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(w.forward_hz[k], reference[k], 1e-3) << "mode " << k + 1;
}

// The oracle: forward and backward natural frequencies of a free–free spinning rod (d = 40 mm,
// L = 150 mm: first mode ≈ 6.9 kHz, the cut-off ≈ 45 kHz) at 0, 30 000 and 60 000 rpm: the conical
// mode and the first four elastic modes of each whirl (up to 36 kHz). The FE rotor's roots on 16,
// 32, 64, 128 and 256 elements (fe_root, each mesh starting from the coarser one's root; the first
// from the dense state-space eigensolution of the 16-element rotor, which also gives the whirl
// sense), extrapolated by Richardson (h², h⁴, h⁶, h⁸ removed). Tolerance 1e-6 relative for every
// mode; the extrapolation's own remaining change must be below a tenth of that (seen: below 1e-9
// for every mode; modes 3–4 were 5e-6 short of it with 8–64 elements).
TEST(Spin, WhirlFrequenciesAgreeWithTheFiniteElementRotor) {
  const SectionProperties p = rod_section(0.04);
  const double L = 0.15;
  constexpr double kTol = 1e-6;
  const std::vector<int> meshes = {16, 32, 64, 128, 256};
  std::vector<FeRotor> rotors;
  for (int n : meshes) rotors.push_back(fe_rotor(p, L, n));
  for (double rpm : {0.0, 30000.0, 60000.0}) {
    const double spin = rpm_to_rad_s(rpm);
    const toolpoint::WhirlFrequencies exact = toolpoint::whirl_frequencies(p, L, spin, 4);
    const FeWhirls start = fe_whirls(p, L, meshes.front(), spin, 1.0);
    // One FE mode from the coarsest mesh's eigenvalue up the meshes, extrapolated, against `expected`.
    auto compare = [&](double expected, double coarse_hz, bool forward, const char* what, int k) {
      std::vector<double> v{coarse_hz};
      for (std::size_t m = 0; m < rotors.size(); ++m) {
        const FeRoot root = fe_root(rotors[m], spin, v.back(), forward);
        if (rpm > 0.0) EXPECT_EQ(root.forward, forward) << what << " mode " << k << " on " << meshes[m] << " elements";
        if (m == 0) v.clear();
        v.push_back(root.hz);
      }
      double err = 0.0;
      const double fe = richardson(v, &err);
      EXPECT_LT(err, 0.1 * kTol * fe) << what << " mode " << k << " at " << rpm << " rpm: the FE has not converged";
      EXPECT_NEAR(expected, fe, kTol * fe) << what << " mode " << k << " at " << rpm << " rpm";
    };
    if (rpm == 0.0) {
      // No spin: the planes are identical, each frequency twice; the eigenvectors' sense is arbitrary.
      std::vector<double> all = start.forward;
      all.insert(all.end(), start.backward.begin(), start.backward.end());
      std::sort(all.begin(), all.end());
      for (int k = 0; k < 4; ++k) compare(exact.forward_hz[k], all[2 * k], true, "standstill", k + 1);
      continue;
    }
    // The FE's forward list starts with the conical mode.
    compare(exact.conical_hz, start.forward[0], true, "conical", 0);
    for (int k = 0; k < 4; ++k) {
      compare(exact.forward_hz[k], start.forward[k + 1], true, "forward", k + 1);
      compare(exact.backward_hz[k], start.backward[k], false, "backward", k + 1);
    }
    // Physics, independent of both: forward rises and backward falls with the spin.
    const toolpoint::WhirlFrequencies still = toolpoint::whirl_frequencies(p, L, 0.0, 4);
    for (int k = 0; k < 4; ++k) {
      EXPECT_GT(exact.forward_hz[k], still.forward_hz[k]);
      EXPECT_LT(exact.backward_hz[k], still.backward_hz[k]);
    }
  }
}

// The conical mode against the rigid body's closed form ρI_p L Ω/J_d, J_d = ρAL³/12 + ρIL: at
// 1000 rpm (conical ≈ 4 Hz, 2000 times below the first elastic mode) the rod is rigid to within
// the square of that ratio, so 1e-5 relative.
TEST(Spin, SlowConicalModeIsTheRigidBodys) {
  const SectionProperties p = rod_section(0.04);
  const double L = 0.15, spin = rpm_to_rad_s(1000.0);
  const double Jd = p.rhoA * L * L * L / 12.0 + p.rhoI * L;
  const double rigid = 2.0 * p.rhoI * L * spin / Jd / (2.0 * kPi);
  EXPECT_NEAR(toolpoint::whirl_frequencies(p, L, spin, 2).conical_hz, rigid, 1e-5 * rigid);
}

// The directional FRFs' sign convention: the exact two-plane T11 (x = L) against the FE rotor's
// (K(1+iη) + iωΩG − ω²M)⁻¹ at the last node, η = 0.02, 60 000 rpm, between the backward and the
// forward first mode and above it. The FE receptance converges like h² (fe_beam.hpp): 48 and 96
// elements extrapolated are good to ~1e-5 of the block here; 1e-4 of the block's norm is asked,
// while a wrong sense of rotation would change H_xy by 2|H_xy| (≈ 1e-2 of the block at least).
TEST(Spin, DirectionalFrfSignAgreesWithTheFiniteElementRotor) {
  const SectionProperties p = rod_section(0.04, 0.02);
  const double L = 0.15, spin = rpm_to_rad_s(60000.0);
  const toolpoint::WhirlFrequencies w = toolpoint::whirl_frequencies(p, L, spin, 1);
  ASSERT_GT(w.forward_hz[0] - w.backward_hz[0], 10.0);
  for (double f : {0.5 * (w.forward_hz[0] + w.backward_hz[0]), w.forward_hz[0] + 5.0, 2000.0}) {
    const double om = 2.0 * kPi * f;
    auto fe_tip = [&](int n) {
      const FeRotor r = fe_rotor(p, L, n);
      const Eigen::MatrixXcd D = fe_oracle::dynamic_stiffness(r, om, spin);
      const int t = 4 * (r.nodes - 1);
      Eigen::MatrixXcd F = Eigen::MatrixXcd::Zero(D.rows(), 4);
      for (int j = 0; j < 4; ++j) F(t + j, j) = 1.0;
      const Eigen::MatrixXcd X = D.partialPivLu().solve(F);
      return Eigen::Matrix4cd(X.middleRows(t, 4));
    };
    const Eigen::Matrix4cd fe = (4.0 * fe_tip(96) - fe_tip(48)) / 3.0;
    const toolpoint::Block4 exact = toolpoint::spinning_receptance(p, L, f, spin).b11;
    EXPECT_LT((exact - fe).norm(), 1e-4 * fe.norm()) << f << " Hz";
    // H_xy itself, to 1e-3 of its own size, and skew: H_yx = −H_xy.
    EXPECT_LT(std::abs(exact(0, 2) - fe(0, 2)), 1e-3 * std::abs(fe(0, 2))) << f << " Hz";
    EXPECT_LT(std::abs(exact(2, 0) + exact(0, 2)), 1e-12 * std::abs(exact(0, 2)));
  }
}

// Bad input: a non-finite spin, a non-positive whirl frequency, count < 1.
TEST(Spin, BadInputIsRefused) {
  const SectionProperties p = rod_section(0.04);
  EXPECT_THROW(toolpoint::whirl_receptance(p, 0.15, 100.0, std::nan(""), Whirl::Forward), toolpoint::InvalidArgument);
  EXPECT_THROW(toolpoint::whirl_receptance(p, 0.15, 0.0, 100.0, Whirl::Forward), toolpoint::InvalidArgument);
  EXPECT_THROW(toolpoint::whirl_frequencies(p, 0.15, 100.0, 0), toolpoint::InvalidArgument);
}
