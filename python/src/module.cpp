// toolpoint Python bindings: the module, the exceptions, the conversions (common.hpp).
#include <memory>

#include "common.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/version.hpp"

namespace toolpoint::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void require_shape(const py::array& a, const std::string& name, std::initializer_list<py::ssize_t> tail, const char* expected) {
  bool ok = a.ndim() == static_cast<py::ssize_t>(tail.size()) + 1;
  py::ssize_t d = 1;
  for (py::ssize_t t : tail) ok = ok && a.shape(d++) == t;
  if (!ok)
    throw InputError(fmt::format("{}: an array of shape {} where {} was expected", name, shape_text(a), expected),
                     fmt::format("pass {} as a numpy array of shape {}", name, expected));
}

// The exception classes (created once, kept for the interpreter's life).
PyObject* g_error = nullptr;
PyObject* g_invalid = nullptr;
PyObject* g_input = nullptr;
PyObject* g_numerical = nullptr;
PyObject* g_verdict = nullptr;
PyObject* g_io = nullptr;
PyObject* g_warning = nullptr;

PyObject* new_class(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  const std::string qualified = std::string("toolpoint.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
  if (!cls) throw py::error_already_set();
  m.attr(name) = py::handle(cls);
  return cls;
}

void raise(PyObject* cls, const Error& e) {
  py::object instance = py::reinterpret_borrow<py::object>(cls)(py::str(e.what()));
  instance.attr("hint") = py::str(e.hint());
  // Python 3.11+ prints notes under the message in tracebacks: the hint as the CLI's "fix:" line.
  if (!e.hint().empty() && py::hasattr(instance, "add_note")) instance.attr("add_note")(py::str("fix: " + e.hint()));
  PyErr_SetObject(cls, instance.ptr());
}

}  // namespace

std::vector<double> vector_of(const RealArray& a, const std::string& name) {
  require_shape(a, name, {}, "(n,)");
  return {a.data(), a.data() + a.size()};
}

std::vector<Complex> complex_vector_of(const ComplexArray& a, const std::string& name) {
  require_shape(a, name, {}, "(n,)");
  return {a.data(), a.data() + a.size()};
}

std::vector<Block> blocks_of(const ComplexArray& a, const std::string& name) {
  require_shape(a, name, {2, 2}, "(n, 2, 2)");
  std::vector<Block> out(static_cast<std::size_t>(a.shape(0)));
  const auto r = a.unchecked<3>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    out[static_cast<std::size_t>(i)] = make_block(r(i, 0, 0), r(i, 0, 1), r(i, 1, 0), r(i, 1, 1));
  return out;
}

std::vector<TwoPort> two_ports_of(const ComplexArray& a, const std::string& name) {
  require_shape(a, name, {4, 4}, "(n, 4, 4)");
  std::vector<TwoPort> out(static_cast<std::size_t>(a.shape(0)));
  const auto r = a.unchecked<3>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    auto blk = [&](int r0, int c0) { return make_block(r(i, r0, c0), r(i, r0, c0 + 1), r(i, r0 + 1, c0), r(i, r0 + 1, c0 + 1)); };
    out[static_cast<std::size_t>(i)] = {blk(0, 0), blk(0, 2), blk(2, 0), blk(2, 2)};
  }
  return out;
}

py::array_t<double> array_of(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::array_t<std::complex<double>> array_of(const std::vector<Complex>& v) {
  py::array_t<std::complex<double>> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::array_t<std::complex<double>> blocks_array(const std::vector<Block>& blocks) {
  py::array_t<std::complex<double>> a({static_cast<py::ssize_t>(blocks.size()), py::ssize_t{2}, py::ssize_t{2}});
  auto w = a.mutable_unchecked<3>();
  for (std::size_t i = 0; i < blocks.size(); ++i)
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) w(static_cast<py::ssize_t>(i), r, c) = blocks[i](r, c);
  return a;
}

py::array_t<std::complex<double>> block_array(const Block& b) {
  py::array_t<std::complex<double>> a({py::ssize_t{2}, py::ssize_t{2}});
  auto w = a.mutable_unchecked<2>();
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) w(r, c) = b(r, c);
  return a;
}

py::array_t<std::complex<double>> two_ports_array(const std::vector<TwoPort>& t) {
  py::array_t<std::complex<double>> a({static_cast<py::ssize_t>(t.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto w = a.mutable_unchecked<3>();
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Block* b[2][2] = {{&t[i].b11, &t[i].b12}, {&t[i].b21, &t[i].b22}};
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) w(static_cast<py::ssize_t>(i), r, c) = (*b[r / 2][c / 2])(r % 2, c % 2);
  }
  return a;
}

py::array_t<double> matrix_array(const Eigen::MatrixXd& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = a.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) w(r, c) = m(r, c);
  return a;
}

Eigen::MatrixXd rows_matrix(const std::vector<std::vector<double>>& rows) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), rows.empty() ? 0 : static_cast<Eigen::Index>(rows.front().size()));
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) m(r, c) = rows[static_cast<std::size_t>(r)].at(static_cast<std::size_t>(c));
  return m;
}

BlockSeries block_series(const RealArray& frequency_hz, const ComplexArray& blocks, const std::string& what) {
  BlockSeries s{vector_of(frequency_hz, "frequency_hz"), blocks_of(blocks, what)};
  if (s.frequency_hz.size() != s.blocks.size())
    throw InputError(fmt::format("{}: {} blocks for {} frequencies", what, s.blocks.size(), s.frequency_hz.size()),
                     "give one (2, 2) block per frequency");
  return s;
}

