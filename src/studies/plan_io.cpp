// toolpoint study: the plan's files — part files (exact), CSV tables and the study file
// (studies/plan.hpp). Units: SI in files unless a column name says otherwise (mm, rpm, cm³/min, kW).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/plan.hpp"
#include "toolpoint/io/stability_io.hpp"
#include "toolpoint/studies/plan_io.hpp"
#include "part_file.hpp"
#include "toml_reader.hpp"

namespace toolpoint {

namespace {

// Version 2: the envelope of part_file.hpp (shard and study first, so a file cut short names its shard).
// Version 3: the options' scalar fields from their tables (fit, lobes, cut, machine, safety_rule).
// Version 4: the cutting conditions' and the speed range's too (cutting, speeds).
constexpr part_file::PartKind kPlanPart{"toolpoint plan part", 4, "run_plan_part", "format_plan_part"};

using part_file::hex;
using part_file::hexes;
using part_file::PartReader;

// The options' scalar fields come from their tables (option_fields.hpp), the rest by hand.
nlohmann::json header_json(const PlanHeader& h) {
  const PlanOptions& o = h.options;
  const LobesStudyOptions& l = o.lobes;
  nlohmann::json opt = {{"name", o.name},
                        {"method", to_string(l.method)},
                        {"cutting", fields_json(cutting_fields(), l.cutting, part_file::hex_json)},
                        {"entry_rad", hex(l.cutting.engagement.entry_rad)},
                        {"exit_rad", hex(l.cutting.engagement.exit_rad)},
                        {"pitch_rad", hexes(l.cutting.pitch_rad)},
                        {"helix_rad", hexes(l.cutting.helix_rad)},
                        {"runout_m", hexes(l.cutting.runout_m)},
                        {"speeds", fields_json(speed_range_fields(), l.speeds, part_file::hex_json)},
                        {"fit_band_hz", l.fit.band_hz ? nlohmann::json{hex(l.fit.band_hz->first), hex(l.fit.band_hz->second)}
                                                      : nlohmann::json(nullptr)},
                        {"fit", fields_json(modal_fit_fields(), l.fit, part_file::hex_json)},
                        {"speed_model", to_string(l.speed_model)},
                        {"lobes", fields_json(lobes_study_fields(), l, part_file::hex_json)},
                        {"cut", fields_json(plan_fields(), o, part_file::hex_json)},
                        {"machine", fields_json(machine_limits_fields(), o.machine, part_file::hex_json)},
                        {"safety", o.safety.kind == SafetyRule::Kind::Factor ? "factor" : "probability"},
                        {"safety_rule", fields_json(safety_rule_fields(), o.safety, part_file::hex_json)},
                        {"seed", std::to_string(o.safety.seed)}};
  nlohmann::json cands = nlohmann::json::array();
  for (const PlanCandidateSummary& c : h.candidates)
    cands.push_back({{"name", c.name},
                     {"measured_holder", c.measured_holder},
                     {"sh11_name", c.sh11_name},
                     {"uncertain_joint", c.uncertain_joint},
                     {"tool_diameter_m", hex(c.tool_diameter_m)},
                     {"flute_length_m", hex(c.flute_length_m)},
                     {"overhangs_m", hexes(c.overhangs_m)},
                     {"left_out", c.left_out},
                     {"content", fmt::format("{:016x}", c.content)}});
  return {{"options", opt}, {"candidates", cands}, {"speeds_rpm", hexes(h.speeds_rpm)}, {"jobs", h.jobs}};
}

PlanHeader parse_header(const PartReader& r, const nlohmann::json& j) {
  PlanHeader h;
  const nlohmann::json& o = r.at(j, "options", "");
  const std::string p = "options.";
  PlanOptions& opt = h.options;
  LobesStudyOptions& l = opt.lobes;
  opt.name = r.get<std::string>(o, "name", p);
  const std::string method = r.get<std::string>(o, "method", p);
  const std::optional<LobesMethod> m = lobes_method_from(method);
  if (!m) r.fail(fmt::format("options.method '{}' is none of zoa, fd, sd", method));
  l.method = *m;
  part_file::read_fields(r, r.at(o, "cutting", p), p + "cutting.", cutting_fields(), l.cutting);
  l.cutting.engagement.entry_rad = r.number(o, "entry_rad", p);
  l.cutting.engagement.exit_rad = r.number(o, "exit_rad", p);
  l.cutting.pitch_rad = r.numbers(o, "pitch_rad", p);
  l.cutting.helix_rad = r.numbers(o, "helix_rad", p);
  l.cutting.runout_m = r.numbers(o, "runout_m", p);
  part_file::read_fields(r, r.at(o, "speeds", p), p + "speeds.", speed_range_fields(), l.speeds);
  const nlohmann::json& band = r.at(o, "fit_band_hz", p);
  if (!band.is_null()) {
    if (!band.is_array() || band.size() != 2) r.fail("options.fit_band_hz is not a pair");
    l.fit.band_hz = std::pair{r.number(band[0], "options.fit_band_hz[0]"), r.number(band[1], "options.fit_band_hz[1]")};
  }
  part_file::read_fields(r, r.at(o, "fit", p), p + "fit.", modal_fit_fields(), l.fit);
  const std::string model_name = r.get<std::string>(o, "speed_model", p);
  const std::optional<SpeedModel> model = speed_model_from(model_name);
  if (!model) r.fail(fmt::format("options.speed_model '{}' is none of auto, standstill, bearings, spinning", model_name));
  l.speed_model = *model;
  part_file::read_fields(r, r.at(o, "lobes", p), p + "lobes.", lobes_study_fields(), l);
  part_file::read_fields(r, r.at(o, "cut", p), p + "cut.", plan_fields(), opt);
  part_file::read_fields(r, r.at(o, "machine", p), p + "machine.", machine_limits_fields(), opt.machine);
  const std::string safety = r.get<std::string>(o, "safety", p);
  if (safety != "factor" && safety != "probability")
    r.fail(fmt::format("options.safety '{}' is neither factor nor probability", safety));
  opt.safety.kind = safety == "factor" ? SafetyRule::Kind::Factor : SafetyRule::Kind::Probability;
  part_file::read_fields(r, r.at(o, "safety_rule", p), p + "safety_rule.", safety_rule_fields(), opt.safety);
  const std::string seed = r.get<std::string>(o, "seed", p);
  std::uint64_t sv = 0;
  if (std::from_chars(seed.data(), seed.data() + seed.size(), sv).ec != std::errc()) r.fail("options.seed is not a number");
  opt.safety.seed = sv;
  const nlohmann::json& cands = r.at(j, "candidates", "");
  if (!cands.is_array()) r.fail("'candidates' is not an array");
  for (std::size_t c = 0; c < cands.size(); ++c) {
    const std::string cp = fmt::format("candidates[{}].", c);
    PlanCandidateSummary s;
    s.name = r.get<std::string>(cands[c], "name", cp);
    s.measured_holder = r.get<bool>(cands[c], "measured_holder", cp);
    s.sh11_name = r.get<std::string>(cands[c], "sh11_name", cp);
    s.uncertain_joint = r.get<std::string>(cands[c], "uncertain_joint", cp);
    s.tool_diameter_m = r.number(cands[c], "tool_diameter_m", cp);
    s.flute_length_m = r.number(cands[c], "flute_length_m", cp);
    s.overhangs_m = r.numbers(cands[c], "overhangs_m", cp);
    s.left_out = r.get<std::size_t>(cands[c], "left_out", cp);
    s.content = r.hash(cands[c], "content", cp);
    h.candidates.push_back(std::move(s));
  }
  h.speeds_rpm = r.numbers(j, "speeds_rpm", "");
  h.jobs = r.get<std::size_t>(j, "jobs", "");
  return h;
}

}  // namespace

std::string format_plan_part(const PlanPart& part) {
  nlohmann::json jobs = nlohmann::json::array();
  for (const PlanJob& job : part.jobs)
    jobs.push_back({{"job", plan_job_index(part.header, job.candidate, job.overhang_index)},
                    {"candidate", job.candidate},
                    {"overhang_index", job.overhang_index},
                    {"overhang_m", hex(job.overhang_m)},
                    {"stable_depth_m", hexes(job.stable_depth_m)},
                    {"safe_depth_m", hexes(job.safe_depth_m)},
                    {"chatter_hz", hexes(job.chatter_hz)},
                    {"lobe", job.lobe},
                    {"probability", hexes(job.probability)},
                    {"modes_hz", hexes(job.modes_hz)},
                    {"warnings", job.warnings}});
  return part_file::format_envelope(kPlanPart, {part.index, part.count}, part.study, part.header.fingerprint,
                                    header_json(part.header), jobs);
}

PlanPart parse_plan_part(const std::string& text, const std::string& source) {
  return part_file::parse_part(
      text, source, kPlanPart, &PlanPart::jobs, parse_header, plan_fingerprint,
      [](const PartReader& r, const nlohmann::json& x, const std::string& p, const PlanHeader& h) {
        const std::size_t ns = h.speeds_rpm.size();
        const bool sampled = h.options.safety.kind == SafetyRule::Kind::Probability;
        PlanJob job;
        job.candidate = r.get<std::size_t>(x, "candidate", p);
        job.overhang_index = r.get<std::size_t>(x, "overhang_index", p);
        if (job.candidate >= h.candidates.size() || job.overhang_index >= h.candidates[job.candidate].overhangs_m.size())
          r.fail(fmt::format("{}: candidate {} overhang {} is not in the plan", p, job.candidate, job.overhang_index));
        if (r.get<std::size_t>(x, "job", p) != plan_job_index(h, job.candidate, job.overhang_index))
          r.fail(p + "job does not match its candidate and overhang");
        job.overhang_m = r.number(x, "overhang_m", p);
        if (job.overhang_m != h.candidates[job.candidate].overhangs_m[job.overhang_index])
          r.fail(p + "overhang_m is not the plan's");
        job.stable_depth_m = r.numbers(x, "stable_depth_m", p);
        job.safe_depth_m = r.numbers(x, "safe_depth_m", p);
        job.chatter_hz = r.numbers(x, "chatter_hz", p);
        job.lobe = r.get<std::vector<int>>(x, "lobe", p);
        job.probability = r.numbers(x, "probability", p);
        job.modes_hz = r.numbers(x, "modes_hz", p);
        job.warnings = r.get<std::vector<std::string>>(x, "warnings", p);
        if (job.stable_depth_m.size() != ns || job.safe_depth_m.size() != ns || job.chatter_hz.size() != ns ||
            job.lobe.size() != ns || job.probability.size() != (sampled ? ns : 0))
          r.fail(fmt::format("{}: arrays of the wrong length (the plan has {} speeds)", p, ns));
        return job;
      });
}

PlanResult merge_plan_part_files(const std::vector<std::string>& paths) {
  return merge_plan_parts(part_file::read_part_files<PlanPart>(paths, kPlanPart, parse_plan_part), paths);
}

// ---- CSV tables ----------------------------------------------------------------------------------

namespace {

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); }

