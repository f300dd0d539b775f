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

double chi_square_quantile(double p, double dof) {
  if (!(dof > 0.0)) throw InvalidArgument(fmt::format("chi_square_quantile: {} degrees of freedom must be > 0", dof));
  const double z = normal_quantile(p);
  const double a = 2.0 / (9.0 * dof);
  return dof * std::pow(std::max(0.0, 1.0 - a + z * std::sqrt(a)), 3.0);
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
