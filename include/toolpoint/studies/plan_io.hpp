// toolpoint study: a plan's part files and results as CSV tables — the I/O layer of studies/plan.hpp (as
// stability_io.hpp is of stability.hpp). Each file's first comment line states the plan, the
// units and the safety rule.
//
// Units (in the column names): overhang mm, spindle speed rpm, depths mm, MRR cm³/min, power kW,
// torque N·m, chatter frequency Hz.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/studies/plan.hpp"

namespace toolpoint {

// A part as text (JSON; doubles in hexadecimal, so reading gives the same bits; the header's
// fingerprint and a checksum over the jobs) and back. parse throws InputError naming `source` (not
// a part file, another format version, a damaged or edited entry: the fingerprint or checksum).
// A part that names its shard (every part this version writes, even cut short) is refused with
// ShardSetError, so the shard to run again is known.
std::string format_plan_part(const PlanPart& part);
PlanPart parse_plan_part(const std::string& text, const std::string& source);

// Reads the part files and merges them (merge_plan_parts). Every problem of the set is named at
// once in one ShardSetError: parts cut short or damaged, of other plans or splits, shards given
// twice or missing (check_shard_set). Throws IoError for a file that cannot be read, InputError for
// one that is no plan part at all.
PlanResult merge_plan_part_files(const std::vector<std::string>& paths);

// CSV text (units in the column names; text quoted where needed):
//   best set-ups: rank,candidate,overhang_mm,spindle_speed_rpm,axial_depth_mm,stable_depth_mm,
//     safe_depth_mm,mrr_cm3_per_min,power_kw,torque_nm,limit,depth_margin_percent,probability,
//     chatter_frequency_hz,lobe,window_low_rpm,window_high_rpm,reason
//   per job (the tuning curve): candidate,overhang_mm, then the best set-up's columns as above
//   per job and speed: candidate,overhang_mm,spindle_speed_rpm,stable_depth_mm,safe_depth_mm,
//     axial_depth_mm,limit,mrr_cm3_per_min,chatter_frequency_hz,lobe[,probability]
std::string format_plan_setups_csv(const PlanResult& result);
std::string format_plan_tuning_csv(const PlanResult& result);
std::string format_plan_map_csv(const PlanResult& result);

}  // namespace toolpoint
