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
// (Walking the holder and tool as point receptances too is cheaper, but it cancels the rigid-body
// part of each light piece separately and loses 20× more at 10 Hz against an 80-digit reference.)
// Units: SI, frequencies in Hz.
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "lanes.hpp"
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

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // TOOLPOINT_LANES

// The series over `frequency_hz`, through the lanes when every chain is exact, with `at` (the
// per-frequency function) for the lanes they cannot certify or for modal chains.
BlockSeries sweep(const Plans* plans, const Assembly& a, const std::vector<double>& frequency_hz,
                  const std::function<Block(double)>& at, AssemblyModel::SweepDiagnostics* diagnostics, double whirl_spin = 0.0) {
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
    const std::size_t n = frequency_hz.size(), width = kWidth;
    for (std::size_t start = 0; start < n; start += width) {
      const std::size_t m = std::min(width, n - start);
      double f[kWidth];
      for (std::size_t i = 0; i < width; ++i) f[i] = frequency_hz[start + std::min(i, m - 1)];  // a short batch repeats its last
      double out[8][kWidth];
      const unsigned bad = batch(*plans, a, f, out, whirl_spin);
      for (std::size_t i = 0; i < m; ++i) {
        if (bad >> i & 1u) {
          one(start + i);
        } else {
          s.blocks[start + i] = make_block({out[0][i], out[4][i]}, {out[1][i], out[5][i]}, {out[2][i], out[6][i]},
                                           {out[3][i], out[7][i]});
          ++count.simd;
        }
      }
    }
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

BlockSeries4 AssemblyModel::tool_point_two_plane(const std::vector<double>& frequency_hz, double spin_rad_s) const {
  BlockSeries4 out;
  out.frequency_hz = frequency_hz;
  out.blocks.resize(frequency_hz.size());
  if (!isotropic()) {
    for (std::size_t i = 0; i < frequency_hz.size(); ++i) {
      const double f = frequency_hz[i];
      Block4 b;
      block_at(
          [&](double x) {
            b = tool_point_two_plane(x, spin_rad_s);
            return Block();
          },
          f);
      out.blocks[i] = b;
    }
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
  const BlockSeries fwd = sweep(
      p, assembly_, frequency_hz, [&](double f) { return tool_point(f, spin_rad_s, Whirl::Forward); }, nullptr, -spin_rad_s);
  const BlockSeries bwd = sweep(
      p, assembly_, frequency_hz, [&](double f) { return tool_point(f, spin_rad_s, Whirl::Backward); }, nullptr, spin_rad_s);
  for (std::size_t i = 0; i < fwd.size(); ++i) out.blocks[i] = two_plane(fwd.blocks[i], bwd.blocks[i]);
  return out;
}

}  // namespace toolpoint
