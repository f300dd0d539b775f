// toolpoint: receptance coupling (seed Eq. 1–5) and structural modification.
#include "toolpoint/coupling.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <fmt/format.h>
#include <vector>

#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

// |z| as sqrt(x² + y²): within an ulp of std::abs (hypot), which guards against over- and
// underflow at several times the cost; std::abs is kept for outside the safe range.
inline double abs_fast(Complex z) {
  const double n = z.real() * z.real() + z.imag() * z.imag();
  return n > 1e-290 && n < 1e290 ? std::sqrt(n) : std::abs(z);
}

// 2×2 products written out: the same sums in the same order as Eigen's coefficient-based
// product, without its per-call temporaries (the coupling runs once per piece per frequency).
inline Block mul(const Block& x, const Block& y) {
  Block r;
  r(0, 0) = x(0, 0) * y(0, 0) + x(0, 1) * y(1, 0);
  r(1, 0) = x(1, 0) * y(0, 0) + x(1, 1) * y(1, 0);
  r(0, 1) = x(0, 0) * y(0, 1) + x(0, 1) * y(1, 1);
  r(1, 1) = x(1, 0) * y(0, 1) + x(1, 1) * y(1, 1);
  return r;
}

// I + x y
inline Block identity_plus_mul(const Block& x, const Block& y) {
  Block r = mul(x, y);
  r(0, 0) += 1.0;
  r(1, 1) += 1.0;
  return r;
}

}  // namespace

Block inverse_checked(const Block& m, const char* what) {
  const Complex ad = m(0, 0) * m(1, 1), bc = m(0, 1) * m(1, 0);
  const Complex det = ad - bc;
  const double adet = abs_fast(det);
  if (!(adet > 1e-14 * (abs_fast(ad) + abs_fast(bc))) || !std::isfinite(adet))
    throw NumericalError(fmt::format("{} is singular: {} (|det| = {:.3g})", what, format_block(m), std::abs(det)),
                         "the structure has an undamped resonance exactly at this frequency, or the data are "
                         "inconsistent; add damping or move the frequency grid");
  const Complex r = 1.0 / det;
  Block inv;
  inv(0, 0) = m(1, 1) * r;
  inv(1, 0) = -m(1, 0) * r;
  inv(0, 1) = -m(0, 1) * r;
  inv(1, 1) = m(0, 0) * r;
  return inv;
}

double condition_number(const Block& m) {
  // σ² are the eigenvalues of the Hermitian MᴴM: (t ± sqrt(t² − 4d))/2 with t = ‖M‖_F², d = |det M|².
  const double t = m.squaredNorm();
  const double d = std::norm(m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0));
  const double disc = std::sqrt(std::max(t * t - 4.0 * d, 0.0));
  const double smax2 = 0.5 * (t + disc);
  if (smax2 <= 0.0) return std::numeric_limits<double>::infinity();
  const double smin2 = d / smax2;  // product of the two is d; avoids cancellation in t − disc
  return smin2 > 0.0 ? std::sqrt(smax2 / smin2) : std::numeric_limits<double>::infinity();
}

double frobenius_condition(const Block& m) {
  const double det = abs_fast(m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0));
  return det > 0.0 ? m.squaredNorm() / det : std::numeric_limits<double>::infinity();
}

namespace {

Block interface_rigid(const TwoPort& a, const Block& b11) { return inverse_checked(a.b22 + b11, "rigid-coupling interface matrix (A22 + B11)"); }

Block interface_elastic(const TwoPort& a, const Block& b11, const Block& K) {
  return mul(K, inverse_checked(identity_plus_mul(a.b22 + b11, K), "elastic-coupling interface matrix (I + (A22 + B11) K)"));
}

TwoPort assemble(const TwoPort& a, const TwoPort& b, const Block& X) {
  const Block xa21 = mul(X, a.b21), xb12 = mul(X, b.b12);
  return {a.b11 - mul(a.b12, xa21), mul(a.b12, xb12), mul(b.b21, xa21), b.b22 - mul(b.b21, xb12)};
}

}  // namespace

TwoPort couple_elastic(const TwoPort& a, const TwoPort& b, const Block& K) { return assemble(a, b, interface_elastic(a, b.b11, K)); }

TwoPort couple_rigid(const TwoPort& a, const TwoPort& b) { return assemble(a, b, interface_rigid(a, b.b11)); }

TwoPort couple(const TwoPort& a, const TwoPort& b, const Joint& joint, double frequency_hz) {
  return joint.rigid ? couple_rigid(a, b) : couple_elastic(a, b, joint.parameters.stiffness(frequency_hz));
}

Block couple_elastic_point(const TwoPort& a, const Block& b11, const Block& K) {
  return a.b11 - mul(mul(a.b12, interface_elastic(a, b11, K)), a.b21);
}

Block couple_rigid_point(const TwoPort& a, const Block& b11) { return a.b11 - mul(mul(a.b12, interface_rigid(a, b11)), a.b21); }

Block couple_point(const TwoPort& a, const Block& b11, const Joint& joint, double frequency_hz) {
  return joint.rigid ? couple_rigid_point(a, b11) : couple_elastic_point(a, b11, joint.parameters.stiffness(frequency_hz));
}

Junction couple_rigid_junction(const TwoPort& a, const Block& b11) {
  // Loads at A1 and at j; f_A2 (A's share at j) from compatibility x_A2 = x_B1 and equilibrium.
  const Block X = interface_rigid(a, b11);
  Junction j;
  j.g11 = a.b11 - a.b12 * X * a.b21;
  j.gj1 = b11 * X * a.b21;
  j.g1j = a.b12 * X * b11;
  j.gjj = a.b22 * X * b11;
  return j;
}

