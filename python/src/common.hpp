// toolpoint Python bindings: conversions shared by the binding files.
//
// Conventions (those of pyFBS/SDynPy, docs/python.md): frequencies in Hz as float64 arrays of
// shape (n,); a 2×2 receptance block series [[H, L], [N, P]] as complex128 (n, 2, 2); a single FRF
// as complex128 (n,); a two-end component's end receptances as complex128 (n, 4, 4) over
// (w1, θ1, w2, θ2), i.e. [[b11, b12], [b21, b22]] (coupling.hpp's as_matrix); SI units; enums as
// lower-case strings. Inputs are copied once into the library's value types (its studies own their
// data); outputs are new numpy arrays. Long computations run with the GIL released; mutable inputs
// (Assembly, Segment, JointFile) are taken by value, copied while the GIL is held, so another Python
// thread changing the object meanwhile cannot race with the computation.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <complex>
#include <cstdint>
#include <memory>
#include <fmt/format.h>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "toolpoint/option_fields.hpp"
#include "toolpoint/plausibility.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/study.hpp"
#include "toolpoint/studies/tap_test.hpp"

namespace toolpoint {
struct UncertaintyOptions;
}  // namespace toolpoint

namespace toolpoint::python {

namespace py = pybind11;

using RealArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using ComplexArray = py::array_t<std::complex<double>, py::array::c_style | py::array::forcecast>;

// A 1-D float array as a vector; InputError naming `name` for another shape.
std::vector<double> vector_of(const RealArray& a, const std::string& name);
// A 1-D complex array as a vector; InputError naming `name` for another shape.
std::vector<Complex> complex_vector_of(const ComplexArray& a, const std::string& name);
// (n, 2, 2) complex as blocks; InputError naming `name` for another shape.
std::vector<Block> blocks_of(const ComplexArray& a, const std::string& name);
// (n, 4, 4) complex as two-ports; InputError naming `name` for another shape.
std::vector<TwoPort> two_ports_of(const ComplexArray& a, const std::string& name);

py::array_t<double> array_of(const std::vector<double>& v);
py::array_t<std::complex<double>> array_of(const std::vector<Complex>& v);
py::array_t<std::complex<double>> blocks_array(const std::vector<Block>& blocks);
py::array_t<std::complex<double>> block_array(const Block& b);  // (2, 2)
py::array_t<std::complex<double>> two_ports_array(const std::vector<TwoPort>& t);
py::array_t<double> matrix_array(const Eigen::MatrixXd& m);  // (rows, cols)
// [row][column] vectors (rows of equal length) as a matrix.
Eigen::MatrixXd rows_matrix(const std::vector<std::vector<double>>& rows);

// Series from arrays (no validation here: the library validates and names `what`).
BlockSeries block_series(const RealArray& frequency_hz, const ComplexArray& blocks, const std::string& what);
FrfSeries frf_series(const RealArray& frequency_hz, const ComplexArray& values, const std::string& what);

// The library's plausibility checks (plausibility.hpp) on what Python gives, as the CLI makes them on
// its files and options: a receptance's top frequency and largest |H| (judge_receptance_data), a
// value against its range (require_plausible). Unusual: a toolpoint.Warning; cannot be meant:
// InputError (data) or InvalidArgument (a value), naming `what`.
void judge_receptance(const FrfSeries& receptance, const std::string& what);
void judge_receptance(const BlockSeries& receptance, const std::string& what);
void check_plausible(const PlausibleRange& range, double value, const std::string& what, const std::string& fix);

// (min_rpm, max_rpm, points) as a SpeedRange; speeds judged as the CLI's --rpm (rpm, not rad/s or Hz).
SpeedRange speed_range(const std::tuple<double, double, int>& s);

// A tap test's hammer plan by name (run_tap_test_study, run_precision_study).
inline const std::vector<std::pair<const char*, HammerPlan>> kHammers{{"roving", HammerPlan::Roving}, {"tip", HammerPlan::Tip}};

// RotationalOptions as given from Python, judged as the CLI's --spacing and --shear-stiffness
// (plausibility.hpp), then checked.
RotationalOptions checked_rotational(const RotationalOptions& o);

// Translational FRFs on `frequency_hz` from a dict {(response, force): complex (n,)} (points 0, 1, 2;
// InvalidArgument for another key), as rotational_frfs and the rotational study take them.
PointFrfs point_frfs_of(const std::vector<double>& frequency_hz, const py::dict& H);
// The same dict from PointFrfs: {(response, force): complex (n,)} for the FRFs it holds.
py::dict point_frfs_dict(const PointFrfs& frfs);

// UncertaintyOptions from keyword arguments (bind_identify.cpp).
UncertaintyOptions uncertainty_options(int samples, std::uint64_t seed, std::vector<double> levels, int threads,
                                       const py::object& progress);

// nlohmann::json as plain Python objects (dict, list, float, int, str, bool, None).
py::object to_python(const nlohmann::json& j);
template <class T>
py::object dict_of(const T& value) {
  const nlohmann::json j = value;
  return to_python(j);
}

// A Python callable (or None) as a library progress callback: called with the GIL taken, from
// whichever thread reports; an exception it raises is reported as unraisable and ignored (the
// library's callbacks must not throw).
ProgressCallback progress_of(const py::object& callback);

// Each message as a Python warning of category toolpoint.Warning.
void warn_all(const std::vector<std::string>& warnings);

// The enum spelt as a string: the value whose name equals `text`, else InvalidArgument naming
// `option` and listing the names.
template <class E>
E enum_of(const std::string& text, const std::vector<std::pair<const char*, E>>& names, const std::string& option);

// A library *Options struct as a Python class: default-constructed (the C++ defaults), its fields
// read/write (added by the caller), check(); `fields` lists them in order, as `_fields`, from which
// toolpoint/__init__.py gives the class a keyword-only constructor whose defaults are a default
// instance's values (so they cannot drift from the C++ ones) and a repr of every field.
template <class T>
py::class_<T> options_class(py::module_& m, const char* name, const char* doc, std::initializer_list<const char*> fields) {
  py::class_<T> c(m, name, doc);
  c.def(py::init<>());
  // An options struct without a check() (every value valid) has none.
  if constexpr (requires(const T& o) { o.check(); })
    c.def(
        "check", [](const T& o) { o.check(); },
        "Raises InvalidArgument naming Options::field for a value out of range (the functions taking the options "
        "check them too).");
  py::tuple names(fields.size());
  std::size_t i = 0;
  for (const char* f : fields) names[i++] = py::str(f);
  c.attr("_fields") = names;
  return c;
}


// A docstring followed by its option fields' definitions (option_fields.hpp): each keyword, its
// unit and range, what its automatic value means, its help and the CLI's flag (`command` FLAG).
// The text lives in a static string per call site's Options type and doc: pybind11 copies a
// docstring, but the one given must outlive m.def.
template <class Options>
const char* fields_doc(const std::vector<OptionField<Options>>& fields, const char* options, const char* command,
                       const char* doc);

// An option table as data (toolpoint._option_fields): what python/tests check the keywords against.
template <class Options>
py::list fields_data(const std::vector<OptionField<Options>>& fields);

// An options class's attributes from its option fields (option_fields.hpp): each field read/write
// as its own type (float, int, bool), its docstring the field's unit, range, note and help, and the
// CLI's flag (`command` FLAG).
template <class Options>
void def_option_fields(py::class_<Options>& c, const std::vector<OptionField<Options>>& fields, const char* command);

// Binding groups (one file each).
void bind_errors(py::module_& m);
void bind_model(py::module_& m);
void bind_signal_io(py::module_& m);
void bind_identify(py::module_& m);
void bind_stability(py::module_& m);
void bind_simulation(py::module_& m);
void bind_pitch(py::module_& m);

}  // namespace toolpoint::python

