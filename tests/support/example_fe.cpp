// Test oracle: the example assembly as a finite-element model (example_fe.hpp).
#include "support/example_fe.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace toolpoint::test {

namespace {

Annulus ring(double D, double d, const Material& m) { return Annulus{D, d, m, std::nullopt}; }

fe_oracle::FeSegment fe_segment(double len, const std::vector<Annulus>& layers, double element_length) {
  Segment s;
  s.length = len;
  s.layers = layers;
  const SectionProperties p = s.properties();
  return fe_oracle::FeSegment{len, p.EI, p.kGA, p.rhoA, p.rhoI, std::max(1, static_cast<int>(std::ceil(len / element_length)))};
}

struct Section {
  double length;
  std::vector<Annulus> layers;
};

// A chain given by its sections from the outer end (the tip) inwards, cut also at `stations`
// (distances from the tip), added to `fem` in increasing x (inner end first). Returns the chain
// and the node at each station.
std::pair<fe_oracle::Chain, std::vector<int>> add_chain_from_tip(fe_oracle::FeModel& fem, const std::vector<Section>& from_tip,
                                                                 const std::vector<double>& stations, double h) {
  constexpr double eps = 1e-12;
  std::vector<double> cuts{0.0};
  for (const Section& s : from_tip) cuts.push_back(cuts.back() + s.length);
  const double total = cuts.back();
  for (double d : stations) {
    if (!(d >= -eps && d <= total + eps)) throw std::invalid_argument("station outside the chain");
    cuts.push_back(std::clamp(d, 0.0, total));
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(), [&](double a, double b) { return std::abs(a - b) < eps; }), cuts.end());
  std::vector<fe_oracle::FeSegment> segments;  // inner end first
  for (std::size_t k = cuts.size() - 1; k-- > 0;) {
    const double mid = 0.5 * (cuts[k] + cuts[k + 1]);
    double start = 0.0;
    for (const Section& s : from_tip) {
      if (mid < start + s.length) {
        segments.push_back(fe_segment(cuts[k + 1] - cuts[k], s.layers, h));
        break;
      }
      start += s.length;
    }
  }
  const fe_oracle::Chain chain = fem.add_chain(segments);
  std::vector<int> nodes;
  for (double d : stations) {
    // cuts[k] from the tip is node (cuts.size() − 1 − k) counted from the inner end.
    const auto k = static_cast<std::size_t>(
        std::min_element(cuts.begin(), cuts.end(), [&](double a, double b) { return std::abs(a - d) < std::abs(b - d); }) -
        cuts.begin());
    nodes.push_back(chain.nodes[cuts.size() - 1 - k]);
  }
  return {chain, nodes};
}

void add_joint(fe_oracle::FeModel& fem, int outer_end2, int inner_end1, const JointParameters& p) {
  Eigen::Matrix2cd K;
  K << p.k_yf, p.k_ym, p.k_tf, p.k_tm;
  Eigen::Matrix2d C;
  C << p.c_yf, p.c_ym, p.c_tf, p.c_tm;
  fem.add_joint(outer_end2, inner_end1, K, C);
}

}  // namespace

ExampleFe build_example_fe(fe_oracle::FeModel& fem, const Assembly& a, const ExampleFeOptions& o) {
  const Material st = a.holder.front().layers.front().material, cb = a.tool.material;
  const double h = o.element_length;
  ExampleFe out;
  // Spindle, from the nose inwards (0.485 m), cut at the bearings 0.080, 0.120, 0.355, 0.395 m.
  const std::vector<double> bearings = {0.080, 0.120, 0.355, 0.395};
  auto [spindle, bearing_nodes] = add_chain_from_tip(fem,
                                                     {{0.065, {ring(0.090, 0.010, st)}},
                                                      {0.070, {ring(0.070, 0.030, st)}},
                                                      {0.200, {ring(0.070, 0.025, st)}},
                                                      {0.070, {ring(0.055, 0.025, st)}},
                                                      {0.080, {ring(0.045, 0.020, st)}}},
                                                     bearings, h);
  out.spindle = spindle;
  for (const Bearing& b : a.spindle.bearings) {
    const auto k = std::find_if(bearings.begin(), bearings.end(), [&](double x) { return std::abs(x - b.position) < 1e-12; });
    if (k == bearings.end()) throw std::invalid_argument("bearing position not in the typed-in example geometry");
    fem.add_ground_spring(bearing_nodes[static_cast<std::size_t>(k - bearings.begin())], b.stiffness, b.rotational_stiffness,
                          b.damping, b.rotational_damping);
  }
  // Holder from its tip inwards; the shank fills the bore over the outer 74 mm.
  std::tie(out.holder, out.holder_stations) = add_chain_from_tip(fem,
                                                                 {{0.040, {ring(0.032, 0.016, st), ring(0.016, 0.0, cb)}},
                                                                  {0.030, {ring(0.044, 0.016, st), ring(0.016, 0.0, cb)}},
                                                                  {0.004, {ring(0.063, 0.016, st), ring(0.016, 0.0, cb)}},
                                                                  {0.012, {ring(0.063, 0.016, st)}}},
                                                                 o.holder_stations_m, h);
  add_joint(fem, out.holder.first(), out.spindle.last(), a.spindle_holder.parameters);
  if (!o.with_tool) {
    if (!o.tool_stations_m.empty()) throw std::invalid_argument("tool stations without the tool");
    return out;
  }
  // Tool outside the holder, from its tip: 32 mm fluted (0.8 × 16 mm), then 17 mm of shank.
  std::tie(out.tool, out.tool_stations) = add_chain_from_tip(fem,
                                                             {{0.032, {ring(0.0128, 0.0, cb)}}, {0.017, {ring(0.016, 0.0, cb)}}},
                                                             o.tool_stations_m, h);
  add_joint(fem, out.tool.first(), out.holder.last(), a.holder_tool.parameters);
  return out;
}

}  // namespace toolpoint::test
