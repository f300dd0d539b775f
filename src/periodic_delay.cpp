// toolpoint: full-discretization of linear time-periodic delay equations and the dominant Floquet
// multiplier of the period map (periodic_delay.hpp). Units: time in s; the rest as the caller's.
#include "toolpoint/periodic_delay.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

// Spectra (Debian libspectra-dev, header-only): restarted Arnoldi for the dominant multipliers.
// GCC 12 flags a use-after-free inside Eigen's storage as inlined into Spectra's Hessenberg
// eigenvectors (a false positive: the pointer is compared, never read); silenced for this file.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic ignored "-Wuse-after-free"
#endif
#include <Spectra/GenEigsSolver.h>

namespace toolpoint {

namespace {

using Complex = std::complex<double>;

// Gauss–Legendre nodes and weights on [0, 1], 5 points: exact for polynomials of degree 9.
constexpr int kGauss = 5;
constexpr double kGaussNode[kGauss] = {0.046910077030668, 0.230765344947158, 0.5, 0.769234655052842, 0.953089922969332};
constexpr double kGaussWeight[kGauss] = {0.118463442528095, 0.239314335249683, 0.284444444444444, 0.239314335249683,
                                         0.118463442528095};

// A block of A₀ as V diag(λ) V⁻¹, so e^{A₀t} is exact for any t at the cost of a few complex
// exponentials.
struct EigenBlock {
  Eigen::VectorXcd lambda;
  Eigen::MatrixXcd v, v_inv;
};

EigenBlock decompose(const Eigen::MatrixXd& a, std::size_t index) {
  Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(a.cast<Complex>());
  if (es.info() != Eigen::Success)
    throw InvalidArgument(fmt::format("PeriodicDelaySystem::a0_blocks[{}]: its eigenvalues did not converge", index));
  EigenBlock b{es.eigenvalues(), es.eigenvectors(), {}};
  b.v_inv = b.v.inverse();
  const double cond = b.v.norm() * b.v_inv.norm();
  if (!std::isfinite(cond) || cond > 1e8)
    throw InvalidArgument(fmt::format("PeriodicDelaySystem::a0_blocks[{}] is not diagonalisable in a well-conditioned "
                                      "basis (condition {:.3g}), e.g. a critically damped mode",
                                      index, cond),
                          "perturb the block slightly (a damping ratio of 0.999 instead of 1)");
  return b;
}

// e^{A t} for a decomposed block (real part: A is real).
Eigen::MatrixXd block_exp(const EigenBlock& b, double t) {
  Eigen::VectorXcd e(b.lambda.size());
  for (Eigen::Index i = 0; i < e.size(); ++i) e(i) = std::exp(b.lambda(i) * t);
  return (b.v * e.asDiagonal() * b.v_inv).real();
}

// A fixed start vector for the Arnoldi iteration (a small linear congruential generator with a
// fixed seed): the same on every call and every thread, so results do not depend on either.
Eigen::VectorXd start_vector(int n) {
  Eigen::VectorXd v(n);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < n; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    v(i) = static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;
  }
  return v.normalized();
}

// Maps of up to this size are decomposed densely.
constexpr int kDenseUpTo = 40;

// Index of the eigenvalue of largest modulus; of a complex pair the one with Im ≥ 0.
Eigen::Index dominant_index(const Eigen::VectorXcd& ev) {
  Eigen::Index k = 0;
  for (Eigen::Index i = 1; i < ev.size(); ++i) {
    const double a = std::abs(ev(i)), b = std::abs(ev(k));
    if (a > b * (1.0 + 1e-13) || (a >= b * (1.0 - 1e-13) && ev(i).imag() > ev(k).imag())) k = i;
  }
  return k;
}

// The eigenvector of a (real, square) for its eigenvalue mu by inverse iteration with the shift
// mu + 1e-9 max(|mu|, ‖a‖) (a shift, since a − mu I is singular to rounding): three solves, then
// the residual ‖a v − mu v‖ ≤ 1e-8 ‖a‖ with ‖v‖ = 1. Empty when the residual is larger.
Eigen::VectorXcd inverse_iteration(const Eigen::MatrixXd& a, Complex mu) {
  const double scale = std::max(std::abs(mu), a.norm());
  Eigen::MatrixXcd shifted = a.cast<Complex>();
  shifted.diagonal().array() -= mu + Complex(1e-9 * scale, 0.0);
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(shifted);
  Eigen::VectorXcd v = start_vector(static_cast<int>(a.rows())).cast<Complex>();
  for (int it = 0; it < 3; ++it) {
    v = lu.solve(v);
    const double norm = v.norm();
    if (!std::isfinite(norm) || norm == 0.0) return {};
    v /= norm;
  }
  if ((a * v - mu * v).norm() > 1e-8 * scale) return {};
  return v;
}

}  // namespace

