// toolpoint: joint files (joint_file.hpp).
#include "toolpoint/io/joint_file.hpp"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "toolpoint/io/io.hpp"
#include "toml_reader.hpp"

namespace toolpoint {

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

template <class T>
std::string array_of(const std::array<T, 8>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < 8; ++i) s += fmt::format("{}{}", i ? ", " : "", v[i]);
  return s + "]";
}

}  // namespace

std::string format_joint_file(const JointFile& f) {
  std::string s = "# toolpoint joint file (SI units). Use it with e.g. `toolpoint predict A.toml --joint " +
                  std::string(f.interface == JointInterface::HolderTool ? "holder-tool" : "spindle-holder") + "=THIS.toml`.\n";
  s += "[joint]\n";
  s += fmt::format("interface = \"{}\"\n", to_string(f.interface));
  for (int k = 0; k < 8; ++k)
    s += fmt::format("{} = {}    # {}\n", JointParameters::name(k), f.parameters[k], JointParameters::unit(k));
  if (f.uncertainty) {
    const JointUncertainty& u = *f.uncertainty;
    s += "\n# Order of every list: k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm.\n[uncertainty]\n";
    s += fmt::format("confidence = {}\n", u.confidence);
    s += "lower = " + array_of(u.lower) + "\n";
    s += "upper = " + array_of(u.upper) + "\n";
    std::array<std::string, 8> det;
    for (std::size_t i = 0; i < 8; ++i) det[i] = u.determined[i] ? "true" : "false";
    s += "determined = " + array_of(det) + "\n";
    s += "covariance = [\n";
    for (int i = 0; i < 8; ++i) {
      std::array<double, 8> row{};
      for (int j = 0; j < 8; ++j) row[static_cast<std::size_t>(j)] = u.covariance(i, j);
      s += "  " + array_of(row) + (i < 7 ? ",\n" : "\n");
    }
    s += "]\n";
  }
  if (!f.identification.empty()) {
    s += "\n[identification]\n";
    for (const auto& [k, v] : f.identification) s += fmt::format("{} = {}\n", k, quoted(v));
  }
  return s;
}

void write_joint_file(const std::string& path, const JointFile& f) { write_text_file(path, format_joint_file(f)); }

