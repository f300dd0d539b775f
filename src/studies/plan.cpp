// toolpoint study: the plan — set-ups and spindle speeds for the most metal removed without
// chatter (studies/plan.hpp). Units: SI, rpm, Hz.
#include "toolpoint/studies/plan.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <map>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"
#include "part_file.hpp"

namespace toolpoint {

namespace {

// Set-ups whose MRR lies within this fraction of the best are equally productive (a power-limited
// plateau differs only by rounding): the larger stability margin decides between them.
constexpr double kTie = 1e-9;

bool finite_positive(double x) { return std::isfinite(x) && x > 0.0; }

// The plan's fingerprint: FNV-1a (part_file.hpp) over the assemblies' numbers too.
struct Fnv : part_file::Fnv1a {
  using Fnv1a::add;
  void add(const std::optional<double>& x) {
    add(x.has_value());
    if (x) add(*x);
  }
  void add(const Material& m) {
    add(m.name);
    add(m.youngs_modulus);
    add(m.poisson);
    add(m.shear_modulus);
    add(m.density);
    add(m.loss_factor);
  }
  void add(const Segment& s) {
    add(s.length);
    add(static_cast<int>(s.shear_model));
    add(static_cast<std::uint64_t>(s.layers.size()));
    for (const Annulus& l : s.layers) {
      add(l.outer_diameter);
      add(l.inner_diameter);
      add(l.material);
      add(l.shear_coefficient);
    }
  }
  void add(const std::vector<Segment>& v) {
    add(static_cast<std::uint64_t>(v.size()));
    for (const Segment& s : v) add(s);
  }
  void add(const JointParameters& p) {
    for (int k = 0; k < 8; ++k) add(p[k]);
  }
  void add(const Joint& j) {
    add(j.rigid);
    add(j.parameters);
  }
  void add(const Assembly& a) {
    add(a.spindle.segments);
    add(static_cast<std::uint64_t>(a.spindle.bearings.size()));
    for (const Bearing& b : a.spindle.bearings) {
      add(b.position);
      add(b.stiffness);
      add(b.damping);
      add(b.rotational_stiffness);
      add(b.rotational_damping);
    }
    add(a.holder);
    const Tool& t = a.tool;
    add(t.material);
    add(t.length);
    add(t.overhang);
    add(t.diameter);
    add(t.shank_diameter);
    add(t.flute_length);
    add(t.flute_diameter_ratio);
    add(t.shear_coefficient);
    add(a.spindle_holder);
    add(a.holder_tool);
    add(static_cast<int>(a.shear_model));
    add(static_cast<int>(a.method));
    add(a.modal_terms);
    add(a.grid.start_hz);
    add(a.grid.stop_hz);
    add(a.grid.step_hz);
  }
};

std::uint64_t candidate_content(const PlanCandidate& c) {
  Fnv f;
  f.add(c.assembly);
  f.add(c.sh11.has_value());
  if (c.sh11) {
    f.add(c.sh11->frequency_hz);
    for (const Block& b : c.sh11->blocks)
      for (int k = 0; k < 4; ++k) {
        f.add(b(k / 2, k % 2).real());
        f.add(b(k / 2, k % 2).imag());
      }
  }
  f.add(c.uncertain_joint.has_value());
  if (c.uncertain_joint) {
    f.add(static_cast<int>(c.uncertain_joint->interface));
    f.add(c.uncertain_joint->parameters);
    f.add(c.uncertain_joint->uncertainty.has_value());
    if (c.uncertain_joint->uncertainty)
      for (Eigen::Index i = 0; i < 64; ++i) f.add(c.uncertain_joint->uncertainty->covariance(i / 8, i % 8));
  }
  return f.h;
}

std::string mm(double m) { return fmt::format("{:.1f} mm", 1e3 * m); }

}  // namespace

const char* to_string(DepthLimit limit) {
  switch (limit) {
    case DepthLimit::Stability: return "stability";
    case DepthLimit::Power: return "power";
    case DepthLimit::Torque: return "torque";
    case DepthLimit::Depth: return "depth";
    case DepthLimit::None: break;
  }
  return "none";
}

std::string safety_rule_text(const SafetyRule& rule) {
  return rule.kind == SafetyRule::Kind::Factor
             ? fmt::format("the stable depth / {:g}", rule.factor)
             : fmt::format("the depth stable with probability >= {:g} ({} joint samples, seed {})", rule.probability,
                           rule.samples, rule.seed);
}

// ---- The cut's mechanics ------------------------------------------------------------------------

double radial_width_m(const CuttingConditions& cutting, double diameter_m) {
  return 0.5 * diameter_m * (std::cos(cutting.engagement.entry_rad) - std::cos(cutting.engagement.exit_rad));
}

double torque_per_depth(const CuttingConditions& cutting, double diameter_m, double feed_per_tooth_m, double edge_n_per_m) {
  const Engagement& e = cutting.engagement;
  return cutting.teeth * diameter_m / (4.0 * kPi) *
         (cutting.tangential_coefficient * feed_per_tooth_m * (std::cos(e.entry_rad) - std::cos(e.exit_rad)) +
          edge_n_per_m * (e.exit_rad - e.entry_rad));
}

double power_per_depth(const CuttingConditions& cutting, double diameter_m, double feed_per_tooth_m, double edge_n_per_m,
                       double speed_rpm) {
  return torque_per_depth(cutting, diameter_m, feed_per_tooth_m, edge_n_per_m) * rad_s_of_rpm(speed_rpm);
}

// ---- Options ------------------------------------------------------------------------------------

CuttingConditions plan_cutting(const PlanOptions& options, double tool_diameter_m) {
  CuttingConditions c = options.lobes.cutting;
  c.diameter_m = tool_diameter_m;
  c.feed_per_tooth_m = options.feed_per_tooth_m;
  return c;
}

const std::vector<OptionField<PlanOptions>>& plan_fields() {
  using O = PlanOptions;
  // The plan file's [cut] holds these keys; the cap on c: no milling cutter takes a centimetre per
  // tooth, so such a value is millimetres given as metres.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "feed_per_tooth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .max = 0.01,
        .min_open = true,
        .help = "feed per tooth c, in metres (0.1 mm is 1e-4; no cutter takes over 10 mm per tooth: millimetres?)",
        .plan_key = "feed_per_tooth",
        .plausible = &plausible::kFeedPerTooth},
       [](O& o) -> double& { return o.feed_per_tooth_m; }},
      {{.name = "edge_coefficient_n_per_m",
        .kind = FieldKind::Real,
        .unit = "N/m",
        .min = 0.0,
        .help = "tangential edge force per unit depth K_te, in N/m (e.g. 2e4; 0: none), for the torque and power",
        .plan_key = "edge_coefficient",
        .plausible = &plausible::kEdgeCoefficient},
       [](O& o) -> double& { return o.edge_coefficient_n_per_m; }},
      {{.name = "max_depth_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .max = 1.0,
        .note = "0: no cap",
        .help = "the deepest cut the feature allows, in metres (e.g. 0.02)",
        .plan_key = "max_depth",
        .plausible = &plausible::kDepth},
       [](O& o) -> double& { return o.max_depth_m; }},
  };
  return fields;
}

