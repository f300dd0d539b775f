// toolpoint: the assembly's point receptances over a frequency grid, several frequencies at a time.
//
// AssemblyModel::tool_point(f) and holder_tip(f) for a whole grid, four frequencies at a time,
// one per lane of lanes.hpp's vectors, by the same algebra as the per-frequency functions:
//   S11   Chain::point: the spindle walked from its rear end, g ← T11 − T12 (T22 + g)⁻¹ T21 piece
//         by piece (rigid coupling), its bearings by modification g (I + D g)⁻¹;
//   H, T  Chain::two_port: the holder's and the tool's pieces coupled rigidly into two-ports;
//   SH11 = H11 − H12 (H22 + K_sh⁻¹ + S11)⁻¹ H21 (Eq. 1), SHT11 = T11 − T12 (T22 + K_ht⁻¹ + SH11)⁻¹
//         T21 (Eq. 5), as couple_point forms them.
// The segment receptances are beam.cpp's closed form (exact_receptance from section_waves),
// written once more in lanes. Same association, same formulas: the two paths differ only in
// rounding (SLEEF's exp/sin/cos against libm's, a reciprocal for a Smith division), and a lane
// that meets a near-singular inverse goes to the per-frequency function, which meets the same one.
// The two-plane tool point (tool_point_two_plane) goes through the same lanes: once per whirl with
// isotropic bearings, and in the whirl basis with anisotropic ones (batch_two_plane).
// (Walking the holder and tool as point receptances too is cheaper, but it cancels the rigid-body
// part of each light piece separately and loses 20× more at 10 Hz against an 80-digit reference.)
// Units: SI, frequencies in Hz.
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "lanes.hpp"
#include "whirl_pole.hpp"
#include "toolpoint/model/assembly.hpp"
#include "toolpoint/conventions.hpp"

namespace toolpoint {

namespace {

using lanes::kWidth;

// What the sweep needs of a chain, read once: per piece its length and section (consecutive
// pieces of one cut segment share a section, so its wavenumbers are computed once), per node
// its ground springs.
struct ChainPlan {
  struct Piece {
    double length;
    const SectionProperties* section;
    bool new_section;  // differs from the previous piece's (towards end 2)
  };
  std::vector<Piece> pieces;  // from end 1
  std::vector<const std::vector<Bearing>*> grounds;