JointFile parse_joint_file(const std::string& text, const std::string& source) {
  const toml::table root = parse_toml(text, source, "a joint file is written by write_joint_file");
  Reader r(source);
  r.only(root, "", {"joint", "uncertainty", "identification"});
  JointFile f;
  f.source = source;
  const toml::table* jt = r.table(root, "joint", "", true);
  const auto iface = r.string(*jt, "interface", "joint");
  if (!iface) r.fail(*jt, "missing key joint.interface (\"holder_tool\" or \"spindle_holder\")");
  if (*iface == "holder_tool") f.interface = JointInterface::HolderTool;
  else if (*iface == "spindle_holder") f.interface = JointInterface::SpindleHolder;
  else
    r.fail(*jt->get("interface"),
           fmt::format("joint.interface = \"{}\": expected \"holder_tool\" or \"spindle_holder\"", *iface));
  f.parameters = read_joint_table(r, jt, "joint", true).parameters;

  if (const toml::table* ut = r.table(root, "uncertainty", "", false)) {
    r.only(*ut, "uncertainty", {"confidence", "lower", "upper", "determined", "covariance"});
    JointUncertainty u;
    u.confidence = r.number(*ut, "confidence", "uncertainty", "(fraction)").value_or(0.95);
    if (!(u.confidence > 0.0 && u.confidence < 1.0))
      r.fail(*ut->get("confidence"), fmt::format("uncertainty.confidence = {} must lie in (0, 1)", u.confidence));
    auto list = [&](const char* key, auto& out, auto convert) {
      const toml::node* n = ut->get(key);
      if (!n) return;
      const toml::array* a = n->as_array();
      if (!a || a->size() != 8) r.fail(*n, fmt::format("uncertainty.{} must be a list of 8 values (k_yf … c_tm)", key));
      for (std::size_t i = 0; i < 8; ++i) out[i] = convert(*a->get(i), fmt::format("uncertainty.{}[{}]", key, i));
    };
    auto number = [&](const toml::node& n, const std::string& what) {
      std::optional<double> v;
      if (auto i = n.as_integer()) v = static_cast<double>(i->get());
      if (auto x = n.as_floating_point()) v = x->get();
      if (!v || !std::isfinite(*v)) r.fail(n, fmt::format("{} must be a finite number", what));
      return *v;
    };
    list("lower", u.lower, number);
    list("upper", u.upper, number);
    list("determined", u.determined, [&](const toml::node& n, const std::string& what) {
      if (!n.is_boolean()) r.fail(n, fmt::format("{} must be true or false", what));
      return n.as_boolean()->get();
    });
    if (const toml::node* n = ut->get("covariance")) {
      const toml::array* rows = n->as_array();
      if (!rows || rows->size() != 8) r.fail(*n, "uncertainty.covariance must be 8 rows of 8 numbers (k_yf … c_tm, SI units)");
      for (std::size_t i = 0; i < 8; ++i) {
        const toml::array* row = rows->get(i)->as_array();
        if (!row || row->size() != 8)
          r.fail(*rows->get(i), fmt::format("uncertainty.covariance row {} must hold 8 numbers", i + 1));
        for (std::size_t k = 0; k < 8; ++k)
          u.covariance(static_cast<int>(i), static_cast<int>(k)) = number(*row->get(k),
                                                                          fmt::format("uncertainty.covariance[{}][{}]", i, k));
      }
      if ((u.covariance.diagonal().array() < 0.0).any()) r.fail(*n, "uncertainty.covariance has a negative variance");
      const double scale = u.covariance.diagonal().cwiseAbs().maxCoeff();
      for (int i = 0; i < 8; ++i)
        for (int k = 0; k < i; ++k)
          if (std::abs(u.covariance(i, k) - u.covariance(k, i)) >
              1e-9 * std::sqrt(std::abs(u.covariance(i, i) * u.covariance(k, k))) + 1e-300)
            r.fail(*n, fmt::format("uncertainty.covariance is not symmetric (row {}, column {})", i + 1, k + 1));
      // Positive semidefinite to rounding, judged on the correlation matrix (entries differ by
      // many orders of magnitude in SI units).
      Eigen::Matrix<double, 8, 8> c = u.covariance;
      for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 8; ++k) {
          const double d = std::sqrt(u.covariance(i, i) * u.covariance(k, k));
          c(i, k) = d > 0.0 ? u.covariance(i, k) / d : (i == k ? 1.0 : 0.0);
        }
      if (scale > 0.0 && Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 8, 8>>(c).eigenvalues()(0) < -1e-6)
        r.fail(*n, "uncertainty.covariance is not positive semidefinite: not a covariance");
    }
    f.uncertainty = u;
  }
  if (const toml::table* it = r.table(root, "identification", "", false)) {
    for (auto&& [k, v] : *it) {
      std::string value;
      if (auto s = v.as_string()) value = s->get();
      else if (auto i = v.as_integer()) value = fmt::format("{}", i->get());
      else if (auto x = v.as_floating_point()) value = fmt::format("{}", x->get());
      else if (auto b = v.as_boolean()) value = b->get() ? "true" : "false";
      else r.fail(v, fmt::format("identification.{} must be a string or a number", k.str()));
      f.identification.emplace_back(std::string(k.str()), value);
    }
  }
  return f;
}

JointFile load_joint_file(const std::string& path) { return parse_joint_file(read_text_file(path), path); }

LoadedAssembly with_joint(LoadedAssembly loaded, const JointFile& file) {
  const std::string replaced = assembly_joint_name(loaded.source, to_string(file.interface)) + ": ";
  std::erase_if(loaded.notes, [&](const std::string& n) { return n.starts_with(replaced); });
  for (std::string& n :
       joint_warnings(file.parameters, fmt::format("{} (the {} joint in use)", file.source, to_string(file.interface))))
    loaded.notes.push_back(std::move(n));
  loaded.assembly = with_joint(loaded.assembly, file);
  return loaded;
}

}  // namespace toolpoint