// ---- template definitions ----------------------------------------------------------------------

#include "toolpoint/error.hpp"

namespace toolpoint::python {

template <class E>
E enum_of(const std::string& text, const std::vector<std::pair<const char*, E>>& names, const std::string& option) {
  std::string list;
  for (const auto& [name, value] : names) {
    if (text == name) return value;
    list += (list.empty() ? "'" : ", '") + std::string(name) + "'";
  }
  throw InvalidArgument(fmt::format("{} '{}' is not one of {}", option, text, list),
                        fmt::format("give {} as one of {}", option, list));
}

template <class E>
const char* name_of(E value, const std::vector<std::pair<const char*, E>>& names) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "?";
}

// A field's description after its unit and range, as both docstrings below write it:
// " (note): help (command FLAG)".
inline std::string field_doc_tail(const FieldSpec& s, const char* command) {
  std::string t = *s.note ? fmt::format(" ({})", s.note) : std::string();
  t += fmt::format(": {}", s.help);
  if (s.cli_name) t += fmt::format(" ({} {})", command, field_flag(s));
  return t;
}

template <class Options>
const char* fields_doc(const std::vector<OptionField<Options>>& fields, const char* options, const char* command,
                       const char* doc) {
  static std::vector<std::unique_ptr<std::string>> texts;  // each docstring made, kept for the module's life
  std::string text = fmt::format("{} Keywords defined with {}:", doc, options);
  for (const OptionField<Options>& f : fields) {
    const FieldSpec& s = f.spec;
    text += fmt::format(" {}{}", s.name, *s.unit ? fmt::format(" [{}]", s.unit) : std::string());
    if (s.kind != FieldKind::Flag) text += fmt::format(", {}", field_range_text(s));
    text += field_doc_tail(s, command) + ".";
  }
  return texts.emplace_back(std::make_unique<std::string>(std::move(text)))->c_str();
}

