// toolpoint: free–free Timoshenko beam segments, exact and modal end receptances.
#include "toolpoint/model/beam.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <fmt/format.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/model/coupling.hpp"
#include "complex_pairs.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

using detail::both;
using detail::CPair;
using detail::lane;
using detail::Lanes;
using detail::pair;
using detail::reciprocal;

// ---- Material, section --------------------------------------------------------------------------

double Material::G() const { return shear_modulus > 0.0 ? shear_modulus : youngs_modulus / (2.0 * (1.0 + poisson)); }

void Material::check() const {
  const std::string who = name.empty() ? std::string("material") : fmt::format("material '{}'", name);
  auto finite = [&](double v, const char* key) {
    if (!std::isfinite(v)) throw InvalidArgument(fmt::format("{}: {} = {} is not finite", who, key, v));
  };
  finite(youngs_modulus, "youngs_modulus");
  finite(poisson, "poisson");
  finite(shear_modulus, "shear_modulus");
  finite(density, "density");
  finite(loss_factor, "loss_factor");
  if (!(youngs_modulus > 0.0))
    throw InvalidArgument(fmt::format("{}: youngs_modulus = {} Pa must be > 0", who, youngs_modulus), "steel is about 2.1e11 Pa");
  if (!(density > 0.0))
    throw InvalidArgument(fmt::format("{}: density = {} kg/m³ must be > 0", who, density), "steel is about 7800 kg/m³");
  if (!(poisson > -1.0 && poisson < 0.5))
    throw InvalidArgument(fmt::format("{}: poisson = {} must lie in (−1, 0.5)", who, poisson), "steel is about 0.3");
  if (shear_modulus < 0.0)
    throw InvalidArgument(fmt::format("{}: shear_modulus = {} Pa must be > 0 (or 0 for E/(2(1+ν)))", who, shear_modulus));
  if (loss_factor < 0.0) throw InvalidArgument(fmt::format("{}: loss_factor = {} must be ≥ 0", who, loss_factor));
}

double shear_coefficient(ShearModel model, double nu, double outer_diameter, double inner_diameter) {
  const double a = outer_diameter / 2.0, b = inner_diameter / 2.0;
  if (model == ShearModel::Cowper) {
    const double m = b / a, m2 = m * m, q = (1.0 + m2) * (1.0 + m2);
    return 6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * m2);
  }
  const double a2 = a * a, b2 = b * b, a4 = a2 * a2, b4 = b2 * b2, ab = a2 * b2;
  const double num = 6.0 * (a2 + b2) * (a2 + b2) * (1.0 + nu) * (1.0 + nu);
  const double den = 7.0 * a4 + 34.0 * ab + 7.0 * b4 + nu * (12.0 * a4 + 48.0 * ab + 12.0 * b4) +
                     nu * nu * (4.0 * a4 + 16.0 * ab + 4.0 * b4);
  return num / den;
}

double Annulus::area() const { return kPi / 4.0 * (outer_diameter * outer_diameter - inner_diameter * inner_diameter); }

double Annulus::second_moment() const {
  const double d4 = outer_diameter * outer_diameter * outer_diameter * outer_diameter;
  const double i4 = inner_diameter * inner_diameter * inner_diameter * inner_diameter;
  return kPi / 64.0 * (d4 - i4);
}

void Annulus::check() const {
  if (!std::isfinite(outer_diameter) || !(outer_diameter > 0.0))
    throw InvalidArgument(fmt::format("outer diameter {} m must be > 0", outer_diameter));
  if (!std::isfinite(inner_diameter) || inner_diameter < 0.0)
    throw InvalidArgument(fmt::format("inner diameter {} m must be ≥ 0", inner_diameter));
  if (!(inner_diameter < outer_diameter))
    throw InvalidArgument(
        fmt::format("inner diameter {} m must be below the outer diameter {} m", inner_diameter, outer_diameter));
  if (shear_coefficient && !(*shear_coefficient > 0.0 && *shear_coefficient <= 1.5))
    throw InvalidArgument(fmt::format("shear coefficient {} must lie in (0, 1.5]", *shear_coefficient),
                          "circular sections have κ ≈ 0.5–0.9");
  material.check();
}

double SectionProperties::cutoff_frequency_hz() const { return std::sqrt(kGA.real() / rhoI) / (2.0 * kPi); }

SectionProperties Segment::properties() const {
  SectionProperties p{{0.0, 0.0}, {0.0, 0.0}, 0.0, 0.0};
  // A composite section shears as one body: unless a layer overrides κ, the whole section takes
  // the coefficient of its outer circle with its innermost bore (ν area-weighted), so concentric
  // layers of one material are exactly the solid section (per-layer κ of thin sleeves would not
  // be). With an override, each layer keeps its own.
  bool overridden = false;
  double outer = 0.0, inner = std::numeric_limits<double>::infinity(), area = 0.0, nu_area = 0.0;
  for (const Annulus& l : layers) {
    overridden = overridden || l.shear_coefficient.has_value();
    outer = std::max(outer, l.outer_diameter);
    inner = std::min(inner, l.inner_diameter);
    area += l.area();
    nu_area += l.material.poisson * l.area();
  }
  const double whole_kappa = layers.size() > 1 && !overridden && area > 0.0
                                 ? shear_coefficient(shear_model, nu_area / area, outer, inner)
                                 : 0.0;
  for (const Annulus& l : layers) {
    const double A = l.area(), I = l.second_moment();
    const double kappa = l.shear_coefficient ? *l.shear_coefficient
                         : whole_kappa > 0.0
                             ? whole_kappa
                             : shear_coefficient(shear_model, l.material.poisson, l.outer_diameter, l.inner_diameter);
    const Complex damp(1.0, l.material.loss_factor);
    p.EI += l.material.youngs_modulus * I * damp;
    p.kGA += kappa * l.material.G() * A * damp;
    p.rhoA += l.material.density * A;
    p.rhoI += l.material.density * I;
  }
  return p;
}

void Segment::check() const {
  const std::string who = name.empty() ? std::string("segment") : name;
  if (!std::isfinite(length) || !(length > 0.0)) throw InvalidArgument(fmt::format("{}: length {} m must be > 0", who, length));
  if (layers.empty()) throw InvalidArgument(fmt::format("{}: no cross-section layer", who));
  for (const Annulus& l : layers) {
    try {
      l.check();
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(fmt::format("{}: {}", who, e.what()), e.hint());
    }
  }
}