  explicit ChainPlan(const Chain& c) {
    for (std::size_t i = 0; i < c.size(); ++i) {
      const SectionProperties& p = c.properties()[i];
      pieces.push_back({c.segments()[i].length, &p, i == 0 || !(c.properties()[i - 1] == p)});
    }
    for (std::size_t k = 0; k <= c.size(); ++k) grounds.push_back(&c.grounds(k));
  }
};

// The three chains of a sweep (no tool for SH11).
struct Plans {
  ChainPlan spindle, holder;
  std::optional<ChainPlan> tool;
};

#if TOOLPOINT_LANES
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // as in lanes.hpp

using lanes::B;
using lanes::C;
using lanes::Mask;
using lanes::Port;
using lanes::V;

// A joint's K(ω) (joint.hpp, Eq. 8) in lanes: k + iωc per entry.
B joint_stiffness(const JointParameters& j, V w) {
  return {{lanes::splat(j.k_yf), j.c_yf * w},
          {lanes::splat(j.k_ym), j.c_ym * w},
          {lanes::splat(j.k_tf), j.c_tf * w},
          {lanes::splat(j.k_tm), j.c_tm * w}};
}

// The summed dynamic stiffness of the bearings at one node, diag(k + iωc, k_θ + iωc_θ).
B ground_stiffness(const std::vector<Bearing>& node, V w) {
  double k = 0.0, c = 0.0, kt = 0.0, ct = 0.0;
  for (const Bearing& b : node) {
    k += b.stiffness;
    c += b.damping;
    kt += b.rotational_stiffness;
    ct += b.rotational_damping;
  }
  const C zero = lanes::cplx(0.0, 0.0);
  return {{lanes::splat(k), c * w}, zero, zero, {lanes::splat(kt), ct * w}};
}

// beam.cpp's section_waves in lanes: the two wavenumbers of the section and the constants the
// closed form needs (see SectionWaves).
struct Waves {
  C s[2], inv_s[2], e[2];
  C a_over_b, f_a, f_d;
};

// `gyro`, if given, is ∓2Ω_spin Ω per lane: a whirl's rotary inertia times Ω² is then
// ρI (Ω² + gyro) (beam.hpp's whirl_rotary_inertia, forward −, backward +).
[[gnu::always_inline]] inline Waves section_waves(const SectionProperties& sp, V w2, const V* gyro, Mask& bad) {
  const Complex a = sp.kGA, b = sp.EI, ab = a * b;
  const double mA = sp.rhoA, mI = sp.rhoI;
  C Bq, Cq;
  if (!gyro) {
    const Complex cb = a * mI + b * mA;
    Bq = {cb.real() * w2, cb.imag() * w2};                      // (a ρI + b ρA) Ω²
    Cq = {mA * w2 * (a.real() - mI * w2), mA * w2 * a.imag()};  // ρA Ω² (a − ρI Ω²)
  } else {
    const V mIw2 = mI * (w2 + *gyro);
    Bq = {a.real() * mIw2 + (b.real() * mA) * w2, a.imag() * mIw2 + (b.imag() * mA) * w2};
    Cq = {mA * w2 * (a.real() - mIw2), mA * w2 * a.imag()};
  }
  const C disc = Bq * Bq + lanes::cplx(4.0 * ab) * Cq;
  C sq = lanes::sqrt_principal(disc, bad);
  const Mask flip = (Bq.re * sq.re + Bq.im * sq.im) < 0.0;  // Re(conj(B) sq) < 0
  sq = lanes::select(flip, -sq, sq);
  const C q = -0.5 * (Bq + sq);
  const Complex inv_ab = 1.0 / ab;
  Waves w;
  const C p[2] = {q * lanes::cplx(inv_ab), -(Cq * lanes::reciprocal(q, bad))};
  const C ac = lanes::cplx(a);
  for (int j = 0; j < 2; ++j) {
    w.s[j] = lanes::sqrt_principal(p[j], bad);
    w.inv_s[j] = lanes::reciprocal(w.s[j], bad);
    w.e[j] = ac * p[j] + C{mA * w2, V{}};
  }
  const C de = w.e[1] - w.e[0];
  const Complex inv_b = a * inv_ab, a_over_b = a * inv_b;
  w.a_over_b = lanes::cplx(a_over_b);
  w.f_a = (-1.0 / (mA * w2)) * de;
  w.f_d = de * lanes::cplx(inv_b);
  return w;
}

// beam.cpp's exact_receptance(waves, length) in lanes (the derivation is there): the four end
// blocks from the symmetric (s) and antisymmetric (a) parts.
[[gnu::always_inline]] inline Port segment(const Waves& w, double length, Mask& bad) {
  C c[2], pS[2], S[2];
  for (int j = 0; j < 2; ++j) {
    const C m1 = lanes::exp_neg_minus_one(length * w.s[j]);  // e^{−sL} − 1
    c[j] = {1.0 + 0.5 * m1.re, 0.5 * m1.im};
    const C sigma = -0.5 * m1;
    pS[j] = sigma * w.s[j];
    S[j] = sigma * w.inv_s[j];
  }
  const C P = c[0] * pS[1], Q = c[1] * pS[0], U = c[1] * S[0], Vv = c[0] * S[1];
  const C ts1 = w.e[1] * P, ts2 = w.e[0] * Q, ta1 = w.e[1] * U, ta2 = w.e[0] * Vv;
  const C ds = ts1 - ts2, da = ta1 - ta2;
  lanes::check_well_above_roundoff(ds, ts1, ts2, bad);
  lanes::check_well_above_roundoff(da, ta1, ta2, bad);
  const C rs = lanes::reciprocal(ds, bad), ra = lanes::reciprocal(da, bad);
  const C cc = c[0] * c[1];
  const C ga_s = (w.f_a * rs) * (pS[0] * pS[1]), ga_a = (w.f_a * ra) * cc;
  const C gb_s = (w.a_over_b * rs) * (P - Q), gb_a = (w.a_over_b * ra) * (U - Vv);
  const C gd_s = (w.f_d * rs) * cc, gd_a = (w.f_d * ra) * (S[0] * S[1]);
  const C h = 0.5 * (ga_s + ga_a), l = 0.5 * (gb_s + gb_a), pp = 0.5 * (gd_s + gd_a);
  const C h12 = 0.5 * (ga_a - ga_s), l12 = 0.5 * (gb_s - gb_a), p12 = 0.5 * (gd_s - gd_a);
  return {{h, l, l, pp}, {h12, l12, -l12, p12}, {h12, -l12, l12, p12}, {h, -l, -l, pp}};
}

// The pieces of a chain at the lanes' frequencies, asked for from end 2 to end 1 (i = n−1, …, 0):
// a piece reuses the waves of the piece asked for before it unless the section changes.
class Pieces {
 public:
  Pieces(const ChainPlan& chain, V w2, const V* gyro, Mask& bad) : chain_(chain), w2_(w2), gyro_(gyro), bad_(bad) {}
  Port operator()(std::size_t i) {
    const ChainPlan::Piece& p = chain_.pieces[i];
    if (i + 1 == chain_.pieces.size() || chain_.pieces[i + 1].new_section) waves_ = section_waves(*p.section, w2_, gyro_, bad_);
    return segment(waves_, p.length, bad_);
  }

