// toolpoint: full-discretization of linear time-periodic delay equations (periodic_delay.hpp):
// the system's check and the period map's construction — e^{A₀h} and the quadrature weights, all
// that does not depend on the gain. Applying the map is in periodic_delay_run.cpp, its dominant
// multiplier in periodic_delay_dominant.cpp (three files: one took 1.7 GB and 35 s to compile).
// Units: time in s; the rest as the caller's.
#include "toolpoint/stability/periodic_delay.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

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
  for (std::size_t j = 0; j < delays.size(); ++j) {
    if (!std::isfinite(delays[j].delay) || !(delays[j].delay > 0.0) || delays[j].delay > period * (1.0 + 1e-12))
      throw InvalidArgument(fmt::format("PeriodicDelaySystem::delays[{}].delay {} s must lie in (0, {}] s (the period)", j,
                                        delays[j].delay, period));
    if (!delays[j].coefficient) throw InvalidArgument(fmt::format("PeriodicDelaySystem::delays[{}].coefficient is empty", j));
  }
}

PeriodicDelaySystem with_velocity_feedback(const PeriodicDelaySystem& system, const Eigen::MatrixXd& velocity_output,
                                           std::function<void(double t, Eigen::MatrixXd& out)> feedback) {
  system.check();
  const Eigen::Index n = system.output.cols(), d = system.output.rows();
  if (velocity_output.rows() != d || velocity_output.cols() != n || !velocity_output.allFinite())
    throw InvalidArgument(fmt::format("with_velocity_feedback: the velocity output must be {}×{}, finite (is {}×{})", d, n,
                                      velocity_output.rows(), velocity_output.cols()));
  if (!feedback) throw InvalidArgument("with_velocity_feedback: the feedback V(t) is empty");
  PeriodicDelaySystem out;
  out.a0_blocks = system.a0_blocks;
  out.period = system.period;
  out.breakpoints = system.breakpoints;
  out.input = Eigen::MatrixXd::Zero(n, 2 * d);
  out.input.leftCols(d) = system.input;
  out.output.resize(2 * d, n);
  out.output << system.output, velocity_output;
  using Coefficient = std::function<void(double, Eigen::MatrixXd&)>;
  // A d × d coefficient placed in the top-left corner of the 2d × 2d one (scaled by `sign`).
  auto corner = [d](Coefficient f, double sign) -> Coefficient {
    if (!f) return {};
    return [f, d, sign](double t, Eigen::MatrixXd& o) {
      Eigen::MatrixXd c = Eigen::MatrixXd::Zero(d, d);
      f(t, c);
      o.topLeftCorner(d, d) = sign * c;
    };
  };
  const Coefficient current = system.current;
  out.current = [current, feedback, d](double t, Eigen::MatrixXd& o) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(d, d);
    if (current) {
      current(t, c);
      o.topLeftCorner(d, d) = c;
      c.setZero();
    }
    feedback(t, c);
    o.topRightCorner(d, d) = c;
  };
  out.delayed = system.regenerative ? corner(system.current, -1.0) : corner(system.delayed, 1.0);
  for (const DelayedTerm& term : system.delays) out.delays.push_back({term.delay, corner(term.coefficient, 1.0)});
  if (system.forcing) {
    const auto forcing = system.forcing;
    out.forcing = [forcing, d](double t, Eigen::VectorXd& o) {
      Eigen::VectorXd w = Eigen::VectorXd::Zero(d);
      forcing(t, w);
      o.head(d) = w;
    };
  }
  return out;
}

