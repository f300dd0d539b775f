// toolpoint study: the simulation's tables and the simulated map's part files (studies/simulation_io.hpp).
// Units: SI in the tables unless a column name says otherwise (rpm, mm, µm, degrees).
#include "toolpoint/studies/simulation_io.hpp"

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <nlohmann/json.hpp>

#include "part_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {

// Version 2: the envelope of part_file.hpp, as the plan's part (shard and study first, so a file
// cut short names its shard). Version 3: the simulation's scalar fields from their table.
constexpr part_file::PartKind kMapPart{"toolpoint simulated map part", 3, "run_simulated_map_part", "format_simulated_map_part"};

using part_file::hex;
using part_file::hexes;
using part_file::PartReader;

double finite_or_empty(double v) { return std::isfinite(v) ? v : kNaN; }

}  // namespace

Table simulation_history_table(const SimulationResult& s) {
  if (s.time_s.empty())
    throw InvalidArgument("the simulation kept no histories (SimulationOptions::record = false)",
                          "simulate with SimulationOptions::record = true");
  Table t;
  t.columns = {"time_s", "force_x_n", "force_y_n", "x_m", "y_m", "vx_m_per_s", "vy_m_per_s", "torque_nm"};
  for (std::size_t j = 0; j < s.tooth_force_n.size(); ++j) t.columns.push_back(fmt::format("tooth_{}_force_n", j));
  t.rows.reserve(s.time_s.size());
  for (std::size_t k = 0; k < s.time_s.size(); ++k) {
    std::vector<double> row{s.time_s[k], s.force_x_n[k],  s.force_y_n[k],  s.x_m[k],
                            s.y_m[k],    s.vx_m_per_s[k], s.vy_m_per_s[k], s.torque_nm[k]};
    for (const auto& f : s.tooth_force_n) row.push_back(f[k]);
    t.rows.push_back(std::move(row));
  }
  return t;
}

Table simulation_samples_table(const SimulationResult& s) {
  Table t;
  t.columns = {"kind", "time_s", "tooth", "x_m", "y_m", "vx_m_per_s", "vy_m_per_s"};
  t.may_be_empty = {"tooth"};
  for (int kind = 0; kind < 2; ++kind)
    for (const MotionSample& m : kind == 0 ? s.per_revolution : s.per_tooth)
      t.rows.push_back({static_cast<double>(kind), m.time_s, kind == 0 ? kNaN : static_cast<double>(m.tooth), m.x_m, m.y_m,
                        m.vx_m_per_s, m.vy_m_per_s});
  return t;
}

Table simulation_wall_table(const SimulationResult& s) {
  Table t;
  t.columns = {"wall_angle_deg", "slice", "height_m", "sle_m"};
  t.may_be_empty = {"sle_m"};
  for (const Wall& w : s.walls)
    for (std::size_t l = 0; l < w.sle_m.size(); ++l)
      t.rows.push_back({degrees_of(w.angle_rad), static_cast<double>(l), w.slice_height_m[l], finite_or_empty(w.sle_m[l])});
  return t;
}

Table simulated_map_table(const SimulatedMap& m) {
  Table t;
  t.columns = {"spindle_speed_rpm",    "axial_depth_mm", "stable",       "growth_per_revolution", "chatter_metric",
               "chatter_frequency_hz", "sle_um",         "peak_force_n", "out_of_cut_fraction"};
  t.may_be_empty = {"growth_per_revolution", "chatter_metric",     "chatter_frequency_hz", "sle_um",
                    "peak_force_n",          "out_of_cut_fraction"};
  for (const SimulatedMapRow& r : m.rows)
    for (std::size_t d = 0; d < r.stable.size(); ++d)
      t.rows.push_back({m.header.speeds_rpm[r.speed_index], 1e3 * m.header.depths_m[d], static_cast<double>(r.stable[d]),
                        finite_or_empty(r.growth[d]), finite_or_empty(r.chatter_metric[d]), finite_or_empty(r.chatter_hz[d]),
                        finite_or_empty(1e6 * r.sle_m[d]), finite_or_empty(r.peak_force_n[d]),
                        finite_or_empty(r.out_of_cut_fraction[d])});
  return t;
}

// ---- Part files ----------------------------------------------------------------------------------

