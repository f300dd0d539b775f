// toolpoint: joint constants fitted over a band, with bootstrap or linearised intervals
// (joint_fit.hpp).
#include "toolpoint/identify/joint_fit.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/statistics.hpp"

namespace toolpoint {

namespace {

using Jac = Eigen::Matrix<double, 8, Eigen::Dynamic>;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// ---- Parameters ------------------------------------------------------------------------------

// The free parameters q (scaled to O(1)) and the map to the eight: p_j = scale_k q_k for the
// free parameter k that j belongs to (k_θf, c_θf belong to k_ym, c_ym in a reciprocal fit).
struct Parametrization {
  std::vector<int> free;  // index among the 8 of each free parameter
  VectorXd scale;         // SI units per unit of q
  bool reciprocal = true;

  int size() const { return static_cast<int>(free.size()); }
  // Whether value j is not free but its transposed counterpart's (k_θf, c_θf in a reciprocal fit).
  bool tied(int j) const { return reciprocal && JointParameters::row(j) > JointParameters::column(j); }
  // The free parameter (index into q) that value j of the eight belongs to.
  int owner(int j) const {
    if (tied(j)) j = JointParameters::transposed(j);
    return static_cast<int>(std::find(free.begin(), free.end(), j) - free.begin());
  }
  JointParameters params(const VectorXd& q) const {
    JointParameters p;
    for (int j = 0; j < 8; ++j) p[j] = scale(owner(j)) * q(owner(j));
    return p;
  }
  VectorXd from(const JointParameters& p) const {
    VectorXd q(size());
    for (int k = 0; k < size(); ++k) {
      const int j = free[static_cast<std::size_t>(k)];
      const bool off_diagonal = JointParameters::row(j) != JointParameters::column(j);
      const double v = reciprocal && off_diagonal ? 0.5 * (p[j] + p[JointParameters::transposed(j)]) : p[j];
      q(k) = v / scale(k);
    }
    return q;
  }
  // T (8 × free): ∂p/∂q, for carrying covariances to SI units.
  MatrixXd jacobian() const {
    MatrixXd t = MatrixXd::Zero(8, size());
    for (int j = 0; j < 8; ++j) t(j, owner(j)) = scale(owner(j));
    return t;
  }
};

// Scales from the starting values: a stiffness by its own size; an off-diagonal stiffness no
// smaller than 10 % of √|k_yf k_θm| (its natural scale, as identify.hpp's noise gains); a damping
// no smaller than 1e-3 of its entry's stiffness scale over ω at the band's middle.
Parametrization make_parametrization(const JointParameters& start, bool reciprocal, double omega_mid) {
  Parametrization par;
  par.reciprocal = reciprocal;
  for (int j = 0; j < 8; ++j)
    if (!par.tied(j)) par.free.push_back(j);
  par.scale.resize(par.size());
  const double off = 0.1 * std::sqrt(std::abs(start.k_yf * start.k_tm));
  for (int k = 0; k < par.size(); ++k) {
    const int j = par.free[static_cast<std::size_t>(k)];
    const int r = JointParameters::row(j), c = JointParameters::column(j);
    const bool diagonal = r == c;
    double ks = std::max(std::abs(start[JointParameters::stiffness_of(r, c)]), diagonal ? 0.0 : off);
    if (reciprocal && !diagonal) ks = std::max(ks, 0.5 * std::abs(start.k_ym + start.k_tf));  // k_ym stands for k_θf too
    if (!(ks > 0.0)) ks = 1.0;
    double s = ks;
    if (JointParameters::is_damping(j)) s = std::max(std::abs(start[j]), 1e-3 * ks / omega_mid);
    par.scale(k) = s > 0.0 && std::isfinite(s) ? s : 1.0;
  }
  return par;
}

// ---- The Savitzky–Golay filter as a matrix -------------------------------------------------------

// Rows of S on n points: interior rows are the centred weights; the first and last window/2 rows
// come from the polynomial fitted to the end windows (signal.hpp), read off by filtering impulses.
struct FilterRows {
  std::vector<std::size_t> start;           // first column of row i
  std::vector<std::vector<double>> weight;  // its weights