void PeriodicDelaySystem::check() const {
  if (a0_blocks.empty()) throw InvalidArgument("PeriodicDelaySystem::a0_blocks is empty: the equation needs a state");
  Eigen::Index n = 0;
  for (std::size_t b = 0; b < a0_blocks.size(); ++b) {
    const Eigen::MatrixXd& a = a0_blocks[b];
    if (a.rows() == 0 || a.rows() != a.cols() || !a.allFinite())
      throw InvalidArgument(
          fmt::format("PeriodicDelaySystem::a0_blocks[{}] must be square, non-empty and finite ({}×{})", b, a.rows(), a.cols()));
    n += a.rows();
  }
  if (input.rows() != n || input.cols() == 0 || !input.allFinite())
    throw InvalidArgument(
        fmt::format("PeriodicDelaySystem::input must be n × d = {} × d, finite (is {}×{})", n, input.rows(), input.cols()));
  if (output.rows() != input.cols() || output.cols() != n || !output.allFinite())
    throw InvalidArgument(fmt::format("PeriodicDelaySystem::output must be d × n = {} × {}, finite (is {}×{})", input.cols(), n,
                                      output.rows(), output.cols()));
  if (!std::isfinite(period) || !(period > 0.0))
    throw InvalidArgument(fmt::format("PeriodicDelaySystem::period {} s must be positive", period));
  for (double t : breakpoints)
    if (!std::isfinite(t) || !(t > 0.0) || !(t < period))
      throw InvalidArgument(fmt::format("PeriodicDelaySystem::breakpoints: {} s lies outside (0, {}) s", t, period));
}

