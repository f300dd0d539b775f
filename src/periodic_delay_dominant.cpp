// toolpoint: the dominant Floquet multiplier of a period map (periodic_delay.hpp): restarted
// Arnoldi on the map's product, or the dense eigen-decomposition for small maps.
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/stability/periodic_delay.hpp"

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
  const int nev = 4;
  const Eigen::VectorXd start = start_vector(n);
  // A map whose leading multipliers crowd together (process damping at low speed: the velocity
  // feedback pulls many of them to similar moduli) restarts a 20-vector space many times, each
  // restart ~16 map products: after two restarts a 40-vector space (one pass, ~40 products, in
  // the cases measured) takes over. Maps that converge within two restarts are unchanged.
  for (const auto& [ncv, restarts] : {std::pair{std::min(n - 1, 20), 2}, {std::min(n - 1, 40), 300}}) {
    Spectra::GenEigsSolver<Product> solver(op, nev, ncv);
    solver.init(start.data());
    solver.compute(Spectra::SortRule::LargestMagn, restarts, 1e-10, Spectra::SortRule::LargestMagn);
    if (solver.info() != Spectra::CompInfo::Successful) continue;
    const Eigen::VectorXcd values = solver.eigenvalues();
    const Eigen::Index k = dominant_index(values);
    out.krylov = true;
    return finish(values(k), vector ? Eigen::VectorXcd(solver.eigenvectors().col(k)) : Eigen::VectorXcd());
  }
  return dense();
}

}  // namespace toolpoint