  FilterRows(const SavgolOptions& o, std::size_t n) {
    const auto w = static_cast<std::size_t>(o.window), m = w / 2;
    const std::vector<double> c = savgol_coefficients(o);
    std::vector<std::vector<double>> edge(w, std::vector<double>(w));  // edge[i][k] = S(i, k) on w points
    for (std::size_t k = 0; k < w; ++k) {
      std::vector<double> impulse(w, 0.0);
      impulse[k] = 1.0;
      const std::vector<double> y = savgol_filter(std::span<const double>(impulse), o, "impulse");
      for (std::size_t i = 0; i < w; ++i) edge[i][k] = y[i];
    }
    start.resize(n);
    weight.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (i < m) {
        start[i] = 0;
        weight[i] = edge[i];
      } else if (i + m >= n) {
        start[i] = n - w;
        weight[i] = edge[i - (n - w)];
      } else {
        start[i] = i - m;
        weight[i] = c;
      }
    }
  }
};

// ---- One set-up ------------------------------------------------------------------------------------

// Whether B11's additive floor reaches a tenth of an entry's magnitude somewhere (σ of a part over
// |B_e| of its noise-free estimate): there, raw values put noise-driven poles into the model, the
// cost has local minima and the first-order noise propagation fails (joint_fit.hpp).
bool floor_reaches(const BlockNoise& noise, const BlockSeries& smooth) {
  if (!noise.has_floor()) return false;
  for (std::size_t i = 0; i < smooth.size(); ++i)
    for (int e = 0; e < 4; ++e)
      if (std::sqrt(noise.additive[i](e)) > 0.1 * std::abs(smooth.blocks[i](e / 2, e % 2))) return true;
  return false;
}

struct Setup {
  std::string label;
  std::vector<double> f, omega;
  std::vector<TwoPort> A;
  BlockSeries B, G;    // as fitted: B11 enters the model, G11 is compared (filtered if filtering)
  BlockSeries B_base;  // the bootstrap world's B11: the smoothed raw B11 (exact B11 itself)
  const BlockNoise* b_noise = nullptr;
  const BlockNoise* g_noise = nullptr;
  std::optional<FilterRows> rows;          // when filtering
  std::optional<FilterRows> b_rows;        // when B11 enters the model smoothed (B = B_base; see fit_joint)
  std::vector<Cov8> W;                     // whitening per frequency (W Σ_w Wᵀ = I)
  std::vector<Cov8> sigma;                 // noise covariance of the fitted residual at i (filtered: S's diagonal block)
  std::vector<Cov8> sigma_raw;             // Σ_G + J_B Σ_B' J_Bᵀ per frequency, before any filter (Σ_B' of B as it enters)
  std::vector<Cov8> sigma_g, sigma_b, jb;  // with b_rows: Σ_G, the raw B11's Σ_B, J_B = ∂G11/∂B11 per frequency
  std::size_t b_group = 0;                 // set-ups with the same B11 data share its calibration factor
};

// Calibration factors (noise.hpp): each measured series scales by its own 1 + δ, except that
// set-ups with the same B11 share its factor (one measurement), and with shared calibration one
// factor scales every measured series. Factor k: σ and which series it scales.
struct CalibrationFactor {
  double sigma = 0.0;
  std::vector<std::size_t> g, b;  // set-ups whose G11, B11 it scales
};

std::vector<CalibrationFactor> calibration_factors(const std::vector<Setup>& setups, bool shared) {
  std::vector<CalibrationFactor> out;
  if (shared) {
    CalibrationFactor f;
    for (std::size_t s = 0; s < setups.size(); ++s) {
      f.sigma = std::max({f.sigma, setups[s].g_noise->calibration, setups[s].b_noise->calibration});
      f.g.push_back(s);
      if (!setups[s].b_noise->exact()) f.b.push_back(s);
    }
    if (f.sigma > 0.0) out.push_back(f);
    return out;
  }
  for (std::size_t s = 0; s < setups.size(); ++s)
    if (setups[s].g_noise->calibration > 0.0) out.push_back({setups[s].g_noise->calibration, {s}, {}});
  for (std::size_t s = 0; s < setups.size(); ++s) {
    if (!(setups[s].b_noise->calibration > 0.0) || setups[s].b_group != s) continue;
    CalibrationFactor f{setups[s].b_noise->calibration, {}, {}};
    for (std::size_t t = 0; t < setups.size(); ++t)
      if (setups[t].b_group == s) f.b.push_back(t);
    out.push_back(f);
  }
  return out;
}

// The model at one frequency, G11 = A11 − A12 K V, and when `jm` is given its Jacobian columns
// vec8(dG11/dq_k) = vec8(−U dK_k V) (p columns of the 8×8; the rest left alone). dK_k has one
// entry (two for a reciprocal off-diagonal pair), so each column is an outer product of a column
// of U and a row of V.
inline Block model_point(const TwoPort& a, const Block& B, const Block& K, double omega, const Parametrization& par, Cov8* jm) {
  const Block I = Block::Identity();
  const Block M = a.b22 + B;
  const Block V = (I + M * K).inverse() * a.b21;
  const Block g = a.b11 - a.b12 * (K * V);
  if (jm) {
    const Block U = a.b12 * (I + K * M).inverse();
    for (int k = 0; k < par.size(); ++k) {
      const int j = par.free[static_cast<std::size_t>(k)];
      const int r = JointParameters::row(j), c = JointParameters::column(j);
      const Complex unit = JointParameters::is_damping(j) ? Complex(0.0, omega * par.scale(k)) : Complex(par.scale(k), 0.0);
      Block d = U.col(r) * V.row(c);
      if (par.reciprocal && r != c) d += U.col(c) * V.row(r);  // k_ym, c_ym: also the transposed entry
      jm->col(k) = vec8(-unit * d);
    }
  }
  return g;
}

// Model G11 and, when `jac`, its Jacobian columns at every frequency of a set-up, with `B` in the
// model: the series a filtered fit needs, filtered.
struct Evaluation {
  std::vector<Block> g;
  std::vector<Cov8> jm;  // per frequency, p columns used
};

void filter_series(std::vector<Block>& s, const SavgolOptions& o) {
  BlockSeries b;
  b.blocks = std::move(s);
  b.frequency_hz.resize(b.blocks.size());
  std::iota(b.frequency_hz.begin(), b.frequency_hz.end(), 1.0);  // even grid: the filter needs only that
  s = std::move(savgol_filter(b, o, "model").series.blocks);
}

Evaluation evaluate(const Setup& s, const BlockSeries& B, const Parametrization& par, const VectorXd& q, bool jac,
                    const std::optional<SavgolOptions>& filter) {
  const JointParameters p = par.params(q);
  const std::size_t n = s.f.size();
  Evaluation ev;
  ev.g.resize(n);
  if (jac) ev.jm.assign(n, Cov8::Zero());
  for (std::size_t i = 0; i < n; ++i)
    ev.g[i] = model_point(s.A[i], B.blocks[i], p.stiffness(s.f[i]), s.omega[i], par, jac ? &ev.jm[i] : nullptr);
  if (filter) {
    filter_series(ev.g, *filter);
    if (jac) {
      // Each Jacobian column is a series of 8 real parts: filtered as a block series of its own.
      for (int k = 0; k < par.size(); ++k) {
        std::vector<Block> col(n);
        for (std::size_t i = 0; i < n; ++i)
          for (int e = 0; e < 4; ++e) col[i](e / 2, e % 2) = Complex(ev.jm[i](2 * e, k), ev.jm[i](2 * e + 1, k));
        filter_series(col, *filter);
        for (std::size_t i = 0; i < n; ++i) ev.jm[i].col(k) = vec8(col[i]);
      }
    }
  }
  return ev;
}

// The weighted cost, and when asked the normal matrix and right-hand side (8×8 fixed, the p × p
// corner used), of the set-ups.
struct Normal {
  double cost = 0.0;
  Cov8 A = Cov8::Zero();
  Vec8 g = Vec8::Zero();
};

inline void add_point(const Cov8& W, const Block& data, const Block& model, const Cov8* jm, Normal& out) {
  const Vec8 r = W * vec8(data - model);
  out.cost += r.squaredNorm();
  if (!jm) return;
  // 8×8 fixed: coefficient-wise products (lazyProduct), not Eigen's packed GEMM, which costs
  // more than the arithmetic at this size.
  const Cov8 J = W.lazyProduct(*jm);
  out.A.noalias() += J.transpose().lazyProduct(J);
  out.g.noalias() += J.transpose() * r;
}

void accumulate(const Setup& s, const BlockSeries& B, const BlockSeries& G, const Parametrization& par, const VectorXd& q,
                bool jac, const std::optional<SavgolOptions>& filter, Normal& out) {
  if (filter) {
    const Evaluation ev = evaluate(s, B, par, q, jac, filter);
    for (std::size_t i = 0; i < s.f.size(); ++i) add_point(s.W[i], G.blocks[i], ev.g[i], jac ? &ev.jm[i] : nullptr, out);
    return;
  }
  // Unfiltered: one frequency at a time, nothing stored.
  const JointParameters p = par.params(q);
  Cov8 jm = Cov8::Zero();
  for (std::size_t i = 0; i < s.f.size(); ++i) {
    const Block g = model_point(s.A[i], B.blocks[i], p.stiffness(s.f[i]), s.omega[i], par, jac ? &jm : nullptr);
    add_point(s.W[i], G.blocks[i], g, jac ? &jm : nullptr, out);
  }
}

// Weights at θ: Σ_raw,i = Σ_G(G_ref) + J_B Σ_B(B_base) J_Bᵀ around the model's values (Σ_B the
// smoother's variance of it where B11 enters smoothed), filtered to S's diagonal blocks when
// filtering, then floored (kWeightFloor within each entry, 1e-12 of |G_ref|² on each part) and
// whitened.
void update_weights(Setup& s, const Parametrization& par, const VectorXd& q) {
  const JointParameters p = par.params(q);
  const std::size_t n = s.f.size();
  s.sigma_raw.resize(n);
  // With B11 smoothed, the parts are kept: the smoothed variance needs the neighbours' Σ_B, and
  // linearise the parts apart. Raw, Σ_G + J_B Σ_B J_Bᵀ is all there is to keep.
  const bool keep_parts = s.b_rows.has_value();
  s.sigma_g.resize(keep_parts ? n : 0);
  s.sigma_b.resize(keep_parts ? n : 0);
  s.jb.resize(keep_parts ? n : 0);
  std::vector<Block> gref(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Block K = p.stiffness(s.f[i]);
    gref[i] = forward_g11(s.A[i], s.B_base.blocks[i], K);
    Cov8 sig = s.g_noise->absolute(i, gref[i]);
    if (keep_parts) {
      s.sigma_g[i] = sig;
      s.jb[i] = b11_jacobian(s.A[i], s.B_base.blocks[i], K);
      s.sigma_b[i] = s.b_noise->absolute(i, s.B_base.blocks[i]);
    } else if (!s.b_noise->exact()) {
      const Cov8 jb = b11_jacobian(s.A[i], s.B_base.blocks[i], K);
      sig.noalias() += jb.lazyProduct(s.b_noise->absolute(i, s.B_base.blocks[i])).lazyProduct(jb.transpose());
    }
    s.sigma_raw[i] = sig;
  }
  if (keep_parts)  // the smoothed B11's variance at i: Σ_k S_ik² Σ_B,k (its correlation: linearise)
    for (std::size_t i = 0; i < n; ++i) {
      Cov8 sb = Cov8::Zero();
      const auto& w = s.b_rows->weight[i];
      for (std::size_t k = 0; k < w.size(); ++k) sb += (w[k] * w[k]) * s.sigma_b[s.b_rows->start[i] + k];
      s.sigma_raw[i].noalias() += s.jb[i].lazyProduct(sb).lazyProduct(s.jb[i].transpose());
    }
  s.sigma = s.sigma_raw;
  if (s.rows) {
    for (std::size_t i = 0; i < n; ++i) {
      Cov8 acc = Cov8::Zero();
      const auto& w = s.rows->weight[i];
      for (std::size_t k = 0; k < w.size(); ++k) acc += (w[k] * w[k]) * s.sigma_raw[s.rows->start[i] + k];
      s.sigma[i] = acc;
    }
  }
  s.W.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Cov8 w = s.sigma[i];
    for (int e = 0; e < 4; ++e) {
      const double t = 0.5 * (w(2 * e, 2 * e) + w(2 * e + 1, 2 * e + 1));
      const double rel = 1e-12 * std::norm(gref[i](e / 2, e % 2));
      w(2 * e, 2 * e) += kWeightFloor * t + rel;
      w(2 * e + 1, 2 * e + 1) += kWeightFloor * t + rel;
    }
    const Eigen::LLT<Cov8> llt(w);
    if (llt.info() != Eigen::Success || !w.allFinite())
      throw NumericalError(fmt::format("{}: the noise covariance at {} Hz is not positive definite", s.label, s.f[i]),
                           "check the data for entries that are zero");
    s.W[i] = llt.matrixL().solve(Cov8::Identity());
  }
}