PeriodMap::PeriodMap(const PeriodicDelaySystem& sys, int steps, int degree) {
  sys.check();
  if (steps < 2 || steps > 100000) throw InvalidArgument(fmt::format("{} discretization steps per period: need 2…100000", steps));
  if (degree < 1 || degree > 3) throw InvalidArgument(fmt::format("interpolation degree {}: need 1, 2 or 3", degree));
  if (steps < degree) throw InvalidArgument(fmt::format("{} steps are too few for degree {}", steps, degree));
  m_ = steps;
  p_ = degree;
  d_ = static_cast<int>(sys.input.cols());
  regenerative_ = sys.regenerative;
  c_ = sys.output;
  const double h = sys.period / m_;

  std::vector<EigenBlock> eig;
  double rate = 0.0;  // the fastest |λ| of A₀: quadrature panels stay short against it
  for (std::size_t b = 0; b < sys.a0_blocks.size(); ++b) {
    eig.push_back(decompose(sys.a0_blocks[b], b));
    block_start_.push_back(n_);
    block_size_.push_back(static_cast<int>(sys.a0_blocks[b].rows()));
    n_ += block_size_.back();
    for (Eigen::Index i = 0; i < eig.back().lambda.size(); ++i) rate = std::max(rate, std::abs(eig.back().lambda(i)));
    const Eigen::MatrixXd e = block_exp(eig.back(), h);
    for (Eigen::Index r = 0; r < e.rows(); ++r)
      for (Eigen::Index c = 0; c < e.cols(); ++c) phi_.push_back(e(r, c));
  }
  // e^{A₀t} B, block by block.
  auto exp_b = [&](double t) {
    Eigen::MatrixXd out(n_, d_);
    for (std::size_t b = 0; b < eig.size(); ++b)
      out.middleRows(block_start_[b], block_size_[b]) = block_exp(eig[b], t) *
                                                        sys.input.middleRows(block_start_[b], block_size_[b]);
    return out;
  };

  // Sample nodes of step k at s_o = (o − p + 1) h, o = 0…p (o = p: the implicit newest sample).
  std::vector<double> node(static_cast<std::size_t>(p_ + 1));
  for (int o = 0; o <= p_; ++o) node[static_cast<std::size_t>(o)] = (o - p_ + 1) * h;
  auto lagrange = [&](int o, double s) {
    double l = 1.0;
    for (int q = 0; q <= p_; ++q)
      if (q != o)
        l *= (s - node[static_cast<std::size_t>(q)]) / (node[static_cast<std::size_t>(o)] - node[static_cast<std::size_t>(q)]);
    return l;
  };
  // Quadrature points of [a, b] ⊂ [0, h]: panels no longer than 2/|λ|max, Gauss on each.
  struct Point {
    double s, w;
  };
  auto points = [&](double a, double b) {
    std::vector<Point> pts;
    const int panels = std::max(1, static_cast<int>(std::ceil(rate * (b - a) / 2.0)));
    const double len = (b - a) / panels;
    for (int j = 0; j < panels; ++j)
      for (int g = 0; g < kGauss; ++g) pts.push_back({a + (j + kGaussNode[g]) * len, kGaussWeight[g] * len});
    return pts;
  };
  // A whole step has the same points and the same e^{A₀(h−s)}B at them: computed once.
  const std::vector<Point> whole = points(0.0, h);
  std::vector<Eigen::MatrixXd> whole_eb;
  for (const Point& pt : whole) whole_eb.push_back(exp_b(h - pt.s));
  std::vector<const Eigen::MatrixXd*> whole_eb_ptr;
  for (const auto& e : whole_eb) whole_eb_ptr.push_back(&e);

  std::vector<double> cuts = sys.breakpoints;
  std::sort(cuts.begin(), cuts.end());
  active_.assign(static_cast<std::size_t>(m_), 0);
  wp_.resize(static_cast<std::size_t>(m_));
  wq_.resize(static_cast<std::size_t>(m_));
  cwp_.resize(static_cast<std::size_t>(m_));
  if (sys.forcing) wf_.assign(static_cast<std::size_t>(m_), Eigen::VectorXd::Zero(n_));
  const int nd = n_ * d_;
  // Scratch reused across steps: a map is built per speed, and allocations were half its cost.
  std::vector<double> ends, wp, wq;
  std::vector<Point> pts;
  std::vector<const Eigen::MatrixXd*> eb;
  std::vector<Eigen::MatrixXd> local;
  Eigen::MatrixXd coef(d_, d_), g(n_, d_);
  Eigen::VectorXd force(d_);
  for (int k = 0; k < m_; ++k) {
    const double t0 = k * h;
    // Pieces of the step between breakpoints (a breakpoint within 1e-12 h of an end is the end).
    ends.assign(1, 0.0);
    for (double t : cuts)
      if (t > t0 + 1e-12 * h && t < t0 + h - 1e-12 * h) ends.push_back(t - t0);
    ends.push_back(h);
    const std::vector<Point>* step_points = &whole;
    const Eigen::MatrixXd* const* step_eb = whole_eb_ptr.data();
    if (ends.size() > 2) {
      pts.clear();
      for (std::size_t j = 0; j + 1 < ends.size(); ++j)
        for (const Point& pt : points(ends[j], ends[j + 1])) pts.push_back(pt);
      local.clear();
      for (const Point& pt : pts) local.push_back(exp_b(h - pt.s));
      eb.clear();
      for (const auto& e : local) eb.push_back(&e);
      step_points = &pts;
      step_eb = eb.data();
    }
    bool any = false;
    for (std::size_t q = 0; q < step_points->size(); ++q) {
      const Point& pt = (*step_points)[q];
      const double t = t0 + pt.s;
      if (sys.forcing) {
        force.setZero();
        sys.forcing(t, force);
        if (force.size() != d_ || !force.allFinite())
          throw InvalidArgument(fmt::format("PeriodicDelaySystem::forcing({} s) must be a finite {}-vector", t, d_));
        wf_[static_cast<std::size_t>(k)].noalias() += pt.w * (*step_eb[q]) * force;
      }
      for (int pass = 0; pass < (regenerative_ ? 1 : 2); ++pass) {
        const auto& f = pass == 0 ? sys.current : sys.delayed;
        if (!f) continue;
        coef.setZero();
        f(t, coef);
        if (coef.rows() != d_ || coef.cols() != d_ || !coef.allFinite())
          throw InvalidArgument(fmt::format("PeriodicDelaySystem::{}({} s) must be a finite {}×{} matrix (is {}×{})",
                                            pass == 0 ? "current" : "delayed", t, d_, d_, coef.rows(), coef.cols()));
        if (coef.isZero(0.0)) continue;
        if (!any) {  // the first non-zero coefficient of this step: its weights start from zero
          wp.assign(static_cast<std::size_t>((p_ + 1) * nd), 0.0);
          wq.assign(regenerative_ ? 0 : wp.size(), 0.0);
          any = true;
        }
        g.noalias() = pt.w * (*step_eb[q]) * coef;  // n × d
        std::vector<double>& w = pass == 0 ? wp : wq;
        for (int o = 0; o <= p_; ++o) {
          const double l = lagrange(o, pt.s);
          double* dst = w.data() + o * nd;
          for (int c = 0; c < d_; ++c)
            for (int r = 0; r < n_; ++r) dst[c * n_ + r] += l * g(r, c);
        }
      }
    }
    const auto kk = static_cast<std::size_t>(k);
    if (!any && sys.forcing && !wf_[kk].isZero(0.0)) {  // forced but no feedback: zero weights
      wp.assign(static_cast<std::size_t>((p_ + 1) * nd), 0.0);
      wq.assign(regenerative_ ? 0 : wp.size(), 0.0);
      any = true;
    }
    if (!any) continue;
    active_[kk] = 1;
    cwp_[kk] = c_ * Eigen::Map<const Eigen::MatrixXd>(wp.data() + p_ * nd, n_, d_);
    wp_[kk] = wp;
    wq_[kk] = wq;
  }

  // Buffer samples y_{−i}, i = 1…m+p−1, that an active step reads; a sample that a later period
  // needs (i > m becomes i − m) is kept as well. Everything else is dropped exactly.
  const int buffer = m_ + p_ - 1;
  std::vector<char> needed(static_cast<std::size_t>(buffer + 1), 0);
  for (int k = 0; k < m_; ++k) {
    if (!active_[static_cast<std::size_t>(k)]) continue;
    for (int o = 0; o <= p_; ++o) {
      const int cur = k + 1 - p_ + o, del = cur - m_;
      if (cur < 0 && o < p_) needed[static_cast<std::size_t>(-cur)] = 1;
      if (del < 0) needed[static_cast<std::size_t>(-del)] = 1;
    }
  }
  for (int i = buffer; i > m_; --i)
    if (needed[static_cast<std::size_t>(i)]) needed[static_cast<std::size_t>(i - m_)] = 1;
  slot_.assign(static_cast<std::size_t>(buffer + 1), -1);
  for (int i = 1; i <= buffer; ++i)
    if (needed[static_cast<std::size_t>(i)]) {
      slot_[static_cast<std::size_t>(i)] = n_ + d_ * static_cast<int>(read_.size());
      read_.push_back(i);
    }

  // Jumps over steps out of the cut: there the state only evolves freely, so when no output in
  // between is read (by a later step of this period or as a delayed sample of the next), k steps
  // are one multiplication by e^{A₀kh}. At low radial immersion most of the period is skipped.
  std::vector<char> read_output(static_cast<std::size_t>(m_ + 1), 0);  // r_j = y_j, j = 0…m, is read
  for (int k = 0; k < m_; ++k)
    if (active_[static_cast<std::size_t>(k)])
      for (int j = std::max(0, k + 1 - p_); j <= k; ++j) read_output[static_cast<std::size_t>(j)] = 1;
  for (int i : read_)
    if (i <= m_) read_output[static_cast<std::size_t>(m_ - i)] = 1;
  jump_.assign(static_cast<std::size_t>(m_), 0);
  jump_phi_.resize(static_cast<std::size_t>(m_));
  for (int k = 0; k < m_;) {
    int len = 0;
    while (k + len < m_ && !active_[static_cast<std::size_t>(k + len)] &&
           (len == 0 || !read_output[static_cast<std::size_t>(k + len)]))
      ++len;
    if (len >= 2) {
      jump_[static_cast<std::size_t>(k)] = len;
      for (const EigenBlock& b : eig) {
        const Eigen::MatrixXd e = block_exp(b, len * h);
        for (Eigen::Index r = 0; r < e.rows(); ++r)
          for (Eigen::Index c = 0; c < e.cols(); ++c) jump_phi_[static_cast<std::size_t>(k)].push_back(e(r, c));
      }
    }
    k += std::max(len, 1);
  }
}

