// toolpoint: shared statistical functions (statistics.hpp).
#include "toolpoint/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/error.hpp"

namespace toolpoint {

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw InvalidArgument(fmt::format("normal_quantile: p = {} must lie in (0, 1)", p));
  if (p < 0.5) return -normal_quantile(1.0 - p);
  if (p == 0.5) return 0.0;
  constexpr double pi = 3.14159265358979323846;
  double z = 2.0;
  for (int i = 0; i < 100; ++i) {
    const double tail = 0.5 * std::erfc(z / std::sqrt(2.0)), pdf = std::exp(-0.5 * z * z) / std::sqrt(2.0 * pi);
    const double dz = (tail - (1.0 - p)) / pdf;
    z += dz;
    if (std::abs(dz) < 1e-14 * std::max(1.0, std::abs(z))) break;
  }
  return z;
}

namespace {

// The regularised lower incomplete gamma P(a, x): its series for x < a + 1, else 1 − Q with Q's
// continued fraction by Lentz's method (Abramowitz & Stegun 6.5.29 and 6.5.31), to 1e-15.
double gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000 && std::abs(term) > 1e-16 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefactor);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

}  // namespace

double chi_square_quantile(double p, double dof) {
  if (!(dof > 0.0)) throw InvalidArgument(fmt::format("chi_square_quantile: {} degrees of freedom must be > 0", dof));
  if (!(p > 0.0 && p < 1.0)) throw InvalidArgument(fmt::format("chi_square_quantile: p = {} must lie in (0, 1)", p));
  if (dof == 1.0) {  // exact: the square of a normal
    const double z = normal_quantile(0.5 + 0.5 * p);
    return z * z;
  }
  if (dof == 2.0) return -2.0 * std::log1p(-p);  // exact: an exponential of mean 2
  // Wilson–Hilferty's cube as the start, then Newton on P(dof/2, x/2) = p (the density is
  // x^(k/2−1) e^(−x/2) / (2^(k/2) Γ(k/2))), safeguarded to stay positive.
  const double z = normal_quantile(p);
  const double a = 2.0 / (9.0 * dof);
  double x = std::max(1e-8, dof * std::pow(std::max(0.0, 1.0 - a + z * std::sqrt(a)), 3.0));
  const double k = 0.5 * dof;
  for (int it = 0; it < 50; ++it) {
    const double f = gamma_p(k, 0.5 * x) - p;
    const double density = std::exp((k - 1.0) * std::log(x) - 0.5 * x - k * std::log(2.0) - std::lgamma(k));
    if (!(density > 0.0)) break;
    double next = x - f / density;
    if (next <= 0.0) next = 0.5 * x;
    if (std::abs(next - x) < 1e-13 * x) {
      x = next;
      break;
    }
    x = next;
  }
  return x;
}

double quantile(std::vector<double> v, double p) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double h = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  if (v[lo] == v[hi]) return v[lo];  // also for ±inf, where the interpolation would give NaN
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

MeanSd mean_sd(const std::vector<double>& values) {
  MeanSd r;
  double sum = 0.0;
  for (double x : values)
    if (std::isfinite(x)) {
      sum += x;
      ++r.count;
    }
  if (r.count < 2) {
    r.mean = r.count ? sum : std::numeric_limits<double>::quiet_NaN();
    r.sd = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  r.mean = sum / static_cast<double>(r.count);
  double ss = 0.0;
  for (double x : values)
    if (std::isfinite(x)) ss += (x - r.mean) * (x - r.mean);
  r.sd = std::sqrt(ss / static_cast<double>(r.count - 1));
  return r;
}

}  // namespace toolpoint