// ---- Levenberg–Marquardt -------------------------------------------------------------------------

struct Solution {
  VectorXd q;
  double cost = 0.0;
  MatrixXd A;  // normal matrix at q
  int iterations = 0;
  bool converged = false;
};

// Minimises the summed cost over the set-ups with their current weights, data (B, G) per set-up.
// Anderson's point (Walker & Ni 2011, type II) from the fixed-point map q → q + δ(q) and its last
// iterates: q + δ − (ΔQ + ΔF) γ, γ minimising |δ − ΔF γ| in the metric A (ΔF, ΔQ: the differences
// of the current step and point to the remembered ones).
VectorXd anderson_point(const VectorXd& q, const VectorXd& step, const std::vector<VectorXd>& past_q,
                        const std::vector<VectorXd>& past_step, const MatrixXd& A) {
  const auto m = static_cast<Eigen::Index>(past_q.size());
  MatrixXd dF(q.size(), m), dQ(q.size(), m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const auto k = static_cast<std::size_t>(j);
    dF.col(j) = step - past_step[k];
    dQ.col(j) = q - past_q[k];
  }
  MatrixXd N = dF.transpose() * A * dF;
  N.diagonal() += 1e-12 * N.diagonal().cwiseAbs().maxCoeff() * VectorXd::Ones(m);
  const VectorXd gamma = N.ldlt().solve(dF.transpose() * (A * step));
  return q + step - (dQ + dF) * gamma;
}

// Converged when the last Gauss–Newton step δ has δᵀ A δ < `tolerance` (its size in standard
// errors squared: 1e-6 is a thousandth of one).
Solution minimise(const std::vector<Setup>& setups, const std::vector<const BlockSeries*>& B,
                  const std::vector<const BlockSeries*>& G, const Parametrization& par, VectorXd q, int max_iterations,
                  const std::optional<SavgolOptions>& filter, double tolerance = 1e-6) {
  const int p = par.size();
  struct Current {
    double cost = 0.0;
    MatrixXd A;
    VectorXd g;
  };
  auto normal = [&](const VectorXd& x, bool jac) {
    Normal nm;
    for (std::size_t s = 0; s < setups.size(); ++s) accumulate(setups[s], *B[s], *G[s], par, x, jac, filter, nm);
    return Current{nm.cost, nm.A.topLeftCorner(p, p), nm.g.head(p)};
  };
  Current cur = normal(q, true);
  double lambda = 1e-3;
  Solution sol;
  // Anderson acceleration (Walker & Ni 2011) of the Gauss–Newton iteration q → q + δ(q), with the
  // last kAndersonDepth steps: where the data hold a misfit the model cannot take up (a calibration
  // factor, an additive floor at the antiresonances) Gauss–Newton converges only linearly (each
  // step ~0.6 of the last on the example with 2 % calibration and a 1 % floor: 24 iterations).
  // The accelerated point is tried first and kept only when it lowers the cost; the convergence
  // test stays on the Gauss–Newton step.
  constexpr std::size_t kAndersonDepth = 3;
  std::vector<VectorXd> past_q, past_step;
  for (int it = 1; it <= max_iterations; ++it) {
    sol.iterations = it;
    const VectorXd d = cur.A.diagonal().cwiseMax(1e-30 * cur.A.diagonal().maxCoeff());
    bool accepted = false;
    VectorXd step;
    // Takes the point `to` with its normal equations `next`; `remember`: q and its step join the
    // Anderson history (Gauss–Newton steps only: a damped step is another map).
    auto accept = [&](VectorXd to, Current next, bool remember) {
      if (remember) {
        past_q.push_back(q);
        past_step.push_back(step);
      } else {
        past_q.clear();
        past_step.clear();
      }
      q = std::move(to);
      cur = std::move(next);
      lambda = std::max(lambda / 10.0, 1e-12);
      accepted = true;
    };
    bool try_accelerated = lambda <= 1e-3 && !past_q.empty();
    while (lambda < 1e16) {
      MatrixXd M = cur.A;
      M.diagonal() += lambda * d;
      step = M.ldlt().solve(cur.g);
      if (!step.allFinite()) {
        lambda *= 10.0;
        continue;
      }
      if (try_accelerated) {
        try_accelerated = false;
        const VectorXd accelerated = anderson_point(q, step, past_q, past_step, cur.A);
        if (accelerated.allFinite()) {
          try {
            Current next = normal(accelerated, true);
            if (next.cost <= cur.cost) {
              accept(accelerated, std::move(next), true);
              break;
            }
          } catch (const NumericalError&) {}
        }
      }
      // The trial with its Jacobian: steps are rarely rejected, so this saves a pass.
      const VectorXd trial = q + step;
      Current next = normal(trial, true);
      if (next.cost <= cur.cost) {
        accept(trial, std::move(next), lambda <= 1e-3);
        break;
      }
      lambda *= 10.0;
    }
    if (past_q.size() > kAndersonDepth) {
      past_q.erase(past_q.begin());
      past_step.erase(past_step.begin());
    }
    if (!accepted) {
      // No step lowers the cost any more: a minimum to rounding.
      sol.converged = true;
      break;
    }
    // Converged when the last step moved the parameters by less than 1e-3 of their standard
    // errors (δᵀ A δ is the step's size in units of the noise; for exact data the 1e-6 relative
    // weight floor makes that ~1e-9 relative), or below rounding.
    if (step.dot(cur.A * step) < tolerance || step.cwiseAbs().maxCoeff() < 1e-11 * std::max(1.0, q.cwiseAbs().maxCoeff())) {
      sol.converged = true;
      break;
    }
  }
  sol.q = q;
  sol.cost = cur.cost;
  sol.A = cur.A;
  return sol;
}

// The sandwich A⁻¹ (Σ Yᵀ Σ_raw Y) A⁻¹ over the set-ups at q, and tr(Ω Σ) for the residual ratio;
// with the calibration factors' share added: a factor 1 + δ on the data moves q by δ A⁻¹ Σ Zᵀ Δ
// (Z = Ω J), Δ the fitted G11 for a factor on G11 and −(J_B B11, filtered alike) for one on B11
// (implicit function theorem at the optimum); its covariance σ² d dᵀ per factor.
struct Linearised {
  MatrixXd covariance;   // of q: the noise's and the calibration's
  MatrixXd calibration;  // the calibration's share
  double expected_cost = 0.0;
  double calibration_cost = 0.0;  // the calibration factors' share of expected_cost
};

