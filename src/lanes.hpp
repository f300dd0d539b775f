// toolpoint (internal, not installed): complex arithmetic on four frequencies at once, one
// frequency per AVX2 lane, for the frequency sweeps of the assembly model (sweep.cpp).
//
// A sweep evaluates the same closed forms at thousands of frequencies; written one frequency at
// a time (beam.cpp, coupling.cpp) most of the time goes to libm's scalar exp/sin/cos and to
// moving complex numbers between registers. Here every value is four frequencies wide (a GCC/Clang
// vector extension of four doubles, one AVX2 register), and the elementary functions come from
// SLEEF's vectorised libm (its 1-ulp AVX2 variants).
//
// Everything here is compiled for AVX2 and FMA (the pragma below) whatever the build's baseline,
// so it may run only when `available()`; sweep.cpp takes the per-frequency path on other
// CPUs. Only sweep.cpp includes this header, and only functions compiled for AVX2 call these.
//
// Nothing here throws: each division (reciprocal, inverse) and square root ORs the lanes where it
// is (nearly) singular or outside its formula's safe range into a `Mask`; the caller recomputes
// those frequencies with the scalar code, which handles the edge or throws its typed error.
// Products and exp/sin/cos are not checked one by one: a NaN or overflow they make reaches one
// of those checks (NaN fails every range test).
#pragma once

// GCC only: the AVX2 region below is a `#pragma GCC target`, which Clang ignores (Clang builds
// take the per-frequency path).
#if defined(__x86_64__) && defined(TOOLPOINT_HAVE_SLEEF) && defined(__GNUC__) && !defined(__clang__)
#define TOOLPOINT_LANES 1
#else
#define TOOLPOINT_LANES 0
#endif

namespace toolpoint::lanes {
inline constexpr int kWidth = 4;  // frequencies per vector
// Whether the lanes can run here: built for x86-64 with SLEEF, on a CPU with AVX2 and FMA (as
// SLEEF's AVX2 variants need). Checked at run time, so one binary serves every x86-64 CPU.
inline bool available() {
#if TOOLPOINT_LANES
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}
}  // namespace toolpoint::lanes

#if TOOLPOINT_LANES

#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdlib>
#include <immintrin.h>
#include <limits>
// Every header is included above, outside the AVX2 region: an inline function first defined
// inside it (immintrin.h pulls in <cstdlib>) would be compiled for AVX2 and could be the copy the
// linker keeps for the whole program.

#pragma GCC push_options
#pragma GCC target("avx2,fma")
// Vectors wider than 16 bytes are passed differently with and without AVX; these functions are
// all internal and called only from AVX2 code, so no call crosses that boundary.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

// SLEEF's 1-ulp AVX2 variants, as sleef.h declares them; sleef.h declares its 256-bit functions
// only in files compiled with -mavx throughout, which the rest of this file must not be.
extern "C" {
struct toolpoint_sleef_m256d_2 {
  __m256d x, y;
};
__m256d Sleef_expm1d4_u10avx2(__m256d);
toolpoint_sleef_m256d_2 Sleef_sincosd4_u10avx2(__m256d);
}

