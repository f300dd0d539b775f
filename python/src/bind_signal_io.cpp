// toolpoint Python bindings: signal processing (signal.hpp), peaks (peaks.hpp) and files (io.hpp,
// frf_file.hpp, uff.hpp). Frequencies in Hz; FRF values in their own units (receptance m/N).
#include "common.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/measured/resample.hpp"
#include "toolpoint/studies/resample.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/filter.hpp"
#include "toolpoint/studies/rotational.hpp"
#include "toolpoint/io/uff.hpp"

namespace toolpoint::python {

namespace {

using namespace pybind11::literals;

const std::vector<std::pair<const char*, PMethod>> kPMethods{{"auto", PMethod::Auto},
                                                             {"cross_terms", PMethod::CrossTerms},
                                                             {"schmitz_smith", PMethod::SchmitzSmith}};
const std::vector<std::pair<const char*, FrfFormat>> kFormats{{"auto", FrfFormat::Auto},
                                                              {"csv", FrfFormat::Csv},
                                                              {"uff", FrfFormat::Uff},
                                                              {"uffb", FrfFormat::UffBinary},
                                                              {"frf", FrfFormat::Frf}};
const std::vector<std::pair<const char*, FrfOrdinate>> kOrdinates{{"receptance", FrfOrdinate::Receptance},
                                                                  {"mobility", FrfOrdinate::Mobility},
                                                                  {"accelerance", FrfOrdinate::Accelerance}};

const std::vector<std::pair<const char*, FrfValueFormat>> kValueFormats{{"re-im", FrfValueFormat::ReIm},
                                                                        {"mag-phase-deg", FrfValueFormat::MagPhaseDeg},
                                                                        {"mag-phase-rad", FrfValueFormat::MagPhaseRad},
                                                                        {"db-phase", FrfValueFormat::DbPhaseDeg},
                                                                        {"db-phase-rad", FrfValueFormat::DbPhaseRad}};

const std::vector<std::pair<const char*, Interpolation>> kInterpolations{{"linear", Interpolation::Linear},
                                                                         {"cubic", Interpolation::Cubic}};

// A frequency grid for functions that only need the samples' order: 1, 2, … n.
std::vector<double> index_grid(std::size_t n) {
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = static_cast<double>(i + 1);
  return f;
}

// One series through a signal function, the GIL released; its warnings to `warnings`.
template <class Series, class F>
Series signal_run(const Series& s, F on, std::vector<std::string>& warnings) {
  std::optional<decltype(on(s))> r;
  {
    py::gil_scoped_release nogil;
    r.emplace(on(s));
  }
  warnings = std::move(r->warnings);
  return std::move(r->series);
}

// Runs a series function on a (n,) or (n, 2, 2) complex array with its frequencies; warnings to Python.
template <class OnFrf, class OnBlock>
py::array series_apply(const py::array& values, const std::vector<double>& f, const std::string& what, OnFrf on_frf,
                       OnBlock on_block) {
  const ComplexArray v = values.cast<ComplexArray>();
  std::vector<std::string> warnings;
  py::array out;
  if (v.ndim() == 1) out = array_of(signal_run(FrfSeries{f, complex_vector_of(v, what)}, on_frf, warnings).values);
  else out = blocks_array(signal_run(BlockSeries{f, blocks_of(v, what)}, on_block, warnings).blocks);
  warn_all(warnings);
  return out;
}

// FilterStudy<Series> as the Python class `name`; `values` (n,) for an FRF, (n, 2, 2) for a block.
template <class Series, class Values>
void bind_filter_study(py::module_& m, const char* name, Values values) {
  using Study = FilterStudy<Series>;
  py::class_<Study>(m, name, "run_filter_study's result (studies/filter.hpp).")
      .def_property_readonly(
          "frequency_hz", [](const Study& r) { return array_of(r.filtered.frequency_hz); }, "(n,) Hz")
      .def_property_readonly(
          "filtered", [values](const Study& r) { return values(r.filtered); }, "the filtered values, the input's shape")
      .def_readonly("noise_gain", &Study::noise_gain, "Σ c² of the interior weights: white-noise variance after / before")
      .def_property_readonly(
          "peaks", [](const Study& r) { return dict_of(r.peaks); },
          "the peaks before and after: {'peaks': [{'entry', 'raw_frequency_hz', …}], 'warnings'}")
      .def_readonly("warnings", &Study::warnings)
      .def(
          "to_dict", [](const Study& r) { return dict_of(r); }, "The result as plain data, the filtered series left out.");
}

UffDof dof_of(const py::object& o) {
  UffDof d;
  if (o.is_none()) return d;
  const py::dict m = o.cast<py::dict>();
  for (auto [k, v] : m) {
    const std::string key = k.cast<std::string>();
    const int x = v.cast<int>();
    if (key == "response_node") d.response_node = x;
    else if (key == "response_direction") d.response_direction = x;
    else if (key == "reference_node") d.reference_node = x;
    else if (key == "reference_direction") d.reference_direction = x;
    else
      throw InvalidArgument(fmt::format("dof: unknown key '{}'", key),
                            "use response_node, response_direction, reference_node, reference_direction");
  }
  return d;
}

}  // namespace

RotationalOptions checked_rotational(const RotationalOptions& o) {
  if (o.spacing != 0.0)
    check_plausible(plausible::kPointSpacing, o.spacing, "RotationalOptions::spacing", "give the spacing in m (15 mm = 0.015)");
  if (o.shear_stiffness)
    check_plausible(plausible::kShearStiffness, *o.shear_stiffness, "RotationalOptions::shear_stiffness",
                    "give κGA in N (pass TapTest.shear_stiffness_n)");
  o.check();
  return o;
}

PointFrfs point_frfs_of(const std::vector<double>& frequency_hz, const py::dict& H) {
  PointFrfs frfs;
  for (auto [key, value] : H) {
    const auto ij = key.cast<std::pair<int, int>>();
    if (ij.first < 0 || ij.first > 2 || ij.second < 0 || ij.second > 2)
      throw InvalidArgument(fmt::format("H key ({}, {}) is not (response, force) with points 0, 1, 2", ij.first, ij.second),
                            "key H by (response, force), e.g. {(0, 0): h00, (1, 0): h10}");
    const std::string name = fmt::format("H{}{}", ij.first, ij.second);
    frfs.set(ij.first, ij.second, FrfSeries{frequency_hz, complex_vector_of(value.cast<ComplexArray>(), name)});
  }
  return frfs;
}

py::dict point_frfs_dict(const PointFrfs& frfs) {
  py::dict H;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (const auto& h = frfs.h[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)])
        H[py::make_tuple(i, j)] = array_of(h->values);
  return H;
}