Linearised linearise(const std::vector<Setup>& setups, const Parametrization& par, const VectorXd& q, const MatrixXd& A,
                     const std::optional<SavgolOptions>& filter, const std::vector<CalibrationFactor>& factors = {}) {
  const int p = par.size();
  MatrixXd middle = MatrixXd::Zero(p, p);
  double trace = 0.0;
  std::vector<VectorXd> g_dir(setups.size(), VectorXd::Zero(p)), b_dir(setups.size(), VectorXd::Zero(p));
  // Σ Δᵀ Ω Δ of each direction, and Σ Δ_gᵀ Ω Δ_b (a factor on both G11 and B11 of a set-up).
  std::vector<double> g_norm(setups.size(), 0.0), b_norm(setups.size(), 0.0), gb_cross(setups.size(), 0.0);
  const JointParameters theta = par.params(q);
  for (std::size_t si = 0; si < setups.size(); ++si) {
    const Setup& s = setups[si];
    const Evaluation ev = evaluate(s, s.B, par, q, true, filter);
    const std::size_t n = s.f.size();
    // Ω J per frequency, 8×8 fixed (columns past p stay zero): small fixed products, no GEMM.
    std::vector<Cov8> Z(n);
    Cov8 mid = Cov8::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      Z[i] = s.W[i].transpose().lazyProduct(s.W[i].lazyProduct(ev.jm[i]));
      trace += (s.W[i].lazyProduct(s.sigma[i]).lazyProduct(s.W[i].transpose())).trace();
    }
    if (!factors.empty()) {
      std::vector<Block> u(n);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec8 v = b11_jacobian(s.A[i], s.B.blocks[i], theta.stiffness(s.f[i])) * vec8(s.B.blocks[i]);
        for (int e = 0; e < 4; ++e) u[i](e / 2, e % 2) = Complex(v(2 * e), v(2 * e + 1));
      }
      if (filter) filter_series(u, *filter);
      Vec8 g = Vec8::Zero(), b = Vec8::Zero();
      for (std::size_t i = 0; i < n; ++i) {
        g.noalias() += Z[i].transpose() * vec8(s.G.blocks[i]);
        b.noalias() -= Z[i].transpose() * vec8(u[i]);
        const Vec8 wg = s.W[i] * vec8(s.G.blocks[i]), wb = s.W[i] * vec8(u[i]);
        g_norm[si] += wg.squaredNorm();
        b_norm[si] += wb.squaredNorm();
        gb_cross[si] -= wg.dot(wb);  // Δ_b = −u
      }
      g_dir[si] = g.head(p);
      b_dir[si] = b.head(p);
    }
    if (s.rows) {  // Y = Sᵀ Z, column by column along frequency
      std::vector<Cov8> Y(n, Cov8::Zero());
      for (std::size_t i = 0; i < n; ++i) {
        const auto& w = s.rows->weight[i];
        for (std::size_t k = 0; k < w.size(); ++k) Y[s.rows->start[i] + k] += w[k] * Z[i];
      }
      Z = std::move(Y);
    }
    if (s.b_rows) {
      // B11 smoothed: the score's B part is −Σ_k U_kᵀ e_B,k with U_k = Σ_j S_jk J_B,jᵀ Y_j, so
      // the middle is Σ_j Y_jᵀ Σ_G,j Y_j + Σ_k U_kᵀ Σ_B,k U_k (the smoother's correlation exact).
      std::vector<Cov8> U(n, Cov8::Zero());
      for (std::size_t j = 0; j < n; ++j) {
        const Cov8 v = s.jb[j].transpose().lazyProduct(Z[j]);
        const auto& w = s.b_rows->weight[j];
        for (std::size_t k = 0; k < w.size(); ++k) U[s.b_rows->start[j] + k] += w[k] * v;
      }
      for (std::size_t i = 0; i < n; ++i) {
        mid.noalias() += Z[i].transpose().lazyProduct(s.sigma_g[i].lazyProduct(Z[i]));
        mid.noalias() += U[i].transpose().lazyProduct(s.sigma_b[i].lazyProduct(U[i]));
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) mid.noalias() += Z[i].transpose().lazyProduct(s.sigma_raw[i].lazyProduct(Z[i]));
    }
    middle += mid.topLeftCorner(p, p);
  }
  const MatrixXd Ainv = A.ldlt().solve(MatrixXd::Identity(p, p));
  Linearised l;
  l.covariance = Ainv * middle * Ainv;
  l.expected_cost = trace - (Ainv * middle).trace();
  l.calibration = MatrixXd::Zero(p, p);
  for (const CalibrationFactor& f : factors) {
    VectorXd d = VectorXd::Zero(p);
    double norm = 0.0;  // Σ Δᵀ Ω Δ over the series the factor scales
    for (std::size_t s : f.g) {
      d += g_dir[s];
      norm += g_norm[s];
    }
    for (std::size_t s : f.b) {
      d += b_dir[s];
      norm += b_norm[s];
      if (std::find(f.g.begin(), f.g.end(), s) != f.g.end()) norm += 2.0 * gb_cross[s];
    }
    // The factor's share of the residual: what the fit cannot absorb of it, σ² (ΔᵀΩΔ − dᵀA⁻¹d).
    const double share = f.sigma * f.sigma * std::max(0.0, norm - d.dot(Ainv * d));
    l.expected_cost += share;
    l.calibration_cost += share;
    d = Ainv * d;
    l.calibration += f.sigma * f.sigma * d * d.transpose();
  }
  l.covariance += l.calibration;
  return l;
}

// Throws NumericalError when a parameter does not act on the fitted FRFs, or two cannot be told
// apart, naming them.
void check_identifiable(const MatrixXd& A, const Parametrization& par, const std::vector<Setup>& setups) {
  const int p = par.size();
  auto band = [&] {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const Setup& s : setups) {
      lo = std::min(lo, s.f.front());
      hi = std::max(hi, s.f.back());
    }
    return fmt::format("{:g}–{:g} Hz", lo, hi);
  };
  for (int k = 0; k < p; ++k)
    if (!(A(k, k) > 1e-4))
      throw NumericalError(
          fmt::format("{} does not act on the fitted FRFs in {}: doubling it moves them by less than 1 % of their noise",
                      JointParameters::name(par.free[static_cast<std::size_t>(k)]), band()),
          "fit a band that holds the mode the joint controls (the default band: every frequency)");
  const VectorXd d = A.diagonal().cwiseSqrt().cwiseInverse();
  const MatrixXd R = d.asDiagonal() * A * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(R);
  if (es.eigenvalues()(0) < 1e-12) {
    const VectorXd v = es.eigenvectors().col(0).cwiseAbs();
    std::vector<int> idx(static_cast<std::size_t>(p));
    std::iota(idx.begin(), idx.end(), 0);
    std::sort(idx.begin(), idx.end(), [&](int a, int b) { return v(a) > v(b); });
    throw NumericalError(
        fmt::format("{} and {} cannot be told apart by the FRFs in {}: a combination of them has no effect on the "
                    "fit (normalised eigenvalue {:.1e})",
                    JointParameters::name(par.free[static_cast<std::size_t>(idx[0])]),
                    JointParameters::name(par.free[static_cast<std::size_t>(idx[1])]), band(), es.eigenvalues()(0)),
        "fit a wider band, or several set-ups together, so that each parameter leaves its own mark");
  }
}

void check_data(const JointFitData& d, std::size_t index) {
  const std::string label = d.label.empty() ? fmt::format("set-up {}", index + 1) : d.label;
  const std::string bn = d.b_name.empty() ? "B11" : d.b_name, gn = d.g_name.empty() ? "G11" : d.g_name;
  validate(d.G11, label + ": " + gn, 1);
  validate(d.B11, label + ": " + bn, 1);
  require_same_grid(d.B11.frequency_hz, label + ": " + bn, d.G11.frequency_hz, label + ": " + gn);
  if (d.A.size() != d.G11.size())
    throw InputError(fmt::format("{}: {} model component blocks for {} frequencies", label, d.A.size(), d.G11.size()));
  if (!d.g_noise.exact() && d.g_noise.size() != d.G11.size())
    throw InputError(
        fmt::format("{}: the noise of {} covers {} frequencies, the data {}", label, gn, d.g_noise.size(), d.G11.size()));
  if (!d.b_noise.exact() && d.b_noise.size() != d.B11.size())
    throw InputError(
        fmt::format("{}: the noise of {} covers {} frequencies, the data {}", label, bn, d.b_noise.size(), d.B11.size()));
}

}  // namespace

Cov8 b11_jacobian(const TwoPort& a, const Block& B, const Block& K) {
  const Block X = K * (Block::Identity() + (a.b22 + B) * K).inverse();
  const Block P = a.b12 * X, Q = X * a.b21;
  Cov8 j;
  for (int e = 0; e < 4; ++e) {
    Block E = Block::Zero();
    E(e / 2, e % 2) = 1.0;
    const Block d = P * E * Q;
    j.col(2 * e) = vec8(d);
    j.col(2 * e + 1) = vec8(Complex(0.0, 1.0) * d);
  }
  return j;
}