const std::vector<OptionField<MachineLimits>>& machine_limits_fields() {
  using O = MachineLimits;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "power_w",
        .kind = FieldKind::Real,
        .unit = "W",
        .min = 0.0,
        .note = "0: no limit",
        .help = "the cutting power available at the tool, in watts (e.g. 15e3)",
        .plan_key = "power",
        .plausible = &plausible::kPower},
       [](O& o) -> double& { return o.power_w; }},
      {{.name = "torque_nm",
        .kind = FieldKind::Real,
        .unit = "N·m",
        .min = 0.0,
        .note = "0: no limit",
        .help = "the spindle torque, in N·m (e.g. 50)",
        .plan_key = "torque",
        .plausible = &plausible::kTorque},
       [](O& o) -> double& { return o.torque_nm; }},
      {{.name = "min_overhang_m",
        .kind = FieldKind::Real,
        .unit = "m",
        .min = 0.0,
        .max = 1.0,
        .note = "0: none",
        .help = "the reach the part needs: shorter overhangs are not planned, in metres (45 mm is 0.045)",
        .plan_key = "min_overhang",
        .plausible = &plausible::kOverhang},
       [](O& o) -> double& { return o.min_overhang_m; }},
  };
  return fields;
}

const std::vector<OptionField<SafetyRule>>& safety_rule_fields() {
  using O = SafetyRule;
  // The seed (a 64-bit integer, [safety] seed) and the kind (which of factor and probability the
  // file gives) are read by hand.
  static const std::vector<OptionField<O>> fields = {
      {{.name = "factor",
        .kind = FieldKind::Real,
        .min = 1.0,
        .max = 100.0,
        .help = "the depth used is the stable depth divided by it: 1 uses the limit itself, 1.25 keeps 20 % below",
        .plan_key = "factor"},
       [](O& o) -> double& { return o.factor; }},
      {{.name = "probability",
        .kind = FieldKind::Real,
        .min = 0.5,
        .max = 1.0,
        .max_open = true,
        .help = "the depth used is stable with at least this probability over the joints the identification allows "
                "(e.g. 0.95, not 95)",
        .plan_key = "probability"},
       [](O& o) -> double& { return o.probability; }},
      {{.name = "samples",
        .kind = FieldKind::Integer,
        .min = 20.0,
        .max = 100000.0,
        .help = "joints drawn for the probability rule (200 put the 5 % quantile within about ±1.5 % in probability)",
        .plan_key = "samples"},
       nullptr,
       [](O& o) -> int& { return o.samples; }},
  };
  return fields;
}

void PlanOptions::check() const {
  // The scalar fields' ranges first (plan_fields, machine_limits_fields, safety_rule_fields): the
  // plan's feed is the cut's, and a refusal names the field given.
  check_fields(plan_fields(), *this, "PlanOptions");
  check_fields(machine_limits_fields(), machine, "MachineLimits");
  check_fields(safety_rule_fields(), safety, "SafetyRule");
  {
    // The cut with a tool of any size (each candidate's is checked with the plan's header) and
    // some feed (checked below).
    PlanOptions any = *this;
    any.feed_per_tooth_m = finite_positive(feed_per_tooth_m) ? feed_per_tooth_m : 1e-4;
    LobesStudyOptions l = lobes;
    l.cutting = plan_cutting(any, 1.0);
    l.check();
  }
  const CuttingConditions& c = lobes.cutting;
  if (lobes.method == LobesMethod::ZeroOrder &&
      (!c.pitch_rad.empty() || c.helical() || !c.runout_m.empty() || c.process_damping_n_per_m > 0.0))
    throw InvalidArgument(
        "PlanOptions::lobes.cutting has a variable pitch, helix, runout or process damping, which the "
        "zero-order method (LobesStudyOptions::method) cannot take",
        "use the full-discretization method (fd)");
  parallel.check();
}

std::size_t plan_job_index(const PlanHeader& header, std::size_t candidate, std::size_t overhang) {
  std::size_t j = 0;
  for (std::size_t c = 0; c < candidate; ++c) j += header.candidates[c].overhangs_m.size();
  return j + overhang;
}