Segment Segment::tube(double length, double outer_diameter, double inner_diameter, const Material& material, std::string name) {
  Segment s;
  s.name = std::move(name);
  s.length = length;
  s.layers.push_back(Annulus{outer_diameter, inner_diameter, material, std::nullopt});
  return s;
}

// ---- Exact receptances --------------------------------------------------------------------------

namespace {

// Principal square root (Re ≥ 0; the sign of a zero imaginary part kept, as std::sqrt), by the
// cancellation-free t = sqrt((|z| + |x|)/2): a few ulps, like the libm one, at a third of its cost.
inline Complex sqrt_principal(Complex z) {
  const double x = z.real(), y = z.imag();
  const double n = x * x + y * y;
  if (!(n > 1e-290 && n < 1e290)) return std::sqrt(z);
  const double t = std::sqrt(0.5 * (std::sqrt(n) + std::abs(x)));
  if (x >= 0.0) return {t, y / (2.0 * t)};
  return {std::abs(y) / (2.0 * t), std::copysign(t, y)};
}

// e^{−z} − 1 for Re z ≥ 0, accurate for small |z| too (no cancellation):
//   Re = e^{−x} cos y − 1 = expm1(−x) cos y + (cos y − 1), cos y − 1 = −sin²y/(1 + cos y) for cos y > 0,
//   Im = −e^{−x} sin y.
// Both real terms are ≤ 0 for x ≥ 0 and cos y > 0, so they do not cancel. One evaluation per wave
// gives both c = (1 + e^{−z})/2 and σ = (1 − e^{−z})/2. Each wave has one small part: y is η-small on the evanescent wave, x on
// the propagating one. For |y| ≤ 1/32, sin y and cos y − 1 come from their Taylor series through y⁷ and y⁸, and for x ≤ 1/32,
// expm1(−x) through x⁸: the first omitted terms are below 3e-18 relative, and half the libm calls are saved. Products with the
// rounded ratios of factorials: their 1e-16 errors scale terms ≤ 1/6 of the leading one, at most 2e-4 of it.
inline Complex exp_neg_minus_one(Complex z) {
  const double x = z.real();
  const double em1 =
      std::abs(x) <= 0.03125
          ? -x * (1.0 -
                  x * 0.5 *
                      (1.0 -
                       x * (1.0 / 3.0) *
                           (1.0 -
                            x * 0.25 * (1.0 - x * 0.2 * (1.0 - x * (1.0 / 6.0) * (1.0 - x * (1.0 / 7.0) * (1.0 - x * 0.125)))))))
          : std::expm1(-x);
  const double y = z.imag();
  double sy, cy, cm1;
  if (std::abs(y) <= 0.03125) {
    const double y2 = y * y;
    sy = y * (1.0 - y2 * (1.0 / 6.0) * (1.0 - y2 * (1.0 / 20.0) * (1.0 - y2 * (1.0 / 42.0))));
    cm1 = -0.5 * y2 * (1.0 - y2 * (1.0 / 12.0) * (1.0 - y2 * (1.0 / 30.0) * (1.0 - y2 * (1.0 / 56.0))));
    cy = 1.0 + cm1;
  } else {
    cy = std::cos(y);
    sy = std::sin(y);
    cm1 = cy > 0.0 ? -sy * sy / (1.0 + cy) : cy - 1.0;
  }
  return {em1 * cy + cm1, -(1.0 + em1) * sy};
}

}  // namespace

namespace {

SectionWaves waves_with_rotary_inertia(const SectionProperties& sp, double frequency_hz, double mI);

}  // namespace

SectionWaves section_waves(const SectionProperties& sp, double frequency_hz) {
  return waves_with_rotary_inertia(sp, frequency_hz, sp.rhoI);
}

namespace {

// section_waves() with the rotary inertia per length `mI` [kg·m] in the field equations (ρI, or
// a whirl's ρI ∓ ρI_pΩ/ω, which may be ≤ 0); `sp` (with its own ρI > 0) is what is checked.
SectionWaves waves_with_rotary_inertia(const SectionProperties& sp, double frequency_hz, double mI) {
  // Cheap enough for the per-frequency path; a bad section would otherwise give finite garbage.
  if (!(sp.EI.real() > 0.0 && sp.kGA.real() > 0.0 && sp.rhoA > 0.0 && sp.rhoI > 0.0) || !std::isfinite(sp.EI.imag()) ||
      !std::isfinite(sp.kGA.imag()) || !std::isfinite(sp.EI.real() + sp.kGA.real() + sp.rhoA + sp.rhoI))
    throw InvalidArgument(
        fmt::format("section properties EI = {}, κGA = {}, ρA = {}, ρI = {} must be finite with positive real parts",
                    format_complex(sp.EI), format_complex(sp.kGA), sp.rhoA, sp.rhoI));
  if (!(frequency_hz > 0.0) || !std::isfinite(frequency_hz))
    throw InvalidArgument(fmt::format("frequency {} Hz must be > 0 (free–free receptances are unbounded at 0 Hz)", frequency_hz));
  const double w2 = omega_of(frequency_hz) * omega_of(frequency_hz);
  const Complex a = sp.kGA, b = sp.EI;
  const double mA = sp.rhoA;

  // Wavenumbers: a b p² + (a ρI + b ρA) Ω² p − ρA Ω² (a − ρI Ω²) = 0, p = s². The root of larger
  // modulus first, the other from the product of the roots (no cancellation).
  const Complex B = (a * mI + b * mA) * w2;
  const Complex C = mA * w2 * (a - mI * w2);
  const Complex ab = a * b;
  Complex sq = sqrt_principal(B * B + 4.0 * ab * C);
  if ((std::conj(B) * sq).real() < 0.0) sq = -sq;
  const Complex q = -0.5 * (B + sq);
  const Complex inv_ab = reciprocal(ab);
  const Complex p[2] = {q * inv_ab, -C * reciprocal(q)};
  SectionWaves w;
  w.frequency_hz = frequency_hz;
  for (int j = 0; j < 2; ++j) {
    w.s[j] = sqrt_principal(p[j]);
    w.inv_s[j] = w.s[j] == Complex(0.0, 0.0) ? Complex(0.0, 0.0) : reciprocal(w.s[j]);
    w.e[j] = a * p[j] + mA * w2;
  }
  const Complex de = w.e[1] - w.e[0];
  const Complex inv_b = a * inv_ab;
  w.a_over_b = a * inv_b;
  w.f_a = (-1.0 / (mA * w2)) * de;  // a/u = −1/(ρA Ω²)
  w.f_d = de * inv_b;
  w.undamped = sp.EI.imag() == 0.0 && sp.kGA.imag() == 0.0;
  return w;
}

}  // namespace