namespace toolpoint::lanes {

typedef double V __attribute__((vector_size(8 * kWidth)));
typedef long long Mask __attribute__((vector_size(8 * kWidth)));  // comparisons: all bits set = true

[[gnu::always_inline]] inline V splat(double x) { return V{} + x; }
// Lanes where `x` is within (lo, hi); false for NaN.
[[gnu::always_inline]] inline Mask within(V x, double lo, double hi) { return (x > lo) & (x < hi); }

// ---- Elementary functions, per lane (SLEEF, 1 ulp) ---------------------------------------------------

[[gnu::always_inline]] inline V sqrt(V x) { return (V)_mm256_sqrt_pd((__m256d)x); }
// e^x − 1 (accurate for small |x|: no cancellation).
[[gnu::always_inline]] inline V expm1(V x) { return (V)Sleef_expm1d4_u10avx2((__m256d)x); }
[[gnu::always_inline]] inline void sincos(V x, V& s, V& c) {
  const toolpoint_sleef_m256d_2 sc = Sleef_sincosd4_u10avx2((__m256d)x);
  s = (V)sc.x;
  c = (V)sc.y;
}

// |x| and copysign(a, b) by the sign bit, as std::abs and std::copysign (−0 included).
inline constexpr long long kSignBit = std::numeric_limits<long long>::min();
[[gnu::always_inline]] inline V abs(V x) { return (V)((Mask)x & ~(Mask{} + kSignBit)); }
[[gnu::always_inline]] inline V copysign(V a, V b) { return (V)((Mask)abs(a) | ((Mask)b & (Mask{} + kSignBit))); }

// ---- Complex numbers ---------------------------------------------------------------------------

struct C {
  V re, im;
};
[[gnu::always_inline]] inline C cplx(double re, double im) { return {splat(re), splat(im)}; }
[[gnu::always_inline]] inline C cplx(std::complex<double> z) { return cplx(z.real(), z.imag()); }
[[gnu::always_inline]] inline C operator+(C a, C b) { return {a.re + b.re, a.im + b.im}; }
[[gnu::always_inline]] inline C operator-(C a, C b) { return {a.re - b.re, a.im - b.im}; }
[[gnu::always_inline]] inline C operator-(C a) { return {-a.re, -a.im}; }
[[gnu::always_inline]] inline C operator*(C a, C b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
[[gnu::always_inline]] inline C operator*(V k, C a) { return {k * a.re, k * a.im}; }
[[gnu::always_inline]] inline C operator*(double k, C a) { return {k * a.re, k * a.im}; }
[[gnu::always_inline]] inline V norm(C a) { return a.re * a.re + a.im * a.im; }
[[gnu::always_inline]] inline C select(Mask m, C a, C b) { return {m ? a.re : b.re, m ? a.im : b.im}; }

// 1/z as conj(z)/|z|², the scalar detail::reciprocal; lanes where |z|² is outside (1e-290, 1e290)
// (zero, tiny, huge, NaN) are marked in `bad`.
[[gnu::always_inline]] inline C reciprocal(C z, Mask& bad) {
  const V n = norm(z);
  const Mask ok = within(n, 1e-290, 1e290);
  bad |= ~ok;
  const V r = 1.0 / (ok ? n : splat(1.0));
  return {z.re * r, -z.im * r};
}

// Principal square root (Re ≥ 0), by t = sqrt((|z| + |x|)/2), as beam.cpp's scalar form; lanes
// outside its safe range marked in `bad`.
[[gnu::always_inline]] inline C sqrt_principal(C z, Mask& bad) {
  const V n = norm(z);
  const Mask ok = within(n, 1e-290, 1e290);
  bad |= ~ok;
  const V t = sqrt(0.5 * (sqrt(ok ? n : splat(1.0)) + abs(z.re)));
  const V half_y_over_t = z.im / (2.0 * t);
  const Mask pos = z.re >= 0.0;
  return {pos ? t : abs(half_y_over_t), pos ? half_y_over_t : copysign(t, z.im)};
}

// e^{−z} − 1 (beam.cpp's exp_neg_minus_one, with SLEEF's expm1 and sincos in every lane):
// Re = expm1(−x) cos y + (cos y − 1), cos y − 1 = −sin²y/(1 + cos y) where cos y > 0;
// Im = −e^{−x} sin y.
[[gnu::always_inline]] inline C exp_neg_minus_one(C z) {
  const V em1 = expm1(-z.re);
  V sy, cy;
  sincos(z.im, sy, cy);
  const V cm1 = cy > 0.0 ? -sy * sy / (1.0 + cy) : cy - 1.0;
  return {em1 * cy + cm1, -(1.0 + em1) * sy};
}

// |d| > 1e-14 (|x| + |y|), the singularity test of a 2×2 determinant d = x − y
// (detail::well_above_roundoff); lanes that fail it or leave its safe range are marked in `bad`.
[[gnu::always_inline]] inline void check_well_above_roundoff(C d, C x, C y, Mask& bad) {
  const V nd = norm(d), nx = norm(x), ny = norm(y);
  const Mask safe = within(nd, 1e-290, 1e290) & (within(nx, 1e-145, 1e145) | (nx == 0.0)) &
                    (within(ny, 1e-145, 1e145) | (ny == 0.0));
  bad |= ~(safe & (nd > 1e-28 * (nx + ny + 2.0 * sqrt(safe ? nx * ny : splat(0.0)))));
}

// ---- 2×2 complex blocks [[a, b], [c, d]] -----------------------------------------------------------

struct B {
  C a, b, c, d;
};
[[gnu::always_inline]] inline B operator+(const B& x, const B& y) { return {x.a + y.a, x.b + y.b, x.c + y.c, x.d + y.d}; }
[[gnu::always_inline]] inline B operator-(const B& x, const B& y) { return {x.a - y.a, x.b - y.b, x.c - y.c, x.d - y.d}; }
[[gnu::always_inline]] inline B operator*(const B& x, const B& y) {
  return {x.a * y.a + x.b * y.c, x.a * y.b + x.b * y.d, x.c * y.a + x.d * y.c, x.c * y.b + x.d * y.d};
}
[[gnu::always_inline]] inline B identity_plus(B m) {
  m.a.re += 1.0;
  m.d.re += 1.0;
  return m;
}
// The inverse, with inverse_checked's singularity test (|det| ≤ 1e-14 (|ad| + |bc|)) marking `bad`.
[[gnu::always_inline]] inline B inverse(const B& m, Mask& bad) {
  const C ad = m.a * m.d, bc = m.b * m.c, det = ad - bc;
  check_well_above_roundoff(det, ad, bc, bad);
  const C r = reciprocal(det, bad);
  return {m.d * r, -(m.b * r), -(m.c * r), m.a * r};
}

// A two-end component: blocks 11, 12, 21, 22 (receptance.hpp's TwoPort, in lanes).
struct Port {
  B b11, b12, b21, b22;
};

// Seed Eq. (1) for the point receptance only (coupling.hpp's couple_rigid_point and
// couple_elastic_point): G11 = A11 − A12 X A21 with X = (A22 + B11)⁻¹ (rigid) or
// X = K (I + (A22 + B11) K)⁻¹ (elastic; K may be singular).
[[gnu::always_inline]] inline B couple_rigid_point(const Port& a, const B& b11, Mask& bad) {
  return a.b11 - (a.b12 * inverse(a.b22 + b11, bad)) * a.b21;
}
[[gnu::always_inline]] inline B couple_elastic_point(const Port& a, const B& b11, const B& K, Mask& bad) {
  return a.b11 - (a.b12 * (K * inverse(identity_plus((a.b22 + b11) * K), bad))) * a.b21;
}
// Rigid coupling of two two-ends (coupling.hpp's couple_rigid): X = (A22 + B11)⁻¹,
// G11 = A11 − A12 X A21, G12 = A12 X B12, G21 = B21 X A21, G22 = B22 − B21 X B12.
[[gnu::always_inline]] inline Port couple_rigid(const Port& a, const Port& b, Mask& bad) {
  const B X = inverse(a.b22 + b.b11, bad);
  const B xa21 = X * a.b21, xb12 = X * b.b12;
  return {a.b11 - a.b12 * xa21, a.b12 * xb12, b.b21 * xa21, b.b22 - b.b21 * xb12};
}
// Structural modification at a point (coupling.hpp's ground_point): H (I + D H)⁻¹.
[[gnu::always_inline]] inline B ground_point(const B& h, const B& D, Mask& bad) { return h * inverse(identity_plus(D * h), bad); }

}  // namespace toolpoint::lanes

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // TOOLPOINT_LANES