PlanHeader plan_header(const std::vector<PlanCandidate>& candidates, const PlanOptions& options) {
  options.check();
  if (candidates.empty()) throw InvalidArgument("the plan has no candidates", "give at least one assembly to plan");
  PlanHeader h;
  h.options = options;
  h.options.parallel = {};
  h.options.lobes.parallel = {};
  SpeedRange& sp = h.options.lobes.speeds;
  if (sp.points == 0) sp.points = options.lobes.method == LobesMethod::ZeroOrder ? 2000 : 200;
  h.speeds_rpm = sp.values();
  const double reach = options.machine.min_overhang_m;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const PlanCandidate& in = candidates[c];
    const std::string who = fmt::format("candidates[{}] ('{}')", c, in.name);
    if (in.name.empty())
      throw InvalidArgument(fmt::format("candidates[{}] has no name", c), "name every candidate (its rows in the tables)");
    for (std::size_t k = 0; k < c; ++k)
      if (candidates[k].name == in.name)
        throw InvalidArgument(fmt::format("{}: the name is also candidates[{}]'s", who, k), "give each candidate its own name");
    try {
      in.assembly.check();
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(fmt::format("{}: {}", who, e.what()), e.hint());
    }
    const std::vector<double> all = in.overhangs_m.empty() ? std::vector<double>{in.assembly.tool.overhang} : in.overhangs_m;
    for (std::size_t i = 0; i < all.size(); ++i) {
      const double L = all[i];
      if (!finite_positive(L))
        throw InvalidArgument(fmt::format("{}: overhangs_m[{}] = {} m must be > 0", who, i, L),
                              "give the tool's length outside the holder in metres");
      if (L > 1.0)
        throw InvalidArgument(fmt::format("{}: overhangs_m[{}] = {} m is over 1 m: millimetres?", who, i, L),
                              fmt::format("overhangs are in metres: {} mm is {:g} m", L, L / 1000.0));
      if (i > 0 && !(L > all[i - 1]))
        throw InvalidArgument(fmt::format("{}: overhangs_m must be strictly increasing: [{}] = {} m follows {} m", who, i, L,
                                          all[i - 1]),
                              "sort the overhangs and drop repeats");
    }
    if (options.safety.kind == SafetyRule::Kind::Probability) {
      if (!in.uncertain_joint || !in.uncertain_joint->uncertainty)
        throw InvalidArgument(
            fmt::format("{}: SafetyRule::probability needs a joint with uncertainty to sample (PlanCandidate::uncertain_joint)",
                        who),
            "give the candidate a band-fitted joint with [uncertainty] (write_joint_file), or use a safety factor");
    }
    if (in.uncertain_joint && in.sh11 && in.uncertain_joint->interface != JointInterface::HolderTool)
      throw InvalidArgument(
          fmt::format("{}: with a measured SH11 only the holder–tool joint can be sampled; {} holds the {} joint", who,
                      in.uncertain_joint->source, to_string(in.uncertain_joint->interface)),
          "the spindle–holder joint is inside the measured SH11: sample the holder–tool joint");
    PlanCandidateSummary s;
    s.name = in.name;
    s.measured_holder = in.sh11.has_value();
    s.sh11_name = in.sh11 ? in.sh11_name : std::string();
    s.uncertain_joint = in.uncertain_joint
                            ? (in.uncertain_joint->source.empty() ? std::string("joint") : in.uncertain_joint->source)
                            : std::string();
    s.tool_diameter_m = in.assembly.tool.diameter;
    s.flute_length_m = in.assembly.tool.flute_length;
    try {
      plan_cutting(options, s.tool_diameter_m).check();  // runout within this tool's radius
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(fmt::format("{}: {}", who, e.what()), e.hint());
    }
    // Overhang grids built as START + i·STEP land a rounding away from the minimum: 1e-9 relative.
    for (double L : all)
      if (L >= reach * (1.0 - 1e-9)) s.overhangs_m.push_back(L);
      else ++s.left_out;
    if (s.overhangs_m.empty())
      throw InvalidArgument(fmt::format("{}: every overhang ({} to {}) is shorter than MachineLimits::min_overhang_m = {}", who,
                                        mm(all.front()), mm(all.back()), mm(reach)),
                            "extend the candidate's overhangs to the reach the part needs, or lower the minimum overhang");
    s.content = candidate_content(in);
    h.jobs += s.overhangs_m.size();
    h.candidates.push_back(std::move(s));
  }
  h.fingerprint = plan_fingerprint(h);
  return h;
}

std::uint64_t plan_fingerprint(const PlanHeader& h) {
  Fnv f;
  f.add(std::string("toolpoint plan 2"));
  const PlanOptions& o = h.options;
  f.add(o.name);
  const LobesStudyOptions& l = o.lobes;
  f.add(static_cast<int>(l.method));
  part_file::add_fields(f, cutting_fields(), l.cutting);
  f.add(l.cutting.engagement.entry_rad);
  f.add(l.cutting.engagement.exit_rad);
  f.add(l.cutting.pitch_rad);
  f.add(l.cutting.helix_rad);
  f.add(l.cutting.runout_m);
  part_file::add_fields(f, speed_range_fields(), l.speeds);
  f.add(l.fit.band_hz.has_value());
  if (l.fit.band_hz) {
    f.add(l.fit.band_hz->first);
    f.add(l.fit.band_hz->second);
  }
  part_file::add_fields(f, modal_fit_fields(), l.fit);
  f.add(static_cast<int>(l.speed_model));
  part_file::add_fields(f, lobes_study_fields(), l);
  part_file::add_fields(f, plan_fields(), o);
  part_file::add_fields(f, machine_limits_fields(), o.machine);
  f.add(static_cast<int>(o.safety.kind));
  part_file::add_fields(f, safety_rule_fields(), o.safety);
  f.add(o.safety.seed);
  f.add(static_cast<std::uint64_t>(h.candidates.size()));
  for (const PlanCandidateSummary& c : h.candidates) {
    f.add(c.name);
    f.add(c.measured_holder);
    f.add(c.sh11_name);
    f.add(c.uncertain_joint);
    f.add(c.tool_diameter_m);
    f.add(c.flute_length_m);
    f.add(c.overhangs_m);
    f.add(static_cast<std::uint64_t>(c.left_out));
    f.add(c.content);
  }
  f.add(h.speeds_rpm);
  f.add(static_cast<std::uint64_t>(h.jobs));
  return f.h;
}

