// toolpoint: reading the assembly TOML file with toml++.
#include "toolpoint/io/assembly_file.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>

#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toml_reader.hpp"

namespace toolpoint {

namespace {

Material read_material(Reader& r, const toml::table& t, const std::string& path, const std::string& name) {
  r.only(t, path, {"youngs_modulus", "poisson", "shear_modulus", "density", "loss_factor"});
  Material m;
  m.name = name;
  m.youngs_modulus = r.required_number(t, "youngs_modulus", path, "Pa");
  m.density = r.required_number(t, "density", path, "kg/m^3");
  m.poisson = r.number(t, "poisson", path, "(dimensionless)").value_or(0.3);
  m.shear_modulus = r.number(t, "shear_modulus", path, "Pa").value_or(0.0);
  m.loss_factor = r.number(t, "loss_factor", path, "(dimensionless)").value_or(0.0);
  r.plausible(t, "youngs_modulus", path, m.youngs_modulus, plausible::kYoungsModulus);
  r.plausible(t, "density", path, m.density, plausible::kDensity);
  r.plausible(t, "shear_modulus", path, m.shear_modulus, plausible::kShearModulus);
  r.plausible(t, "loss_factor", path, m.loss_factor, plausible::kLossFactor);
  try {
    m.check();
  } catch (const InvalidArgument& e) {
    r.fail(t, e.what(), e.hint());
  }
  return m;
}

const Material& material_ref(Reader& r, const std::map<std::string, Material>& mats, const toml::table& t, const char* key,
                             const std::string& path, const Material* fallback) {
  auto name = r.string(t, key, path);
  if (!name) {
    if (fallback) return *fallback;
    r.fail(t, fmt::format("missing key {} (the name of a [materials.NAME] table)", Reader::join(path, key)));
  }
  auto it = mats.find(*name);
  if (it == mats.end()) {
    std::string list;
    for (const auto& [k, v] : mats) list += (list.empty() ? "" : ", ") + k;
    r.fail(*t.get(key), fmt::format("{} = \"{}\" names no material", Reader::join(path, key), *name),
           list.empty() ? "define it in a [materials.NAME] table" : "defined materials: " + list);
  }
  return it->second;
}

std::vector<Segment> read_segments(Reader& r, const toml::table& comp, const std::string& comp_path,
                                   const std::map<std::string, Material>& mats, const Material* default_mat) {
  const toml::node* n = comp.get("segment");
  if (!n) r.fail(comp, fmt::format("[{}] has no segments", comp_path), fmt::format("add [[{}.segment]] tables", comp_path));
  const toml::array* arr = n->as_array();
  if (!arr || !arr->is_array_of_tables())
    r.fail(*n, fmt::format("{}.segment must be an array of tables ([[{}.segment]])", comp_path, comp_path));
  std::vector<Segment> out;
  int i = 0;
  for (const toml::node& e : *arr) {
    ++i;
    const toml::table& t = *e.as_table();
    const std::string path = fmt::format("{}.segment[{}]", comp_path, i);
    r.only(t, path, {"length", "outer_diameter", "inner_diameter", "material", "shear_coefficient"});
    const Material& m = material_ref(r, mats, t, "material", path, default_mat);
    Segment s = Segment::tube(r.required_number(t, "length", path, "m"), r.required_number(t, "outer_diameter", path, "m"),
                              r.number(t, "inner_diameter", path, "m").value_or(0.0), m, path);
    s.layers[0].shear_coefficient = r.number(t, "shear_coefficient", path, "(dimensionless)");
    r.plausible(t, "length", path, s.length, plausible::kSegmentLength);
    r.plausible(t, "outer_diameter", path, s.layers[0].outer_diameter, plausible::kOuterDiameter);
    r.plausible(t, "inner_diameter", path, s.layers[0].inner_diameter, plausible::kInnerDiameter);
    try {
      s.check();
    } catch (const InvalidArgument& ex) {
      r.fail(t, ex.what(), ex.hint());
    }
    out.push_back(std::move(s));
  }
  return out;
}

// [analysis]: the frequency grid (FrequencyGrid defaults where a key is missing). False when the
// file has no [analysis] table (the caller says so in a note).
bool read_analysis(Reader& r, const toml::table& root, FrequencyGrid& grid) {
  const toml::table* t = r.table(root, "analysis", "", false);
  if (!t) return false;
  r.only(*t, "analysis", {"frequency_min", "frequency_max", "frequency_step", "points"});
  const double fmin = r.number(*t, "frequency_min", "analysis", "Hz").value_or(grid.start_hz);
  const double fmax = r.number(*t, "frequency_max", "analysis", "Hz").value_or(grid.stop_hz);
  auto step = r.number(*t, "frequency_step", "analysis", "Hz");
  auto points = r.number(*t, "points", "analysis", "(count)");
  if (step && points) r.fail(*t, "[analysis] gives both frequency_step and points: choose one");
  grid = {fmin, fmax, step ? *step : grid.step_hz};
  if (points) {
    if (*points < 2 || *points != std::floor(*points))
      r.fail(*t->get("points"), fmt::format("analysis.points = {} must be an integer ≥ 2", *points));
    grid.step_hz = (fmax - fmin) / (*points - 1.0);
  }
  try {
    grid.check();
  } catch (const InvalidArgument& e) {
    r.fail(*t, fmt::format("[analysis]: {}", e.what()), e.hint());
  }
  return true;
}

// [model]: the shear model, the receptance method and the number of modal terms.
void read_model(Reader& r, const toml::table& root, Assembly& a) {
  if (const toml::table* t = r.table(root, "model", "", false)) {
    r.only(*t, "model", {"shear_model", "method", "modal_terms"});
    if (auto s = r.string(*t, "shear_model", "model")) {
      if (*s == "hutchinson") a.shear_model = ShearModel::Hutchinson;
      else if (*s == "cowper") a.shear_model = ShearModel::Cowper;
      else r.fail(*t->get("shear_model"), fmt::format("model.shear_model = \"{}\": expected \"hutchinson\" or \"cowper\"", *s));
    }
    if (auto s = r.string(*t, "method", "model")) {
      if (*s == "exact") a.method = ReceptanceMethod::Exact;
      else if (*s == "modal") a.method = ReceptanceMethod::Modal;
      else r.fail(*t->get("method"), fmt::format("model.method = \"{}\": expected \"exact\" or \"modal\"", *s));
    }
    if (auto n = r.number(*t, "modal_terms", "model", "(count)")) {
      if (*n < 1 || *n > 20000 || *n != std::floor(*n))
        r.fail(*t->get("modal_terms"), fmt::format("model.modal_terms = {} must be an integer in 1..20000", *n),
               "100 is plenty below ~10 kHz");
      a.modal_terms = static_cast<int>(*n);
    }
  }
}

// [materials.NAME] tables, by name.
std::map<std::string, Material> read_materials(Reader& r, const toml::table& root) {
  std::map<std::string, Material> mats;
  if (const toml::table* t = r.table(root, "materials", "", true)) {
    for (auto&& [k, v] : *t) {
      const std::string name(k.str());
      if (!v.is_table()) r.fail(v, fmt::format("materials.{} must be a table ([materials.{}])", name, name));
      mats[name] = read_material(r, *v.as_table(), "materials." + name, name);
    }
  }
  return mats;
}

// [[spindle.bearing]]: each bearing with its y direction and speed table, within the spindle
// (`segments` give its length).
std::vector<Bearing> read_bearings(Reader& r, const toml::table& sp, const std::vector<Segment>& segments) {
  std::vector<Bearing> bearings;
  if (const toml::node* bn = sp.get("bearing")) {
    const toml::array* arr = bn->as_array();
    if (!arr || !arr->is_array_of_tables()) r.fail(*bn, "spindle.bearing must be an array of tables ([[spindle.bearing]])");
    double ls = 0.0;
    for (const auto& s : segments) ls += s.length;
    int i = 0;
    for (const toml::node& e : *arr) {
      ++i;
      const toml::table& t = *e.as_table();
      const std::string path = fmt::format("spindle.bearing[{}]", i);
      r.only(t, path,
             {"name", "position", "stiffness", "damping", "rotational_stiffness", "rotational_damping", "stiffness_y",
              "damping_y", "speed_rpm", "stiffness_at_speed", "damping_at_speed"});
      Bearing b;
      b.name = r.string(t, "name", path).value_or(path);
      if (b.name != path) b.name = fmt::format("{} ({})", path, b.name);
      b.position = r.required_number(t, "position", path, "m from the spindle nose");
      b.stiffness = r.required_number(t, "stiffness", path, "N/m");
      b.damping = r.number(t, "damping", path, "N s/m").value_or(0.0);
      b.rotational_stiffness = r.number(t, "rotational_stiffness", path, "N m/rad").value_or(0.0);
      b.rotational_damping = r.number(t, "rotational_damping", path, "N m s/rad").value_or(0.0);
      r.plausible(t, "stiffness", path, b.stiffness, plausible::kBearingStiffness);
      r.plausible(t, "damping", path, b.damping, plausible::kBearingDamping);
      // The y direction where it differs (anisotropic bearing; the two-plane model only).
      b.stiffness_y = r.number(t, "stiffness_y", path, "N/m");
      b.damping_y = r.number(t, "damping_y", path, "N s/m");
      if (b.stiffness_y) r.plausible(t, "stiffness_y", path, *b.stiffness_y, plausible::kBearingStiffness);
      if (b.damping_y) r.plausible(t, "damping_y", path, *b.damping_y, plausible::kBearingDamping);
      // The speed table: speed_rpm, stiffness_at_speed (and damping_at_speed, else the constant
      // damping) as arrays of one length.
      auto numbers = [&](const char* key, const char* unit) -> std::optional<std::vector<double>> {
        const toml::node* n = t.get(key);
        if (!n) return std::nullopt;
        const toml::array* values = n->as_array();
        if (!values || values->empty())
          r.fail(*n, fmt::format("{}.{} must be a non-empty array of numbers in {}", path, key, unit));
        std::vector<double> v;
        for (const toml::node& x : *values) {
          if (auto whole = x.as_integer()) v.push_back(static_cast<double>(whole->get()));
          else if (auto real = x.as_floating_point()) v.push_back(real->get());
          else r.fail(x, fmt::format("{}.{} holds a non-number; each entry is a number in {}", path, key, unit));
        }
        return v;
      };
      const auto speeds = numbers("speed_rpm", "rpm");
      const auto ks = numbers("stiffness_at_speed", "N/m");
      const auto cs = numbers("damping_at_speed", "N s/m");
      if (speeds || ks || cs) {
        if (!speeds || !ks)
          r.fail(t,
                 fmt::format("{}: a speed table needs both speed_rpm and stiffness_at_speed (damping_at_speed optional)", path));
        if (ks->size() != speeds->size() || (cs && cs->size() != speeds->size()))
          r.fail(*t.get("stiffness_at_speed"),
                 fmt::format("{}: speed_rpm has {} entries, stiffness_at_speed {}{}: they must be as many", path, speeds->size(),
                             ks->size(), cs ? fmt::format(", damping_at_speed {}", cs->size()) : std::string()));
        for (std::size_t k = 0; k < speeds->size(); ++k) {
          b.speed_table.push_back({(*speeds)[k], (*ks)[k], cs ? (*cs)[k] : b.damping});
          r.plausible(t, "stiffness_at_speed", path, (*ks)[k], plausible::kBearingStiffness);
          r.plausible(t, "speed_rpm", path, (*speeds)[k] == 0.0 ? 0.0 : (*speeds)[k], plausible::kSpindleSpeedRpm);
        }
      }
      try {
        b.check();
      } catch (const InvalidArgument& ex) {
        r.fail(t, ex.what(), ex.hint());
      }
      if (b.position > ls + 1e-9)
        r.fail(*t.get("position"),
               fmt::format("{}.position = {} m lies outside the spindle (0 to {} m from the nose)", path, b.position, ls),
               "positions are measured from the spindle nose, inwards, in metres");
      bearings.push_back(b);
    }
  }
  return bearings;
}

// [tool]: its dimensions and material, judged for plausibility; a tool held over less than its
// diameter is a warning.
Tool read_tool(Reader& r, const toml::table& root, const std::map<std::string, Material>& mats) {
  Tool tool;
  const toml::table& to = *r.table(root, "tool", "", true);
  r.only(to, "tool",
         {"material", "length", "overhang", "diameter", "shank_diameter", "flute_length", "flute_diameter_ratio",
          "shear_coefficient"});
  tool.material = material_ref(r, mats, to, "material", "tool", nullptr);
  tool.length = r.required_number(to, "length", "tool", "m");
  tool.overhang = r.required_number(to, "overhang", "tool", "m");
  tool.diameter = r.required_number(to, "diameter", "tool", "m");
  tool.shank_diameter = r.number(to, "shank_diameter", "tool", "m").value_or(0.0);
  tool.flute_length = r.number(to, "flute_length", "tool", "m").value_or(0.0);
  tool.flute_diameter_ratio = r.number(to, "flute_diameter_ratio", "tool", "(dimensionless)").value_or(0.8);
  tool.shear_coefficient = r.number(to, "shear_coefficient", "tool", "(dimensionless)");
  r.plausible(to, "length", "tool", tool.length, plausible::kToolLength);
  r.plausible(to, "overhang", "tool", tool.overhang, plausible::kOverhang);
  r.plausible(to, "diameter", "tool", tool.diameter, plausible::kToolDiameter);
  // Held over less than its diameter (0 when the overhang is the whole length): no holder grips a
  // tool so, so a length or an overhang is most likely mistyped.
  if (const double held = tool.length - tool.overhang; held >= 0.0 && held < tool.diameter && to.get("overhang"))
    r.warnings.push_back(
        fmt::format("{}: the tool is held over {:.4g} mm (tool.length {} m − tool.overhang {} m), less than its "
                    "diameter {:.4g} mm: check both",
                    r.where(*to.get("overhang")), 1e3 * held, tool.length, tool.overhang, 1e3 * tool.diameter));
  return tool;
}

}  // namespace

LoadedAssembly parse_assembly(const std::string& text, const std::string& source) {
  const toml::table root = parse_toml(text, source, "see examples/bt40_shrinkfit_16mm.toml for the file format");
  Reader r(source);
  r.only(root, "", {"assembly", "analysis", "model", "materials", "spindle", "holder", "tool", "joints"});
  Assembly a;

  if (const toml::table* t = r.table(root, "assembly", "", false)) {
    r.only(*t, "assembly", {"name", "description"});
    a.name = r.string(*t, "name", "assembly").value_or("");
  }

  const bool has_analysis = read_analysis(r, root, a.grid);

  read_model(r, root, a);

  const std::map<std::string, Material> mats = read_materials(r, root);

  const toml::table& sp = *r.table(root, "spindle", "", true);
  r.only(sp, "spindle", {"material", "segment", "bearing"});
  const Material* sp_mat = sp.get("material") ? &material_ref(r, mats, sp, "material", "spindle", nullptr) : nullptr;
  a.spindle.segments = read_segments(r, sp, "spindle", mats, sp_mat);
  a.spindle.bearings = read_bearings(r, sp, a.spindle.segments);

  const toml::table& ho = *r.table(root, "holder", "", true);
  r.only(ho, "holder", {"material", "segment"});
  const Material* ho_mat = ho.get("material") ? &material_ref(r, mats, ho, "material", "holder", nullptr) : nullptr;
  a.holder = read_segments(r, ho, "holder", mats, ho_mat);

  a.tool = read_tool(r, root, mats);

  if (const toml::table* t = r.table(root, "joints", "", false)) {
    r.only(*t, "joints", {"spindle_holder", "holder_tool"});
    a.spindle_holder = read_joint_table(r, r.table(*t, "spindle_holder", "joints", false), "joints.spindle_holder");
    a.holder_tool = read_joint_table(r, r.table(*t, "holder_tool", "joints", false), "joints.holder_tool");
  }

  try {
    a.check();
  } catch (const InvalidArgument& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()), e.hint());
  }
  std::vector<std::string> notes;
  if (!has_analysis)  // a default that changes every result: said once, never silent
    notes.push_back(fmt::format("{}: no [analysis] table: the default grid {:g}–{:g} Hz in steps of {:g} Hz is used", source,
                                a.grid.start_hz, a.grid.stop_hz, a.grid.step_hz));
  for (const auto& [joint, key] : {std::pair{&a.spindle_holder, "spindle_holder"}, std::pair{&a.holder_tool, "holder_tool"}})
    if (!joint->rigid)
      for (auto& n : joint_warnings(joint->parameters, assembly_joint_name(source, key))) notes.push_back(std::move(n));
  return {std::move(a), std::move(r.warnings), std::move(notes), source};
}

std::string assembly_joint_name(const std::string& source, const std::string& key) {
  return fmt::format("{}: joints.{}", source, key);
}

LoadedAssembly load_assembly(const std::string& path) { return parse_assembly(read_text_file(path), path); }

}  // namespace toolpoint
