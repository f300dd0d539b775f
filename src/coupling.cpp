// toolpoint: receptance coupling (seed Eq. 1–5) and structural modification.
#include "toolpoint/model/coupling.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <fmt/format.h>
#include <vector>

#include "complex_pairs.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

using detail::block;
using detail::cols;
using detail::Cols;

// I + m
inline Cols identity_plus(Cols m) {
  m.c0.re[0] += 1.0;
  m.c1.re[1] += 1.0;
  return m;
}

// The four blocks of a two-end component by columns.
struct Port {
  Cols b11, b12, b21, b22;
};
inline Port port(const TwoPort& t) { return {cols(t.b11), cols(t.b12), cols(t.b21), cols(t.b22)}; }
inline TwoPort two_port(const Port& p) { return {block(p.b11), block(p.b12), block(p.b21), block(p.b22)}; }

}  // namespace

Block inverse_checked(const Block& m, const char* what) { return block(detail::inverse_checked(cols(m), what)); }

void detail::throw_singular(const Block& m, const char* what) {
  const Complex det = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  // A determinant that overflows, or underflows while the entries do not vanish, is a matter of
  // range, not of a singular matrix: say so rather than blame a resonance.
  double largest = 0.0;
  bool finite = true;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      finite = finite && std::isfinite(m(r, c).real()) && std::isfinite(m(r, c).imag());
      largest = std::max(largest, std::abs(m(r, c)));
    }
  if (!finite || !std::isfinite(std::abs(det)) || (largest > 0.0 && largest < 1e-145))
    throw NumericalError(fmt::format("{} cannot be inverted in double precision: its entries reach {:.3g}, and its "
                                     "determinant {}: out of the range of double precision",
                                     what, largest,
                                     std::isfinite(std::abs(det)) ? fmt::format("is {:.3g}", std::abs(det)) : "overflows"),
                         "check the magnitudes and units of the receptances (m/N, rad/(N m)) and joint values given");
  throw NumericalError(fmt::format("{} is singular: {} (|det| = {:.3g})", what, format_block(m), std::abs(det)),
                       "the structure has an undamped resonance exactly at this frequency, or the data are "
                       "inconsistent; add damping or move the frequency grid");
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
  const double det = std::abs(m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0));
  return det > 0.0 ? m.squaredNorm() / det : std::numeric_limits<double>::infinity();
}

namespace {

Cols interface_rigid(const Cols& a22, const Cols& b11) {
  return detail::inverse_checked(a22 + b11, "rigid-coupling interface matrix (A22 + B11)");
}

Cols interface_elastic(const Cols& a22, const Cols& b11, const Cols& K) {
  return K * detail::inverse_checked(identity_plus((a22 + b11) * K), "elastic-coupling interface matrix (I + (A22 + B11) K)");
}

TwoPort assemble(const Port& a, const Port& b, const Cols& X) {
  const Cols xa21 = X * a.b21, xb12 = X * b.b12;
  return two_port({a.b11 - a.b12 * xa21, a.b12 * xb12, b.b21 * xa21, b.b22 - b.b21 * xb12});
}

}  // namespace

TwoPort couple_elastic(const TwoPort& a, const TwoPort& b, const Block& K) {
  const Port pa = port(a), pb = port(b);
  return assemble(pa, pb, interface_elastic(pa.b22, pb.b11, cols(K)));
}

TwoPort couple_rigid(const TwoPort& a, const TwoPort& b) {
  const Port pa = port(a), pb = port(b);
  return assemble(pa, pb, interface_rigid(pa.b22, pb.b11));
}

TwoPort couple(const TwoPort& a, const TwoPort& b, const Joint& joint, double frequency_hz) {
  return joint.rigid ? couple_rigid(a, b) : couple_elastic(a, b, joint.parameters.stiffness(frequency_hz));
}

Block couple_elastic_point(const TwoPort& a, const Block& b11, const Block& K) {
  return block(cols(a.b11) - (cols(a.b12) * interface_elastic(cols(a.b22), cols(b11), cols(K))) * cols(a.b21));
}

Block couple_rigid_point(const TwoPort& a, const Block& b11) {
  return block(cols(a.b11) - (cols(a.b12) * interface_rigid(cols(a.b22), cols(b11))) * cols(a.b21));
}

Block couple_point(const TwoPort& a, const Block& b11, const Joint& joint, double frequency_hz) {
  return joint.rigid ? couple_rigid_point(a, b11) : couple_elastic_point(a, b11, joint.parameters.stiffness(frequency_hz));
}

Junction couple_rigid_junction(const TwoPort& a, const Block& b11) {
  // Loads at A1 and at j; f_A2 (A's share at j) from compatibility x_A2 = x_B1 and equilibrium.
  const Block X = block(interface_rigid(cols(a.b22), cols(b11)));
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
    const Eigen::MatrixXcd fb = (q == b_node ? Eigen::MatrixXcd(Eigen::MatrixXcd::Identity(2, 2))
                                             : Eigen::MatrixXcd::Zero(2, 2)) -
                                fa;
    G.middleCols(2 * col, 2).topRows(2 * na) = Acj * fa;
    for (Eigen::Index k = 0; k < nb; ++k)
      if (k != b_node)
        G.block(2 * bmap[static_cast<std::size_t>(k)], 2 * col, 2, 2) = (q == b_node
                                                                             ? Eigen::MatrixXcd(Eigen::MatrixXcd::Zero(2, 2))
                                                                             : Eigen::MatrixXcd(B.block(2 * k, 2 * q, 2, 2))) +
                                                                        Bcj.middleRows(2 * k, 2) * fb;
  }
  return G;
}