// ---- Derived numbers: the depth used, its limit, the MRR, the best set-up ------------------------

namespace {

// The depth used, its limit and the MRR at every speed (closed forms in plan.hpp).
void derive_depths(PlanJob& job, const PlanHeader& h) {
  const PlanOptions& o = h.options;
  const CuttingConditions& cut = o.lobes.cutting;
  const PlanCandidateSummary& cs = h.candidates[job.candidate];
  const double d = cs.tool_diameter_m;
  const double t1 = torque_per_depth(cut, d, o.feed_per_tooth_m, o.edge_coefficient_n_per_m);
  const double width = radial_width_m(cut, d);
  const double a_torque = o.machine.torque_nm > 0.0 ? o.machine.torque_nm / t1 : kInf;
  double a_cap = o.max_depth_m > 0.0 ? o.max_depth_m : kInf;
  if (cs.flute_length_m > 0.0) a_cap = std::min(a_cap, cs.flute_length_m);
  const std::size_t ns = h.speeds_rpm.size();
  job.depth_m.assign(ns, kNaN);
  job.limit.assign(ns, DepthLimit::None);
  job.mrr_m3_per_s.assign(ns, kNaN);
  for (std::size_t k = 0; k < ns; ++k) {
    const double n = h.speeds_rpm[k], safe = job.safe_depth_m[k];
    if (!(std::isfinite(safe) && safe >= 0.0)) continue;  // no lobe reaches this speed: its stability is unknown
    double a = safe;
    DepthLimit limit = DepthLimit::Stability;
    if (a_torque < a) {
      a = a_torque;
      limit = DepthLimit::Torque;
    }
    if (o.machine.power_w > 0.0) {
      const double a_power = o.machine.power_w / (t1 * rad_s_of_rpm(n));
      if (a_power < a) {
        a = a_power;
        limit = DepthLimit::Power;
      }
    }
    if (a_cap < a) {
      a = a_cap;
      limit = DepthLimit::Depth;
    }
    job.depth_m[k] = a;
    job.limit[k] = limit;
    job.mrr_m3_per_s[k] = a * width * o.feed_per_tooth_m * cut.teeth * n / 60.0;
  }
}

// Among set-ups within kTie of the largest MRR, the largest stability margin, then the first.
// `mrr`, `margin` per item; npos when no MRR is finite.
std::size_t best_of(const std::vector<double>& mrr, const std::vector<double>& margin) {
  double top = -kInf;
  for (double m : mrr)
    if (std::isfinite(m)) top = std::max(top, m);
  std::size_t best = std::string::npos;
  for (std::size_t k = 0; k < mrr.size(); ++k) {
    if (!(std::isfinite(mrr[k]) && mrr[k] >= top - kTie * std::abs(top))) continue;
    if (best == std::string::npos || margin[k] > margin[best]) best = k;
  }
  return best;
}

std::string reason_for(const PlanJob& job, const PlanHeader& h, const PlanSetup& s) {
  const PlanOptions& o = h.options;
  const std::size_t k = s.speed_index, ns = h.speeds_rpm.size();
  const int teeth = o.lobes.cutting.teeth;
  const std::string at_limit = s.lobe >= 0 ? fmt::format("lobe {}, chatter at {:.0f} Hz", s.lobe, s.chatter_hz)
                                           : std::string("no instability found below the ceiling");
  switch (s.limit) {
    case DepthLimit::Stability: {
      if (k + 1 == ns)
        return fmt::format(
            "the top of the speed range ({:.0f} rpm): the stable depth does not fall faster than the speed rises there ({})",
            s.speed_rpm, at_limit);
      if (k == 0) return fmt::format("the bottom of the speed range ({:.0f} rpm) ({})", s.speed_rpm, at_limit);
      // Climb the allowed depth from the best speed to the pocket's peak.
      const std::vector<double>& a = job.safe_depth_m;
      std::size_t p = k;
      const int dir = a[k + 1] > a[k] ? 1 : (a[k - 1] > a[k] ? -1 : 0);
      while (dir != 0) {
        const std::size_t q = dir > 0 ? p + 1 : p - 1;
        if ((dir > 0 && p + 1 >= ns) || (dir < 0 && p == 0) || !(a[q] > a[p])) break;
        p = q;
      }
      return fmt::format(
          "the stability pocket above lobe {}: the allowed depth peaks at {:.2f} mm at {:.0f} rpm (tooth passing {:.0f} Hz); "
          "depth × speed is largest at {:.0f} rpm ({})",
          s.lobe, 1e3 * a[p], h.speeds_rpm[p], teeth * h.speeds_rpm[p] / 60.0, s.speed_rpm, at_limit);
    }
    case DepthLimit::Power:
      return fmt::format(
          "the spindle's power ({:.3g} kW) limits the depth: the MRR is the same at every power-limited speed, and this one "
          "keeps the most distance from the stability limit ({:.0f} % above the depth used; {})",
          1e-3 * o.machine.power_w, 100.0 * s.depth_margin, at_limit);
    case DepthLimit::Torque:
      return fmt::format("the spindle's torque ({:.3g} N·m) limits the depth to {:.2f} mm; stable to {:.2f} mm here ({})",
                         o.machine.torque_nm, 1e3 * s.depth_m, 1e3 * s.stable_depth_m, at_limit);
    case DepthLimit::Depth: {
      const PlanCandidateSummary& cs = h.candidates[job.candidate];
      const bool flute = cs.flute_length_m > 0.0 && (o.max_depth_m <= 0.0 || cs.flute_length_m <= o.max_depth_m);
      return fmt::format("the depth is capped at {:.2f} mm ({}); stable to {:.2f} mm here ({})", 1e3 * s.depth_m,
                         flute ? "the tool's flute length" : "PlanOptions::max_depth_m", 1e3 * s.stable_depth_m, at_limit);
    }
    case DepthLimit::None: break;
  }
  return "no stable depth on the speed grid";
}

PlanSetup setup_at(const PlanJob& job, const PlanHeader& h, std::size_t job_index, std::size_t k) {
  const PlanOptions& o = h.options;
  const double d = h.candidates[job.candidate].tool_diameter_m;
  PlanSetup s;
  s.candidate = job.candidate;
  s.job = job_index;
  s.speed_index = k;
  s.overhang_m = job.overhang_m;
  s.speed_rpm = h.speeds_rpm[k];
  s.depth_m = job.depth_m[k];
  s.stable_depth_m = job.stable_depth_m[k];
  s.safe_depth_m = job.safe_depth_m[k];
  s.mrr_m3_per_s = job.mrr_m3_per_s[k];
  s.torque_nm = s.depth_m * torque_per_depth(o.lobes.cutting, d, o.feed_per_tooth_m, o.edge_coefficient_n_per_m);
  s.power_w = s.torque_nm * rad_s_of_rpm(s.speed_rpm);
  s.limit = job.limit[k];
  s.depth_margin = s.stable_depth_m / s.depth_m - 1.0;
  s.probability = job.probability.empty() ? kNaN : job.probability[k];
  s.chatter_hz = job.chatter_hz[k];
  s.lobe = job.lobe[k];
  const auto within = [&](std::size_t q) { return std::isfinite(job.stable_depth_m[q]) && s.depth_m < job.stable_depth_m[q]; };
  std::size_t lo = k, hi = k;
  while (lo > 0 && within(lo - 1)) --lo;
  while (hi + 1 < h.speeds_rpm.size() && within(hi + 1)) ++hi;
  s.window_low_rpm = h.speeds_rpm[lo];
  s.window_high_rpm = h.speeds_rpm[hi];
  s.reason = reason_for(job, h, s);
  return s;
}

// A set-up that does not exist (no finite MRR): NaN numbers.
PlanSetup no_setup(const PlanJob& job, std::size_t job_index) {
  PlanSetup s;
  s.candidate = job.candidate;
  s.job = job_index;
  s.overhang_m = job.overhang_m;
  s.speed_rpm = s.depth_m = s.stable_depth_m = s.safe_depth_m = s.mrr_m3_per_s = s.power_w = s.torque_nm = kNaN;
  s.depth_margin = s.probability = s.chatter_hz = s.window_low_rpm = s.window_high_rpm = kNaN;
  s.reason = "no stable depth on the speed grid";
  return s;
}

void finish_job(PlanJob& job, const PlanHeader& h, std::size_t job_index) {
  derive_depths(job, h);
  std::vector<double> margin(job.depth_m.size());
  for (std::size_t k = 0; k < margin.size(); ++k) margin[k] = job.stable_depth_m[k] / job.depth_m[k];
  const std::size_t k = best_of(job.mrr_m3_per_s, margin);
  // Nothing removed at any speed (no stable depth: a set-up unstable on its own) is no set-up,
  // not the slowest speed at depth 0.
  job.best = k == std::string::npos || !(job.mrr_m3_per_s[k] > 0.0) ? no_setup(job, job_index) : setup_at(job, h, job_index, k);
}

// "40.0–45.5 mm" for the overhangs of a candidate's jobs (listed by index).
std::string overhang_list(const PlanCandidateSummary& cs, const std::vector<std::size_t>& which) {
  if (which.size() == cs.overhangs_m.size()) return "every overhang";
  std::string s;
  constexpr std::size_t kShown = 5;
  for (std::size_t q = 0; q < which.size() && q < kShown; ++q)
    s += fmt::format("{}{:.1f}", q ? ", " : "", 1e3 * cs.overhangs_m[which[q]]);
  if (which.size() > kShown) s += fmt::format(", … ({} of {})", which.size(), cs.overhangs_m.size());
  return s + " mm";
}

PlanResult assemble(PlanHeader header, std::vector<PlanJob> jobs) {
  PlanResult r;
  r.header = std::move(header);
  r.jobs = std::move(jobs);
  const PlanHeader& h = r.header;
  for (std::size_t j = 0; j < r.jobs.size(); ++j) finish_job(r.jobs[j], h, j);
  std::size_t j0 = 0;
  for (std::size_t c = 0; c < h.candidates.size(); ++c) {
    const PlanCandidateSummary& cs = h.candidates[c];
    const std::size_t nj = cs.overhangs_m.size();
    if (cs.left_out > 0)
      r.warnings.push_back(
          fmt::format("candidate '{}': {} overhang(s) shorter than the minimum overhang {:.1f} mm were not planned", cs.name,
                      cs.left_out, 1e3 * h.options.machine.min_overhang_m));
    // Job warnings, each message once with the overhangs it came from.
    std::vector<std::pair<std::string, std::vector<std::size_t>>> seen;
    for (std::size_t i = 0; i < nj; ++i)
      for (const std::string& w : r.jobs[j0 + i].warnings) {
        auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& x) { return x.first == w; });
        if (it == seen.end()) seen.push_back({w, {i}});
        else it->second.push_back(i);
      }
    for (const auto& [w, which] : seen)
      r.warnings.push_back(fmt::format("candidate '{}' ({}): {}", cs.name, overhang_list(cs, which), w));
    std::vector<double> mrr(nj), margin(nj);
    for (std::size_t i = 0; i < nj; ++i) {
      mrr[i] = r.jobs[j0 + i].best.mrr_m3_per_s;
      margin[i] = r.jobs[j0 + i].best.depth_margin;
    }
    const std::size_t i = best_of(mrr, margin);
    if (i == std::string::npos) {
      r.warnings.push_back(fmt::format("candidate '{}': no stable depth at any overhang and speed", cs.name));
    } else {
      r.best.push_back(r.jobs[j0 + i].best);
      if (nj > 1 && (i == 0 || i + 1 == nj) && !(i == 0 && cs.left_out > 0))
        r.warnings.push_back(
            fmt::format("candidate '{}': the best overhang, {:.1f} mm, is the {} one planned: a {} overhang may remove more",
                        cs.name, 1e3 * cs.overhangs_m[i], i == 0 ? "shortest" : "longest", i == 0 ? "shorter" : "longer"));
    }
    j0 += nj;
  }
  std::stable_sort(r.best.begin(), r.best.end(),
                   [](const PlanSetup& a, const PlanSetup& b) { return a.mrr_m3_per_s > b.mrr_m3_per_s; });
  return r;
}

