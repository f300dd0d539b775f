// toolpoint Python bindings: the pitch choice (stability/pitch.hpp). Angles in radians, depths in m,
// speeds in rpm, frequencies in Hz.
#include "common.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/stability/pitch.hpp"

namespace toolpoint::python {

namespace {
using namespace pybind11::literals;
const std::vector<std::pair<const char*, PitchPattern>> kPatterns{{"alternating", PitchPattern::Alternating},
                                                                  {"linear", PitchPattern::Linear},
                                                                  {"three-angle", PitchPattern::ThreeAngle}};
}  // namespace

void bind_pitch(py::module_& m) {
  options_class<PitchChoiceOptions>(m, "PitchChoiceOptions", "choose_pitch's options (stability/pitch.hpp; toolpoint pitch's).",
                                    {"speed_rpm", "pattern", "min_pitch_rad", "max_pitch_rad", "chatter_hz", "window",
                                     "search_points", "robustness", "steps", "degree", "max_depth_m", "depth_steps"})
      .def_readwrite("speed_rpm", &PitchChoiceOptions::speed_rpm, "the target spindle speed [rpm]")
      .def_property(
          "pattern", [](const PitchChoiceOptions& o) { return std::string(to_string(o.pattern)); },
          [](PitchChoiceOptions& o, const std::string& s) { o.pattern = enum_of(s, kPatterns, "pattern"); },
          "'alternating' (P1/P2/…, even teeth), 'linear' (P, P+ΔP, P+2ΔP, …) or 'three-angle' (P0/P1/P2/…, a multiple of "
          "3 teeth, two parameters u and v)")
      .def_readwrite("min_pitch_rad", &PitchChoiceOptions::min_pitch_rad, "smallest pitch angle [rad] (0: half the even pitch)")
      .def_readwrite("max_pitch_rad", &PitchChoiceOptions::max_pitch_rad, "largest pitch angle [rad] (0: 1.5 × the even pitch)")
      .def_readwrite("chatter_hz", &PitchChoiceOptions::chatter_hz,
                     "the chatter frequency Budak's rule aims at [Hz] (0: the evenly spaced tool's at the speed)")
      .def_readwrite("window", &PitchChoiceOptions::window, "search ΔP over (1 ± window) × the closed form's")
      .def_readwrite("search_points", &PitchChoiceOptions::search_points, "points of the first search grid, 3…201")
      .def_readwrite("robustness", &PitchChoiceOptions::robustness,
                     "maximise the lowest limit of ΔP and ΔP(1 ± robustness), 0…0.2")
      .def_readwrite("steps", &PitchChoiceOptions::steps, "steps per tooth period (0: 12 per chatter wave)")
      .def_readwrite("degree", &PitchChoiceOptions::degree, "interpolation degree 1…3")
      .def_readwrite("max_depth_m", &PitchChoiceOptions::max_depth_m,
                     "depths searched up to this [m] (0: 20 × the zero-order floor)")
      .def_readwrite("depth_steps", &PitchChoiceOptions::depth_steps, "equal depth steps of the search, 4…10000");

  py::class_<PitchChoice>(m, "PitchChoice", "choose_pitch's result: the chosen pitch against the evenly spaced tool.")
      .def_property_readonly("pattern", [](const PitchChoice& c) { return std::string(to_string(c.pattern)); })
      .def_readonly("speed_rpm", &PitchChoice::speed_rpm)
      .def_readonly("chatter_hz", &PitchChoice::chatter_hz, "the frequency Budak's rule aimed at [Hz]")
      .def_readonly("max_variation_rad", &PitchChoice::max_variation_rad, "the largest ΔP the limits allow [rad]")
      .def_readonly("closed_form_variation_rad", &PitchChoice::closed_form_variation_rad, "Budak's ΔP (three-angle: u) [rad]")
      .def_readonly("closed_form_second_variation_rad", &PitchChoice::closed_form_second_variation_rad,
                    "Budak's v (three-angle; else 0) [rad]")
      .def_readonly("closed_form_pitch_rad", &PitchChoice::closed_form_pitch_rad)
      .def_readonly("closed_form_depth_m", &PitchChoice::closed_form_depth_m)
      .def_readonly("variation_rad", &PitchChoice::variation_rad, "the chosen ΔP (three-angle: u) [rad]")
      .def_readonly("second_variation_rad", &PitchChoice::second_variation_rad, "the chosen v (three-angle; else 0) [rad]")
      .def_readonly("pitch_rad", &PitchChoice::pitch_rad, "the chosen pitch angles [rad]")
      .def_property_readonly("chosen_depth_m", [](const PitchChoice& c) { return c.chosen.depth_m; })
      .def_property_readonly("chosen_depth_error_m", [](const PitchChoice& c) { return c.chosen.depth_error_m; })
      .def_property_readonly("uniform_depth_m", [](const PitchChoice& c) { return c.uniform.depth_m; })
      .def_property_readonly("uniform_depth_error_m", [](const PitchChoice& c) { return c.uniform.depth_error_m; })
      .def_readonly("gain", &PitchChoice::gain, "chosen / evenly spaced limit")
      .def_readonly("warnings", &PitchChoice::warnings)
      .def(
          "to_dict", [](const PitchChoice& c) { return dict_of(c); },
          "The result as plain data (toolpoint pitch --json's choice, SI units, radians), the samples included.");
  m.def(
      "choose_pitch",
      [](const std::vector<Mode>& x_modes, const std::vector<Mode>& y_modes, const CuttingConditions& cutting,
         const PitchChoiceOptions& options, int threads) {
        PitchChoiceOptions o = options;
        o.parallel.threads = threads;
        PitchChoice r;
        {
          py::gil_scoped_release nogil;
          r = choose_pitch(ModalModel{x_modes, y_modes, {}}, cutting, o);
        }
        warn_all(r.warnings);
        return r;
      },
      "x_modes"_a, "y_modes"_a, "cutting"_a, "options"_a, "threads"_a = 0,
      "The variable pitch (options.pattern) that maximises the stable depth of the modal model (y_modes empty: rigid in y) at "
      "options.speed_rpm: Budak's closed form, then the full-discretization limit over a bounded search; against the evenly "
      "spaced tool. threads: 0 every core; results identical for any count.");
}

}  // namespace toolpoint::python
