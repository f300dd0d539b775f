// toolpoint: uncertainty results as tables and figure data (uncertainty_io.hpp).
// Units: Hz, m/N, degrees, rpm, mm.
#include "toolpoint/io/uncertainty_io.hpp"

#include <cmath>
#include <complex>
#include <fmt/format.h>

#include "toolpoint/conventions.hpp"

namespace toolpoint {

Table band_table(const FrfBand& b) {
  Table t;
  t.columns = {"frequency_hz"};
  for (double l : b.levels) t.columns.push_back(fmt::format("magnitude_q{:g}_m_per_n", 100 * l));
  for (double l : b.levels) t.columns.push_back(fmt::format("phase_q{:g}_deg", 100 * l));
  for (std::size_t i = 0; i < b.frequency_hz.size(); ++i) {
    std::vector<double> row{b.frequency_hz[i]};
    for (const auto& m : b.magnitude) row.push_back(m[i]);
    for (const auto& p : b.phase_rad) row.push_back(degrees_of(p[i]));
    t.rows.push_back(std::move(row));
  }
  return t;
}

std::vector<plot::FrfTrace> band_traces(const FrfBand& b) {
  std::vector<plot::FrfTrace> traces{{b.nominal, "identified joint", plot::CurveStyle::Line}};
  for (std::size_t l = 0; l < b.levels.size(); ++l) {
    if (std::abs(b.levels[l] - 0.5) < 1e-9) continue;
    FrfSeries q;
    q.frequency_hz = b.frequency_hz;
    for (std::size_t i = 0; i < b.frequency_hz.size(); ++i) q.values.push_back(std::polar(b.magnitude[l][i], b.phase_rad[l][i]));
    traces.push_back(
        {q, fmt::format("{:g} % quantile ({} joint samples)", 100 * b.levels[l], b.samples), plot::CurveStyle::Dashed});
  }
  return traces;
}

Table probability_table(const StabilityUncertainty& s) {
  Table t;
  t.columns = {"spindle_speed_rpm", "axial_depth_mm", "probability_stable"};
  for (std::size_t i = 0; i < s.speed_rpm.size(); ++i)
    for (std::size_t j = 0; j < s.depth_grid_m.size(); ++j)
      t.rows.push_back(
          {s.speed_rpm[i], 1e3 * s.depth_grid_m[j], s.probability(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j))});
  return t;
}

std::vector<plot::LobesFigureData::Envelope> quantile_envelopes(const StabilityUncertainty& s) {
  std::vector<plot::LobesFigureData::Envelope> e;
  for (std::size_t l = 0; l < s.levels.size(); ++l)
    // Short: the legend beside the lobes takes the panel's width (the count once, on the first).
    e.push_back({s.depth_m[l], fmt::format("stable in {:g} % of {}", 100 * (1.0 - s.levels[l]),
                                           l == 0 ? fmt::format("{} joints", s.samples) : std::string("them"))});
  return e;
}

plot::ProbabilityMapData probability_map(const StabilityUncertainty& s, const std::string& joint_source) {
  plot::ProbabilityMapData m;
  m.title = fmt::format("Probability of stability, the joint of {} uncertain ({} samples)", plot::literal(joint_source),
                        s.samples);
  const auto mm = [](const std::vector<double>& v) {
    std::vector<double> out;
    for (double a : v) out.push_back(1e3 * a);
    return out;
  };
  m.speed_rpm = s.speed_rpm;
  m.depth_mm = mm(s.depth_grid_m);
  for (std::size_t j = 0; j < s.depth_grid_m.size(); ++j)
    for (std::size_t i = 0; i < s.speed_rpm.size(); ++i)
      m.probability.push_back(s.probability(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
  m.envelopes.push_back({mm(s.nominal_depth_m), "nominal envelope"});
  if (!s.levels.empty())
    m.envelopes.push_back({mm(s.depth_m.front()), fmt::format("stable with {:g} % probability", 100 * (1.0 - s.levels.front()))});
  return m;
}

}  // namespace toolpoint