// ---- One job's computed numbers -------------------------------------------------------------------

struct Envelope {
  std::vector<double> depth_m, chatter_hz;
  std::vector<int> lobe;
  std::vector<std::string> warnings;
};

// The stable envelope of a symmetric tool with tool point FRF `g` (the lobes study's method). A
// set-up whose tool point is not passive (a mode with negative damping: passivity_violation's
// second case) chatters at any depth: its stable depth is 0 at every speed, and it says why, so a
// long overhang of a doubtful joint loses the plan instead of stopping it.
Envelope stable_envelope(const FrfSeries& g, const std::string& name, const LobesStudyOptions& lo) {
  std::vector<EnvelopePoint> env;
  Envelope out;
  if (const auto v = passivity_violation(g)) {
    out.depth_m.assign(lo.speeds.points, 0.0);
    out.chatter_hz.assign(lo.speeds.points, v->frequency_hz);
    out.lobe.assign(lo.speeds.points, -1);
    // Without the numbers, so that the plan's summary groups the overhangs it holds for.
    (void)name;
    out.warnings.push_back(
        v->violating == v->peaks
            ? "the tool point FRF has Im G > 0 at every resonance peak: not a passive point receptance in the e^{iωt} "
              "convention (data in the conjugate convention, or of the opposite sign?); its stable depth is taken as 0"
            : "the tool point FRF has Im G > 0 at a resonance peak beside passive ones: a mode of negative damping (as a "
              "joint whose damping matrix is not positive definite gives), so the set-up is unstable at any depth of cut; "
              "its stable depth is taken as 0");
    return out;
  }
  MillingFrfs frfs;
  frfs.xx = g;
  if (lo.method == LobesMethod::ZeroOrder) {
    ZeroOrderOptions zo;
    zo.lobes = lo.lobes;
    zo.speeds = lo.speeds;
    zo.max_depth_m = lo.max_depth_m;
    ZeroOrderResult z = zero_order_lobes(frfs, lo.cutting, zo);
    env = std::move(z.envelope);
    out.warnings = std::move(z.warnings);
  } else {
    LobesInput in;
    in.frfs = std::move(frfs);
    in.frf_name = name;
    LobesStudyOptions o = lo;
    o.parallel.threads = 1;                  // the plan runs jobs (or samples) in parallel
    o.speed_model = SpeedModel::Standstill;  // one FRF here (the job says when that is not the speed model asked for)
    o.speed_nodes = 0;
    o.extrapolate_bearings = false;
    LobesStudyResult r = run_lobes_study(in, o);
    env = std::move(r.envelope);
    out.warnings = std::move(r.warnings);
  }
  for (const EnvelopePoint& e : env) {
    out.depth_m.push_back(e.depth_m);
    out.chatter_hz.push_back(e.chatter_hz);
    out.lobe.push_back(e.lobe);
  }
  return out;
}

