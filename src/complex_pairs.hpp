// toolpoint (internal: under src/, never installed): two complex numbers per vector register, for
// the per-frequency kernels of beam, coupling and identify. It lives here, not in a public header,
// because its complex division is only right when compiled with the library's own
// -fcx-fortran-rules (a consumer's flags could differ) and it uses a GCC/Clang vector extension.
//
// The std::complex code GCC emits for small complex matrices spends as many instructions moving
// values as computing and leaves half of each SSE2 register idle. A CPair holds two complex numbers with
// both real parts in one vector and both imaginary parts in another (GCC/Clang vector extension:
// SSE2 on x86-64, scalars elsewhere), so one product serves two matrix entries. The operations are
// those of std::complex under -fcx-fortran-rules, (ac − bd) + i(ad + bc), and of Eigen's 2×2
// product, so results are bit-identical to the scalar forms.
#pragma once

#include <cmath>
#include <complex>

#include "toolpoint/model/receptance.hpp"

namespace toolpoint::detail {

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
  if (!(n[0] > 1e-290 && n[0] < 1e290 && n[1] > 1e-290 && n[1] < 1e290))
    return pair(reciprocal(lane(z, 0)), reciprocal(lane(z, 1)));
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
  if (!well_above_roundoff(det, ad, bc) || !std::isfinite(det.real()) || !std::isfinite(det.imag()))
    throw_singular(block(m), what);
  const CPair r = both(1.0 / det);
  const Lanes neg{1.0, -1.0};
  // [[m11, −m01], [−m10, m00]] r
  return {CPair{Lanes{m.c1.re[1], m.c0.re[1]} * neg, Lanes{m.c1.im[1], m.c0.im[1]} * neg} * r,
          CPair{Lanes{m.c1.re[0], m.c0.re[0]} * -neg, Lanes{m.c1.im[0], m.c0.im[0]} * -neg} * r};
}

}  // namespace toolpoint::detail