 private:
  const ChainPlan& chain_;
  V w2_;
  const V* gyro_;
  Mask& bad_;
  Waves waves_;
};

// Chain::point in lanes: the point receptance at end 1 of a chain with a free end 2 and ground
// springs at its nodes (the spindle), walked from end 2.
B chain_point(const ChainPlan& chain, V w, V w2, const V* gyro, Mask& bad) {
  const std::size_t n = chain.pieces.size();
  Pieces piece(chain, w2, gyro, bad);
  const Port last = piece(n - 1);
  B g = last.b11;
  if (!chain.grounds[n]->empty()) {
    // Chain::point's ground_end2: T11 − T12 D (I + T22 D)⁻¹ T21, i.e. a joint D to a body of
    // zero receptance.
    const C zero = lanes::cplx(0.0, 0.0);
    g = lanes::couple_elastic_point(last, B{zero, zero, zero, zero}, ground_stiffness(*chain.grounds[n], w), bad);
  }
  for (std::size_t k = n - 1; k-- > 0;) {
    if (!chain.grounds[k + 1]->empty()) g = lanes::ground_point(g, ground_stiffness(*chain.grounds[k + 1], w), bad);
    g = lanes::couple_rigid_point(piece(k), g, bad);
  }
  if (!chain.grounds[0]->empty()) g = lanes::ground_point(g, ground_stiffness(*chain.grounds[0], w), bad);
  return g;
}

// Chain::two_port in lanes for a chain without ground springs (the holder, the tool): the pieces
// coupled rigidly from end 2. A grounded chain is left to the per-frequency path.
Port chain_two_port(const ChainPlan& chain, V w2, const V* gyro, Mask& bad) {
  for (const auto* node : chain.grounds)
    if (!node->empty()) bad |= Mask{} - 1;
  const std::size_t n = chain.pieces.size();
  Pieces piece(chain, w2, gyro, bad);
  Port g = piece(n - 1);
  for (std::size_t k = n - 1; k-- > 0;) g = lanes::couple_rigid(piece(k), g, bad);
  return g;
}

// couple_point (coupling.hpp) in lanes: A's end 1 with `b11` attached at its end 2 through `joint`.
B couple_point(const Port& a, const B& b11, const Joint& joint, V w, Mask& bad) {
  return joint.rigid ? lanes::couple_rigid_point(a, b11, bad)
                     : lanes::couple_elastic_point(a, b11, joint_stiffness(joint.parameters, w), bad);
}

// SH11 (or SHT11 when plans.tool is set) at the kWidth frequencies f_in [Hz]: entry e (H, L, N,
// P) of lane i in out[e][i] (real parts) and out[e + 4][i] (imaginary parts). Returns the lanes
// to recompute one at a time, bit i for lane i. (Blocks are built by the caller: GCC refused to
// inline one of Eigen's SSE2 packet functions into this AVX2 code, "target specific option
// mismatch".)
// `whirl_spin` [rad/s]: 0 standing, else −Ω_spin for the forward whirl and +Ω_spin for the backward.
unsigned batch(const Plans& plans, const Assembly& a, const double* f_in, double (*out)[kWidth], double whirl_spin) {
  Mask bad{};
  V f;
  for (int i = 0; i < kWidth; ++i) f[i] = f_in[i];
  bad |= ~lanes::within(f, 0.0, std::numeric_limits<double>::infinity());
  const V w = (2.0 * kPi) * f, w2 = w * w;  // omega_of(f), squared
  const V gyro_lanes = (2.0 * whirl_spin) * w;
  const V* gyro = whirl_spin == 0.0 ? nullptr : &gyro_lanes;
  // As AssemblyModel::holder_tip and tool_point: SH11 = H ⊕ S11 (Eq. 1), SHT11 = T ⊕ SH11 (Eq. 5).
  B g = couple_point(chain_two_port(plans.holder, w2, gyro, bad), chain_point(plans.spindle, w, w2, gyro, bad), a.spindle_holder,
                     w, bad);
  if (plans.tool) g = couple_point(chain_two_port(*plans.tool, w2, gyro, bad), g, a.holder_tool, w, bad);
  const C e[4] = {g.a, g.b, g.c, g.d};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < kWidth; ++i) {
      out[k][i] = e[k].re[i];
      out[k + 4][i] = e[k].im[i];
    }
  return static_cast<unsigned>(_mm256_movemask_pd((__m256d)bad));
}

// ---- Two planes with anisotropic bearings, in the whirl basis (docs/reference.md §10) -------------
//
// With u = Q q, Q = [[I, iI], [I, −iI]] on q = (w_x, ψ_x, w_y, ψ_y) (u = forward r = w_x + i w_y,
// backward w_x − i w_y, and likewise for the loads), a two-plane receptance G becomes
// Q G Q⁻¹ and a dynamic stiffness D becomes Q D Q⁻¹. An axisymmetric piece is then
// diag(F, B), its whirls' planar blocks (receptance.hpp's two_plane is Q⁻¹ diag(F, B) Q), and
// a bearing diag(D_x, D_y) becomes [[D_s, D_d], [D_d, D_s]] with D_s = (D_x + D_y)/2,
// D_d = (D_x − D_y)/2: only the bearings couple the whirls. Coupling and modification are
// similarity-invariant, so Chain::point_two_plane's and couple_point's algebra applies as
// written, the pieces' blocks computed per whirl by the planar lanes above (exact, no 4×4 piece)
// and every 4×4 inverse by blocks (Schur complement on the forward block). Q/√2 is unitary: the
// basis change costs no conditioning. The lanes' singularity tests are those of the 2×2 blocks
// (the forward block and its Schur complement); a lane failing one goes to the per-frequency
// path (plane basis, complete pivoting), which handles it or throws.

// A 4×4 block in the whirl basis as 2×2 blocks [[ff, fb], [bf, bb]].
struct W4 {
  B ff, fb, bf, bb;
};
[[gnu::always_inline]] inline W4 operator*(const W4& x, const W4& y) {
  return {x.ff * y.ff + x.fb * y.bf, x.ff * y.fb + x.fb * y.bb, x.bf * y.ff + x.bb * y.bf, x.bf * y.fb + x.bb * y.bb};
}
[[gnu::always_inline]] inline B operator*(double k, const B& x) { return {k * x.a, k * x.b, k * x.c, k * x.d}; }
// M⁻¹ by the Schur complement of the forward block: with P⁻¹ = ff⁻¹ and S = bb − bf P⁻¹ fb,
// M⁻¹ = [[P⁻¹ + P⁻¹ fb S⁻¹ bf P⁻¹, −P⁻¹ fb S⁻¹], [−S⁻¹ bf P⁻¹, S⁻¹]].
[[gnu::always_inline]] inline W4 inverse(const W4& m, Mask& bad) {
  const B pi = lanes::inverse(m.ff, bad);
  const B pi_fb = pi * m.fb, bf_pi = m.bf * pi;
  const B si = lanes::inverse(m.bb - m.bf * pi_fb, bad);
  const B bf_out = -1.0 * (si * bf_pi);
  return {pi - pi_fb * bf_out, -1.0 * (pi_fb * si), bf_out, si};
}
[[gnu::always_inline]] inline W4 identity_plus(W4 m) {
  m.ff = lanes::identity_plus(m.ff);
  m.bb = lanes::identity_plus(m.bb);
  return m;
}
// A pair of whirls' two-ports: the piece diag(F, B) in the whirl basis.
struct Port2 {
  Port f, b;
};
// G11 = A11 − A12 X A21 for a block-diagonal A (its whirls) and a full X.
[[gnu::always_inline]] inline W4 through(const Port2& a, const W4& X) {
  return {a.f.b11 - a.f.b12 * X.ff * a.f.b21, -1.0 * (a.f.b12 * X.fb * a.b.b21), -1.0 * (a.b.b12 * X.bf * a.f.b21),
          a.b.b11 - a.b.b12 * X.bb * a.b.b21};
}
// A22 + g.
[[gnu::always_inline]] inline W4 plus22(const Port2& a, const W4& g) { return {a.f.b22 + g.ff, g.fb, g.bf, a.b.b22 + g.bb}; }
// couple_rigid_point (X = (A22 + g)⁻¹) and couple_elastic_point (X = K (I + (A22 + g) K)⁻¹, K
// any 4×4 in the whirl basis: a joint's diag(K, K), a bearing's [[D_s, D_d], [D_d, D_s]]).
[[gnu::always_inline]] inline W4 couple_rigid_point(const Port2& a, const W4& g, Mask& bad) {
  return through(a, inverse(plus22(a, g), bad));
}
[[gnu::always_inline]] inline W4 couple_elastic_point(const Port2& a, const W4& g, const W4& K, Mask& bad) {
  return through(a, K * inverse(identity_plus(plus22(a, g) * K), bad));
}
// ground_point: g (I + D g)⁻¹.
[[gnu::always_inline]] inline W4 ground_point(const W4& g, const W4& D, Mask& bad) {
  return g * inverse(identity_plus(D * g), bad);
}
W4 whirl_diagonal(const B& f, const B& b) {
  const C zero = lanes::cplx(0.0, 0.0);
  const B z{zero, zero, zero, zero};
  return {f, z, z, b};
}

// The bearings at one node in the whirl basis: [[D_s, D_d], [D_d, D_s]] (above), the x values
// from Bearing::stiffness/damping, the y values from stiffness_y/damping_y (unset: as x).
W4 ground_stiffness_whirls(const std::vector<Bearing>& node, V w) {
  double kx = 0.0, cx = 0.0, ky = 0.0, cy = 0.0, kt = 0.0, ct = 0.0;
  for (const Bearing& b : node) {
    kx += b.stiffness;
    cx += b.damping;
    ky += b.stiffness_y.value_or(b.stiffness);
    cy += b.damping_y.value_or(b.damping);
    kt += b.rotational_stiffness;
    ct += b.rotational_damping;
  }
  const C zero = lanes::cplx(0.0, 0.0);
  const B s{{lanes::splat(0.5 * (kx + ky)), (0.5 * (cx + cy)) * w}, zero, zero, {lanes::splat(kt), ct * w}};
  const B d{{lanes::splat(0.5 * (kx - ky)), (0.5 * (cx - cy)) * w}, zero, zero, zero};
  return {s, d, d, s};
}

// Chain::point_two_plane in lanes, in the whirl basis: the spindle walked from its rear end, each
// piece's whirls from `fwd` and `bwd` (the same object at standstill: one evaluation serves both).
W4 chain_point_whirls(const ChainPlan& chain, V w, Pieces& fwd, Pieces& bwd, bool standstill, Mask& bad) {
  const std::size_t n = chain.pieces.size();
  auto piece = [&](std::size_t i) {
    Port2 p;
    p.f = fwd(i);
    p.b = standstill ? p.f : bwd(i);
    return p;
  };
  const Port2 last = piece(n - 1);
  W4 g = whirl_diagonal(last.f.b11, last.b.b11);
  if (!chain.grounds[n]->empty()) {
    // ground_end2_point: a joint D to a body of zero receptance (as chain_point above).
    const C zero = lanes::cplx(0.0, 0.0);
    const B z{zero, zero, zero, zero};
    g = couple_elastic_point(last, W4{z, z, z, z}, ground_stiffness_whirls(*chain.grounds[n], w), bad);
  }
  for (std::size_t k = n - 1; k-- > 0;) {
    if (!chain.grounds[k + 1]->empty()) g = ground_point(g, ground_stiffness_whirls(*chain.grounds[k + 1], w), bad);
    g = couple_rigid_point(piece(k), g, bad);
  }
  if (!chain.grounds[0]->empty()) g = ground_point(g, ground_stiffness_whirls(*chain.grounds[0], w), bad);
  return g;
}

// couple_point through a joint (both planes alike: diag(K, K) in either basis) in the whirl basis.
W4 couple_point_whirls(const Port2& a, const W4& g, const Joint& joint, V w, Mask& bad) {
  if (joint.rigid) return couple_rigid_point(a, g, bad);
  const B K = joint_stiffness(joint.parameters, w);
  return couple_elastic_point(a, g, whirl_diagonal(K, K), bad);
}

// AssemblyModel::tool_point_two_plane at the kWidth frequencies f_in [Hz], the spindle spinning
// at `spin_rad_s`: entry (r, c) of the 4×4 block of lane i in out[2 (4r + c)][i] (real part) and
// out[2 (4r + c) + 1][i] (imaginary part). Returns the lanes to recompute one at a time.
unsigned batch_two_plane(const Plans& plans, const Assembly& a, const double* f_in, double (*out)[kWidth], double spin_rad_s) {
  Mask bad{};
  V f;
  for (int i = 0; i < kWidth; ++i) f[i] = f_in[i];
  bad |= ~lanes::within(f, 0.0, std::numeric_limits<double>::infinity());
  const V w = (2.0 * kPi) * f, w2 = w * w;
  const bool standstill = spin_rad_s == 0.0;
  // batch()'s gyro: forward −Ω_spin, backward +Ω_spin.
  const V gyro_f = (-2.0 * spin_rad_s) * w, gyro_b = (2.0 * spin_rad_s) * w;
  const V* gf = standstill ? nullptr : &gyro_f;
  const V* gb = standstill ? nullptr : &gyro_b;
  auto whirls = [&](const ChainPlan& chain) {
    Port2 p;
    p.f = chain_two_port(chain, w2, gf, bad);
    p.b = standstill ? p.f : chain_two_port(chain, w2, gb, bad);
    return p;
  };
  Pieces sf(plans.spindle, w2, gf, bad), sb(plans.spindle, w2, gb, bad);
  const W4 s11 = chain_point_whirls(plans.spindle, w, sf, sb, standstill, bad);
  const W4 sh11 = couple_point_whirls(whirls(plans.holder), s11, a.spindle_holder, w, bad);
  const W4 g = couple_point_whirls(whirls(*plans.tool), sh11, a.holder_tool, w, bad);
  // Back to the planes, G = Q⁻¹ G_w Q: xx = (ff + bf + fb + bb)/2, xy = i (ff + bf − fb − bb)/2,
  // yx = −i (ff − bf + fb − bb)/2, yy = (ff − bf − fb + bb)/2.
  const B sum_f = g.ff + g.bf, dif_f = g.ff - g.bf, sum_b = g.fb + g.bb, dif_b = g.fb - g.bb;
  const B xx = 0.5 * (sum_f + sum_b), yy = 0.5 * (dif_f - dif_b);
  const B xy_i = 0.5 * (sum_f - sum_b), yx_mi = 0.5 * (dif_f + dif_b);  // xy / i, yx / (−i)
  auto put = [&](int r, int c, C z) {
    for (int i = 0; i < kWidth; ++i) {
      out[2 * (4 * r + c)][i] = z.re[i];
      out[2 * (4 * r + c) + 1][i] = z.im[i];
    }
  };
  auto put_block = [&](int r0, int c0, const B& b, int rot) {  // b × i^rot (rot: 0, 1, −1)
    const C e[4] = {b.a, b.b, b.c, b.d};
    for (int k = 0; k < 4; ++k) {
      const C z = rot == 0 ? e[k] : rot == 1 ? C{-e[k].im, e[k].re} : C{e[k].im, -e[k].re};
      put(r0 + k / 2, c0 + k % 2, z);
    }
  };
  put_block(0, 0, xx, 0);
  put_block(0, 2, xy_i, 1);
  put_block(2, 0, yx_mi, -1);
  put_block(2, 2, yy, 0);
  return static_cast<unsigned>(_mm256_movemask_pd((__m256d)bad));
}

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // TOOLPOINT_LANES

static_assert(kWidth == 4, "the whirl-pole stencil (whirl_pole.hpp) fills one batch");

// Walks `frequency_hz` kWidth at a time: `run(f)` evaluates a batch (a short last batch repeats its
// last frequency) and returns the lanes to recompute, bit i for lane i; those go to `one(index)`,
// the others to `take(index, lane)`.
template <class Run, class Take, class One>
void for_each_batch(const std::vector<double>& frequency_hz, Run run, Take take, One one) {
  const std::size_t n = frequency_hz.size(), width = kWidth;
  for (std::size_t start = 0; start < n; start += width) {
    const std::size_t m = std::min(width, n - start);
    double f[kWidth];
    for (std::size_t i = 0; i < width; ++i) f[i] = frequency_hz[start + std::min(i, m - 1)];
    const unsigned bad = run(f);
    for (std::size_t i = 0; i < m; ++i) {
      if (bad >> i & 1u) one(start + i);
      else take(start + i, i);
    }
  }
}

// for_each_batch with the whirl poles' windows (whirl_pole.hpp): a frequency inside one gets the
// stencil, its four points in one batch (`lane(i)` reads lane i after `run`), else the lane; a
// stencil the lanes cannot certify goes to `one(index)`. Results into `blocks`, counted.
template <class B, class Run, class Lane, class One>
void for_each_batch_with_poles(const std::vector<double>& frequency_hz, const std::vector<WhirlPole>& poles, Run run, Lane lane,
                               One one, std::vector<B>& blocks, AssemblyModel::SweepDiagnostics& count) {
  std::vector<std::size_t> near;
  for_each_batch(
      frequency_hz, run,
      [&](std::size_t k, std::size_t i) {
        if (whirl_pole_window(frequency_hz[k], poles) > 0.0) return near.push_back(k);
        blocks[k] = lane(i);
        ++count.simd;
      },
      one);
  for (std::size_t k : near) {
    const double f = frequency_hz[k];
    B v;
    const bool ok = detail::whirl_pole_stencil<B>(
        f, whirl_pole_window(f, poles),
        [&](const double* x, B* g) {
          if (run(x) != 0u) return false;
          for (std::size_t i = 0; i < 4; ++i) g[i] = lane(i);
          return true;
        },
        v);
    if (!ok) {
      one(k);
      continue;
    }
    blocks[k] = v;
    ++count.simd;
  }
}

// The series over `frequency_hz`, through the lanes when every chain is exact, with `at` (the
// per-frequency function) for the lanes they cannot certify, for modal chains and for the
// frequencies in one of the windows of `poles` (their stencil's four points in one batch).
BlockSeries sweep(const Plans* plans, const Assembly& a, const std::vector<double>& frequency_hz,
                  const std::function<Block(double)>& at, AssemblyModel::SweepDiagnostics* diagnostics, double whirl_spin = 0.0,
                  const std::vector<WhirlPole>& poles = {}) {
  AssemblyModel::SweepDiagnostics count;
  BlockSeries s;
  s.frequency_hz = frequency_hz;
  s.blocks.resize(frequency_hz.size());
  auto one = [&](std::size_t i) {
    ++count.per_frequency;
    s.blocks[i] = block_at(at, frequency_hz[i]);
  };
#if TOOLPOINT_LANES
  if (plans) {
    double out[8][kWidth];
    auto lane = [&](std::size_t i) {
      return make_block({out[0][i], out[4][i]}, {out[1][i], out[5][i]}, {out[2][i], out[6][i]}, {out[3][i], out[7][i]});
    };
    for_each_batch_with_poles(
        frequency_hz, poles, [&](const double* f) { return batch(*plans, a, f, out, whirl_spin); }, lane, one, s.blocks, count);
    if (diagnostics) *diagnostics = count;
    return s;
  }
#else
  (void)plans, (void)a, (void)whirl_spin;
#endif
  for (std::size_t i = 0; i < frequency_hz.size(); ++i) one(i);
  if (diagnostics) *diagnostics = count;
  return s;
}

}  // namespace