// The stable envelope of assembly `a` at speed (LobesStudyOptions::speed_model: the x–y FRF at
// each speed, lobes_at_speed), on the lobes study's speeds, one thread (the plan runs jobs in parallel).
Envelope speed_envelope(const Assembly& a, const std::string& name, const LobesStudyOptions& lo) {
  LobesInput in;
  in.assembly = a;
  in.frf_name = name;
  LobesStudyOptions o = lo;
  o.parallel.threads = 1;
  LobesStudyResult r = run_lobes_study(in, o);
  Envelope out;
  for (const EnvelopePoint& e : r.envelope) {
    out.depth_m.push_back(e.depth_m);
    out.chatter_hz.push_back(e.chatter_hz);
    out.lobe.push_back(e.lobe);
  }
  out.warnings = std::move(r.warnings);
  return out;
}

}  // namespace

FrfSeries resolved_tool_point(const AssemblyModel& model, const std::vector<double>& grid) {
  constexpr double kMaxTurn = radians_of(0.25);
  FrfSeries g = entry(model.tool_point(grid), 0);
  for (int level = 0; level < 4; ++level) {
    const std::size_t n = g.size();
    std::vector<double> extra;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double turn = std::abs(std::arg(g.values[i + 1] / g.values[i]));
      if (!(turn > kMaxTurn)) continue;
      const int parts = static_cast<int>(std::min(50.0, std::ceil(turn / kMaxTurn)));
      const double h = (g.frequency_hz[i + 1] - g.frequency_hz[i]) / parts;
      for (int q = 1; q < parts; ++q) extra.push_back(g.frequency_hz[i] + q * h);
    }
    if (extra.empty()) break;
    const FrfSeries e = entry(model.tool_point(extra), 0);  // increasing: the steps are in order
    FrfSeries merged;
    merged.frequency_hz.reserve(n + e.size());
    merged.values.reserve(n + e.size());
    std::size_t p = 0, q = 0;
    while (p < n || q < e.size()) {
      const bool take_old = q == e.size() || (p < n && g.frequency_hz[p] <= e.frequency_hz[q]);
      const FrfSeries& from = take_old ? g : e;
      const std::size_t k = take_old ? p++ : q++;
      if (!merged.frequency_hz.empty() && !(from.frequency_hz[k] > merged.frequency_hz.back()))
        continue;  // a point already there
      merged.frequency_hz.push_back(from.frequency_hz[k]);
      merged.values.push_back(from.values[k]);
    }
    g = std::move(merged);
  }
  return g;
}

