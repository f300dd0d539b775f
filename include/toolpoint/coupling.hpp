// toolpoint: receptance coupling and structural modification, one frequency at a time.
//
// All blocks follow conventions.hpp: one global axis, every component's end 1 outer, end 2 inner,
// and A's end 2 joined to B's end 1. Units of blocks as in receptance.hpp; joint stiffness K and
// ground stiffness D as in joint.hpp (N/m, N, N/rad, N·m/rad; complex parts ω·c).
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "toolpoint/joint.hpp"
#include "toolpoint/receptance.hpp"

namespace toolpoint {

// Inverse of a 2×2 block; throws NumericalError naming `what` when it is singular to working
// precision (|det| ≤ 1e-14 (|ad| + |bc|)).
Block inverse_checked(const Block& m, const char* what);

// 2-norm condition number σ_max/σ_min of a 2×2 block (∞ when singular).
double condition_number(const Block& m);
// Frobenius condition number ‖M‖_F ‖M⁻¹‖_F = ‖M‖²_F / |det M| (∞ when singular); for a 2×2 it
// lies between cond₂ and cond₂ + 1/cond₂, at a fraction of the cost.
double frobenius_condition(const Block& m);

// Elastic coupling, seed Eq. (1)–(4): with X = (A22 + K⁻¹ + B11)⁻¹,
//   G11 = A11 − A12 X A21,  G12 = A12 X B12,  G21 = B21 X A21,  G22 = B22 − B21 X B12.
// X is formed as K (I + (A22 + B11) K)⁻¹, which needs no inverse of K: a hinge (singular K) or a
// free joint (K = 0) are legal. The result's ends are A's end 1 and B's end 2.
TwoPort couple_elastic(const TwoPort& a, const TwoPort& b, const Block& K);

// Rigid coupling: the same with K⁻¹ = 0, X = (A22 + B11)⁻¹.
TwoPort couple_rigid(const TwoPort& a, const TwoPort& b);

// Through a Joint (rigid or elastic with K(ω) from its parameters) at `frequency_hz`.
TwoPort couple(const TwoPort& a, const TwoPort& b, const Joint& joint, double frequency_hz);

// Only G11 of the above, seed Eq. (1) and (5): the point receptance at A's end 1 when B is
// known only by its point receptance B11 at the joined end.
Block couple_elastic_point(const TwoPort& a, const Block& b11, const Block& K);
Block couple_rigid_point(const TwoPort& a, const Block& b11);
Block couple_point(const TwoPort& a, const Block& b11, const Joint& joint, double frequency_hz);

// Receptances around a rigid junction j between A (ends 1 and j) and a structure known by its
// point receptance B11 at j: G11 (= couple_rigid_point), G1j, Gj1 and Gjj. Used to reach interior
// stations (finite-difference points, bearing positions).
struct Junction {
  Block g11, g1j, gj1, gjj;
};
Junction couple_rigid_junction(const TwoPort& a, const Block& b11);

// Receptances over several points (2 DOFs per point, block (i, j) = response at i to a load at
// j), for structures whose interior points matter. `join_rigid` joins point a_node of A to point
// b_node of B rigidly and keeps every point: the result lists A's points (a_node being the
// junction), then B's points without b_node. Same algebra as couple_rigid_junction: one 2×2
// inverse (A_jj + B_jj)⁻¹, no inverse of a free–free receptance.
Eigen::MatrixXcd join_rigid(const Eigen::MatrixXcd& A, Eigen::Index a_node, const Eigen::MatrixXcd& B, Eigen::Index b_node);
// A two-end component as a 2-point matrix (point 0 = end 1, point 1 = end 2).
Eigen::MatrixXcd as_matrix(const TwoPort& t);
// Ground springs with dynamic stiffness D at point `node`: G' = G − G[:, n] D (I + G_nn D)⁻¹ G[n, :].
Eigen::MatrixXcd ground_node(const Eigen::MatrixXcd& G, Eigen::Index node, const Block& D);

// Structural modification (Özgüven): springs/dampers to ground with dynamic stiffness D (2×2,
// e.g. diag(k + iωc, k_θ + iωc_θ)) at one point. H' = H − H (D⁻¹ + H)⁻¹ H, evaluated as
// H (I + D H)⁻¹ so that D may be singular (no rotational spring).
Block ground_point(const Block& h, const Block& D);
// The same at end 1 or end 2 of a two-end component: every block changes,
// T' = T − T[:, e] D (I + T_ee D)⁻¹ T[e, :].
TwoPort ground_end1(const TwoPort& t, const Block& D);
TwoPort ground_end2(const TwoPort& t, const Block& D);

// ---- Internal: two complex numbers per vector register ------------------------------------------
// Not part of the API: the per-frequency kernels of beam, coupling and identify share it. The
// std::complex code GCC emits for small complex matrices spends as many instructions moving values
// as computing and leaves half of each SSE2 register idle. A CPair holds two complex numbers with
// both real parts in one vector and both imaginary parts in another (GCC/Clang vector extension:
// SSE2 on x86-64, scalars elsewhere), so one product serves two matrix entries. The operations are
// those of std::complex under -fcx-fortran-rules, (ac − bd) + i(ad + bc), and of Eigen's 2×2
// product, so results are bit-identical to the scalar forms.
namespace detail {

// |z| as sqrt(x² + y²): within an ulp of std::abs (hypot), which guards against over- and
// underflow at several times the cost; std::abs is kept for outside the safe range.
inline double abs_fast(Complex z) {
  const double n = z.real() * z.real() + z.imag() * z.imag();
  return (n > 1e-290 && n < 1e290) || z == Complex(0.0, 0.0) ? std::sqrt(n) : std::abs(z);
}

// |d| > 1e-14 (|x| + |y|), the singularity test of a 2×2 determinant d = x − y, with one square
// root instead of three: both sides squared, (|x| + |y|)² = |x|² + |y|² + 2 sqrt(|x|²|y|²). The
// abs form is kept where a square could over- or underflow; false for NaN, as the abs form.
inline bool well_above_roundoff(Complex d, Complex x, Complex y) {
  const double nd = std::norm(d), nx = std::norm(x), ny = std::norm(y);
  // Exact zeros are common (a bearing without rotational stiffness) and safe.
  auto in_range = [](double n, Complex z) { return (n > 1e-145 && n < 1e145) || z == Complex(0.0, 0.0); };
  const bool safe = nd > 1e-290 && nd < 1e290 && in_range(nx, x) && in_range(ny, y);
  if (!safe) return abs_fast(d) > 1e-14 * (abs_fast(x) + abs_fast(y));
  return nd > 1e-28 * (nx + ny + 2.0 * std::sqrt(nx * ny));
}

// 1/z as conj(z)/|z|²: one real division instead of Smith's three (a few ulps, like Smith's);
// 1/z is kept outside the range where |z|² neither over- nor underflows.
inline Complex reciprocal(Complex z) {
  const double n = z.real() * z.real() + z.imag() * z.imag();
  if (!(n > 1e-290 && n < 1e290)) return 1.0 / z;
  const double r = 1.0 / n;
  return {z.real() * r, -z.imag() * r};
}

// Throws the NumericalError of inverse_checked (out of line: the message is formatted only then).
[[noreturn]] void throw_singular(const Block& m, const char* what);

typedef double Lanes __attribute__((vector_size(16)));
struct CPair {
  Lanes re, im;
};
inline CPair operator+(const CPair& a, const CPair& b) { return {a.re + b.re, a.im + b.im}; }
inline CPair operator-(const CPair& a, const CPair& b) { return {a.re - b.re, a.im - b.im}; }
inline CPair operator*(const CPair& a, const CPair& b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
inline CPair both(Complex z) { return {Lanes{z.real(), z.real()}, Lanes{z.imag(), z.imag()}}; }
inline CPair pair(Complex x, Complex y) { return {Lanes{x.real(), y.real()}, Lanes{x.imag(), y.imag()}}; }
inline Complex lane(const CPair& a, int i) { return {a.re[i], a.im[i]}; }

// reciprocal() of both lanes, with one vector division (the same quotients as two).
inline CPair reciprocals(const CPair& z) {
  const Lanes n = z.re * z.re + z.im * z.im;
  if (!(n[0] > 1e-290 && n[0] < 1e290 && n[1] > 1e-290 && n[1] < 1e290)) return pair(reciprocal(lane(z, 0)), reciprocal(lane(z, 1)));
  const Lanes r = Lanes{1.0, 1.0} / n;
  return {z.re * r, -z.im * r};
}

// A 2×2 block by columns: c0 = (m00, m10), c1 = (m01, m11).
struct Cols {
  CPair c0, c1;
};
inline Cols cols(const Block& m) { return {pair(m(0, 0), m(1, 0)), pair(m(0, 1), m(1, 1))}; }
inline Block block(const Cols& m) { return make_block(lane(m.c0, 0), lane(m.c1, 0), lane(m.c0, 1), lane(m.c1, 1)); }
inline Cols operator+(const Cols& x, const Cols& y) { return {x.c0 + y.c0, x.c1 + y.c1}; }
inline Cols operator-(const Cols& x, const Cols& y) { return {x.c0 - y.c0, x.c1 - y.c1}; }
// (x y)_ij = x_i0 y_0j + x_i1 y_1j, column j at a time.
inline Cols operator*(const Cols& x, const Cols& y) {
  return {x.c0 * both(lane(y.c0, 0)) + x.c1 * both(lane(y.c0, 1)), x.c0 * both(lane(y.c1, 0)) + x.c1 * both(lane(y.c1, 1))};
}

// inverse_checked by columns: ad and bc as one paired product, then the same operations. For the
// library's own sources only: its complex division must be compiled with the library's
// -fcx-fortran-rules (Smith's), as inverse_checked is.
inline Cols inverse_checked(const Cols& m, const char* what) {
  const CPair adbc = m.c0 * CPair{Lanes{m.c1.re[1], m.c1.re[0]}, Lanes{m.c1.im[1], m.c1.im[0]}};  // (m00 m11, m10 m01)
  const Complex ad = lane(adbc, 0), bc = lane(adbc, 1);
  const Complex det = ad - bc;
  if (!well_above_roundoff(det, ad, bc) || !std::isfinite(det.real()) || !std::isfinite(det.imag())) throw_singular(block(m), what);
  const CPair r = both(1.0 / det);
  const Lanes neg{1.0, -1.0};
  // [[m11, −m01], [−m10, m00]] r
  return {CPair{Lanes{m.c1.re[1], m.c0.re[1]} * neg, Lanes{m.c1.im[1], m.c0.im[1]} * neg} * r,
          CPair{Lanes{m.c1.re[0], m.c0.re[0]} * -neg, Lanes{m.c1.im[0], m.c0.im[0]} * -neg} * r};
}

}  // namespace detail

}  // namespace toolpoint