Block forward_g11(const TwoPort& A, const Block& B11, const Block& K) {
  return A.b11 - A.b12 * (K * ((Block::Identity() + (A.b22 + B11) * K).inverse() * A.b21));
}

void JointFitOptions::check() const {
  if (filter) {
    try {
      filter->check();
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(fmt::format("JointFitOptions::filter: {}", e.what()), e.hint());
    }
  }
  // The scalar fields' ranges (joint_fit_fields); the replicates only where they are drawn.
  for (const OptionField<JointFitOptions>& f : joint_fit_fields())
    if (uncertainty == UncertaintyMethod::Bootstrap || std::string_view(f.spec.name) != "bootstrap_samples")
      check_field(f.spec, f.get(*this), "JointFitOptions");
  parallel.check();
}

const std::vector<OptionField<JointFitOptions>>& joint_fit_fields() {
  using O = JointFitOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "reciprocal", .kind = FieldKind::Flag, .help = "six parameters (k_θf = k_ym, c_θf = c_ym); false: all eight"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.reciprocal; }},
      {{.name = "bootstrap_samples",
        .kind = FieldKind::Integer,
        .min = 20.0,
        .max = 100000.0,
        .help = "bootstrap replicates (200 give intervals whose own Monte Carlo error is about 5 %)"},
       nullptr,
       [](O& o) -> int& { return o.bootstrap_samples; }},
      {{.name = "shared_calibration",
        .kind = FieldKind::Flag,
        .help = "the measured series' calibration is one factor for all of them (one sensor chain)"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.shared_calibration; }},
      {{.name = "check_linearisation",
        .kind = FieldKind::Flag,
        .help = "linearised intervals with a measured B11: checked by bootstrap replicates (off: the plain sandwich)"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.check_linearisation; }},
      {{.name = "confidence",
        .kind = FieldKind::Real,
        .min = 0.5,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "confidence of the intervals (e.g. 0.95)"},
       [](O& o) -> double& { return o.confidence; }},
      {{.name = "max_iterations",
        .kind = FieldKind::Integer,
        .min = 1.0,
        .max = 100000.0,
        .help = "Levenberg–Marquardt iterations per pass"},
       nullptr,
       [](O& o) -> int& { return o.max_iterations; }},
  };
  return fields;
}

double residual_limit(const JointFit& fit, double noise_limit, double probability) {
  const double share = std::clamp(fit.residual_calibration_share, 0.0, 1.0);
  return noise_limit * (1.0 - share) + chi_square_quantile(probability, 1) * share;
}

Eigen::Matrix<double, 8, 8> JointFit::correlation() const {
  Eigen::Matrix<double, 8, 8> c = covariance;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const double d = std::sqrt(covariance(i, i) * covariance(j, j));
      c(i, j) = d > 0.0 ? covariance(i, j) / d : (i == j ? 1.0 : 0.0);
    }
  return c;
}

