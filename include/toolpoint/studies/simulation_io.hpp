// toolpoint study: the simulation's tables and the simulated map's part files — the I/O layer of
// studies/simulation.hpp (as plan_io.hpp is of plan.hpp). Tables go to CSV through io.hpp's
// write_table_csv (units in the column names; an empty cell: no value).
#pragma once

#include <string>
#include <vector>

#include "toolpoint/io/io.hpp"
#include "toolpoint/studies/simulation.hpp"

namespace toolpoint {

// Every step: time_s, force_x_n, force_y_n, x_m, y_m, vx_m_per_s, vy_m_per_s, torque_nm, then
// tooth_<j>_force_n (tangential, summed over the slices) per tooth. Throws InvalidArgument without
// recorded histories.
Table simulation_history_table(const SimulationResult& result);
// The once-per-revolution (kind 0) and once-per-tooth (kind 1) samples: kind, time_s, tooth, x_m,
// y_m, vx_m_per_s, vy_m_per_s (tooth empty once per revolution).
Table simulation_samples_table(const SimulationResult& result);
// Per wall and slice: wall_angle_deg, slice, height_m, sle_m (+: material left).
Table simulation_wall_table(const SimulationResult& result);
// Per speed and depth: spindle_speed_rpm, axial_depth_mm, stable (1/0), growth_per_revolution,
// chatter_metric, chatter_frequency_hz, sle_um, peak_force_n, out_of_cut_fraction (empty: none; an
// overflowing cell has no growth).
Table simulated_map_table(const SimulatedMap& map);

// A map's part as text (JSON; doubles in hexadecimal, so reading gives the same bits; the shard,
// the study and the header's fingerprint first, a checksum over the speeds' rows: the part file
// of every sharded study, as the plan's) and back. parse throws InputError naming `source` (not a
// part file of a simulated map, another format version); a part that names its shard (even cut
// short) but is damaged or edited (fingerprint, checksum) is refused with ShardSetError, so the
// shard to run again is known.
std::string format_simulated_map_part(const SimulatedMapPart& part);
SimulatedMapPart parse_simulated_map_part(const std::string& text, const std::string& source);

// Reads the part files and merges them (merge_simulated_map_parts). Every problem of the set is
// named at once in one ShardSetError: parts cut short or damaged, of other maps or splits, shards
// given twice or missing (check_shard_set). Throws IoError for a file that cannot be read,
// InputError for one that is no part of a simulated map at all.
SimulatedMap merge_simulated_map_part_files(const std::vector<std::string>& paths);

}  // namespace toolpoint