bool simd_sweeps_available() { return lanes::available(); }

namespace {
// The lanes' plans for spindle + holder (+ tool), or none where the lanes cannot run: no AVX2
// here, or a chain summed modally.
std::optional<Plans> plans_for(const Chain& spindle, const Chain& holder, const Chain* tool) {
  if (!lanes::available() || spindle.has_modal_pieces() || holder.has_modal_pieces() || (tool && tool->has_modal_pieces()))
    return std::nullopt;
  return Plans{ChainPlan(spindle), ChainPlan(holder), tool ? std::optional<ChainPlan>(ChainPlan(*tool)) : std::nullopt};
}
// The free pieces' conical whirl poles over the span of a grid.
std::vector<WhirlPole> grid_whirl_poles(const AssemblyModel& m, const std::vector<double>& frequency_hz, double spin_rad_s) {
  if (frequency_hz.empty()) return {};
  const auto [lo, hi] = std::minmax_element(frequency_hz.begin(), frequency_hz.end());
  return m.whirl_poles(spin_rad_s, *lo, *hi);
}
}  // namespace

BlockSeries AssemblyModel::holder_tip(const std::vector<double>& frequency_hz, SweepDiagnostics* diagnostics) const {
  const std::optional<Plans> plans = plans_for(spindle_, holder_, nullptr);
  return sweep(
      plans ? &*plans : nullptr, assembly_, frequency_hz, [this](double f) { return holder_tip(f); }, diagnostics);
}

