// toolpoint: units and the one sign convention every substructure uses.
//
// Units: SI everywhere (m, kg, N, Pa, s, rad). Frequencies are in Hz at every interface (files,
// options, results); formulas use Ω = 2πf in rad/s internally.
//
// Sign convention (see docs/files.md, "Conventions", for the sketch):
//
//        spindle rear                                                tool tip
//        ──────────────[spindle]──[holder]──[tool]──────────────────────► x
//                       end 2  end 1 end 2  end 1 end 2      end 1
//
//   * One global axis x along the assembly, pointing from the spindle towards the tool tip.
//   * w: transverse displacement (m), positive along +y for every component.
//   * θ: bending rotation of the cross section (rad), positive in the sense of dw/dx along +x
//     (θ = ψ of Timoshenko theory; at a free end with no shear force it equals dw/dx).
//   * f: transverse force (N) along +y; m: bending moment (N·m) in the sense of θ, so f·w and
//     m·θ are work.
//   * Every component's end 1 is its outer end (towards the tool tip, larger x) and end 2 its
//     inner end. Segments are listed from end 1 inwards. The tool's end 1 is the tool tip, the
//     holder's end 1 the holder tip, the spindle's end 1 the spindle nose.
//
// This is the seed paper's convention: the free–free tip receptances of Eq. (11)–(14) hold as
// printed (rigid-body part of L11 = N11 = −6/(ρAL²Ω²) at the outer end), Duarte–Ewins finite
// differences hold as printed with points spaced inwards from the tip, and the coupling
// equations (1)–(5), (15), (17) hold as printed with A's end 2 joined to B's end 1.
// A joint matrix K maps the relative displacement (w, θ) of the outer body's end 2 minus the
// inner body's end 1 to the force and moment (f, m) acting on the inner body.
#pragma once

#include <limits>
#include <numbers>
#include <vector>

namespace toolpoint {

inline constexpr double kPi = std::numbers::pi;
// "No value" (a gap, a mode not found) and "no limit": the library's one spelling of each.
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Ω = 2πf: rad/s from Hz.
inline double omega_of(double frequency_hz) { return 2.0 * kPi * frequency_hz; }

// A spindle speed: Ω = 2πn/60 in rad/s from n in rpm (spindle speeds are in rpm at every
// interface, in rad/s inside the spinning-rotor formulas), and back. The one place it is written.
inline constexpr double rad_s_of_rpm(double rpm) { return rpm * 2.0 * kPi / 60.0; }
inline constexpr double rpm_of_rad_s(double rad_s) { return rad_s * 60.0 / (2.0 * kPi); }

// An angle: degrees from radians and back (angles are in rad in the library and its files; the CLI
// and the figures show degrees).
inline constexpr double degrees_of(double rad) { return rad * 180.0 / kPi; }
inline constexpr double radians_of(double deg) { return deg * kPi / 180.0; }

// An evenly spaced frequency grid START:STOP:STEP in Hz (both ends included when STOP is on the
// grid).
struct FrequencyGrid {
  double start_hz = 0.0;
  double stop_hz = 0.0;
  double step_hz = 0.0;

  // Throws InvalidArgument unless 0 < start ≤ stop, step > 0 and at least 1e-9 of stop (the
  // relative tolerance grids are compared with; finer steps repeat frequencies in double
  // precision), all finite, and the grid has at most 10 million points.
  void check() const;
  std::vector<double> values() const;
};

}  // namespace toolpoint
