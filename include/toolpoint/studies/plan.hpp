// toolpoint study: the set-up and spindle speed that remove the most metal without chatter — the
// procedure behind `toolpoint plan`, as one library call (and in parts, for a batch engine).
//
// A plan is a list of independent jobs, one per (candidate, overhang). A candidate is an assembly
// (spindle, holder, tool, joints) whose tool overhang may vary, its tool point FRF either from the
// model (seed Eq. 1–5) or from a measured holder-tip SH11 coupled to the model's tool (Eq. 5,
// Schmitz's RCSA; the `couple` route). Per job:
//   1. the tool point FRF at overhang L (with_overhang: the length inside the holder is kept); the
//      model's is refined where its phase turns faster than the lobes can follow
//      (resolved_tool_point), a measured SH11 keeps its grid;
//   2. the stable envelope a_lim(n) over the spindle speeds (the lobes study: zero-order by default,
//      full-discretization on request, its depths searched up to the flute length or the depth cap
//      unless lobes.max_depth_m is given; a symmetric tool, G_yy = G_xx);
//   3. the safety rule: the depth allowed a_safe(n) = a_lim(n)/factor, or the depth stable with
//      probability ≥ p when the joint is uncertain (the type-7 quantile at 1 − p of the envelopes of
//      `samples` joints drawn from the joint file's covariance, uncertainty.hpp; the same draws for
//      every overhang, so overhangs are compared on common random numbers);
//   4. the machine: with straight teeth, feed per tooth c, radial width b = (D/2)(cos φ_st − cos φ_ex)
//      and the tangential force per tooth F_t = K_t a c sin φ + K_te a, the mean cutting torque and
//      power of depth a at n rpm are (Altintas, Manufacturing Automation, 2nd ed., §2.3, the average
//      over one revolution)
//          T(a) = a · N D/(4π) · [K_t c (cos φ_st − cos φ_ex) + K_te (φ_ex − φ_st)]      [N·m]
//          P(a, n) = T(a) · 2π n/60                                                     [W]
//      (with K_te = 0, P = K_t · MRR: the specific cutting energy is K_t). The depth used is
//          a(n) = min(a_safe(n), T_max / T(1), P_max / P(1, n), a_max)
//      with a_max the tool's flute length and PlanOptions::max_depth_m (whichever are set);
//   5. the material removal rate MRR(n) = a(n) · b · c · N · n/60 [m³/s] and its maximum over n.
// The best set-up of a job is its largest MRR; within a relative 1e-9 of it (a power-limited
// plateau, where MRR = P_max/K_t at every speed) the speed with the largest stability margin, then
// the lowest. The best set-up of a candidate is its best job by the same rule. Jobs with an
// overhang below MachineLimits::min_overhang_m (the reach the part needs) are not planned.
//
// Scale: run_plan uses every core (jobs in parallel, or a single job's samples). For a batch
// engine, run_plan_part computes the jobs j ≡ I (mod N) of shard I/N and merge_plan_parts combines
// the N parts into the result run_plan gives, bit for bit: a job's numbers do not depend on which
// process or thread computed it, and part files keep every double exactly (hexadecimal).
//
// Units: SI (m, N, W, N·m, m³/s), spindle speeds in rpm, frequencies in Hz.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/shards.hpp"
#include "toolpoint/studies/study.hpp"