const char* const kSetupColumns =
    "overhang_mm,spindle_speed_rpm,axial_depth_mm,stable_depth_mm,safe_depth_mm,mrr_cm3_per_min,power_kw,torque_nm,limit,"
    "depth_margin_percent,probability,chatter_frequency_hz,lobe,window_low_rpm,window_high_rpm,reason";

std::string setup_fields(const PlanSetup& s) {
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", num(1e3 * s.overhang_m), num(s.speed_rpm),
                     num(1e3 * s.depth_m), num(1e3 * s.stable_depth_m), num(1e3 * s.safe_depth_m),
                     num(kCubicCentimetresPerMinute * s.mrr_m3_per_s), num(1e-3 * s.power_w), num(s.torque_nm),
                     to_string(s.limit), num(100.0 * s.depth_margin), num(s.probability), num(s.chatter_hz), s.lobe,
                     num(s.window_low_rpm), num(s.window_high_rpm), csv_text(s.reason));
}

std::string head(const PlanResult& r, const std::string& what) {
  const PlanOptions& o = r.header.options;
  const std::string rule = safety_rule_text(o.safety);
  // The tool beyond straight, even teeth (its diameter each candidate's own): a line of its own.
  CuttingConditions cut = o.lobes.cutting;
  cut.diameter_m = 0.0;
  cut.feed_per_tooth_m = o.feed_per_tooth_m;
  const std::string tool = tool_geometry_text(cut);
  return fmt::format(
      "# toolpoint plan: {}; units: overhang mm, spindle speed rpm, depths mm, MRR cm^3/min, power kW, torque N m, "
      "chatter frequency Hz; empty: none\n# safety rule: {}; fingerprint {:016x}\n{}",
      what, rule, r.header.fingerprint, tool.empty() ? "" : fmt::format("# tool: {} (each candidate's diameter)\n", tool));
}

}  // namespace