namespace {

// Further delays: τ_j = (i_j + f_j) h, snapped to whole steps within 1e-9 (see the header): the
// whole steps i_j (at most m) and the fractions f_j.
struct DelaySteps {
  std::vector<int> whole;
  std::vector<double> fraction;
};

DelaySteps delay_steps(const PeriodicDelaySystem& sys, double h, int m) {
  DelaySteps out;
  for (std::size_t j = 0; j < sys.delays.size(); ++j) {
    const double steps_back = sys.delays[j].delay / h;
    const double snapped = std::round(steps_back);
    const double exact = std::abs(steps_back - snapped) < 1e-9 ? snapped : steps_back;
    const int whole = static_cast<int>(std::floor(exact));
    if (whole < 1)
      throw InvalidArgument(fmt::format("PeriodicDelaySystem::delays[{}].delay {} s is shorter than a step ({} s)", j,
                                        sys.delays[j].delay, h),
                            "use more steps per period");
    out.whole.push_back(std::min(whole, m));
    out.fraction.push_back(whole >= m ? 0.0 : exact - whole);
  }
  return out;
}

// The quadrature of one step's weights ∫ e^{A₀(h−s)} B P(t_k + s) ℓ_o(s) ds (and the same for Q, the
// further delays and the forcing): the set-up that is the same for every step, and scratch reused
// across steps (a map is built per speed, and allocations were half its cost).
class StepQuadrature {
 public:
  struct Point {
    double s, w;
  };

  StepQuadrature(const PeriodicDelaySystem& sys, const std::vector<EigenBlock>& eig, const std::vector<int>& block_start,
                 const std::vector<int>& block_size, double rate, double h, int p, const DelaySteps& delays)
      : sys_(sys),
        eig_(eig),
        block_start_(block_start),
        block_size_(block_size),
        rate_(rate),
        h_(h),
        p_(p),
        n_(static_cast<int>(sys.input.rows())),
        d_(static_cast<int>(sys.input.cols())),
        delays_(delays) {
    // Sample nodes of step k at s_o = (o − p + 1) h, o = 0…p (o = p: the implicit newest sample).
    node_.resize(static_cast<std::size_t>(p_ + 1));
    for (int o = 0; o <= p_; ++o) node_[static_cast<std::size_t>(o)] = (o - p_ + 1) * h_;
    // A whole step has the same points and the same e^{A₀(h−s)}B at them: computed once.
    whole_ = points(0.0, h_);
    for (const Point& pt : whole_) whole_eb_.push_back(exp_b(h_ - pt.s));
    for (const auto& e : whole_eb_) whole_eb_ptr_.push_back(&e);
    cuts_ = sys.breakpoints;
    std::sort(cuts_.begin(), cuts_.end());
    coef_.resize(d_, d_);
    g_.resize(n_, d_);
    force_.resize(d_);
    wd.resize(sys.delays.size());
    wd_any.resize(sys.delays.size());
  }

  // Step k's weights into wp, wq (P and Q), wd[j] where wd_any[j] (the further delays) and, with
  // forcing, adds its integral to *wf. False when the step has no non-zero weight (and no forcing).
  bool build(int k, Eigen::VectorXd* wf);

  std::vector<double> wp, wq;
  std::vector<std::vector<double>> wd;
  std::vector<char> wd_any;

