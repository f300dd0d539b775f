// toolpoint study: milling simulated in the time domain, one cut or a map (studies/simulation.hpp).
// Units: SI, rpm, Hz.
#include "toolpoint/studies/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "part_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {


bool has_source(const LobesInput& in) { return in.frfs || in.assembly || !in.x_modes.empty() || !in.y_modes.empty(); }

// The value of a series at the grid point nearest `f`.
Complex nearest(const FrfSeries& s, double f) {
  const auto it = std::lower_bound(s.frequency_hz.begin(), s.frequency_hz.end(), f);
  std::size_t i = static_cast<std::size_t>(it - s.frequency_hz.begin());
  if (i == s.size() || (i > 0 && f - s.frequency_hz[i - 1] < s.frequency_hz[i] - f)) --i;
  return s.values[i];
}

// x and y modes that are one mode of the tool seen in two directions, as the cross FRFs show: an x
// mode and a y mode whose frequencies lie within the wider half-power band, where the cross FRF
// G = ½(G_xy + G_yx) at the resonance is at least half of √|G_xx G_yy| (a mode's block is of rank
// one: |G_xy| = √(|G_xx||G_yy|)), become one planar mode ψ = (1/√m_x, ±1/√m_y), the sign that of
// −Im G (at resonance G_xy ≈ ψ_xψ_y/(2iζω²)), frequency and damping averaged. The rest stay along
// their axes.
ToolDynamics coupled_by_cross_frfs(const ModalModel& m, const MillingFrfs& frfs, std::vector<std::string>& warnings) {
  ToolDynamics d;
  std::vector<bool> used(m.y.size(), false);
  for (const Mode& x : m.x) {
    std::size_t best = m.y.size();
    for (std::size_t s = 0; s < m.y.size(); ++s) {
      const Mode& y = m.y[s];
      const double band = 2.0 * std::max(x.damping_ratio * x.frequency_hz, y.damping_ratio * y.frequency_hz);
      if (!used[s] && std::abs(x.frequency_hz - y.frequency_hz) <= band &&
          (best == m.y.size() || std::abs(y.frequency_hz - x.frequency_hz) < std::abs(m.y[best].frequency_hz - x.frequency_hz)))
        best = s;
    }
    if (best < m.y.size()) {
      const Mode& y = m.y[best];
      const double f = 0.5 * (x.frequency_hz + y.frequency_hz);
      const Complex gxy = 0.5 * (nearest(*frfs.xy, f) + nearest(*frfs.yx, f));
      const double direct = std::sqrt(std::abs(nearest(frfs.xx, f)) * std::abs(nearest(frfs.yy ? *frfs.yy : frfs.xx, f)));
      const double share = direct > 0.0 ? std::abs(gxy) / direct : 0.0;
      if (share >= 0.5) {
        used[best] = true;
        const double sign = gxy.imag() > 0.0 ? -1.0 : 1.0;
        d.modes.push_back(
            {f, 0.5 * (x.damping_ratio + y.damping_ratio), 1.0 / std::sqrt(x.mass_kg), sign / std::sqrt(y.mass_kg)});
        warnings.push_back(
            fmt::format("the x mode at {:.1f} Hz and the y mode at {:.1f} Hz are one mode coupling x and y "
                        "(|G_xy| is {:.0f} % of √|G_xx G_yy| there)",
                        x.frequency_hz, y.frequency_hz, 100.0 * share));
        continue;
      }
    }
    d.modes.push_back(planar_mode(x, 0.0));
  }
  for (std::size_t s = 0; s < m.y.size(); ++s)
    if (!used[s]) d.modes.push_back(planar_mode(m.y[s], kPi / 2));
  return d;
}

}  // namespace

ModalFitOptions simulation_fit_options() {
  ModalFitOptions o;
  o.max_modes = 8;
  return o;
}

ToolDynamics simulation_dynamics(const SimulationInput& input, const ModalFitOptions& fit, double fit_target,
                                 std::vector<ModalFitSummary>& fits, std::vector<std::string>& warnings) {
  ToolDynamics d;
  if (input.rigid) {
    if (has_source(input.source) || !input.planar_modes.empty())
      throw InvalidArgument("SimulationInput::rigid: a rigid tool has no modes, but modes or FRFs are given as well",
                            "drop the modes, or the rigid tool");
    return d;
  }
  if (!has_source(input.source) && input.planar_modes.empty())
    throw InvalidArgument(
        "the simulation needs the tool point dynamics: modes, a tool point FRF or an assembly "
        "(SimulationInput), or a rigid tool (SimulationInput::rigid)",
        "give the x modes, or the FRF to fit them from");
  if (has_source(input.source)) {
    // Fitted modes and cross FRFs: the FRF block says which modes couple x and y.
    const bool cross = input.source.frfs && input.source.frfs->xy && input.source.frfs->yx && input.source.x_modes.empty() &&
                       input.source.y_modes.empty() && !input.source.rigid_in_y();
    const ModalModel m = time_domain_modes(input.source, fit, fit_target, fits, warnings, cross);
    d = cross ? coupled_by_cross_frfs(m, *input.source.frfs, warnings) : tool_dynamics(m);
  }
  d.modes.insert(d.modes.end(), input.planar_modes.begin(), input.planar_modes.end());
  d.check();
  return d;
}