namespace {

// The fit's set-ups on their data as fitted (filtered G11; B11 raw, or smoothed where its additive
// floor reaches its entries), the set-ups sharing one measured B11 grouped. `smoothed_b` receives
// the labels of those whose B11 enters smoothed.
std::vector<Setup> prepare_setups(const std::vector<JointFitData>& data, const JointFitOptions& options,
                                  std::vector<std::string>& smoothed_b) {
  std::vector<Setup> setups(data.size());
  for (std::size_t s = 0; s < data.size(); ++s) {
    const JointFitData& d = data[s];
    Setup& u = setups[s];
    u.label = d.label.empty() ? fmt::format("set-up {}", s + 1) : d.label;
    u.f = d.G11.frequency_hz;
    for (double x : u.f) u.omega.push_back(omega_of(x));
    u.A = d.A;
    u.b_noise = &d.b_noise;
    u.g_noise = &d.g_noise;
    const std::size_t n = u.f.size();
    u.B_base = noise_free_estimate(d.B11, d.b_noise, u.label + ": " + d.b_name);
    if (options.filter) {
      if (n < static_cast<std::size_t>(options.filter->window))
        throw InputError(fmt::format("{}: the band holds {} frequencies, fewer than the filter window of {}", u.label, n,
                                     options.filter->window),
                         "fit a wider band or use a shorter filter window");
      u.G = savgol_filter(d.G11, *options.filter, d.g_name).series;
      u.rows.emplace(*options.filter, n);
    } else {
      u.G = d.G11;
    }
    // B11 enters the model raw, unless its additive floor reaches its entries (joint_fit.hpp): then
    // its noise-free estimate, the short smoother's, does (B_base; the same smoother in each replicate).
    if (floor_reaches(d.b_noise, u.B_base)) {
      u.B = u.B_base;
      u.b_rows.emplace(kNoiseFreeSmoothing, n);
      smoothed_b.push_back(u.label);
    } else {
      u.B = d.B11;
    }
  }
  for (std::size_t s = 0; s < setups.size(); ++s) {
    setups[s].b_group = s;
    for (std::size_t t = 0; t < s; ++t)
      if (data[t].B11.blocks == data[s].B11.blocks && data[t].B11.frequency_hz == data[s].B11.frequency_hz) {
        setups[s].b_group = setups[t].b_group;
        break;
      }
  }
  return setups;
}

// The set-ups' fitted data, B11 and G11, as the minimiser takes them.
struct FittedData {
  std::vector<const BlockSeries*> B, G;
  explicit FittedData(const std::vector<Setup>& setups) {
    for (const Setup& u : setups) {
      B.push_back(&u.B);
      G.push_back(&u.G);
    }
  }
};

// The optimum: the best of `starts` under the weights of the first, then two passes of the
// minimiser, each with the weights at the previous solution.
Solution fit_from_starts(std::vector<Setup>& setups, const Parametrization& par, const std::vector<JointParameters>& starts,
                         const JointFitOptions& options) {
  const FittedData fd(setups);
  VectorXd q = par.from(starts.front());
  if (starts.size() > 1)
    for (Setup& u : setups) update_weights(u, par, q);
  double best = std::numeric_limits<double>::infinity();
  for (const JointParameters& s : starts) {
    if (starts.size() == 1) break;
    const VectorXd x = par.from(s);
    double c = 0.0;
    try {
      Normal nm;
      for (std::size_t k = 0; k < setups.size(); ++k)
        accumulate(setups[k], *fd.B[k], *fd.G[k], par, x, false, options.filter, nm);
      c = nm.cost;
    } catch (const NumericalError&) {
      continue;
    }
    if (std::isfinite(c) && c < best) {
      best = c;
      q = x;
    }
  }
  Solution sol;
  for (int pass = 0; pass < 2; ++pass) {
    for (Setup& u : setups) update_weights(u, par, q);
    sol = minimise(setups, fd.B, fd.G, par, q, options.max_iterations, options.filter);
    q = sol.q;
  }
  // A cost that overflowed leaves the fit where it started (every step looks as bad): values far
  // out of range in the data (a unit slip by many orders) or in the noise, not a joint.
  if (!std::isfinite(sol.cost))
    throw NumericalError(fmt::format("the band fit's residuals are out of the range of double precision (weighted cost {}): "
                                     "the data's magnitudes or their noise are far from a receptance's",
                                     sol.cost),
                         "check the FRFs' units (m/N, 1/N, rad/(N m)) and how their rotational entries were made");
  return sol;
}

// What the parametric bootstrap (joint_fit.hpp) needs of the fit: the set-ups, the optimum q and
// the calibration factors.
struct BootstrapContext {
  const std::vector<Setup>& setups;
  const Parametrization& par;
  const VectorXd& q;
  const std::vector<CalibrationFactor>& factors;
  const JointFitOptions& options;
};

// A set-up for one bootstrap replicate: what the replicate reads of `u`. Its data, its B_base and
// its weights are its own (update_weights writes all of them), so they are not copied: the copy
// was a tenth of the replicates' time.
Setup replicate_setup(const Setup& u) {
  Setup r;
  r.label = u.label;
  r.f = u.f;
  r.omega = u.omega;
  r.A = u.A;
  r.b_noise = u.b_noise;
  r.g_noise = u.g_noise;
  r.rows = u.rows;
  r.b_rows = u.b_rows;
  r.b_group = u.b_group;
  return r;
}

// The refitted q of each replicate of one bootstrap world, in replicate order; q[b] is valid where
// ok[b] (the replicate converged).
struct Replicates {
  std::vector<VectorXd> q;
  std::vector<char> ok;
  // The converged replicates, in order.
  std::vector<VectorXd> good() const {
    std::vector<VectorXd> out;
    for (std::size_t b = 0; b < q.size(); ++b)
      if (ok[b]) out.push_back(q[b]);
    return out;
  }
};

// Parametric bootstrap replicates of the whole fit in the world θ̂ = q with B11 `b11_world`, data
// drawn from the noise models: the first `N` replicates of the seed JointFitOptions::seed. Replicate
// b draws the same noise in every world (common random numbers: a difference between two worlds
// is then measured replicate by replicate, without the noise's own spread).
Replicates bootstrap_replicates(const BootstrapContext& c, std::size_t N, const std::function<void(double)>& progress,
                                const std::vector<BlockSeries>& b11_world) {
  const std::vector<Setup>& setups = c.setups;
  const JointFitOptions& options = c.options;
  Replicates out{std::vector<VectorXd>(N), std::vector<char>(N, 0)};
  std::vector<VectorXd>& rep = out.q;
  std::vector<char>& ok = out.ok;
  const JointParameters theta = c.par.params(c.q);
  std::vector<BlockSeries> truth_g(setups.size());
  for (std::size_t s = 0; s < setups.size(); ++s) {
    truth_g[s].frequency_hz = setups[s].f;
    for (std::size_t i = 0; i < setups[s].f.size(); ++i)
      truth_g[s].blocks.push_back(forward_g11(setups[s].A[i], b11_world[s].blocks[i], theta.stiffness(setups[s].f[i])));
  }
  parallel_for(
      N, options.parallel,
      [&](std::size_t b) {
        // The whole procedure again on data drawn in the bootstrap world, weights included: they
        // come from the smoothed B11, whose noise then correlates with the fit's (as it does
        // in the fit of the measured data) — leaving that out misjudges the bias.
        std::vector<Setup> local;
        for (const Setup& u : setups) local.push_back(replicate_setup(u));
        std::vector<BlockSeries> Bb(setups.size()), Gb(setups.size());
        std::vector<const BlockSeries*> bp, gp;
        // Calibration: one draw per factor, applied to the series it scales.
        std::vector<double> g_scale(setups.size(), 1.0), b_scale(setups.size(), 1.0);
        for (std::size_t k = 0; k < c.factors.size(); ++k) {
          const double scale = 1.0 +
                               c.factors[k].sigma * calibration_normal(stream_seed(options.seed, b * 1000 + 999 - k));
          for (std::size_t s : c.factors[k].g) g_scale[s] *= scale;
          for (std::size_t s : c.factors[k].b) b_scale[s] *= scale;
        }
        for (std::size_t s = 0; s < setups.size(); ++s) {
          const std::uint64_t base = stream_seed(options.seed, b * 1000 + s);
          Bb[s] = draw_block_noise(b11_world[s], *setups[s].b_noise, stream_seed(base, 1), false);
          Gb[s] = draw_block_noise(truth_g[s], *setups[s].g_noise, stream_seed(base, 2), false);
          for (Block& x : Bb[s].blocks) x *= b_scale[s];
          for (Block& x : Gb[s].blocks) x *= g_scale[s];
          local[s].B_base = noise_free_estimate(Bb[s], *setups[s].b_noise, "bootstrap B11");
          if (local[s].b_rows) Bb[s] = local[s].B_base;  // enters the model as in the fit
          if (options.filter) Gb[s] = savgol_filter(Gb[s], *options.filter, "bootstrap G11").series;
        }
        for (std::size_t s = 0; s < setups.size(); ++s) {
          bp.push_back(&Bb[s]);
          gp.push_back(&Gb[s]);
        }
        try {
          for (Setup& u : local) update_weights(u, c.par, c.q);
          // A replicate needs its optimum to a few hundredths of a standard error (0.03 σ adds
          // 0.1 % to the spread's variance), not the fit's thousandth.
          const Solution r = minimise(local, bp, gp, c.par, c.q, options.max_iterations, options.filter, 1e-3);
          if (r.converged && r.q.allFinite()) {
            rep[b] = r.q;
            ok[b] = 1;
          }
        } catch (const NumericalError&) {}
      },
      progress);
  return out;
}

VectorXd mean_of(const std::vector<VectorXd>& v) {
  VectorXd mean = VectorXd::Zero(v.front().size());
  for (const auto& x : v) mean += x;
  return mean / static_cast<double>(v.size());
}

// The uncertainty of the fit in its parameters q: the bias-corrected estimate and its covariance,
// what was done (appended to the method's description) and the warnings.
struct Uncertainty {
  VectorXd estimate, bias;
  MatrixXd covariance;
  // The second world's step b₁ − b₂: the correction extrapolates by it once, and is taken to be
  // uncertain by kExtrapolationUncertainty times as much (a systematic term added to the
  // covariance).
  VectorXd extrapolation;
  double bias_mc = 1.0;  // the bias's Monte Carlo variance, in the replicates' variance over N
  MatrixXd spread;       // the first world's replicates' covariance (take_replicates)
  std::size_t replicates = 0;  // their number
  std::size_t second_world_pairs = 0;  // the bias corrected once more in a second world: its pairs
  int bootstrap_samples = 0;
  std::string description;
  std::vector<std::string> warnings;

  Uncertainty(const VectorXd& q, const MatrixXd& linearised)
      : estimate(q), bias(VectorXd::Zero(q.size())), covariance(linearised), extrapolation(VectorXd::Zero(q.size())) {}

  // From replicates: the bias (their mean minus q), subtracted, and the covariance with each
  // standard error the larger of the replicates' spread and the linearised one (the spread of N
  // replicates carries a Monte Carlo error of its own, ~1/√(2N): 5 % at 200, which the linearised
  // error bounds from below; the correlations are the replicates'). The replicates' own covariance
  // is kept in `spread`.
  void take_replicates(const std::vector<VectorXd>& good, const VectorXd& q, const MatrixXd& linearised) {
    const int p = static_cast<int>(q.size());
    const VectorXd mean = mean_of(good);
    MatrixXd c = MatrixXd::Zero(p, p);
    for (const auto& v : good) c += (v - mean) * (v - mean).transpose();
    c /= static_cast<double>(good.size() - 1);
    bias = mean - q;
    estimate = q - bias;
    Eigen::VectorXd d = Eigen::VectorXd::Ones(p);
    for (int k = 0; k < p; ++k)
      if (c(k, k) > 0.0 && linearised(k, k) > c(k, k)) d(k) = std::sqrt(linearised(k, k) / c(k, k));
    covariance = d.asDiagonal() * c * d.asDiagonal();
    spread = c;
    replicates = good.size();
  }