std::string format_plan_setups_csv(const PlanResult& r) {
  std::string s = head(r, "the best set-up of each candidate, most metal removed first");
  s += std::string("rank,candidate,") + kSetupColumns + "\n";
  for (std::size_t i = 0; i < r.best.size(); ++i)
    s += fmt::format("{},{},{}\n", i + 1, csv_text(r.header.candidates[r.best[i].candidate].name), setup_fields(r.best[i]));
  return s;
}

std::string format_plan_tuning_csv(const PlanResult& r) {
  std::string s = head(r, "the best set-up at each overhang (the tuning curve)");
  s += std::string("candidate,") + kSetupColumns + "\n";
  for (const PlanJob& job : r.jobs)
    s += fmt::format("{},{}\n", csv_text(r.header.candidates[job.candidate].name), setup_fields(job.best));
  return s;
}

std::string format_plan_map_csv(const PlanResult& r) {
  const bool sampled = r.header.options.safety.kind == SafetyRule::Kind::Probability;
  std::string s = head(r, "every overhang and speed");
  s += "candidate,overhang_mm,spindle_speed_rpm,stable_depth_mm,safe_depth_mm,axial_depth_mm,limit,mrr_cm3_per_min,chatter_"
       "frequency_hz,lobe";
  s += sampled ? ",probability\n" : "\n";
  auto out = std::back_inserter(s);
  for (const PlanJob& job : r.jobs) {
    const std::string name = csv_text(r.header.candidates[job.candidate].name);
    const std::string overhang = num(1e3 * job.overhang_m);
    for (std::size_t k = 0; k < r.header.speeds_rpm.size(); ++k) {
      fmt::format_to(out, "{},{},{},{},{},{},{},{},{},{}", name, overhang, num(r.header.speeds_rpm[k]),
                     num(1e3 * job.stable_depth_m[k]), num(1e3 * job.safe_depth_m[k]), num(1e3 * job.depth_m[k]),
                     to_string(job.limit[k]), num(kCubicCentimetresPerMinute * job.mrr_m3_per_s[k]), num(job.chatter_hz[k]),
                     job.lobe[k]);
      if (sampled) fmt::format_to(out, ",{}", num(job.probability[k]));
      s += '\n';
    }
  }
  return s;
}

