// toolpoint: the period map of periodic_delay.hpp applied at a gain σ — the recursion over one
// period for one state (the Arnoldi iteration's product) or many at once (the dense map, the
// outputs), and the periodic solution of a forced system. Units: time in s; the rest as the caller's.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"

namespace toolpoint {

using Complex = std::complex<double>;

// Step k (in the cut) by semi-discretization for nc columns in run()'s layout (nc = 1: run_one's):
// z = e^{A_k h} y + σ Σ_j Σ_{o=0,1} W_jo y_{k+o−i_j} (periodic_delay.hpp), `sample(j)` the outputs y_j.
template <typename S, typename Sample>
void PeriodMap::semi_step(const SemiMatrices& sm, int k, double sigma, std::size_t nc, const S* y, S* z,
                          const Sample& sample) const {
  const int n = n_, d = d_;
  const auto kk = static_cast<std::size_t>(k);
  const Eigen::MatrixXd& ph = sm.phi[kk];
  for (int i = 0; i < n; ++i) {
    S* zi = z + i * nc;
    std::fill(zi, zi + nc, S(0.0));
    for (int j = 0; j < n; ++j) {
      const double e = ph(i, j);
      if (e == 0.0) continue;
      const S* yj = y + j * nc;
      for (std::size_t q = 0; q < nc; ++q) zi[q] += e * yj[q];
    }
  }
  const std::vector<SemiDelay>& dl = semi_[kk].delays;
  for (std::size_t j = 0; j < dl.size(); ++j)
    for (int o = 0; o <= 1; ++o) {
      const double* w = sm.w[kk][2 * j + static_cast<std::size_t>(o)].data();  // n × d, column-major
      const S* x = sample(k + o - dl[j].whole_steps);
      for (int c = 0; c < d; ++c)
        for (int i = 0; i < n; ++i) {
          const double wi = sigma * w[c * n + i];
          if (wi == 0.0) continue;
          S* zi = z + i * nc;
          const S* xc = x + c * nc;
          for (std::size_t q = 0; q < nc; ++q) zi[q] += wi * xc[q];
        }
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
  auto add = [&](const double* w, const S* x, double f) {  // z += f W x, W n × d column-major
    for (int c = 0; c < d; ++c) {
      const S xc = f * x[c];
      const double* col = w + c * n;
      for (int i = 0; i < n; ++i) z[static_cast<std::size_t>(i)] += col[i] * xc;
    }
  };
  const std::shared_ptr<const SemiMatrices> semi = semi_.empty() ? nullptr : semi_matrices(sigma);
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
    S* rk1 = r.data() + (k + 1) * d;
    if (semi && active_[kk]) {
      semi_step(*semi, k, sigma, 1, y.data(), z.data(), sample);
      outputs_of(z, rk1);
      y.swap(z);
      continue;
    }
    propagate(phi_.data());
    if (!active_[kk]) {
      y.swap(z);
      outputs_of(y, rk1);
      continue;
    }
    const double* wp = wp_[kk].data();
    const double* wq = regenerative_ || wq_[kk].empty() ? nullptr : wq_[kk].data();
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
        if (wq) add(wq + o * nd, del, sigma);
      }
      for (const DelayWeights& dw : wd_[kk]) add(dw.w.data() + o * nd, sample(cur - dw.whole_steps), sigma);
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
  const std::shared_ptr<const SemiMatrices> semi = semi_.empty() ? nullptr : semi_matrices(sigma);
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
    S* rk1 = r + static_cast<std::size_t>((k + 1) * d) * nc;
    if (semi && active_[kk]) {
      semi_step(*semi, k, sigma, nc, y, z, sample);
      outputs_of(z, rk1);
      std::swap(y, z);
      continue;
    }
    propagate(phi_.data());
    if (!active_[kk]) {
      std::swap(y, z);
      outputs_of(y, rk1);
      continue;
    }
    const double* wp = wp_[kk].data();
    const double* wq = regenerative_ || wq_[kk].empty() ? nullptr : wq_[kk].data();
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
        if (wq) add(wq + o * nd, del, sigma);
      }
      for (const DelayWeights& dw : wd_[kk]) add(dw.w.data() + o * nd, sample(cur - dw.whole_steps), sigma);
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
  if (!semi_.empty())
    throw InvalidArgument("PeriodMap::periodic_solution is not implemented for Discretization::Semi",
                          "build the map with Discretization::Full");
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

}  // namespace toolpoint
