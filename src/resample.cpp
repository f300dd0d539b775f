// toolpoint: cropping and interpolating FRFs onto another frequency grid (resample.hpp).
#include "toolpoint/measured/resample.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

void check_band(double low, double high) {
  if (!(std::isfinite(low) && std::isfinite(high) && low <= high))
    throw InvalidArgument(fmt::format("band {}–{} Hz: expected finite LOW ≤ HIGH", low, high), "e.g. 500:3000");
}

std::pair<std::size_t, std::size_t> kept_range(const std::vector<double>& f, double low, double high, const std::string& what) {
  check_band(low, high);
  const auto first = std::lower_bound(f.begin(), f.end(), low);
  const auto last = std::upper_bound(f.begin(), f.end(), high);
  if (first >= last)
    throw InputError(fmt::format("{}: no frequency in the band {}–{} Hz (the data cover {}–{} Hz)", what, low, high,
                                 f.empty() ? 0.0 : f.front(), f.empty() ? 0.0 : f.back()),
                     "choose a band inside the measured range");
  return {static_cast<std::size_t>(first - f.begin()), static_cast<std::size_t>(last - f.begin())};
}

void check_grid(const std::vector<double>& grid) {
  if (grid.empty()) throw InvalidArgument("the target frequency grid is empty");
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!std::isfinite(grid[i]))
      throw InvalidArgument(fmt::format("target frequency {} (point {}) is not finite", grid[i], i + 1));
    if (i > 0 && !(grid[i] > grid[i - 1]))
      throw InvalidArgument(
          fmt::format("target frequencies must increase strictly: {} Hz after {} Hz (point {})", grid[i], grid[i - 1], i + 1));
  }
}

// Interpolation only inside [f_first, f_last]: the first target outside it is an error.
void check_inside(const std::vector<double>& f, const std::vector<double>& grid, const std::string& what) {
  for (double x : grid)
    if (x < f.front() || x > f.back())
      throw InputError(fmt::format("{}: target frequency {} Hz lies outside the measured range {}–{} Hz; FRFs are "
                                   "interpolated, never extrapolated",
                                   what, x, f.front(), f.back()),
                       fmt::format("crop the target grid to the measured range (a band of at most {}:{})", f.front(), f.back()));
}

// Second derivatives of the natural cubic spline through (x_i, y_i): M_0 = M_{n−1} = 0 and, for
// 0 < i < n−1, h_{i−1} M_{i−1}/6 + (h_{i−1} + h_i) M_i/3 + h_i M_{i+1}/6
//   = (y_{i+1} − y_i)/h_i − (y_i − y_{i−1})/h_{i−1}, by the Thomas algorithm (the matrix is
// strictly diagonally dominant, so no pivoting is needed).
template <class T>
std::vector<T> spline_moments(const std::vector<double>& x, const std::vector<T>& y) {
  const std::size_t n = x.size();
  std::vector<T> m(n, T{});
  if (n < 3) return m;
  std::vector<double> diag(n), upper(n);
  std::vector<T> rhs(n);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    diag[i] = (h0 + h1) / 3.0;
    upper[i] = h1 / 6.0;
    rhs[i] = (y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0;
    if (i > 1) {  // eliminate the lower entry h0/6 with the previous row
      const double w = (h0 / 6.0) / diag[i - 1];
      diag[i] -= w * upper[i - 1];
      rhs[i] -= w * rhs[i - 1];
    }
  }
  for (std::size_t i = n - 2; i >= 1; --i) {
    m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
    if (i == 1) break;
  }
  return m;
}

// y at each of `grid` (inside [x_0, x_{n−1}], checked by the caller), by `method`.
template <class T>
std::vector<T> interpolate(const std::vector<double>& x, const std::vector<T>& y, const std::vector<double>& grid,
                           Interpolation method) {
  const std::vector<T> m = method == Interpolation::Cubic ? spline_moments(x, y) : std::vector<T>();
  std::vector<T> out;
  out.reserve(grid.size());
  std::size_t k = 0;  // both grids increase: one pass
  for (double g : grid) {
    while (k + 1 < x.size() && x[k + 1] <= g) ++k;
    if (x[k] == g || k + 1 == x.size()) {
      out.push_back(y[k]);  // a measured frequency: the measured value, exactly
      continue;
    }
    const double h = x[k + 1] - x[k], b = (g - x[k]) / h, a = 1.0 - b;
    T v = a * y[k] + b * y[k + 1];
    if (method == Interpolation::Cubic) v += ((a * a * a - a) * m[k] + (b * b * b - b) * m[k + 1]) * (h * h / 6.0);
    out.push_back(v);
  }
  return out;
}

template <class V>
V slice(const V& v, std::size_t begin, std::size_t end) {
  return V(v.begin() + static_cast<std::ptrdiff_t>(begin), v.begin() + static_cast<std::ptrdiff_t>(end));
}

}  // namespace

FrfSeries crop(const FrfSeries& s, double low, double high, const std::string& what) {
  const auto [b, e] = kept_range(s.frequency_hz, low, high, what);
  return {slice(s.frequency_hz, b, e), slice(s.values, b, e)};
}

BlockSeries crop(const BlockSeries& s, double low, double high, const std::string& what) {
  const auto [b, e] = kept_range(s.frequency_hz, low, high, what);
  return {slice(s.frequency_hz, b, e), slice(s.blocks, b, e)};
}

std::vector<double> crop_values(const std::vector<double>& f, const std::vector<double>& values, double low, double high) {
  if (values.empty()) return {};
  std::vector<double> out;
  for (std::size_t i = 0; i < f.size() && i < values.size(); ++i)
    if (f[i] >= low && f[i] <= high) out.push_back(values[i]);
  return out;
}

namespace {

// What every resampling checks first: a usable series with enough points for the method, a
// usable target grid, and every target inside the measured range.
template <class Series>
void check_resampling(const Series& s, const std::vector<double>& grid, Interpolation method, const std::string& what) {
  validate(s, what, method == Interpolation::Cubic ? 3 : 2);
  check_grid(grid);
  check_inside(s.frequency_hz, grid, what);
}

}  // namespace

FrfSeries resample(const FrfSeries& s, const std::vector<double>& grid, Interpolation method, const std::string& what) {
  check_resampling(s, grid, method, what);
  return {grid, interpolate(s.frequency_hz, s.values, grid, method)};
}

BlockSeries resample(const BlockSeries& s, const std::vector<double>& grid, Interpolation method, const std::string& what) {
  check_resampling(s, grid, method, what);
  BlockSeries out;
  out.frequency_hz = grid;
  out.blocks.assign(grid.size(), Block::Zero());
  for (int k = 0; k < 4; ++k) {
    const FrfSeries e = entry(s, k);
    const std::vector<Complex> v = interpolate(e.frequency_hz, e.values, grid, method);
    for (std::size_t i = 0; i < grid.size(); ++i) out.blocks[i](k / 2, k % 2) = v[i];
  }
  return out;
}

std::vector<double> resample_values(const std::vector<double>& f, const std::vector<double>& values,
                                    const std::vector<double>& grid, const std::string& what) {
  if (values.empty()) return {};
  if (values.size() != f.size()) throw InputError(fmt::format("{}: {} values for {} frequencies", what, values.size(), f.size()));
  check_grid(grid);
  check_inside(f, grid, what);
  return interpolate(f, values, grid, Interpolation::Linear);
}

const char* interpolation_name(Interpolation method) { return method == Interpolation::Cubic ? "cubic" : "linear"; }

}  // namespace toolpoint
