// toolpoint: the step matrices of semi-discretization (periodic_delay.hpp, docs/reference.md §13)
// at a gain σ: per step in the cut e^{A_k h} and the delayed terms' weights, A_k = A₀ + σ B P̄_k C.
// Kept for the latest σ: the Arnoldi iteration applies the map tens of times at one σ.
// Units: time in s; the rest as the caller's.
#include <mutex>
#include <unsupported/Eigen/MatrixFunctions>

#include "toolpoint/stability/periodic_delay.hpp"

namespace toolpoint {

std::shared_ptr<const PeriodMap::SemiMatrices> PeriodMap::semi_matrices(double sigma) const {
  {
    const std::lock_guard<std::mutex> lock(semi_cache_->mutex);
    if (semi_cache_->latest && semi_cache_->latest->sigma == sigma) return semi_cache_->latest;
  }
  auto out = std::make_shared<SemiMatrices>();
  out->sigma = sigma;
  out->phi.resize(static_cast<std::size_t>(m_));
  out->w.resize(static_cast<std::size_t>(m_));
  const double h = h_;
  const int n = n_;
  // Van Loan: e^{M h} of M = [[A, I, 0], [0, 0, I], [0, 0, 0]] carries e^{Ah} | Γ₀ | Γ₁ in its first block row.
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  big.block(0, n, n, n).setIdentity();
  big.block(n, 2 * n, n, n).setIdentity();
  for (int k = 0; k < m_; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    if (!active_[kk]) continue;
    const SemiStep& st = semi_[kk];
    big.topLeftCorner(n, n) = a0_ + sigma * b_ * st.p * c_;
    const Eigen::MatrixXd e = (big * h).exp();
    out->phi[kk] = e.topLeftCorner(n, n);
    const Eigen::MatrixXd g0 = e.block(0, n, n, n), g1 = e.block(0, 2 * n, n, n);
    for (const SemiDelay& dl : st.delays) {
      const Eigen::MatrixXd bq = b_ * dl.q;
      const double f = dl.fraction;
      if (semi_order_ == 0) {
        out->w[kk].push_back((0.5 + f) * g0 * bq);
        out->w[kk].push_back((0.5 - f) * g0 * bq);
      } else {
        out->w[kk].push_back(((1.0 + f) * g0 - g1 / h) * bq);
        out->w[kk].push_back((g1 / h - f * g0) * bq);
      }
    }
  }
  const std::lock_guard<std::mutex> lock(semi_cache_->mutex);
  semi_cache_->latest = out;
  return out;
}

}  // namespace toolpoint