namespace {

// The tool point FRF (H of SHT11) of `a`: the model's (resolved), or the measured SH11 coupled to
// its tool on SH11's own grid (a measurement is not interpolated).
FrfSeries tool_point_frf(const PlanCandidate& c, const Assembly& a) {
  if (c.sh11) return entry(couple_tool(a, *c.sh11, c.sh11_name), 0);
  return resolved_tool_point(AssemblyModel(a), a.grid.values());
}

// What needs the model: the envelopes (nominal and sampled), the allowed depth, the probability
// at the depth used, the modes. `samples` on `sample_threads` (the probability rule).
PlanJob compute_job(const PlanCandidate& cand, const PlanHeader& h, std::size_t c, std::size_t i,
                    const std::vector<JointParameters>& samples, const ParallelOptions& sample_threads,
                    const ProgressCallback& progress) {
  const PlanCandidateSummary& cs = h.candidates[c];
  PlanJob job;
  job.candidate = c;
  job.overhang_index = i;
  job.overhang_m = cs.overhangs_m[i];
  const std::string where = fmt::format("candidate '{}', overhang {} m", cs.name, job.overhang_m);
  Assembly a;
  try {
    // A sampled joint file's joint is the nominal one (PlanCandidate::uncertain_joint).
    a = with_overhang(cand.uncertain_joint ? with_joint(cand.assembly, *cand.uncertain_joint) : cand.assembly, job.overhang_m);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("{}: {}", where, e.what()), e.hint());
  }
  const std::string frf_name = fmt::format("the tool point FRF of '{}' at {:.1f} mm", cs.name, 1e3 * job.overhang_m);
  // The time domain searches depths up to a ceiling: by default the deepest cut the plan could use
  // (the flute length or the depth cap), not its own guess, so no usable pocket is cut off.
  LobesStudyOptions lobes = h.options.lobes;
  lobes.cutting = plan_cutting(h.options, cs.tool_diameter_m);
  if (time_domain(lobes.method) && lobes.max_depth_m == 0.0)
    lobes.max_depth_m = std::max(cs.flute_length_m, h.options.max_depth_m);
  // At speed (the assembly's bearings, or LobesStudyOptions::speed_model): the lobes (either
  // method) of the x–y FRF at each speed; a measured SH11 keeps the standstill FRF, said.
  const bool wants_speed = lobes_at_speed(a, lobes.speed_model);
  const bool at_speed = wants_speed && !cand.sh11;
  const auto envelope_of = [&](const Assembly& x) {
    return at_speed ? speed_envelope(x, frf_name, lobes) : stable_envelope(tool_point_frf(cand, x), frf_name, lobes);
  };
  FrfSeries g;
  Envelope nominal;
  try {
    g = tool_point_frf(cand, a);
    nominal = envelope_of(a);
  } catch (const NumericalError& e) {
    throw NumericalError(fmt::format("{}: {}", where, e.what()), e.hint());
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("{}: {}", where, e.what()), e.hint());
  }
  for (const Peak& p : find_peaks(g, PeakOptions{0.1})) job.modes_hz.push_back(p.frequency_hz);
  job.stable_depth_m = std::move(nominal.depth_m);
  job.chatter_hz = std::move(nominal.chatter_hz);
  job.lobe = std::move(nominal.lobe);
  job.warnings = a.warnings();  // what the joints' sources say against them
  for (const std::string& w : nominal.warnings)
    if (std::find(job.warnings.begin(), job.warnings.end(), w) == job.warnings.end()) job.warnings.push_back(w);
  if (wants_speed && !at_speed)
    job.warnings.push_back(
        "the tool point FRF from the measured SH11 is the standstill one: the lobes do not follow the bearings' speed "
        "tables or x–y values");
  if (std::none_of(job.stable_depth_m.begin(), job.stable_depth_m.end(), [](double d) { return std::isfinite(d); }))
    throw NumericalError(fmt::format("{}: no lobe reaches any speed of {}–{} rpm", where, h.speeds_rpm.front(),
                                     h.speeds_rpm.back()),
                         "widen the FRF's frequency range or the speed range");

  const std::size_t ns = h.speeds_rpm.size();
  job.safe_depth_m.resize(ns);
  if (h.options.safety.kind == SafetyRule::Kind::Factor) {
    for (std::size_t k = 0; k < ns; ++k) job.safe_depth_m[k] = job.stable_depth_m[k] / h.options.safety.factor;
    if (progress) progress(1.0);
    return job;
  }
  // The probability rule: each sampled joint's envelope in its own slot, then per speed the
  // type-7 quantile at 1 − p, and the fraction of samples stable at the depth used.
  std::vector<std::vector<double>> depth(samples.size());
  parallel_for(
      samples.size(), sample_threads,
      [&](std::size_t s) {
        JointFile js = *cand.uncertain_joint;
        js.parameters = samples[s];
        try {
          depth[s] = envelope_of(with_joint(a, js)).depth_m;
        } catch (const Error& e) {
          throw NumericalError(fmt::format("{}, joint sample {} of {}: {}", where, s + 1, samples.size(), e.what()), e.hint());
        }
      },
      progress);
  std::vector<double> at(samples.size());
  for (std::size_t k = 0; k < ns; ++k) {
    for (std::size_t s = 0; s < samples.size(); ++s) at[s] = depth[s][k];
    job.safe_depth_m[k] = quantile(at, 1.0 - h.options.safety.probability);
  }
  PlanJob used = job;  // the depth used needs the machine's limits
  derive_depths(used, h);
  job.probability.assign(ns, kNaN);
  for (std::size_t k = 0; k < ns; ++k) {
    if (!std::isfinite(used.depth_m[k])) continue;
    std::size_t above = 0;
    for (std::size_t s = 0; s < samples.size(); ++s) above += depth[s][k] > used.depth_m[k];
    job.probability[k] = static_cast<double>(above) / static_cast<double>(samples.size());
  }
  return job;
}

}  // namespace

