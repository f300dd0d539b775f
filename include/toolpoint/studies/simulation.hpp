// toolpoint study: milling simulated in the time domain — the procedure behind `toolpoint simulate`
// (one cut: forces, vibration, the wall and its SLE, chatter) and `toolpoint simulate map` (stable
// or not, and the SLE, over spindle speed × depth, on every core or in shards for a batch engine),
// as library calls. The model and the scheme: simulation.hpp.
//
// Units: SI (m, N, s, W, N·m), spindle speeds in rpm, frequencies in Hz.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "toolpoint/parallel.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/lobes.hpp"
#include "toolpoint/studies/shards.hpp"
#include "toolpoint/studies/study.hpp"

namespace toolpoint {

// Where the tool point dynamics come from: the time-domain modes of the lobes study (modes given,
// or fitted to measured FRFs or to an assembly's tool point FRF: time_domain_modes), and/or planar
// modes given with their shapes (x–y coupled), or a rigid tool.
struct SimulationInput {
  LobesInput source;                     // empty (no FRF, assembly or modes): only the planar modes
  std::vector<PlanarMode> planar_modes;  // added to the source's
  bool rigid = false;                    // no modes at all (nothing else may be given)
};

// The modes the simulation uses, the fits' summaries and the warnings. With measured cross FRFs
// (G_xy and G_yx) and the modes fitted: an x mode and a y mode at the same frequency (within the
// half-power band) whose cross FRF at resonance is at least half of √|G_xx G_yy| are one mode
// coupling x and y, ψ = (1/√m_x, ±1/√m_y), the sign from Im G_xy (said in a warning). Throws
// InvalidArgument (nothing given, rigid with modes), InputError (bad FRFs), NumericalError (a fit).
ToolDynamics simulation_dynamics(const SimulationInput& input, const ModalFitOptions& fit, double fit_target,
                                 std::vector<ModalFitSummary>& fits, std::vector<std::string>& warnings);

// Modal fits as the lobes study makes them: at most 8 modes per FRF, the fewest within 2 %.
ModalFitOptions simulation_fit_options();

struct SimulationStudyOptions {
  Cutter cutter;
  ForceLaw force;
  MillingCut cut;
  SimulationOptions simulation;
  ModalFitOptions fit = simulation_fit_options();
  double fit_target = 0.02;
  // Throws InvalidArgument naming the field (simulation_study_fields' ranges after the nested
  // options' checks).
  void check() const;
};

/// \brief SimulationStudyOptions' own scalar fields defined once (option_fields.hpp): fit.max_modes
/// and fit_target, the lobes study's fields (fitted_modes_field: range, unit, help,
/// flag); check() derives from it, and `toolpoint simulate`'s `--max-modes` and `--fit-target` are
/// the lobes study's flags.
/// \return the table, in the order of the fields
const std::vector<OptionField<SimulationStudyOptions>>& simulation_study_fields();

struct SimulationStudyResult {
  ToolDynamics dynamics;
  std::vector<ModalFitSummary> fits;
  Cutter cutter;
  ForceLaw force;
  MillingCut cut;
  SimulationResult simulation;
  std::vector<std::string> warnings;
};

// One cut. Progress: per revolution.
SimulationStudyResult run_simulation_study(const SimulationInput& input, const SimulationStudyOptions& options,
                                           const ProgressCallback& progress = {});

// ---- Figures (plot.hpp): displacement in µm, force in N, time in ms, feed position in mm ---------

// Forces and displacements over the last (up to 5) revolutions, and the once-per-tooth samples.
plot::Figure simulation_time_figure(const SimulationStudyResult& r);
// The tool's path in the x–y plane over the analysed revolutions with the once-per-revolution and
// once-per-tooth samples (the Poincaré section: one point for a periodic cut, a cloud or ring for chatter).
plot::Figure simulation_poincare_figure(const SimulationStudyResult& r);
// The amplitude spectrum of the displacement over the analysed revolutions (Hann window), the
// tooth-passing harmonics and the chatter frequency marked.
plot::Figure simulation_spectrum_figure(const SimulationStudyResult& r);
// The wall's profile along the feed (material left, +: undercut) at the bottom, middle and top
// slices over the analysed revolutions. Throws InvalidArgument when the cut leaves no wall or no
// histories were recorded.
plot::Figure simulation_surface_figure(const SimulationStudyResult& r);

// ---- The simulated stability map ---------------------------------------------------------------

// An evenly spaced grid of depths MIN…MAX [m], both ends included.
struct DepthRange {
  double min_m = 0.0, max_m = 0.0;
  int points = 100;
  // Throws InvalidArgument naming `DepthRange::<field>`: the ranges of depth_range_fields() (a depth
  // in mm refused as cannot be meant), then MIN < MAX.
  void check() const;
  std::vector<double> values() const;
};
// DepthRange's fields (option_fields.hpp): min_m, max_m (simulate map --depth MIN:MAX [mm], parsed
// beside) and points (--depths).
const std::vector<OptionField<DepthRange>>& depth_range_fields();

struct SimulatedMapOptions {
  Cutter cutter;
  ForceLaw force;
  MillingCut cut;                // its engagement and feed; the speed and depth are the grid's
  SimulationOptions simulation;  // per cell; histories are not recorded
  SpeedRange speeds{0.0, 0.0, 200};
  DepthRange depths;
  ParallelOptions parallel;  // cells on this many threads; results identical for any count
  void check() const;        // throws InvalidArgument naming the field
};

// Everything a map's results depend on (what a part file carries).
struct SimulatedMapHeader {
  ToolDynamics dynamics;
  SimulatedMapOptions options;
  std::vector<double> speeds_rpm, depths_m;
  std::uint64_t fingerprint = 0;  // simulated_map_fingerprint
};

// One spindle speed of the map (a job): per depth, the simulation's summary.
struct SimulatedMapRow {
  std::size_t speed_index = 0;
  std::vector<int> stable;  // 1 stable, 0 chatter
  std::vector<double> growth, chatter_metric, chatter_hz, sle_m, peak_force_n, out_of_cut_fraction;
};

struct SimulatedMap {
  SimulatedMapHeader header;
  std::vector<SimulatedMapRow> rows;  // by speed
  // Per speed the lowest depth of the grid judged unstable (+inf when none; chatter_hz there).
  std::vector<EnvelopePoint> boundary;
  std::vector<std::string> warnings;
};

// A shard: the speeds i with i mod count = index (studies/shards.hpp: counted from 0).
struct SimulatedMapPart {
  SimulatedMapHeader header;
  int index = 0, count = 1;
  std::vector<SimulatedMapRow> rows;  // in speed order
  // What the map was computed from, as its caller names it ("" unknown; `toolpoint simulate map`
  // keeps its options): kept in the part file so that a merge can name the commands that redo a
  // missing shard. Not in the fingerprint.
  std::string study;
};

// The header of the map run_simulated_map would compute (checks the dynamics and options).
SimulatedMapHeader simulated_map_header(const ToolDynamics& dynamics, const SimulatedMapOptions& options);
// A 64-bit FNV-1a hash of the header's dynamics, options and grids.
std::uint64_t simulated_map_fingerprint(const SimulatedMapHeader& header);

// The whole map on every core. A cell whose motion overflows (violent chatter) counts as unstable
// (growth +inf). Throws InvalidArgument (dynamics, options).
SimulatedMap run_simulated_map(const ToolDynamics& dynamics, const SimulatedMapOptions& options,
                               const ProgressCallback& progress = {});
// Shard `index` of `count` (0 ≤ index < count ≤ 100000). Throws InvalidArgument for a shard that
// does not exist (check_shard: an index equal to the count is named as an array numbered from 1),
// and what run_simulated_map throws.
SimulatedMapPart run_simulated_map_part(const ToolDynamics& dynamics, const SimulatedMapOptions& options, int index, int count,
                                        const ProgressCallback& progress = {});
// The map from its parts (any order), bit for bit the unsharded one. Throws ShardSetError (an
// InputError) naming every problem at once — parts of different maps (fingerprint) or splits
// (shard count), shards given twice, shards missing — with the shards to run again and the parts
// to leave out (check_shard_set), and InputError naming a part that holds speeds not its own.
SimulatedMap merge_simulated_map_parts(const std::vector<SimulatedMapPart>& parts, const std::vector<std::string>& sources);

// Stable or not over spindle speed [rpm] × depth [mm] (chatter cells coloured by their growth per
// revolution, stable ones by theirs, on one scale with 1 the boundary), the lowest unstable depth
// per speed drawn; and the SLE [µm] of the stable cells in a second panel when the cut has a wall.
plot::Figure simulated_map_figure(const SimulatedMap& map);

}  // namespace toolpoint
