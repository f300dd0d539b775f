// toolpoint Python bindings: modal models (modal_fit.hpp) and milling stability (stability.hpp,
// studies/lobes.hpp; with the joint uncertain: bind_identify.cpp). SI units (depths in m), frequencies in Hz,
// spindle speeds in rpm; tables come back as dicts of arrays.
#include "common.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/modal_fit.hpp"
#include "toolpoint/io/uff.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/identify/forward_check.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/beam.hpp"
#include "toolpoint/studies/pitch.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/precision.hpp"
#include "toolpoint/studies/rotational.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint::python {

namespace {

using namespace pybind11::literals;

const std::vector<std::pair<const char*, MillingDirection>> kMilling{{"up", MillingDirection::Up},
                                                                     {"down", MillingDirection::Down}};
const std::vector<std::pair<const char*, LobesMethod>> kLobesMethods{{"zoa", LobesMethod::ZeroOrder},
                                                                     {"fd", LobesMethod::FullDiscretization},
                                                                     {"sd", LobesMethod::SemiDiscretization}};
// The time-domain schemes by the lobes methods' names.
const std::vector<std::pair<const char*, Discretization>> kSchemes{{"fd", Discretization::Full}, {"sd", Discretization::Semi}};
const std::vector<std::pair<const char*, SpeedModel>> kSpeedModels{{"auto", SpeedModel::Automatic},
                                                                   {"standstill", SpeedModel::Standstill},
                                                                   {"bearings", SpeedModel::Bearings},
                                                                   {"spinning", SpeedModel::Spinning}};

template <class Rows, class Get>
py::array_t<double> column(const Rows& rows, Get get) {
  std::vector<double> v(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) v[i] = get(rows[i]);
  return array_of(v);
}

template <class Rows, class Get>
py::array_t<int> int_column(const Rows& rows, Get get) {
  py::array_t<int> a(static_cast<py::ssize_t>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) a.mutable_at(static_cast<py::ssize_t>(i)) = get(rows[i]);
  return a;
}

py::dict envelope_dict(const std::vector<EnvelopePoint>& e) {
  return py::dict("speed_rpm"_a = column(e, [](const EnvelopePoint& p) { return p.speed_rpm; }),
                  "depth_m"_a = column(e, [](const EnvelopePoint& p) { return p.depth_m; }),
                  "chatter_hz"_a = column(e, [](const EnvelopePoint& p) { return p.chatter_hz; }),
                  "lobe"_a = int_column(e, [](const EnvelopePoint& p) { return p.lobe; }));
}

py::dict boundary_dict(const std::vector<BoundaryPoint>& b) {
  std::vector<std::string> kind;
  std::vector<Complex> mult;
  for (const BoundaryPoint& p : b) {
    kind.emplace_back(to_string(p.kind));
    mult.push_back(p.multiplier);
  }
  return py::dict("speed_rpm"_a = column(b, [](const BoundaryPoint& p) { return p.speed_rpm; }),
                  "depth_m"_a = column(b, [](const BoundaryPoint& p) { return p.depth_m; }),
                  "depth_error_m"_a = column(b, [](const BoundaryPoint& p) { return p.depth_error_m; }),
                  "steps"_a = int_column(b, [](const BoundaryPoint& p) { return p.steps; }),
                  "chatter_hz"_a = column(b, [](const BoundaryPoint& p) { return p.chatter_hz; }),
                  "lobe"_a = int_column(b, [](const BoundaryPoint& p) { return p.lobe; }), "kind"_a = kind,
                  "multiplier"_a = array_of(mult));
}

MillingFrfs milling_of(const RealArray& f, const ComplexArray& xx, const std::optional<ComplexArray>& yy,
                       const std::optional<ComplexArray>& xy, const std::optional<ComplexArray>& yx, bool rigid_y) {
  MillingFrfs m;
  m.xx = frf_series(f, xx, "xx");
  judge_receptance(m.xx, "xx");
  if (yy) {
    m.yy = frf_series(f, *yy, "yy");
    judge_receptance(*m.yy, "yy");
  }
  if (xy) m.xy = frf_series(f, *xy, "xy");
  if (yx) m.yx = frf_series(f, *yx, "yx");
  m.rigid_y = rigid_y;
  return m;
}

// The lobes study's options from keyword arguments (run_lobes_study, stability_uncertainty).
LobesStudyOptions lobes_study_options(const CuttingConditions& cutting, const std::tuple<double, double, int>& speeds,
                                      const std::string& method, double max_depth_m, int lobes, double tolerance, int steps,
                                      int degree, int max_modes, const std::optional<std::pair<double, double>>& band_hz,
                                      double fit_target) {
  LobesStudyOptions o;
  o.method = enum_of(method, kLobesMethods, "method");
  o.cutting = cutting;
  o.speeds = speed_range(speeds);
  o.max_depth_m = max_depth_m;
  o.lobes = lobes;
  o.tolerance = tolerance;
  o.steps = steps;
  o.degree = degree;
  o.fit.max_modes = max_modes;
  o.fit.band_hz = band_hz;
  o.fit_target = fit_target;
  return o;
}

// Modal models: modes, their fit to a measured FRF, the modal fit study.
void bind_modal_models(py::module_& m) {
  auto fit =
      options_class<ModalFitOptions>(m, "ModalFitOptions",
                                     "How fit_modes fits modes to a point receptance (modal_fit.hpp; toolpoint modes' options).",
                                     {"max_modes", "band_hz", "min_prominence_db", "residual_terms", "max_evaluations"})
          .def_readwrite("band_hz", &ModalFitOptions::band_hz, "(F1, F2): fit only F1 ≤ f ≤ F2 [Hz]; None: all points");
  def_option_fields(fit, modal_fit_fields(), "toolpoint modes");  // max_modes, min_prominence_db, residual_terms, max_evaluations

  // ---- Modal models ---------------------------------------------------------------------------------
  py::class_<Mode>(
      m, "Mode", "One mode of a point receptance as a 1-DOF oscillator: modal mass [kg], damping ratio, natural frequency [Hz].")
      .def(py::init([](double mass, double zeta, double f) {
             // As the CLI's --mode: a mass in g or a frequency in rad/s is said (or refused).
             check_plausible(plausible::kModalMass, mass, "Mode::mass_kg", "give the modal mass in kg (40 g = 0.04)");
             check_plausible(plausible::kNaturalFrequency, f, "Mode::frequency_hz",
                             "give the natural frequency in Hz (rad/s ÷ 2π)");
             return Mode{mass, zeta, f};
           }),
           "mass_kg"_a, "damping_ratio"_a, "frequency_hz"_a)
      .def_readwrite("mass_kg", &Mode::mass_kg)
      .def_readwrite("damping_ratio", &Mode::damping_ratio)
      .def_readwrite("frequency_hz", &Mode::frequency_hz)
      .def("stiffness", &Mode::stiffness, "k = m (2πf)² [N/m]")
      .def(
          "check", [](const Mode& x) { x.check(); }, "Raises InvalidArgument for m ≤ 0, ζ outside [0, 1), f ≤ 0 or NaN.")
      .def(
          "to_dict", [](const Mode& x) { return dict_of(x); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).")
      .def("__repr__", [](const Mode& x) {
        return fmt::format("Mode(mass_kg={:.17g}, damping_ratio={:.17g}, frequency_hz={:.17g})", x.mass_kg, x.damping_ratio,
                           x.frequency_hz);
      });
  m.def(
      "modal_frf",
      [](const std::vector<Mode>& modes, const RealArray& f) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        FrfSeries s;
        {
          py::gil_scoped_release nogil;
          s = modal_frf(modes, grid);
        }
        return array_of(s.values);
      },
      "modes"_a, "frequency_hz"_a, "G(f) = Σ 1/(m_r(ω_r² − ω² + 2iζ_r ω_r ω)) [m/N], complex (n,).");
  py::class_<ModalFitResult>(m, "ModalFitResult", "fit_modes' result.")
      .def_property_readonly(
          "modes",
          [](const ModalFitResult& r) {
            std::vector<Mode> v;
            for (const FittedMode& x : r.modes) v.push_back(x.mode);
            return v;
          },
          "list of Mode (ascending frequency)")
      .def_property_readonly(
          "residues", [](const ModalFitResult& r) { return column(r.modes, [](const FittedMode& x) { return x.residue; }); },
          "A_r [1/kg]")
      .def_property_readonly("mode_residuals",
                             [](const ModalFitResult& r) {
                               return column(r.modes, [](const FittedMode& x) { return x.normalised_residual; });
                             })
      .def_readonly("lower_residual", &ModalFitResult::lower_residual, "L [1/kg]")
      .def_readonly("upper_residual", &ModalFitResult::upper_residual, "U [m/N]")
      .def_readonly("normalised_residual", &ModalFitResult::normalised_residual)
      .def_property_readonly("band_hz", [](const ModalFitResult& r) { return std::make_pair(r.band_low_hz, r.band_high_hz); })
      .def_readonly("points", &ModalFitResult::points)
      .def_readonly("evaluations", &ModalFitResult::evaluations)
      .def_readonly("converged", &ModalFitResult::converged)
      .def_readonly("warnings", &ModalFitResult::warnings)
      .def(
          "to_dict", [](const ModalFitResult& r) { return dict_of(r); },
          "The result as plain data (dicts, lists, floats, str, bool, None; toolpoint modes --json's keys, SI units).")
      .def("modal_model", &ModalFitResult::modal_model,
           "The fitted modes without residual terms (raises NumericalError for a non-positive residue).")
      .def(
          "receptance",
          [](const ModalFitResult& r, const RealArray& f) {
            std::vector<Complex> v;
            for (double x : vector_of(f, "frequency_hz")) v.push_back(r.receptance(x));
            return array_of(v);
          },
          "frequency_hz"_a, "The fitted receptance, residual terms included [m/N].");
  m.def(
      "fit_modes",
      [](const RealArray& f, const ComplexArray& values, const std::optional<ModalFitOptions>& options) {
        const FrfSeries s = frf_series(f, values, "values");
        judge_receptance(s, "values");
        const ModalFitOptions o = options.value_or(ModalFitOptions{});
        py::gil_scoped_release nogil;
        return fit_modes(s, o, "values");
      },
      "frequency_hz"_a, "values"_a, py::kw_only(), "options"_a = py::none(),
      "options: ModalFitOptions (None: the defaults). Modal parameters of a point receptance [m/N] (toolpoint modes): peak "
      "picking, then Levenberg–Marquardt on all modes (and "
      "residual "
      "terms) at once.");

  py::class_<ModalFitStudy>(m, "ModalFitStudy", "run_modal_fit_study's result (modal_fit.hpp).")
      .def_readonly("fit", &ModalFitStudy::fit, "ModalFitResult")
      .def_property_readonly(
          "frequency_hz", [](const ModalFitStudy& r) { return array_of(r.fitted.frequency_hz); },
          "(n,) the band's measured frequencies [Hz]")
      .def_property_readonly(
          "fitted", [](const ModalFitStudy& r) { return array_of(r.fitted.values); },
          "the fitted receptance there, residual terms included, complex (n,) [m/N]")
      .def_readonly("model", &ModalFitStudy::model,
                    "list of Mode: the fitted modes that are resonances (positive residue, ζ < 1), as lobes takes them")
      .def_readonly("warnings", &ModalFitStudy::warnings)
      .def(
          "to_dict", [](const ModalFitStudy& r) { return dict_of(r); },
          "The result as plain data, the fitted series left out ('fit' has toolpoint modes --json's keys; SI units).");
  m.def(
      "run_modal_fit_study",
      [](const RealArray& f, const ComplexArray& values, const std::optional<ModalFitOptions>& options, const std::string& what) {
        const FrfSeries s = frf_series(f, values, "values");
        judge_receptance(s, what);
        const ModalFitOptions o = options.value_or(ModalFitOptions{});
        py::gil_scoped_release nogil;
        return run_modal_fit_study(s, o, what);
      },
      "frequency_hz"_a, "values"_a, py::kw_only(), "options"_a = py::none(), "what"_a = "values",
      "options: ModalFitOptions (None: the defaults). The modal fit study (toolpoint modes): fit_modes on a point receptance "
      "[m/N] against frequency_hz [Hz], the fitted "
      "receptance on the band's measured frequencies, and the modal model of the fitted resonances.");
}

// Cutting conditions and the zero-order lobes (Altintas & Budak 1995).
void bind_zero_order(py::module_& m) {
  py::class_<CuttingConditions>(
      m, "CuttingConditions",
      "Milling: teeth N, tangential coefficient K_t [N/m²], radial ratio K_r = K_n/K_t, engagement from "
      "the radial immersion a/D and 'up'/'down' milling, or entry/exit angles [rad] clockwise from y. Optional "
      "(time-domain method only): pitch_rad, the angle from each tooth to the next [rad] (variable pitch); runout_m, "
      "the radius offset of each tooth [m] with feed_per_tooth_m [m]; process_damping_n_per_m, the indentation "
      "coefficient C_i [N/m] with diameter_m [m]; helix_rad, the helix angle [rad] of every tooth ([β]) or of each "
      "(a variable helix, helix_slices axial slices, 0: 8) with diameter_m [m].")
      .def(py::init([](int teeth, double kt, double kr, std::optional<double> immersion, const std::string& milling,
                       std::optional<double> entry_rad, std::optional<double> exit_rad, std::vector<double> pitch_rad,
                       std::vector<double> runout_m, double feed_per_tooth_m, double diameter_m, double process_damping_n_per_m,
                       std::vector<double> helix_rad, int helix_slices) {
             CuttingConditions c;
             c.teeth = teeth;
             c.tangential_coefficient = kt;
             c.radial_ratio = kr;
             c.pitch_rad = std::move(pitch_rad);
             c.runout_m = std::move(runout_m);
             c.feed_per_tooth_m = feed_per_tooth_m;
             c.diameter_m = diameter_m;
             c.process_damping_n_per_m = process_damping_n_per_m;
             c.helix_rad = std::move(helix_rad);
             c.helix_slices = helix_slices;
             if (immersion && (entry_rad || exit_rad))
               throw InvalidArgument("CuttingConditions: give the immersion or the entry and exit angles, not both",
                                     "drop one of them");
             if (immersion) c.engagement = engagement_from_immersion(*immersion, enum_of(milling, kMilling, "milling"));
             else if (entry_rad && exit_rad) c.engagement = {*entry_rad, *exit_rad};
             else
               throw InvalidArgument(
                   "CuttingConditions: give the radial immersion (with milling 'up' or 'down') or entry_rad and exit_rad",
                   "e.g. immersion=0.5, milling='down'");
             // As the CLI's --kt, --kr, --diameter: a K_t in N/mm² (MPa) refused by check(), an
             // unusual value said (cutting_fields' plausible ranges).
             c.check();
             warn_all(field_plausibility_warnings(cutting_fields(), c, "CuttingConditions"));
             return c;
           }),
           "teeth"_a, "tangential_coefficient"_a, "radial_ratio"_a, "immersion"_a = py::none(), "milling"_a = "down",
           "entry_rad"_a = py::none(), "exit_rad"_a = py::none(), "pitch_rad"_a = std::vector<double>{},
           "runout_m"_a = std::vector<double>{}, "feed_per_tooth_m"_a = 0.0, "diameter_m"_a = 0.0,
           "process_damping_n_per_m"_a = 0.0, "helix_rad"_a = std::vector<double>{}, "helix_slices"_a = 0)
      .def_readonly("teeth", &CuttingConditions::teeth)
      .def_readonly("pitch_rad", &CuttingConditions::pitch_rad, "angle from each tooth to the next [rad] (empty: even)")
      .def_readonly("runout_m", &CuttingConditions::runout_m, "radius offset of each tooth [m] (empty: none)")
      .def_readonly("feed_per_tooth_m", &CuttingConditions::feed_per_tooth_m)
      .def_readonly("diameter_m", &CuttingConditions::diameter_m)
      .def_readonly("process_damping_n_per_m", &CuttingConditions::process_damping_n_per_m, "C_i [N/m]")
      .def_readonly("helix_rad", &CuttingConditions::helix_rad, "helix angle [rad]: one for every tooth, or one per tooth")
      .def_readonly("helix_slices", &CuttingConditions::helix_slices, "axial slices of a variable helix (0: 8)")
      .def_readonly("tangential_coefficient", &CuttingConditions::tangential_coefficient, "K_t [N/m²]")
      .def_readonly("radial_ratio", &CuttingConditions::radial_ratio)
      .def_property_readonly("entry_rad", [](const CuttingConditions& c) { return c.engagement.entry_rad; })
      .def_property_readonly("exit_rad", [](const CuttingConditions& c) { return c.engagement.exit_rad; })
      .def(
          "directional_factors", [](const CuttingConditions& c) { return matrix_array(directional_factors(c)); },
          "α over the engagement (2, 2)")
      .def(
          "to_dict", [](const CuttingConditions& c) { return dict_of(c); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");

  py::class_<ZeroOrderResult>(m, "ZeroOrderResult", "Zero-order lobes (Altintas & Budak 1995).")
      .def_readonly("floor_depth_m", &ZeroOrderResult::floor_depth_m, "absolute stability limit [m]")
      .def_readonly("floor_chatter_hz", &ZeroOrderResult::floor_chatter_hz)
      .def_readonly("lobes", &ZeroOrderResult::lobes, "K: lobes 0…K")
      .def_property_readonly(
          "alpha", [](const ZeroOrderResult& r) { return matrix_array(r.alpha); },
          "directional factors α over the engagement (2, 2), dimensionless")
      .def_property_readonly(
          "envelope", [](const ZeroOrderResult& r) { return envelope_dict(r.envelope); },
          "{'speed_rpm', 'depth_m' (inf where no lobe), 'chatter_hz', 'lobe'} arrays")
      .def_property_readonly(
          "points",
          [](const ZeroOrderResult& r) {
            const std::vector<LobePoint> p = r.points();
            return py::dict("lobe"_a = int_column(p, [](const LobePoint& x) { return x.lobe; }),
                            "root"_a = int_column(p, [](const LobePoint& x) { return x.root; }),
                            "speed_rpm"_a = column(p, [](const LobePoint& x) { return x.speed_rpm; }),
                            "depth_m"_a = column(p, [](const LobePoint& x) { return x.depth_m; }),
                            "chatter_hz"_a = column(p, [](const LobePoint& x) { return x.chatter_hz; }));
          },
          "every lobe point in range: {'lobe', 'root', 'speed_rpm', 'depth_m', 'chatter_hz'} arrays (toolpoint lobes --output's "
          "rows)")
      .def_readonly("warnings", &ZeroOrderResult::warnings)
      .def(
          "to_dict", [](const ZeroOrderResult& r) { return dict_of(r); },
          "The result as plain data, the lobe points and envelope left out (toolpoint lobes --json's zero_order, SI units).");
  m.def(
      "zero_order_lobes",
      [](const RealArray& f, const ComplexArray& xx, const CuttingConditions& cutting, std::tuple<double, double, int> speeds,
         int lobes, double max_depth_m, const std::optional<ComplexArray>& yy, const std::optional<ComplexArray>& xy,
         const std::optional<ComplexArray>& yx, bool rigid_y) {
        const MillingFrfs frfs = milling_of(f, xx, yy, xy, yx, rigid_y);
        ZeroOrderOptions o;
        o.lobes = lobes;
        o.speeds = speed_range(speeds);
        o.max_depth_m = max_depth_m;
        py::gil_scoped_release nogil;
        return zero_order_lobes(frfs, cutting, o);
      },
      "frequency_hz"_a, "xx"_a, "cutting"_a, "speeds"_a, "lobes"_a = -1, "max_depth_m"_a = 0.0, "yy"_a = py::none(),
      "xy"_a = py::none(), "yx"_a = py::none(), "rigid_y"_a = false,
      fields_doc(zero_order_fields(), "ZeroOrderOptions", "toolpoint lobes",
                 "Zero-order stability lobes from the tool point FRFs [m/N] on frequency_hz [Hz] (G_yy default G_xx: a "
                 "symmetric tool; cross FRFs both or neither). speeds = (min_rpm, max_rpm, points) for the envelope; depths "
                 "in m."));
}

// The time domain: full-discretization (Insperger & Stépán) and its stability boundary.
void bind_time_domain(py::module_& m) {
  py::class_<BoundaryResult>(m, "BoundaryResult", "The time-domain stability boundary with its error estimate.")
      .def_property_readonly(
          "boundary", [](const BoundaryResult& r) { return boundary_dict(r.boundary); },
          "{'speed_rpm', 'depth_m', 'depth_error_m', 'steps', 'chatter_hz', 'lobe', 'kind' (hopf/flip/fold/none), "
          "'multiplier'} per speed")
      .def_readonly("max_depth_m", &BoundaryResult::max_depth_m)
      .def_readonly("tolerance", &BoundaryResult::tolerance)
      .def_readonly("degree", &BoundaryResult::degree)
      .def_property_readonly(
          "scheme", [](const BoundaryResult& r) { return name_of(r.scheme, kSchemes); },
          "'fd' (full-discretization) or 'sd' (semi-discretization)")
      .def_readonly("evaluations", &BoundaryResult::evaluations, "spectral radii computed")
      .def_readonly("warnings", &BoundaryResult::warnings)
      .def("worst_relative_error", &BoundaryResult::worst_relative_error,
           "The largest depth_error_m/depth_m over the speeds with a boundary.")
      .def(
          "to_dict", [](const BoundaryResult& r) { return dict_of(r); },
          "The result as plain data, the per-speed boundary left out (toolpoint lobes --json's boundary, SI units).");
  m.def(
      "stability_boundary",
      [](const std::vector<Mode>& x_modes, const std::vector<Mode>& y_modes, const CuttingConditions& cutting,
         std::tuple<double, double, int> speeds, double tolerance, int steps, int max_steps, int degree, double max_depth_m,
         int threads, const py::object& progress, const std::string& scheme) {
        BoundaryOptions o;
        o.scheme = enum_of(scheme, kSchemes, "scheme");
        o.speeds = speed_range(speeds);
        o.tolerance = tolerance;
        o.steps = steps;
        o.max_steps = max_steps;
        o.degree = degree;
        o.max_depth_m = max_depth_m;
        o.parallel.threads = threads;
        o.progress = progress_of(progress);
        const ModalModel model{x_modes, y_modes, {}};
        py::gil_scoped_release nogil;
        return stability_boundary(model, cutting, o);
      },
      "x_modes"_a, "y_modes"_a, "cutting"_a, "speeds"_a, "tolerance"_a = 0.01, "steps"_a = 0, "max_steps"_a = 4000,
      "degree"_a = 2, "max_depth_m"_a = 0.0, "threads"_a = 0, "progress"_a = py::none(), "scheme"_a = "fd",
      fields_doc(boundary_fields(), "BoundaryOptions", "toolpoint lobes",
                 "The milling stability boundary in the time domain (scheme 'fd': full-discretization, Ding et al. 2010, "
                 "degree 1-3; 'sd': semi-discretization, Insperger & Stepan, degree the order 0 or 1) of a modal model "
                 "(y_modes empty: rigid in y) at each speed of speeds = (min_rpm, max_rpm, points), each depth [m] with its "
                 "Richardson error estimate meeting `tolerance` (relative)."));
  py::class_<FullDiscretization, std::shared_ptr<FullDiscretization>>(
      m, "FullDiscretization",
      "The milling equation's period map at a fixed number of steps per tooth period (degree-p interpolation).")
      .def(py::init([](const std::vector<Mode>& x, const std::vector<Mode>& y, const CuttingConditions& c, int steps, int degree,
                       const std::string& scheme) {
             return std::make_shared<FullDiscretization>(ModalModel{x, y, {}}, c, steps, degree,
                                                         enum_of(scheme, kSchemes, "scheme"));
           }),
           "x_modes"_a, "y_modes"_a, "cutting"_a, "steps"_a = 40, "degree"_a = 2, "scheme"_a = "fd",
           "scheme 'fd' (degree 1-3) or 'sd' (semi-discretization, degree its order 0 or 1)")
      .def(
          "spectral_radius",
          [](const FullDiscretization& fd, double rpm, double depth) {
            py::gil_scoped_release nogil;
            return fd.spectral_radius(rpm, depth);
          },
          "speed_rpm"_a, "depth_m"_a, "ρ, the largest Floquet multiplier's modulus (< 1: stable) at a speed [rpm] and depth [m].")
      .def(
          "spectral_radius_map",
          [](const FullDiscretization& fd, const RealArray& speeds, const RealArray& depths, int threads) {
            const std::vector<double> s = vector_of(speeds, "speeds_rpm"), d = vector_of(depths, "depths_m");
            Eigen::MatrixXd r;
            {
              py::gil_scoped_release nogil;
              r = fd.spectral_radius_map(s, d, ParallelOptions{threads});
            }
            return matrix_array(r);
          },
          "speeds_rpm"_a, "depths_m"_a, "threads"_a = 0,
          "ρ on a grid: (speeds, depths). threads: 0 every core; results identical for any count.")
      .def(
          "analyse",
          [](const FullDiscretization& fd, double rpm, double depth) {
            FloquetAnalysis a;
            {
              py::gil_scoped_release nogil;
              a = fd.analyse(rpm, depth);
            }
            return py::dict("spectral_radius"_a = a.spectral_radius, "critical_multiplier"_a = a.critical_multiplier,
                            "kind"_a = to_string(a.kind), "chatter_hz"_a = a.chatter_hz, "lobe"_a = a.lobe,
                            "matrix_size"_a = a.matrix_size);
          },
          "speed_rpm"_a, "depth_m"_a, "ρ with the critical multiplier, its kind (hopf/flip/fold) and the chatter frequency [Hz].")
      .def_property_readonly("steps", &FullDiscretization::steps)
      .def_property_readonly("degree", &FullDiscretization::degree);
}

// The lobes study: the modal fits it made, its result, the best speeds.
void bind_lobes_study(py::module_& m) {
  py::class_<ModalFitSummary>(m, "ModalFitSummary", "How a modal model was fitted to one FRF for the time domain.")
      .def_readonly("what", &ModalFitSummary::what)
      .def_readonly("modes", &ModalFitSummary::modes)
      .def_readonly("residual", &ModalFitSummary::residual)
      .def_property_readonly("band_hz", [](const ModalFitSummary& s) { return std::make_pair(s.band_low_hz, s.band_high_hz); })
      .def_readonly("target_met", &ModalFitSummary::target_met)
      .def(
          "to_dict", [](const ModalFitSummary& s) { return dict_of(s); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  py::class_<LobesStudyResult>(m, "LobesStudyResult", "run_lobes_study's result.")
      .def_property_readonly("method", [](const LobesStudyResult& r) { return name_of(r.method, kLobesMethods); })
      .def_readonly("cutting", &LobesStudyResult::cutting)
      .def_readonly("zero_order", &LobesStudyResult::zero_order, "ZeroOrderResult (method 'zoa') or None")
      .def_readonly("boundary", &LobesStudyResult::boundary, "BoundaryResult (method 'fd' or 'sd') or None")
      .def_property_readonly("x_modes", [](const LobesStudyResult& r) { return r.modes.x; })
      .def_property_readonly("y_modes", [](const LobesStudyResult& r) { return r.modes.y; })
      .def_readonly("fits", &LobesStudyResult::fits)
      .def_property_readonly("envelope", [](const LobesStudyResult& r) { return envelope_dict(r.envelope); })
      .def_property_readonly(
          "pockets", [](const LobesStudyResult& r) { return envelope_dict(r.pockets); }, "the best speeds, deepest first")
      .def_readonly("uncertainty", &LobesStudyResult::uncertainty, "StabilityUncertainty (with `joint`) or None")
      .def_readonly("uncertain_joint", &LobesStudyResult::uncertain_joint, "the joint file sampled (with `joint`)")
      .def_property_readonly(
          "speed_model", [](const LobesStudyResult& r) { return name_of(r.speed_model, kSpeedModels); },
          "the dynamics used: 'standstill', or at speed 'bearings' / 'spinning'")
      .def_readonly("frf_speeds_rpm", &LobesStudyResult::frf_speeds_rpm,
                    "at speed: the speeds [rpm] where the x-y FRF was evaluated (nodes and midpoints); [] otherwise")
      .def_readonly(
          "frf_interpolation_error", &LobesStudyResult::frf_interpolation_error,
          "at speed: the largest relative error of the FRF interpolated between nodes, at the midpoints (NaN otherwise)")
      .def_readonly("envelope_interpolation_error", &LobesStudyResult::envelope_interpolation_error,
                    "at speed: the largest relative change of the envelope's depth, nodes alone against nodes and midpoints")
      .def_readonly("fit_residual", &LobesStudyResult::fit_residual,
                    "fd at speed: the largest residual of the direct modal fits over the speeds (NaN otherwise)")
      .def_readonly("block_fit_residual", &LobesStudyResult::block_fit_residual,
                    "fd at speed: the largest residual of the whole model against the x-y block, relative to the direct FRFs "
                    "(NaN otherwise)")
      .def_readonly("warnings", &LobesStudyResult::warnings)
      .def(
          "to_dict", [](const LobesStudyResult& r) { return dict_of(r); },
          "toolpoint lobes --json's keys (SI: depths in m; the envelope and figure data left out).");
  m.def(
      "run_lobes_study",
      [](const CuttingConditions& cutting, std::tuple<double, double, int> speeds, const std::string& method,
         const std::optional<RealArray>& f, const std::optional<ComplexArray>& xx, const std::optional<ComplexArray>& yy,
         const std::optional<ComplexArray>& xy, const std::optional<ComplexArray>& yx, std::vector<Mode> x_modes,
         std::vector<Mode> y_modes, bool rigid_y, std::string frf_name, double max_depth_m, int lobes, double tolerance,
         int steps, int degree, int max_modes, std::optional<std::pair<double, double>> band_hz, double fit_target,
         double pocket_prominence, int pockets, int threads, std::optional<Assembly> assembly, std::optional<JointFile> joint,
         int samples, std::uint64_t seed, std::vector<double> levels, const std::string& speed_model, int speed_nodes,
         bool extrapolate_bearings, const py::object& progress) {
        LobesInput in;
        in.assembly = std::move(assembly);
        in.uncertain_joint = std::move(joint);
        if (xx) {
          if (!f) throw InvalidArgument("run_lobes_study: xx needs frequency_hz", "pass frequency_hz [Hz] with the FRFs");
          in.frfs = milling_of(*f, *xx, yy, xy, yx, rigid_y);
        }
        in.frf_name = std::move(frf_name);
        in.x_modes = std::move(x_modes);
        in.y_modes = std::move(y_modes);
        in.rigid_y = rigid_y;
        LobesStudyOptions o = lobes_study_options(cutting, speeds, method, max_depth_m, lobes, tolerance, steps, degree,
                                                  max_modes, band_hz, fit_target);
        o.pocket_prominence = pocket_prominence;
        o.pockets = pockets;
        o.parallel.threads = threads;
        o.uncertainty = uncertainty_options(samples, seed, std::move(levels), threads, py::none());
        o.speed_model = enum_of(speed_model, kSpeedModels, "speed_model");
        o.speed_nodes = speed_nodes;
        o.extrapolate_bearings = extrapolate_bearings;
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_lobes_study(in, o, cb);
      },
      "cutting"_a, "speeds"_a, "method"_a = "zoa", "frequency_hz"_a = py::none(), "xx"_a = py::none(), "yy"_a = py::none(),
      "xy"_a = py::none(), "yx"_a = py::none(), "x_modes"_a = std::vector<Mode>{}, "y_modes"_a = std::vector<Mode>{},
      "rigid_y"_a = false, "frf_name"_a = "tool point FRF", "max_depth_m"_a = 0.0, "lobes"_a = -1, "tolerance"_a = 0.01,
      "steps"_a = 0, "degree"_a = 2, "max_modes"_a = 8, "band_hz"_a = py::none(), "fit_target"_a = 0.02,
      "pocket_prominence"_a = 0.02, "pockets"_a = 5, "threads"_a = 0, "assembly"_a = py::none(), "joint"_a = py::none(),
      "samples"_a = 200, "seed"_a = 1, "levels"_a = std::vector<double>{0.05, 0.5, 0.95}, "speed_model"_a = "auto",
      "speed_nodes"_a = 0, "extrapolate_bearings"_a = false, "progress"_a = py::none(),
      fields_doc(
          lobes_study_fields(), "LobesStudyOptions", "toolpoint lobes",
          "The lobes study (toolpoint lobes): method 'zoa' (zero-order, from the FRFs xx[, yy, xy, yx] [m/N] on frequency_hz "
          "[Hz]) "
          "or 'fd' / 'sd' (time-domain boundary by full- / semi-discretization of x_modes/y_modes, or of modes fitted to "
          "the FRFs: at most max_modes, the fewest within fit_target). "
          "speeds = (min_rpm, max_rpm, points; 0 points: 2000 zoa, 200 fd). Depths in m. The best speeds rise pocket_prominence "
          "above "
          "their valleys. With `assembly` (whose tool point FRF xx is) and `joint` (a JointFile with [uncertainty]): also the "
          "stable depth's quantiles and the probability of stability over `samples` joints drawn from its covariance "
          "(result.uncertainty, as toolpoint lobes --samples). With `assembly` and no FRFs, speed_model ('auto', 'standstill', "
          "'bearings', 'spinning'; toolpoint lobes --speed-model) chooses the dynamics: at speed the x-y FRF at speed_nodes "
          "speeds (0: 17) and midway, interpolated in speed, its error in result.frf_interpolation_error and "
          "envelope_interpolation_error (method 'fd': a modal model with x-y pole-residue terms fitted at each speed, "
          "result.fit_residual, block_fit_residual); a speed outside a bearing's table is refused unless extrapolate_bearings."));
  m.def(
      "milling_frfs",
      [](const AssemblyModel& md, const RealArray& f, bool rigid_y) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        MillingFrfs r;
        {
          py::gil_scoped_release nogil;
          r = milling_frfs(md, grid, rigid_y);
        }
        return array_of(r.xx.values);
      },
      "model"_a, "frequency_hz"_a, "rigid_y"_a = false,
      "The tool point FRF G_xx = SHT11's H [m/N] of an AssemblyModel on frequency_hz [Hz], as toolpoint lobes --assembly uses it "
      "for x and y.");
  m.def(
      "stability_pockets",
      [](const py::dict& envelope, int count, double min_prominence) {
        const std::vector<double> n = vector_of(envelope["speed_rpm"].cast<RealArray>(), "speed_rpm"),
                                  d = vector_of(envelope["depth_m"].cast<RealArray>(), "depth_m"),
                                  c = vector_of(envelope["chatter_hz"].cast<RealArray>(), "chatter_hz");
        const std::vector<int> lobe = envelope["lobe"].cast<std::vector<int>>();
        std::vector<EnvelopePoint> e(n.size());
        for (std::size_t i = 0; i < n.size(); ++i) e[i] = {n[i], d.at(i), c.at(i), lobe.at(i)};
        return envelope_dict(stability_pockets(e, count, min_prominence));
      },
      "envelope"_a, "count"_a = 5, "min_prominence"_a = 0.02,
      "The best spindle speeds of an envelope dict: maxima rising min_prominence above their valleys.");
}

// Stability with the joint uncertain.
void bind_stability_uncertainty(py::module_& m) {
  py::class_<StabilityUncertainty>(m, "StabilityUncertainty",
                                   "Quantiles of the stable depth per speed and the probability of stability.")
      .def_property_readonly(
          "speed_rpm", [](const StabilityUncertainty& s) { return array_of(s.speed_rpm); }, "(speeds,) rpm")
      .def_property_readonly(
          "levels", [](const StabilityUncertainty& s) { return array_of(s.levels); }, "the quantile levels")
      .def_property_readonly(
          "nominal_depth_m", [](const StabilityUncertainty& s) { return array_of(s.nominal_depth_m); },
          "(speeds,) the envelope with the joint's constants [m]")
      .def_property_readonly(
          "depth_m", [](const StabilityUncertainty& s) { return matrix_array(rows_matrix(s.depth_m)); },
          "(levels, speeds) quantiles of the stable depth [m]")
      .def_property_readonly(
          "depth_grid_m", [](const StabilityUncertainty& s) { return array_of(s.depth_grid_m); }, "(depths,) [m]")
      .def_property_readonly(
          "probability", [](const StabilityUncertainty& s) { return matrix_array(s.probability); },
          "(speeds, depths): the fraction of samples stable there, in [0, 1]")
      .def_readonly("samples", &StabilityUncertainty::samples)
      .def(
          "to_dict", [](const StabilityUncertainty& s) { return dict_of(s); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  m.def(
      "stability_uncertainty",
      [](Assembly a, JointFile joint, const RealArray& f, const CuttingConditions& cutting,
         std::tuple<double, double, int> speeds, const RealArray& depth_grid_m, const std::string& method, double max_depth_m,
         int lobes, double tolerance, int steps, int degree, int max_modes, std::optional<std::pair<double, double>> band_hz,
         double fit_target, int samples, std::uint64_t seed, std::vector<double> levels, int threads,
         const py::object& progress) {
        const std::vector<double> grid = vector_of(f, "frequency_hz"), depths = vector_of(depth_grid_m, "depth_grid_m");
        const LobesStudyOptions lo = lobes_study_options(cutting, speeds, method, max_depth_m, lobes, tolerance, steps, degree,
                                                         max_modes, band_hz, fit_target);
        const UncertaintyOptions o = uncertainty_options(samples, seed, std::move(levels), threads, progress);
        py::gil_scoped_release nogil;
        return stability_uncertainty(a, joint, grid, lo, depths, o);
      },
      "assembly"_a, "joint"_a, "frequency_hz"_a, "cutting"_a, "speeds"_a, "depth_grid_m"_a, "method"_a = "zoa",
      "max_depth_m"_a = 0.0, "lobes"_a = -1, "tolerance"_a = 0.01, "steps"_a = 0, "degree"_a = 2, "max_modes"_a = 8,
      "band_hz"_a = py::none(), "fit_target"_a = 0.02, "samples"_a = 200, "seed"_a = 1,
      "levels"_a = std::vector<double>{0.05, 0.5, 0.95}, "threads"_a = 0, "progress"_a = py::none(),
      "Stability with the joint of a JointFile (with [uncertainty]) uncertain (toolpoint lobes --joint ... --samples N): each "
      "sampled joint's tool point FRF on frequency_hz [Hz] through the lobes study (method 'zoa' or 'fd', its options as in "
      "run_lobes_study); per speed the quantiles of the stable depth [m], and on depth_grid_m [m] the probability of stability. "
      "threads: 0 every core; results identical for any count.");
}

}  // namespace

void bind_stability(py::module_& m) {
  py::dict tables;
  tables["LobesStudyOptions"] = fields_data(lobes_study_fields());
  tables["CuttingConditions"] = fields_data(cutting_fields());
  tables["SpeedRange"] = fields_data(speed_range_fields());
  tables["NoiseSpec"] = fields_data(noise_spec_fields());
  tables["ForceLaw"] = fields_data(force_law_fields());
  tables["SimulationOptions"] = fields_data(simulation_fields());
  tables["PitchChoiceOptions"] = fields_data(pitch_choice_fields());
  tables["JointFitOptions"] = fields_data(joint_fit_fields());
  tables["ForwardCheckOptions"] = fields_data(forward_check_fields());
  tables["IdentificationOptions"] = fields_data(identification_fields());
  tables["TapTestOptions"] = fields_data(tap_test_fields());
  tables["NoiseOptions"] = fields_data(noise_fields());
  tables["TapNoise"] = fields_data(tap_noise_fields());
  tables["SavgolOptions"] = fields_data(savgol_fields());
  tables["PeakChangeOptions"] = fields_data(peak_change_fields());
  tables["RotationalOptions"] = fields_data(rotational_fields());
  tables["PeakOptions"] = fields_data(peak_fields());
  tables["NoiseEstimateOptions"] = fields_data(noise_estimate_fields());
  tables["TapTestFileOptions"] = fields_data(tap_test_file_fields());
  tables["ReadoutOptions"] = fields_data(readout_fields());
  tables["VerdictOptions"] = fields_data(verdict_fields());
  tables["UffWriteOptions"] = fields_data(uff_write_fields());
  tables["PlotOptions"] = fields_data(plot::plot_fields());
  tables["FrfFigureOptions"] = fields_data(plot::frf_figure_fields());
  tables["ModalFitOptions"] = fields_data(modal_fit_fields());
  tables["CaseStudyOptions"] = fields_data(case_study_fields());
  tables["PrecisionOptions"] = fields_data(precision_fields());
  tables["ParallelOptions"] = fields_data(parallel_fields());
  tables["UncertaintyOptions"] = fields_data(uncertainty_fields());
  tables["ZeroOrderOptions"] = fields_data(zero_order_fields());
  tables["BoundaryOptions"] = fields_data(boundary_fields());
  tables["ModalOptions"] = fields_data(modal_fields());
  tables["BeamStudyOptions"] = fields_data(beam_study_fields());
  tables["PredictOptions"] = fields_data(predict_fields());
  tables["OverhangStudyOptions"] = fields_data(overhang_study_fields());
  m.attr("_option_fields") = tables;
  bind_modal_models(m);
  bind_zero_order(m);
  bind_time_domain(m);
  bind_lobes_study(m);
  bind_stability_uncertainty(m);
}

}  // namespace toolpoint::python