// ---- The study file --------------------------------------------------------------------------------

namespace {

namespace fs = std::filesystem;

const char* const kStudyHint = "see examples/plan_bt40.toml for the study file's keys and units";

std::string resolve(const std::string& directory, const std::string& path) {
  const fs::path p(path);
  return p.is_absolute() || directory.empty() ? path : (fs::path(directory) / p).lexically_normal().string();
}

// A file named by a key: read by `load`, its IoError given the key's place in the study file.
template <class Load>
auto load_named(Reader& r, const toml::table& t, const char* key, const std::string& path, const std::string& file, Load&& load) {
  try {
    return load(file);
  } catch (const IoError& e) {
    throw IoError(fmt::format("{}: {} = \"{}\": {}", r.where(*t.get(key)), Reader::join(path, key), file, e.what()),
                  "paths in a study file are relative to the study file's folder");
  }
}

int integer(Reader& r, const toml::table& t, const char* key, const std::string& path, int lo, int hi, int fallback) {
  const auto v = r.number(t, key, path, "(count)");
  if (!v) return fallback;
  if (*v != std::floor(*v) || *v < lo || *v > hi)
    r.fail(*t.get(key), fmt::format("{} = {} must be an integer in {}…{}", Reader::join(path, key), *v, lo, hi),
           "write a whole number in that range");
  return static_cast<int>(*v);
}

// A number required to satisfy `ok`, failing at its key with `expected`.
double checked(Reader& r, const toml::table& t, const char* key, const std::string& path, const char* unit, bool required,
               double fallback, bool (*ok)(double), const std::string& expected, const std::string& hint = {}) {
  const auto v = required ? std::optional<double>(r.required_number(t, key, path, unit)) : r.number(t, key, path, unit);
  if (!v) return fallback;
  if (!ok(*v))
    r.fail(*t.get(key), fmt::format("{} = {} {}", Reader::join(path, key), *v, expected), hint.empty() ? kStudyHint : hint);
  return *v;
}

PlanCandidate read_candidate(Reader& r, const toml::table& t, const std::string& path, const std::string& directory,
                             PlanStudy& study, int number) {
  r.only(t, path,
         {"name", "assembly", "overhang", "overhang_min", "overhang_max", "overhang_step", "overhang_points", "sh11", "joints"});
  PlanCandidate c;
  c.name = r.string(t, "name", path).value_or(fmt::format("candidate {}", number));
  const auto assembly = r.string(t, "assembly", path);
  if (!assembly)
    r.fail(t, fmt::format("missing key {}.assembly (the assembly file, TOML)", path),
           "e.g. assembly = \"bt40_shrinkfit_16mm.toml\"");
  const std::string file = resolve(directory, *assembly);
  LoadedAssembly loaded = load_named(r, t, "assembly", path, file, [](const std::string& f) { return load_assembly(f); });
  study.inputs.push_back(file);
  for (auto& w : loaded.warnings) study.warnings.push_back(std::move(w));

  // Joint files: identified joints in place of the assembly file's; the one with [uncertainty] is sampled.
  if (const toml::node* jn = t.get("joints")) {
    const toml::array* arr = jn->as_array();
    if (!arr) r.fail(*jn, fmt::format("{}.joints must be an array of file names", path), "e.g. joints = [\"kht.toml\"]");
    for (const toml::node& e : *arr) {
      if (!e.is_string())
        r.fail(e, fmt::format("{}.joints must hold file names (strings)", path), "e.g. joints = [\"kht.toml\"]");
      const std::string jf = resolve(directory, e.as_string()->get());
      JointFile f = load_named(r, t, "joints", path, jf, [](const std::string& x) { return load_joint_file(x); });
      study.inputs.push_back(jf);
      loaded = with_joint(std::move(loaded), f);  // its notes then describe the joint in use
      if (f.uncertainty) {
        if (c.uncertain_joint)
          r.fail(e,
                 fmt::format("{}.joints: {} and {} both carry [uncertainty]; only one joint can be sampled", path,
                             c.uncertain_joint->source, jf),
                 "give one of them without its [uncertainty] table, or plan them separately");
        c.uncertain_joint = std::move(f);
      }
    }
  }
  for (auto& n : loaded.notes) study.notes.push_back(std::move(n));
  c.assembly = std::move(loaded.assembly);
  if (const auto sh = r.string(t, "sh11", path)) {
    const std::string f = resolve(directory, *sh);
    c.sh11 = load_named(r, t, "sh11", path, f, [](const std::string& x) { return read_block_csv(x); });
    c.sh11_name = f;
    study.inputs.push_back(f);
  }

  // Overhangs: one, or MIN…MAX by STEP (or POINTS), in m.
  const auto lo = r.number(t, "overhang_min", path, "m"), hi = r.number(t, "overhang_max", path, "m");
  const auto step = r.number(t, "overhang_step", path, "m");
  const bool has_points = t.contains("overhang_points");
  if (const auto one = r.number(t, "overhang", path, "m")) {
    if (lo || hi || step || has_points)
      r.fail(*t.get("overhang"), fmt::format("{} gives overhang and an overhang range: choose one", path),
             "overhang = L for one, or overhang_min, overhang_max and overhang_step for a range");
    r.plausible(t, "overhang", path, *one, plausible::kOverhang);
    c.overhangs_m = {*one};
  } else if (lo || hi || step || has_points) {
    if (!lo || !hi)
      r.fail(t, fmt::format("{}: an overhang range needs overhang_min and overhang_max (m)", path),
             "e.g. overhang_min = 0.040, overhang_max = 0.090");
    if (step && has_points)
      r.fail(*t.get("overhang_step"), fmt::format("{} gives overhang_step and overhang_points: choose one", path),
             "keep one of them");
    if (!step && !has_points)
      r.fail(t, fmt::format("{}: an overhang range needs overhang_step (m) or overhang_points", path),
             "e.g. overhang_step = 0.0005");
    r.plausible(t, "overhang_min", path, *lo, plausible::kOverhang);
    r.plausible(t, "overhang_max", path, *hi, plausible::kOverhang);
    if (!(*lo > 0.0) || !(*hi > *lo))
      r.fail(*t.get("overhang_max"),
             fmt::format("{}: overhang range {} to {} m must have 0 < overhang_min < overhang_max", path, *lo, *hi),
             "overhangs are in metres, e.g. overhang_min = 0.040, overhang_max = 0.090");
    if (step) {
      if (!(*step > 0.0))
        r.fail(*t.get("overhang_step"), fmt::format("{}.overhang_step = {} m must be > 0", path, *step), "e.g. 0.0005 (0.5 mm)");
      if (!(*step >= 1e-9))
        r.fail(*t.get("overhang_step"), fmt::format("{}.overhang_step = {} m is below a nanometre", path, *step),
               "give the step in metres, e.g. 0.0005 (0.5 mm)");
      const std::size_t n = overhang_sweep_size(*lo, *hi, *step);
      if (n > 100000)
        r.fail(*t.get("overhang_step"), fmt::format("{}: the overhang range gives {} overhangs; at most 100000", path, n),
               "use a larger step");
      // The decimal overhangs meant, not lo + i·step with its binary error (0.10200000000000001).
      c.overhangs_m = overhang_sweep(*lo, *hi, *step);
    } else {
      const int points = integer(r, t, "overhang_points", path, 2, 100000, 2);
      for (int i = 0; i < points; ++i) c.overhangs_m.push_back(*lo + (*hi - *lo) * i / (points - 1));
    }
  }
  if (c.overhangs_m.empty()) c.overhangs_m = {c.assembly.tool.overhang};
  for (double L : c.overhangs_m)
    if (L > 1.0)
      r.fail(t, fmt::format("{}: overhang {} m is over 1 m: millimetres?", path, L),
             fmt::format("overhangs are in metres: {} mm is {:g} m", L, L / 1000.0));
  return c;
}

// [cut]'s tool beyond straight, even teeth (CuttingConditions; the time-domain method only): pitch
// [rad] per tooth, helix [rad] (one, or one per tooth), runout [m] per tooth; with process_damping
// C_i [N/m] (read with cutting_fields), checked with the rest of the cut (CuttingConditions::check,
// the message naming the key).
void read_tool_geometry(const Reader& r, const toml::table& cut, CuttingConditions& c) {
  if (auto v = r.numbers(cut, "pitch", "cut", "rad")) c.pitch_rad = *v;
  if (auto v = r.numbers(cut, "helix", "cut", "rad")) c.helix_rad = *v;
  if (auto v = r.numbers(cut, "runout", "cut", "m")) c.runout_m = *v;
  CuttingConditions probe = c;
  probe.diameter_m = probe.helical() || probe.process_damping_n_per_m > 0.0 ? 1.0 : 0.0;  // the candidates' tools
  probe.feed_per_tooth_m = 1e-4;                                                          // the feed is read apart
  try {
    probe.check();
  } catch (const InvalidArgument& e) {
    std::string what = e.what();
    for (const auto& [key, field] : {std::pair{"pitch", "CuttingConditions::pitch_rad"},
                                     {"helix", "CuttingConditions::helix_rad"},
                                     {"runout", "CuttingConditions::runout_m"},
                                     {"process_damping", "CuttingConditions::process_damping_n_per_m"}}) {
      const std::size_t at = what.find(field);
      if (at == std::string::npos || !cut.get(key)) continue;
      what.replace(at, std::string(field).size(), fmt::format("cut.{}", key));
      r.fail(*cut.get(key), what, e.hint());
    }
    // Anything else belongs to the rest of the cut: PlanOptions::check reports it.
  }
}

}  // namespace