// One state at a time: the path Arnoldi takes (plain loops, no column dimension).
template <typename S>
void PeriodMap::run_one(double sigma, const S* u, S* v, S* out, bool forced) const {
  const int n = n_, d = d_, m = m_, p = p_, nd = n * d;
  // Scratch kept per thread between calls (this runs ~20 times per spectral radius).
  static thread_local std::vector<S> y, z, r, zero, delta, rhs;
  y.assign(u, u + n);
  z.resize(static_cast<std::size_t>(n));
  r.resize(static_cast<std::size_t>((m + 1) * d));  // the outputs y_0 … y_m of this period, d values each
  zero.assign(static_cast<std::size_t>(d), S(0.0));
  delta.resize(static_cast<std::size_t>(d));
  rhs.resize(static_cast<std::size_t>(d));
  auto sample = [&](int j) -> const S* {
    if (j >= 0) return r.data() + j * d;
    const int at = slot_[static_cast<std::size_t>(-j)];
    return at >= 0 ? u + at : zero.data();
  };
  auto outputs_of = [&](const std::vector<S>& x, S* dst) {
    for (int i = 0; i < d; ++i) {
      S acc(0.0);
      for (int c = 0; c < n; ++c) acc += c_(i, c) * x[static_cast<std::size_t>(c)];
      dst[i] = acc;
    }
  };
  // z = e^{A₀t} y, block by block (ph: the blocks of e^{A₀t}).
  auto propagate = [&](const double* ph) {
    for (std::size_t b = 0; b < block_start_.size(); ++b) {
      const int s0 = block_start_[b], bs = block_size_[b];
      for (int i = 0; i < bs; ++i) {
        S acc(0.0);
        for (int j = 0; j < bs; ++j) acc += ph[i * bs + j] * y[static_cast<std::size_t>(s0 + j)];
        z[static_cast<std::size_t>(s0 + i)] = acc;
      }
      ph += bs * bs;
    }
  };
  outputs_of(y, r.data());
  for (int k = 0; k < m; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    if (!out && !forced && jump_[kk] > 0) {  // free motion over jump_[k] steps whose outputs nobody reads
      propagate(jump_phi_[kk].data());
      y.swap(z);
      k += jump_[kk] - 1;
      outputs_of(y, r.data() + (k + 1) * d);
      continue;
    }
    propagate(phi_.data());
    S* rk1 = r.data() + (k + 1) * d;
    if (!active_[kk]) {
      y.swap(z);
      outputs_of(y, rk1);
      continue;
    }
    const double* wp = wp_[kk].data();
    const double* wq = regenerative_ ? nullptr : wq_[kk].data();
    auto add = [&](const double* w, const S* x, double f) {  // z += f W x, W n × d column-major
      for (int c = 0; c < d; ++c) {
        const S xc = f * x[c];
        const double* col = w + c * n;
        for (int i = 0; i < n; ++i) z[static_cast<std::size_t>(i)] += col[i] * xc;
      }
    };
    for (int o = 0; o <= p; ++o) {
      const int cur = k + 1 - p + o;
      const S* del = sample(cur - m);
      if (regenerative_) {
        if (o < p) {
          const S* now = sample(cur);
          for (int i = 0; i < d; ++i) delta[static_cast<std::size_t>(i)] = now[i] - del[i];
          add(wp + o * nd, delta.data(), sigma);
        } else {
          add(wp + o * nd, del, -sigma);
        }
      } else {
        if (o < p) add(wp + o * nd, sample(cur), sigma);
        add(wq + o * nd, del, sigma);
      }
    }
    if (forced)
      for (int i = 0; i < n; ++i) z[static_cast<std::size_t>(i)] += sigma * wf_[kk](i);
    // y_{k+1} = z + σ W^P_p y_{k+1}: (I − σ C W^P_p) y_{k+1} = C z, a d × d solve.
    outputs_of(z, rhs.data());
    const Eigen::MatrixXd& cw = cwp_[kk];
    if (d == 1) {
      rk1[0] = rhs[0] / (1.0 - sigma * cw(0, 0));
    } else if (d == 2) {
      const double a = 1.0 - sigma * cw(0, 0), b = -sigma * cw(0, 1), c = -sigma * cw(1, 0), e = 1.0 - sigma * cw(1, 1);
      const double det = a * e - b * c;
      rk1[0] = (e * rhs[0] - b * rhs[1]) / det;
      rk1[1] = (a * rhs[1] - c * rhs[0]) / det;
    } else {
      using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
      using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
      const Mat lhs = (Eigen::MatrixXd::Identity(d, d) - sigma * cw).template cast<S>();
      const Vec sol = lhs.partialPivLu().solve(Eigen::Map<const Vec>(rhs.data(), d));
      for (int i = 0; i < d; ++i) rk1[i] = sol(i);
    }
    add(wp + p * nd, rk1, sigma);
    y.swap(z);
  }
  if (v) {
    std::copy(y.begin(), y.end(), v);
    for (int i : read_) {
      const S* src = i <= m ? r.data() + (m - i) * d : sample(-(i - m));
      std::copy(src, src + d, v + slot_[static_cast<std::size_t>(i)]);
    }
  }
  if (out) std::copy(r.begin(), r.end(), out);
}