 private:
  // e^{A₀t} B, block by block.
  Eigen::MatrixXd exp_b(double t) const {
    Eigen::MatrixXd out(n_, d_);
    for (std::size_t b = 0; b < eig_.size(); ++b)
      out.middleRows(block_start_[b], block_size_[b]) = block_exp(eig_[b], t) *
                                                        sys_.input.middleRows(block_start_[b], block_size_[b]);
    return out;
  }
  double lagrange(int o, double s) const {
    double l = 1.0;
    for (int q = 0; q <= p_; ++q)
      if (q != o)
        l *= (s - node_[static_cast<std::size_t>(q)]) / (node_[static_cast<std::size_t>(o)] - node_[static_cast<std::size_t>(q)]);
    return l;
  }
  // Quadrature points of [a, b] ⊂ [0, h]: panels no longer than 2/|λ|max, Gauss on each.
  std::vector<Point> points(double a, double b) const {
    std::vector<Point> pts;
    const int panels = std::max(1, static_cast<int>(std::ceil(rate_ * (b - a) / 2.0)));
    const double len = (b - a) / panels;
    for (int j = 0; j < panels; ++j)
      for (int g = 0; g < kGauss; ++g) pts.push_back({a + (j + kGaussNode[g]) * len, kGaussWeight[g] * len});
    return pts;
  }
  // w += Σ_o ℓ_o(s) g at node blocks o (each n × d, column-major).
  void accumulate(std::vector<double>& w, double s) const {
    const int nd = n_ * d_;
    for (int o = 0; o <= p_; ++o) {
      const double l = lagrange(o, s);
      double* dst = w.data() + o * nd;
      for (int c = 0; c < d_; ++c)
        for (int r = 0; r < n_; ++r) dst[c * n_ + r] += l * g_(r, c);
    }
  }
  void start_weights() {
    wp.assign(static_cast<std::size_t>((p_ + 1) * n_ * d_), 0.0);
    wq.assign(sys_.regenerative || !sys_.delayed ? 0 : wp.size(), 0.0);  // no Q: no weights
  }

