// Model data for joint identification tests: the example assembly (or a variant with a stiff
// spindle–holder joint), the three identification routes, and the seed's multiplicative noise.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint::test {

inline Assembly example_assembly() {
  return load_assembly(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml").assembly;
}

// A spindle–holder joint 30× stiffer in k_yf than the example's holder–tool joint (the case
// issue 11 measured the closed form on: −24 % (Eq. 18) and −30 % (Eq. 15) in k_yf at 2 % noise).
inline JointParameters stiff_spindle_holder() {
  JointParameters p;
  p.k_yf = 1.26e9;
  p.c_yf = 1200.0;
  p.k_tm = 6.0e6;
  p.c_tm = 60.0;
  p.k_ym = p.k_tf = -2.0e7;
  p.c_ym = p.c_tf = -20.0;
  return p;
}

// What a route measures: the component A, the structure B11 it is joined to, the FRF G11 read.
struct RouteData {
  std::vector<double> f;
  std::vector<TwoPort> A;
  BlockSeries B, G;
  bool b_measured = true;  // holder–tool: SH11 is measured; spindle–holder: S11 from the model
  JointParameters truth;
};

inline RouteData route_data(const Assembly& a, Route route, const std::vector<double>& f) {
  const AssemblyModel m(a);
  RouteData d;
  d.f = f;
  for (double x : f)
    d.A.push_back(route == Route::HolderTool ? m.tool(x) : route == Route::SpindleHolderFromSH ? m.holder(x) : m.holder_tool(x));
  if (route == Route::HolderTool) {
    d.B = m.holder_tip(f);
    d.G = m.tool_point(f);
    d.truth = a.holder_tool.parameters;
  } else {
    d.B = block_series(f, [&](double x) { return m.spindle_nose(x); });
    d.G = route == Route::SpindleHolderFromSH ? m.holder_tip(f) : m.tool_point(f);
    d.b_measured = false;
    d.truth = a.spindle_holder.parameters;
  }
  return d;
}

enum class NoiseKnowledge { Estimated, Stated };

// The fit's input for one noise draw (the seed's multiplicative noise σ, seeds `seed` for G11 and
// `seed + 1` for B11 when measured). σ = 0: exact data.
inline JointFitData noisy_fit_data(const RouteData& d, double sigma, std::uint64_t seed,
                                   NoiseKnowledge knowledge = NoiseKnowledge::Estimated) {
  JointFitData x;
  x.label = "test";
  x.A = d.A;
  x.b_name = "B11";
  x.g_name = "G11";
  if (sigma == 0.0) {
    x.B11 = d.B;
    x.G11 = d.G;
    x.b_noise = x.g_noise = exact_block_noise();
    return x;
  }
  x.G11 = add_measurement_noise(d.G, NoiseOptions{sigma, seed}).series;
  x.B11 = d.b_measured ? add_measurement_noise(d.B, NoiseOptions{sigma, seed + 1}).series : d.B;
  auto noise = [&](const BlockSeries& s, bool measured) {
    if (!measured) return exact_block_noise();
    return knowledge == NoiseKnowledge::Stated ? stated_block_noise(s, StatedNoise{sigma, 0.0, 0.0}) : estimate_block_noise(s, {}, "test");
  };
  x.g_noise = noise(x.G11, true);
  x.b_noise = noise(x.B11, d.b_measured);
  return x;
}

// Starting values a fixed distance from the truth (10 % in stiffness, 30 % in damping; coupling
// terms from their natural scale when zero), as a poor closed-form read-out would give.
inline JointParameters offset_start(const JointParameters& t) {
  JointParameters s = t;
  for (int k = 0; k < 8; ++k) s[k] *= k % 2 ? 1.3 : 1.1;
  if (t.k_ym == 0.0) s.k_ym = s.k_tf = 0.05 * std::sqrt(std::abs(t.k_yf * t.k_tm));
  if (t.c_ym == 0.0) s.c_ym = s.c_tf = 0.05 * std::sqrt(std::abs(t.c_yf * t.c_tm));
  return s;
}

// A covariance of relative size `rel` on every parameter of p, with a correlation between k_yf
// and k_tm, for a reciprocal joint (k_tf ≡ k_ym, c_tf ≡ c_ym: perfectly correlated, singular).
inline Eigen::Matrix<double, 8, 8> covariance_of(const JointParameters& p, double rel) {
  Eigen::Matrix<double, 8, 8> c = Eigen::Matrix<double, 8, 8>::Zero();
  for (int k : {0, 1, 2, 3, 6, 7}) c(k, k) = std::pow(rel * p[k], 2);
  c(0, 6) = c(6, 0) = 0.5 * std::sqrt(c(0, 0) * c(6, 6));
  for (int k = 0; k < 8; ++k) {
    c(4, k) = c(k, 4) = c(2, k);
    c(5, k) = c(k, 5) = c(3, k);
  }
  c(4, 4) = c(2, 2);
  c(5, 5) = c(3, 3);
  c(4, 2) = c(2, 4) = c(2, 2);
  c(5, 3) = c(3, 5) = c(3, 3);
  return c;
}

// The seed's Table 1 joint with covariance_of(·, rel) as its [uncertainty], source "test".
inline JointFile uncertain_joint(double rel) {
  JointFile f;
  f.parameters = seed_table1_joint();
  JointUncertainty u;
  u.covariance = covariance_of(f.parameters, rel);
  f.uncertainty = u;
  f.source = "test";
  return f;
}

}  // namespace toolpoint::test
