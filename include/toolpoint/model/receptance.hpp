// toolpoint: receptance blocks and frequency series.
//
// Units (SI): frequency in Hz at every interface (rad/s only inside formulas), displacement w in
// m, rotation θ in rad, force f in N, moment m in N·m.
//
// A receptance block at a pair of points j, k (seed Eq. 10):
//     [[H, L],   H = w_j/f_k [m/N]      L = w_j/m_k [m/(N·m) = 1/N]
//      [N, P]]   N = θ_j/f_k [rad/N]    P = θ_j/m_k [rad/(N·m)]
// A component with two connection ends holds four such blocks: 11 (point receptance at end 1),
// 12 (response at end 1 to loads at end 2), 21 and 22. The sign convention is in conventions.hpp.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

namespace toolpoint {

using Complex = std::complex<double>;

// [[H, L], [N, P]] at one frequency. An Eigen fixed-size type: lives on the stack.
using Block = Eigen::Matrix2cd;

inline Complex H_of(const Block& b) { return b(0, 0); }
inline Complex L_of(const Block& b) { return b(0, 1); }
inline Complex N_of(const Block& b) { return b(1, 0); }
inline Complex P_of(const Block& b) { return b(1, 1); }
inline Block make_block(Complex h, Complex l, Complex n, Complex p) {
  Block b;
  b << h, l, n, p;
  return b;
}

// End receptances of a component with ends 1 and 2 at one frequency.
struct TwoPort {
  Block b11, b12, b21, b22;
};

// Two planes together: a 4×4 block on the DOFs (w_x, ψ_x, w_y, ψ_y) (beam.hpp, "A segment
// spinning about its axis": x, y transverse, z the axis, each plane with the planar convention).
using Block4 = Eigen::Matrix4cd;
// End blocks of a two-plane component with ends 1 and 2.
struct TwoPort4 {
  Block4 b11, b12, b21, b22;
};

// The two-plane block of an axisymmetric component from its whirls' planar blocks: with
// r = w_x + i w_y and likewise for ψ and the loads, r = F (f_x + i f_y) (forward) and
// w_x − i w_y = B (f_x − i f_y) (backward) give
//     [[xx, xy], [yx, yy]] = [[(F + B)/2, i(F − B)/2], [−i(F − B)/2, (F + B)/2]]
// (docs/reference.md §10): the cross blocks are skew (gyroscopic) and vanish when F = B (no spin).
Block4 two_plane(const Block& forward, const Block& backward);
TwoPort4 two_plane(const TwoPort& forward, const TwoPort& backward);
// The same 2×2 block in both planes, no cross terms (a standing, isotropic component).
Block4 two_plane(const Block& both);

// A two-plane 4×4 block per frequency.
struct BlockSeries4 {
  std::vector<double> frequency_hz;
  std::vector<Block4> blocks;

  std::size_t size() const { return frequency_hz.size(); }
};

// A 2×2 receptance block per frequency (the FRF CSV's 9-column form).
struct BlockSeries {
  std::vector<double> frequency_hz;
  std::vector<Block> blocks;

  std::size_t size() const { return frequency_hz.size(); }
};

// A single complex FRF per frequency (the FRF CSV's 3-column form).
struct FrfSeries {
  std::vector<double> frequency_hz;
  std::vector<Complex> values;

  std::size_t size() const { return frequency_hz.size(); }
};

// "re+imi" with 6 significant digits, for messages (fmt 9 has no std::complex formatter).
std::string format_complex(Complex z);
// "[[H, L], [N, P]]" with format_complex entries.
std::string format_block(const Block& b);

// One entry of every block (0: H, 1: L, 2: N, 3: P) as a single FRF.
FrfSeries entry(const BlockSeries& series, int index);

// Checks that the series is usable: sizes agree, at least `min_points` points, frequencies finite,
// positive and strictly increasing, values finite. `what` names the data (a file name) in errors.
// Throws InputError.
void validate(const BlockSeries& series, const std::string& what, std::size_t min_points = 1);
void validate(const FrfSeries& series, const std::string& what, std::size_t min_points = 1);

// A direct (point) FRF meant as a receptance that is a mobility: a point mobility Y = iωH has
// Re Y = −ω Im H ≥ 0 at every frequency and Im Y = ω Re H, which changes sign at each resonance,
// where a point receptance has Im H ≤ 0 at every frequency (conventions.hpp). Said when Re ≥ 0 at
// 95 % of the points of |G| ≥ 1 % of its largest and Im takes either sign at 10 % of them each.
// Throws InputError naming `what` (fit or lobes from such data give negative masses, nonsense).
void require_not_mobility(const FrfSeries& series, const std::string& what);

// Throws InputError unless the two grids hold the same frequencies (relative tolerance 1e-9).
void require_same_grid(const std::vector<double>& a, const std::string& what_a, const std::vector<double>& b,
                       const std::string& what_b);

}  // namespace toolpoint