namespace {

// savgol_filter on a real (n,), complex (n,) or block (n, 2, 2) array (both forms of the binding).
py::array savgol_filter_array(const py::array& values, const SavgolOptions& o, const py::object& frequency_hz) {
  const bool is_complex = values.dtype().kind() == 'c';
  if (!is_complex && values.ndim() == 1 && frequency_hz.is_none()) {
    const std::vector<double> x = vector_of(values.cast<RealArray>(), "values");
    std::vector<double> y;
    {
      py::gil_scoped_release nogil;
      y = savgol_filter(std::span<const double>(x), o, "values");
    }
    return array_of(y);
  }
  const std::size_t n = values.ndim() > 0 ? static_cast<std::size_t>(values.shape(0)) : 0;
  const std::vector<double> f = frequency_hz.is_none() ? index_grid(n)
                                                       : vector_of(frequency_hz.cast<RealArray>(), "frequency_hz");
  return series_apply(
      values, f, "values", [&](const FrfSeries& s) { return savgol_filter(s, o, "values"); },
      [&](const BlockSeries& s) { return savgol_filter(s, o, "values"); });
}

// Savitzky–Golay, the seed's noise, rotational FRFs by finite differences.
void bind_signal(py::module_& m) {
  auto savgol = options_class<SavgolOptions>(m, "SavgolOptions",
                                             "A Savitzky–Golay filter (signal.hpp; toolpoint filter's --window, --order): "
                                             "window and polynomial order.",
                                             {"window", "order"});
  def_option_fields(savgol, savgol_fields(), "toolpoint filter");
  m.def(
      "savgol_coefficients",
      [](int window, int order) {
        return array_of(savgol_coefficients(SavgolOptions{window, order}));
      },
      "window"_a = 5, "order"_a = 2,
      fields_doc(savgol_fields(), "SavgolOptions", "toolpoint filter",
                 "The Savitzky–Golay interior weights c_{−m..m} (left to right) for an odd `window` [points] and polynomial "
                 "`order`."));
  m.def(
      "savgol_coefficients", [](const SavgolOptions& options) { return array_of(savgol_coefficients(options)); },
      "options"_a, "savgol_coefficients with its options as one SavgolOptions (the same as the keyword form above).");
  m.def(
      "savgol_filter",
      [](const py::array& values, int window, int order, const py::object& frequency_hz) {
        return savgol_filter_array(values, SavgolOptions{window, order}, frequency_hz);
      },
      "values"_a, "window"_a = 5, "order"_a = 2, "frequency_hz"_a = py::none(),
      "Savitzky–Golay smoothing (seed Section 4; matches scipy.signal.savgol_filter(mode='interp')) along the first axis: real "
      "(n,), "
      "complex (n,) or a block series (n, 2, 2) (real and imaginary parts separately). `window` in points (odd), `order` the "
      "polynomial degree. With frequency_hz [Hz] an uneven grid is flagged (toolpoint.Warning).");
  m.def(
      "savgol_filter",
      [](const py::array& values, const SavgolOptions& options, const py::object& frequency_hz) {
        return savgol_filter_array(values, options, frequency_hz);
      },
      "values"_a, "options"_a, py::kw_only(), "frequency_hz"_a = py::none(),
      "savgol_filter with its options as one SavgolOptions (the same as the keyword form above).");
  bind_filter_study<FrfSeries>(m, "FilterStudy", [](const FrfSeries& x) { return array_of(x.values); });
  bind_filter_study<BlockSeries>(m, "BlockFilterStudy", [](const BlockSeries& x) { return blocks_array(x.blocks); });
  m.def(
      "run_filter_study",
      [](const RealArray& f, const ComplexArray& values, int window, int order, double min_prominence, double min_height,
         double warn_above, double noise_prominence, const std::string& what) -> py::object {
        FilterStudyOptions o;
        o.savgol = {window, order};
        o.peaks = {min_prominence, min_height, warn_above, noise_prominence};
        const std::vector<double> grid = vector_of(f, "frequency_hz");
        if (values.ndim() == 1) {
          const FrfSeries s{grid, complex_vector_of(values, "values")};
          FilterStudy<FrfSeries> r;
          {
            py::gil_scoped_release nogil;
            r = run_filter_study(s, o, what);
          }
          return py::cast(std::move(r));
        }
        const BlockSeries s{grid, blocks_of(values, "values")};
        FilterStudy<BlockSeries> r;
        {
          py::gil_scoped_release nogil;
          r = run_filter_study(s, o, what);
        }
        return py::cast(std::move(r));
      },
      "frequency_hz"_a, "values"_a, "window"_a, "order"_a, "min_prominence"_a = 0.2, "min_height"_a = 0.05, "warn_above"_a = 0.02,
      "noise_prominence"_a = 8.0, "what"_a = "FRF",
      "The filter study (toolpoint filter): Savitzky–Golay smoothing of a measured FRF, complex (n,), or block (n, 2, 2) "
      "[m/N] against frequency_hz [Hz] (window [points] at most a quarter of n, polynomial order), its interior white-noise "
      "gain Σc², and each prominent peak before and after (peak_changes' options; a change beyond warn_above is a warning).");
  m.def(
      "add_measurement_noise",
      [](const RealArray& f, const py::array& values, double sigma, std::uint64_t seed, double floor, double calibration,
         int averages, bool with_coherence) -> py::object {
        const NoiseOptions o{.sigma = sigma, .seed = seed, .floor = floor, .calibration = calibration, .averages = averages};
        std::vector<double> coherence;
        py::array out = series_apply(
            values, vector_of(f, "frequency_hz"), "values",
            [&](const FrfSeries& s) {
              auto r = add_measurement_noise(s, o, "values");
              coherence = r.coherence;
              return r;
            },
            [&](const BlockSeries& s) {
              auto r = add_measurement_noise(s, o, "values");
              coherence = r.coherence;
              return r;
            });
        if (!with_coherence) return out;
        return py::make_tuple(out, array_of(coherence));
      },
      "frequency_hz"_a, "values"_a, "sigma"_a = 0.05, "seed"_a = 1, py::kw_only(), "floor"_a = 0.0, "calibration"_a = 0.0,
      "averages"_a = 0, "with_coherence"_a = false,
      fields_doc(noise_fields(), "NoiseOptions", "toolpoint noise",
                 "The seed's multiplicative noise (Section 3): every entry at every frequency times its own factor 1 + σz, z "
                 "standard normal (mt19937_64 + Box–Muller, reproducible from `seed`; order: frequency, then H, L, N, P); with "
                 "floor an additive floor relative to each entry's peak; with averages ≥ 2 an averaged test of that many hits "
                 "(each varying by σ) instead; with calibration one factor on the whole series. values: complex (n,) or (n, 2, "
                 "2). Returns the noisy values, or with with_coherence=True (values, coherence γ² (n,) of H; empty without "
                 "averages)."));
  m.def(
      "standard_normals", [](std::size_t count, std::uint64_t seed) { return array_of(standard_normals(count, seed)); },
      "count"_a, "seed"_a, "`count` standard normal numbers from `seed` (Box–Muller on mt19937_64; portable).");

  auto rotational = options_class<RotationalOptions>(
      m, "RotationalOptions",
      "How rotational_frfs, finite_difference_error and run_rotational_study take finite differences (signal.hpp; "
      "toolpoint rotational's options). spacing [m] has no default.",
      {"spacing", "order", "symmetrise", "p_method", "shear_stiffness", "assume_reciprocity"});
  def_option_fields(rotational, rotational_fields(), "toolpoint rotational");  // order, spacing, symmetrise, assume_reciprocity
  rotational
      .def_property(
          "p_method", [](const RotationalOptions& o) { return std::string(name_of(o.p_method, kPMethods)); },
          [](RotationalOptions& o, const std::string& v) { o.p_method = enum_of(v, kPMethods, "RotationalOptions::p_method"); },
          "'auto', 'cross_terms' or 'schmitz_smith'")
      .def_readwrite("shear_stiffness", &RotationalOptions::shear_stiffness,
                     "κGA [N] of the section the points lie on (pass TapTest.shear_stiffness_n): the shear strain removed; "
                     "None: the total-slope quantities");

  py::class_<RotationalResult>(m, "RotationalResult", "rotational_frfs' result.")
      .def_property_readonly("frequency_hz", [](const RotationalResult& r) { return array_of(r.block.frequency_hz); })
      .def_property_readonly(
          "block", [](const RotationalResult& r) { return blocks_array(r.block.blocks); }, "[[H00, L], [N, P]] complex (n, 2, 2)")
      .def_readonly("p_from_cross_terms", &RotationalResult::p_from_cross_terms)
      .def_readonly("l_equals_n_by_reciprocity", &RotationalResult::l_equals_n_by_reciprocity)
      .def_readonly("reciprocity_mismatch", &RotationalResult::reciprocity_mismatch)
      .def_readonly("warnings", &RotationalResult::warnings)
      .def(
          "to_dict", [](const RotationalResult& r) { return dict_of(r); }, "The result as plain data, the block left out.");
  m.def(
      "rotational_frfs",
      [](const RealArray& f, const py::dict& h, const RotationalOptions& options) {
        const PointFrfs frfs = point_frfs_of(vector_of(f, "frequency_hz"), h);
        const RotationalOptions o = checked_rotational(options);
        py::gil_scoped_release nogil;
        return rotational_frfs(frfs, o);
      },
      "frequency_hz"_a, "H"_a, "options"_a,
      "Rotational FRFs by finite differences (Duarte & Ewins; docs/reference.md §5): H is a dict {(response, force): complex "
      "(n,) [m/N]} of "
      "the "
      "translational FRFs at points 0 (tip), 1, 2 spaced options.spacing m inwards (options: RotationalOptions).");
}

// Peaks and mode tracking.
void bind_peaks(py::module_& m) {
  auto peaks = options_class<PeakOptions>(m, "PeakOptions", "Which local maxima of |H| find_peaks counts as peaks (peaks.hpp).",
                                          {"min_prominence"});
  def_option_fields(peaks, peak_fields(), "");
  m.def(
      "find_peaks",
      [](const RealArray& f, const ComplexArray& values, const std::optional<PeakOptions>& options) {
        const FrfSeries s = frf_series(f, values, "values");
        return find_peaks(s, options.value_or(PeakOptions{}));
      },
      "frequency_hz"_a, "values"_a, py::kw_only(), "options"_a = py::none(),
      "options: PeakOptions (None: the defaults). Local maxima of |values| rising min_prominence (relative) above their valleys, "
      "ascending, refined by a parabola through "
      "log|H|.");
  m.def(
      "track_modes",
      [](const std::vector<std::vector<Peak>>& family, std::size_t reference, double tolerance, bool ordered) {
        const auto t = track_modes(family, reference, tolerance, ordered);
        py::array_t<double> a({static_cast<py::ssize_t>(t.size()), static_cast<py::ssize_t>(family.size())});
        auto w = a.mutable_unchecked<2>();
        for (std::size_t i = 0; i < t.size(); ++i)
          for (std::size_t j = 0; j < family.size(); ++j) w(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = t[i][j];
        return a;
      },
      "family"_a, "reference"_a, "tolerance"_a = 0.15, "ordered"_a = true,
      "Modes (the peaks of family[reference]) followed through a family of peak lists: (modes, members) frequencies [Hz], NaN "
      "where lost.");
}

// write_frf_file on a complex (n,) or block (n, 2, 2) array (both forms of the binding); what the format lost.
std::vector<std::string> write_frf_array(const std::string& path, const RealArray& f, const py::array& values,
                                         const FrfWriteOptions& o) {
  if (values.ndim() == 3) {
    const BlockSeries s = block_series(f, values.cast<ComplexArray>(), "values");
    py::gil_scoped_release nogil;
    return write_frf_file(path, s, o);
  }
  const FrfSeries s = frf_series(f, values.cast<ComplexArray>(), "values");
  py::gil_scoped_release nogil;
  return write_frf_file(path, s, o);
}

// The FRF file reader's and writer's options.
void bind_frf_file_options(py::module_& m) {
  options_class<FrfReadOptions>(m, "FrfReadOptions",
                                "read_frf_file's options (frf_file.hpp; the CLI's --format, --dataset, --ordinate, --units, "
                                "--columns of every command reading an FRF).",
                                {"format", "dataset", "response_node", "response_direction", "reference_node",
                                 "reference_direction", "ordinate", "units", "value_format", "columns"})
      .def_property(
          "format", [](const FrfReadOptions& o) { return std::string(name_of(o.format, kFormats)); },
          [](FrfReadOptions& o, const std::string& v) { o.format = enum_of(v, kFormats, "FrfReadOptions::format"); },
          "'auto' (by extension), 'csv', 'uff', 'uffb' or 'frf'")
      .def_property(
          "dataset", [](const FrfReadOptions& o) { return o.uff.index; },
          [](FrfReadOptions& o, std::optional<std::size_t> v) { o.uff.index = v; },
          "UFF: the index of the dataset 58 among the file's datasets 58 (None: chosen by the codes, or the only one)")
      .def_property(
          "response_node", [](const FrfReadOptions& o) { return o.uff.response_node; },
          [](FrfReadOptions& o, std::optional<int> v) { o.uff.response_node = v; }, "UFF: record 6's response node, or None")
      .def_property(
          "response_direction", [](const FrfReadOptions& o) { return o.uff.response_direction; },
          [](FrfReadOptions& o, std::optional<int> v) { o.uff.response_direction = v; },
          "UFF: record 6's response direction code, or None")
      .def_property(
          "reference_node", [](const FrfReadOptions& o) { return o.uff.reference_node; },
          [](FrfReadOptions& o, std::optional<int> v) { o.uff.reference_node = v; }, "UFF: record 6's reference node, or None")
      .def_property(
          "reference_direction", [](const FrfReadOptions& o) { return o.uff.reference_direction; },
          [](FrfReadOptions& o, std::optional<int> v) { o.uff.reference_direction = v; },
          "UFF: record 6's reference direction code, or None")
      .def_property(
          "ordinate",
          [](const FrfReadOptions& o) {
            return o.ordinate ? std::optional<std::string>(name_of(*o.ordinate, kOrdinates)) : std::nullopt;
          },
          [](FrfReadOptions& o, const std::optional<std::string>& v) {
            o.ordinate = v ? std::optional(enum_of(*v, kOrdinates, "FrfReadOptions::ordinate")) : std::nullopt;
          },
          "'receptance', 'mobility' or 'accelerance' (None: the file's units or codes, else receptance)")
      .def_property(
          "units", [](const FrfReadOptions& o) { return o.units ? std::optional<std::string>(o.units->label) : std::nullopt; },
          [](FrfReadOptions& o, const std::optional<std::string>& v) {
            if (!v) {
              o.units.reset();
              return;
            }
            o.units = parse_frf_units(*v);
            if (!o.units)
              throw InvalidArgument(fmt::format("FrfReadOptions::units '{}' is not a unit of an FRF", *v),
                                    "give e.g. 'm/N', 'mm/N', 'um/N', 'm/s/N', 'g/N' (None: the file's)");
            o.units->label = *v;
          },
          "the values' units ('mm/N', 'um/N', 'm/s/N', 'g/N', …; they imply the ordinate), or None: the file's, else SI")
      .def_property(
          "value_format",
          [](const FrfReadOptions& o) {
            return o.csv.format ? std::optional<std::string>(name_of(*o.csv.format, kValueFormats)) : std::nullopt;
          },
          [](FrfReadOptions& o, const std::optional<std::string>& v) {
            o.csv.format = v ? std::optional(enum_of(*v, kValueFormats, "FrfCsvOptions::format")) : std::nullopt;
          },
          "CSV: the value columns' meaning, 're-im', 'mag-phase-deg', 'mag-phase-rad', 'db-phase' or 'db-phase-rad' (None: "
          "from the header)")
      .def_property(
          "columns", [](const FrfReadOptions& o) { return o.csv.columns; },
          [](FrfReadOptions& o, std::vector<std::string> v) { o.csv.columns = std::move(v); },
          "CSV: the frequency, two value and optionally coherence columns, each a 1-based number or a header cell's text "
          "([]: by the header's names)");
  options_class<FrfWriteOptions>(m, "FrfWriteOptions",
                                 "write_frf_file's options (frf_file.hpp; toolpoint's --output of an FRF). The file's "
                                 "writer judges them (a coherence of another length, out of [0, 1]).",
                                 {"format", "description", "comments", "dof", "coherence"})
      .def_property(
          "format", [](const FrfWriteOptions& o) { return std::string(name_of(o.format, kFormats)); },
          [](FrfWriteOptions& o, const std::string& v) { o.format = enum_of(v, kFormats, "FrfWriteOptions::format"); },
          "'auto' (by extension), 'csv', 'uff' (ASCII 58), 'uffb' (binary 58b) or 'frf'")
      .def_readwrite("description", &FrfWriteOptions::description, "UFF ID line 1; a CSV comment line")
      .def_readwrite("comments", &FrfWriteOptions::comments, "CSV comment lines")
      .def_property(
          "dof", [](const FrfWriteOptions& o) { return dict_of(o.dof); },
          [](FrfWriteOptions& o, const py::object& v) { o.dof = dof_of(v); },
          "UFF record 6 labels {'response_node', 'response_direction', 'reference_node', 'reference_direction'}")
      .def_readwrite("coherence", &FrfWriteOptions::coherence,
                     "γ² per frequency, or []: a CSV column (UFF and .frf cannot hold it: said in what is returned)");
}

// FRF files (one reader for every format, the writer) and resampling.
void bind_files(py::module_& m) {
  py::class_<FrfFileData>(m, "FrfFile", "An FRF file read: receptance [m/N] against frequency [Hz], and where it came from.")
      .def_property_readonly("frequency_hz",
                             [](const FrfFileData& d) {
                               return array_of(d.is_block ? d.block.frequency_hz : d.single.frequency_hz);
                             })
      .def_property_readonly(
          "values",
          [](const FrfFileData& d) -> py::array {
            if (d.is_block) return blocks_array(d.block.blocks);
            return array_of(d.single.values);
          },
          "complex (n,) or, for a block CSV, (n, 2, 2)")
      .def_readonly("is_block", &FrfFileData::is_block)
      .def_property_readonly("format", [](const FrfFileData& d) { return frf_format_name(d.format); })
      .def_property_readonly(
          "ordinate", [](const FrfFileData& d) { return frf_ordinate_name(d.ordinate); }, "what the file held, before conversion")
      .def_readonly("description", &FrfFileData::description)
      .def_property_readonly(
          "dof", [](const FrfFileData& d) { return dict_of(d.dof); }, "UFF record 6 labels")
      .def_readonly("warnings", &FrfFileData::warnings)
      .def_property_readonly(
          "metadata", [](const FrfFileData& d) { return dict_of(d); }, "Everything but the arrays, as a dict (json.hpp).");
  m.def(
      "read_frf_file",
      [](const std::string& path, const std::string& format, const std::optional<std::string>& ordinate,
         std::optional<std::size_t> dataset, std::optional<int> response_node, std::optional<int> response_direction,
         std::optional<int> reference_node, std::optional<int> reference_direction) {
        FrfReadOptions o;
        o.format = enum_of(format, kFormats, "format");
        if (ordinate) o.ordinate = enum_of(*ordinate, kOrdinates, "ordinate");
        o.uff.index = dataset;
        o.uff.response_node = response_node;
        o.uff.response_direction = response_direction;
        o.uff.reference_node = reference_node;
        o.uff.reference_direction = reference_direction;
        py::gil_scoped_release nogil;
        return read_frf_file(path, o);
      },
      "path"_a, "format"_a = "auto", "ordinate"_a = py::none(), "dataset"_a = py::none(), "response_node"_a = py::none(),
      "response_direction"_a = py::none(), "reference_node"_a = py::none(), "reference_direction"_a = py::none(),
      "Reads an FRF file: FRF CSV (single or 2×2 block), UFF 58/58b (one dataset 58, chosen by `dataset` index among the file's "
      "datasets 58 and/or node/direction codes), CutPro .frf. format 'auto' (by extension), 'csv', 'uff', 'frf'. Mobility or "
      "accelerance (from the UFF codes, or ordinate='mobility'/'accelerance') is converted to receptance [m/N]. Raises "
      "InputError "
      "naming file, line or dataset; IoError.");
  m.def(
      "read_frf_file",
      [](const std::string& path, const FrfReadOptions& options) {
        py::gil_scoped_release nogil;
        return read_frf_file(path, options);
      },
      "path"_a, "options"_a, "read_frf_file with its options as one FrfReadOptions (the same as the keyword form above; "
      "besides, the units and a CSV's columns and value format).");
  py::class_<FrfResampled>(m, "FrfResampled", "run_resample_study's result (resample.hpp).")
      .def_readonly("file", &FrfResampled::data, "FrfFile: the FRF on the new grid, in the input's form")
      .def_property_readonly(
          "coherence", [](const FrfResampled& r) { return array_of(r.data.coherence); }, "(n,) or empty")
      .def_readonly("description", &FrfResampled::description, "what was done (the CLI's comment line)")
      .def_readonly("warnings", &FrfResampled::warnings);
  m.def(
      "run_resample_study",
      [](const FrfFileData& file, std::optional<std::pair<double, double>> band_hz, const py::object& target_hz,
         const std::string& target_name, const std::string& method, const std::string& what) {
        FrfResampleOptions o;
        o.band_hz = band_hz;
        if (!target_hz.is_none()) o.target_hz = vector_of(target_hz.cast<RealArray>(), "target_hz");
        o.target_name = target_name;
        o.method = enum_of(method, kInterpolations, "method");
        py::gil_scoped_release nogil;
        return run_resample_study(file, o, what);
      },
      "file"_a, "band_hz"_a = py::none(), "target_hz"_a = py::none(), "target_name"_a = "the target grid", "method"_a = "linear",
      "what"_a = "FRF",
      "An FRF file's data (read_frf_file) on another grid (toolpoint resample): with target_hz [Hz], cropped to band_hz "
      "(low, high) when given, the FRF and its coherence interpolated onto it ('linear' or 'cubic', real and imaginary parts, "
      "never extrapolated); without, the FRF and its coherence cropped to band_hz.");
  m.def(
      "write_frf_file",
      [](const std::string& path, const RealArray& f, const py::array& values, const std::string& format,
         const std::string& description, const std::vector<std::string>& comments, const py::object& dof) {
        FrfWriteOptions o;
        o.format = enum_of(format, kFormats, "format");
        o.description = description;
        o.comments = comments;
        o.dof = dof_of(dof);
        return write_frf_array(path, f, values, o);
      },
      "path"_a, "frequency_hz"_a, "values"_a, "format"_a = "auto", "description"_a = "",
      "comments"_a = std::vector<std::string>{}, "dof"_a = py::none(),
      "Writes a receptance [m/N] against frequency [Hz]: complex (n,) as CSV, UFF 58 ('uff'), 58b ('uffb') or CutPro .frf; a "
      "block "
      "(n, 2, 2) as FRF CSV only. Written whole or not at all. dof: UFF record 6 labels {'response_node', 'response_direction', "
      "'reference_node', 'reference_direction'}. Returns what the format lost (list of str).");
  m.def(
      "write_frf_file",
      [](const std::string& path, const RealArray& f, const py::array& values, const FrfWriteOptions& options) {
        return write_frf_array(path, f, values, options);
      },
      "path"_a, "frequency_hz"_a, "values"_a, "options"_a,
      "write_frf_file with its options as one FrfWriteOptions (the same as the keyword form above; besides, a coherence "
      "column).");
}

// Universal files: datasets 58/58b, units, a tap test picked from one file.
void bind_uff(py::module_& m) {
  py::class_<UffAxis>(m, "UffAxis", "UFF records 8–11: data characteristics of one axis.")
      .def(py::init<>())
      .def_readwrite("data_type", &UffAxis::data_type,
                     "specific data type (8 displacement, 12 acceleration, 13 force, 18 frequency, ...)")
      .def_readwrite("length_exponent", &UffAxis::length_exponent)
      .def_readwrite("force_exponent", &UffAxis::force_exponent)
      .def_readwrite("temperature_exponent", &UffAxis::temperature_exponent)
      .def_readwrite("label", &UffAxis::label)
      .def_readwrite("units", &UffAxis::units);
  py::class_<UffUnits>(m, "UffUnits", "UFF dataset 164: units in force (SI value = file value / factor).")
      .def_readonly("code", &UffUnits::code)
      .def_readonly("description", &UffUnits::description)
      .def_readonly("length_factor", &UffUnits::length_factor)
      .def_readonly("force_factor", &UffUnits::force_factor)
      .def_readonly("temperature_factor", &UffUnits::temperature_factor);
  py::class_<UffDataset58>(m, "UffDataset58",
                           "One UFF dataset 58 (function at nodal DOF), as read or to be written: x (abscissa, float (n,)) and y "
                           "(ordinate, complex (n,)) arrays, the records' fields as attributes, the rest in metadata.")
      .def(py::init([](const RealArray& x, const ComplexArray& y) {
             UffDataset58 d;
             d.x = vector_of(x, "x");
             d.y = complex_vector_of(y, "y");
             d.even = false;
             return d;
           }),
           "x"_a, "y"_a, "A complex double FRF dataset with uneven abscissa; set fields (id, nodes, axes) before writing.")
      .def_property(
          "x", [](const UffDataset58& d) { return array_of(d.x); },
          [](UffDataset58& d, const RealArray& a) { d.x = vector_of(a, "x"); })
      .def_property(
          "y", [](const UffDataset58& d) { return array_of(d.y); },
          [](UffDataset58& d, const ComplexArray& a) { d.y = complex_vector_of(a, "y"); })
      .def_readwrite("id", &UffDataset58::id, "records 1–5 (list of 5 str)")
      .def_readwrite("function_type", &UffDataset58::function_type)
      .def_readwrite("function_id", &UffDataset58::function_id)
      .def_readwrite("version", &UffDataset58::version)
      .def_readwrite("load_case", &UffDataset58::load_case)
      .def_readwrite("response_entity", &UffDataset58::response_entity)
      .def_readwrite("response_node", &UffDataset58::response_node)
      .def_readwrite("response_direction", &UffDataset58::response_direction)
      .def_readwrite("reference_entity", &UffDataset58::reference_entity)
      .def_readwrite("reference_node", &UffDataset58::reference_node)
      .def_readwrite("reference_direction", &UffDataset58::reference_direction)
      .def_readwrite("ordinate_data_type", &UffDataset58::ordinate_data_type)
      .def_readwrite("even", &UffDataset58::even)
      .def_readwrite("abscissa_min", &UffDataset58::abscissa_min)
      .def_readwrite("abscissa_increment", &UffDataset58::abscissa_increment)
      .def_readwrite("z_value", &UffDataset58::z_value)
      .def_readwrite("abscissa", &UffDataset58::abscissa)
      .def_readwrite("ordinate", &UffDataset58::ordinate)
      .def_readwrite("denominator", &UffDataset58::denominator)
      .def_readwrite("z_axis", &UffDataset58::z_axis)
      .def_readonly("declared_points", &UffDataset58::declared_points)
      .def_readonly("index", &UffDataset58::index)
      .def_readonly("line", &UffDataset58::line)
      .def_readonly("binary", &UffDataset58::binary)
      .def_readonly("byte_order", &UffDataset58::byte_order)
      .def_readonly("units", &UffDataset58::units)
      .def_readonly("warnings", &UffDataset58::warnings)
      .def_property_readonly(
          "metadata", [](const UffDataset58& d) { return dict_of(d); },
          "Every record field but x and y, with names for the codes, as a dict (json.hpp; toolpoint convert --list --json).")
      .def("check", &UffDataset58::check, "Raises InvalidArgument unless the dataset can be written.");
  py::class_<UffFile>(m, "UffFile", "A universal file read: its datasets 58, and every problem found.")
      .def_readonly("source", &UffFile::source)
      .def_readonly("functions", &UffFile::functions, "list of UffDataset58 (the readable datasets 58/58b, in file order)")
      .def_property_readonly(
          "datasets", [](const UffFile& f) { return dict_of(f.datasets); },
          "every dataset in file order: {'type', 'binary', 'line', 'offset'}")
      .def_readonly("warnings", &UffFile::warnings)
      .def_readonly("skipped", &UffFile::skipped);
  m.def(
      "read_uff",
      [](const std::string& path) {
        py::gil_scoped_release nogil;
        return read_uff(path);
      },
      "path"_a,
      "Reads a universal file (datasets 58 and 58b; other datasets listed and skipped). Liberal: problems go to warnings, never "
      "exceptions, except IoError for a file that cannot be read. Values as written (no unit conversion: read_frf_file "
      "converts).");
  py::class_<TapTestFileFrfs>(m, "TapTestFileFrfs", "A tap test's FRFs picked from one universal file (tap_test_frfs).")
      .def_property_readonly(
          "frequency_hz", [](const TapTestFileFrfs& t) { return array_of(t.frfs.h[0][0]->frequency_hz); }, "H00's grid [Hz]")
      .def_property_readonly(
          "H", [](const TapTestFileFrfs& t) { return point_frfs_dict(t.frfs); },
          "{(response, force): complex (n,) [m/N]}, as rotational_frfs and run_rotational_study take it")
      .def_property_readonly(
          "dataset",
          [](const TapTestFileFrfs& t) {
            py::dict d;
            for (std::size_t i = 0; i < 3; ++i)
              for (std::size_t j = 0; j < 3; ++j)
                if (t.dataset[i][j]) d[py::make_tuple(i, j)] = *t.dataset[i][j];
            return d;
          },
          "{(response, force): index of the dataset among UffFile.functions}")
      .def_readonly("warnings", &TapTestFileFrfs::warnings, "the conversions' (the file's own are UffFile.warnings)");
  m.def(
      "tap_test_frfs",
      [](const UffFile& file, const std::vector<int>& nodes, std::optional<int> direction, int order,
         const std::optional<std::string>& ordinate) {
        TapTestFileOptions o;
        o.nodes = nodes;
        o.direction = direction;
        o.order = order;
        if (ordinate) o.ordinate = enum_of(*ordinate, kOrdinates, "ordinate");
        py::gil_scoped_release nogil;
        return tap_test_frfs(file, o);
      },
      "file"_a, "nodes"_a = std::vector<int>{1, 2, 3}, "direction"_a = py::none(), "order"_a = 2, "ordinate"_a = py::none(),
      fields_doc(tap_test_file_fields(), "TapTestFileOptions", "toolpoint rotational",
                 "The tap test in one universal file (read_uff): H_ij is the dataset whose response node is nodes[i] and whose "
                 "reference node is nodes[j] (tip first), in `direction` (record 6 code, +Y = 2; None: any), for points "
                 "0…order, as receptance [m/N]. Raises InputError for two datasets of one pair of points or none for the tip "
                 "(listing the nodes present)."));
  m.def(
      "write_uff",
      [](const std::string& path, const std::vector<UffDataset58>& sets, bool binary, int byte_order) {
        UffWriteOptions o{binary, byte_order};
        py::gil_scoped_release nogil;
        return write_uff(path, sets, o);
      },
      "path"_a, "datasets"_a, "binary"_a = false, "byte_order"_a = 1,
      fields_doc(uff_write_fields(), "UffWriteOptions", "toolpoint taptest",
                 "Writes datasets 58 (ASCII) or 58b (binary=True; byte_order 1 little, 2 big endian), whole or not at all. "
                 "Returns what ASCII rounding lost (list of str)."));
}

}  // namespace

void bind_signal_io(py::module_& m) {
  bind_signal(m);
  bind_peaks(m);
  bind_frf_file_options(m);
  bind_files(m);
  bind_uff(m);
}

}  // namespace toolpoint::python