void SimulationStudyOptions::check() const {
  cutter.check();
  force.check();
  cut.check();
  simulation.check();
  fit.check();
  check_fields(simulation_study_fields(), *this, "SimulationStudyOptions");
}

const std::vector<OptionField<SimulationStudyOptions>>& simulation_study_fields() {
  using O = SimulationStudyOptions;
  static const std::vector<OptionField<O>> fields = {{fitted_modes_field("max_modes"), nullptr,
                                                      [](O& o) -> int& { return o.fit.max_modes; }},
                                                     {fitted_modes_field("fit_target"),
                                                      [](O& o) -> double& { return o.fit_target; }}};
  return fields;
}

SimulationStudyResult run_simulation_study(const SimulationInput& input, const SimulationStudyOptions& options,
                                           const ProgressCallback& progress) {
  options.check();
  SimulationStudyResult r;
  r.dynamics = simulation_dynamics(input, options.fit, options.fit_target, r.fits, r.warnings);
  r.cutter = options.cutter;
  r.force = options.force;
  r.cut = options.cut;
  r.simulation = simulate_milling(r.dynamics, options.cutter, options.force, options.cut, options.simulation, progress);
  r.warnings.insert(r.warnings.end(), r.simulation.warnings.begin(), r.simulation.warnings.end());
  return r;
}

// ---- The map ------------------------------------------------------------------------------------

void DepthRange::check() const {
  check_fields(depth_range_fields(), *this, "DepthRange");
  if (!(max_m > min_m))
    throw InvalidArgument(fmt::format("the depth range {}…{} m is empty (DepthRange::min_m and max_m must have min < max)",
                                      min_m, max_m));
}

const std::vector<OptionField<DepthRange>>& depth_range_fields() {
  using O = DepthRange;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "min_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "the shallowest axial depth",
        .plausible = &plausible::kDepth},
       [](O& o) -> double& { return o.min_m; }},
      {{.name = "max_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .min_open = true,
        .help = "the deepest axial depth",
        .plausible = &plausible::kDepth},
       [](O& o) -> double& { return o.max_m; }},
      {{.name = "points",
        .kind = FieldKind::Integer,
        .min = 2.0,
        .max = 100000.0,
        .help = "depths on the grid, both ends included",
        .cli_name = "depths"},
       nullptr,
       [](O& o) -> int& { return o.points; }}};
  return fields;
}

std::vector<double> DepthRange::values() const {
  std::vector<double> v;
  for (int i = 0; i < points; ++i) v.push_back(i + 1 == points ? max_m : min_m + (max_m - min_m) * i / (points - 1));
  return v;
}

void SimulatedMapOptions::check() const {
  cutter.check();
  force.check();
  cut.engagement.check();
  check_field(option_field(milling_cut_fields(), "feed_per_tooth_m").spec, cut.feed_per_tooth_m, "MillingCut");
  simulation.check();
  speeds.check();
  depths.check();
  parallel.check();
  if (cutter.flute_length_m > 0.0 && depths.max_m > cutter.flute_length_m)
    throw InvalidArgument(
        fmt::format("SimulatedMapOptions::depths reach {} m, beyond the flute length Cutter::flute_length_m = {} m", depths.max_m,
                    cutter.flute_length_m),
        "map depths up to the flute length");
}

SimulatedMapHeader simulated_map_header(const ToolDynamics& dynamics, const SimulatedMapOptions& options) {
  dynamics.check();
  options.check();
  SimulatedMapHeader h;
  h.dynamics = dynamics;
  h.options = options;
  h.options.simulation.record = false;
  h.options.parallel = {};
  h.speeds_rpm = options.speeds.values();
  h.depths_m = options.depths.values();
  h.fingerprint = simulated_map_fingerprint(h);
  return h;
}

std::uint64_t simulated_map_fingerprint(const SimulatedMapHeader& h) {
  part_file::Fnv1a f;
  f.add(std::string("toolpoint simulated map 2"));
  f.add(static_cast<std::uint64_t>(h.dynamics.modes.size()));
  for (const PlanarMode& m : h.dynamics.modes) {
    f.add(m.frequency_hz);
    f.add(m.damping_ratio);
    f.add(m.shape_x);
    f.add(m.shape_y);
  }
  const SimulatedMapOptions& o = h.options;
  f.add(o.cutter.diameter_m);
  f.add(o.cutter.pitch_rad);
  f.add(o.cutter.helix_rad);
  f.add(o.cutter.tooth_helix_rad);
  f.add(o.cutter.runout_m);
  f.add(o.cutter.flute_length_m);
  const ForceLaw& l = o.force;
  for (double x : {l.tangential_coefficient, l.radial_ratio, l.tangential_edge, l.radial_edge, l.exponent, l.reference_chip_m,
                   l.process_damping_n_per_m})
    f.add(x);
  f.add(o.cut.feed_per_tooth_m);
  f.add(o.cut.engagement.entry_rad);
  f.add(o.cut.engagement.exit_rad);
  const SimulationOptions& s = o.simulation;
  part_file::add_fields(f, simulation_fields(), s);
  f.add(s.initial_state);
  f.add(h.speeds_rpm);
  f.add(h.depths_m);
  return f.h;
}

