// toolpoint: the overhang study — the tool point FRF for any tool overhang from a measured
// holder-tip FRF, and the modes followed through the overhangs (the seed's Section 4, Fig. 10).
//
// Per overhang L (the tool's length inside the holder kept, so the measured SH11 stays valid),
// the semi-analytical coupling of Schmitz's RCSA in the seed's Eq. (5):
//     SHT11(L) = T11 − T12 (T22 + K_ht⁻¹ + SH11)⁻¹ T21
// with SH11 measured (or finite-differenced) and T the model's free–free tool of overhang L,
// joined through the assembly's holder–tool joint K_ht. The modes of each SHT11 are the peaks of
// |H|; they are followed from the overhang nearest the assembly's own, outwards in both
// directions, to the nearest peak within a relative tolerance (track_modes). With the holder–tool
// joint uncertain (one overhang), also the band of the coupled tool point FRF: the quantiles of |H|
// and ∠H over joints drawn from the joint file's covariance (coupled_tool_point_band).
// Units: overhangs in m; receptances SI (H m/N, L 1/N, N rad/N, P rad/(N·m)); frequencies in Hz.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/model/receptance.hpp"
#include "toolpoint/studies/study.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint {

struct OverhangStudyOptions {
  // Tool overhangs [m], strictly increasing, each > 0 (a tool must stick out at least 0.1 mm;
  // Assembly::check decides). Empty: the assembly's own tool.overhang alone.
  std::vector<double> overhangs_m;
  PeakOptions peaks{0.1};            // a peak is a mode when it rises 10 % above its valleys: noise in a
                                     // measured SH11 makes no modes
  double tracking_tolerance = 0.15;  // a mode moves at most this fraction of its frequency per step
  int threads = 0;                   // overhangs run in parallel on this many threads (ParallelOptions::
                                     // threads: 0 every core, 1 none); results identical for any count
  std::string sh11_name = "SH11";    // names the measured SH11 in messages (e.g. its file)
  // The holder–tool joint uncertain (one overhang only): the band of the coupled tool point FRF over
  // joints drawn from this file's [uncertainty], the measured SH11 taken as exact; the file's joint
  // is in place for the coupled FRFs themselves too (the band's nominal). None: no band.
  std::optional<JointFile> uncertain_joint;
  UncertaintyOptions band;  // the band's samples, seed, levels and threads (its progress: the study's)
  // Throws InvalidArgument naming `OverhangStudyOptions::<field>` and the value (the ranges of
  // overhang_study_fields(); the overhangs, the peaks, a band with several overhangs, the band's).
  void check() const;
};

// OverhangStudyOptions' scalar fields (option_fields.hpp): tracking_tolerance, and threads as
// parallel_fields()' threads (`toolpoint couple --threads`).
const std::vector<OptionField<OverhangStudyOptions>>& overhang_study_fields();

// One overhang's result.
struct OverhangFrf {
  double overhang_m = 0.0;
  BlockSeries sht11;        // the tool point block on SH11's grid
  std::vector<Peak> modes;  // peaks of |H| (options.peaks), on the grid (no model to refine on)
};

struct OverhangStudy {
  double tool_inside_holder_m = 0.0;   // kept for every overhang
  std::vector<OverhangFrf> overhangs;  // in the order of options.overhangs_m
  std::size_t reference = 0;           // index of the overhang nearest the assembly's own: the modes
                                       // tracked are its peaks
  // Tracked mode frequencies [Hz], [mode][overhang]; NaN where the mode was not found.
  std::vector<std::vector<double>> tracked_modes_hz;
  std::optional<FrfBand> band;        // with options.uncertain_joint: the tool point FRF's quantiles on SH11's grid
  std::vector<std::string> warnings;  // modes lost at some overhangs, no peak at the reference
};

// Runs the study on `assembly` (its tool and holder–tool joint; a rigid joint is rigid coupling)
// with the measured `sh11` (≥ 3 points). Throws InvalidArgument (options, an overhang the tool
// cannot have, naming it), InputError (an invalid SH11, naming options.sh11_name),
// NumericalError (a singular coupling, naming the overhang and frequency). With several failing
// overhangs, the error is the first overhang's, whatever the thread count. Progress: per overhang,
// then per joint sample of the band.
OverhangStudy run_overhang_study(const Assembly& assembly, const BlockSeries& sh11, const OverhangStudyOptions& options = {},
                                 const ProgressCallback& progress = {});

// The overhangs of a sweep start, start + step, … up to stop [m] (stop included when a whole number
// of steps away, to 1e-12 relative), each rounded to a nanometre: the lengths the sweep means,
// without the float noise of repeated steps (0.04 + 6 × 0.002 is 0.052, not 0.052000000000000005).
// Throws InvalidArgument unless 0 < start ≤ stop, all finite, and step ≥ 1 nm.
std::vector<double> overhang_sweep(double start_m, double stop_m, double step_m);
// How many overhangs overhang_sweep gives, with its checks, without making them: a caller bounds
// the count first (a nanometre step over a metre would be a billion overhangs).
std::size_t overhang_sweep_size(double start_m, double stop_m, double step_m);

// The tracked modes as a table (the seed's Fig. 10): overhang_m, then mode_<k>_hz per tracked mode
// (an empty cell where the mode was not found).
Table natural_frequency_table(const OverhangStudy& study);

// The same as figure data (plot::natural_frequency_figure), with its title; no modes: none to draw.
plot::OverhangSweep natural_frequency_sweep(const OverhangStudy& study);

// The tool point FRF (SHT11's H) of each overhang, for plot::overhang_frf_figure.
std::vector<FrfSeries> tool_point_frfs(const OverhangStudy& study);

}  // namespace toolpoint