// The recursion over one period for `cols` states at once. Layout: entry i of column c at
// [i * cols + c] (columns innermost, so the loops over them vectorise); outputs likewise, sample j
// output i at [(j * d + i) * cols + c]. Scratch is kept per thread between calls.
template <typename S>
void PeriodMap::run(double sigma, int cols, const S* u, S* v, S* out) const {
  const int n = n_, d = d_, m = m_, p = p_, nd = n * d;
  const auto nc = static_cast<std::size_t>(cols);
  static thread_local std::vector<S> scratch;
  const std::size_t need = (2 * static_cast<std::size_t>(n) + static_cast<std::size_t>((m + 1) * d) +
                            3 * static_cast<std::size_t>(d)) *
                           nc;
  if (scratch.size() < need) scratch.resize(need);
  S* y = scratch.data();
  S* z = y + n * nc;
  S* r = z + n * nc;  // the outputs y_0 … y_m of this period
  S* zero = r + static_cast<std::size_t>((m + 1) * d) * nc;
  S* delta = zero + d * nc;
  S* rhs = delta + d * nc;
  std::fill(zero, zero + d * nc, S(0.0));
  std::copy(u, u + n * nc, y);
  auto sample = [&](int j) -> const S* {
    if (j >= 0) return r + static_cast<std::size_t>(j * d) * nc;
    const int at = slot_[static_cast<std::size_t>(-j)];
    return at >= 0 ? u + static_cast<std::size_t>(at) * nc : zero;
  };
  auto outputs_of = [&](const S* x, S* dst) {
    for (int i = 0; i < d; ++i) {
      S* row = dst + i * nc;
      std::fill(row, row + nc, S(0.0));
      for (int k = 0; k < n; ++k) {
        const double c = c_(i, k);
        if (c == 0.0) continue;
        const S* xr = x + k * nc;
        for (std::size_t q = 0; q < nc; ++q) row[q] += c * xr[q];
      }
    }
  };
  // z += f W x for W n × d (column-major), x d rows.
  auto add = [&](const double* w, const S* x, double f) {
    for (int c = 0; c < d; ++c) {
      const double* col = w + c * n;
      const S* xc = x + c * nc;
      for (int i = 0; i < n; ++i) {
        const double wi = f * col[i];
        if (wi == 0.0) continue;
        S* zi = z + i * nc;
        for (std::size_t q = 0; q < nc; ++q) zi[q] += wi * xc[q];
      }
    }
  };
  // z = e^{A₀t} y, block by block (ph: the blocks of e^{A₀t}).
  auto propagate = [&](const double* ph) {
    for (std::size_t b = 0; b < block_start_.size(); ++b) {
      const int s0 = block_start_[b], bs = block_size_[b];
      for (int i = 0; i < bs; ++i) {
        S* zi = z + (s0 + i) * nc;
        std::fill(zi, zi + nc, S(0.0));
        for (int j = 0; j < bs; ++j) {
          const double e = ph[i * bs + j];
          const S* yj = y + (s0 + j) * nc;
          for (std::size_t q = 0; q < nc; ++q) zi[q] += e * yj[q];
        }
      }
      ph += bs * bs;
    }
  };
  outputs_of(y, r);
  for (int k = 0; k < m; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    if (!out && jump_[kk] > 0) {  // free motion over jump_[k] steps whose outputs nobody reads
      propagate(jump_phi_[kk].data());
      std::swap(y, z);
      k += jump_[kk] - 1;
      outputs_of(y, r + static_cast<std::size_t>((k + 1) * d) * nc);
      continue;
    }
    propagate(phi_.data());
    S* rk1 = r + static_cast<std::size_t>((k + 1) * d) * nc;
    if (!active_[kk]) {
      std::swap(y, z);
      outputs_of(y, rk1);
      continue;
    }
    const double* wp = wp_[kk].data();
    const double* wq = regenerative_ ? nullptr : wq_[kk].data();
    for (int o = 0; o <= p; ++o) {
      const int cur = k + 1 - p + o;
      const S* del = sample(cur - m);
      if (regenerative_) {
        if (o < p) {
          const S* now = sample(cur);
          for (std::size_t q = 0; q < static_cast<std::size_t>(d) * nc; ++q) delta[q] = now[q] - del[q];
          add(wp + o * nd, delta, sigma);
        } else {
          add(wp + o * nd, del, -sigma);
        }
      } else {
        if (o < p) add(wp + o * nd, sample(cur), sigma);
        add(wq + o * nd, del, sigma);
      }
    }
    // y_{k+1} = z + σ W^P_p y_{k+1}: (I − σ C W^P_p) y_{k+1} = C z, a d × d solve per column.
    outputs_of(z, rhs);
    const Eigen::MatrixXd& cw = cwp_[kk];
    if (d == 1) {
      const double f = 1.0 / (1.0 - sigma * cw(0, 0));
      for (std::size_t q = 0; q < nc; ++q) rk1[q] = f * rhs[q];
    } else if (d == 2) {
      const double a = 1.0 - sigma * cw(0, 0), b = -sigma * cw(0, 1), c = -sigma * cw(1, 0), e = 1.0 - sigma * cw(1, 1);
      const double inv = 1.0 / (a * e - b * c);
      for (std::size_t q = 0; q < nc; ++q) {
        const S r0 = rhs[q], r1 = rhs[nc + q];
        rk1[q] = inv * (e * r0 - b * r1);
        rk1[nc + q] = inv * (a * r1 - c * r0);
      }
    } else {
      using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
      const Mat lhs = (Eigen::MatrixXd::Identity(d, d) - sigma * cw).template cast<S>();
      const Eigen::PartialPivLU<Mat> lu(lhs);
      Mat col(d, 1);
      for (std::size_t q = 0; q < nc; ++q) {
        for (int i = 0; i < d; ++i) col(i, 0) = rhs[static_cast<std::size_t>(i) * nc + q];
        const Mat sol = lu.solve(col);
        for (int i = 0; i < d; ++i) rk1[static_cast<std::size_t>(i) * nc + q] = sol(i, 0);
      }
    }
    add(wp + p * nd, rk1, sigma);
    std::swap(y, z);
  }
  if (v) {
    std::copy(y, y + n * nc, v);
    for (int i : read_) {
      const S* src = i <= m ? r + static_cast<std::size_t>((m - i) * d) * nc : sample(-(i - m));
      std::copy(src, src + d * nc, v + static_cast<std::size_t>(slot_[static_cast<std::size_t>(i)]) * nc);
    }
  }
  if (out) std::copy(r, r + static_cast<std::size_t>((m + 1) * d) * nc, out);
}