template <class Options>
py::list fields_data(const std::vector<OptionField<Options>>& fields) {
  py::list out;
  const Options defaults{};
  for (const OptionField<Options>& f : fields) {
    const FieldSpec& s = f.spec;
    py::dict d;
    d["name"] = s.name;
    d["kind"] = s.kind == FieldKind::Real ? "real" : s.kind == FieldKind::Integer ? "integer" : "flag";
    d["unit"] = s.unit;
    d["min"] = s.min;
    d["max"] = s.max;
    d["default"] = f.get(defaults);
    d["flag"] = s.cli_name ? py::object(py::str(field_flag(s))) : py::object(py::none());
    d["cli_unit"] = s.cli_unit ? s.cli_unit : s.unit;
    d["cli_per_unit"] = s.cli_per_unit;
    d["plan_key"] = s.plan_key ? py::object(py::str(s.plan_key)) : py::object(py::none());
    d["help"] = s.help;
    out.append(d);
  }
  return out;
}

template <class Options>
void def_option_fields(py::class_<Options>& c, const std::vector<OptionField<Options>>& fields, const char* command) {
  for (const OptionField<Options>& f : fields) {
    const FieldSpec& s = f.spec;
    std::string doc = *s.unit ? fmt::format("[{}] ", s.unit) : std::string();
    if (s.kind != FieldKind::Flag) doc += field_range_text(s);
    doc += field_doc_tail(s, command);
    const OptionField<Options>* field = &f;  // the table is static: the address outlives the module
    switch (s.kind) {
      case FieldKind::Real:
        c.def_property(
            s.name, [field](const Options& o) { return field->get(o); }, [field](Options& o, double v) { field->set(o, v); },
            doc.c_str());
        break;
      case FieldKind::Integer:
        c.def_property(
            s.name, [field](const Options& o) { return static_cast<int>(field->get(o)); },
            [field](Options& o, int v) { field->set(o, v); }, doc.c_str());
        break;
      case FieldKind::Flag:
        c.def_property(
            s.name, [field](const Options& o) { return field->get(o) != 0.0; },
            [field](Options& o, bool v) { field->set(o, v ? 1.0 : 0.0); }, doc.c_str());
        break;
    }
  }
}

}  // namespace toolpoint::python