// ---- The plan, whole or in parts ------------------------------------------------------------------

PlanPart run_plan_part(const std::vector<PlanCandidate>& candidates, const PlanOptions& options, int index, int count,
                       const ProgressCallback& progress) {
  check_shard({index, count});
  PlanPart part;
  part.header = plan_header(candidates, options);
  part.index = index;
  part.count = count;
  const PlanHeader& h = part.header;
  struct Item {
    std::size_t candidate, overhang;
  };
  std::vector<Item> all, mine;  // by job index
  for (std::size_t c = 0; c < h.candidates.size(); ++c)
    for (std::size_t i = 0; i < h.candidates[c].overhangs_m.size(); ++i) all.push_back({c, i});
  for (std::size_t j : shard_jobs(all.size(), {index, count})) mine.push_back(all[j]);
  // The same draws for every overhang of a candidate: overhangs compared on common random numbers.
  std::vector<std::vector<JointParameters>> samples(candidates.size());
  const bool sampled = options.safety.kind == SafetyRule::Kind::Probability;
  if (sampled)
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      const JointFile& jf = *candidates[c].uncertain_joint;
      samples[c] = sample_joints(jf.parameters, jf.uncertainty->covariance, options.safety.samples, options.safety.seed);
    }
  part.jobs.resize(mine.size());
  const std::size_t cores = static_cast<std::size_t>(options.parallel.resolved(std::numeric_limits<std::size_t>::max()));
  if (sampled && mine.size() < cores) {
    // Fewer jobs than threads: one job at a time, its samples in parallel.
    for (std::size_t q = 0; q < mine.size(); ++q) {
      const double n = static_cast<double>(mine.size());
      const auto part_progress = [&](double f) {
        if (progress) progress((static_cast<double>(q) + f) / n);
      };
      part.jobs[q] = compute_job(candidates[mine[q].candidate], h, mine[q].candidate, mine[q].overhang,
                                 samples[mine[q].candidate], options.parallel, part_progress);
    }
  } else {
    parallel_for(
        mine.size(), options.parallel,
        [&](std::size_t q) {
          part.jobs[q] = compute_job(candidates[mine[q].candidate], h, mine[q].candidate, mine[q].overhang,
                                     samples[mine[q].candidate], ParallelOptions{1}, {});
        },
        progress);
  }
  return part;
}

PlanResult run_plan(const std::vector<PlanCandidate>& candidates, const PlanOptions& options, const ProgressCallback& progress) {
  PlanPart part = run_plan_part(candidates, options, 0, 1, progress);
  return assemble(std::move(part.header), std::move(part.jobs));
}

PartLabel plan_part_label(const PlanPart& part, const std::string& source) { return part_file::label_of(part, source); }

PlanResult merge_plan_parts(const std::vector<PlanPart>& parts, const std::vector<std::string>& sources) {
  const std::size_t n = parts.empty() ? 0 : parts.front().header.jobs;
  const PlanHeader* h = parts.empty() ? nullptr : &parts.front().header;
  std::vector<PlanJob> jobs = part_file::merged_jobs(
      parts, sources, "plan", "run_plan_part", n, [](const PlanPart& p) -> const std::vector<PlanJob>& { return p.jobs; },
      [h](const PlanJob& job, const std::string& source) {
        if (job.candidate >= h->candidates.size() || job.overhang_index >= h->candidates[job.candidate].overhangs_m.size())
          throw InputError(fmt::format("{}: a job of candidate {} overhang {} that the plan does not have", source, job.candidate,
                                       job.overhang_index));
        return plan_job_index(*h, job.candidate, job.overhang_index);
      });
  return assemble(*h, std::move(jobs));
}

}  // namespace toolpoint
