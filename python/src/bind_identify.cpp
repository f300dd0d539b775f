// toolpoint Python bindings: joint identification — the closed form per frequency (identify.hpp),
// effect analysis, the identification study with the band fit (studies/identification.hpp,
// joint_fit.hpp), noise (noise.hpp), joint files (joint_file.hpp), the uncertainty carried to the
// tool point FRF (uncertainty.hpp) and the seed's case study (case_study.hpp). SI units; Hz.
#include <algorithm>

#include "common.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/precision.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint::python {

namespace {

using namespace pybind11::literals;

const std::vector<std::pair<const char*, Route>> kRoutes{{"holder_tool", Route::HolderTool},
                                                         {"spindle_holder_sh", Route::SpindleHolderFromSH},
                                                         {"spindle_holder_sht", Route::SpindleHolderFromSHT}};
const std::vector<std::pair<const char*, IdentificationMethod>> kIdMethods{{"fit", IdentificationMethod::Fit},
                                                                           {"seed", IdentificationMethod::Seed}};
const std::vector<std::pair<const char*, UncertaintyMethod>> kUncertainty{{"bootstrap", UncertaintyMethod::Bootstrap},
                                                                          {"linearised", UncertaintyMethod::Linearised}};
const std::vector<std::pair<const char*, NoiseSpec::Source>> kNoiseSources{{"estimated", NoiseSpec::Source::Estimated},
                                                                           {"stated", NoiseSpec::Source::Stated}};
const std::vector<std::pair<const char*, JointInterface>> kInterfaces{{"holder_tool", JointInterface::HolderTool},
                                                                      {"spindle_holder", JointInterface::SpindleHolder}};

template <std::size_t N>
py::array_t<double> array_of(const std::array<double, N>& a) {
  return python::array_of(std::vector<double>(a.begin(), a.end()));
}

// (rows, 8) from a per-row array of 8.
template <class Rows, class Get>
py::array_t<double> table8(const Rows& rows, Get get) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), py::ssize_t{8}});
  auto w = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 8; ++k) w(static_cast<py::ssize_t>(i), k) = get(rows[i], k);
  return a;
}

// (8,) one field of each parameter's precision.
py::array_t<double> per_parameter(const PrecisionStudy& r, double ParameterPrecision::*field) {
  std::array<double, 8> v{};
  for (std::size_t k = 0; k < 8; ++k) v[k] = r.parameters[k].*field;
  return array_of(v);
}

template <class Rows, class Get>
py::array_t<double> column(const Rows& rows, Get get) {
  std::vector<double> v(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) v[i] = get(rows[i]);
  return python::array_of(v);
}

// One bool per row, as a list.
template <class Rows, class Get>
std::vector<bool> flags(const Rows& rows, Get get) {
  std::vector<bool> v;
  for (const auto& r : rows) v.push_back(get(r));
  return v;
}

py::array_t<double> matrix8(const Eigen::Matrix<double, 8, 8>& c) { return matrix_array(c); }

// An (8, 8) float array (order of JointParameters.names()); InputError naming `name` otherwise.
Eigen::Matrix<double, 8, 8> matrix8_of(const RealArray& c, const std::string& name) {
  if (c.ndim() != 2 || c.shape(0) != 8 || c.shape(1) != 8)
    throw InputError(fmt::format("{}: an (8, 8) array was expected", name),
                     "order k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm");
  Eigen::Matrix<double, 8, 8> m;
  for (int r = 0; r < 8; ++r)
    for (int k = 0; k < 8; ++k) m(r, k) = c.at(r, k);
  return m;
}

// The std::array<ParameterInterval, 8> of a fit as one array per field.
template <class Get>
py::array_t<double> interval_field(const JointFit& f, Get get) {
  std::vector<double> v(8);
  for (std::size_t k = 0; k < 8; ++k) v[k] = get(f.intervals[k]);
  return python::array_of(v);
}

}  // namespace

UncertaintyOptions uncertainty_options(int samples, std::uint64_t seed, std::vector<double> levels, int threads,
                                       const py::object& progress) {
  UncertaintyOptions o;
  o.samples = samples;
  o.seed = seed;
  o.levels = std::move(levels);
  o.parallel.threads = threads;
  o.progress = progress_of(progress);
  return o;
}

namespace {

// The closed form per frequency (seed Eq. 6, 15, 18), the band read-out, the effect analysis.
void bind_closed_form(py::module_& m) {
  py::class_<JointSeries>(m, "JointSeries",
                          "K(ω) by the closed form over a grid, with k = Re K, c = Im K/ω per frequency and the conditioning.")
      .def_property_readonly("frequency_hz", [](const JointSeries& s) { return python::array_of(s.frequency_hz); })
      .def_property_readonly(
          "K",
          [](const JointSeries& s) {
            std::vector<Block> k(s.size());
            for (std::size_t i = 0; i < s.size(); ++i) k[i] = s.estimates[i].K;
            return blocks_array(k);
          },
          "complex (n, 2, 2): N/m, N, N/rad, N·m/rad")
      .def_property_readonly(
          "parameters",
          [](const JointSeries& s) { return table8(s.parameters, [](const JointParameters& p, int k) { return p[k]; }); },
          "(n, 8) in the order of JointParameters.names() (SI)")
      .def_property_readonly(
          "noise_gain",
          [](const JointSeries& s) {
            return table8(s.estimates, [](const JointEstimate& e, int k) { return e.noise_gain[static_cast<std::size_t>(k)]; });
          },
          "(n, 8): relative error of each parameter per unit relative error on every FRF entry (first order)")
      .def_property_readonly(
          "cond_difference",
          [](const JointSeries& s) { return column(s.estimates, [](const JointEstimate& e) { return e.cond_difference; }); },
          "cond(A11 − G11), Frobenius (n,)")
      .def_property_readonly("cond_flexibility",
                             [](const JointSeries& s) {
                               return column(s.estimates, [](const JointEstimate& e) { return e.cond_flexibility; });
                             })
      .def_property_readonly("cond_A12",
                             [](const JointSeries& s) {
                               return column(s.estimates, [](const JointEstimate& e) { return e.cond_A12; });
                             })
      .def_property_readonly("flexibility_share",
                             [](const JointSeries& s) {
                               return column(s.estimates, [](const JointEstimate& e) { return e.flexibility_share; });
                             })
      .def("__len__", &JointSeries::size);
  m.def(
      "identify_series",
      [](const RealArray& f, const ComplexArray& A, const ComplexArray& B11, const ComplexArray& G11, const std::string& b_name,
         const std::string& g_name) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        const std::vector<TwoPort> a = two_ports_of(A, "A");
        if (a.size() != grid.size())
          throw InputError(fmt::format("A: {} two-ports for {} frequencies", a.size(), grid.size()),
                           "give A on the frequencies of B11 and G11");
        const BlockSeries b{grid, blocks_of(B11, b_name)}, g{grid, blocks_of(G11, g_name)};
        py::gil_scoped_release nogil;
        // A is sampled on the grid (validated increasing by identify_series): look each frequency up.
        return identify_series(
            [&](double x) {
              return a.at(static_cast<std::size_t>(std::lower_bound(grid.begin(), grid.end(), x) - grid.begin()));
            },
            b, b_name, g, g_name);
      },
      "frequency_hz"_a, "A"_a, "B11"_a, "G11"_a, "b_name"_a = "B11", "g_name"_a = "G11",
      "The seed's closed form per frequency, K = (A21 (A11 − G11)⁻¹ A12 − A22 − B11)⁻¹: A the free–free component (n, 4, 4) "
      "(AssemblyModel.tool for Eq. 6, .holder for Eq. 15, .holder_tool for Eq. 18), B11 and G11 blocks (n, 2, 2) on the same "
      "grid [Hz].");