  // Where B11 enters the model smoothed, the world's B11 (the smoothed data) carries smoothed noise
  // itself, and the bias, set by B11's noise where B11 is small, comes out smaller there than at
  // the truth (the example with a 1 % floor: 0.77 of it). A second world, the smoothed B11 of one
  // draw in the first, shows by how much: the bias becomes 2 b₁ − b₂ (the iterated bootstrap's
  // correction, Hall 1992 §3.11). The step b₁ − b₂ is measured in pairs: the second world's
  // replicates draw the same noise as the first world's first M = second_world_samples(N)
  // (common random numbers), so each pair's difference lacks part of the noise's own spread and M,
  // a quarter of N, measures it about as well as N independent replicates did (joint_fit.hpp; the
  // pairs' scatter is measured: bias_mc). Called after take_replicates on the first world's good
  // replicates. False when it does not apply or fewer than half of the pairs could be refitted in
  // both worlds.
  bool correct_in_second_world(const BootstrapContext& c, const Replicates& first) {
    if (std::none_of(c.setups.begin(), c.setups.end(), [](const Setup& u) { return u.b_rows.has_value(); })) return false;
    std::vector<BlockSeries> world(c.setups.size());
    for (std::size_t s = 0; s < c.setups.size(); ++s) {
      world[s] = c.setups[s].B_base;
      if (c.setups[s].b_rows)
        world[s] = noise_free_estimate(draw_block_noise(c.setups[s].B_base, *c.setups[s].b_noise,
                                                        stream_seed(stream_seed(c.options.seed, 0x5ec0d), s), false),
                                       *c.setups[s].b_noise, "bootstrap B11");
    }
    const std::size_t M = second_world_samples(first.q.size());
    const Replicates second = bootstrap_replicates(c, M, {}, world);
    std::vector<VectorXd> step, x;  // per pair: b₁ − b₂'s sample, and the first world's replicate
    for (std::size_t b = 0; b < M; ++b)
      if (first.ok[b] && second.ok[b]) {
        step.push_back(first.q[b] - second.q[b]);
        x.push_back(first.q[b]);
      }
    if (step.size() < 2 || 2 * step.size() < M) return false;
    extrapolation = mean_of(step);
    bias += extrapolation;
    estimate = c.q - bias;
    // The bias 2 b₁ − b₂ = b̂₁ + mean(step): its Monte Carlo variance, per parameter in units of
    // the replicates' variance over N, is 1 + (N/P) var(step)/s² + 2 cov(x, step)/s² (P pairs;
    // b̂₁'s replicates include the pairs' x; s² their spread, from take_replicates); the largest over
    // the parameters is kept.
    const VectorXd m_x = mean_of(x);
    const double n = static_cast<double>(replicates), pairs = static_cast<double>(step.size());
    bias_mc = 1.0;
    for (Eigen::Index k = 0; k < c.q.size(); ++k) {
      const double s2 = spread(k, k);
      double v = 0.0, cv = 0.0;
      for (std::size_t j = 0; j < step.size(); ++j) {
        v += (step[j](k) - extrapolation(k)) * (step[j](k) - extrapolation(k));
        cv += (x[j](k) - m_x(k)) * (step[j](k) - extrapolation(k));
      }
      v /= pairs - 1.0;
      cv /= pairs - 1.0;
      if (s2 > 0.0) bias_mc = std::max(bias_mc, 1.0 + (n / pairs) * v / s2 + 2.0 * cv / s2);
    }
    second_world_pairs = step.size();
    return true;
  }
};

// The first world: the smoothed B11 of each set-up (exact B11 itself).
std::vector<BlockSeries> first_world(const std::vector<Setup>& setups) {
  std::vector<BlockSeries> world(setups.size());
  for (std::size_t s = 0; s < setups.size(); ++s) world[s] = setups[s].B_base;
  return world;
}

// UncertaintyMethod::Bootstrap: JointFitOptions::bootstrap_samples replicates, bias-corrected.
Uncertainty bootstrap_uncertainty(const BootstrapContext& c, const Linearised& lin, double z) {
  Uncertainty u(c.q, lin.covariance);
  const auto N = static_cast<std::size_t>(c.options.bootstrap_samples);
  const Replicates first = bootstrap_replicates(c, N, c.options.progress, first_world(c.setups));
  const std::vector<VectorXd> good = first.good();
  if (good.size() < N / 2)
    throw NumericalError(fmt::format("the bootstrap failed: only {} of {} replicates could be refitted", good.size(), N),
                         "the fit is unstable under its own noise: fit a wider band, or use the linearised intervals");
  if (good.size() < N)
    u.warnings.push_back(
        fmt::format("{} of {} bootstrap replicates could not be refitted and were left out", N - good.size(), N));
  u.take_replicates(good, c.q, lin.covariance);
  if (u.correct_in_second_world(c, first)) u.covariance *= 1.0 + u.bias_mc / static_cast<double>(good.size());
  u.bootstrap_samples = static_cast<int>(good.size());
  u.description = fmt::format(
      "parametric bootstrap on the fitted model, {} replicates, bias-corrected; ±{:.3g} standard errors "
      "(each the larger of the replicates' and the linearised)",
      good.size(), z);
  return u;
}

// UncertaintyMethod::Linearised. With B11 measured the model is nonlinear in data that carry noise
// (errors in variables); where that noise is large the linearisation fails, by far (20× in one case
// of an additive floor on SH11). A few bootstrap replicates check it: a spread beyond
// kLinearisationLimit times the linearised standard error (three times the Monte Carlo error of 20
// replicates' spread) makes the result the bootstrap's on them, and says so.
Uncertainty linearised_uncertainty(const BootstrapContext& c, const Linearised& lin, double z) {
  Uncertainty u(c.q, lin.covariance);
  u.description = fmt::format("linearised (sandwich covariance at the optimum{}); ±{:.3g} standard errors",
                              c.options.filter ? ", with the filter's correlation" : "", z);
  const bool errors_in_variables = std::any_of(c.setups.begin(), c.setups.end(),
                                               [](const Setup& s) { return !s.b_noise->exact(); });
  if (!errors_in_variables || !c.options.check_linearisation) return u;
  const Replicates first = bootstrap_replicates(c, kLinearisationCheck, {}, first_world(c.setups));
  const std::vector<VectorXd> good = first.good();
  if (good.size() < kLinearisationCheck / 2) return u;
  u.take_replicates(good, c.q, lin.covariance);
  u.correct_in_second_world(c, first);
  const int p = static_cast<int>(c.q.size());
  std::vector<std::string> off;
  double worst = 1.0;
  for (int k = 0; k < p; ++k) {
    const double ratio = std::sqrt(u.spread(k, k) / lin.covariance(k, k));
    if (ratio > kLinearisationLimit) off.push_back(JointParameters::name(c.par.free[static_cast<std::size_t>(k)]));
    worst = std::max(worst, ratio);
  }
  const double n_good = static_cast<double>(good.size());
  if (off.empty()) {
    // The spread agrees with the linearisation, but the bias (second order in B11's noise) is no
    // smaller for it: 0.6–0.8 standard errors on the example's k_θm, c_θm at 5 % noise cut their
    // coverage to 86 %. The replicates' bias is kept; its Monte Carlo error (the spread over √N)
    // adds to the estimate's variance.
    u.covariance = lin.covariance * (1.0 + u.bias_mc / n_good);
    u.description += fmt::format("; bias-corrected by {} bootstrap replicates (their spread agrees)", good.size());
    return u;
  }
  u.covariance *= 1.0 + u.bias_mc / n_good;
  u.bootstrap_samples = static_cast<int>(good.size());
  u.description += fmt::format(
      "; checked by {} bootstrap replicates, whose spread exceeds it (×{:.2g}): bias-corrected by them, each standard "
      "error the larger",
      good.size(), worst);
  u.warnings.push_back(fmt::format(
      "the linearised intervals understate the uncertainty of {} by up to ×{:.2g}: B11's noise acts nonlinearly through the "
      "model; the intervals are those of {} bootstrap replicates instead (JointFitOptions::uncertainty bootstrap with more "
      "replicates is more exact)",
      fmt::join(off, ", "), worst, good.size()));
  return u;
}

// Several set-ups: each fitted alone, and whether the joint transfers between them (joint_fit.hpp:
// Q against the 99.9 % point of χ² with (S − 1)·p degrees of freedom).
void test_transfer(const std::vector<Setup>& setups, const Parametrization& par, const VectorXd& q,
                   const JointFitOptions& options, JointFit& out, std::vector<std::string>& warnings) {
  const MatrixXd T = par.jacobian();
  double Q = 0.0;
  for (std::size_t s = 0; s < setups.size(); ++s) {
    const std::vector<Setup> one{setups[s]};
    const Solution r = minimise(one, {&setups[s].B}, {&setups[s].G}, par, q, options.max_iterations, options.filter);
    SetupFit sf;
    sf.label = setups[s].label;
    sf.fitted = par.params(r.q);
    Linearised l;
    try {
      l = linearise(one, par, r.q, r.A, options.filter);
    } catch (const NumericalError&) {
      continue;
    }
    const MatrixXd cs = T * l.covariance * T.transpose();
    for (int j = 0; j < 8; ++j) sf.std_error[static_cast<std::size_t>(j)] = std::sqrt(std::max(0.0, cs(j, j)));
    sf.residual_ratio = l.expected_cost > 0.0 ? r.cost / l.expected_cost : std::numeric_limits<double>::quiet_NaN();
    const VectorXd dq = r.q - q;
    sf.disagreement = dq.dot(l.covariance.ldlt().solve(dq));
    Q += sf.disagreement;
    out.setups.push_back(sf);
  }
  out.transfer_statistic = Q;
  out.transfer_limit = chi_square_quantile(0.999,
                                           static_cast<double>((setups.size() - 1) * static_cast<std::size_t>(par.size())));
  out.transfers = Q <= out.transfer_limit;
  if (out.transfers) return;
  std::string worst;
  double wd = -1.0;
  for (const auto& sf : out.setups)
    if (sf.disagreement > wd) {
      wd = sf.disagreement;
      worst = sf.label;
    }
  warnings.push_back(
      fmt::format("the joint does not transfer between the set-ups: fitted alone they disagree beyond their noise "
                  "(χ² = {:.3g}, 99.9 % limit {:.3g}; most: {}); the common fit describes none of them well",
                  Q, out.transfer_limit, worst));
}

// The frequencies to fit, after every set-up's data are checked; the band's geometric middle
// (rad/s) in `omega_mid`.
std::size_t checked_points(const std::vector<JointFitData>& data, const std::vector<JointParameters>& starts,
                           const JointFitOptions& options, double& omega_mid) {
  options.check();
  if (data.empty()) throw InvalidArgument("fit_joint: no set-up given");
  if (starts.empty()) throw InvalidArgument("fit_joint: no starting values given");
  for (const auto& s : starts) s.check();
  std::size_t total = 0;
  double wlo = std::numeric_limits<double>::infinity(), whi = 0.0;
  for (std::size_t s = 0; s < data.size(); ++s) {
    check_data(data[s], s);
    total += data[s].G11.size();
    wlo = std::min(wlo, data[s].G11.frequency_hz.front());
    whi = std::max(whi, data[s].G11.frequency_hz.back());
  }
  const int p_free = options.reciprocal ? 6 : 8;
  if (total < static_cast<std::size_t>(p_free))
    throw InputError(fmt::format("{} frequencies to fit {} parameters: too few", total, p_free),
                     "fit a wider band or a finer grid");
  omega_mid = omega_of(std::sqrt(wlo * whi));
  return total;
}

}  // namespace