// Symmetric basis φ = e^{−sL/2} cosh(s y), antisymmetric φ = e^{−sL/2} sinh(s y)/s, y from
// mid-span; fields w = a φ', ψ = (a p + ρAΩ²) φ = e φ, M = b e φ', Q = u φ with u = −a ρA Ω².
// At y = +L/2, per wave j: c_j = e^{−sL/2} cosh(sL/2) = (1 + e^{−sL})/2 and
// S_j = e^{−sL/2} sinh(sL/2)/s = σ_j/s_j with σ_j = (1 − e^{−sL})/2 (L/2 at s = 0), so
// p_j S_j = s_j σ_j (1/s_j is per section, so no division by s per piece). (Q, M) = M_x α and
// (w, ψ) = R_x α for the wave amplitudes α; the end compliance is g_x = R_x M_x⁻¹ with, for the
// symmetric part,
//   M_s = [[u c_0, u c_1], [b e_0 p_0 S_0, b e_1 p_1 S_1]],  R_s = [[a p_0 S_0, a p_1 S_1], [e_0 c_0, e_1 c_1]]
// and for the antisymmetric part M_a = [[u S_0, u S_1], [b e_0 c_0, b e_1 c_1]], R_a = [[a c_0, a c_1], [e_0 S_0, e_1 S_1]].
// Written out (det M_s = u b Δ_s, det M_a = u b Δ_a, Δe = e_1 − e_0, pS_j = p_j S_j):
//   g_s = [[a/u · pS_0 pS_1 Δe, a/b · X_s], [e_0 e_1/u · X_s, c_0 c_1 Δe/b]] / Δ_s,
//         Δ_s = c_0 e_1 pS_1 − c_1 e_0 pS_0,  X_s = c_0 pS_1 − c_1 pS_0;
//   g_a = [[a/u · c_0 c_1 Δe, a/b · X_a], [e_0 e_1/u · X_a, S_0 S_1 Δe/b]] / Δ_a,
//         Δ_a = S_0 e_1 c_1 − S_1 e_0 c_0,  X_a = S_0 c_1 − S_1 c_0,
// and e_0 e_1/u = a/b (Vieta: p_0 p_1 = −C/(ab), p_0 + p_1 = −B/(ab)), which is reciprocity
// (L = N, T21 = T12ᵀ), exact here. All terms stay bounded for any sL (the e^{−sL/2} scaling) and
// are entire in s, so the cut-off (p_1 = 0) needs no special case.
TwoPort exact_receptance(const SectionWaves& w, double length) {
  if (!(length > 0.0) || !std::isfinite(length)) throw InvalidArgument(fmt::format("segment length {} m must be > 0", length));
  // Per wave j: c_j, and (pS_j, S_j) = σ_j (s_j, 1/s_j) as a pair.
  Complex c[2];
  CPair pS_S[2];
  for (int j = 0; j < 2; ++j) {
    const Complex m1 = exp_neg_minus_one(w.s[j] * length);  // e^{−sL} − 1
    c[j] = 1.0 + 0.5 * m1;
    pS_S[j] = both(-0.5 * m1) * pair(w.s[j], w.inv_s[j]);
    if (w.inv_s[j] == Complex(0.0, 0.0)) {  // S → L/2 as s → 0
      pS_S[j].re[1] = 0.5 * length;
      pS_S[j].im[1] = 0.0;
    }
  }
  // Lane 0 symmetric, lane 1 antisymmetric: X = (P, U) − (Q, V) and Δ = e_1 (P, U) − e_0 (Q, V)
  // with P = c_0 pS_1, Q = c_1 pS_0, U = c_1 S_0, V = c_0 S_1.
  const CPair c01 = pair(c[0], c[1]), c10 = pair(c[1], c[0]);
  const CPair PU = c01 * CPair{Lanes{pS_S[1].re[0], pS_S[0].re[1]}, Lanes{pS_S[1].im[0], pS_S[0].im[1]}};
  const CPair QV = c10 * CPair{Lanes{pS_S[0].re[0], pS_S[1].re[1]}, Lanes{pS_S[0].im[0], pS_S[1].im[1]}};
  const CPair t1 = both(w.e[1]) * PU, t2 = both(w.e[0]) * QV;
  const CPair d = t1 - t2;
  // inverse_checked's singularity test applied to M_s and M_a, |det| ≤ 1e-14 (|m_00 m_11| +
  // |m_01 m_10|), with u b divided out.
  for (int k = 0; k < 2; ++k)
    if (!detail::well_above_roundoff(lane(d, k), lane(t1, k), lane(t2, k))) {
      // A true resonance (possible only undamped), a frequency so near one (or near 0 Hz, the
      // rigid-body modes: 1e-10 Hz) that rounding hides the damping, or terms that under- or
      // overflow double precision (1e100 Hz).
      const double n1 = std::norm(lane(t1, k)), n2 = std::norm(lane(t2, k));
      const bool representable = std::isfinite(n1) && std::isfinite(n2) && std::max(n1, n2) > 1e-290 && std::max(n1, n2) < 1e290;
      if (!representable)
        throw InvalidArgument(fmt::format("{} Hz: the end receptances of a {} m segment under- or overflow double precision "
                                          "at this frequency",
                                          w.frequency_hz, length),
                              "use a frequency in the range of structural dynamics (mHz to MHz)");
      throw NumericalError(w.undamped
                               ? fmt::format("{} Hz is a natural frequency of an undamped free–free segment (L = {} m): "
                                             "the receptance is unbounded there",
                                             w.frequency_hz, length)
                               : fmt::format("{} Hz lies so close to a natural frequency of a free–free segment (L = {} m), "
                                             "or to 0 Hz where its rigid-body motion is unbounded, that its "
                                             "receptance cannot be resolved in double precision",
                                             w.frequency_hz, length),
                           "give the material a (larger) loss factor or move the frequency grid off the resonance");
    }
  const CPair r = detail::reciprocals(d);  // (1/Δ_s, 1/Δ_a)
  const Complex cc = c[0] * c[1];
  const CPair prod = pS_S[0] * pS_S[1];  // (pS_0 pS_1, S_0 S_1)
  // (w, ψ) at y = +L/2 from (Q, M) at y = +L/2: lane 0 g_s, lane 1 g_a.
  const CPair ga = (both(w.f_a) * r) * pair(lane(prod, 0), cc);
  const CPair gb = (both(w.a_over_b) * r) * (PU - QV);
  const CPair gd = (both(w.f_d) * r) * pair(cc, lane(prod, 1));

  TwoPort t;
  const Complex h = 0.5 * (lane(ga, 0) + lane(ga, 1)), l = 0.5 * (lane(gb, 0) + lane(gb, 1)),
                pp = 0.5 * (lane(gd, 0) + lane(gd, 1));
  const Complex h12 = 0.5 * (lane(ga, 1) - lane(ga, 0)), l12 = 0.5 * (lane(gb, 0) - lane(gb, 1)),
                p12 = 0.5 * (lane(gd, 0) - lane(gd, 1));
  t.b11 << h, l, l, pp;  // Eigen's comma initializer, row by row
  t.b12 << h12, l12, -l12, p12;
  t.b21 << h12, -l12, l12, p12;
  t.b22 << h, -l, -l, pp;
  return t;
}

