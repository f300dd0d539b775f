// toolpoint: peak picking on FRF magnitudes.
#include "toolpoint/measured/peaks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <fmt/format.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

void PeakOptions::check() const { check_fields(peak_fields(), *this, "PeakOptions"); }

const std::vector<OptionField<PeakOptions>>& peak_fields() {
  using O = PeakOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "min_prominence",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .max_open = true,
        .help = "fraction of its height a local maximum rises above the higher of its valleys to count as a peak (ripple "
                "and noise on a flank are not modes)",
        .cli_name = "prominence"},
       [](O& o) -> double& { return o.min_prominence; }}};
  return fields;
}

std::vector<Peak> find_peaks(const std::vector<double>& m, double min_prominence) {
  std::vector<Peak> out;
  const std::size_t n = m.size();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    if (!std::isfinite(m[i]) || !(m[i] > m[i - 1])) continue;
    std::size_t j = i;  // the end of a plateau
    while (j + 1 < n && m[j + 1] == m[i]) ++j;
    if (j + 1 >= n || !(m[j + 1] < m[i])) {  // rises again (or runs to the end): a shoulder
      i = j;
      continue;
    }
    // The valleys: the lowest value between the peak and the nearest higher point on each side
    // (or the end), NaN (a gap) skipped. A naive scan, as scipy's peak_prominences: long scans
    // happen only for the few tall peaks.
    double left = m[i], right = m[i];
    for (std::size_t k = i; k-- > 0 && !(m[k] > m[i]);)
      if (std::isfinite(m[k])) left = std::min(left, m[k]);
    for (std::size_t k = j + 1; k < n && !(m[k] > m[i]); ++k)
      if (std::isfinite(m[k])) right = std::min(right, m[k]);
    const double prom = (m[i] - std::max(left, right)) / m[i];
    if (prom >= min_prominence) {
      Peak p;
      p.index = (i + j) / 2;
      p.prominence = prom;
      p.magnitude = m[i];
      out.push_back(p);
    }
    i = j;
  }
  return out;
}

std::vector<Peak> find_peaks(const FrfSeries& frf, const PeakOptions& options) {
  options.check();
  std::vector<double> m(frf.size());
  for (std::size_t i = 0; i < frf.size(); ++i) m[i] = std::abs(frf.values[i]);
  std::vector<Peak> out = find_peaks(m, options.min_prominence);
  for (Peak& p : out) {
    const std::size_t i = p.index;
    // Parabola through (f, log m) at i−1, i, i+1 (non-uniform spacing allowed).
    const double x0 = frf.frequency_hz[i - 1], x1 = frf.frequency_hz[i], x2 = frf.frequency_hz[i + 1];
    const double y0 = std::log(m[i - 1]), y1 = std::log(m[i]), y2 = std::log(m[i + 1]);
    const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
    const double a = (d12 - d01) / (x2 - x0);
    if (a < 0.0) {
      const double b = d01 - a * (x0 + x1);
      const double xv = std::clamp(-b / (2.0 * a), x0, x2);
      p.frequency_hz = xv;
      p.magnitude = std::exp(y1 + d01 * (xv - x1) + a * (xv - x0) * (xv - x1));
    } else {
      p.frequency_hz = x1;
    }
  }
  return out;
}

std::vector<Peak> find_peaks(const FrfSeries& frf, const PeakOptions& options, const std::function<double(double)>& magnitude) {
  std::vector<Peak> peaks = find_peaks(frf, options);
  for (Peak& p : peaks) {
    const auto [f, m] = refine_peak(magnitude, frf.frequency_hz[p.index - 1], frf.frequency_hz[p.index + 1]);
    p.frequency_hz = f;
    p.magnitude = m;
  }
  return peaks;
}

std::vector<std::vector<double>> track_modes(const std::vector<std::vector<Peak>>& family, std::size_t reference,
                                             double tolerance, bool ordered) {
  if (reference >= family.size())
    throw InvalidArgument(fmt::format("mode tracking: reference member {} outside the {} FRFs", reference, family.size()));
  if (!(tolerance > 0.0 && tolerance < 1.0))
    throw InvalidArgument(fmt::format("mode tracking tolerance {} must lie in (0, 1)", tolerance));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t modes = family[reference].size(), n = family.size();
  std::vector<std::vector<double>> f(modes, std::vector<double>(n, nan));
  for (std::size_t m = 0; m < modes; ++m) f[m][reference] = family[reference][m].frequency_hz;
  // Walk away from the reference; `last[m]` is the frequency where mode m was last seen.
  for (int dir : {-1, 1}) {
    std::vector<double> last(modes);
    for (std::size_t m = 0; m < modes; ++m) last[m] = f[m][reference];
    for (std::ptrdiff_t k = static_cast<std::ptrdiff_t>(reference) + dir; k >= 0 && k < static_cast<std::ptrdiff_t>(n);
         k += dir) {
      const auto& peaks = family[static_cast<std::size_t>(k)];
      struct Pair {
        double d;
        std::size_t m, p;
      };
      std::vector<Pair> pairs;
      for (std::size_t m = 0; m < modes; ++m)
        for (std::size_t p = 0; p < peaks.size(); ++p) {
          const double d = std::abs(peaks[p].frequency_hz - last[m]) / last[m];
          if (d <= tolerance) pairs.push_back({d, m, p});
        }
      std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
      std::vector<bool> mode_used(modes, false), peak_used(peaks.size(), false);
      for (const Pair& q : pairs) {
        if (mode_used[q.m] || peak_used[q.p]) continue;
        mode_used[q.m] = peak_used[q.p] = true;
        f[q.m][static_cast<std::size_t>(k)] = peaks[q.p].frequency_hz;
        if (ordered) last[q.m] = peaks[q.p].frequency_hz;
      }
    }
  }
  return f;
}

std::pair<double, double> refine_peak(const std::function<double(double)>& magnitude, double lo, double hi) {
  if (!(lo > 0.0 && hi > lo)) throw InvalidArgument(fmt::format("peak bracket [{}, {}] Hz is not a valid interval", lo, hi));
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = lo, b = hi;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = magnitude(c), fd = magnitude(d);
  for (int it = 0; it < 200 && (b - a) > 1e-9 * b; ++it) {
    if (fc > fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = magnitude(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = magnitude(d);
    }
  }
  const double x = 0.5 * (a + b);
  return {x, magnitude(x)};
}

}  // namespace toolpoint