void PeriodMap::apply(double sigma, const double* u, double* v) const { run_one(sigma, u, v, static_cast<double*>(nullptr)); }

void PeriodMap::apply(double sigma, const Complex* u, Complex* v) const { run_one(sigma, u, v, static_cast<Complex*>(nullptr)); }

Eigen::MatrixXcd PeriodMap::outputs(double sigma, const Eigen::VectorXcd& u) const {
  if (u.size() != size())
    throw InvalidArgument(fmt::format("PeriodMap::outputs: state of size {}, expected {}", u.size(), size()));
  Eigen::MatrixXcd out(d_, m_ + 1);  // column-major: sample j's d outputs together, as run() writes them
  run(sigma, 1, u.data(), static_cast<Complex*>(nullptr), out.data());
  return out;
}

// All columns in one pass: the identity in run()'s layout (row-major) gives the map row-major.
Eigen::MatrixXd PeriodMap::matrix(double sigma) const {
  const int n = size();
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> a(n, n);
  run(sigma, n, identity.data(), a.data(), static_cast<double*>(nullptr));
  return a;
}

PeriodMap::PeriodicSolution PeriodMap::periodic_solution(double sigma) const {
  if (wf_.empty()) throw InvalidArgument("PeriodMap::periodic_solution: the system has no PeriodicDelaySystem::forcing");
  if (!std::isfinite(sigma)) throw InvalidArgument(fmt::format("PeriodMap: gain {} is not finite", sigma));
  const int n = size();
  const Eigen::VectorXd rest = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd q(n);
  run_one(sigma, rest.data(), q.data(), static_cast<double*>(nullptr), true);
  const Eigen::MatrixXd lhs = Eigen::MatrixXd::Identity(n, n) - matrix(sigma);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(lhs);
  if (!lu.isInvertible() || lu.rcond() < 1e-14)
    throw NumericalError(fmt::format("the period map at gain {} has a multiplier at 1: no unique periodic solution", sigma));
  PeriodicSolution out;
  out.state = lu.solve(q);
  std::vector<double> y(static_cast<std::size_t>((m_ + 1) * d_));
  run_one(sigma, out.state.data(), static_cast<double*>(nullptr), y.data(), true);
  out.outputs = Eigen::Map<const Eigen::MatrixXd>(y.data(), d_, m_ + 1);
  return out;
}