BlockSeries AssemblyModel::tool_point(const std::vector<double>& frequency_hz, SweepDiagnostics* diagnostics) const {
  const std::optional<Plans> plans = plans_for(spindle_, holder_, &tool_);
  return sweep(
      plans ? &*plans : nullptr, assembly_, frequency_hz, [this](double f) { return tool_point(f); }, diagnostics);
}

BlockSeries4 AssemblyModel::tool_point_two_plane(const std::vector<double>& frequency_hz, double spin_rad_s,
                                                 SweepDiagnostics* diagnostics) const {
  BlockSeries4 out;
  out.frequency_hz = frequency_hz;
  out.blocks.resize(frequency_hz.size());
  if (!isotropic()) {
    // The spindle in 4×4: through the lanes in the whirl basis, the lanes they cannot certify
    // (and every frequency without lanes) one at a time in the planes.
    SweepDiagnostics count;
    auto one = [&](std::size_t i) {
      ++count.per_frequency;
      block_at(
          [&](double x) {
            out.blocks[i] = tool_point_two_plane(x, spin_rad_s);
            return Block();
          },
          frequency_hz[i]);
    };
    const std::optional<Plans> plans = plans_for(spindle_, holder_, &tool_);
#if TOOLPOINT_LANES
    if (plans) {
      double b[32][kWidth];
      const std::vector<WhirlPole> poles = grid_whirl_poles(*this, frequency_hz, spin_rad_s);
      auto lane = [&](std::size_t i) {
        Block4 x;
        for (int e = 0; e < 16; ++e) x(e / 4, e % 4) = Complex(b[2 * e][i], b[2 * e + 1][i]);
        return x;
      };
      for_each_batch_with_poles(
          frequency_hz, poles, [&](const double* f) { return batch_two_plane(*plans, assembly_, f, b, spin_rad_s); }, lane, one,
          out.blocks, count);
      if (diagnostics) *diagnostics = count;
      return out;
    }
#endif
    (void)plans;
    for (std::size_t i = 0; i < frequency_hz.size(); ++i) one(i);
    if (diagnostics) *diagnostics = count;
    return out;
  }
  if (spin_rad_s == 0.0) {
    const BlockSeries s = tool_point(frequency_hz);
    for (std::size_t i = 0; i < s.size(); ++i) out.blocks[i] = two_plane(s.blocks[i]);
    return out;
  }
  // The whirls decouple (isotropic bearings): one sweep each, −Ω and +Ω in the lanes.
  const std::optional<Plans> plans = plans_for(spindle_, holder_, &tool_);
  const Plans* p = plans ? &*plans : nullptr;
  // The conical poles lie in the forward whirl for a positive spin, in the backward for a negative.
  const std::vector<WhirlPole> poles = grid_whirl_poles(*this, frequency_hz, spin_rad_s), none;
  const BlockSeries fwd = sweep(
      p, assembly_, frequency_hz, [&](double f) { return tool_point(f, spin_rad_s, Whirl::Forward); }, nullptr, -spin_rad_s,
      spin_rad_s > 0.0 ? poles : none);
  const BlockSeries bwd = sweep(
      p, assembly_, frequency_hz, [&](double f) { return tool_point(f, spin_rad_s, Whirl::Backward); }, nullptr, spin_rad_s,
      spin_rad_s < 0.0 ? poles : none);
  for (std::size_t i = 0; i < fwd.size(); ++i) out.blocks[i] = two_plane(fwd.blocks[i], bwd.blocks[i]);
  return out;
}

}  // namespace toolpoint