  const PeriodicDelaySystem& sys_;
  const std::vector<EigenBlock>& eig_;
  const std::vector<int>&block_start_, &block_size_;
  double rate_, h_;
  int p_, n_, d_;
  const DelaySteps& delays_;
  std::vector<double> node_, cuts_;
  std::vector<Point> whole_;
  std::vector<Eigen::MatrixXd> whole_eb_;
  std::vector<const Eigen::MatrixXd*> whole_eb_ptr_;
  // Scratch.
  std::vector<double> ends_;
  std::vector<Point> pts_;
  std::vector<const Eigen::MatrixXd*> eb_;
  std::vector<Eigen::MatrixXd> local_;
  Eigen::MatrixXd coef_, g_;
  Eigen::VectorXd force_;
};

bool StepQuadrature::build(int k, Eigen::VectorXd* wf) {
  const double h = h_, t0 = k * h;
  std::fill(wd_any.begin(), wd_any.end(), 0);
  // Pieces of the step between breakpoints (a breakpoint within 1e-12 h of an end is the end).
  ends_.assign(1, 0.0);
  for (double t : cuts_)
    if (t > t0 + 1e-12 * h && t < t0 + h - 1e-12 * h) ends_.push_back(t - t0);
  ends_.push_back(h);
  const std::vector<Point>* step_points = &whole_;
  const Eigen::MatrixXd* const* step_eb = whole_eb_ptr_.data();
  if (ends_.size() > 2) {
    pts_.clear();
    for (std::size_t j = 0; j + 1 < ends_.size(); ++j)
      for (const Point& pt : points(ends_[j], ends_[j + 1])) pts_.push_back(pt);
    local_.clear();
    for (const Point& pt : pts_) local_.push_back(exp_b(h - pt.s));
    eb_.clear();
    for (const auto& e : local_) eb_.push_back(&e);
    step_points = &pts_;
    step_eb = eb_.data();
  }
  const bool regenerative = sys_.regenerative;
  bool any = false;
  for (std::size_t q = 0; q < step_points->size(); ++q) {
    const Point& pt = (*step_points)[q];
    const double t = t0 + pt.s;
    if (wf) {
      force_.setZero();
      sys_.forcing(t, force_);
      if (force_.size() != d_ || !force_.allFinite())
        throw InvalidArgument(fmt::format("PeriodicDelaySystem::forcing({} s) must be a finite {}-vector", t, d_));
      wf->noalias() += pt.w * (*step_eb[q]) * force_;
    }
    for (int pass = 0; pass < (regenerative ? 1 : 2); ++pass) {
      const auto& f = pass == 0 ? sys_.current : sys_.delayed;
      if (!f) continue;
      coef_.setZero();
      f(t, coef_);
      if (coef_.rows() != d_ || coef_.cols() != d_ || !coef_.allFinite())
        throw InvalidArgument(fmt::format("PeriodicDelaySystem::{}({} s) must be a finite {}×{} matrix (is {}×{})",
                                          pass == 0 ? "current" : "delayed", t, d_, d_, coef_.rows(), coef_.cols()));
      if (coef_.isZero(0.0)) continue;
      if (!any) {  // the first non-zero coefficient of this step: its weights start from zero
        start_weights();
        any = true;
      }
      g_.noalias() = pt.w * (*step_eb[q]) * coef_;  // n × d
      accumulate(pass == 0 ? wp : wq, pt.s);
    }
  }
  // The further delays: Q_j(t) y(t − τ_j) with y through the nodes around t_k − i_j h, evaluated at
  // s − f_j h.
  for (std::size_t j = 0; j < sys_.delays.size(); ++j)
    for (std::size_t q = 0; q < step_points->size(); ++q) {
      const Point& pt = (*step_points)[q];
      const double t = t0 + pt.s;
      coef_.setZero();
      sys_.delays[j].coefficient(t, coef_);
      if (coef_.rows() != d_ || coef_.cols() != d_ || !coef_.allFinite())
        throw InvalidArgument(
            fmt::format("PeriodicDelaySystem::delays[{}].coefficient({} s) must be a finite {}×{} matrix", j, t, d_, d_));
      if (coef_.isZero(0.0)) continue;
      if (!wd_any[j]) {
        wd[j].assign(static_cast<std::size_t>((p_ + 1) * n_ * d_), 0.0);
        wd_any[j] = 1;
      }
      g_.noalias() = pt.w * (*step_eb[q]) * coef_;
      accumulate(wd[j], pt.s - delays_.fraction[j] * h);
    }
  const bool delayed_any = std::find(wd_any.begin(), wd_any.end(), 1) != wd_any.end();
  // A further delay read, or forced but no feedback: zero weights.
  if (!any && (delayed_any || (wf && !wf->isZero(0.0)))) {
    start_weights();
    any = true;
  }
  return any;
}

// The buffer samples y_{−i}, i = 1…m+p−1, that an active step reads (`reads_period[k]`: step k
// reads y(t − T); `delay_reads[k]`: the whole steps i_j of the further delays it reads); a sample
// that a later period needs (i > m becomes i − m) is kept as well. Everything else is dropped exactly.
std::vector<int> buffer_samples_read(int m, int p, const std::vector<char>& active, const std::vector<char>& reads_period,
                                     const std::vector<std::vector<int>>& delay_reads) {
  const int buffer = m + p - 1;
  std::vector<char> needed(static_cast<std::size_t>(buffer + 1), 0);
  for (int k = 0; k < m; ++k) {
    if (!active[static_cast<std::size_t>(k)]) continue;
    for (int o = 0; o <= p; ++o) {
      const int cur = k + 1 - p + o, del = cur - m;
      if (cur < 0 && o < p) needed[static_cast<std::size_t>(-cur)] = 1;
      if (reads_period[static_cast<std::size_t>(k)] && del < 0) needed[static_cast<std::size_t>(-del)] = 1;
      for (int whole : delay_reads[static_cast<std::size_t>(k)]) {
        const int at = cur - whole;
        if (at < 0) needed[static_cast<std::size_t>(-at)] = 1;
      }
    }
  }
  for (int i = buffer; i > m; --i)
    if (needed[static_cast<std::size_t>(i)]) needed[static_cast<std::size_t>(i - m)] = 1;
  std::vector<int> read;
  for (int i = 1; i <= buffer; ++i)
    if (needed[static_cast<std::size_t>(i)]) read.push_back(i);
  return read;
}

// Jumps over steps out of the cut: there the state only evolves freely, so when no output in
// between is read (by a later step of this period or as a delayed sample of the next), k steps
// are one multiplication by e^{A₀kh}. At low radial immersion most of the period is skipped.
// Per step: the length of the jump that starts there (≥ 2), or 0.
std::vector<int> free_motion_jumps(int m, int p, const std::vector<char>& active,
                                   const std::vector<std::vector<int>>& delay_reads, const std::vector<int>& read) {
  std::vector<char> read_output(static_cast<std::size_t>(m + 1), 0);  // r_j = y_j, j = 0…m, is read
  for (int k = 0; k < m; ++k)
    if (active[static_cast<std::size_t>(k)]) {
      for (int j = std::max(0, k + 1 - p); j <= k; ++j) read_output[static_cast<std::size_t>(j)] = 1;
      for (int whole : delay_reads[static_cast<std::size_t>(k)])
        for (int o = 0; o <= p; ++o) {
          const int at = k + 1 - p + o - whole;
          if (at >= 0) read_output[static_cast<std::size_t>(at)] = 1;
        }
    }
  for (int i : read)
    if (i <= m) read_output[static_cast<std::size_t>(m - i)] = 1;
  std::vector<int> jump(static_cast<std::size_t>(m), 0);
  for (int k = 0; k < m;) {
    int len = 0;
    while (k + len < m && !active[static_cast<std::size_t>(k + len)] &&
           (len == 0 || !read_output[static_cast<std::size_t>(k + len)]))
      ++len;
    if (len >= 2) jump[static_cast<std::size_t>(k)] = len;
    k += std::max(len, 1);
  }
  return jump;
}

}  // namespace