namespace toolpoint {

// One set-up family: an assembly whose tool overhang is varied.
struct PlanCandidate {
  std::string name;
  Assembly assembly;  // its joints in place (joint files applied: with_joint)
  // The measured-holder route: SH11 measured at the holder tip (with the tool's inside length as in
  // the assembly), coupled to the model's tool through the holder–tool joint (Eq. 5, couple_tool),
  // on SH11's grid. Absent: the model's tool point FRF on assembly.grid.
  std::optional<BlockSeries> sh11;
  std::string sh11_name = "SH11";
  // The joint sampled by SafetyRule::Probability (its [uncertainty] covariance); its constants are
  // the nominal ones, in place of the assembly's. A holder–tool joint for the measured-holder route.
  std::optional<JointFile> uncertain_joint;
  // Tool overhangs [m], strictly increasing, each in (0, 1]; empty: the assembly's own.
  std::vector<double> overhangs_m;
};

// The spindle's limits and the part's reach.
struct MachineLimits {
  double power_w = 0.0;         // cutting power available at the tool [W]; 0: no limit
  double torque_nm = 0.0;       // spindle torque [N·m]; 0: no limit (with power: the base speed is P/(2πT/60))
  double min_overhang_m = 0.0;  // shorter overhangs cannot reach the feature [m]; 0: none
};

// How far below the stability limit the depth used stays.
struct SafetyRule {
  enum class Kind {
    Factor,       // a_safe = a_lim / factor
    Probability,  // a_safe = the depth stable with probability ≥ `probability` (joint uncertainty)
  };
  Kind kind = Kind::Factor;
  double factor = 1.0;        // ≥ 1
  double probability = 0.95;  // in [0.5, 1)
  int samples = 200;          // joints drawn, 20…100000
  std::uint64_t seed = 1;     // of the draws (sample_joints)
};

struct PlanOptions {
  std::string name;  // the plan's name, for reports and files (a study file's study.name)
  // The cut (cutting conditions: teeth, K_t, K_r, engagement), the speeds (points 0: 2000 zero-order,
  // 200 full-discretization), the method and its settings, the pocket prominence. `lobes.parallel`
  // and `lobes.progress` are not used (the plan's own are). The cutting conditions' variable pitch,
  // helix, runout and process damping (full-discretization only) are used as given; their
  // diameter_m and feed_per_tooth_m are not: each candidate's tool diameter and feed_per_tooth_m
  // below are (plan_cutting).
  LobesStudyOptions lobes;
  double feed_per_tooth_m = 0.0;          // c > 0 [m]
  double edge_coefficient_n_per_m = 0.0;  // K_te ≥ 0 [N/m]: tangential edge force per unit depth (torque, power)
  double max_depth_m = 0.0;               // a cap on the depth [m] (the feature's height); 0: none
  MachineLimits machine;
  SafetyRule safety;
  ParallelOptions parallel;  // jobs (or one job's samples) on this many threads; results identical for any count
  // Throws InvalidArgument naming `PlanOptions::<field>` (or the nested options' fields) and the value.
  void check() const;
};

/// \brief The scalar fields of PlanOptions, defined once (option_fields.hpp): feed_per_tooth_m,
/// edge_coefficient_n_per_m and max_depth_m, their units, ranges and help, the plan file's [cut]
/// keys (feed_per_tooth, edge_coefficient, max_depth) and the JSON echo derive from it.
/// \return the table, in the order of the fields
const std::vector<OptionField<PlanOptions>>& plan_fields();

/// \brief MachineLimits' fields, defined once (option_fields.hpp): the plan file's [machine] keys
/// (power, torque, min_overhang), the checks and the JSON echo derive from it.
/// \return the table, in the order of the fields
const std::vector<OptionField<MachineLimits>>& machine_limits_fields();

/// \brief SafetyRule's numeric fields but the seed, defined once (option_fields.hpp): the plan
/// file's [safety] keys (factor, probability, samples), the checks and the JSON echo derive from it
/// (the kind and the 64-bit seed are read by hand).
/// \return the table, in the order of the fields
const std::vector<OptionField<SafetyRule>>& safety_rule_fields();

// The cut of a candidate whose tool has diameter D [m]: PlanOptions::lobes.cutting with diameter_m
// = D and feed_per_tooth_m = PlanOptions::feed_per_tooth_m (one definition of each: the helix's
// lag, process damping's speed and the runout's surfaces read them).
CuttingConditions plan_cutting(const PlanOptions& options, double tool_diameter_m);

// What bounds the depth used at a speed.
enum class DepthLimit { Stability, Power, Torque, Depth, None };
const char* to_string(DepthLimit limit);  // "stability", "power", "torque", "depth", "none"

// The candidate as the plan saw it: what the results need without the assembly.
struct PlanCandidateSummary {
  std::string name;
  bool measured_holder = false;  // the SH11 route
  std::string sh11_name;
  std::string uncertain_joint;      // the sampled joint file's source ("" when none is sampled)
  double tool_diameter_m = 0.0;     // D
  double flute_length_m = 0.0;      // the depth cap it implies (0: not modelled, no cap)
  std::vector<double> overhangs_m;  // those planned (≥ the minimum overhang)
  std::size_t left_out = 0;         // overhangs shorter than MachineLimits::min_overhang_m
  std::uint64_t content = 0;        // hash of the assembly, SH11 and sampled joint (plan_fingerprint)
};

// Everything a plan's results depend on besides the jobs' numbers (what a part file carries).
struct PlanHeader {
  PlanOptions options;  // as given, speeds.points resolved
  std::vector<PlanCandidateSummary> candidates;
  std::vector<double> speeds_rpm;  // the grid
  std::size_t jobs = 0;            // Σ overhangs planned
  std::uint64_t fingerprint = 0;   // of the options and candidates (plan_fingerprint)
};

// The job index of (candidate c, overhang i): candidates in order, overhangs in order.
std::size_t plan_job_index(const PlanHeader& header, std::size_t candidate, std::size_t overhang);

// A set-up: one candidate, overhang and spindle speed.
struct PlanSetup {
  std::size_t candidate = 0;  // index into PlanHeader::candidates
  std::size_t job = 0;        // index into PlanResult::jobs
  std::size_t speed_index = 0;
  double overhang_m = 0.0;
  double speed_rpm = 0.0;
  double depth_m = 0.0;         // used
  double stable_depth_m = 0.0;  // a_lim with the joints' constants
  double safe_depth_m = 0.0;    // a_safe
  double mrr_m3_per_s = 0.0;
  double power_w = 0.0;    // P(depth, speed)
  double torque_nm = 0.0;  // T(depth)
  DepthLimit limit = DepthLimit::None;
  double depth_margin = 0.0;  // stable_depth/depth − 1
  double probability = 0.0;   // P(stable at depth): the fraction of sampled joints whose envelope lies above (NaN unless sampled)
  double chatter_hz = 0.0;    // of the stability limit above (the lobe limiting at this speed)
  int lobe = -1;
  // The speeds around it where `depth` stays below the stable depth a_lim: how far the speed may
  // drift (or the lobes be off in speed) before this depth chatters.
  double window_low_rpm = 0.0, window_high_rpm = 0.0;
  std::string reason;  // why it is best: the pocket, the speed range's end, the limit
};

// One job's result. Primary (computed; what a part file keeps): stable_depth_m, safe_depth_m,
// chatter_hz, lobe, probability, modes_hz, warnings. The rest follows from them and the header.
struct PlanJob {
  std::size_t candidate = 0;
  std::size_t overhang_index = 0;
  double overhang_m = 0.0;
  std::vector<double> stable_depth_m;  // per speed; +inf where no lobe reaches
  std::vector<double> safe_depth_m;
  std::vector<double> chatter_hz;  // of the limiting lobe (NaN where none)
  std::vector<int> lobe;
  std::vector<double> probability;    // P(stable at depth_m) per speed (SafetyRule::Probability only; else empty)
  std::vector<double> modes_hz;       // peaks of the tool point |H| rising 10 % above their valleys
  std::vector<std::string> warnings;  // prefixed with the candidate and overhang
  // Derived.
  std::vector<double> depth_m;  // used (NaN where the envelope is not finite)
  std::vector<DepthLimit> limit;
  std::vector<double> mrr_m3_per_s;
  PlanSetup best;
};

struct PlanResult {
  PlanHeader header;
  std::vector<PlanJob> jobs;    // by job index
  std::vector<PlanSetup> best;  // the best set-up of each candidate, largest MRR first
  std::vector<std::string> warnings;
};

// One shard's jobs (a part of the plan): shard `index` of `count` holds the jobs j with j mod count
// = index (studies/shards.hpp: counted from 0).
struct PlanPart {
  PlanHeader header;
  int index = 0, count = 1;
  std::vector<PlanJob> jobs;  // primary members only, in job order
  // The study file the part was computed from, as its caller names it ("" unknown): kept in the
  // part file so that a merge can name the commands that redo a missing shard. Not in the
  // fingerprint (the same study under another path is the same plan).
  std::string study;
};

// The header of the plan run_plan would compute: checks the options and candidates (InvalidArgument
// naming `PlanOptions::<field>`, or `candidates[i]` and its field), filters the overhangs by the
// minimum overhang (InvalidArgument when a candidate has none left).
PlanHeader plan_header(const std::vector<PlanCandidate>& candidates, const PlanOptions& options);

// Runs the whole plan on every core. Throws InvalidArgument (options, candidates), InputError (an
// SH11 that is not a valid series), NumericalError (no positive stable depth anywhere: naming the
// candidate and overhang). Several failing jobs: the first job's error, for any thread count.
PlanResult run_plan(const std::vector<PlanCandidate>& candidates, const PlanOptions& options,
                    const ProgressCallback& progress = {});

// Shard `index` of `count` (0 ≤ index < count ≤ 100000): its jobs' primary results. Throws
// InvalidArgument for a shard that does not exist (check_shard: an index equal to the count is named
// as an array numbered from 1), and what run_plan throws.
PlanPart run_plan_part(const std::vector<PlanCandidate>& candidates, const PlanOptions& options, int index, int count,
                       const ProgressCallback& progress = {});

// The result of the whole plan from its parts (any order). Throws ShardSetError (an InputError)
// naming every problem at once — parts of different plans (fingerprint) or splits (shard count),
// shards given twice, shards missing — with the shards to run again and the parts to leave out
// (check_shard_set), and InputError naming the part that holds jobs that do not belong to it.
PlanResult merge_plan_parts(const std::vector<PlanPart>& parts, const std::vector<std::string>& sources);

// What check_shard_set needs of a part: its source, fingerprint, shard and study.
PartLabel plan_part_label(const PlanPart& part, const std::string& source);

// A 64-bit FNV-1a hash of the header's options, speeds and candidates (their names, overhangs and
// content: every number of the assembly, the SH11 and the sampled joint), so parts of different
// plans are not merged.
std::uint64_t plan_fingerprint(const PlanHeader& header);

// The model's tool point FRF (H of SHT11) on `grid` [Hz], refined where its phase turns faster than
// the lobes can follow. A lobe's speed is n = 60 f/(N(k + ε/2π)) with ε set by the phase of H (for a
// symmetric tool Δε = 2Δ∠H), and the envelope joins lobe points linearly in speed; across a lightly
// damped mode (a carbide tool's, ζ ~ 0.1 %: a few hertz wide) the points of an even 1 Hz grid lie
// hundreds of rpm apart on a lobe's steep wall, so walls and pockets come out tens of per cent too
// deep (the example at 103 mm showed a pocket that is not there). Every step across which ∠H
// turns by more than 0.25° is split evenly into parts turning by about 0.25° (at most 50 per step),
// repeated up to 4 times. Measured on the example (110 and 120 mm, the pocket walls near
// 10 000 rpm) against 0.02°: 2° leaves +23 %, 0.5° +2.1 %, 0.25° +0.46 %, 0.1° +0.1 %; 0.25° costs
// about 1.8× the points of the 1 Hz grid (9 000 instead of 4 991).
FrfSeries resolved_tool_point(const AssemblyModel& model, const std::vector<double>& grid);

// ---- The cut's mechanics (closed forms above) --------------------------------------------------

// Radial width of cut b = (D/2)(cos φ_st − cos φ_ex) [m] (a/D × D for up or down milling).
double radial_width_m(const CuttingConditions& cutting, double diameter_m);
// Mean torque per unit depth T(1) [N·m/m] and power per unit depth at `speed_rpm`, P(1, n) [W/m].
double torque_per_depth(const CuttingConditions& cutting, double diameter_m, double feed_per_tooth_m, double edge_n_per_m);
double power_per_depth(const CuttingConditions& cutting, double diameter_m, double feed_per_tooth_m, double edge_n_per_m,
                       double speed_rpm);

// The safety rule in words, as every output states it: "the stable depth / 1.25", "the depth stable
// with probability >= 0.95 (200 joint samples, seed 1)".
std::string safety_rule_text(const SafetyRule& rule);

// cm³/min per m³/s: MRR as machinists read it.
inline constexpr double kCubicCentimetresPerMinute = 6e7;

// ---- Figures -------------------------------------------------------------------------------------

// The stable depth (after the safety rule) [mm] as a map over spindle speed [rpm] × overhang [mm],
// one panel per candidate, with each overhang's best speed marked and the best set-up labelled.
plot::Figure plan_map_figure(const PlanResult& result);
// The tuning curve: the best MRR [cm³/min] and its spindle speed [rpm] against overhang [mm], one
// curve per candidate, the minimum overhang and the best set-up marked.
plot::Figure plan_tuning_figure(const PlanResult& result);

// ---- The study file ------------------------------------------------------------------------------

// A plan read from a study file (TOML; every key documented in examples/plan_bt40.toml).
struct PlanStudy {
  std::string name;
  std::vector<PlanCandidate> candidates;
  PlanOptions options;
  std::vector<std::string> inputs;    // every file read (the study, assemblies, SH11s, joint files)
  std::vector<std::string> warnings;  // implausible values ("file:line: key = …"), the assemblies' warnings
  std::vector<std::string> notes;     // the assemblies' notes (indefinite joints)
};

// Parses study TOML; paths inside are relative to `directory`. Throws InputError "file:line: …" for
// syntax errors, unknown (with the nearest valid key), missing or mistyped keys and values outside
// their range; IoError for a file it names that cannot be read; and what the files it names throw.
PlanStudy parse_plan_study(const std::string& text, const std::string& source, const std::string& directory);
PlanStudy load_plan_study(const std::string& path);

}  // namespace toolpoint