// The plan file's tables, one phase each (parse_plan_study): the keys, their units and checks.
namespace {

// [study]: the name and the lobes' method.
void read_study_table(Reader& r, const toml::table& root, PlanStudy& s) {
  PlanOptions& o = s.options;
  LobesStudyOptions& l = o.lobes;
  if (const toml::table* t = r.table(root, "study", "", false)) {
    r.only(*t, "study", {"name", "description", "method"});
    s.name = r.string(*t, "name", "study").value_or("");
    o.name = s.name;
    if (const auto m = r.string(*t, "method", "study")) {
      if (const std::optional<LobesMethod> lm = lobes_method_from(*m)) l.method = *lm;
      else
        r.fail(*t->get("method"),
               fmt::format("study.method = \"{}\": expected \"zoa\" (zero-order), \"fd\" (full-discretization) or \"sd\" "
                           "(semi-discretization)",
                           *m),
               "zoa is fast and exact where the cut is time-invariant; fd finds the flip lobes of low immersion");
    }
  }
}

// [cut]: the cutting conditions, the feed and the depth limit.
void read_cut_table(Reader& r, const toml::table& root, PlanOptions& o) {
  LobesStudyOptions& l = o.lobes;
  const toml::table& cut = *r.table(root, "cut", "", true);
  std::vector<const char*> keys = field_keys(plan_fields());  // feed_per_tooth, edge_coefficient, max_depth
  const std::vector<const char*> cutting_keys = field_keys(cutting_fields());  // teeth, K_t, K_r, process_damping
  keys.insert(keys.end(), cutting_keys.begin(), cutting_keys.end());
  keys.insert(keys.end(), {"normal_coefficient", "radial_immersion", "milling", "pitch", "helix", "runout"});
  r.only(cut, "cut", keys);
  for (const char* key : {"teeth", "tangential_coefficient"})
    if (!cut.contains(key))
      r.fail(cut, fmt::format("missing key cut.{} ({})", key, option_field(cutting_fields(), key).spec.help),
             key == std::string_view("teeth") ? "e.g. teeth = 4" : "e.g. tangential_coefficient = 6e8 (N/m^2)");
  read_fields(r, cut, "cut", cutting_fields(), l.cutting);
  // K_n = K_r·K_t: the radial coefficient's other form, as the CLI's --kn.
  const auto kn = r.number(cut, "normal_coefficient", "cut", "N/m^2");
  if (cut.contains("radial_ratio") && kn)
    r.fail(*cut.get("normal_coefficient"), "[cut] gives radial_ratio and normal_coefficient: choose one",
           "K_r = K_n/K_t: give one of them");
  if (!cut.contains("radial_ratio") && !kn)
    r.fail(cut, "missing key cut.radial_ratio (K_n/K_t) or cut.normal_coefficient (K_n, N/m^2)", "e.g. radial_ratio = 0.3");
  if (kn) {
    if (!(*kn >= 0.0))
      r.fail(*cut.get("normal_coefficient"), fmt::format("cut.normal_coefficient = {} N/m^2 must be ≥ 0", *kn),
             "K_n in N/m^2, e.g. 2e8");
    r.plausible(cut, "normal_coefficient", "cut", *kn, plausible::kCuttingCoefficient);
    l.cutting.radial_ratio = *kn / l.cutting.tangential_coefficient;
  }
  const double immersion = checked(
      r, cut, "radial_immersion", "cut", "(a/D)", true, 0.0, [](double v) { return v > 0.0 && v <= 1.0; },
      "must lie in (0, 1]: the radial depth over the tool diameter", "e.g. 0.5 for half immersion, 1 for a slot");
  const auto milling = r.string(cut, "milling", "cut");
  if (!milling) r.fail(cut, "missing key cut.milling (\"up\" or \"down\")", "e.g. milling = \"down\"");
  if (*milling != "up" && *milling != "down")
    r.fail(*cut.get("milling"), fmt::format("cut.milling = \"{}\": expected \"up\" or \"down\"", *milling),
           "down: the tooth leaves the cut at the full chip (climb milling); up: it enters there (conventional)");
  l.cutting.engagement = engagement_from_immersion(immersion, *milling == "up" ? MillingDirection::Up : MillingDirection::Down);
  r.required_number(cut, "feed_per_tooth", "cut", "m");
  read_fields(r, cut, "cut", plan_fields(), o);
  read_tool_geometry(r, cut, l.cutting);
}

// [machine]: the speed range and the spindle's limits.
void read_machine_table(Reader& r, const toml::table& root, PlanOptions& o) {
  LobesStudyOptions& l = o.lobes;
  const toml::table& mach = *r.table(root, "machine", "", true);
  std::vector<const char*> keys = field_keys(machine_limits_fields());  // power, torque, min_overhang
  const std::vector<const char*> speed_keys = field_keys(speed_range_fields());  // speed_min, speed_max, speed_points
  keys.insert(keys.end(), speed_keys.begin(), speed_keys.end());
  r.only(mach, "machine", keys);
  r.required_number(mach, "speed_min", "machine", "rpm");
  r.required_number(mach, "speed_max", "machine", "rpm");
  read_fields(r, mach, "machine", speed_range_fields(), l.speeds);  // points absent: 0, the method's
  if (!(l.speeds.max_rpm > l.speeds.min_rpm))
    r.fail(*mach.get("speed_max"),
           fmt::format("machine.speed_max = {} rpm must exceed machine.speed_min = {} rpm", l.speeds.max_rpm, l.speeds.min_rpm),
           "give the spindle's speed range in rpm, e.g. speed_min = 2000, speed_max = 12000");
  read_fields(r, mach, "machine", machine_limits_fields(), o.machine);
}

// [safety]: the rule that turns a stable depth into a safe one.
void read_safety_table(Reader& r, const toml::table& root, PlanOptions& o) {
  if (const toml::table* t = r.table(root, "safety", "", false)) {
    std::vector<const char*> keys = field_keys(safety_rule_fields());  // factor, probability, samples
    keys.push_back("seed");
    r.only(*t, "safety", keys);
    const bool probability = t->contains("probability");
    if (probability && t->contains("factor"))
      r.fail(*t->get("probability"), "[safety] gives factor and probability: choose one rule",
             "keep factor (the stable depth divided by it) or probability (a joint file with [uncertainty] sampled)");
    read_fields(r, *t, "safety", safety_rule_fields(), o.safety);
    if (probability) o.safety.kind = SafetyRule::Kind::Probability;
    if ((t->contains("samples") || t->contains("seed")) && !probability)
      r.fail(*t, "safety.samples and safety.seed belong to the probability rule (safety.probability)",
             "drop them, or give safety.probability");
    o.safety.seed = static_cast<std::uint64_t>(integer(r, *t, "seed", "safety", 0, std::numeric_limits<int>::max(), 1));
  }
}

// [lobes]: the lobes' numerics and speed model (LobesStudyOptions).
void read_lobes_table(Reader& r, const toml::table& root, LobesStudyOptions& l) {
  if (const toml::table* t = r.table(root, "lobes", "", false)) {
    std::vector<const char*> keys = field_keys(lobes_study_fields());
    keys.push_back("speed_model");
    r.only(*t, "lobes", keys);
    read_fields(r, *t, "lobes", lobes_study_fields(), l);
    // The speed model, as `lobes --speed-model` (LobesStudyOptions).
    if (const auto m = r.string(*t, "speed_model", "lobes")) {
      const std::optional<SpeedModel> model = speed_model_from(*m);
      if (!model)
        r.fail(*t->get("speed_model"),
               fmt::format("lobes.speed_model = \"{}\": expected \"auto\", \"standstill\", \"bearings\" or \"spinning\"", *m),
               "auto: the x–y FRF at each speed where a bearing has a speed table or differs in x and y");
      l.speed_model = *model;
    }
  }
}

// [[candidate]]: each candidate (read_candidate), distinct names, a sampled joint where the rule needs one.
void read_candidates(Reader& r, const toml::table& root, const std::string& directory, PlanStudy& s) {
  const PlanOptions& o = s.options;
  const toml::node* cn = root.get("candidate");
  if (!cn) r.fail(root, "the study has no [[candidate]]", "add a [[candidate]] table with name, assembly and the overhangs");
  const toml::array* arr = cn->as_array();
  if (!arr || !arr->is_array_of_tables())
    r.fail(*cn, "candidate must be an array of tables ([[candidate]])", "write [[candidate]] above each candidate's keys");
  int i = 0;
  for (const toml::node& e : *arr) {
    ++i;
    s.candidates.push_back(read_candidate(r, *e.as_table(), fmt::format("candidate[{}]", i), directory, s, i));
  }
  for (std::size_t a = 0; a < s.candidates.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (s.candidates[a].name == s.candidates[b].name)
        r.fail(*arr->get(a),
               fmt::format("candidate[{}] and candidate[{}] are both named '{}'", b + 1, a + 1, s.candidates[a].name),
               "give each candidate its own name");
  if (o.safety.kind == SafetyRule::Kind::Probability)
    for (std::size_t a = 0; a < s.candidates.size(); ++a)
      if (!s.candidates[a].uncertain_joint)
        r.fail(*arr->get(a),
               fmt::format("candidate[{}] ('{}'): safety.probability needs a joint file with [uncertainty] in candidate.joints",
                           a + 1, s.candidates[a].name),
               "write a band-fitted joint to kht.toml (write_joint_file) and add joints = [\"kht.toml\"], or use "
               "safety.factor");
}

}  // namespace

PlanStudy parse_plan_study(const std::string& text, const std::string& source, const std::string& directory) {
  const toml::table root = parse_toml(text, source, kStudyHint);
  Reader r(source);
  r.only(root, "", {"study", "candidate", "cut", "machine", "safety", "lobes"});
  PlanStudy s;
  s.inputs.push_back(source);
  PlanOptions& o = s.options;
  read_study_table(r, root, s);
  read_cut_table(r, root, o);
  read_machine_table(r, root, o);
  read_safety_table(r, root, o);
  read_lobes_table(r, root, o.lobes);
  read_candidates(r, root, directory, s);
  try {
    o.check();
    plan_header(s.candidates, o);
  } catch (const InvalidArgument& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()), e.hint());
  }
  s.warnings.insert(s.warnings.begin(), r.warnings.begin(), r.warnings.end());
  return s;
}

PlanStudy load_plan_study(const std::string& path) {
  return parse_plan_study(read_text_file(path), path, fs::path(path).parent_path().string());
}

}  // namespace toolpoint