FrfSeries frf_series(const RealArray& frequency_hz, const ComplexArray& values, const std::string& what) {
  FrfSeries s{vector_of(frequency_hz, "frequency_hz"), complex_vector_of(values, what)};
  if (s.frequency_hz.size() != s.values.size())
    throw InputError(fmt::format("{}: {} values for {} frequencies", what, s.values.size(), s.frequency_hz.size()),
                     "give one value per frequency");
  return s;
}

void judge_receptance(const FrfSeries& receptance, const std::string& what) { warn_all(judge_receptance_data(receptance, what)); }

void judge_receptance(const BlockSeries& receptance, const std::string& what) {
  warn_all(judge_receptance_data(receptance, what));
}

void check_plausible(const PlausibleRange& range, double value, const std::string& what, const std::string& fix) {
  if (const std::string w = require_plausible(range, value, what, fix); !w.empty()) warn_all({w});
}

SpeedRange speed_range(const std::tuple<double, double, int>& s) {
  const SpeedRange r{std::get<0>(s), std::get<1>(s), std::get<2>(s)};
  // The speeds here (the points may be the study's automatic 0, checked by the study): a speed no
  // spindle turns at refused, an unusual one said.
  for (const char* name : {"min_rpm", "max_rpm"}) {
    const OptionField<SpeedRange>& f = option_field(speed_range_fields(), name);
    check_field(f.spec, f.get(r), "SpeedRange");
  }
  warn_all(field_plausibility_warnings(speed_range_fields(), r, "SpeedRange"));
  return r;
}

py::object to_python(const nlohmann::json& j) {
  using T = nlohmann::json::value_t;
  switch (j.type()) {
    case T::boolean: return py::bool_(j.get<bool>());
    case T::number_integer: return py::int_(j.get<std::int64_t>());
    case T::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case T::number_float: return py::float_(j.get<double>());
    case T::string: return py::str(j.get_ref<const std::string&>());
    case T::array: {
      py::list l;
      for (const auto& e : j) l.append(to_python(e));
      return l;
    }
    case T::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = to_python(v);
      return d;
    }
    default: return py::none();
  }
}

ProgressCallback progress_of(const py::object& callback) {
  if (callback.is_none()) return {};
  if (!PyCallable_Check(callback.ptr()))
    throw InvalidArgument("progress must be a callable taking the fraction done (0…1) or None", "pass e.g. progress=print");
  // The callable is released with the GIL held, whichever thread drops the last copy.
  std::shared_ptr<py::object> held(new py::object(callback), [](py::object* o) {
    py::gil_scoped_acquire gil;
    delete o;
  });
  return [held](double fraction) {
    py::gil_scoped_acquire gil;
    try {
      (*held)(fraction);
    } catch (py::error_already_set& e) {
      e.discard_as_unraisable("toolpoint progress callback");
    }
  };
}

void warn_all(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings)
    if (PyErr_WarnEx(g_warning, w.c_str(), 2) < 0) throw py::error_already_set();
}

void bind_errors(py::module_& m) {
  g_error = new_class(m, "Error", PyExc_Exception,
                      "Base of every toolpoint error. str(e): what is wrong, with the values involved; e.hint: how to fix it "
                      "(also shown as a 'fix:' note in tracebacks).");
  PyObject_SetAttrString(g_error, "hint", py::str("").ptr());
  const py::tuple invalid_bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
  g_invalid =
      new_class(m, "InvalidArgument", invalid_bases.ptr(),
                "A parameter outside its valid range (a negative length, an even filter window, ...): the CLI's exit code 2. "
                "Also a ValueError.");
  g_input = new_class(m, "InputError", g_error,
                      "Malformed or inconsistent input data: a file that cannot be parsed, a missing key, NaN, mismatched grids, "
                      "an array of the wrong shape: exit code 3.");
  g_numerical = new_class(m, "NumericalError", g_error,
                          "A computation that cannot give a trustworthy answer (a singular inversion): exit code 4.");
  g_verdict = new_class(m, "VerdictFailure", g_error, "A result that was computed but fails its own checks: exit code 6.");
  g_io = new_class(m, "IoError", g_error, "A file that cannot be opened, read or written: exit code 5.");
  g_warning = new_class(m, "Warning", PyExc_UserWarning, "Warnings from toolpoint functions that return bare arrays.");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidArgument& e) {
      raise(g_invalid, e);
    } catch (const InputError& e) {
      raise(g_input, e);
    } catch (const NumericalError& e) {
      raise(g_numerical, e);
    } catch (const VerdictFailure& e) {
      raise(g_verdict, e);
    } catch (const IoError& e) {
      raise(g_io, e);
    } catch (const Error& e) {
      raise(g_error, e);
    }
  });
}

}  // namespace toolpoint::python

PYBIND11_MODULE(_toolpoint, m) {
  using namespace toolpoint::python;
  m.doc() =
      "toolpoint: tool point FRFs, joint identification and chatter stability (the C++ library's bindings; "
      "import toolpoint, not this module).";
  m.attr("__version__") = TOOLPOINT_VERSION;
  bind_errors(m);
  bind_model(m);
  bind_signal_io(m);
  bind_identify(m);
  bind_stability(m);
  bind_simulation(m);
  bind_pitch(m);
}