namespace {

nlohmann::json header_json(const SimulatedMapHeader& h) {
  nlohmann::json modes = nlohmann::json::array();
  for (const PlanarMode& m : h.dynamics.modes)
    modes.push_back({hex(m.frequency_hz), hex(m.damping_ratio), hex(m.shape_x), hex(m.shape_y)});
  const SimulatedMapOptions& o = h.options;
  const SimulationOptions& s = o.simulation;
  // The simulation's scalar fields from their table (option_fields.hpp), the rest by hand.
  nlohmann::json simulation = fields_json(simulation_fields(), s, part_file::hex_json);
  simulation["initial_state"] = hexes(s.initial_state);
  simulation["memory_limit_bytes"] = hex(s.memory_limit_bytes);
  return {{"modes", modes},
          {"cutter",
           {{"diameter_m", hex(o.cutter.diameter_m)},
            {"pitch_rad", hexes(o.cutter.pitch_rad)},
            {"helix_rad", hex(o.cutter.helix_rad)},
            {"tooth_helix_rad", hexes(o.cutter.tooth_helix_rad)},
            {"runout_m", hexes(o.cutter.runout_m)},
            {"flute_length_m", hex(o.cutter.flute_length_m)}}},
          {"force", fields_json(force_law_fields(), o.force, part_file::hex_json)},
          {"cut",
           {{"feed_per_tooth_m", hex(o.cut.feed_per_tooth_m)},
            {"entry_rad", hex(o.cut.engagement.entry_rad)},
            {"exit_rad", hex(o.cut.engagement.exit_rad)}}},
          {"simulation", simulation},
          {"speeds", fields_json(speed_range_fields(), o.speeds, part_file::hex_json)},
          {"depths", fields_json(depth_range_fields(), o.depths, part_file::hex_json)}};
}

SimulatedMapHeader parse_header(const PartReader& r, const nlohmann::json& j) {
  SimulatedMapHeader h;
  const nlohmann::json& modes = r.at(j, "modes", "");
  if (!modes.is_array()) r.fail("'modes' is not an array");
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::string p = fmt::format("modes[{}]", i);
    if (!modes[i].is_array() || modes[i].size() != 4) r.fail(p + " is not [frequency, damping, shape x, shape y]");
    h.dynamics.modes.push_back(
        {r.number(modes[i][0], p), r.number(modes[i][1], p), r.number(modes[i][2], p), r.number(modes[i][3], p)});
  }
  SimulatedMapOptions& o = h.options;
  const nlohmann::json& c = r.at(j, "cutter", "");
  o.cutter.diameter_m = r.number(c, "diameter_m", "cutter.");
  o.cutter.pitch_rad = r.numbers(c, "pitch_rad", "cutter.");
  o.cutter.helix_rad = r.number(c, "helix_rad", "cutter.");
  o.cutter.tooth_helix_rad = r.numbers(c, "tooth_helix_rad", "cutter.");
  o.cutter.runout_m = r.numbers(c, "runout_m", "cutter.");
  o.cutter.flute_length_m = r.number(c, "flute_length_m", "cutter.");
  const nlohmann::json& f = r.at(j, "force", "");
  part_file::read_fields(r, f, "force.", force_law_fields(), o.force);
  const nlohmann::json& cut = r.at(j, "cut", "");
  o.cut.feed_per_tooth_m = r.number(cut, "feed_per_tooth_m", "cut.");
  o.cut.engagement.entry_rad = r.number(cut, "entry_rad", "cut.");
  o.cut.engagement.exit_rad = r.number(cut, "exit_rad", "cut.");
  const nlohmann::json& s = r.at(j, "simulation", "");
  part_file::read_fields(r, s, "simulation.", simulation_fields(), o.simulation);
  o.simulation.initial_state = r.numbers(s, "initial_state", "simulation.");
  o.simulation.memory_limit_bytes = r.number(s, "memory_limit_bytes", "simulation.");
  o.simulation.record = false;
  const nlohmann::json& sp = r.at(j, "speeds", "");
  part_file::read_fields(r, sp, "speeds.", speed_range_fields(), o.speeds);
  const nlohmann::json& dp = r.at(j, "depths", "");
  part_file::read_fields(r, dp, "depths.", depth_range_fields(), o.depths);
  try {
    h.dynamics.check();
    o.check();
  } catch (const InvalidArgument& e) {
    r.fail(std::string("its options are not valid: ") + e.what());
  }
  h.speeds_rpm = o.speeds.values();
  h.depths_m = o.depths.values();
  return h;
}

}  // namespace

std::string format_simulated_map_part(const SimulatedMapPart& part) {
  nlohmann::json rows = nlohmann::json::array();
  for (const SimulatedMapRow& r : part.rows)
    rows.push_back({{"speed_index", r.speed_index},
                    {"stable", r.stable},
                    {"growth", hexes(r.growth)},
                    {"chatter_metric", hexes(r.chatter_metric)},
                    {"chatter_hz", hexes(r.chatter_hz)},
                    {"sle_m", hexes(r.sle_m)},
                    {"peak_force_n", hexes(r.peak_force_n)},
                    {"out_of_cut_fraction", hexes(r.out_of_cut_fraction)}});
  return part_file::format_envelope(kMapPart, {part.index, part.count}, part.study, part.header.fingerprint,
                                    header_json(part.header), rows);
}

SimulatedMapPart parse_simulated_map_part(const std::string& text, const std::string& source) {
  return part_file::parse_part(
      text, source, kMapPart, &SimulatedMapPart::rows, parse_header, simulated_map_fingerprint,
      [](const PartReader& r, const nlohmann::json& x, const std::string& p, const SimulatedMapHeader& h) {
        const std::size_t nd = h.depths_m.size();
        SimulatedMapRow row;
        row.speed_index = r.get<std::size_t>(x, "speed_index", p);
        if (row.speed_index >= h.speeds_rpm.size())
          r.fail(fmt::format("{}speed_index {} is not in the map ({} speeds)", p, row.speed_index, h.speeds_rpm.size()));
        row.stable = r.get<std::vector<int>>(x, "stable", p);
        row.growth = r.numbers(x, "growth", p);
        row.chatter_metric = r.numbers(x, "chatter_metric", p);
        row.chatter_hz = r.numbers(x, "chatter_hz", p);
        row.sle_m = r.numbers(x, "sle_m", p);
        row.peak_force_n = r.numbers(x, "peak_force_n", p);
        row.out_of_cut_fraction = r.numbers(x, "out_of_cut_fraction", p);
        for (const auto* v :
             {&row.growth, &row.chatter_metric, &row.chatter_hz, &row.sle_m, &row.peak_force_n, &row.out_of_cut_fraction})
          if (v->size() != nd) r.fail(fmt::format("{}: arrays of the wrong length (the map has {} depths)", p, nd));
        if (row.stable.size() != nd) r.fail(fmt::format("{}: arrays of the wrong length (the map has {} depths)", p, nd));
        return row;
      });
}

SimulatedMap merge_simulated_map_part_files(const std::vector<std::string>& paths) {
  return merge_simulated_map_parts(part_file::read_part_files<SimulatedMapPart>(paths, kMapPart, parse_simulated_map_part),
                                   paths);
}

}  // namespace toolpoint
