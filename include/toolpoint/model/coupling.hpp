// toolpoint: receptance coupling and structural modification, one frequency at a time.
//
// All blocks follow conventions.hpp: one global axis, every component's end 1 outer, end 2 inner,
// and A's end 2 joined to B's end 1. Units of blocks as in receptance.hpp; joint stiffness K and
// ground stiffness D as in joint.hpp (N/m, N, N/rad, N·m/rad; complex parts ω·c).
#pragma once

#include <Eigen/Core>

#include "toolpoint/model/joint.hpp"
#include "toolpoint/model/receptance.hpp"

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

// ---- Two planes (4×4 blocks on w_x, ψ_x, w_y, ψ_y; receptance.hpp's Block4) ---------------------

// The same algebra as couple_rigid_point, couple_point (the joint's K(ω) in both planes alike),
// ground_point and ground_end2 (point at end 1 only) for two-plane blocks. Throw NumericalError
// where the 4×4 inverse is singular to working precision.
Block4 couple_rigid_point(const TwoPort4& a, const Block4& b11);
Block4 couple_point(const TwoPort4& a, const Block4& b11, const Joint& joint, double frequency_hz);
Block4 ground_point(const Block4& h, const Block4& D);
// T11 − T12 D (I + T22 D)⁻¹ T21: end 1's point receptance with springs D at end 2.
Block4 ground_end2_point(const TwoPort4& t, const Block4& D);

}  // namespace toolpoint
