// toolpoint: plausible magnitudes of physical inputs in SI units, one table for the assembly and
// study files and the command line, so that the same value gets the same verdict wherever it is
// given.
//
// Why. A value in the wrong unit (mm for m, MPa for Pa) is the commonest input error and yields
// results that look like numbers (a 49 m tool, a 1 000 000 mm stable depth). A value outside the
// usual range draws a warning that names the likely slip; a value so far outside that no machine
// tool could have it (beyond the range by the range's `slack` factor) cannot be meant and is refused.
// Zero is left to the caller (it means "none" for some inputs and is invalid for others).
#pragma once

#include <string>

namespace toolpoint {

struct PlausibleRange {
  double low = 0.0, high = 0.0;  // the usual range, in SI units (low may be 0)
  double slack = 10.0;           // beyond [low / slack, high · slack]: cannot be meant
  const char* hint = "";         // the likely slip and the fix, e.g. "lengths are in metres (49 mm = 0.049)"
};

enum class Plausibility { Usual, Unusual, Impossible };

// Usual inside [low, high]; Impossible beyond [low / slack, high · slack] (below only when low > 0)
// or not finite; Unusual otherwise. Zero and negative values are judged by magnitude.
Plausibility judge(const PlausibleRange& range, double value);

// "<what> = <value> is outside the usual range [low, high]; <hint>" or "… cannot be meant: …".
std::string plausibility_message(const PlausibleRange& range, double value, const std::string& what);

/// \brief The verdict on `value` applied, as the files, the command line and the Python package apply it.
/// \param range the plausible range (plausible::k…)
/// \param value the value, in SI units
/// \param what the value's name in the message (a library field, e.g. "CuttingConditions::tangential_coefficient")
/// \param fix the hint of the InvalidArgument thrown when the value cannot be meant
/// \return the warning when the value is unusual, else an empty string
/// \throws InvalidArgument when the value cannot be meant (plausibility_message naming `what`)
std::string require_plausible(const PlausibleRange& range, double value, const std::string& what, const std::string& fix);

namespace plausible {
// Lengths [m]
inline constexpr PlausibleRange kSegmentLength{1e-4, 2.0, 10.0, "lengths are in metres (49 mm = 0.049)"};
inline constexpr PlausibleRange kOuterDiameter{1e-3, 0.5, 10.0, "diameters are in metres (16 mm = 0.016)"};
inline constexpr PlausibleRange kInnerDiameter{1e-4, 0.5, 10.0, "diameters are in metres (8 mm = 0.008)"};
inline constexpr PlausibleRange kToolLength{5e-3, 0.5, 10.0, "lengths are in metres (123 mm = 0.123)"};
inline constexpr PlausibleRange kToolDiameter{2e-4, 0.2, 10.0, "diameters are in metres (16 mm = 0.016)"};
inline constexpr PlausibleRange kOverhang{2e-3, 0.5, 10.0, "overhangs are in metres (49 mm = 0.049)"};
inline constexpr PlausibleRange kPointSpacing{1e-3, 0.1, 10.0, "the spacing is in metres (15 mm = 0.015)"};
inline constexpr PlausibleRange kFeedPerTooth{1e-6, 2e-3, 10.0, "the feed per tooth is in metres (0.1 mm = 1e-4)"};
inline constexpr PlausibleRange kDepth{1e-4, 0.3, 10.0, "depths are in metres (20 mm = 0.02)"};
// Materials
inline constexpr PlausibleRange kYoungsModulus{1e9, 1.2e12, 10.0, "Young's modulus is in Pa (steel 2.1e11), not MPa or GPa"};
inline constexpr PlausibleRange kShearModulus{4e8, 5e11, 10.0, "the shear modulus is in Pa (steel 8e10), not MPa or GPa"};
inline constexpr PlausibleRange kDensity{500.0, 25000.0, 10.0, "density is in kg/m^3 (steel 7800), not g/cm^3"};
inline constexpr PlausibleRange kLossFactor{0.0, 0.2, 5.0, "a structural loss factor is usually 0.001–0.05"};
// Stiffnesses
inline constexpr PlausibleRange kBearingStiffness{1e6, 1e10, 100.0, "bearing stiffness is in N/m (typically 1e7–1e9)"};
inline constexpr PlausibleRange kJointTranslationalStiffness{1e5, 1e11, 1e3, "translational stiffness is in N/m"};
inline constexpr PlausibleRange kJointRotationalStiffness{1e3, 1e9, 1e3, "rotational stiffness is in N m/rad"};
// Damping
inline constexpr PlausibleRange kJointTranslationalDamping{0.1, 1e5, 1e3,
                                                           "translational damping is in N s/m (the seed's joint: 54)"};
inline constexpr PlausibleRange kJointRotationalDamping{1e-4, 1e2, 1e3,
                                                        "rotational damping is in N m s/rad (the seed's joint: 1)"};
inline constexpr PlausibleRange kBearingDamping{10.0, 1e6, 100.0, "bearing damping is in N s/m (typically 1e2–1e4)"};
// Cutting
inline constexpr PlausibleRange kCuttingCoefficient{
    5e7, 1e10, 100.0, "cutting coefficients are in N/m^2 (aluminium about 7e8, steel 2e9), not N/mm^2 or MPa"};
inline constexpr PlausibleRange kEdgeCoefficient{1e2, 1e6, 100.0, "K_te is in N/m (typically 1e4–5e4)"};
// Machine
// A milling spindle below 100 rpm is unusual (thousands of rpm given as krpm?), below 10 impossible.
inline constexpr PlausibleRange kSpindleSpeedRpm{100.0, 2e5, 10.0, "spindle speeds are in rpm (12 000 rpm = 12000, not 12)"};
// The spin of a rotating model [rpm]: below 1000 rpm gyroscopic effects are negligible and a value
// there is more likely rad/s (15 000 rpm = 1571 rad/s) than meant.
inline constexpr PlausibleRange kSpinSpeedRpm{1000.0, 1.5e5, 40.0,
                                              "spindle speeds are in rpm, not rad/s (15 000 rpm = 1571 rad/s)"};
// Below 50 W no machining spindle: a power in kW (15 for 15 kW) is refused, not computed with.
inline constexpr PlausibleRange kPower{200.0, 5e5, 4.0, "power is in watts (15 kW = 15e3)"};
inline constexpr PlausibleRange kTorque{0.5, 5000.0, 10.0, "torque is in N m"};
inline constexpr PlausibleRange kRadialRatio{0.05, 1.5, 10.0, "K_r = K_n/K_t is a ratio, typically 0.2–0.6 (30 % = 0.3)"};
// Modal models
inline constexpr PlausibleRange kModalMass{1e-3, 1e3, 1e3, "modal masses are in kg (40 g = 0.04)"};
inline constexpr PlausibleRange kNaturalFrequency{5.0, 2e4, 100.0, "frequencies are in Hz, not rad/s (922 Hz = 5793 rad/s)"};
// Measurements: the largest |H| of a translational receptance over its band [m/N] (a tool point's
// peak is typically 1e-8…1e-5 m/N: a 0.1 mm/N peak is a very slender tool; refused beyond 1e-14
// and 1 m/N, where a µm/N file of a tool point read as m/N lands)
inline constexpr PlausibleRange kPeakReceptance{
    1e-10, 1e-4, 1e4, "receptances are in m/N (1 µm/N = 1e-6 m/N): check the file's units or give them (FrfReadOptions::units)"};
inline constexpr PlausibleRange kRelativeNoise{1e-4, 0.2, 5.0, "σ is a fraction (5 % = 0.05)"};
// The top of a frequency grid [Hz]: tool point FRFs are measured to a few kHz
inline constexpr PlausibleRange kTopFrequency{100.0, 2e4, 10.0, "frequencies are in Hz (5 kHz = 5000)"};
// κGA of a beam section [N]: a 2 mm carbide tool 6e5, a 16 mm one 2.8e7, a spindle shaft 1e9
inline constexpr PlausibleRange kShearStiffness{
    1e5, 1e10, 100.0, "κGA is in N: the shear modulus [Pa] × the area [m²] × κ (a 16 mm carbide tool: 2.8e7)"};
inline constexpr PlausibleRange kShearCoefficient{0.3, 1.0, 3.0,
                                                  "κ is the Timoshenko shear coefficient, about 0.9 for a solid round section"};
}  // namespace plausible

}  // namespace toolpoint