JointFit fit_joint(const std::vector<JointFitData>& data, const std::vector<JointParameters>& starts,
                   const JointFitOptions& options) {
  double omega_mid = 0.0;
  const std::size_t total = checked_points(data, starts, options, omega_mid);
  const Parametrization par = make_parametrization(starts.front(), options.reciprocal, omega_mid);
  std::vector<std::string> warnings, smoothed_b;
  std::vector<Setup> setups = prepare_setups(data, options, smoothed_b);
  const std::vector<CalibrationFactor> factors = calibration_factors(setups, options.shared_calibration);
  const Solution sol = fit_from_starts(setups, par, starts, options);
  const VectorXd& q = sol.q;
  check_identifiable(sol.A, par, setups);
  const Linearised lin = linearise(setups, par, q, sol.A, options.filter, factors);

  JointFit out;
  out.reciprocal = options.reciprocal;
  out.confidence = options.confidence;
  out.points = total;
  out.iterations = sol.iterations;
  out.converged = sol.converged;
  if (!sol.converged)
    warnings.push_back(
        fmt::format("the fit did not converge in {} iterations (JointFitOptions::max_iterations)", options.max_iterations));
  out.residual_ratio = lin.expected_cost > 0.0 ? sol.cost / lin.expected_cost : std::numeric_limits<double>::quiet_NaN();
  out.residual_calibration_share = lin.expected_cost > 0.0 ? lin.calibration_cost / lin.expected_cost : 0.0;
  // Widen only for a ratio beyond its own scatter (its standard deviation is √(2/(8n)) for n
  // frequencies: 0.007 for the whole example grid, 0.05 for a hundred points) and beyond what the
  // stated calibration makes at 95 % (its share is one draw of a factor, not averaged over
  // frequencies); continuous with √ratio without a calibration.
  const double widen_above = residual_limit(out, 1.1, 0.95);
  const double inflation = std::isfinite(out.residual_ratio) && out.residual_ratio > widen_above
                               ? std::sqrt(1.1 * out.residual_ratio / widen_above)
                               : 1.0;
  if (std::isfinite(out.residual_ratio) && out.residual_ratio > residual_limit(out, 1.5, 0.99))
    warnings.push_back(
        fmt::format("the fitted model leaves residuals {:.2g} times what the noise explains: the model (the joint, the "
                    "components) or the noise model does not match the data; intervals are widened by {:.2g}",
                    out.residual_ratio, inflation));

  const double z = normal_quantile(0.5 + 0.5 * options.confidence);
  out.method = options.uncertainty;
  const BootstrapContext context{setups, par, q, factors, options};
  Uncertainty u = options.uncertainty == UncertaintyMethod::Bootstrap ? bootstrap_uncertainty(context, lin, z)
                                                                      : linearised_uncertainty(context, lin, z);
  out.bootstrap_samples = u.bootstrap_samples;
  out.method_description = u.description;
  warnings.insert(warnings.end(), u.warnings.begin(), u.warnings.end());
  if (u.second_world_pairs > 0) {
    u.covariance += kExtrapolationUncertainty * kExtrapolationUncertainty * u.extrapolation * u.extrapolation.transpose() +
                    kCorrectionUncertainty * kCorrectionUncertainty * u.bias * u.bias.transpose();
    out.method_description += fmt::format(
        "; the bias corrected once more from a second bootstrap world (2 b₁ − b₂, b₁ − b₂ from {} replicates paired with the "
        "first world's by their noise; uncertain by {:g} (b₁ − b₂) and by {:g} of the whole correction)",
        u.second_world_pairs, kExtrapolationUncertainty, kCorrectionUncertainty);
  }
  if (!smoothed_b.empty())
    out.method_description += fmt::format(
        "; B11 of {} (its additive floor reaching its entries) enters the model smoothed by the {}-point degree-{} "
        "Savitzky–Golay filter, its correlation carried",
        fmt::join(smoothed_b, ", "), kNoiseFreeSmoothing.window, kNoiseFreeSmoothing.order);
  if (inflation > 1.0) {
    u.covariance *= inflation * inflation;
    out.method_description += fmt::format(", widened ×{:.2g} for the residual ratio", inflation);
  }
  const MatrixXd T = par.jacobian();
  out.covariance = T * u.covariance * T.transpose();
  const MatrixXd cal = T * lin.calibration * T.transpose() * (inflation * inflation);
  for (int j = 0; j < 8; ++j) out.calibration_std_error[static_cast<std::size_t>(j)] = std::sqrt(std::max(0.0, cal(j, j)));
  out.parameters = par.params(u.estimate);
  const JointParameters fitted = par.params(q), biases = par.params(u.bias);
  for (int j = 0; j < 8; ++j) {
    ParameterInterval& iv = out.intervals[static_cast<std::size_t>(j)];
    iv.estimate = out.parameters[j];
    iv.fitted = fitted[j];
    iv.bias = biases[j];
    iv.std_error = std::sqrt(std::max(0.0, out.covariance(j, j)));
    iv.lower = iv.estimate - z * iv.std_error;
    iv.upper = iv.estimate + z * iv.std_error;
    iv.determined = iv.lower > 0.0 ? iv.upper < 2.0 * iv.lower : iv.upper < 0.0 && iv.lower > 2.0 * iv.upper;
    iv.free = !par.tied(j);
  }
  if (setups.size() > 1) test_transfer(setups, par, q, options, out, warnings);
  for (const JointFitData& d : data)
    for (const auto* n : {&d.b_noise, &d.g_noise})
      for (const auto& w : n->warnings) warnings.push_back(w);
  out.warnings = std::move(warnings);
  return out;
}

}  // namespace toolpoint