  py::class_<JointReadout>(m, "JointReadout",
                           "The eight parameters read in a band: median and robust spread per parameter, diagnostics.")
      .def_property_readonly("band_hz", [](const JointReadout& r) { return std::make_pair(r.band_lo_hz, r.band_hi_hz); })
      .def_readonly("points", &JointReadout::points)
      .def_property_readonly(
          "median",
          [](const JointReadout& r) { return column(r.parameters, [](const ParameterReadout& p) { return p.median; }); },
          "(8,) SI")
      .def_property_readonly(
          "spread",
          [](const JointReadout& r) { return column(r.parameters, [](const ParameterReadout& p) { return p.spread; }); },
          "(8,) 1.4826 × median absolute deviation")
      .def_property_readonly(
          "min", [](const JointReadout& r) { return column(r.parameters, [](const ParameterReadout& p) { return p.min; }); },
          "(8,) SI")
      .def_property_readonly(
          "max", [](const JointReadout& r) { return column(r.parameters, [](const ParameterReadout& p) { return p.max; }); },
          "(8,) SI")
      .def_property_readonly(
          "noise_gain", [](const JointReadout& r) { return array_of(r.noise_gain); }, "(8,) median over the band")
      .def_property_readonly(
          "determined",
          [](const JointReadout& r) { return flags(r.parameters, [](const ParameterReadout& p) { return p.determined; }); },
          "(8,) noise gain at most the warning level (20) and spread at most |median|")
      .def("medians", &JointReadout::medians, "The medians as JointParameters.")
      .def_readonly("reciprocity_k", &JointReadout::reciprocity_k)
      .def_readonly("reciprocity_c", &JointReadout::reciprocity_c)
      .def_readonly("max_cond_difference", &JointReadout::max_cond_difference)
      .def_readonly("max_cond_flexibility", &JointReadout::max_cond_flexibility)
      .def_readonly("warnings", &JointReadout::warnings)
      .def(
          "to_dict", [](const JointReadout& r) { return dict_of(r); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  m.def(
      "band_readout", [](const JointSeries& s, double lo, double hi) { return band_readout(s, lo, hi); }, "series"_a,
      "band_lo_hz"_a, "band_hi_hz"_a,
      "The seed's read-out: median and spread of each parameter over lo ≤ f ≤ hi [Hz], with warnings (conditioning, reciprocity, "
      "gain).");

  py::class_<EffectAnalysis>(m, "EffectAnalysis", "Which mode a joint controls (Ertürk et al. 2007).")
      .def_property_readonly("frequency_hz",
                             [](const EffectAnalysis& e) {
                               return column(e.modes, [](const ModeEffect& x) { return x.frequency_hz; });
                             })
      .def_property_readonly(
          "magnitude", [](const EffectAnalysis& e) { return column(e.modes, [](const ModeEffect& x) { return x.magnitude; }); },
          "m/N")
      .def_property_readonly(
          "stiffness_shift",
          [](const EffectAnalysis& e) { return column(e.modes, [](const ModeEffect& x) { return x.stiffness_shift; }); },
          "relative frequency shift per `step` growth of the joint's k's")
      .def_property_readonly(
          "damping_effect",
          [](const EffectAnalysis& e) { return column(e.modes, [](const ModeEffect& x) { return x.damping_effect; }); },
          "relative peak change per `step` growth of its c's")
      .def_readonly("dominant", &EffectAnalysis::dominant, "index of the mode the joint controls")
      .def(
          "to_dict", [](const EffectAnalysis& e) { return dict_of(e); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  m.def(
      "effect_analysis",
      [](Assembly a, const std::string& route, const RealArray& f, double step) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        const Route r = enum_of(route, kRoutes, "route");
        py::gil_scoped_release nogil;
        return effect_analysis(a, r, grid, step);
      },
      "assembly"_a, "route"_a, "frequency_hz"_a, "step"_a = 0.1,
      "Effect analysis: perturb the route's joint's k's (then c's) by `step` in the model and see which peak of the FRF it is "
      "identified "
      "from moves most. route 'holder_tool' (Eq. 6), 'spindle_holder_sh' (Eq. 15) or 'spindle_holder_sht' (Eq. 18).");

  py::class_<ModeComparison>(m, "ModeComparison", "A forward check's mode: measured against predicted (relative errors).")
      .def_readonly("measured_hz", &ModeComparison::measured_hz)
      .def_readonly("predicted_hz", &ModeComparison::predicted_hz)
      .def_readonly("frequency_error", &ModeComparison::frequency_error, "relative")
      .def_readonly("measured_peak", &ModeComparison::measured_peak, "m/N")
      .def_readonly("predicted_peak", &ModeComparison::predicted_peak, "m/N")
      .def_readonly("magnitude_error", &ModeComparison::magnitude_error, "relative")
      .def(
          "to_dict", [](const ModeComparison& c) { return dict_of(c); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
}

// The noise of measured FRFs: estimated, stated, drawn.
void bind_noise(py::module_& m) {
  py::class_<BlockNoise>(
      m, "BlockNoise",
      "The noise of a measured block series: C(f), the 8×8 covariance of the relative errors (Re, Im of ε/x for H, L, N, P).")
      .def_property_readonly(
          "relative",
          [](const BlockNoise& n) {
            py::array_t<double> a({static_cast<py::ssize_t>(n.size()), py::ssize_t{8}, py::ssize_t{8}});
            auto w = a.mutable_unchecked<3>();
            for (std::size_t i = 0; i < n.size(); ++i)
              for (int r = 0; r < 8; ++r)
                for (int c = 0; c < 8; ++c) w(static_cast<py::ssize_t>(i), r, c) = n.relative[i](r, c);
            return a;
          },
          "(n, 8, 8), empty for exact data")
      .def_readonly("source", &BlockNoise::source)
      .def_property_readonly(
          "magnitude_sigma", [](const BlockNoise& n) { return array_of(n.magnitude_sigma); },
          "(4,) H, L, N, P: median relative σ")
      .def_property_readonly(
          "phase_sigma_rad", [](const BlockNoise& n) { return array_of(n.phase_sigma_rad); }, "(4,) rad")
      .def_property_readonly(
          "additive",
          [](const BlockNoise& n) {
            py::array_t<double> a({static_cast<py::ssize_t>(n.additive.size()), py::ssize_t{4}});
            auto w = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < n.additive.size(); ++i)
              for (int e = 0; e < 4; ++e) w(static_cast<py::ssize_t>(i), e) = n.additive[i](e);
            return a;
          },
          "(n, 4): the floor's variance of each part of H, L, N, P per frequency (empty without a floor)")
      .def_property_readonly(
          "floor", [](const BlockNoise& n) { return array_of(n.floor); },
          "(4,) σ of each part of the additive floor [entry units]")
      .def_property_readonly(
          "floor_relative", [](const BlockNoise& n) { return array_of(n.floor_relative); },
          "(4,) the floor over each entry's peak |value|")
      .def_readwrite("calibration", &BlockNoise::calibration, "σ of the calibration factor of the whole series")
      .def("summary", &BlockNoise::summary, "One line for reports.")
      .def_readonly("residual_correlation", &BlockNoise::residual_correlation)
      .def_readonly("warnings", &BlockNoise::warnings)
      .def("exact", &BlockNoise::exact, "True for data from a model (no noise).")
      .def("__len__", &BlockNoise::size)
      .def(
          "to_dict", [](const BlockNoise& n) { return dict_of(n); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  auto noise_estimate =
      options_class<NoiseEstimateOptions>(m, "NoiseEstimateOptions",
                                          "estimate_block_noise's options (noise.hpp; how the identification estimates the noise "
                                          "of measured data).",
                                          {"local", "window", "floor"})
          .def_readwrite("local", &NoiseEstimateOptions::local,
                         "SavgolOptions: the local polynomial the residuals are taken about (default 7 points, cubic)");
  def_option_fields(noise_estimate, noise_estimate_fields(), "");  // window, floor
  m.def(
      "estimate_block_noise",
      [](const RealArray& f, const ComplexArray& blocks, const NoiseEstimateOptions& options, const std::string& what) {
        const BlockSeries s = block_series(f, blocks, what);
        py::gil_scoped_release nogil;
        return estimate_block_noise(s, options, what);
      },
      "frequency_hz"_a, "blocks"_a, "options"_a, py::kw_only(), "what"_a = "data",
      "estimate_block_noise with its options as one NoiseEstimateOptions (the same as the keyword form below).");
  m.def(
      "estimate_block_noise",
      [](const RealArray& f, const ComplexArray& blocks, int local_window, int local_order, int window, const std::string& what,
         bool floor) {
        const BlockSeries s = block_series(f, blocks, what);
        NoiseEstimateOptions o;
        o.local = {local_window, local_order};
        o.window = window;
        o.floor = floor;
        py::gil_scoped_release nogil;
        return estimate_block_noise(s, o, what);
      },
      "frequency_hz"_a, "blocks"_a, "local_window"_a = 7, "local_order"_a = 3, "window"_a = 201, "what"_a = "data",
      "floor"_a = true,
      "The noise of a measured block series estimated from the data: residuals about a local Savitzky–Golay polynomial "
      "(local_window points, local_order), averaged over `window` frequency points; with floor, an additive floor "
      "beside the multiplicative noise.");
  m.def(
      "stated_block_noise",
      [](const RealArray& f, const ComplexArray& blocks, double magnitude_sigma, double phase_sigma_rad, double floor,
         double calibration) {
        BlockNoise n = stated_block_noise(block_series(f, blocks, "data"), StatedNoise{magnitude_sigma, phase_sigma_rad, floor});
        n.calibration = calibration;
        return n;
      },
      "frequency_hz"_a, "blocks"_a, py::kw_only(), "magnitude_sigma"_a = 0.0, "phase_sigma_rad"_a = 0.0, "floor"_a = 0.0,
      "calibration"_a = 0.0,
      "Noise stated for the data: relative magnitude σ (0.05 = 5 %) and phase σ [rad] on every entry, an additive floor "
      "(σ of each part relative to each entry's peak |value|, 0.01 = 1 %) and the σ of a calibration factor scaling the "
      "whole series.");
  m.def("h1_relative_variance", &h1_relative_variance, "coherence"_a, "averages"_a,
        "(1 − γ²)/(2 n γ²): the relative variance of an H1 estimate's magnitude (and its phase's variance in rad²) from "
        "its coherence and number of averages (Bendat & Piersol).");
  m.def(
      "draw_block_noise",
      [](const RealArray& f, const ComplexArray& truth, const BlockNoise& noise, std::uint64_t seed) {
        const BlockSeries s = block_series(f, truth, "truth");
        BlockSeries out;
        {
          py::gil_scoped_release nogil;
          out = draw_block_noise(s, noise, seed);
        }
        return blocks_array(out.blocks);
      },
      "frequency_hz"_a, "truth"_a, "noise"_a, "seed"_a,
      "One reproducible draw (1 + δ)(truth + ε): ε Gaussian with the noise's covariance (multiplicative and floor), δ its "
      "calibration factor's.");
}

// Joint files.
void bind_joint_files(py::module_& m) {
  py::class_<JointUncertainty>(m, "JointUncertainty", "A joint file's [uncertainty]: intervals and the 8×8 covariance (SI).")
      .def(py::init<>())
      .def_readwrite("confidence", &JointUncertainty::confidence)
      .def_property(
          "lower", [](const JointUncertainty& u) { return array_of(u.lower); },
          [](JointUncertainty& u, const std::array<double, 8>& v) { u.lower = v; })
      .def_property(
          "upper", [](const JointUncertainty& u) { return array_of(u.upper); },
          [](JointUncertainty& u, const std::array<double, 8>& v) { u.upper = v; })
      .def_readwrite("determined", &JointUncertainty::determined)
      .def_property(
          "covariance", [](const JointUncertainty& u) { return matrix8(u.covariance); },
          [](JointUncertainty& u, const RealArray& c) { u.covariance = matrix8_of(c, "covariance"); });
  py::class_<JointFile>(m, "JointFile",
                        "An identified joint as a file: its interface, constants, uncertainty and how it was identified.")
      .def(py::init([](const std::string& interface, const JointParameters& p, std::optional<JointUncertainty> u,
                       std::vector<std::pair<std::string, std::string>> identification) {
             JointFile f;
             f.interface = enum_of(interface, kInterfaces, "interface");
             f.parameters = p;
             f.uncertainty = std::move(u);
             f.identification = std::move(identification);
             return f;
           }),
           "interface"_a, "parameters"_a, "uncertainty"_a = py::none(),
           "identification"_a = std::vector<std::pair<std::string, std::string>>{})
      .def_property(
          "interface", [](const JointFile& f) { return to_string(f.interface); },
          [](JointFile& f, const std::string& v) { f.interface = enum_of(v, kInterfaces, "interface"); },
          "'holder_tool' or 'spindle_holder'")
      .def_readwrite("parameters", &JointFile::parameters)
      .def_readwrite("uncertainty", &JointFile::uncertainty)
      .def_readwrite("identification", &JointFile::identification)
      .def_readonly("source", &JointFile::source);
  m.def("load_joint_file", &load_joint_file, "path"_a,
        "Reads a joint file (TOML). Raises InputError with file:line and key, IoError.");
  m.def("parse_joint_file", &parse_joint_file, "text"_a, "source"_a = "<string>",
        "Parses joint file TOML text; `source` names it in errors.");
  m.def("format_joint_file", &format_joint_file, "joint"_a, "The joint file's TOML text (shortest round-trip numbers).");
  m.def("write_joint_file", &write_joint_file, "path"_a, "joint"_a, "Writes a joint file whole or not at all.");
}

// The band fit's result.
void bind_joint_fit(py::module_& m) {
  py::class_<JointFit>(m, "JointFit",
                       "The band fit of a joint's constants (output error) with intervals; arrays (8,) per field, SI.")
      .def_readonly("parameters", &JointFit::parameters, "the estimates")
      .def_property_readonly(
          "estimate", [](const JointFit& f) { return interval_field(f, [](const ParameterInterval& i) { return i.estimate; }); },
          "(8,) reported values, SI, order of JointParameters.names(): bias-corrected (bootstrap) or fitted (linearised)")
      .def_property_readonly(
          "fitted", [](const JointFit& f) { return interval_field(f, [](const ParameterInterval& i) { return i.fitted; }); },
          "(8,) least-squares values, SI")
      .def_property_readonly(
          "bias", [](const JointFit& f) { return interval_field(f, [](const ParameterInterval& i) { return i.bias; }); },
          "(8,) bootstrap bias of fitted, SI (0 when linearised)")
      .def_property_readonly(
          "std_error",
          [](const JointFit& f) { return interval_field(f, [](const ParameterInterval& i) { return i.std_error; }); },
          "(8,) standard errors of estimate, SI")
      .def_property_readonly(
          "lower", [](const JointFit& f) { return interval_field(f, [](const ParameterInterval& i) { return i.lower; }); },
          "(8,) lower ends of the intervals at `confidence`, SI")
      .def_property_readonly(
          "upper", [](const JointFit& f) { return interval_field(f, [](const ParameterInterval& i) { return i.upper; }); },
          "(8,) upper ends of the intervals, SI")
      .def_property_readonly("determined",
                             [](const JointFit& f) {
                               return flags(f.intervals, [](const ParameterInterval& i) { return i.determined; });
                             })
      .def_property_readonly("free",
                             [](const JointFit& f) {
                               return flags(f.intervals, [](const ParameterInterval& i) { return i.free; });
                             })
      .def_property_readonly(
          "covariance", [](const JointFit& f) { return matrix8(f.covariance); }, "(8, 8) SI")
      .def_property_readonly("correlation", [](const JointFit& f) { return matrix8(f.correlation()); })
      .def_property_readonly(
          "calibration_std_error", [](const JointFit& f) { return array_of(f.calibration_std_error); },
          "(8,) the stated calibration's share of each standard error, SI")
      .def_readonly("confidence", &JointFit::confidence)
      .def_property_readonly("method", [](const JointFit& f) { return name_of(f.method, kUncertainty); })
      .def_readonly("method_description", &JointFit::method_description)
      .def_readonly("bootstrap_samples", &JointFit::bootstrap_samples)
      .def_readonly("reciprocal", &JointFit::reciprocal)
      .def_readonly("points", &JointFit::points)
      .def_readonly("residual_ratio", &JointFit::residual_ratio)
      .def_readonly("residual_calibration_share", &JointFit::residual_calibration_share)
      .def_readonly("iterations", &JointFit::iterations)
      .def_readonly("converged", &JointFit::converged)
      .def_readonly("transfers", &JointFit::transfers)
      .def_readonly("transfer_statistic", &JointFit::transfer_statistic)
      .def_readonly("transfer_limit", &JointFit::transfer_limit)
      .def_readonly("warnings", &JointFit::warnings)
      .def(
          "to_dict", [](const JointFit& f) { return dict_of(f); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");

  options_class<JointFitOptions>(m, "JointFitOptions",
                                 fields_doc(joint_fit_fields(), "JointFitOptions", "toolpoint identify",
                                            "The band fit's options (joint_fit.hpp; IdentificationOptions.fit, "
                                            "CaseStudyOptions.fit_options). Progress is the function's `progress` argument."),
                                 {"reciprocal", "filter", "uncertainty", "bootstrap_samples", "seed", "shared_calibration",
                                  "check_linearisation", "confidence", "max_iterations", "threads"})
      .def_readwrite("reciprocal", &JointFitOptions::reciprocal, "six parameters (k_θf = k_ym, c_θf = c_ym); False: all eight")
      .def_readwrite("filter", &JointFitOptions::filter,
                     "SavgolOptions: fit filtered data (the model filtered alike), or None: raw (the identification sets it "
                     "from its own filter)")
      .def_property(
          "uncertainty", [](const JointFitOptions& o) { return std::string(name_of(o.uncertainty, kUncertainty)); },
          [](JointFitOptions& o, const std::string& v) {
            o.uncertainty = enum_of(v, kUncertainty, "JointFitOptions::uncertainty");
          },
          "the intervals: 'bootstrap' or 'linearised'")
      .def_readwrite("bootstrap_samples", &JointFitOptions::bootstrap_samples, "replicates, ≥ 20")
      .def_readwrite("seed", &JointFitOptions::seed, "of the bootstrap's noise draws (replicate b: stream_seed(seed, b))")
      .def_readwrite("shared_calibration", &JointFitOptions::shared_calibration,
                     "one calibration factor for every measured series (one sensor chain)")
      .def_readwrite("check_linearisation", &JointFitOptions::check_linearisation,
                     "linearised intervals with a measured B11 checked by a few bootstrap replicates")
      .def_readwrite("confidence", &JointFitOptions::confidence, "of the intervals, in (0.5, 1)")
      .def_readwrite("max_iterations", &JointFitOptions::max_iterations, "Levenberg–Marquardt iterations per pass")
      .def_property(
          "threads", [](const JointFitOptions& o) { return o.parallel.threads; },
          [](JointFitOptions& o, int threads) { o.parallel.threads = threads; },
          "bootstrap replicates on this many threads (0: every core); results identical for any count");

  m.def("weighted_median_parameters", &weighted_median_parameters, "series"_a, "lo_hz"_a, "hi_hz"_a,
        "The median of each parameter over [lo, hi] Hz, each point weighted by 1/gain²: the fit's starting values.");
}

// The identification study's options: the read-out's and the verdict's levels, the noise, the study's.
void bind_identification_options(py::module_& m) {
  auto readout = options_class<ReadoutOptions>(m, "ReadoutOptions", "The seed's read-out's warning levels (identify.hpp).",
                                               {"cond_warning", "reciprocity_warning", "gain_warning"});
  def_option_fields(readout, readout_fields(), "");
  options_class<ForwardCheckOptions>(m, "ForwardCheckOptions",
                                     fields_doc(forward_check_fields(), "ForwardCheckOptions", "toolpoint identify",
                                                "The forward check's options (forward_check.hpp; "
                                                "IdentificationOptions.verdict.forward)."),
                                     {"smoothing", "min_prominence", "replicates", "false_alarm", "frequency_tolerance",
                                      "peak_tolerance", "seed", "shared_calibration", "threads"})
      .def_readwrite("smoothing", &ForwardCheckOptions::smoothing,
                     "SavgolOptions applied to measured and predicted alike, or None: (15, 3)")
      .def_readwrite("min_prominence", &ForwardCheckOptions::min_prominence,
                     "a peak counts when it stands this fraction above its valleys")
      .def_readwrite("replicates", &ForwardCheckOptions::replicates, "Monte Carlo replicates of the noise (≥ 50)")
      .def_readwrite("false_alarm", &ForwardCheckOptions::false_alarm,
                     "P(fail) for data made by the identified model with the stated noise")
      .def_readwrite("frequency_tolerance", &ForwardCheckOptions::frequency_tolerance,
                     "relative natural-frequency error that matters")
      .def_readwrite("peak_tolerance", &ForwardCheckOptions::peak_tolerance, "relative peak-height error that matters")
      .def_readwrite("seed", &ForwardCheckOptions::seed, "replicate r draws from stream_seed(seed, r)")
      .def_readwrite("shared_calibration", &ForwardCheckOptions::shared_calibration,
                     "B11 and G11 share one calibration factor (one sensor chain)")
      .def_property(
          "threads", [](const ForwardCheckOptions& o) { return o.parallel.threads; },
          [](ForwardCheckOptions& o, int threads) { o.parallel.threads = threads; },
          "replicates on this many threads (0: every core); results identical for any count");
  auto verdict = options_class<VerdictOptions>(m, "VerdictOptions",
                                               "How the identification's verdict is reached (studies/identification.hpp).",
                                               {"forward", "residual_doubt", "residual_fail"})
                     .def_readwrite("forward", &VerdictOptions::forward,
                                    "ForwardCheckOptions (its smoothing, seed and threads are the study's: filter, fit)");
  def_option_fields(verdict, verdict_fields(), "");
  auto noise_spec = options_class<NoiseSpec>(m, "NoiseSpec",
                           "The noise of the measured series (studies/identification.hpp): estimated from the data or "
                           "stated; the calibration always stated.",
                           {"source", "estimate", "magnitude_sigma", "phase_sigma_rad", "floor", "calibration",
                            "calibration_shared", "averages"})
      .def_property(
          "source", [](const NoiseSpec& o) { return std::string(name_of(o.source, kNoiseSources)); },
          [](NoiseSpec& o, const std::string& v) { o.source = enum_of(v, kNoiseSources, "NoiseSpec::source"); },
          "'estimated' (from the data, by `estimate`) or 'stated' (the σ's and floor below)")
      .def_readwrite("estimate", &NoiseSpec::estimate, "NoiseEstimateOptions: how, when estimated")
      .def_readwrite("calibration_shared", &NoiseSpec::calibration_shared,
                     "one sensor chain for every measured FRF: one factor for all");
  // magnitude_sigma, phase_sigma_rad, floor, calibration, averages
  def_option_fields(noise_spec, noise_spec_fields(), "toolpoint identify");
  options_class<IdentificationOptions>(
      m, "IdentificationOptions",
      fields_doc(identification_fields(), "IdentificationOptions", "toolpoint identify",
                 "run_identification_study' options (studies/identification.hpp; toolpoint identify's). The overhang FRFs "
                 "(arrays) and progress stay the function's arguments."),
      {"route", "method", "band_hz", "at_hz", "width", "filter", "noise", "fit", "readout", "verdict"})
      .def_property(
          "route", [](const IdentificationOptions& o) { return std::string(name_of(o.route, kRoutes)); },
          [](IdentificationOptions& o, const std::string& v) { o.route = enum_of(v, kRoutes, "IdentificationOptions::route"); },
          "'holder_tool' (Eq. 6), 'spindle_holder_sh' (Eq. 15) or 'spindle_holder_sht' (Eq. 18)")
      .def_property(
          "method", [](const IdentificationOptions& o) { return std::string(to_string(o.method)); },
          [](IdentificationOptions& o, const std::string& v) {
            o.method = enum_of(v, kIdMethods, "IdentificationOptions::method");
          },
          "which result is `identified`: 'fit' (the band fit) or 'seed' (the read-out's medians)")
      .def_readwrite("band_hz", &IdentificationOptions::band_hz, "the read-out band (lo, hi) [Hz], also bounding the fit; or None")
      .def_readwrite("at_hz", &IdentificationOptions::at_hz, "the mode [Hz] read ± width around, or None")
      .def_readwrite("width", &IdentificationOptions::width, "± relative around the mode (0.02 = ±2 %)")
      .def_readwrite("filter", &IdentificationOptions::filter,
                     "SavgolOptions: the read-out reads filtered data and the fit filters G11 and its model alike; None: raw")
      .def_readwrite("noise", &IdentificationOptions::noise, "NoiseSpec of every measured series")
      .def_readwrite("fit", &IdentificationOptions::fit, "JointFitOptions (its filter is set from `filter`)")
      .def_readwrite("readout", &IdentificationOptions::readout, "ReadoutOptions")
      .def_readwrite("verdict", &IdentificationOptions::verdict, "VerdictOptions");
}

// The identification study from Python (both forms): the overhang FRFs judged as the CLI's files, the
// stated noise as its --sigma and --floor (plausibility.hpp), then the library's checks.
Identification identify_from_python(const Assembly& a, const std::vector<IdentificationData>& data, IdentificationOptions o,
                                    const std::vector<std::pair<RealArray, ComplexArray>>& overhang_frfs,
                                    const py::object& progress) {
  for (std::size_t k = 0; k < overhang_frfs.size(); ++k) {
    const std::string name = fmt::format("overhang_frfs[{}]", k);
    o.overhang_frfs.push_back(frf_series(overhang_frfs[k].first, overhang_frfs[k].second, name));
    judge_receptance(o.overhang_frfs.back(), name);
  }
  // As the CLI's --sigma, --floor: a σ in per cent refused (check()), an unusual one said.
  o.noise.check();
  warn_all(field_plausibility_warnings(noise_spec_fields(), o.noise, "NoiseSpec"));
  const ProgressCallback cb = progress_of(progress);
  py::gil_scoped_release nogil;
  return run_identification_study(a, data, o, cb);
}

// The identification study: the measured data in, the identification out.
void bind_identification_study(py::module_& m) {
  py::class_<IdentificationData>(
      m, "IdentificationData",
      "One measured set-up: G11 (SHT11 for Eq. 6/18, SH11 for Eq. 15) and B11 (SH11 for Eq. 6; S11 for Eq. 15/18, "
      "default the model's) as complex (n, 2, 2) on frequency_hz [Hz]; overhang_m [m] default the assembly's; "
      "g_coherence, b_coherence: the coherence γ² of each series' H entry (n,), used with the study's averages.")
      .def(py::init([](const RealArray& f, const ComplexArray& G11, const std::optional<ComplexArray>& B11,
                       std::optional<double> overhang_m, std::string label, std::string g_name, std::string b_name,
                       std::vector<double> g_coherence, std::vector<double> b_coherence) {
             IdentificationData d;
             d.g_coherence = std::move(g_coherence);
             d.b_coherence = std::move(b_coherence);
             d.G11 = block_series(f, G11, g_name.empty() ? "G11" : g_name);
             judge_receptance(d.G11, g_name.empty() ? "G11" : g_name);
             if (B11) {
               d.B11 = block_series(f, *B11, b_name.empty() ? "B11" : b_name);
               judge_receptance(*d.B11, b_name.empty() ? "B11" : b_name);
             }
             d.overhang_m = overhang_m;
             d.label = std::move(label);
             d.g_name = std::move(g_name);
             d.b_name = std::move(b_name);
             return d;
           }),
           "frequency_hz"_a, "G11"_a, "B11"_a = py::none(), "overhang_m"_a = py::none(), "label"_a = "", "g_name"_a = "",
           "b_name"_a = "", "g_coherence"_a = std::vector<double>{}, "b_coherence"_a = std::vector<double>{});

  py::class_<Identification>(
      m, "Identification",
      "run_identification_study' result: the seed's read-out and the band fit side by side, the mode choice, a forward "
      "check and a verdict. identified: the chosen method's JointParameters.")
      .def_property_readonly("route", [](const Identification& i) { return name_of(i.route, kRoutes); })
      .def_property_readonly("method", [](const Identification& i) { return to_string(i.method); })
      .def_readonly("equation", &Identification::equation)
      .def_readonly("closed_form", &Identification::closed_form, "JointSeries on the first set-up")
      .def_property_readonly(
          "mode", [](const Identification& i) { return dict_of(i.mode); }, "how the band was chosen (dict)")
      .def_readonly("seed", &Identification::seed, "the seed's read-out (JointReadout)")
      .def_readonly("fit", &Identification::fit, "the band fit (JointFit) or None")
      .def_readonly("fit_band_hz", &Identification::fit_band_hz)
      .def_readonly("g_noise", &Identification::g_noise)
      .def_readonly("b_noise", &Identification::b_noise)
      .def_readonly("identified", &Identification::identified)
      .def_property_readonly(
          "forward_checks", [](const Identification& i) { return dict_of(i.forward_checks); },
          "per set-up, the forward check (dicts: modes with their errors, the noise's spread and agreement; failures)")
      .def_property_readonly(
          "verdict", [](const Identification& i) { return to_string(i.verdict.verdict); }, "'pass', 'doubtful' or 'fail'")
      .def_property_readonly("verdict_reasons", [](const Identification& i) { return i.verdict.reasons; })
      .def_readonly("warnings", &Identification::warnings)
      .def(
          "joint_file", [](const Identification& i, const std::vector<std::string>& inputs) { return joint_file_of(i, inputs); },
          "inputs"_a = std::vector<std::string>{}, "The identified joint as a JointFile (the fit's covariance when fitted).")
      .def(
          "to_dict", [](const Identification& i) { return dict_of(i); }, "toolpoint identify --json's keys.");
  m.def(
      "run_identification_study",
      [](Assembly a, const std::vector<IdentificationData>& data, IdentificationOptions options,
         const std::vector<std::pair<RealArray, ComplexArray>>& overhang_frfs, const py::object& progress) {
        return identify_from_python(a, data, std::move(options), overhang_frfs, progress);
      },
      "assembly"_a, "data"_a, "options"_a, py::kw_only(),
      "overhang_frfs"_a = std::vector<std::pair<RealArray, ComplexArray>>{}, "progress"_a = py::none(),
      "The identification study with its options as one IdentificationOptions (the same as the keyword form below; "
      "besides, the read-out's warning levels and the verdict's).");
  m.def(
      "run_identification_study",
      [](Assembly a, const std::vector<IdentificationData>& data, const std::string& route, const std::string& method,
         std::optional<std::pair<double, double>> band_hz, std::optional<double> at_hz, double width,
         const std::vector<std::pair<RealArray, ComplexArray>>& overhang_frfs, std::optional<std::pair<int, int>> filter,
         std::optional<double> magnitude_sigma, double phase_sigma_rad, std::optional<double> floor, double calibration,
         bool calibration_shared, int averages, bool reciprocal, const std::string& uncertainty, int bootstrap_samples,
         std::uint64_t seed, double confidence, int threads, const py::object& progress) {
        IdentificationOptions o;
        o.route = enum_of(route, kRoutes, "route");
        o.method = enum_of(method, kIdMethods, "method");
        o.band_hz = band_hz;
        o.at_hz = at_hz;
        o.width = width;
        if (filter) o.filter = SavgolOptions{filter->first, filter->second};
        if (magnitude_sigma || floor) {
          o.noise.source = NoiseSpec::Source::Stated;
          o.noise.magnitude_sigma = magnitude_sigma.value_or(0.0);
          o.noise.phase_sigma_rad = phase_sigma_rad;
          o.noise.floor = floor.value_or(0.0);
        }
        o.noise.calibration = calibration;
        o.noise.calibration_shared = calibration_shared;
        o.noise.averages = averages;
        o.fit.reciprocal = reciprocal;
        o.fit.uncertainty = enum_of(uncertainty, kUncertainty, "uncertainty");
        o.fit.bootstrap_samples = bootstrap_samples;
        o.fit.seed = seed;
        o.fit.confidence = confidence;
        o.fit.parallel.threads = threads;
        return identify_from_python(a, data, std::move(o), overhang_frfs, progress);
      },
      "assembly"_a, "data"_a, "route"_a = "holder_tool", "method"_a = "fit", "band_hz"_a = py::none(), "at_hz"_a = py::none(),
      "width"_a = 0.02, "overhang_frfs"_a = std::vector<std::pair<RealArray, ComplexArray>>{}, "filter"_a = py::none(),
      "magnitude_sigma"_a = py::none(), "phase_sigma_rad"_a = 0.0, "floor"_a = py::none(), "calibration"_a = 0.0,
      "calibration_shared"_a = false, "averages"_a = 0, "reciprocal"_a = true, "uncertainty"_a = "bootstrap",
      "bootstrap_samples"_a = 200, "seed"_a = 1, "confidence"_a = 0.95, "threads"_a = 0, "progress"_a = py::none(),
      "The identification study (toolpoint identify): the joint of `route` ('holder_tool' Eq. 6, 'spindle_holder_sh' Eq. 15, "
      "'spindle_holder_sht' Eq. 18) from measured set-ups (list of IdentificationData). The seed's read-out in a band (band_hz "
      "(lo, hi) [Hz], or ± width around at_hz [Hz], around the mode that moves most across overhang_frfs [(frequency_hz, H)], or "
      "by effect analysis) and the band fit (method 'fit', default) of the constants to every frequency, with intervals "
      "('bootstrap' with bootstrap_samples replicates, or 'linearised') at `confidence`. filter (window, order): Savitzky–Golay. "
      "Noise estimated from the data (multiplicative and a floor) unless magnitude_sigma (0.05 = 5 %), phase_sigma_rad [rad] "
      "and floor (relative to each entry's peak) are stated; calibration: σ of each measured FRF's sensitivity (one factor "
      "for all with calibration_shared); averages: behind the data's coherence (IdentificationData g_coherence). Six parameters "
      "(reciprocal) or eight. threads: the bootstrap's (0: every core; results identical for any count).");
}

// The precision study from Python (both forms): the spacings, σ and floor judged as the CLI's
// --tool-spacing, --holder-spacing, --sigma and --floor (plausibility.hpp), then the library's checks.
PrecisionStudy precision_from_python(const Assembly& a, const PrecisionOptions& o, const py::object& progress) {
  if (o.tool.spacing_m > 0.0)
    check_plausible(plausible::kPointSpacing, o.tool.spacing_m, "PrecisionOptions::tool.spacing_m",
                    "give the spacing in m (15 mm = 0.015)");
  if (o.holder.spacing_m > 0.0)
    check_plausible(plausible::kPointSpacing, o.holder.spacing_m, "PrecisionOptions::holder.spacing_m",
                    "give the spacing in m (15 mm = 0.015)");
  if (o.noise.sigma > 0.0)
    check_plausible(plausible::kRelativeNoise, o.noise.sigma, "TapNoise::sigma", "give σ as a fraction (1 % = 0.01)");
  if (o.noise.floor > 0.0)
    check_plausible(plausible::kRelativeNoise, o.noise.floor, "TapNoise::floor", "give the floor as a fraction (1 % = 0.01)");
  const ProgressCallback cb = progress_of(progress);
  py::gil_scoped_release nogil;
  return run_precision_study(a, o, cb);
}

// The precision study: how tight the joint will be before the tap test.
void bind_precision(py::module_& m) {
  py::class_<PrecisionStudy>(m, "PrecisionStudy",
                             "run_precision_study's result: each joint parameter's expected interval before the tap test.")
      .def_property_readonly("route", [](const PrecisionStudy& r) { return name_of(r.route, kRoutes); })
      .def_property_readonly(
          "values", [](const PrecisionStudy& r) { return per_parameter(r, &ParameterPrecision::value); },
          "(8,) the assembly's joint (the trial values) [SI]")
      .def_property_readonly(
          "half_width", [](const PrecisionStudy& r) { return per_parameter(r, &ParameterPrecision::half_width); },
          "(8,) expected half-width of each parameter's interval at `confidence` [SI]")
      .def_property_readonly(
          "relative", [](const PrecisionStudy& r) { return per_parameter(r, &ParameterPrecision::relative); },
          "(8,) half_width / |value|")
      .def_property_readonly(
          "averages_for_target",
          [](const PrecisionStudy& r) {
            std::vector<std::optional<int>> n;
            for (const ParameterPrecision& p : r.parameters) n.push_back(p.averages_for_target);
            return n;
          },
          "hits per FRF each parameter needs for the target width (None: unreachable, or no target)")
      .def_readonly("confidence", &PrecisionStudy::confidence)
      .def_readonly("averages", &PrecisionStudy::averages)
      .def_readonly("measured", &PrecisionStudy::measured)
      .def_readonly("warnings", &PrecisionStudy::warnings)
      .def(
          "to_dict", [](const PrecisionStudy& r) { return dict_of(r); }, "toolpoint precision --json's keys.");
  auto tap_noise = options_class<TapNoise>(m, "TapNoise", "The noise of the tap tests being planned (studies/precision.hpp).",
                                           {"sigma", "floor", "averages", "calibration", "shared_calibration"});
  def_option_fields(tap_noise, tap_noise_fields(), "toolpoint precision");
  auto precision =
      options_class<PrecisionOptions>(m, "PrecisionOptions",
                                      "run_precision_study's options (studies/precision.hpp; toolpoint precision's).",
                                      {"route", "tool", "holder", "noise", "reciprocal", "confidence", "target"})
          .def_property(
              "route", [](const PrecisionOptions& o) { return std::string(name_of(o.route, kRoutes)); },
              [](PrecisionOptions& o, const std::string& v) { o.route = enum_of(v, kRoutes, "PrecisionOptions::route"); },
              "'holder_tool', 'spindle_holder_sh' or 'spindle_holder_sht'")
          .def_readwrite("tool", &PrecisionOptions::tool,
                         "TapTestOptions of the tool's tap test (spacing_m required when the route measures SHT11)")
          .def_readwrite("holder", &PrecisionOptions::holder,
                         "TapTestOptions of the holder's tap test (spacing_m required when the route measures SH11)")
          .def_readwrite("noise", &PrecisionOptions::noise, "TapNoise: one hit's variation, floor, averages, calibration")
          .def_readwrite("target", &PrecisionOptions::target,
                         "a relative half-width wanted for each parameter (0.01 = ±1 %), or None");
  def_option_fields(precision, precision_fields(), "toolpoint precision");  // reciprocal, confidence
  m.def(
      "run_precision_study",
      [](Assembly a, const PrecisionOptions& options, const py::object& progress) {
        return precision_from_python(a, options, progress);
      },
      "assembly"_a, "options"_a, py::kw_only(), "progress"_a = py::none(),
      "The precision study with its options as one PrecisionOptions (the same as the keyword form below; besides, a "
      "different point count or hammer per tap test).");
  m.def(
      "run_precision_study",
      [](Assembly a, const std::string& route, std::optional<double> tool_spacing_m, std::optional<double> holder_spacing_m,
         int points, const std::string& hammer, double sigma, double floor, int averages, double calibration,
         bool calibration_shared, bool reciprocal, double confidence, std::optional<double> target, const py::object& progress) {
        PrecisionOptions o;
        o.route = enum_of(route, kRoutes, "route");
        for (TapTestOptions* t : {&o.tool, &o.holder}) {
          t->points = points;
          t->hammer = enum_of(hammer, kHammers, "hammer");
        }
        o.tool.spacing_m = tool_spacing_m.value_or(0.0);
        o.holder.spacing_m = holder_spacing_m.value_or(0.0);
        o.noise.sigma = sigma;
        o.noise.floor = floor;
        o.noise.averages = averages;
        o.noise.calibration = calibration;
        o.noise.shared_calibration = calibration_shared;
        o.reciprocal = reciprocal;
        o.confidence = confidence;
        o.target = target;
        return precision_from_python(a, o, progress);
      },
      "assembly"_a, "route"_a = "holder_tool", "tool_spacing_m"_a = py::none(), "holder_spacing_m"_a = py::none(), "points"_a = 3,
      "hammer"_a = "roving", "sigma"_a = 0.01, "floor"_a = 0.0, "averages"_a = 1, "calibration"_a = 0.0,
      "calibration_shared"_a = false, "reciprocal"_a = true, "confidence"_a = 0.95, "target"_a = py::none(),
      "progress"_a = py::none(),
      "How tight the joint of `route` will be before the tap test (toolpoint precision): the tap tests its identification needs "
      "(points spaced tool_spacing_m / holder_spacing_m [m] on the tool for SHT11, the holder for SH11; hammer 'roving' or "
      "'tip'), one hit's variation sigma (0.01 = 1 %) and floor (relative to each FRF's peak), `averages` hits per FRF, each "
      "test's calibration σ; the expected half-width of each parameter's interval at `confidence` (the linearised band fit on "
      "the model's exact FRFs), and the averages a relative half-width `target` (0.05 = ±5 %) needs.");
}

// The joint's uncertainty carried forward: tool point bands, sampled joints, quantiles.
void bind_uncertainty(py::module_& m) {
  py::class_<FrfBand>(m, "FrfBand", "The tool point FRF H with the joint uncertain: quantiles per frequency.")
      .def_property_readonly("frequency_hz", [](const FrfBand& b) { return python::array_of(b.frequency_hz); })
      .def_property_readonly("levels", [](const FrfBand& b) { return python::array_of(b.levels); })
      .def_property_readonly(
          "nominal", [](const FrfBand& b) { return python::array_of(b.nominal.values); },
          "H with the joint's constants, complex (n,) m/N")
      .def_property_readonly(
          "magnitude", [](const FrfBand& b) { return matrix_array(rows_matrix(b.magnitude)); },
          "(levels, n) quantiles of |H| [m/N]")
      .def_property_readonly(
          "phase_rad", [](const FrfBand& b) { return matrix_array(rows_matrix(b.phase_rad)); }, "(levels, n) [rad]")
      .def_readonly("samples", &FrfBand::samples)
      .def(
          "to_dict", [](const FrfBand& b) { return dict_of(b); },
          "The result as plain data (dicts, lists, floats, str, bool, None; the CLI's --json keys, SI units).");
  m.def(
      "tool_point_band",
      [](Assembly a, JointFile joint, const RealArray& f, int samples, std::uint64_t seed, std::vector<double> levels,
         int threads, const py::object& progress) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        const UncertaintyOptions o = uncertainty_options(samples, seed, std::move(levels), threads, progress);
        py::gil_scoped_release nogil;
        return tool_point_band(a, joint, grid, o);
      },
      "assembly"_a, "joint"_a, "frequency_hz"_a, "samples"_a = 200, "seed"_a = 1,
      "levels"_a = std::vector<double>{0.05, 0.5, 0.95}, "threads"_a = 0, "progress"_a = py::none(),
      "Monte Carlo over the joint of a JointFile with [uncertainty] (samples drawn from N(θ̂, C), seed per sample): quantiles of "
      "the "
      "tool point FRF's |H| and phase per frequency [Hz]. Threads: 0 every core; results identical for any count.");
  m.def(
      "tool_point_band",
      [](Assembly a, JointFile joint, const RealArray& f, UncertaintyOptions options, const py::object& progress) {
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        options.progress = progress_of(progress);
        py::gil_scoped_release nogil;
        return tool_point_band(a, joint, grid, options);
      },
      "assembly"_a, "joint"_a, "frequency_hz"_a, "options"_a, py::kw_only(), "progress"_a = py::none(),
      "tool_point_band with its options as one UncertaintyOptions (the same as the keyword form above).");
  m.def(
      "sample_joints",
      [](const JointParameters& mean, const RealArray& covariance, int count, std::uint64_t seed) {
        return sample_joints(mean, matrix8_of(covariance, "covariance"), count, seed);
      },
      "mean"_a, "covariance"_a, "count"_a, "seed"_a,
      "`count` JointParameters drawn from N(mean, covariance) (8×8, SI), reproducibly from `seed`.");
  m.def("quantile", &quantile, "values"_a, "p"_a, "Type-7 quantile (numpy's default) at level p of values (NaN left out).");
}

// The seed's case study.
void bind_case_study(py::module_& m) {
  py::class_<CaseStudy>(m, "CaseStudy", "run_case_study's result (the seed's Section 3 and the band fit; toolpoint demo).")
      .def_readonly("assembly", &CaseStudy::assembly)
      .def_readonly("reference", &CaseStudy::reference, "the holder–tool joint put in (Table 1 in the example)")
      .def_property_readonly("frequency_hz", [](const CaseStudy& c) { return python::array_of(c.sht_true.frequency_hz); })
      .def_property_readonly(
          "sh_true", [](const CaseStudy& c) { return blocks_array(c.sh_true.blocks); }, "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sht_true", [](const CaseStudy& c) { return blocks_array(c.sht_true.blocks); }, "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sh_noisy", [](const CaseStudy& c) { return blocks_array(c.sh_noisy.blocks); }, "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sht_noisy", [](const CaseStudy& c) { return blocks_array(c.sht_noisy.blocks); }, "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sh_filtered", [](const CaseStudy& c) { return blocks_array(c.sh_filtered.blocks); },
          "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sht_filtered", [](const CaseStudy& c) { return blocks_array(c.sht_filtered.blocks); },
          "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sht_verified", [](const CaseStudy& c) { return blocks_array(c.sht_verified.blocks); },
          "complex (n, 2, 2) on frequency_hz")
      .def_property_readonly(
          "sht_fitted", [](const CaseStudy& c) { return blocks_array(c.sht_fitted.blocks); }, "complex (n, 2, 2) on frequency_hz")
      .def_readonly("clean", &CaseStudy::clean)
      .def_readonly("noisy", &CaseStudy::noisy)
      .def_readonly("filtered", &CaseStudy::filtered)
      .def_property_readonly("clean_max_deviation", [](const CaseStudy& c) { return array_of(c.clean_max_deviation); })
      .def_readonly("effect", &CaseStudy::effect)
      .def_readonly("mode_hz", &CaseStudy::mode_hz)
      .def_readonly("clean_readout", &CaseStudy::clean_readout)
      .def_readonly("noisy_readout", &CaseStudy::noisy_readout)
      .def_readonly("filtered_readout", &CaseStudy::filtered_readout)
      .def_readonly("verification", &CaseStudy::verification)
      .def_readonly("seed", &CaseStudy::seed, "the seed's procedure (Identification)")
      .def_readonly("fitted", &CaseStudy::fitted, "the band fit (Identification) or None")
      .def_readonly("fit_verification", &CaseStudy::fit_verification)
      .def_readonly("warnings", &CaseStudy::warnings)
      .def(
          "to_dict", [](const CaseStudy& c) { return dict_of(c); },
          "The result as plain data, the series left out (toolpoint demo --json's keys, less what the CLI adds; SI units).");
  auto case_options = options_class<CaseStudyOptions>(m, "CaseStudyOptions",
                                                      "run_case_study's options (studies/case_study.hpp; toolpoint demo's).",
                                                      {"noise_sigma", "seed", "filter", "apply_filter", "band_width", "fit",
                                                       "fit_options"})
                          .def_readwrite("seed", &CaseStudyOptions::seed, "SH11 draws from `seed`, SHT11 from `seed + 1`")
                          .def_readwrite("filter", &CaseStudyOptions::filter, "SavgolOptions (window in frequency points, order)")
                          .def_readwrite("fit_options", &CaseStudyOptions::fit_options,
                                         "JointFitOptions: its intervals, threads, seed");
  def_option_fields(case_options, case_study_fields(), "toolpoint demo");  // noise_sigma, apply_filter, band_width, fit
  m.def(
      "run_case_study",
      [](Assembly a, const CaseStudyOptions& options, const py::object& progress) {
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_case_study(a, options, cb);
      },
      "assembly"_a, "options"_a, py::kw_only(), "progress"_a = py::none(),
      "The case study with its options as one CaseStudyOptions (the same as the keyword form below).");
  m.def(
      "run_case_study",
      [](Assembly a, double noise_sigma, std::uint64_t seed, std::pair<int, int> filter, bool apply_filter, double band_width,
         bool fit, const std::string& uncertainty, int bootstrap_samples, std::uint64_t fit_seed, int threads,
         const py::object& progress) {
        CaseStudyOptions o;
        o.noise_sigma = noise_sigma;
        o.seed = seed;
        o.filter = {filter.first, filter.second};
        o.apply_filter = apply_filter;
        o.band_width = band_width;
        o.fit = fit;
        o.fit_options.uncertainty = enum_of(uncertainty, kUncertainty, "uncertainty");
        o.fit_options.bootstrap_samples = bootstrap_samples;
        o.fit_options.seed = fit_seed;
        o.fit_options.parallel.threads = threads;
        const ProgressCallback cb = progress_of(progress);
        py::gil_scoped_release nogil;
        return run_case_study(a, o, cb);
      },
      "assembly"_a, "noise_sigma"_a = 0.05, "seed"_a = 1, "filter"_a = std::make_pair(81, 2), "apply_filter"_a = true,
      "band_width"_a = 0.02, "fit"_a = true, "uncertainty"_a = "bootstrap", "bootstrap_samples"_a = 200, "fit_seed"_a = 1,
      "threads"_a = 0, "progress"_a = py::none(),
      "The seed's analytical case study (Section 3; toolpoint demo): predict, identify noise-free, add noise_sigma "
      "multiplicative noise "
      "(SH11 seed, SHT11 seed + 1), Savitzky–Golay filter (window, order), read at the tool mode ± band_width; and the band fit "
      "to the "
      "raw noisy data (bootstrap seed fit_seed; the CLI passes its --seed for both).");
}

}  // namespace

void bind_identify(py::module_& m) {
  bind_closed_form(m);
  bind_noise(m);
  bind_joint_files(m);
  bind_joint_fit(m);
  bind_identification_options(m);
  bind_identification_study(m);
  bind_precision(m);
  bind_uncertainty(m);
  bind_case_study(m);
}

}  // namespace toolpoint::python