PeriodMap::PeriodMap(const PeriodicDelaySystem& sys, int steps, int degree, Discretization scheme) {
  sys.check();
  const bool semi = scheme == Discretization::Semi;
  if (steps < 2 || steps > 100000) throw InvalidArgument(fmt::format("{} discretization steps per period: need 2…100000", steps));
  if (semi && (degree < 0 || degree > 1)) throw InvalidArgument(fmt::format("semi-discretization order {}: need 0 or 1", degree));
  if (!semi && (degree < 1 || degree > 3)) throw InvalidArgument(fmt::format("interpolation degree {}: need 1, 2 or 3", degree));
  if (steps < degree) throw InvalidArgument(fmt::format("{} steps are too few for degree {}", steps, degree));
  m_ = steps;
  // Semi-discretization reads the delayed outputs at the nodes of degree 1 (y_{k−i}, y_{k+1−i}):
  // the full-discretization set-up at p = 1 gives its buffer, active steps and jumps.
  p_ = semi ? 1 : degree;
  semi_order_ = degree;
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
  const DelaySteps delays = delay_steps(sys, h, m_);

  // The weights, step by step.
  active_.assign(static_cast<std::size_t>(m_), 0);
  wp_.resize(static_cast<std::size_t>(m_));
  wq_.resize(static_cast<std::size_t>(m_));
  cwp_.resize(static_cast<std::size_t>(m_));
  wd_.resize(static_cast<std::size_t>(m_));
  if (sys.forcing) wf_.assign(static_cast<std::size_t>(m_), Eigen::VectorXd::Zero(n_));
  StepQuadrature quad(sys, eig, block_start_, block_size_, rate, h, p_, delays);
  const int nd = n_ * d_;
  for (int k = 0; k < m_; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const bool any = quad.build(k, sys.forcing ? &wf_[kk] : nullptr);
    for (std::size_t j = 0; j < sys.delays.size(); ++j)
      if (quad.wd_any[j]) wd_[kk].push_back({delays.whole[j], quad.wd[j]});
    if (!any) continue;
    active_[kk] = 1;
    cwp_[kk] = c_ * Eigen::Map<const Eigen::MatrixXd>(quad.wp.data() + p_ * nd, n_, d_);
    wp_[kk] = quad.wp;
    wq_[kk] = quad.wq;
  }

  // The reduced state's buffer, then the free-motion jumps.
  std::vector<char> reads_period(static_cast<std::size_t>(m_));
  std::vector<std::vector<int>> delay_reads(static_cast<std::size_t>(m_));
  for (std::size_t k = 0; k < reads_period.size(); ++k) {
    reads_period[k] = regenerative_ || !wq_[k].empty();  // y(t − T) is read
    for (const DelayWeights& dw : wd_[k]) delay_reads[k].push_back(dw.whole_steps);
  }
  read_ = buffer_samples_read(m_, p_, active_, reads_period, delay_reads);
  slot_.assign(static_cast<std::size_t>(m_ + p_), -1);
  for (std::size_t r = 0; r < read_.size(); ++r) slot_[static_cast<std::size_t>(read_[r])] = n_ + d_ * static_cast<int>(r);
  jump_ = free_motion_jumps(m_, p_, active_, delay_reads, read_);
  jump_phi_.resize(static_cast<std::size_t>(m_));
  for (int k = 0; k < m_; ++k)
    if (jump_[static_cast<std::size_t>(k)] >= 2)
      for (const EigenBlock& b : eig) {
        const Eigen::MatrixXd e = block_exp(b, jump_[static_cast<std::size_t>(k)] * h);
        for (Eigen::Index r = 0; r < e.rows(); ++r)
          for (Eigen::Index c = 0; c < e.cols(); ++c) jump_phi_[static_cast<std::size_t>(k)].push_back(e(r, c));
      }
  if (semi) build_semi(sys, h, delays.whole, delays.fraction);
}

