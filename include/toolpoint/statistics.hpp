// toolpoint: the few statistical functions the estimators and tests share.
#pragma once

#include <vector>

namespace toolpoint {

// The standard normal quantile Φ⁻¹(p) for p in (0, 1), by Newton's method on erfc (to ~1e-12).
// Throws InvalidArgument outside (0, 1).
double normal_quantile(double p);

// The quantile of χ² with `dof` degrees of freedom at p in (0, 1): exact for 1 and 2 degrees
// (a squared normal, an exponential), else Newton on the regularised incomplete gamma from the
// Wilson–Hilferty cube (to 1e-12 relative). Throws InvalidArgument for dof ≤ 0 or p outside (0, 1).
double chi_square_quantile(double p, double dof);

// The type-7 quantile at level p in [0, 1] of `values` (numpy's default; sorted here; NaN values
// are left out; NaN when none is left).
double quantile(std::vector<double> values, double p);

// The mean and the sample standard deviation (n − 1) of the finite values (NaN when fewer than two).
struct MeanSd {
  double mean = 0.0, sd = 0.0;
  std::size_t count = 0;
};
MeanSd mean_sd(const std::vector<double>& values);

}  // namespace toolpoint