TwoPort exact_receptance(const SectionProperties& sp, double length, double frequency_hz) {
  return exact_receptance(section_waves(sp, frequency_hz), length);
}

TwoPort exact_receptance(const Segment& segment, double frequency_hz) {
  segment.check();
  return exact_receptance(segment.properties(), segment.length, frequency_hz);
}

// ---- Spinning segments ----------------------------------------------------------------------------

const char* whirl_name(Whirl whirl) { return whirl == Whirl::Forward ? "forward" : "backward"; }

double whirl_rotary_inertia(const SectionProperties& sp, double spin_rad_s, Whirl whirl, double frequency_hz) {
  if (!std::isfinite(spin_rad_s)) throw InvalidArgument(fmt::format("spin {} rad/s is not finite", spin_rad_s));
  if (!(frequency_hz > 0.0) || !std::isfinite(frequency_hz))
    throw InvalidArgument(fmt::format("whirl frequency {} Hz must be > 0", frequency_hz));
  // ρI_p = 2ρI for every annulus (docs/reference.md §10); at Ω = 0 exactly ρI.
  const double gyro = 2.0 * sp.rhoI * spin_rad_s / omega_of(frequency_hz);
  return whirl == Whirl::Forward ? sp.rhoI - gyro : sp.rhoI + gyro;
}

SectionWaves section_waves(const SectionProperties& sp, double frequency_hz, double spin_rad_s, Whirl whirl) {
  return waves_with_rotary_inertia(sp, frequency_hz, whirl_rotary_inertia(sp, spin_rad_s, whirl, frequency_hz));
}

TwoPort whirl_receptance(const SectionProperties& sp, double length, double frequency_hz, double spin_rad_s, Whirl whirl) {
  return exact_receptance(section_waves(sp, frequency_hz, spin_rad_s, whirl), length);
}

TwoPort4 spinning_receptance(const SectionProperties& sp, double length, double frequency_hz, double spin_rad_s) {
  if (spin_rad_s == 0.0) {
    const TwoPort t = exact_receptance(sp, length, frequency_hz);
    return two_plane(t, t);
  }
  return two_plane(whirl_receptance(sp, length, frequency_hz, spin_rad_s, Whirl::Forward),
                   whirl_receptance(sp, length, frequency_hz, spin_rad_s, Whirl::Backward));
}

namespace {

// The free–free determinants Δ_s, Δ_a of exact_receptance(SectionWaves) (its comment) for an
// undamped section, made real and scaled to [−1, 1]: each term carries the phase
// e^{−i Im(s_0 + s_1) L/2} of the e^{−sL/2} scaling (c, pS and S of a propagating wave s = ik are
// e^{−ikL/2} times cos, −k sin and sin/k of kL/2), removed here; dividing by the terms' moduli
// keeps the sign. Zero exactly at the natural frequencies of the symmetric (lane 0) and
// antisymmetric (lane 1) modes; entire in s, so continuous through the cut-off.
std::array<double, 2> free_free_determinants(const SectionWaves& w, double length) {
  Complex c[2], pS[2], S[2];
  for (int j = 0; j < 2; ++j) {
    const Complex m1 = exp_neg_minus_one(w.s[j] * length);
    c[j] = 1.0 + 0.5 * m1;
    const Complex sigma = -0.5 * m1;
    pS[j] = w.s[j] * sigma;
    S[j] = w.inv_s[j] == Complex(0.0, 0.0) ? Complex(0.5 * length, 0.0) : sigma * w.inv_s[j];
  }
  const Complex phase = std::polar(1.0, 0.5 * length * (w.s[0].imag() + w.s[1].imag()));
  const Complex s1 = c[0] * w.e[1] * pS[1], s2 = c[1] * w.e[0] * pS[0];
  const Complex a1 = S[0] * w.e[1] * c[1], a2 = S[1] * w.e[0] * c[0];
  // Both determinants change sign when the two waves swap labels (section_waves orders them by
  // |p|, whose order changes along ω where ρI ≤ 0); times the sign of p_0 − p_1 = (e_0 − e_1)/κGA
  // they do not, so only a mode changes their sign.
  const double label = (w.e[0] - w.e[1]).real() < 0.0 ? -1.0 : 1.0;
  auto scaled = [&](Complex x, Complex y) {
    const double n = std::abs(x) + std::abs(y);
    return n > 0.0 ? label * ((x - y) * phase).real() / n : 0.0;
  };
  return {scaled(s1, s2), scaled(a1, a2)};
}

}  // namespace

