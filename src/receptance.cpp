// toolpoint: receptance series helpers.
#include "toolpoint/model/receptance.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

std::string format_complex(Complex z) { return fmt::format("{:.6g}{:+.6g}i", z.real(), z.imag()); }

std::string format_block(const Block& b) {
  return fmt::format("[[{}, {}], [{}, {}]]", format_complex(b(0, 0)), format_complex(b(0, 1)), format_complex(b(1, 0)),
                     format_complex(b(1, 1)));
}

FrfSeries entry(const BlockSeries& series, int index) {
  if (index < 0 || index > 3) throw InvalidArgument(fmt::format("block entry index {} outside 0..3", index));
  FrfSeries out;
  out.frequency_hz = series.frequency_hz;
  out.values.reserve(series.size());
  for (const Block& b : series.blocks) out.values.push_back(b(index / 2, index % 2));
  return out;
}

Block4 two_plane(const Block& forward, const Block& backward) {
  const Complex i(0.0, 1.0);
  const Block sum = 0.5 * (forward + backward), cross = (0.5 * i) * (forward - backward);
  Block4 b;
  b.topLeftCorner<2, 2>() = sum;
  b.bottomRightCorner<2, 2>() = sum;
  b.topRightCorner<2, 2>() = cross;
  b.bottomLeftCorner<2, 2>() = -cross;
  return b;
}

TwoPort4 two_plane(const TwoPort& forward, const TwoPort& backward) {
  return {two_plane(forward.b11, backward.b11), two_plane(forward.b12, backward.b12), two_plane(forward.b21, backward.b21),
          two_plane(forward.b22, backward.b22)};
}

Block4 two_plane(const Block& both) {
  Block4 b = Block4::Zero();
  b.topLeftCorner<2, 2>() = both;
  b.bottomRightCorner<2, 2>() = both;
  return b;
}

namespace {

void validate_grid(const std::vector<double>& f, const std::string& what, std::size_t min_points) {
  if (f.size() < min_points)
    throw InputError(fmt::format("{}: {} frequency point(s), at least {} needed", what, f.size(), min_points));
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!std::isfinite(f[i]) || f[i] <= 0.0)
      throw InputError(fmt::format("{}: frequency {} at point {} is not a positive finite value in Hz", what, f[i], i + 1),
                       "frequencies must be positive (Hz); drop the 0 Hz line of a measurement");
    if (i > 0 && !(f[i] > f[i - 1]))
      throw InputError(
          fmt::format("{}: frequencies not strictly increasing at point {} ({} Hz after {} Hz)", what, i + 1, f[i], f[i - 1]));
  }
}

bool finite(const Complex& z) { return std::isfinite(z.real()) && std::isfinite(z.imag()); }

}  // namespace

void validate(const BlockSeries& series, const std::string& what, std::size_t min_points) {
  if (series.blocks.size() != series.frequency_hz.size())
    throw InputError(fmt::format("{}: {} frequencies but {} blocks", what, series.frequency_hz.size(), series.blocks.size()));
  validate_grid(series.frequency_hz, what, min_points);
  static const char* names[] = {"H", "L", "N", "P"};
  for (std::size_t i = 0; i < series.size(); ++i)
    for (int k = 0; k < 4; ++k)
      if (!finite(series.blocks[i](k / 2, k % 2)))
        throw InputError(fmt::format("{}: {} at {} Hz (point {}) is not finite", what, names[k], series.frequency_hz[i], i + 1),
                         "remove or repair the NaN/Inf values in the data");
}

void validate(const FrfSeries& series, const std::string& what, std::size_t min_points) {
  if (series.values.size() != series.frequency_hz.size())
    throw InputError(fmt::format("{}: {} frequencies but {} values", what, series.frequency_hz.size(), series.values.size()));
  validate_grid(series.frequency_hz, what, min_points);
  for (std::size_t i = 0; i < series.size(); ++i)
    if (!finite(series.values[i]))
      throw InputError(fmt::format("{}: value at {} Hz (point {}) is not finite", what, series.frequency_hz[i], i + 1),
                       "remove or repair the NaN/Inf values in the data");
}

void require_not_mobility(const FrfSeries& s, const std::string& what) {
  double largest = 0.0;
  for (const Complex& v : s.values) largest = std::max(largest, std::abs(v));
  double n = 0.0, re_nonnegative = 0.0, im_positive = 0.0, im_negative = 0.0;  // counts of the points of |G| ≥ 1 % of the largest
  for (const Complex& v : s.values) {
    if (!(std::abs(v) >= 0.01 * largest)) continue;
    n += 1.0;
    re_nonnegative += v.real() >= 0.0 ? 1.0 : 0.0;
    im_positive += v.imag() > 0.0 ? 1.0 : 0.0;
    im_negative += v.imag() < 0.0 ? 1.0 : 0.0;
  }
  const double share = n;
  if (n < 5.0 || re_nonnegative < 0.95 * share || im_positive < 0.1 * share || im_negative < 0.1 * share) return;
  throw InputError(fmt::format("{}: Re G ≥ 0 at {:.0f} % of its points while Im G changes sign (> 0 at {:.0f} %, < 0 at "
                               "{:.0f} %): a point mobility [(m/s)/N], Re Y = −ω Im H ≥ 0, not a receptance [m/N], whose "
                               "Im is ≤ 0 at every frequency",
                               what, 100.0 * re_nonnegative / share, 100.0 * im_positive / share, 100.0 * im_negative / share),
                   "give the file's units so that it is converted (FrfReadOptions::units, e.g. m/s/N or mm/s/N), or its "
                   "ordinate (FrfReadOptions::ordinate mobility)");
}

namespace {

// Where the grid-mismatch error points: the library functions that do it (resample.hpp).
const char* const kOneGrid = "put them on one grid: resample() (interpolation) or crop() (cropping)";

}  // namespace

void require_same_grid(const std::vector<double>& a, const std::string& what_a, const std::vector<double>& b,
                       const std::string& what_b) {
  if (a.size() != b.size())
    throw InputError(fmt::format("frequency grids differ: {} has {} points, {} has {}", what_a, a.size(), what_b, b.size()),
                     kOneGrid);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::abs(a[i] - b[i]) > 1e-9 * std::max(std::abs(a[i]), std::abs(b[i])))
      throw InputError(fmt::format("frequency grids differ at point {}: {} has {} Hz, {} has {} Hz", i + 1, what_a, a[i], what_b,
                                   b[i]),
                       kOneGrid);
  }
}

}  // namespace toolpoint