Eigen::MatrixXcd as_matrix(const TwoPort& t) {
  Eigen::MatrixXcd m(4, 4);
  m << t.b11, t.b12, t.b21, t.b22;
  return m;
}

Eigen::MatrixXcd join_rigid(const Eigen::MatrixXcd& A, Eigen::Index a_node, const Eigen::MatrixXcd& B, Eigen::Index b_node) {
  const Eigen::Index na = A.rows() / 2, nb = B.rows() / 2;
  if (a_node < 0 || a_node >= na || b_node < 0 || b_node >= nb)
    throw InvalidArgument(fmt::format("join_rigid: points {} and {} outside {} and {} points", a_node, b_node, na, nb));
  const Eigen::Index n = na + nb - 1;
  // Map B's points to result points: b_node → a_node, others after A's.
  std::vector<Eigen::Index> bmap(static_cast<std::size_t>(nb));
  for (Eigen::Index k = 0, next = na; k < nb; ++k) bmap[static_cast<std::size_t>(k)] = k == b_node ? a_node : next++;
  const Block X = inverse_checked(A.block<2, 2>(2 * a_node, 2 * a_node) + B.block<2, 2>(2 * b_node, 2 * b_node),
                                  "rigid-junction matrix (A_jj + B_jj)");
  // Loads F_A (A's points), F_B (B's points), F_j at the junction: A's share of the junction
  // force f_a = X (B_jB F_B + B_jj F_j − A_jA F_A) (F_j counted in B's columns), f_b = F_j − f_a.
  // Responses: x_A = A_A· F + A_Aj f_a, x_B = B_B· F + B_Bj f_b. Assemble column blocks per load.
  Eigen::MatrixXcd G = Eigen::MatrixXcd::Zero(2 * n, 2 * n);
  const Eigen::MatrixXcd Aj = A.middleRows(2 * a_node, 2);  // A_j· (2 × 2na)
  const Eigen::MatrixXcd Bj = B.middleRows(2 * b_node, 2);  // B_j· (2 × 2nb)
  const Eigen::MatrixXcd Acj = A.middleCols(2 * a_node, 2), Bcj = B.middleCols(2 * b_node, 2);
  // Loads on A's points (excluding the junction): f_a = −X A_jA F, f_b = −f_a.
  for (Eigen::Index p = 0; p < na; ++p) {
    if (p == a_node) continue;
    const Eigen::MatrixXcd fa = -X * Aj.middleCols(2 * p, 2);
    G.middleCols(2 * p, 2).topRows(2 * na) = A.middleCols(2 * p, 2) + Acj * fa;
    for (Eigen::Index k = 0; k < nb; ++k)
      if (k != b_node) G.block(2 * bmap[static_cast<std::size_t>(k)], 2 * p, 2, 2) = -B.block(2 * k, 2 * b_node, 2, 2) * fa;
  }
  // Loads on B's points (including the junction, where B's column carries F_j):
  for (Eigen::Index q = 0; q < nb; ++q) {
    const Eigen::Index col = bmap[static_cast<std::size_t>(q)];
    const Eigen::MatrixXcd fa = X * Bj.middleCols(2 * q, 2);
    const Eigen::MatrixXcd fb = (q == b_node ? Eigen::MatrixXcd(Eigen::MatrixXcd::Identity(2, 2)) : Eigen::MatrixXcd::Zero(2, 2)) - fa;
    G.middleCols(2 * col, 2).topRows(2 * na) = Acj * fa;
    for (Eigen::Index k = 0; k < nb; ++k)
      if (k != b_node) G.block(2 * bmap[static_cast<std::size_t>(k)], 2 * col, 2, 2) = (q == b_node ? Eigen::MatrixXcd(Eigen::MatrixXcd::Zero(2, 2)) : Eigen::MatrixXcd(B.block(2 * k, 2 * q, 2, 2))) + Bcj.middleRows(2 * k, 2) * fb;
  }
  return G;
}

Eigen::MatrixXcd ground_node(const Eigen::MatrixXcd& G, Eigen::Index node, const Block& D) {
  const Block Y = D * inverse_checked(Block::Identity() + G.block<2, 2>(2 * node, 2 * node) * D, "structural-modification matrix (I + G_nn D)");
  return G - G.middleCols(2 * node, 2) * Y * G.middleRows(2 * node, 2);
}

Block ground_point(const Block& h, const Block& D) {
  return mul(h, inverse_checked(identity_plus_mul(D, h), "structural-modification matrix (I + D H)"));
}

TwoPort ground_end1(const TwoPort& t, const Block& D) {
  const Block Y = mul(D, inverse_checked(identity_plus_mul(t.b11, D), "structural-modification matrix (I + T11 D)"));
  const Block y11 = mul(Y, t.b11), y12 = mul(Y, t.b12);
  return {t.b11 - mul(t.b11, y11), t.b12 - mul(t.b11, y12), t.b21 - mul(t.b21, y11), t.b22 - mul(t.b21, y12)};
}

TwoPort ground_end2(const TwoPort& t, const Block& D) {
  const Block Y = mul(D, inverse_checked(identity_plus_mul(t.b22, D), "structural-modification matrix (I + T22 D)"));
  const Block y21 = mul(Y, t.b21), y22 = mul(Y, t.b22);
  return {t.b11 - mul(t.b12, y21), t.b12 - mul(t.b12, y22), t.b21 - mul(t.b22, y21), t.b22 - mul(t.b22, y22)};
}

}  // namespace toolpoint