WhirlFrequencies whirl_frequencies(const SectionProperties& sp, double length, double spin_rad_s, int count) {
  if (count < 1) throw InvalidArgument(fmt::format("whirl_frequencies: count {} must be ≥ 1", count));
  if (!std::isfinite(spin_rad_s))
    throw InvalidArgument(fmt::format("whirl_frequencies: spin {} rad/s is not finite", spin_rad_s));
  SectionProperties undamped = sp;
  undamped.EI = sp.EI.real();
  undamped.kGA = sp.kGA.real();
  // The grid: the standstill modes' least spacing / 32 (a whirl's modes of one parity lie further
  // apart than any two standstill modes do, as long as the spin moves them less than that).
  const std::vector<double> standstill = free_free_frequencies(undamped, length, count + 2);
  double spacing = standstill.front();
  for (std::size_t k = 1; k < standstill.size(); ++k) spacing = std::min(spacing, standstill[k] - standstill[k - 1]);
  const double step = spacing / 32.0, f1 = standstill.front();
  WhirlFrequencies out;
  out.spin_rad_s = spin_rad_s;
  out.conical_hz = spin_rad_s == 0.0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
  for (Whirl whirl : {Whirl::Forward, Whirl::Backward}) {
    auto det = [&](double f) { return free_free_determinants(section_waves(undamped, f, spin_rad_s, whirl), length); };
    // Roots by parity; the grid starts geometric (1e-7 f1 … step) for a slow conical mode.
    std::array<std::vector<double>, 2> roots;
    double f = 1e-7 * f1;
    std::array<double, 2> d = det(f);
    // A forward whirl with spin has the conical mode besides its elastic ones.
    const std::size_t wanted = static_cast<std::size_t>(count) + (whirl == Whirl::Forward && spin_rad_s != 0.0 ? 1 : 0);
    auto enough = [&] { return roots[0].size() + roots[1].size() >= wanted; };
    while (!enough()) {
      const double g = f < step ? std::min(f * 1.25, step) : f + step;
      const std::array<double, 2> e = det(g);
      for (int k = 0; k < 2; ++k) {
        if (d[k] == 0.0 || (d[k] < 0.0) == (e[k] < 0.0)) continue;
        double lo = f, hi = g, dlo = d[k];
        while (hi - lo > 1e-13 * hi) {
          const double mid = 0.5 * (lo + hi), dm = det(mid)[k];
          if (dm == 0.0) lo = hi = mid;
          else if ((dm < 0.0) == (dlo < 0.0)) lo = mid, dlo = dm;
          else hi = mid;
        }
        roots[k].push_back(0.5 * (lo + hi));
      }
      f = g;
      d = e;
      if (f > 1e3 * standstill.back())
        throw NumericalError(
            fmt::format("whirl_frequencies: {} {} whirl modes not found below {} Hz", count, whirl_name(whirl), f));
    }
    // The conical mode: the lowest forward root of lane 0 (φ symmetric, so w antisymmetric: the
    // tilt), below 2Ω (its rigid-body value ρI_pLΩ/J_d < 2Ω); elastic roots lie above the
    // standstill ones.
    const double omega_spin = std::abs(spin_rad_s);
    if (whirl == Whirl::Forward && spin_rad_s != 0.0 && !roots[0].empty() && omega_of(roots[0].front()) < 2.0 * omega_spin) {
      out.conical_hz = roots[0].front();
      roots[0].erase(roots[0].begin());
    }
    std::vector<double> all = roots[0];
    all.insert(all.end(), roots[1].begin(), roots[1].end());
    std::sort(all.begin(), all.end());
    all.resize(count);
    (whirl == Whirl::Forward ? out.forward_hz : out.backward_hz) = all;
  }
  return out;
}

double conical_whirl_estimate_hz(const SectionProperties& sp, double length, double spin_rad_s) {
  const double jd = sp.rhoA * length * length * length / 12.0 + sp.rhoI * length;  // J_d [kg·m²]
  return 2.0 * sp.rhoI * length * std::abs(spin_rad_s) / jd / (2.0 * kPi);         // ρI_p = 2ρI
}

double conical_whirl_hz(const SectionProperties& sp, double length, double spin_rad_s) {
  if (!std::isfinite(spin_rad_s)) throw InvalidArgument(fmt::format("conical_whirl_hz: spin {} rad/s is not finite", spin_rad_s));
  if (!(length > 0.0) || !std::isfinite(length)) throw InvalidArgument(fmt::format("segment length {} m must be > 0", length));
  if (spin_rad_s == 0.0) return 0.0;
  SectionProperties undamped = sp;
  undamped.EI = sp.EI.real();
  undamped.kGA = sp.kGA.real();
  const double spin = std::abs(spin_rad_s);  // its whirl: forward with |Ω| (beam.hpp)
  const double f0 = conical_whirl_estimate_hz(sp, length, spin);
  auto det = [&](double f) { return free_free_determinants(section_waves(undamped, f, spin, Whirl::Forward), length)[0]; };
  double lo = f0 / 1.25, hi = 1.25 * f0, dlo = det(lo);
  if (dlo == 0.0) return lo;
  if ((dlo < 0.0) == (det(hi) < 0.0)) return whirl_frequencies(sp, length, spin, 1).conical_hz;
  while (hi - lo > 1e-13 * hi) {
    const double mid = 0.5 * (lo + hi), dm = det(mid);
    if (dm == 0.0) return mid;
    if ((dm < 0.0) == (dlo < 0.0)) lo = mid, dlo = dm;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

const Block& end_block(const TwoPort& ports, EndBlock block) {
  switch (block) {
    case EndBlock::T11: return ports.b11;
    case EndBlock::T12: return ports.b12;
    case EndBlock::T21: return ports.b21;
    case EndBlock::T22: return ports.b22;
  }
  return ports.b11;
}

namespace {

// One end block of `at(f)` at every frequency of the grid.
template <class At>
BlockSeries end_block_series(const std::vector<double>& frequency_hz, EndBlock block, At&& at) {
  BlockSeries s;
  s.frequency_hz = frequency_hz;
  s.blocks.reserve(frequency_hz.size());
  for (double f : frequency_hz) s.blocks.push_back(end_block(at(f), block));
  return s;
}

}  // namespace

BlockSeries exact_receptance(const SectionProperties& section, double length, const std::vector<double>& frequency_hz,
                             EndBlock block) {
  return end_block_series(frequency_hz, block, [&](double f) { return exact_receptance(section, length, f); });
}

// ---- Modal summation ----------------------------------------------------------------------------

void ModalOptions::check() const { check_fields(modal_fields(), *this, "ModalOptions"); }

const std::vector<OptionField<ModalOptions>>& modal_fields() {
  using O = ModalOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "modes",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 20000.0,
        .help = "elastic free–free modes summed by the modal method (P converges like 1/N, like 1/N³ with the static "
                "residual)",
        .cli_name = "modal-terms"},
       nullptr,
       [](O& o) -> int& { return o.modes; }},
      {{.name = "static_residual",
        .kind = FieldKind::Flag,
        .help = "modal method: add the truncated modes' static flexibility",
        .cli_name = "static-residual"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.static_residual; }}};
  return fields;
}