DominantMultiplier PeriodMap::dominant(double sigma, bool vector) const {
  if (!std::isfinite(sigma)) throw InvalidArgument(fmt::format("PeriodMap: gain {} is not finite", sigma));
  const int n = size();
  DominantMultiplier out;
  auto finish = [&](Complex mu, const Eigen::VectorXcd& vec) {
    if (!std::isfinite(std::abs(mu)) || !vec.allFinite())
      throw NumericalError(fmt::format("the period map has non-finite multipliers at gain {}", sigma),
                           "reduce the depth range or check the modal model");
    // Of a complex pair, the member with Im ≥ 0 (and its eigenvector, the conjugate).
    out.multiplier = mu.imag() < 0.0 ? std::conj(mu) : mu;
    out.spectral_radius = std::abs(mu);
    out.vector = mu.imag() < 0.0 ? Eigen::VectorXcd(vec.conjugate()) : vec;
    return out;
  };
  auto dense = [&] {
    Eigen::EigenSolver<Eigen::MatrixXd> es;
    const Eigen::MatrixXd a = matrix(sigma);
    es.compute(a, false);
    if (es.info() != Eigen::Success)
      throw NumericalError(fmt::format("the multipliers of the {}×{} period map at gain {} did not converge", n, n, sigma));
    const Complex mu = es.eigenvalues()(dominant_index(es.eigenvalues()));
    if (!vector) return finish(mu, Eigen::VectorXcd());
    // Its eigenvector alone by inverse iteration (cheaper than every eigenvector from the Schur
    // vectors); the full decomposition when the residual says it did not converge (a multiplier
    // with a close neighbour).
    if (const Eigen::VectorXcd v = inverse_iteration(a, mu); v.size() > 0) return finish(mu, v);
    es.compute(a, true);
    if (es.info() != Eigen::Success)
      throw NumericalError(fmt::format("the multipliers of the {}×{} period map at gain {} did not converge", n, n, sigma));
    const Eigen::Index k = dominant_index(es.eigenvalues());
    return finish(es.eigenvalues()(k), Eigen::VectorXcd(es.eigenvectors().col(k)));
  };
  // Small maps: forming the matrix and decomposing it costs less than the iteration.
  if (n <= kDenseUpTo) return dense();

  // Implicitly restarted Arnoldi (Spectra's GenEigsSolver, as ARPACK) on the product with the
  // map: the four multipliers of largest modulus from a 20-vector Krylov subspace, to a relative
  // residual of 1e-10. A fixed start vector keeps the result independent of threads and calls.
  struct Product {
    using Scalar = double;
    const PeriodMap* map;
    double sigma;
    Eigen::Index rows() const { return map->size(); }
    Eigen::Index cols() const { return map->size(); }
    void perform_op(const double* x, double* y) const { map->apply(sigma, x, y); }
  };
  Product op{this, sigma};
  const int nev = 4, ncv = std::min(n - 1, 20);
  Spectra::GenEigsSolver<Product> solver(op, nev, ncv);
  const Eigen::VectorXd start = start_vector(n);
  solver.init(start.data());
  solver.compute(Spectra::SortRule::LargestMagn, 300, 1e-10, Spectra::SortRule::LargestMagn);
  if (solver.info() != Spectra::CompInfo::Successful) return dense();
  const Eigen::VectorXcd values = solver.eigenvalues();
  const Eigen::Index k = dominant_index(values);
  out.krylov = true;
  return finish(values(k), vector ? Eigen::VectorXcd(solver.eigenvectors().col(k)) : Eigen::VectorXcd());
}

}  // namespace toolpoint
