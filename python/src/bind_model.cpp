// toolpoint Python bindings: materials, beam segments, assemblies, joints and the forward model
// (beam.hpp, assembly.hpp, assembly_file.hpp, joint.hpp, studies/predict.hpp, overhang.hpp,
// tap_test.hpp). Units SI; frequencies in Hz.
#include "common.hpp"
#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/model/beam.hpp"
#include "toolpoint/model/coupling.hpp"
#include "toolpoint/model/joint.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/beam.hpp"
#include "toolpoint/studies/fd_correction.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/rotational.hpp"
#include "toolpoint/studies/tap_test.hpp"

namespace toolpoint::python {

namespace {

using namespace pybind11::literals;

const std::vector<std::pair<const char*, EndBlock>> kEndBlocks{{"11", EndBlock::T11},
                                                               {"12", EndBlock::T12},
                                                               {"21", EndBlock::T21},
                                                               {"22", EndBlock::T22}};
const std::vector<std::pair<const char*, BeamMethod>> kBeamMethods{{"exact", BeamMethod::Exact}, {"modal", BeamMethod::Modal}};
const std::vector<std::pair<const char*, ShearModel>> kShearModels{{"hutchinson", ShearModel::Hutchinson},
                                                                   {"cowper", ShearModel::Cowper}};
const std::vector<std::pair<const char*, ReceptanceMethod>> kMethods{{"exact", ReceptanceMethod::Exact},
                                                                     {"modal", ReceptanceMethod::Modal}};
const std::vector<std::pair<const char*, PredictedFrf>> kPredicted{{"SHT11", PredictedFrf::ToolPoint},
                                                                   {"SH11", PredictedFrf::HolderTip}};
const std::vector<std::pair<const char*, TapSide>> kSides{{"tool", TapSide::Tool}, {"holder", TapSide::Holder}};

// A per-frequency function of the model over an array of frequencies, GIL released.
template <class F>
py::array_t<std::complex<double>> blocks_over(const RealArray& frequency_hz, F&& at) {
  const std::vector<double> f = vector_of(frequency_hz, "frequency_hz");
  std::vector<Block> out(f.size());
  {
    py::gil_scoped_release nogil;
    for (std::size_t i = 0; i < f.size(); ++i) out[i] = block_at(at, f[i]);
  }
  return blocks_array(out);
}

template <class F>
py::array_t<std::complex<double>> two_ports_over(const RealArray& frequency_hz, F&& at) {
  const std::vector<double> f = vector_of(frequency_hz, "frequency_hz");
  std::vector<TwoPort> out(f.size());
  {
    py::gil_scoped_release nogil;
    for (std::size_t i = 0; i < f.size(); ++i) out[i] = at(f[i]);
  }
  return two_ports_array(out);
}

py::object joint_get(const Joint& j) { return j.rigid ? py::none() : py::cast(j.parameters); }
Joint joint_set(const py::object& o) {
  if (o.is_none()) return Joint::make_rigid();
  return Joint::make_elastic(o.cast<JointParameters>());
}

std::string repr_parameters(const JointParameters& p) {
  std::string s = "JointParameters(";
  for (int k = 0; k < 8; ++k) s += fmt::format("{}{}={:.17g}", k ? ", " : "", JointParameters::name(k), p[k]);
  return s + ")";
}

int parameter_index(const py::object& key) {
  if (py::isinstance<py::str>(key)) {
    const std::string name = key.cast<std::string>();
    for (int k = 0; k < 8; ++k)
      if (name == JointParameters::name(k)) return k;
    throw py::key_error(fmt::format("'{}' is not a joint parameter (k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm)", name));
  }
  const int k = key.cast<int>();
  if (k < 0 || k > 7) throw py::index_error(fmt::format("joint parameter index {} is outside 0…7", k));
  return k;
}

// Joints: the eight parameters, K(ω), the seed's Table 1.
void bind_joints(py::module_& m) {
  // ---- Joints ------------------------------------------------------------------------------------
  py::class_<JointParameters>(m, "JointParameters",
                              "The eight contact parameters of a joint (seed Eq. 8): K(ω) = [[k_yf + iωc_yf, k_ym + iωc_ym], "
                              "[k_tf + iωc_tf, k_tm + iωc_tm]]. Units: k_yf N/m, c_yf N·s/m, k_ym N, c_ym N·s, k_tf N/rad, "
                              "c_tf N·s/rad, k_tm N·m/rad, c_tm N·m·s/rad (θ spelt 't'). Index by name or 0…7.")
      .def(py::init([](double k_yf, double c_yf, double k_ym, double c_ym, py::object k_tf, py::object c_tf, double k_tm,
                       double c_tm) {
             JointParameters p{k_yf, c_yf, k_ym, c_ym, 0, 0, k_tm, c_tm};
             p.k_tf = k_tf.is_none() ? k_ym : k_tf.cast<double>();
             p.c_tf = c_tf.is_none() ? c_ym : c_tf.cast<double>();
             return p;
           }),
           "k_yf"_a = 0.0, "c_yf"_a = 0.0, "k_ym"_a = 0.0, "c_ym"_a = 0.0, "k_tf"_a = py::none(), "c_tf"_a = py::none(),
           "k_tm"_a = 0.0, "c_tm"_a = 0.0, "k_tf and c_tf default to k_ym and c_ym (reciprocity), as in an assembly file.")
      .def_readwrite("k_yf", &JointParameters::k_yf, "N/m")
      .def_readwrite("c_yf", &JointParameters::c_yf, "N·s/m")
      .def_readwrite("k_ym", &JointParameters::k_ym, "N")
      .def_readwrite("c_ym", &JointParameters::c_ym, "N·s")
      .def_readwrite("k_tf", &JointParameters::k_tf, "N/rad")
      .def_readwrite("c_tf", &JointParameters::c_tf, "N·s/rad")
      .def_readwrite("k_tm", &JointParameters::k_tm, "N·m/rad")
      .def_readwrite("c_tm", &JointParameters::c_tm, "N·m·s/rad")
      .def("__getitem__", [](const JointParameters& p, const py::object& key) { return p[parameter_index(key)]; })
      .def("__setitem__", [](JointParameters& p, const py::object& key, double v) { p[parameter_index(key)] = v; })
      .def("__len__", [](const JointParameters&) { return 8; })
      .def("__eq__",
           [](const JointParameters& a, const JointParameters& b) {
             for (int k = 0; k < 8; ++k)
               if (!(a[k] == b[k])) return false;
             return true;
           })
      .def("__repr__", &repr_parameters)
      .def(
          "to_array",
          [](const JointParameters& p) {
            std::vector<double> v(8);
            for (int k = 0; k < 8; ++k) v[static_cast<std::size_t>(k)] = p[k];
            return array_of(v);
          },
          "The eight values as a float array (8,), order k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm (SI).")
      .def_static(
          "from_array",
          [](const RealArray& a) {
            const std::vector<double> v = vector_of(a, "values");
            if (v.size() != 8)
              throw InputError(fmt::format("values: {} numbers where 8 joint parameters were expected", v.size()),
                               "give k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm");
            JointParameters p;
            for (int k = 0; k < 8; ++k) p[k] = v[static_cast<std::size_t>(k)];
            return p;
          },
          "values"_a, "From a float array (8,) in the order of to_array() (SI).")
      .def(
          "to_dict", [](const JointParameters& p) { return dict_of(p); }, "{'k_yf': value, ...} (SI).")
      .def(
          "stiffness",
          [](const JointParameters& p, const RealArray& f) { return blocks_over(f, [&](double x) { return p.stiffness(x); }); },
          "frequency_hz"_a, "K(ω) of Eq. 8 at each frequency [Hz]: complex (n, 2, 2), entries in N/m, N, N/rad, N·m/rad.")
      .def("check", &JointParameters::check, "Raises InvalidArgument naming a parameter that is not finite.")
      .def_static(
          "names",
          [] {
            std::vector<std::string> n;
            for (int k = 0; k < 8; ++k) n.emplace_back(JointParameters::name(k));
            return n;
          },
          "['k_yf', 'c_yf', 'k_ym', 'c_ym', 'k_tf', 'c_tf', 'k_tm', 'c_tm']")
      .def_static(
          "units",
          [] {
            std::vector<std::string> n;
            for (int k = 0; k < 8; ++k) n.emplace_back(JointParameters::unit(k));
            return n;
          },
          "The SI unit of each parameter, in the order of names().");
  m.def("seed_table1_joint", &seed_table1_joint, "The seed's Table 1 holder–tool joint (Özşahin et al. 2009), SI units.");
  m.def("joint_warnings", &joint_warnings, "parameters"_a, "name"_a = "joint",
        "Warnings about a legal but indefinite joint (negative stiffness or damping motions), labelled with `name`.");
}

// Materials, sections and segments: free–free receptances, exact and modal, spinning; the beam study.
void bind_segments(py::module_& m) {
  // ---- Materials and segments ---------------------------------------------------------------------
  py::class_<Material>(m, "Material",
                       "An isotropic material. E and G in Pa, density in kg/m³, ν and loss factor η dimensionless.")
      .def(py::init([](std::string name, double E, double nu, double G, double rho, double eta) {
             return Material{std::move(name), E, nu, G, rho, eta};
           }),
           "name"_a = "", "youngs_modulus"_a = 0.0, "poisson"_a = 0.3, "shear_modulus"_a = 0.0, "density"_a = 0.0,
           "loss_factor"_a = 0.0)
      .def_readwrite("name", &Material::name)
      .def_readwrite("youngs_modulus", &Material::youngs_modulus, "E [Pa]")
      .def_readwrite("poisson", &Material::poisson, "ν, in (−1, 0.5)")
      .def_readwrite("shear_modulus", &Material::shear_modulus, "G [Pa]; 0 means E/(2(1+ν))")
      .def_readwrite("density", &Material::density, "ρ [kg/m³]")
      .def_readwrite("loss_factor", &Material::loss_factor, "η ≥ 0, applied to E and G")
      .def("G", &Material::G, "The shear modulus used [Pa].")
      .def("check", &Material::check, "Raises InvalidArgument naming a value out of range.")
      .def(
          "__eq__",
          [](const Material& a, const Material& b) {
            return a.name == b.name && a.youngs_modulus == b.youngs_modulus && a.poisson == b.poisson &&
                   a.shear_modulus == b.shear_modulus && a.density == b.density && a.loss_factor == b.loss_factor;
          },
          py::is_operator())
      .def("__repr__", [](const Material& x) {
        return fmt::format(
            "Material(name='{}', youngs_modulus={:g}, poisson={:g}, shear_modulus={:g}, density={:g}, loss_factor={:g})", x.name,
            x.youngs_modulus, x.poisson, x.shear_modulus, x.density, x.loss_factor);
      });

  py::class_<Annulus>(m, "Annulus", "One concentric layer of a circular section. Diameters in m (inner 0: solid).")
      .def(py::init([](double outer, double inner, Material material, std::optional<double> kappa) {
             return Annulus{outer, inner, std::move(material), kappa};
           }),
           "outer_diameter"_a, "inner_diameter"_a = 0.0, "material"_a = Material{}, "shear_coefficient"_a = py::none())
      .def_readwrite("outer_diameter", &Annulus::outer_diameter, "m")
      .def_readwrite("inner_diameter", &Annulus::inner_diameter, "m")
      .def_readwrite("material", &Annulus::material)
      .def_readwrite("shear_coefficient", &Annulus::shear_coefficient, "κ override (None: from the section's shear model)")
      .def("area", &Annulus::area, "Area [m²].")
      .def("second_moment", &Annulus::second_moment, "Second moment of area I [m⁴].");

  py::class_<SectionProperties>(m, "SectionProperties", "Per-unit-length section properties of a segment.")
      .def_readonly("EI", &SectionProperties::EI, "bending stiffness Σ E(1+iη) I [N·m²] (complex)")
      .def_readonly("kGA", &SectionProperties::kGA, "shear stiffness Σ κ G(1+iη) A [N] (complex)")
      .def_readonly("rhoA", &SectionProperties::rhoA, "mass per length [kg/m]")
      .def_readonly("rhoI", &SectionProperties::rhoI, "rotary inertia per length [kg·m]")
      .def("cutoff_frequency_hz", &SectionProperties::cutoff_frequency_hz, "Ω_c = sqrt(κGA/ρI) in Hz.");

  py::class_<Segment>(m, "Segment",
                      "A uniform Timoshenko segment: length [m] and concentric layers (Annulus). End 1 is its outer end "
                      "(towards the tool tip). Lists are copied in and out: assign a whole list to change layers.")
      .def(py::init([](double length, std::vector<Annulus> layers, std::string name, const std::string& shear) {
             return Segment{std::move(name), length, std::move(layers), enum_of(shear, kShearModels, "shear_model")};
           }),
           "length"_a, "layers"_a, "name"_a = "", "shear_model"_a = "hutchinson")
      .def_static(
          "tube",
          [](double length, double outer, double inner, const Material& mat, std::string name) {
            return Segment::tube(length, outer, inner, mat, std::move(name));
          },
          "length"_a, "outer_diameter"_a, "inner_diameter"_a, "material"_a, "name"_a = "",
          "A one-layer segment; lengths and diameters in m.")
      .def_readwrite("name", &Segment::name)
      .def_readwrite("length", &Segment::length, "m")
      .def_readwrite("layers", &Segment::layers, "list of Annulus (a copy)")
      .def_property(
          "shear_model", [](const Segment& s) { return name_of(s.shear_model, kShearModels); },
          [](Segment& s, const std::string& v) { s.shear_model = enum_of(v, kShearModels, "shear_model"); },
          "'hutchinson' or 'cowper'")
      .def("properties", &Segment::properties, "EI, κGA, ρA, ρI of the section.")
      .def("check", &Segment::check, "Raises InvalidArgument naming a value out of range.");

  m.def(
      "exact_receptance",
      [](Segment s, const RealArray& f) { return two_ports_over(f, [&](double x) { return exact_receptance(s, x); }); },
      "segment"_a, "frequency_hz"_a,
      "Free–free end receptances of a uniform Timoshenko segment by the exact (truncation-free) solution, seed Eq. 9–14 "
      "generalised: complex (n, 4, 4) over (w1, θ1, w2, θ2) = [[T11, T12], [T21, T22]]; H in m/N, L 1/N, N rad/N, P rad/(N·m). "
      "Frequencies in Hz (> 0).");
  m.def(
      "spinning_receptance",
      [](Segment s, const RealArray& frequency_hz, double speed_rpm) {
        s.check();
        const std::vector<double> f = vector_of(frequency_hz, "frequency_hz");
        const SectionProperties p = s.properties();
        const double spin = rad_s_of_rpm(speed_rpm);
        py::array_t<std::complex<double>> out({static_cast<py::ssize_t>(f.size()), py::ssize_t{8}, py::ssize_t{8}});
        auto a = out.mutable_unchecked<3>();
        std::vector<TwoPort4> t(f.size());
        {
          py::gil_scoped_release nogil;
          for (std::size_t i = 0; i < f.size(); ++i) t[i] = spinning_receptance(p, s.length, f[i], spin);
        }
        for (std::size_t i = 0; i < f.size(); ++i) {
          const Block4* b[2][2] = {{&t[i].b11, &t[i].b12}, {&t[i].b21, &t[i].b22}};
          for (int r = 0; r < 8; ++r)
            for (int c = 0; c < 8; ++c) a(static_cast<py::ssize_t>(i), r, c) = (*b[r / 4][c / 4])(r % 4, c % 4);
        }
        return out;
      },
      "segment"_a, "frequency_hz"_a, "speed_rpm"_a,
      "Free–free end receptances of a segment spinning at `speed_rpm` [rpm] (docs/reference.md §10), both planes: complex "
      "(n, 8, 8) over (w_x1, ψ_x1, w_y1, ψ_y1, w_x2, ψ_x2, w_y2, ψ_y2) = [[T11, T12], [T21, T22]] of 4×4 blocks; the x–y "
      "blocks are the gyroscopic cross receptances (skew). Frequencies in Hz (> 0).");
  m.def(
      "whirl_frequencies",
      [](const Segment& s, double speed_rpm, int count) {
        s.check();
        return dict_of(whirl_frequencies(s.properties(), s.length, rad_s_of_rpm(speed_rpm), count));
      },
      "segment"_a, "speed_rpm"_a, "count"_a,
      "The first `count` natural frequencies [Hz] of each whirl of a free–free segment spinning at `speed_rpm` [rpm], "
      "undamped: {'forward_hz', 'backward_hz', 'conical_hz', 'spin_rad_s', 'speed_rpm'}.");
  m.def(
      "free_free_frequencies",
      [](const Segment& s, int count) { return array_of(free_free_frequencies(s.properties(), s.length, count)); }, "segment"_a,
      "count"_a,
      "The first `count` elastic free–free natural frequencies [Hz] (exact frequency equation, both branches), undamped.");
  py::class_<ModalBeam, std::shared_ptr<ModalBeam>>(
      m, "ModalBeam",
      "A segment's free–free modes (mass-normalised, rigid-body modes plus `modes` elastic ones): "
      "receptances by modal summation (seed Eq. 11–14).")
      .def(py::init([](Segment s, int modes, bool static_residual) {
             ModalOptions o{modes, static_residual};
             py::gil_scoped_release nogil;
             return std::make_shared<ModalBeam>(s.properties(), s.length, o);
           }),
           "segment"_a, "modes"_a = 100, "static_residual"_a = false)
      .def(
          "receptance",
          [](const ModalBeam& b, const RealArray& f) { return two_ports_over(f, [&](double x) { return b.receptance(x); }); },
          "frequency_hz"_a, "End receptances by modal summation: complex (n, 4, 4) as exact_receptance. Frequencies in Hz.")
      .def_property_readonly(
          "frequency_hz",
          [](const ModalBeam& b) {
            std::vector<double> f;
            for (const FreeMode& x : b.modes()) f.push_back(x.frequency_hz);
            return array_of(f);
          },
          "The elastic modes' undamped natural frequencies [Hz].")
      .def_property_readonly("loss_factor", &ModalBeam::loss_factor);

}

// The beam study from Python (both forms): the section, speed and material judged as the CLI's
// --length, --diameter, --inner-diameter, --speed (beam_study_fields), --youngs-modulus, --density,
// --shear-modulus, --loss-factor and --shear-coefficient (plausibility.hpp), then the library's checks.
BeamStudy beam_from_python(const BeamStudyOptions& o) {
  // The geometry and the speed: unusual ones warned about as the flags warn (a value that cannot
  // be meant is refused by BeamStudyOptions::check, as at the flags).
  warn_all(field_plausibility_warnings(beam_study_fields(), o, "BeamStudyOptions"));
  check_plausible(plausible::kYoungsModulus, o.material.youngs_modulus, "Material::youngs_modulus",
                  "give E in Pa (steel 2.1e11)");
  check_plausible(plausible::kDensity, o.material.density, "Material::density", "give ρ in kg/m³ (steel 7800)");
  if (o.material.shear_modulus > 0.0)
    check_plausible(plausible::kShearModulus, o.material.shear_modulus, "Material::shear_modulus",
                    "give G in Pa (steel 8e10)");
  check_plausible(plausible::kLossFactor, o.material.loss_factor, "Material::loss_factor", "give η as a fraction (0.01)");
  if (o.shear_coefficient)
    check_plausible(plausible::kShearCoefficient, *o.shear_coefficient, "BeamStudyOptions::shear_coefficient",
                    "κ is about 0.9 for a solid round section");
  py::gil_scoped_release nogil;
  return run_beam_study(o);
}

// The beam study: a segment's section, natural frequencies and end block.
void bind_beam_study(py::module_& m) {
  auto modal = options_class<ModalOptions>(m, "ModalOptions", "Modal summation's options (beam.hpp; BeamStudyOptions.modal).",
                                           {"modes", "static_residual"});
  def_option_fields(modal, modal_fields(), "toolpoint beam");
  auto beam = options_class<BeamStudyOptions>(m, "BeamStudyOptions", "run_beam_study's options (studies/beam.hpp; toolpoint beam's).",
                                              {"length", "outer_diameter", "inner_diameter", "material", "shear_coefficient",
                                               "shear_model", "modes", "frequency_hz", "block", "method", "modal", "speed_rpm",
                                               "campbell_rpm"});
  def_option_fields(beam, beam_study_fields(), "toolpoint beam");
  beam.def_readwrite("material", &BeamStudyOptions::material, "Material (default steel, undamped)")
      .def_readwrite("shear_coefficient", &BeamStudyOptions::shear_coefficient,
                     "κ, or None: from shear_model, ν and the diameters")
      .def_property(
          "shear_model", [](const BeamStudyOptions& o) { return std::string(name_of(o.shear_model, kShearModels)); },
          [](BeamStudyOptions& o, const std::string& v) {
            o.shear_model = enum_of(v, kShearModels, "BeamStudyOptions::shear_model");
          },
          "'hutchinson' or 'cowper'")
      .def_readwrite("frequency_hz", &BeamStudyOptions::frequency_hz, "the receptance's grid [Hz]; []: no receptance")
      .def_property(
          "block", [](const BeamStudyOptions& o) { return std::string(name_of(o.block, kEndBlocks)); },
          [](BeamStudyOptions& o, const std::string& v) { o.block = enum_of(v, kEndBlocks, "BeamStudyOptions::block"); },
          "which end block: '11' (end 1 = the outer end), '12', '21' or '22'")
      .def_property(
          "method", [](const BeamStudyOptions& o) { return std::string(name_of(o.method, kBeamMethods)); },
          [](BeamStudyOptions& o, const std::string& v) { o.method = enum_of(v, kBeamMethods, "BeamStudyOptions::method"); },
          "'exact' (closed form) or 'modal' (summation over `modal`'s modes)")
      .def_readwrite("modal", &BeamStudyOptions::modal, "ModalOptions of the 'modal' method")
      .def_readwrite("campbell_rpm", &BeamStudyOptions::campbell_rpm, "speeds [rpm] of the Campbell diagram; []: none");
  py::class_<BeamStudy>(m, "BeamStudy", "run_beam_study's result (studies/beam.hpp).")
      .def_readonly("segment", &BeamStudy::segment, "the Segment built from the options")
      .def_readonly("properties", &BeamStudy::properties, "SectionProperties: EI, κGA (complex, with η), ρA, ρI")
      .def_property_readonly(
          "section", [](const BeamStudy& r) { return dict_of(r.section); },
          "{'area' m², 'second_moment' m⁴, 'shear_coefficient', 'rhoA' kg/m, 'rhoI' kg·m, 'cutoff_frequency_hz'}")
      .def_property_readonly(
          "mode_frequency_hz",
          [](const BeamStudy& r) {
            std::vector<double> f;
            for (const FreeMode& x : r.modes) f.push_back(x.frequency_hz);
            return array_of(f);
          },
          "(modes,) the elastic free–free natural frequencies [Hz], undamped, ascending")
      .def_property_readonly(
          "frequency_hz", [](const BeamStudy& r) { return array_of(r.receptance.frequency_hz); }, "(n,) Hz")
      .def_property_readonly(
          "receptance", [](const BeamStudy& r) { return blocks_array(r.receptance.blocks); },
          "the end block asked for, complex (n, 2, 2) [[H m/N, L 1/N], [N rad/N, P rad/(N·m)]]")
      .def_readonly("method", &BeamStudy::method, "'exact' or 'modal (N modes[ + static residual])'")
      .def_readonly("speed_rpm", &BeamStudy::speed_rpm, "the spin [rpm] (0: standing)")
      .def_property_readonly(
          "whirl", [](const BeamStudy& r) { return r.whirl ? dict_of(*r.whirl) : py::object(py::none()); },
          "spinning: {'forward_hz': [...], 'backward_hz': [...], 'conical_hz', 'spin_rad_s', 'speed_rpm'}; else None")
      .def_property_readonly(
          "campbell", [](const BeamStudy& r) { return dict_of(r.campbell); },
          "the Campbell diagram: one whirl dict (as `whirl`) per campbell_rpm speed")
      .def_readonly("warnings", &BeamStudy::warnings)
      .def(
          "to_dict", [](const BeamStudy& r) { return dict_of(r); },
          "The result as plain data, the receptance left out (toolpoint beam --json's 'section' and 'modes'; SI units).");
  m.def(
      "run_beam_study",
      [](double length, double outer_diameter, double inner_diameter, Material material, std::optional<double> shear_coefficient,
         const std::string& shear_model, int modes, const py::object& frequency_hz, const std::string& block,
         const std::string& method, int modal_terms, bool static_residual, double speed_rpm, const py::object& campbell_rpm) {
        BeamStudyOptions o;
        o.length = length;
        o.outer_diameter = outer_diameter;
        o.inner_diameter = inner_diameter;
        o.material = std::move(material);
        o.shear_coefficient = shear_coefficient;
        o.shear_model = enum_of(shear_model, kShearModels, "shear_model");
        o.modes = modes;
        if (!frequency_hz.is_none()) o.frequency_hz = vector_of(frequency_hz.cast<RealArray>(), "frequency_hz");
        o.block = enum_of(block, kEndBlocks, "block");
        o.method = enum_of(method, kBeamMethods, "method");
        o.modal = {modal_terms, static_residual};
        o.speed_rpm = speed_rpm;
        if (!campbell_rpm.is_none()) o.campbell_rpm = vector_of(campbell_rpm.cast<RealArray>(), "campbell_rpm");
        return beam_from_python(o);
      },
      "length"_a, "outer_diameter"_a, "inner_diameter"_a = 0.0, "material"_a = Material{"beam", 2.0e11, 0.3, 0.0, 7800.0, 0.0},
      "shear_coefficient"_a = py::none(), "shear_model"_a = "hutchinson", "modes"_a = 5, "frequency_hz"_a = py::none(),
      "block"_a = "11", "method"_a = "exact", "modal_terms"_a = 100, "static_residual"_a = false, "speed_rpm"_a = 0.0,
      "campbell_rpm"_a = py::none(),
      "The beam study (toolpoint beam): one free–free Timoshenko segment of length `length` m and diameters D, d [m] "
      "(material: E, ν, G, ρ, η; default steel) — its section, its first `modes` natural frequencies [Hz] and, on "
      "`frequency_hz` [Hz], the end block '11' (end 1 = the outer end), '12', '21' or '22' by the 'exact' closed form or "
      "'modal' summation over `modal_terms` modes; spinning at `speed_rpm` [rpm] the natural frequencies of each whirl "
      "(BeamStudy.whirl) and the block's x–x part; `campbell_rpm` [rpm] the Campbell diagram (BeamStudy.campbell).");
  m.def(
      "run_beam_study", [](const BeamStudyOptions& options) { return beam_from_python(options); }, "options"_a,
      "The beam study with its options as one BeamStudyOptions (the same as the keyword form above).");
}

// The assembly and its file.
void bind_assembly(py::module_& m) {
  // ---- Assembly -----------------------------------------------------------------------------------
  py::class_<Bearing>(m, "Bearing", "Springs and dampers to ground at `position` m from the spindle nose.")
      .def(py::init([](double position, double k, double c, double kr, double cr, std::string name, std::optional<double> ky,
                       std::optional<double> cy) { return Bearing{std::move(name), position, k, c, kr, cr, ky, cy, {}}; }),
           "position"_a, "stiffness"_a, "damping"_a = 0.0, "rotational_stiffness"_a = 0.0, "rotational_damping"_a = 0.0,
           "name"_a = "", "stiffness_y"_a = py::none(), "damping_y"_a = py::none())
      .def_readwrite("name", &Bearing::name)
      .def_readwrite("position", &Bearing::position, "m from the spindle nose")
      .def_readwrite("stiffness", &Bearing::stiffness, "N/m")
      .def_readwrite("damping", &Bearing::damping, "N·s/m")
      .def_readwrite("rotational_stiffness", &Bearing::rotational_stiffness, "N·m/rad")
      .def_readwrite("rotational_damping", &Bearing::rotational_damping, "N·m·s/rad")
      .def_readwrite("stiffness_y", &Bearing::stiffness_y, "N/m in y where it differs from x (None: as x; two-plane model)")
      .def_readwrite("damping_y", &Bearing::damping_y, "N·s/m in y where it differs from x (None: as x)")
      .def_property(
          "speed_table",
          [](const Bearing& b) {
            std::vector<std::tuple<double, double, double>> t;
            for (const BearingSpeedPoint& r : b.speed_table) t.emplace_back(r.speed_rpm, r.stiffness, r.damping);
            return t;
          },
          [](Bearing& b, const std::vector<std::tuple<double, double, double>>& t) {
            b.speed_table.clear();
            for (const auto& r : t) b.speed_table.push_back({std::get<0>(r), std::get<1>(r), std::get<2>(r)});
          },
          "[(speed_rpm, stiffness N/m, damping N·s/m), …] by increasing speed; [] none (read by run_prediction_study's "
          "speed_rpm)");

  py::class_<Spindle>(m, "Spindle", "Segments from the nose to the rear, and bearings (lists are copied in and out).")
      .def(py::init([](std::vector<Segment> s, std::vector<Bearing> b) {
             return Spindle{std::move(s), std::move(b)};
           }),
           "segments"_a, "bearings"_a = std::vector<Bearing>{})
      .def_readwrite("segments", &Spindle::segments)
      .def_readwrite("bearings", &Spindle::bearings);

  py::class_<Tool>(m, "Tool", "A solid end mill: fluted part (equivalent diameter) from the tip, then the shank. Lengths in m.")
      .def(py::init([](Material mat, double length, double overhang, double diameter, double shank, double flute, double ratio,
                       std::optional<double> kappa) {
             return Tool{std::move(mat), length, overhang, diameter, shank, flute, ratio, kappa};
           }),
           "material"_a, "length"_a, "overhang"_a, "diameter"_a, "shank_diameter"_a = 0.0, "flute_length"_a = 0.0,
           "flute_diameter_ratio"_a = 0.8, "shear_coefficient"_a = py::none())
      .def_readwrite("material", &Tool::material)
      .def_readwrite("length", &Tool::length, "total length [m]")
      .def_readwrite("overhang", &Tool::overhang, "length outside the holder [m]")
      .def_readwrite("diameter", &Tool::diameter, "nominal diameter [m]")
      .def_readwrite("shank_diameter", &Tool::shank_diameter, "[m]; 0: the nominal diameter")
      .def_readwrite("flute_length", &Tool::flute_length, "fluted length from the tip [m]")
      .def_readwrite("flute_diameter_ratio", &Tool::flute_diameter_ratio, "equivalent fluted diameter / nominal")
      .def_readwrite("shear_coefficient", &Tool::shear_coefficient);

  py::class_<Assembly>(m, "Assembly",
                       "A spindle–holder–tool assembly (seed Section 2.1). Joints are JointParameters, or None for rigid. "
                       "grid = (start_hz, stop_hz, step_hz). Lists (holder segments) are copied in and out.")
      .def(py::init([](std::string name, Spindle spindle, std::vector<Segment> holder, Tool tool, const py::object& sh,
                       const py::object& ht, const std::string& shear, const std::string& method, int modal_terms,
                       std::tuple<double, double, double> grid) {
             Assembly a;
             a.name = std::move(name);
             a.spindle = std::move(spindle);
             a.holder = std::move(holder);
             a.tool = std::move(tool);
             a.spindle_holder = joint_set(sh);
             a.holder_tool = joint_set(ht);
             a.shear_model = enum_of(shear, kShearModels, "shear_model");
             a.method = enum_of(method, kMethods, "method");
             a.modal_terms = modal_terms;
             a.grid = {std::get<0>(grid), std::get<1>(grid), std::get<2>(grid)};
             return a;
           }),
           "name"_a, "spindle"_a, "holder"_a, "tool"_a, "spindle_holder"_a = py::none(), "holder_tool"_a = py::none(),
           "shear_model"_a = "hutchinson", "method"_a = "exact", "modal_terms"_a = 100,
           "grid"_a = std::make_tuple(10.0, 5000.0, 1.0))
      .def_readwrite("name", &Assembly::name)
      .def_readwrite("spindle", &Assembly::spindle)
      .def_readwrite("holder", &Assembly::holder, "holder segments from its tip (a copy)")
      .def_readwrite("tool", &Assembly::tool)
      .def_property(
          "spindle_holder", [](const Assembly& a) { return joint_get(a.spindle_holder); },
          [](Assembly& a, const py::object& o) { a.spindle_holder = joint_set(o); }, "JointParameters, or None (rigid)")
      .def_property(
          "holder_tool", [](const Assembly& a) { return joint_get(a.holder_tool); },
          [](Assembly& a, const py::object& o) { a.holder_tool = joint_set(o); }, "JointParameters, or None (rigid)")
      .def_property(
          "shear_model", [](const Assembly& a) { return name_of(a.shear_model, kShearModels); },
          [](Assembly& a, const std::string& v) { a.shear_model = enum_of(v, kShearModels, "shear_model"); })
      .def_property(
          "method", [](const Assembly& a) { return name_of(a.method, kMethods); },
          [](Assembly& a, const std::string& v) { a.method = enum_of(v, kMethods, "method"); }, "'exact' or 'modal'")
      .def_readwrite("modal_terms", &Assembly::modal_terms)
      .def_property(
          "grid", [](const Assembly& a) { return std::make_tuple(a.grid.start_hz, a.grid.stop_hz, a.grid.step_hz); },
          [](Assembly& a, std::tuple<double, double, double> g) {
            a.grid = {std::get<0>(g), std::get<1>(g), std::get<2>(g)};
          },
          "(start_hz, stop_hz, step_hz)")
      .def_property_readonly(
          "frequency_hz",
          [](const Assembly& a) {
            a.grid.check();
            return array_of(a.grid.values());
          },
          "The grid's frequencies [Hz], (n,).")
      .def("check", &Assembly::check, "Raises InvalidArgument naming the offending item.")
      .def("with_overhang", &with_overhang, "overhang"_a,
           "The same assembly with the tool sticking out `overhang` m (the length inside the holder kept).")
      .def("with_joint", static_cast<Assembly (*)(const Assembly&, const JointFile&)>(&with_joint), "joint"_a,
           "The assembly with a JointFile's joint in place of the one at its interface.");

  py::class_<LoadedAssembly>(m, "LoadedAssembly",
                             "An assembly file read: the assembly, warnings (implausible magnitudes) and notes.")
      .def_readonly("assembly", &LoadedAssembly::assembly)
      .def_readonly("warnings", &LoadedAssembly::warnings)
      .def_readonly("notes", &LoadedAssembly::notes);
  m.def("load_assembly", &load_assembly, "path"_a,
        "Reads an assembly file (TOML, SI units; examples/bt40_shrinkfit_16mm.toml documents every key). Raises InputError "
        "naming file, line and key, IoError.");
  m.def("parse_assembly", &parse_assembly, "text"_a, "source"_a = "<string>",
        "Parses assembly TOML text; `source` names it in errors.");

}

// The assembly's model: the forward model of Eq. 1–5 over the components and joints.
void bind_assembly_model(py::module_& m) {
  py::class_<AssemblyModel, std::shared_ptr<AssemblyModel>>(
      m, "AssemblyModel",
      "An assembly's components built once. Blocks are complex (n, 2, 2) [[H, L], [N, P]] (m/N, 1/N, rad/N, rad/(N·m)); "
      "two-end components (n, 4, 4) over (w1, θ1, w2, θ2). Frequencies in Hz. The GIL is released while computing.")
      .def(py::init([](Assembly a) {
             py::gil_scoped_release nogil;
             return std::make_shared<AssemblyModel>(a);
           }),
           "assembly"_a)
      .def(
          "tool_point",
          [](const AssemblyModel& md, const RealArray& f) {
            const std::vector<double> v = vector_of(f, "frequency_hz");
            BlockSeries s;
            {
              py::gil_scoped_release nogil;
              s = md.tool_point(v);
            }
            return blocks_array(s.blocks);
          },
          "frequency_hz"_a, "SHT11, the tool point (seed Eq. 5), through the SIMD sweep (the same as predict's).")
      .def(
          "holder_tip",
          [](const AssemblyModel& md, const RealArray& f) {
            const std::vector<double> v = vector_of(f, "frequency_hz");
            BlockSeries s;
            {
              py::gil_scoped_release nogil;
              s = md.holder_tip(v);
            }
            return blocks_array(s.blocks);
          },
          "frequency_hz"_a, "SH11, the holder tip with the tool outside removed (seed Eq. 1).")
      .def(
          "spindle_nose",
          [](const AssemblyModel& md, const RealArray& f) {
            return blocks_over(f, [&](double x) { return md.spindle_nose(x); });
          },
          "frequency_hz"_a, "S11, the spindle nose with its bearings.")
      .def(
          "holder",
          [](const AssemblyModel& md, const RealArray& f) { return two_ports_over(f, [&](double x) { return md.holder(x); }); },
          "frequency_hz"_a, "H, the holder with the shank inside, free–free: (n, 4, 4).")
      .def(
          "tool",
          [](const AssemblyModel& md, const RealArray& f) { return two_ports_over(f, [&](double x) { return md.tool(x); }); },
          "frequency_hz"_a, "T, the tool outside the holder, free–free: (n, 4, 4).")
      .def(
          "holder_tool",
          [](const AssemblyModel& md, const RealArray& f) {
            return two_ports_over(f, [&](double x) { return md.holder_tool(x); });
          },
          "frequency_hz"_a, "HT, the holder–tool subassembly through K_ht (Eq. 17's HT), free–free: (n, 4, 4).")
      .def(
          "tool_stations",
          [](const AssemblyModel& md, double f, const std::vector<double>& d) {
            Eigen::MatrixXcd g;
            {
              py::gil_scoped_release nogil;
              g = md.tool_stations(f, d);
            }
            py::array_t<std::complex<double>> a({g.rows(), g.cols()});
            auto w = a.mutable_unchecked<2>();
            for (Eigen::Index r = 0; r < g.rows(); ++r)
              for (Eigen::Index c = 0; c < g.cols(); ++c) w(r, c) = g(r, c);
            return a;
          },
          "frequency_hz"_a, "distances_m"_a,
          "Receptances between stations on the tool at `distances_m` from the tip, the rest attached: complex (2n, 2n), block "
          "(i, j) the "
          "response at station i to a load at station j.")
      .def_property_readonly("warnings", &AssemblyModel::warnings)
      .def_property_readonly("assembly", &AssemblyModel::assembly);

  m.def(
      "couple_tool",
      [](Assembly a, const RealArray& f, const ComplexArray& sh11, const std::string& name) {
        const BlockSeries s = block_series(f, sh11, name);
        judge_receptance(s, name);
        BlockSeries out;
        {
          py::gil_scoped_release nogil;
          out = couple_tool(a, s, name);
        }
        return blocks_array(out.blocks);
      },
      "assembly"_a, "frequency_hz"_a, "sh11"_a, "name"_a = "SH11",
      "SHT11 from a measured SH11 (n, 2, 2) and the model's tool through the holder–tool joint (seed Eq. 5, Schmitz's RCSA), on "
      "SH11's grid.");
}

// The prediction study (with the Monte Carlo's options it holds).
void bind_prediction(py::module_& m) {
  // ---- Studies: prediction, overhangs, tap test ----------------------------------------------------
  // The Monte Carlo's options, bound here because the prediction and overhang studies hold them.
  auto uncertainty = options_class<UncertaintyOptions>(
      m, "UncertaintyOptions",
      "The Monte Carlo over an uncertain joint (uncertainty.hpp): tool_point_band's options, and the band's in "
      "PredictOptions and OverhangStudyOptions. Progress is the function's `progress` argument.",
      {"samples", "seed", "levels", "threads"});
  def_option_fields(uncertainty, uncertainty_fields(), "toolpoint predict");
  uncertainty.def_readwrite("seed", &UncertaintyOptions::seed, "sample i draws from stream_seed(seed, i)")
      .def_readwrite("levels", &UncertaintyOptions::levels, "quantile levels, increasing in (0, 1)");
  py::class_<Peak>(m, "Peak", "A resonance peak of |H|: grid index, refined frequency [Hz] and magnitude, prominence (relative).")
      .def_readonly("index", &Peak::index)
      .def_readonly("frequency_hz", &Peak::frequency_hz)
      .def_readonly("magnitude", &Peak::magnitude, "|H| at the peak, the FRF's unit (m/N)")
      .def_readonly("prominence", &Peak::prominence)
      .def(
          "to_dict", [](const Peak& p) { return dict_of(p); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).")
      .def("__repr__", [](const Peak& p) {
        return fmt::format("Peak(frequency_hz={:.6g}, magnitude={:.6g}, prominence={:.3g})", p.frequency_hz, p.magnitude,
                           p.prominence);
      });

  py::class_<Prediction>(m, "Prediction", "run_prediction_study's result: the block series on the assembly's grid and its modes.")
      .def_property_readonly(
          "receptance", [](const Prediction& p) { return predicted_frf_name(p.receptance); }, "'SHT11' or 'SH11'")
      .def_property_readonly(
          "frequency_hz", [](const Prediction& p) { return array_of(p.frf.frequency_hz); }, "(n,) Hz")
      .def_property_readonly(
          "frf", [](const Prediction& p) { return blocks_array(p.frf.blocks); }, "complex (n, 2, 2)")
      .def_readonly("modes", &Prediction::modes, "list of Peak (refined on the model)")
      .def_readonly("band", &Prediction::band, "FrfBand (with `joint`) or None")
      .def_readonly("speed_rpm", &Prediction::speed_rpm, "the spindle speed [rpm] of a two-plane prediction")
      .def_property_readonly(
          "two_plane",
          [](const Prediction& p) {
            py::array_t<std::complex<double>> out({static_cast<py::ssize_t>(p.two_plane.size()), py::ssize_t{4}, py::ssize_t{4}});
            auto a = out.mutable_unchecked<3>();
            for (std::size_t i = 0; i < p.two_plane.size(); ++i)
              for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) a(static_cast<py::ssize_t>(i), r, c) = p.two_plane.blocks[i](r, c);
            return out;
          },
          "at a speed or with anisotropic bearings: complex (n, 4, 4) on (w_x, ψ_x, w_y, ψ_y) [[xx, xy], [yx, yy]]; else (0, 4, "
          "4)")
      .def_readonly("warnings", &Prediction::warnings)
      .def(
          "to_dict", [](const Prediction& p) { return dict_of(p); },
          "{'receptance', 'modes', 'warnings'} (toolpoint predict --json's keys).");
  options_class<PredictOptions>(m, "PredictOptions", "run_prediction_study's options (studies/predict.hpp; toolpoint predict's).",
                                {"receptance", "peaks", "uncertain_joint", "band", "speed_rpm", "extrapolate_bearings"})
      .def_property(
          "receptance", [](const PredictOptions& o) { return std::string(name_of(o.receptance, kPredicted)); },
          [](PredictOptions& o, const std::string& v) { o.receptance = enum_of(v, kPredicted, "PredictOptions::receptance"); },
          "'SHT11' (the tool point) or 'SH11' (the holder tip)")
      .def_readwrite("peaks", &PredictOptions::peaks, "PeakOptions: which local maxima of |H| count as modes")
      .def_readwrite("uncertain_joint", &PredictOptions::uncertain_joint,
                     "a JointFile with [uncertainty] (put in place, and the band of the tool point FRF over joints drawn "
                     "from it), or None")
      .def_readwrite("band", &PredictOptions::band, "UncertaintyOptions: the band's samples, seed, levels and threads")
      .def_readwrite("speed_rpm", &PredictOptions::speed_rpm,
                     "spindle speed [rpm] ≥ 0: > 0 gives the tool point in two planes (docs/spindle-at-speed.md)")
      .def_readwrite("extrapolate_bearings", &PredictOptions::extrapolate_bearings,
                     "extend a bearing's speed table beyond its rows (default: refuse)");
  m.def(
      "run_prediction_study",
      [](Assembly a, const std::string& receptance, double min_prominence, std::optional<JointFile> joint, int samples,
         std::uint64_t seed, std::vector<double> levels, int threads, const py::object& progress, double speed_rpm,
         bool extrapolate_bearings) {
        PredictOptions o;
        o.speed_rpm = speed_rpm;
        o.extrapolate_bearings = extrapolate_bearings;
        o.receptance = enum_of(receptance, kPredicted, "receptance");
        o.peaks.min_prominence = min_prominence;
        o.uncertain_joint = std::move(joint);
        o.band = uncertainty_options(samples, seed, std::move(levels), threads, py::none());
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_prediction_study(a, o, cb);
      },
      "assembly"_a, "receptance"_a = "SHT11", "min_prominence"_a = 0.02, "joint"_a = py::none(), "samples"_a = 200, "seed"_a = 1,
      "levels"_a = std::vector<double>{0.05, 0.5, 0.95}, "threads"_a = 0, "progress"_a = py::none(), "speed_rpm"_a = 0.0,
      "extrapolate_bearings"_a = false,
      "The prediction study (toolpoint predict): SHT11 or SH11 on assembly.grid (seed Eq. 1–5) with its modes (peaks of |H| "
      "rising "
      "min_prominence above their valleys, refined on the model). With `joint` (a JointFile with [uncertainty]): also the band "
      "of the tool point FRF over `samples` joints drawn from its covariance (tool_point_band; threads: 0 every core). "
      "progress(fraction) is called as it goes. At `speed_rpm` > 0 (or with anisotropic bearings) the tool point in two "
      "planes: Prediction.two_plane (n, 4, 4) on (w_x, ψ_x, w_y, ψ_y), its x–x block the FRF (docs/spindle-at-speed.md).");

  m.def(
      "run_prediction_study",
      [](Assembly a, const PredictOptions& options, const py::object& progress) {
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_prediction_study(a, options, cb);
      },
      "assembly"_a, "options"_a, py::kw_only(), "progress"_a = py::none(),
      "The prediction study with its options as one PredictOptions (the same as the keyword form above).");
}

// The overhang study.
void bind_overhang_study(py::module_& m) {
  py::class_<OverhangFrf>(m, "OverhangFrf", "One overhang of the overhang study.")
      .def_readonly("overhang_m", &OverhangFrf::overhang_m)
      .def_property_readonly(
          "sht11", [](const OverhangFrf& r) { return blocks_array(r.sht11.blocks); }, "complex (n, 2, 2) on SH11's grid")
      .def_readonly("modes", &OverhangFrf::modes);
  py::class_<OverhangStudy>(m, "OverhangStudy", "run_overhang_study's result.")
      .def_readonly("tool_inside_holder_m", &OverhangStudy::tool_inside_holder_m)
      .def_readonly("overhangs", &OverhangStudy::overhangs)
      .def_readonly("reference", &OverhangStudy::reference, "index of the overhang the modes are tracked from")
      .def_property_readonly(
          "tracked_modes_hz",
          [](const OverhangStudy& s) {
            py::array_t<double> a(
                {static_cast<py::ssize_t>(s.tracked_modes_hz.size()), static_cast<py::ssize_t>(s.overhangs.size())});
            auto w = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < s.tracked_modes_hz.size(); ++i)
              for (std::size_t j = 0; j < s.overhangs.size(); ++j)
                w(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = s.tracked_modes_hz[i][j];
            return a;
          },
          "(modes, overhangs) Hz, NaN where a mode was not found (the seed's Fig. 10)")
      .def_readonly("band", &OverhangStudy::band, "FrfBand (with `joint`) or None")
      .def_readonly("warnings", &OverhangStudy::warnings)
      .def(
          "to_dict", [](const OverhangStudy& s) { return dict_of(s); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  auto overhang = options_class<OverhangStudyOptions>(m, "OverhangStudyOptions",
                                                      "run_overhang_study's options (studies/overhang.hpp; toolpoint couple's).",
                                                      {"overhangs_m", "peaks", "tracking_tolerance", "threads", "sh11_name",
                                                       "uncertain_joint", "band"});
  def_option_fields(overhang, overhang_study_fields(), "toolpoint couple");
  overhang.def_readwrite("overhangs_m", &OverhangStudyOptions::overhangs_m,
                     "tool overhangs [m], strictly increasing; empty: the assembly's own")
      .def_readwrite("peaks", &OverhangStudyOptions::peaks, "PeakOptions: which local maxima of |H| count as modes")
      .def_readwrite("sh11_name", &OverhangStudyOptions::sh11_name, "names the measured SH11 in messages")
      .def_readwrite("uncertain_joint", &OverhangStudyOptions::uncertain_joint,
                     "a holder–tool JointFile with [uncertainty] (one overhang: the band of the coupled FRF), or None")
      .def_readwrite("band", &OverhangStudyOptions::band, "UncertaintyOptions: the band's samples, seed, levels and threads");
  m.def(
      "run_overhang_study",
      [](Assembly a, const RealArray& f, const ComplexArray& sh11, std::vector<double> overhangs_m, double min_prominence,
         double tracking_tolerance, int threads, std::string sh11_name, std::optional<JointFile> joint, int samples,
         std::uint64_t seed, std::vector<double> levels, const py::object& progress) {
        OverhangStudyOptions o;
        o.overhangs_m = std::move(overhangs_m);
        o.peaks.min_prominence = min_prominence;
        o.tracking_tolerance = tracking_tolerance;
        o.threads = threads;
        o.sh11_name = std::move(sh11_name);
        o.uncertain_joint = std::move(joint);
        o.band = uncertainty_options(samples, seed, std::move(levels), threads, py::none());
        const BlockSeries s = block_series(f, sh11, o.sh11_name);
        judge_receptance(s, o.sh11_name);
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_overhang_study(a, s, o, cb);
      },
      "assembly"_a, "frequency_hz"_a, "sh11"_a, "overhangs_m"_a = std::vector<double>{}, "min_prominence"_a = 0.1,
      "tracking_tolerance"_a = 0.15, "threads"_a = 0, "sh11_name"_a = "SH11", "joint"_a = py::none(), "samples"_a = 200,
      "seed"_a = 1, "levels"_a = std::vector<double>{0.05, 0.5, 0.95}, "progress"_a = py::none(),
      "The overhang study (toolpoint couple): SHT11 per tool overhang [m] from a measured SH11 (n, 2, 2) by Eq. 5, modes tracked "
      "from the assembly's own overhang (Fig. 10). With `joint` (a holder–tool JointFile with [uncertainty]; one overhang): "
      "also the band of the coupled tool point FRF over `samples` joints drawn from its covariance (coupled_tool_point_band). "
      "Overhangs and samples run on `threads` threads (0: every core); results identical for any count.");
  m.def(
      "run_overhang_study",
      [](Assembly a, const RealArray& f, const ComplexArray& sh11, const OverhangStudyOptions& options,
         const py::object& progress) {
        const BlockSeries s = block_series(f, sh11, options.sh11_name);
        judge_receptance(s, options.sh11_name);
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_overhang_study(a, s, options, cb);
      },
      "assembly"_a, "frequency_hz"_a, "sh11"_a, "options"_a, py::kw_only(), "progress"_a = py::none(),
      "The overhang study with its options as one OverhangStudyOptions (the same as the keyword form above).");
  m.def("overhang_sweep", &overhang_sweep, "start_m"_a, "stop_m"_a, "step_m"_a,
        "The overhangs [m] of a sweep START:STOP:STEP as toolpoint couple --overhang makes them: start + i·step up to stop, each "
        "rounded to a nanometre.");
}

// The tap test from Python (both forms): the spacing and the floor judged as the CLI's --spacing and
// --floor (plausibility.hpp), then the library's checks.
TapTest tap_test_from_python(const Assembly& a, const TapTestOptions& o, const py::object& progress) {
  if (o.spacing_m > 0.0)
    check_plausible(plausible::kPointSpacing, o.spacing_m, "TapTestOptions::spacing_m", "give the spacing in m (15 mm = 0.015)");
  if (o.floor > 0.0)
    check_plausible(plausible::kRelativeNoise, o.floor, "TapTestOptions::floor", "give the floor as a fraction (1 % = 0.01)");
  const ProgressCallback cb = progress_of(progress);
  py::gil_scoped_release nogil;
  return run_tap_test_study(a, o, cb);
}

// The virtual tap test.
void bind_tap_test(py::module_& m) {
  py::class_<TapTestFrf>(m, "TapTestFrf", "One FRF of the tap test: H_ij = w_i/f_j [m/N], point 0 the tip.")
      .def_readonly("response", &TapTestFrf::response)
      .def_readonly("hammer", &TapTestFrf::hammer)
      .def_property_readonly("frequency_hz", [](const TapTestFrf& r) { return array_of(r.frf.frequency_hz); })
      .def_property_readonly(
          "values", [](const TapTestFrf& r) { return array_of(r.frf.values); }, "complex (n,) m/N");
  py::class_<TapTest>(m, "TapTest", "run_tap_test_study's result.")
      .def_property_readonly("side", [](const TapTest& t) { return tap_side_name(t.side); })
      .def_property_readonly(
          "distance_m", [](const TapTest& t) { return array_of(t.distance_m); }, "each point's distance from the tip [m]")
      .def_readonly("frfs", &TapTest::frfs, "list of TapTestFrf, hammer by hammer (tip first)")
      .def_readonly("shear_stiffness_n", &TapTest::shear_stiffness_n, "smallest κGA [N] under the points (for rotational_frfs)")
      .def_readonly("crosses_step", &TapTest::crosses_step)
      .def_readonly("warnings", &TapTest::warnings)
      .def(
          "frf",
          [](const TapTest& t, int response, int hammer) {
            for (const TapTestFrf& r : t.frfs)
              if (r.response == response && r.hammer == hammer) return array_of(r.frf.values);
            throw InvalidArgument(fmt::format("the tap test has no H{}{} (response {}, hammer {})", response, hammer, response,
                                              hammer),
                                  "see TapTest.frfs for the pairs measured");
          },
          "response"_a, "hammer"_a, "H_ij as complex (n,) [m/N].")
      .def(
          "to_dict", [](const TapTest& t) { return dict_of(t); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  auto tap_options = options_class<TapTestOptions>(m, "TapTestOptions",
                                                   "run_tap_test_study's options (studies/tap_test.hpp; toolpoint taptest's).",
                                                   {"side", "spacing_m", "points", "hammer", "sigma", "seed", "floor", "averages",
                                                    "calibration"})
                         .def_property(
                             "side", [](const TapTestOptions& o) { return std::string(name_of(o.side, kSides)); },
                             [](TapTestOptions& o, const std::string& v) { o.side = enum_of(v, kSides, "TapTestOptions::side"); },
                             "'tool' or 'holder' (the holder without the tool outside)")
                         .def_property(
                             "hammer", [](const TapTestOptions& o) { return std::string(name_of(o.hammer, kHammers)); },
                             [](TapTestOptions& o, const std::string& v) {
                               o.hammer = enum_of(v, kHammers, "TapTestOptions::hammer");
                             },
                             "'roving' (a hit at every point) or 'tip'")
                         .def_readwrite("seed", &TapTestOptions::seed, "FRF k draws from seed + k");
  def_option_fields(tap_options, tap_test_fields(), "toolpoint taptest");  // spacing_m, points, sigma, floor, averages, calibration
  m.def(
      "run_tap_test_study",
      [](Assembly a, double spacing_m, const std::string& side, int points, const std::string& hammer, double sigma,
         std::uint64_t seed, const py::object& progress) {
        TapTestOptions o;
        o.side = enum_of(side, kSides, "side");
        o.spacing_m = spacing_m;
        o.points = points;
        o.hammer = enum_of(hammer, kHammers, "hammer");
        o.sigma = sigma;
        o.seed = seed;
        return tap_test_from_python(a, o, progress);
      },
      "assembly"_a, "spacing_m"_a, "side"_a = "tool", "points"_a = 3, "hammer"_a = "roving", "sigma"_a = 0.0, "seed"_a = 1,
      "progress"_a = py::none(),
      "The virtual tap test (toolpoint taptest): H_ij at the tip and points spacing_m [m] apart inwards on the tool ('tool') or "
      "the "
      "holder without the tool outside ('holder'), hammer at every point ('roving') or the tip ('tip'), multiplicative noise "
      "sigma "
      "(0.005 = 0.5 %; FRF k draws from seed + k), on assembly.grid.");

  m.def(
      "run_tap_test_study",
      [](Assembly a, const TapTestOptions& options, const py::object& progress) {
        return tap_test_from_python(a, options, progress);
      },
      "assembly"_a, "options"_a, py::kw_only(), "progress"_a = py::none(),
      "The virtual tap test with its options as one TapTestOptions (the same as the keyword form above; besides, the "
      "noise floor, averages and calibration).");
}

// The rotational FRFs from a tap test: the finite-difference error estimated on the model, the study.
void bind_fd_correction(py::module_& m) {
  py::class_<FiniteDifferenceError>(
      m, "FiniteDifferenceError", "The finite-difference error of a tap test estimated on the model (studies/fd_correction.hpp).")
      .def_property_readonly(
          "frequency_hz", [](const FiniteDifferenceError& e) { return array_of(e.error.frequency_hz); }, "(n,) Hz")
      .def_property_readonly(
          "error", [](const FiniteDifferenceError& e) { return blocks_array(e.error.blocks); },
          "E = FD[model's H_ij at the points] − model's tip block, complex (n, 2, 2) (H's entry 0): subtract it from the "
          "measured block")
      .def_property_readonly(
          "exact", [](const FiniteDifferenceError& e) { return blocks_array(e.exact.blocks); },
          "the model's tip block, complex (n, 2, 2)")
      .def_property_readonly(
          "max_relative",
          [](const FiniteDifferenceError& e) {
            return array_of(std::vector<double>(e.max_relative.begin(), e.max_relative.end()));
          },
          "(4,) H, L, N, P: max over f of |E| over max over f of |exact|")
      .def_readonly("warnings", &FiniteDifferenceError::warnings, "list of str")
      .def(
          "to_dict", [](const FiniteDifferenceError& e) { return dict_of(e); },
          "The result as plain data, the series left out (SI units).");
  m.def(
      "finite_difference_error",
      [](Assembly a, const RealArray& f, const std::vector<std::pair<int, int>>& pairs, const RotationalOptions& options,
         const std::string& side) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        PointFrfs layout;
        for (const auto& [i, j] : pairs) {
          if (i < 0 || i > 2 || j < 0 || j > 2)
            throw InvalidArgument(fmt::format("pairs: ({}, {}) is not (response, force) with points 0, 1, 2", i, j),
                                  "list the measured H_ij as (response, force), e.g. [(0, 0), (1, 0), (2, 0)]");
          layout.set(i, j, FrfSeries{grid, {}});
        }
        const RotationalOptions o = checked_rotational(options);
        const TapSide s = enum_of(side, kSides, "side");
        py::gil_scoped_release nogil;
        return finite_difference_error(a, s, grid, layout, o);
      },
      "assembly"_a, "frequency_hz"_a, "pairs"_a, "options"_a, "side"_a = "tool",
      "The model-based finite-difference correction: the error E(f) that the differences of rotational_frfs (same options; pairs "
      "the "
      "measured H_ij as (response, force)) make on the model at the same points spaced `spacing` m on the 'tool' or the "
      "'holder'. "
      "measured block − E removes it to the extent the model is right near the tip.");

  py::class_<RotationalStudy>(m, "RotationalStudy", "run_rotational_study's result (studies/rotational.hpp).")
      .def_property_readonly(
          "frequency_hz", [](const RotationalStudy& r) { return array_of(r.block.frequency_hz); }, "(n,) Hz")
      .def_property_readonly(
          "block", [](const RotationalStudy& r) { return blocks_array(r.block.blocks); },
          "the tip block [[H00, L], [N, P]], complex (n, 2, 2), the model's error removed when a model was given")
      .def_readonly("differences", &RotationalStudy::differences, "RotationalResult: the differences before any correction")
      .def_readonly("correction", &RotationalStudy::correction, "FiniteDifferenceError removed, or None")
      .def_readonly("order", &RotationalStudy::order)
      .def_readonly("spacing_m", &RotationalStudy::spacing_m)
      .def_readonly("method", &RotationalStudy::method, "how the block was made (order, spacing, where L, N and P came from)")
      .def_readonly("reciprocity", &RotationalStudy::reciprocity, "the measurements filled by reciprocity")
      .def_readonly("correction_note", &RotationalStudy::correction_note, "the correction and its size")
      .def_readonly("warnings", &RotationalStudy::warnings)
      .def(
          "to_dict", [](const RotationalStudy& r) { return dict_of(r); },
          "The result as plain data, the block left out (SI units).");
  m.def(
      "run_rotational_study",
      [](const RealArray& f, const py::dict& h, const RotationalOptions& options, std::optional<Assembly> model,
         const std::string& side, const std::string& model_name, const py::object& progress) {
        RotationalInput in;
        in.frfs = point_frfs_of(vector_of(f, "frequency_hz"), h);
        in.model = std::move(model);
        in.side = enum_of(side, kSides, "side");
        in.model_name = model_name;
        RotationalStudyOptions o;
        o.differences = checked_rotational(options);
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_rotational_study(in, o, cb);
      },
      "frequency_hz"_a, "H"_a, "options"_a, "model"_a = py::none(), "side"_a = "tool", "model_name"_a = "the model",
      "progress"_a = py::none(),
      "The rotational study (toolpoint rotational): the tip block by finite differences of H = {(response, force): complex (n,) "
      "[m/N]} at points 0 (tip), 1, 2 spaced options.spacing m inwards (RotationalOptions, as rotational_frfs), and with `model` "
      "(an Assembly) the differences' truncation error estimated on it at the same points on "
      "the 'tool' or the 'holder' and removed (finite_difference_error).");
}

}  // namespace

void bind_model(py::module_& m) {
  bind_joints(m);
  bind_segments(m);
  bind_beam_study(m);
  bind_assembly(m);
  bind_assembly_model(m);
  bind_prediction(m);
  bind_overhang_study(m);
  bind_tap_test(m);
  bind_fd_correction(m);
}

}  // namespace toolpoint::python
