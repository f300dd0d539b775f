// The option-field tables (option_fields.hpp) tested against an independent expectation: each
// field written down here by hand — its Options type and name, the edges of its valid range as the
// hand-written checks had them, a typical valid value, its CLI flag and unit, its plan key, and
// the member read and written directly — so that a table that drifts from what the surfaces did
// (a range edge, a unit, a key) fails, which comparing the table with itself could not.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/identify/forward_check.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/stability/pitch.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/plan.hpp"

namespace toolpoint::testing {

/// One field as expected, on the options `Whole` whose check() judges it (the field may live in a
/// nested type: `type` names the type the message must name).
template <class Whole>
struct ExpectedField {
  std::string type;  // "MachineLimits": check() must name "MachineLimits::power_w"
  std::string name;  // "power_w"
  bool integer = false;
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  double typical = 0.0;       // valid, not the default, plausible
  std::string flag;           // "--max-depth" ("" none)
  std::string cli_unit;       // the unit in the flag's --help ("mm", "%", "-")
  double cli_per_unit = 1.0;  // CLI value = SI value × this
  std::string plan_key;       // "machine.power" ("" none)
  std::function<double(const Whole&)> get;
  std::function<void(Whole&, double)> set;
};

// The getter and setter of a member, read and written directly (not through the table).
#define TOOLPOINT_MEMBER(Whole, member)                         \
  [](const Whole& o) { return static_cast<double>(o.member); }, \
      [](Whole& o, double v) { o.member = static_cast<decltype(o.member)>(v); }

/// A value just past an edge, outward (dir −1 below lo, +1 above hi): the next double, or the
/// next integer.
inline double beyond(double edge, int dir, bool integer) {
  return integer ? edge + dir : std::nextafter(edge, dir * std::numeric_limits<double>::infinity());
}

/// A value just outside the expected range, in the field's unit: the next integer, the open edge
/// itself, half as much again past the upper edge, or one below the lower.
template <class Whole>
double outside(const ExpectedField<Whole>& e) {
  if (e.integer) return e.hi + 1.0;
  if (std::isfinite(e.hi)) return e.hi_open ? e.hi : e.hi * 1.5;
  return e.lo_open ? e.lo : e.lo - 1.0;
}

/// `value` [the field's unit] as typed on the command line, in the CLI's unit: an integer in full.
template <class Whole>
std::string cli_text(const ExpectedField<Whole>& e, double value) {
  return e.integer ? std::to_string(static_cast<long long>(value)) : fmt::format("{:g}", value * e.cli_per_unit);
}

/// The line of `help` (a command's --help) that registers `flag`, or "" where none does.
inline std::string help_line(const std::string& help, const std::string& flag) {
  for (std::size_t at = help.find(flag + " "); at != std::string::npos; at = help.find(flag + " ", at + 1)) {
    const std::size_t start = help.rfind('\n', at) + 1;
    if (help.find_first_not_of(' ', start) != at) continue;  // named in another option's help
    return help.substr(start, help.find('\n', at) - start);
  }
  return "";
}

/// check() on `valid` with the field at its typical value (accepted), at each finite edge and one
/// double (or one) past it: accepted at a closed edge, refused at an open one and past either, the
/// refusal naming `type::name`.
template <class Whole>
void expect_edges(const std::vector<ExpectedField<Whole>>& fields, const Whole& valid) {
  ASSERT_NO_THROW(valid.check());
  for (const ExpectedField<Whole>& e : fields) {
    SCOPED_TRACE(e.type + "::" + e.name);
    const auto judged = [&](double v, bool accepted) {
      Whole o = valid;
      e.set(o, v);
      try {
        o.check();
        EXPECT_TRUE(accepted) << "accepted " << v;
      } catch (const InvalidArgument& x) {
        EXPECT_FALSE(accepted) << "refused " << v << ": " << x.what();
        EXPECT_NE(std::string(x.what()).find(e.type + "::" + e.name), std::string::npos) << x.what();
      }
    };
    judged(e.typical, true);
    if (std::isfinite(e.lo)) {
      judged(e.lo, !e.lo_open);
      judged(beyond(e.lo, -1, e.integer), false);
    }
    if (std::isfinite(e.hi)) {
      judged(e.hi, !e.hi_open);
      judged(beyond(e.hi, 1, e.integer), false);
    }
  }
}

/// The table of `Part` (reached from `Whole` by `part`) holds exactly the expected fields of its
/// type, of their kind, with their flag, CLI unit and factor, and plan key (its last component);
/// its accessor reaches the member the expectation names (set directly, read through the table,
/// and the other way).
template <class Whole, class Part>
void expect_table(const std::vector<OptionField<Part>>& table, const std::vector<ExpectedField<Whole>>& fields,
                  const std::string& type, Part& (*part)(Whole&)) {
  std::set<std::string> expected, got;
  for (const ExpectedField<Whole>& e : fields)
    if (e.type == type) expected.insert(e.name);
  for (const OptionField<Part>& f : table) got.insert(f.spec.name);
  EXPECT_EQ(got, expected) << type;
  for (const ExpectedField<Whole>& e : fields) {
    if (e.type != type) continue;
    SCOPED_TRACE(type + "::" + e.name);
    const OptionField<Part>* f = nullptr;
    for (const OptionField<Part>& x : table)
      if (e.name == x.spec.name) f = &x;
    if (!f) continue;
    const FieldSpec& s = f->spec;
    EXPECT_EQ(s.kind == FieldKind::Integer, e.integer);
    EXPECT_EQ(field_flag(s), e.flag);
    if (!e.flag.empty()) {
      EXPECT_EQ(std::string(s.cli_unit ? s.cli_unit : *s.unit ? s.unit : "-"), e.cli_unit);
      EXPECT_DOUBLE_EQ(s.cli_per_unit, e.cli_per_unit);  // 180/π computed or written: within 4 ulps
    }
    const std::string key = e.plan_key.substr(e.plan_key.rfind('.') + 1);
    EXPECT_EQ(std::string(s.plan_key ? s.plan_key : ""), key);
    Whole w{};
    e.set(w, e.typical);
    EXPECT_EQ(f->get(part(w)), e.typical);
    Whole v{};
    f->set(part(v), e.typical);
    EXPECT_EQ(e.get(v), e.typical);
  }
}

/// PlanOptions' scalar fields, MachineLimits' and SafetyRule's as the hand-written PlanOptions::check
/// and the plan file's readers had them (docs/planning.md's keys), before their tables.
inline std::vector<ExpectedField<PlanOptions>> plan_expected_fields() {
  using P = PlanOptions;
  return {
      {"PlanOptions", "feed_per_tooth_m", false, 0.0, 0.01, true, false, 2e-4, "", "", 1.0, "cut.feed_per_tooth",
       TOOLPOINT_MEMBER(P, feed_per_tooth_m)},
      {"PlanOptions", "edge_coefficient_n_per_m", false, 0.0, kInf, false, false, 2e4, "", "", 1.0, "cut.edge_coefficient",
       TOOLPOINT_MEMBER(P, edge_coefficient_n_per_m)},
      {"PlanOptions", "max_depth_m", false, 0.0, 1.0, false, false, 0.02, "", "", 1.0, "cut.max_depth",
       TOOLPOINT_MEMBER(P, max_depth_m)},
      {"MachineLimits", "power_w", false, 0.0, kInf, false, false, 15e3, "", "", 1.0, "machine.power",
       TOOLPOINT_MEMBER(P, machine.power_w)},
      {"MachineLimits", "torque_nm", false, 0.0, kInf, false, false, 50.0, "", "", 1.0, "machine.torque",
       TOOLPOINT_MEMBER(P, machine.torque_nm)},
      {"MachineLimits", "min_overhang_m", false, 0.0, 1.0, false, false, 0.045, "", "", 1.0, "machine.min_overhang",
       TOOLPOINT_MEMBER(P, machine.min_overhang_m)},
      {"SafetyRule", "factor", false, 1.0, 100.0, false, false, 1.5, "", "", 1.0, "safety.factor",
       TOOLPOINT_MEMBER(P, safety.factor)},
      {"SafetyRule", "probability", false, 0.5, 1.0, false, true, 0.9, "", "", 1.0, "safety.probability",
       TOOLPOINT_MEMBER(P, safety.probability)},
      {"SafetyRule", "samples", true, 20.0, 100000.0, false, false, 50.0, "", "", 1.0, "safety.samples",
       TOOLPOINT_MEMBER(P, safety.samples)},
  };
}

/// PitchChoiceOptions' numeric fields as the hand-written PitchChoiceOptions::check has them and
/// `toolpoint pitch` had its flags (degrees for the angles, % for the robustness, mm for the depth).
inline std::vector<ExpectedField<PitchChoiceOptions>> pitch_expected_fields() {
  constexpr double kTwoPi = 6.283185307179586;  // 2π, the angles' open upper edge
  constexpr double kDeg = 57.295779513082323;   // degrees per radian
  using P = PitchChoiceOptions;
  return {
      {"PitchChoiceOptions", "speed_rpm", false, 0.0, kInf, true, false, 5000.0, "--rpm", "rpm", 1.0, "",
       TOOLPOINT_MEMBER(P, speed_rpm)},
      {"PitchChoiceOptions", "min_pitch_rad", false, 0.0, kTwoPi, false, true, 1.4, "--min-pitch", "degrees", kDeg, "",
       TOOLPOINT_MEMBER(P, min_pitch_rad)},
      {"PitchChoiceOptions", "max_pitch_rad", false, 0.0, kTwoPi, false, true, 1.8, "--max-pitch", "degrees", kDeg, "",
       TOOLPOINT_MEMBER(P, max_pitch_rad)},
      {"PitchChoiceOptions", "chatter_hz", false, 0.0, kInf, false, false, 900.0, "--chatter", "Hz", 1.0, "",
       TOOLPOINT_MEMBER(P, chatter_hz)},
      {"PitchChoiceOptions", "window", false, 0.0, 1.0, true, false, 0.3, "--window", "-", 1.0, "", TOOLPOINT_MEMBER(P, window)},
      {"PitchChoiceOptions", "search_points", true, 3.0, 201.0, false, false, 21.0, "--search-points", "-", 1.0, "",
       TOOLPOINT_MEMBER(P, search_points)},
      {"PitchChoiceOptions", "robustness", false, 0.0, 0.2, false, false, 0.05, "--robustness", "% of ΔP", 100.0, "",
       TOOLPOINT_MEMBER(P, robustness)},
      {"PitchChoiceOptions", "steps", true, 4.0, 2000.0, false, false, 100.0, "--intervals", "-", 1.0, "",
       TOOLPOINT_MEMBER(P, steps)},
      {"PitchChoiceOptions", "degree", true, 1.0, 3.0, false, false, 1.0, "", "", 1.0, "", TOOLPOINT_MEMBER(P, degree)},
      {"PitchChoiceOptions", "max_depth_m", false, 0.0, kInf, false, false, 0.005, "--max-depth", "mm", 1e3, "",
       TOOLPOINT_MEMBER(P, max_depth_m)},
      {"PitchChoiceOptions", "depth_steps", true, 4.0, 10000.0, false, false, 100.0, "--depth-steps", "-", 1.0, "",
       TOOLPOINT_MEMBER(P, depth_steps)},
  };
}

/// SimulationOptions' scalar fields (but the memory limit) as the hand-written
/// SimulationOptions::check had them and `toolpoint simulate` had its flags.
inline std::vector<ExpectedField<SimulationOptions>> simulation_expected_fields() {
  using S = SimulationOptions;
  return {
      {"SimulationOptions", "revolutions", true, 2.0, 1e6, false, false, 60.0, "--revolutions", "-", 1.0, "",
       TOOLPOINT_MEMBER(S, revolutions)},
      {"SimulationOptions", "steps_per_tooth", true, 4.0, 1e6, false, false, 80.0, "--steps", "-", 1.0, "",
       TOOLPOINT_MEMBER(S, steps_per_tooth)},
      {"SimulationOptions", "slices", true, 0.0, 1000.0, false, false, 5.0, "--slices", "-", 1.0, "",
       TOOLPOINT_MEMBER(S, slices)},
      {"SimulationOptions", "analysed_fraction", false, 0.0, 1.0, true, false, 0.25, "--analysed", "-", 1.0, "",
       TOOLPOINT_MEMBER(S, analysed_fraction)},
      {"SimulationOptions", "record", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "", TOOLPOINT_MEMBER(S, record)},
      {"SimulationOptions", "memory_revolutions", true, 1.0, 10.0, false, false, 2.0, "--memory-revolutions", "-", 1.0, "",
       TOOLPOINT_MEMBER(S, memory_revolutions)},
  };
}

/// The identification's scalar fields as the hand-written checks had them: JointFitOptions::check,
/// ForwardCheckOptions::check (on options whose false_alarm lets 50 replicates pass the rank
/// test's floor), IdentificationOptions::check, and `toolpoint identify --width`.
inline std::vector<ExpectedField<JointFitOptions>> joint_fit_expected_fields() {
  using J = JointFitOptions;
  return {
      {"JointFitOptions", "reciprocal", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "", TOOLPOINT_MEMBER(J, reciprocal)},
      {"JointFitOptions", "bootstrap_samples", true, 20.0, 100000.0, false, false, 50.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(J, bootstrap_samples)},
      {"JointFitOptions", "shared_calibration", false, -kInf, kInf, false, false, 1.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(J, shared_calibration)},
      {"JointFitOptions", "check_linearisation", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(J, check_linearisation)},
      {"JointFitOptions", "confidence", false, 0.5, 1.0, true, true, 0.9, "", "", 1.0, "", TOOLPOINT_MEMBER(J, confidence)},
      {"JointFitOptions", "max_iterations", true, 1.0, 100000.0, false, false, 50.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(J, max_iterations)},
  };
}

inline std::vector<ExpectedField<ForwardCheckOptions>> forward_check_expected_fields() {
  using F = ForwardCheckOptions;
  return {
      {"ForwardCheckOptions", "min_prominence", false, 0.0, 1.0, true, true, 0.2, "", "", 1.0, "",
       TOOLPOINT_MEMBER(F, min_prominence)},
      {"ForwardCheckOptions", "replicates", true, 50.0, 100000.0, false, false, 100.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(F, replicates)},
      {"ForwardCheckOptions", "false_alarm", false, 0.0, 0.5, true, true, 0.05, "", "", 1.0, "",
       TOOLPOINT_MEMBER(F, false_alarm)},
      {"ForwardCheckOptions", "frequency_tolerance", false, 0.0, 1.0, true, true, 0.02, "", "", 1.0, "",
       TOOLPOINT_MEMBER(F, frequency_tolerance)},
      {"ForwardCheckOptions", "peak_tolerance", false, 0.0, 10.0, true, true, 0.3, "", "", 1.0, "",
       TOOLPOINT_MEMBER(F, peak_tolerance)},
      {"ForwardCheckOptions", "shared_calibration", false, -kInf, kInf, false, false, 1.0, "", "", 1.0, "",
       TOOLPOINT_MEMBER(F, shared_calibration)},
  };
}

inline std::vector<ExpectedField<IdentificationOptions>> identification_expected_fields() {
  using I = IdentificationOptions;
  return {
      {"IdentificationOptions", "width", false, 0.0, 0.5, true, true, 0.05, "--width", "-", 1.0, "", TOOLPOINT_MEMBER(I, width)}};
}

/// The options themselves: the member accessor of a table whose fields lie in the type itself.
template <class O>
O& self(O& o) {
  return o;
}

}  // namespace toolpoint::testing