namespace {

// One speed's row: each depth's simulation (its cells computed by the caller, possibly in parallel).
SimulatedMapRow empty_row(std::size_t speed_index, std::size_t depths) {
  SimulatedMapRow r;
  r.speed_index = speed_index;
  r.stable.assign(depths, 0);
  for (auto* v : {&r.growth, &r.chatter_metric, &r.chatter_hz, &r.sle_m, &r.peak_force_n, &r.out_of_cut_fraction})
    v->assign(depths, kNaN);
  return r;
}

void simulate_cell(const SimulatedMapHeader& h, SimulatedMapRow& row, std::size_t d) {
  MillingCut cut = h.options.cut;
  cut.speed_rpm = h.speeds_rpm[row.speed_index];
  cut.depth_m = h.depths_m[d];
  try {
    const SimulationResult s = simulate_milling(h.dynamics, h.options.cutter, h.options.force, cut, h.options.simulation);
    row.stable[d] = s.stable ? 1 : 0;
    row.growth[d] = s.growth;
    row.chatter_metric[d] = s.chatter_metric;
    row.chatter_hz[d] = s.chatter_hz;
    row.sle_m[d] = s.sle_m;
    row.peak_force_n[d] = s.peak_force_n;
    row.out_of_cut_fraction[d] = s.out_of_cut_fraction;
  } catch (const NumericalError&) {  // the motion overflowed: violently unstable
    row.stable[d] = 0;
    row.growth[d] = kInf;
  }
}

SimulatedMap assemble(SimulatedMapHeader h, std::vector<SimulatedMapRow> rows) {
  SimulatedMap m;
  m.header = std::move(h);
  m.rows = std::move(rows);
  std::size_t never = 0;
  for (const SimulatedMapRow& r : m.rows) {
    EnvelopePoint e;
    e.speed_rpm = m.header.speeds_rpm[r.speed_index];
    e.depth_m = kInf;
    e.chatter_hz = kNaN;
    for (std::size_t d = 0; d < r.stable.size(); ++d)
      if (!r.stable[d]) {
        e.depth_m = m.header.depths_m[d];
        e.chatter_hz = r.chatter_hz[d];
        break;
      }
    never += !std::isfinite(e.depth_m);
    m.boundary.push_back(e);
  }
  if (never > 0)
    m.warnings.push_back(
        fmt::format("{} of {} speeds are stable at every depth up to {:.4g} mm: the map's depths end below "
                    "their limit",
                    never, m.rows.size(), 1e3 * m.header.depths_m.back()));
  return m;
}

}  // namespace

SimulatedMapPart run_simulated_map_part(const ToolDynamics& dynamics, const SimulatedMapOptions& options, int index, int count,
                                        const ProgressCallback& progress) {
  check_shard({index, count});
  SimulatedMapPart part;
  part.header = simulated_map_header(dynamics, options);
  part.index = index;
  part.count = count;
  const SimulatedMapHeader& h = part.header;
  const std::vector<std::size_t> mine = shard_jobs(h.speeds_rpm.size(), {index, count});
  const std::size_t nd = h.depths_m.size();
  for (std::size_t i : mine) part.rows.push_back(empty_row(i, nd));
  // Cells, not speeds, in parallel: a shard of one speed still uses every core. Each cell writes its
  // own slot, so the result does not depend on the thread count.
  parallel_for(
      part.rows.size() * nd, options.parallel, [&](std::size_t c) { simulate_cell(h, part.rows[c / nd], c % nd); }, progress);
  return part;
}

SimulatedMap run_simulated_map(const ToolDynamics& dynamics, const SimulatedMapOptions& options,
                               const ProgressCallback& progress) {
  SimulatedMapPart p = run_simulated_map_part(dynamics, options, 0, 1, progress);
  return assemble(std::move(p.header), std::move(p.rows));
}

SimulatedMap merge_simulated_map_parts(const std::vector<SimulatedMapPart>& parts, const std::vector<std::string>& sources) {
  const std::size_t n = parts.empty() ? 0 : parts.front().header.speeds_rpm.size();
  std::vector<SimulatedMapRow> rows = part_file::merged_jobs(
      parts, sources, "map", "run_simulated_map_part", n,
      [](const SimulatedMapPart& p) -> const std::vector<SimulatedMapRow>& { return p.rows; },
      [](const SimulatedMapRow& r, const std::string&) { return r.speed_index; });
  return assemble(parts.front().header, std::move(rows));
}

}  // namespace toolpoint