void PeriodMap::build_semi(const PeriodicDelaySystem& sys, double h, const std::vector<int>& whole_steps,
                           const std::vector<double>& fraction) {
  h_ = h;
  a0_ = Eigen::MatrixXd::Zero(n_, n_);
  for (std::size_t b = 0; b < sys.a0_blocks.size(); ++b)
    a0_.block(block_start_[b], block_start_[b], block_size_[b], block_size_[b]) = sys.a0_blocks[b];
  b_ = sys.input;
  semi_cache_ = std::make_shared<SemiCache>();
  std::vector<double> cuts = sys.breakpoints;
  std::sort(cuts.begin(), cuts.end());
  // (1/h)∫ f over step k: Gauss on each piece between breakpoints (f is smooth within a piece).
  Eigen::MatrixXd coef(d_, d_);
  auto average = [&](const std::function<void(double, Eigen::MatrixXd&)>& f, int k) {
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(d_, d_);
    const double t0 = k * h;
    std::vector<double> ends{t0};
    for (double t : cuts)
      if (t > t0 + 1e-12 * h && t < t0 + h - 1e-12 * h) ends.push_back(t);
    ends.push_back(t0 + h);
    for (std::size_t j = 0; j + 1 < ends.size(); ++j)
      for (int g = 0; g < kGauss; ++g) {
        coef.setZero();
        f(ends[j] + kGaussNode[g] * (ends[j + 1] - ends[j]), coef);
        sum += kGaussWeight[g] * (ends[j + 1] - ends[j]) * coef;
      }
    return Eigen::MatrixXd(sum / h);
  };
  semi_.assign(static_cast<std::size_t>(m_), SemiStep{});
  for (int k = 0; k < m_; ++k) {
    if (!active_[static_cast<std::size_t>(k)]) continue;
    SemiStep& st = semi_[static_cast<std::size_t>(k)];
    st.p = sys.current ? average(sys.current, k) : Eigen::MatrixXd::Zero(d_, d_);
    if (regenerative_) st.delays.push_back({m_, 0.0, -st.p});
    else if (sys.delayed) st.delays.push_back({m_, 0.0, average(sys.delayed, k)});
    for (std::size_t j = 0; j < sys.delays.size(); ++j) {
      Eigen::MatrixXd q = average(sys.delays[j].coefficient, k);
      if (!q.isZero(0.0)) st.delays.push_back({whole_steps[j], fraction[j], std::move(q)});
    }
  }
}

}  // namespace toolpoint
