// toolpoint Python bindings: milling simulated in the time domain (simulation.hpp,
// studies/simulation.hpp): one cut, the stability map and its shards. SI units (depths, feeds,
// diameters in m, angles in rad), spindle speeds in rpm, frequencies in Hz; histories as arrays.
#include "common.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/studies/simulation.hpp"
#include "toolpoint/studies/simulation_io.hpp"

namespace toolpoint::python {

namespace {

using namespace pybind11::literals;

// The cutter and the force law from keyword arguments (CuttingConditions gives N, K_t, K_r).
Cutter cutter_of(const CuttingConditions& c, double diameter_m, const std::optional<std::vector<double>>& pitch_rad,
                 double helix_rad, const std::optional<std::vector<double>>& runout_m, double flute_length_m) {
  Cutter cu = uniform_cutter(c.teeth, diameter_m);
  if (pitch_rad) cu.pitch_rad = *pitch_rad;
  cu.helix_rad = helix_rad;
  // The cutting conditions' helix (one angle, or one per tooth), unless the keyword gives one.
  if (!c.helix_rad.empty()) {
    if (helix_rad != 0.0)
      throw InvalidArgument("simulate_milling: helix_rad given twice (the keyword and CuttingConditions::helix_rad)",
                            "give it once");
    if (c.helix_rad.size() == 1) cu.helix_rad = c.helix_rad.front();
    else cu.tooth_helix_rad = c.helix_rad;
  }
  if (runout_m) cu.runout_m = *runout_m;
  cu.flute_length_m = flute_length_m;
  return cu;
}

ForceLaw law_of(const CuttingConditions& c, double kte, double kre, double exponent, double h0) {
  ForceLaw f = linear_force_law(c);
  f.tangential_edge = kte;
  f.radial_edge = kre;
  f.exponent = exponent;
  f.reference_chip_m = h0;
  return f;
}

SimulationOptions options_of(int revolutions, int steps_per_tooth, int slices, double analysed_fraction, bool record,
                             int memory_revolutions, const std::optional<std::vector<double>>& initial_state) {
  SimulationOptions o;
  o.revolutions = revolutions;
  o.steps_per_tooth = steps_per_tooth;
  o.slices = slices;
  o.analysed_fraction = analysed_fraction;
  o.record = record;
  o.memory_revolutions = memory_revolutions;
  if (initial_state) o.initial_state = *initial_state;
  return o;
}

SimulationInput input_of(const std::vector<Mode>& x_modes, const std::vector<Mode>& y_modes, const std::vector<PlanarMode>& modes,
                         bool rigid_y, bool rigid) {
  SimulationInput in;
  in.source.x_modes = x_modes;
  in.source.y_modes = y_modes;
  in.source.rigid_y = rigid_y;
  in.planar_modes = modes;
  in.rigid = rigid;
  return in;
}

py::dict samples_dict(const std::vector<MotionSample>& s) {
  std::vector<double> t, x, y, vx, vy;
  py::array_t<int> tooth(static_cast<py::ssize_t>(s.size()));
  for (std::size_t i = 0; i < s.size(); ++i) {
    t.push_back(s[i].time_s);
    x.push_back(s[i].x_m);
    y.push_back(s[i].y_m);
    vx.push_back(s[i].vx_m_per_s);
    vy.push_back(s[i].vy_m_per_s);
    tooth.mutable_at(static_cast<py::ssize_t>(i)) = s[i].tooth;
  }
  return py::dict("time_s"_a = array_of(t), "x_m"_a = array_of(x), "y_m"_a = array_of(y), "vx_m_per_s"_a = array_of(vx),
                  "vy_m_per_s"_a = array_of(vy), "tooth"_a = tooth);
}

// Columns of an io.hpp Table as a dict of arrays.
py::dict table_dict(const Table& t) {
  py::dict d;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    std::vector<double> col;
    col.reserve(t.rows.size());
    for (const auto& row : t.rows) col.push_back(row[c]);
    d[py::str(t.columns[c])] = array_of(col);
  }
  return d;
}

SimulatedMapOptions map_options(const CuttingConditions& cutting, const std::tuple<double, double, int>& speeds,
                                const std::tuple<double, double, int>& depths, double feed, double diameter_m,
                                const std::optional<std::vector<double>>& pitch_rad, double helix_rad,
                                const std::optional<std::vector<double>>& runout_m, double flute_length_m, double kte, double kre,
                                double exponent, double h0, int revolutions, int steps_per_tooth, int slices,
                                double analysed_fraction, int memory_revolutions, int threads) {
  SimulatedMapOptions o;
  o.cutter = cutter_of(cutting, diameter_m, pitch_rad, helix_rad, runout_m, flute_length_m);
  o.force = law_of(cutting, kte, kre, exponent, h0);
  o.cut.engagement = cutting.engagement;
  o.cut.feed_per_tooth_m = feed;
  o.speeds = speed_range(speeds);
  o.depths = {std::get<0>(depths), std::get<1>(depths), std::get<2>(depths)};
  o.simulation = options_of(revolutions, steps_per_tooth, slices, analysed_fraction, false, memory_revolutions, std::nullopt);
  o.parallel.threads = threads;
  return o;
}

// One simulated cut: planar modes, simulate_milling and its result.
void bind_simulated_cut(py::module_& m) {
  py::class_<PlanarMode>(m, "PlanarMode",
                         "A mode of the tool point in the x-y plane: frequency [Hz], damping ratio, mass-normalised shape "
                         "(shape_x, shape_y) [kg^-1/2].")
      .def(py::init([](double f, double z, double sx, double sy) {
             PlanarMode p{f, z, sx, sy};
             p.check();
             return p;
           }),
           "frequency_hz"_a, "damping_ratio"_a, "shape_x"_a, "shape_y"_a)
      .def_readonly("frequency_hz", &PlanarMode::frequency_hz)
      .def_readonly("damping_ratio", &PlanarMode::damping_ratio)
      .def_readonly("shape_x", &PlanarMode::shape_x)
      .def_readonly("shape_y", &PlanarMode::shape_y)
      .def(
          "to_dict", [](const PlanarMode& p) { return dict_of(p); }, "The mode as plain data (the CLI's --json keys, SI units).");
  m.def("planar_mode", &planar_mode, "mode"_a, "direction_rad"_a,
        "A 1-DOF mode (modal mass m) acting along the direction at direction_rad from +x towards +y: shape (cos, sin)/sqrt(m).");

  py::class_<SimulationStudyResult>(m, "SimulationResult", "One simulated cut (toolpoint simulate): summary, histories, samples.")
      .def_property_readonly("stable", [](const SimulationStudyResult& r) { return r.simulation.stable; })
      .def_property_readonly("diverged", [](const SimulationStudyResult& r) { return r.simulation.diverged; })
      .def_property_readonly(
          "growth", [](const SimulationStudyResult& r) { return r.simulation.growth; },
          "per-revolution growth of the once-per-period deviation (< 1 decays)")
      .def_property_readonly("chatter_metric", [](const SimulationStudyResult& r) { return r.simulation.chatter_metric; })
      .def_property_readonly("chatter_hz", [](const SimulationStudyResult& r) { return r.simulation.chatter_hz; })
      .def_property_readonly(
          "sle_m", [](const SimulationStudyResult& r) { return r.simulation.sle_m; },
          "surface location error of the first wall [m] (+: material left)")
      .def_property_readonly("mean_force_n",
                             [](const SimulationStudyResult& r) {
                               return py::make_tuple(r.simulation.mean_force_x_n, r.simulation.mean_force_y_n);
                             })
      .def_property_readonly("power_w", [](const SimulationStudyResult& r) { return r.simulation.power_w; })
      .def_property_readonly("mean_torque_nm", [](const SimulationStudyResult& r) { return r.simulation.mean_torque_nm; })
      .def_property_readonly("step_s", [](const SimulationStudyResult& r) { return r.simulation.step_s; })
      .def_property_readonly("steps_per_tooth", [](const SimulationStudyResult& r) { return r.simulation.steps_per_tooth; })
      .def_property_readonly(
          "history",
          [](const SimulationStudyResult& r) {
            return r.simulation.time_s.empty() ? py::dict() : table_dict(simulation_history_table(r.simulation));
          },
          "every step: {'time_s', 'force_x_n', 'force_y_n', 'x_m', 'y_m', 'vx_m_per_s', 'vy_m_per_s', 'torque_nm', "
          "'tooth_<j>_force_n'} arrays (empty without record)")
      .def_property_readonly("per_revolution",
                             [](const SimulationStudyResult& r) { return samples_dict(r.simulation.per_revolution); })
      .def_property_readonly("per_tooth", [](const SimulationStudyResult& r) { return samples_dict(r.simulation.per_tooth); })
      .def_property_readonly("walls", [](const SimulationStudyResult& r) { return dict_of(r.simulation.walls); })
      .def_readonly("warnings", &SimulationStudyResult::warnings)
      .def(
          "to_dict", [](const SimulationStudyResult& r) { return dict_of(r); },
          "The result as plain data (the CLI's --json keys, SI units).");

  m.def(
      "simulate_milling",
      [](const CuttingConditions& cutting, double speed_rpm, double depth_m, double feed_per_tooth_m, double diameter_m,
         const std::vector<Mode>& x_modes, const std::vector<Mode>& y_modes, const std::vector<PlanarMode>& modes, bool rigid_y,
         bool rigid, const std::optional<std::vector<double>>& pitch_rad, double helix_rad,
         const std::optional<std::vector<double>>& runout_m, double flute_length_m, double kte, double kre, double exponent,
         double h0, int revolutions, int steps_per_tooth, int slices, double analysed_fraction, bool record,
         int memory_revolutions, const std::optional<std::vector<double>>& initial_state, const py::object& progress) {
        SimulationStudyOptions o;
        o.cutter = cutter_of(cutting, diameter_m, pitch_rad, helix_rad, runout_m, flute_length_m);
        o.force = law_of(cutting, kte, kre, exponent, h0);
        o.cut = {speed_rpm, depth_m, feed_per_tooth_m, cutting.engagement};
        o.simulation = options_of(revolutions, steps_per_tooth, slices, analysed_fraction, record, memory_revolutions,
                                  initial_state);
        const SimulationInput in = input_of(x_modes, y_modes, modes, rigid_y, rigid);
        const ProgressCallback report = progress_of(progress);
        SimulationStudyResult r;
        {
          py::gil_scoped_release nogil;
          r = run_simulation_study(in, o, report);
        }
        warn_all(r.warnings);
        return r;
      },
      "cutting"_a, "speed_rpm"_a, "depth_m"_a, "feed_per_tooth_m"_a, "diameter_m"_a, "x_modes"_a = std::vector<Mode>{},
      "y_modes"_a = std::vector<Mode>{}, "modes"_a = std::vector<PlanarMode>{}, "rigid_y"_a = false, "rigid"_a = false,
      "pitch_rad"_a = py::none(), "helix_rad"_a = 0.0, "runout_m"_a = py::none(), "flute_length_m"_a = 0.0,
      "tangential_edge"_a = 0.0, "radial_edge"_a = 0.0, "exponent"_a = 1.0, "reference_chip_m"_a = 1e-4, "revolutions"_a = 40,
      "steps_per_tooth"_a = 0, "slices"_a = 0, "analysed_fraction"_a = 0.5, "record"_a = true, "memory_revolutions"_a = 1,
      "initial_state"_a = py::none(), "progress"_a = py::none(),
      fields_doc(simulation_fields(), "SimulationOptions", "toolpoint simulate",
                 "One cut in the time domain (toolpoint simulate): the teeth, K_t, K_r and the engagement from `cutting` "
                 "(pitch_rad overrides the even spacing), the dynamics from x_modes/y_modes (y_modes empty: the x modes, "
                 "unless rigid_y) and planar modes, or a rigid tool. Returns a SimulationResult."));
}

// The simulated stability map over speed × depth, its parts and their merge.
void bind_simulated_map(py::module_& m) {
  py::class_<SimulatedMap>(m, "SimulatedMap", "A simulated stability map (toolpoint simulate map).")
      .def_property_readonly(
          "table", [](const SimulatedMap& s) { return table_dict(simulated_map_table(s)); },
          "per speed and depth: {'spindle_speed_rpm', 'axial_depth_mm', 'stable', 'growth_per_revolution', 'chatter_metric', "
          "'chatter_frequency_hz', 'sle_um', 'peak_force_n', 'out_of_cut_fraction'} arrays (map.csv's columns)")
      .def_property_readonly(
          "boundary",
          [](const SimulatedMap& s) {
            std::vector<double> n, d, f;
            for (const EnvelopePoint& e : s.boundary) {
              n.push_back(e.speed_rpm);
              d.push_back(e.depth_m);
              f.push_back(e.chatter_hz);
            }
            return py::dict("speed_rpm"_a = array_of(n), "depth_m"_a = array_of(d), "chatter_hz"_a = array_of(f));
          },
          "the lowest unstable depth per speed (inf where none)")
      .def_readonly("warnings", &SimulatedMap::warnings)
      .def(
          "to_dict", [](const SimulatedMap& s) { return dict_of(s); },
          "The map's summary as plain data (the CLI's --json keys, SI units); the cells are in `table`.");

  m.def(
      "simulated_map",
      [](const CuttingConditions& cutting, const std::tuple<double, double, int>& speeds,
         const std::tuple<double, double, int>& depths, double feed, double diameter_m, const std::vector<Mode>& x_modes,
         const std::vector<Mode>& y_modes, const std::vector<PlanarMode>& modes, bool rigid_y,
         const std::optional<std::vector<double>>& pitch_rad, double helix_rad,
         const std::optional<std::vector<double>>& runout_m, double flute_length_m, double kte, double kre, double exponent,
         double h0, int revolutions, int steps_per_tooth, int slices, double analysed_fraction, int memory_revolutions,
         int threads, std::optional<std::pair<int, int>> shard, const py::object& progress) -> py::object {
        const SimulatedMapOptions o = map_options(cutting, speeds, depths, feed, diameter_m, pitch_rad, helix_rad, runout_m,
                                                  flute_length_m, kte, kre, exponent, h0, revolutions, steps_per_tooth, slices,
                                                  analysed_fraction, memory_revolutions, threads);
        std::vector<ModalFitSummary> fits;
        std::vector<std::string> warnings;
        const ToolDynamics d = simulation_dynamics(input_of(x_modes, y_modes, modes, rigid_y, false), simulation_fit_options(),
                                                   0.02, fits, warnings);
        const ProgressCallback report = progress_of(progress);
        if (shard) {
          std::string text;
          {
            py::gil_scoped_release nogil;
            text = format_simulated_map_part(run_simulated_map_part(d, o, shard->first, shard->second, report));
          }
          return py::str(text);
        }
        SimulatedMap r;
        {
          py::gil_scoped_release nogil;
          r = run_simulated_map(d, o, report);
        }
        warn_all(r.warnings);
        return py::cast(std::move(r));
      },
      "cutting"_a, "speeds"_a, "depths_m"_a, "feed_per_tooth_m"_a, "diameter_m"_a, "x_modes"_a = std::vector<Mode>{},
      "y_modes"_a = std::vector<Mode>{}, "modes"_a = std::vector<PlanarMode>{}, "rigid_y"_a = false, "pitch_rad"_a = py::none(),
      "helix_rad"_a = 0.0, "runout_m"_a = py::none(), "flute_length_m"_a = 0.0, "tangential_edge"_a = 0.0, "radial_edge"_a = 0.0,
      "exponent"_a = 1.0, "reference_chip_m"_a = 1e-4, "revolutions"_a = 40, "steps_per_tooth"_a = 0, "slices"_a = 0,
      "analysed_fraction"_a = 0.5, "memory_revolutions"_a = 1, "threads"_a = 0, "shard"_a = py::none(), "progress"_a = py::none(),
      "The simulated stability map over speeds (min_rpm, max_rpm, points) x depths_m (min, max, points) (toolpoint simulate "
      "map). With shard=(index, count): that shard's part file text (JSON, exact), for merge_simulated_map_parts.");
  m.def(
      "merge_simulated_map_parts",
      [](const std::vector<std::string>& texts, const std::vector<std::string>& names) {
        std::vector<SimulatedMapPart> parts;
        for (std::size_t i = 0; i < texts.size(); ++i)
          parts.push_back(parse_simulated_map_part(texts[i], i < names.size() ? names[i] : fmt::format("part {}", i + 1)));
        SimulatedMap r = merge_simulated_map_parts(parts, names);
        warn_all(r.warnings);
        return r;
      },
      "texts"_a, "names"_a = std::vector<std::string>{},
      "The map from its parts' texts (any order): the same as the unsharded map, bit for bit (toolpoint simulate merge).");
}

}  // namespace

void bind_simulation(py::module_& m) {
  bind_simulated_cut(m);
  bind_simulated_map(m);
}

}  // namespace toolpoint::python