Eigen::MatrixXcd ground_node(const Eigen::MatrixXcd& G, Eigen::Index node, const Block& D) {
  const Block Y = D * inverse_checked(Block::Identity() + G.block<2, 2>(2 * node, 2 * node) * D,
                                      "structural-modification matrix (I + G_nn D)");
  return G - G.middleCols(2 * node, 2) * Y * G.middleRows(2 * node, 2);
}

Block ground_point(const Block& h, const Block& D) {
  const Cols hc = cols(h);
  return block(hc * detail::inverse_checked(identity_plus(cols(D) * hc), "structural-modification matrix (I + D H)"));
}

TwoPort ground_end1(const TwoPort& t, const Block& D) {
  const Port p = port(t);
  const Cols d = cols(D);
  const Cols Y = d * detail::inverse_checked(identity_plus(p.b11 * d), "structural-modification matrix (I + T11 D)");
  const Cols y11 = Y * p.b11, y12 = Y * p.b12;
  return two_port({p.b11 - p.b11 * y11, p.b12 - p.b11 * y12, p.b21 - p.b21 * y11, p.b22 - p.b21 * y12});
}

TwoPort ground_end2(const TwoPort& t, const Block& D) {
  const Port p = port(t);
  const Cols d = cols(D);
  const Cols Y = d * detail::inverse_checked(identity_plus(p.b22 * d), "structural-modification matrix (I + T22 D)");
  const Cols y21 = Y * p.b21, y22 = Y * p.b22;
  return two_port({p.b11 - p.b12 * y21, p.b12 - p.b12 * y22, p.b21 - p.b22 * y21, p.b22 - p.b22 * y22});
}

}  // namespace toolpoint

// ---- Two planes ---------------------------------------------------------------------------------

namespace toolpoint {

namespace {

// A 4×4 inverse, refused where the smallest pivot is below 1e-14 of the largest (as
// inverse_checked's relative determinant test for 2×2 blocks). Gauss–Jordan with complete
// pivoting (the pivots of a complete-pivoting LU), pivots compared by squared modulus: no square
// roots (hypot) in the 4×4 walks of the two-plane model, where they were a fifth of the time.
Block4 inverse4_checked(const Block4& m, const char* what) {
  Eigen::Matrix<Complex, 4, 8> a;
  a.leftCols<4>() = m;
  a.rightCols<4>() = Block4::Identity();
  int col_of[4] = {0, 1, 2, 3};  // the column order the pivots impose (undone at the end)
  double largest2 = 0.0, smallest2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    int pr = k, pc = k;
    double best = -1.0;
    for (int r = k; r < 4; ++r)
      for (int c = k; c < 4; ++c)
        if (const double v = std::norm(a(r, c)); v > best) {
          best = v;
          pr = r;
          pc = c;
        }
    largest2 = std::max(largest2, best);
    smallest2 = std::min(smallest2, best);
    if (!(best > 0.0) || !std::isfinite(best)) break;
    a.row(k).swap(a.row(pr));
    if (pc != k) {
      a.col(k).swap(a.col(pc));
      std::swap(col_of[k], col_of[pc]);
    }
    const Complex inv = 1.0 / a(k, k);
    a.row(k) *= inv;
    for (int r = 0; r < 4; ++r)
      if (r != k && a(r, k) != Complex(0.0)) a.row(r) -= a(r, k) * a.row(k);
  }
  if (!(smallest2 > 1e-28 * largest2) || !std::isfinite(largest2))
    throw NumericalError(fmt::format("the {} is singular to working precision", what),
                         "a resonance of an undamped structure hit exactly: add damping or move the frequency");
  // With columns permuted, A P = L…: the rows of the inverse come back in the columns' order.
  Block4 inv;
  for (int k = 0; k < 4; ++k) inv.row(col_of[k]) = a.block<1, 4>(k, 4);
  return inv;
}

Block4 both_planes(const Block& k) {
  Block4 b = Block4::Zero();
  b.topLeftCorner<2, 2>() = k;
  b.bottomRightCorner<2, 2>() = k;
  return b;
}

}  // namespace

Block4 couple_rigid_point(const TwoPort4& a, const Block4& b11) {
  return a.b11 - a.b12 * inverse4_checked(a.b22 + b11, "rigid interface matrix (A22 + B11)") * a.b21;
}

Block4 couple_point(const TwoPort4& a, const Block4& b11, const Joint& joint, double frequency_hz) {
  if (joint.rigid) return couple_rigid_point(a, b11);
  // X = K (I + (A22 + B11) K)⁻¹ = (A22 + K⁻¹ + B11)⁻¹ without K⁻¹ (couple_elastic's form).
  const Block4 K = both_planes(joint.parameters.stiffness(frequency_hz));
  const Block4 X = K * inverse4_checked(Block4::Identity() + (a.b22 + b11) * K, "elastic interface matrix (I + (A22 + B11) K)");
  return a.b11 - a.b12 * X * a.b21;
}

Block4 ground_point(const Block4& h, const Block4& D) {
  return h * inverse4_checked(Block4::Identity() + D * h, "structural-modification matrix (I + D H)");
}

Block4 ground_end2_point(const TwoPort4& t, const Block4& D) {
  return t.b11 -
         t.b12 * (D * inverse4_checked(Block4::Identity() + t.b22 * D, "structural-modification matrix (I + T22 D)")) * t.b21;
}

}  // namespace toolpoint