namespace {

// Dimensionless free–free frequency equation (Han, Benaroya & Wei 1999), with α = ρA L²/ρI,
// γ = κGA ρI/(EI ρA) (= κG/E for one material) and λ = ρA Ω² L²/κGA:
//   λ < α:  −[μ(λ+μ²)/(ω̂(λ−ω̂²)) − ω̂(λ−ω̂²)/(μ(λ+μ²))] sinh μ sin ω̂ + 2 cosh μ cos ω̂ − 2 = 0
//   λ > α:  sin θ sin ω̂ [−θ(λ−θ²)/(2ω̂(λ−ω̂²)) − ω̂(λ−ω̂²)/(2θ(λ−θ²))] − cos θ cos ω̂ + 1 = 0
// The first is divided by cosh μ, the second multiplied by −2; both written with sinh μ/μ and
// sin θ/θ. Then the function is bounded, has no poles, and is continuous through the cut-off
// λ = α (μ, θ → 0), so a sign change is a root on either branch.
struct FreqEq {
  double alpha, gamma;

  struct Waves {
    double omh;     // ω̂
    double second;  // μ (below the cut-off) or θ (above)
    bool above;
  };

  Waves waves(double lambda) const {
    const double delta = 1.0 - 4.0 * gamma * (1.0 - alpha / lambda) / ((1.0 + gamma) * (1.0 + gamma));
    const double rd = std::sqrt(std::max(delta, 0.0));
    const double h = 0.5 * lambda * (1.0 + gamma);
    Waves w;
    w.omh = std::sqrt(h * (rd + 1.0));
    w.above = lambda > alpha;
    w.second = std::sqrt(std::max(w.above ? h * (1.0 - rd) : h * (rd - 1.0), 0.0));
    return w;
  }

  // The free–free frequency equation factors into a symmetric and an antisymmetric part (modes
  // even or odd about mid-span). The combined form above has a double sign change where one mode
  // of each class lie within a scan step — above the cut-off they can be 0.03 % apart — and the
  // pair vanishes; each factor alone has simple roots spaced ≳ π in ω̂ or θ. With P₁ = μ² (or
  // −θ² above the cut-off), P₂ = −ω̂², C(P) = cosh(√P/2), S(P) = sinh(√P/2)/√P (entire in P):
  //   F_odd  = (P₂+λ) P₂ S₂ C₁ − (P₁+λ) P₁ S₁ C₂,    F_even = (P₂+λ) S₁ C₂ − (P₁+λ) S₂ C₁,
  // (from the determinants of the end conditions in the potential form, see exact_receptance)
  // both divided by cosh(μ/2) below the cut-off, continuous through it.
  void factors(double lambda, double& odd, double& even) const {
    const Waves w = waves(lambda);
    const double P1 = w.above ? -w.second * w.second : w.second * w.second, P2 = -w.omh * w.omh;
    double C1, S1;
    if (!w.above) {
      C1 = 1.0;  // cosh(μ/2) divided out
      S1 = w.second < 1e-6 ? 0.5 : std::tanh(0.5 * w.second) / w.second;
    } else {
      C1 = std::cos(0.5 * w.second);
      S1 = w.second < 1e-6 ? 0.5 : std::sin(0.5 * w.second) / w.second;
    }
    const double C2 = std::cos(0.5 * w.omh), S2 = std::sin(0.5 * w.omh) / w.omh;
    odd = (P2 + lambda) * P2 * S2 * C1 - (P1 + lambda) * P1 * S1 * C2;
    even = (P2 + lambda) * S1 * C2 - (P1 + lambda) * S2 * C1;
  }

