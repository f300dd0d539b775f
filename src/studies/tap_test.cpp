// toolpoint: the virtual tap test (studies/tap_test.hpp).
#include "toolpoint/studies/tap_test.hpp"

#include "toolpoint/measured/noise.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/error.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint {

const char* tap_side_name(TapSide side) { return side == TapSide::Tool ? "tool" : "holder"; }
const char* hammer_plan_name(HammerPlan plan) { return plan == HammerPlan::Roving ? "roving" : "tip"; }

void TapTestOptions::check() const { check_fields(tap_test_fields(), *this, "TapTestOptions"); }

const std::vector<OptionField<TapTestOptions>>& tap_test_fields() {
  using O = TapTestOptions;
  using K = FieldKind;
  // The noise beyond σ is the measured-noise model's (NoiseOptions): its range, in a tap test's words.
  const auto noise = [](const char* name, const char* help) { return with_help(option_field(noise_fields(), name).spec, help); };
  static const std::vector<OptionField<O>> fields = {
      {{.name = "spacing_m",
        .kind = K::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "distance s between neighbouring points (0.01 for 10 mm); (points − 1)·s must fit on the tool's overhang "
                "or the holder",
        .cli_name = "spacing"},
       [](O& o) -> double& { return o.spacing_m; }},
      {{.name = "points",
        .kind = K::Integer,
        .min = 2.0,
        .max = 3.0,
        .help = "measurement points: 2 (first-order differences) or 3 (second order)",
        .cli_name = "points"},
       nullptr,
       [](O& o) -> int& { return o.points; }},
      {{.name = "sigma",
        .kind = K::Real,
        .min = 0.0,
        .max = 1.0,
        .max_open = true,
        .note = "0: exact",
        .help = "multiplicative noise on each FRF, standard deviation (0.02 = 2 %)",
        .cli_name = "sigma"},
       [](O& o) -> double& { return o.sigma; }},
      {noise("floor", "additive noise floor: σ of the real and imaginary parts relative to each FRF's peak |H| (0.01 = 1 %)"),
       [](O& o) -> double& { return o.floor; }},
      {noise("averages",
             "hits averaged per FRF (each varying by sigma in magnitude and phase, with the floor); each FRF's "
             "coherence is given"),
       nullptr, [](O& o) -> int& { return o.averages; }},
      {noise("calibration", "σ of one calibration factor scaling every FRF of the test (one hammer, one sensor; 0.02 = 2 %)"),
       [](O& o) -> double& { return o.calibration; }}};
  return fields;
}

TapTest run_tap_test_study(const Assembly& assembly, const TapTestOptions& options, const ProgressCallback& progress) {
  options.check();
  const AssemblyModel model(assembly);
  const bool tool = options.side == TapSide::Tool;
  const Chain& chain = tool ? model.tool_chain() : model.holder_chain();
  TapTest t;
  t.side = options.side;
  for (int i = 0; i < options.points; ++i) t.distance_m.push_back(i * options.spacing_m);
  const double reach = t.distance_m.back();
  if (reach > chain.length() * (1.0 + 1e-12))
    throw InvalidArgument(
        fmt::format("TapTestOptions::spacing_m = {} m puts point {} {} m from the {} tip, beyond the {} ({} m long)",
                    options.spacing_m, options.points - 1, reach, tap_side_name(options.side),
                    tool ? "tool's overhang" : "holder", chain.length()),
        fmt::format("space the points closer: at most {:g} m (in metres: 10 mm is 0.01)", chain.length() / (options.points - 1)));
  t.warnings = model.warnings();

  // One station solve per frequency gives every H_ij.
  const std::vector<double> f = assembly.grid.values();
  const auto n = static_cast<std::size_t>(options.points);
  std::vector<std::vector<FrfSeries>> h(n, std::vector<FrfSeries>(n));
  for (auto& row : h)
    for (FrfSeries& s : row) {
      s.frequency_hz = f;
      s.values.reserve(f.size());
    }
  for (std::size_t k = 0; k < f.size(); ++k) {
    const Eigen::MatrixXcd G = tool ? model.tool_stations(f[k], t.distance_m) : model.holder_stations(f[k], t.distance_m);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        h[i][j].values.push_back(G(2 * static_cast<Eigen::Index>(i), 2 * static_cast<Eigen::Index>(j)));
    if (progress && ((k + 1) % 64 == 0 || k + 1 == f.size()))
      progress(static_cast<double>(k + 1) / static_cast<double>(f.size()));
  }

  const std::size_t hammers = options.hammer == HammerPlan::Tip ? 1 : n;
  std::uint64_t k = 0;
  for (std::size_t j = 0; j < hammers; ++j)
    for (std::size_t i = 0; i < n; ++i, ++k) {
      TapTestFrf r{static_cast<int>(i), static_cast<int>(j), std::move(h[i][j]), {}};
      if (options.sigma > 0.0 || options.floor > 0.0 || options.averages > 0) {
        auto noisy = add_measurement_noise(
            r.frf, NoiseOptions{.sigma = options.sigma, .seed = options.seed + k, .floor = options.floor, .averages = options.averages},
            fmt::format("H{}{}", i, j));
        r.frf = std::move(noisy.series);
        r.coherence = std::move(noisy.coherence);
        t.warnings.insert(t.warnings.end(), noisy.warnings.begin(), noisy.warnings.end());
      }
      t.frfs.push_back(std::move(r));
    }
  if (options.calibration > 0.0) {  // one sensor chain: one factor for every FRF of the test
    const double factor = 1.0 + options.calibration * standard_normals(1, stream_seed(options.seed, 0xCA11B7A7E))[0];
    for (TapTestFrf& r : t.frfs)
      for (Complex& v : r.frf.values) v *= factor;
  }

  // The sections under the points: what the finite differences' shear correction needs.
  const auto under = split_segments(chain.segments(), reach).first;
  t.shear_stiffness_n = std::numeric_limits<double>::infinity();
  for (const Segment& s : under) t.shear_stiffness_n = std::min(t.shear_stiffness_n, s.properties().kGA.real());
  t.crosses_step = under.size() > 1;
  return t;
}

}  // namespace toolpoint