  double operator()(double lambda) const {
    const Waves w = waves(lambda);
    const double om = w.omh, om_t = om * (lambda - om * om);
    if (!w.above) {
      const double mu = w.second;
      const double tanh_over = mu < 1e-4 ? 1.0 - mu * mu / 3.0 : std::tanh(mu) / mu;
      const double sech = mu > 700.0 ? 0.0 : 1.0 / std::cosh(mu);
      const double br = mu * mu * (lambda + mu * mu) / om_t - om_t / (lambda + mu * mu);
      return -br * tanh_over * std::sin(om) + 2.0 * std::cos(om) - 2.0 * sech;
    }
    const double th = w.second;
    const double sinc = th < 1e-4 ? 1.0 - th * th / 6.0 : std::sin(th) / th;
    const double th_t = th * (lambda - th * th);
    return std::sin(th) * std::sin(om) * th_t / om_t + om_t / (lambda - th * th) * sinc * std::sin(om) +
           2.0 * std::cos(th) * std::cos(om) - 2.0;
  }
};

struct Dimensionless {
  double a, b, mA, mI, length;
  FreqEq eq;
  double lambda_of(double omega) const { return mA * omega * omega * length * length / a; }
  double omega_of_lambda(double lambda) const { return std::sqrt(lambda * a / (mA * length * length)); }
};

Dimensionless make_dimensionless(const SectionProperties& sp, double length) {
  Dimensionless d{sp.kGA.real(), sp.EI.real(), sp.rhoA, sp.rhoI, length, {0, 0}};
  d.eq.alpha = d.mA * length * length / d.mI;
  d.eq.gamma = d.a * d.mI / (d.b * d.mA);
  return d;
}

void check_section(const SectionProperties& sp, double length) {
  if (!(length > 0.0) || !std::isfinite(length)) throw InvalidArgument(fmt::format("segment length {} m must be > 0", length));
  if (!(sp.EI.real() > 0.0 && sp.kGA.real() > 0.0 && sp.rhoA > 0.0 && sp.rhoI > 0.0))
    throw InvalidArgument("section properties EI, κGA, ρA, ρI must be positive");
}

// Roots λ_r of the frequency equation, ascending: the even and odd factors are scanned with steps
// that keep the change of ω̂ and of μ or θ below 0.05 rad (each factor's roots are ≳ π apart in
// one of them), sign changes refined by bisection. Every root is checked against the combined
// equation (Han, Benaroya & Wei) as printed, rewritten without poles.
std::vector<double> frequency_roots(const Dimensionless& d, int count) {
  const FreqEq& eq = d.eq;
  std::vector<double> roots;
  double lam = std::min(1.0 / (eq.gamma * eq.alpha), 0.1 * eq.alpha);
  double g[2];
  eq.factors(lam, g[0], g[1]);
  const double max_step_rad = 0.05;
  int guard = 0;
  // Roots come in increasing λ; once `count` are known, every root below the scan point is.
  while (static_cast<int>(roots.size()) < count) {
    if (++guard > 50'000'000) throw NumericalError("free–free frequency equation: root scan did not finish");
    const auto w0 = eq.waves(lam);
    const double probe = lam * 1e-6;
    const auto w1 = eq.waves(lam + probe);
    const double rate = std::max(std::abs(w1.omh - w0.omh), std::abs(w1.second - w0.second)) / probe;
    double step = rate > 0.0 ? max_step_rad / rate : lam * 0.01;
    step = std::min(step, 0.05 * lam + 1e-12);
    double next = lam + step;
    // Land exactly on the cut-off so the branch change is one step of its own.
    if (lam < eq.alpha && next > eq.alpha) next = eq.alpha * (1.0 + 1e-13);
    double gn[2];
    eq.factors(next, gn[0], gn[1]);
    for (int k = 0; k < 2; ++k) {
      if ((g[k] < 0.0) == (gn[k] < 0.0) && g[k] != 0.0) continue;
      double lo = lam, hi = next, glo = g[k];
      for (int it = 0; it < 200 && hi - lo > 1e-15 * hi && glo != 0.0; ++it) {
        const double mid = 0.5 * (lo + hi);
        double gm[2];
        eq.factors(mid, gm[0], gm[1]);
        if ((gm[k] < 0.0) == (glo < 0.0)) {
          lo = mid;
          glo = gm[k];
        } else {
          hi = mid;
        }
      }
      const double root = glo == 0.0 ? lo : 0.5 * (lo + hi);
      // Cross-check with the combined equation: at a root its value is round-off small compared
      // with its size a relative 1e-4 away on either side.
      const double scale = std::abs(eq(root * (1.0 - 1e-4))) + std::abs(eq(root * (1.0 + 1e-4)));
      if (!(std::abs(eq(root)) <= 1e-3 * scale))
        throw NumericalError(
            fmt::format("free–free frequency equation: root λ = {} of the {} factor does not satisfy the "
                        "combined equation ({} against {})",
                        root, k ? "even" : "odd", eq(root), scale));
      roots.push_back(root);
    }
    lam = next;
    g[0] = gn[0];
    g[1] = gn[1];
  }
  std::sort(roots.begin(), roots.end());
  roots.resize(static_cast<std::size_t>(count));
  return roots;
}

// Gauss–Legendre, 6 points on [−1, 1].
constexpr std::array<double, 6> kGlX = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                        0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
constexpr std::array<double, 6> kGlW = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                        0.4679139345726910, 0.3607615730481386, 0.1713244923791704};

// Mode shape in the potential form: φ'' = p̂ φ for each wave, U = φ', Φ = (p̂ + λ) φ
// (U = w/L, Φ = ψ, ζ = x/L). Free ends: shear U' − Φ = −λ φ = 0 and moment Φ' = (p̂+λ) φ' = 0.
// Bases: μ-wave e^{−μζ}, e^{−μ(1−ζ)} (μ > 1) or cosh μζ, sinh(μζ)/μ; θ-wave cos θζ, sin(θζ)/θ;
// ω̂-wave cos ω̂ζ, sin(ω̂ζ)/ω̂. All bounded and non-degenerate, so the null vector is clean.
struct ModeShape {
  double lambda, phat[2];  // p̂ of the second wave (μ² or −θ²) and of the ω̂ wave (−ω̂²)
  double k2, k1;           // μ or θ, ω̂
  bool above, expo;
  Eigen::Vector4d coef;

  // φ and φ' of basis function i at ζ.
  void basis(int i, double z, double& phi, double& dphi) const {
    if (i < 2) {
      const double m = k2;
      if (!above && expo) {
        if (i == 0) {
          phi = std::exp(-m * z);
          dphi = -m * phi;
        } else {
          phi = std::exp(-m * (1.0 - z));
          dphi = m * phi;
        }
      } else if (!above) {
        if (i == 0) {
          phi = std::cosh(m * z);
          dphi = m * std::sinh(m * z);
        } else {
          phi = m > 0.0 ? std::sinh(m * z) / m : z;
          dphi = std::cosh(m * z);
        }
      } else {
        if (i == 0) {
          phi = std::cos(m * z);
          dphi = -m * std::sin(m * z);
        } else {
          phi = m > 0.0 ? std::sin(m * z) / m : z;
          dphi = std::cos(m * z);
        }
      }
    } else {
      const double o = k1;
      if (i == 2) {
        phi = std::cos(o * z);
        dphi = -o * std::sin(o * z);
      } else {
        phi = std::sin(o * z) / o;
        dphi = std::cos(o * z);
      }
    }
  }
  double ph(int i) const { return i < 2 ? phat[0] : phat[1]; }

  void uphi(double z, double& U, double& Phi) const {
    U = 0.0;
    Phi = 0.0;
    for (int i = 0; i < 4; ++i) {
      double f, df;
      basis(i, z, f, df);
      U += coef[i] * df;
      Phi += coef[i] * (ph(i) + lambda) * f;
    }
  }
};

ModeShape mode_shape(const FreqEq& eq, double lambda) {
  const auto w = eq.waves(lambda);
  ModeShape m;
  m.lambda = lambda;
  m.above = w.above;
  m.k2 = w.second;
  m.k1 = w.omh;
  m.expo = !w.above && w.second > 1.0;
  m.phat[0] = w.above ? -w.second * w.second : w.second * w.second;
  m.phat[1] = -w.omh * w.omh;
  Eigen::Matrix4d A;
  for (int i = 0; i < 4; ++i) {
    for (int end = 0; end < 2; ++end) {
      double f, df;
      m.basis(i, static_cast<double>(end), f, df);
      A(2 * end, i) = f;                            // shear: −λ φ = 0
      A(2 * end + 1, i) = (m.ph(i) + lambda) * df;  // moment: (p̂ + λ) φ' = 0
    }
  }
  for (int r = 0; r < 4; ++r) {
    const double s = A.row(r).cwiseAbs().maxCoeff();
    if (s > 0.0) A.row(r) /= s;
  }
  Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  m.coef = svd.matrixV().col(3);
  return m;
}

}  // namespace

std::vector<double> free_free_frequencies(const SectionProperties& sp, double length, int count) {
  check_section(sp, length);
  if (count < 1) return {};
  const Dimensionless d = make_dimensionless(sp, length);
  std::vector<double> f;
  for (double lam : frequency_roots(d, count)) f.push_back(d.omega_of_lambda(lam) / (2.0 * kPi));
  return f;
}

ModalBeam::ModalBeam(const SectionProperties& sp, double length, const ModalOptions& options) : props_(sp), length_(length) {
  check_section(sp, length);
  options.check();
  const double eta_b = sp.EI.imag() / sp.EI.real(), eta_s = sp.kGA.imag() / sp.kGA.real();
  if (std::abs(eta_b - eta_s) > 1e-12 * std::max(1.0, std::abs(eta_b)))
    throw InvalidArgument(fmt::format("modal method needs one loss factor for the section; bending has η = {}, shear η = {}",
                                      eta_b, eta_s),
                          "use the exact method for layers with different loss factors");
  eta_ = eta_b;
  const Dimensionless d = make_dimensionless(sp, length);
  const auto roots = frequency_roots(d, options.modes);
  modes_.reserve(roots.size());
  for (std::size_t r = 0; r < roots.size(); ++r) {
    const ModeShape shape = mode_shape(d.eq, roots[r]);
    // ∫₀ᴸ (ρA W² + ρI Ψ²) dx with W = L U, Ψ = Φ: composite Gauss–Legendre, a panel per half-wave.
    const int panels = static_cast<int>(r) + 8;
    double integral = 0.0;
    for (int k = 0; k < panels; ++k) {
      const double z0 = static_cast<double>(k) / panels, hw = 0.5 / panels;
      for (std::size_t g = 0; g < kGlX.size(); ++g) {
        double U, Phi;
        shape.uphi(z0 + hw * (1.0 + kGlX[g]), U, Phi);
        integral += kGlW[g] * hw * (d.mA * length * length * U * U + d.mI * Phi * Phi);
      }
    }
    const double scale = 1.0 / std::sqrt(integral * length);
    double U1, P1, U0, P0;
    shape.uphi(1.0, U1, P1);
    shape.uphi(0.0, U0, P0);
    FreeMode m;
    m.frequency_hz = d.omega_of_lambda(roots[r]) / (2.0 * kPi);
    m.w1 = length * U1 * scale;
    m.psi1 = P1 * scale;
    m.w2 = length * U0 * scale;
    m.psi2 = P0 * scale;
    m.above_cutoff = shape.above;
    modes_.push_back(m);
  }
  // Rigid-body modes: translation, and rotation about mid-span (the centre of mass).
  w_trans_ = 1.0 / std::sqrt(sp.rhoA * length);
  const double J = sp.rhoA * length * length * length / 12.0 + sp.rhoI * length;
  psi_rot_ = 1.0 / std::sqrt(J);
  w_rot1_ = 0.5 * length * psi_rot_;
  w_rot2_ = -0.5 * length * psi_rot_;

  if (options.static_residual) {
    const double f0 = 1e-3 * modes_.front().frequency_hz;
    const TwoPort exact = exact_receptance(sp, length, f0);
    const TwoPort modal = receptance(f0);
    residual_ = {exact.b11 - modal.b11, exact.b12 - modal.b12, exact.b21 - modal.b21, exact.b22 - modal.b22};
    has_residual_ = true;
  }
}

TwoPort ModalBeam::receptance(double frequency_hz) const {
  if (!(frequency_hz > 0.0) || !std::isfinite(frequency_hz))
    throw InvalidArgument(fmt::format("frequency {} Hz must be > 0 (free–free receptances are unbounded at 0 Hz)", frequency_hz));
  const double W2 = omega_of(frequency_hz) * omega_of(frequency_hz);
  // Accumulate Σ v_j v_kᵀ / d_r with v = (W, Ψ) at ends 1 and 2.
  Eigen::Matrix4cd G = Eigen::Matrix4cd::Zero();
  auto add = [&G](const Eigen::Vector4d& v, Complex factor) { G += factor * (v * v.transpose()).cast<Complex>(); };
  add(Eigen::Vector4d(w_trans_, 0.0, w_trans_, 0.0), Complex(-1.0 / W2, 0.0));
  add(Eigen::Vector4d(w_rot1_, psi_rot_, w_rot2_, psi_rot_), Complex(-1.0 / W2, 0.0));
  Eigen::Matrix4d acc_re = Eigen::Matrix4d::Zero(), acc_im = Eigen::Matrix4d::Zero();
  for (const FreeMode& m : modes_) {
    const double wr2 = omega_of(m.frequency_hz) * omega_of(m.frequency_hz);
    const Complex inv_d = 1.0 / Complex(wr2 - W2, wr2 * eta_);
    const Eigen::Vector4d v(m.w1, m.psi1, m.w2, m.psi2);
    const Eigen::Matrix4d vv = v * v.transpose();
    acc_re += inv_d.real() * vv;
    acc_im += inv_d.imag() * vv;
  }
  G.real() += acc_re;
  G.imag() += acc_im;
  TwoPort t{G.block<2, 2>(0, 0), G.block<2, 2>(0, 2), G.block<2, 2>(2, 0), G.block<2, 2>(2, 2)};
  if (has_residual_) {
    t.b11 += residual_.b11;
    t.b12 += residual_.b12;
    t.b21 += residual_.b21;
    t.b22 += residual_.b22;
  }
  return t;
}

BlockSeries ModalBeam::receptance(const std::vector<double>& frequency_hz, EndBlock block) const {
  return end_block_series(frequency_hz, block, [&](double f) { return receptance(f); });
}

}  // namespace toolpoint
