// toolpoint: identification of a joint from measured FRFs, as one library call — the seed's
// procedure (closed form Eq. 6, 15 or 18 read at the mode the joint controls) and the band fit of
// joint_fit.hpp side by side, with the mode choice, a forward check and a verdict.
//
//   holder–tool     Eq. (6):  A = T (tool outside the holder, model), B11 = SH11 (measured), G11 = SHT11 (measured)
//   spindle–holder  Eq. (15): A = H (holder with the shank, model),   B11 = S11 (model or measured), G11 = SH11
//   spindle–holder  Eq. (18): A = HT (holder + tool through the assembly's K_ht), B11 = S11,          G11 = SHT11
//
// The band the seed reads in: given (`band_hz`), around a given frequency (`at_hz` ± width), around
// the mode that moves most with the overhang (FRFs at other overhangs: the seed's Fig. 10), or
// around the mode effect analysis on the model picks (the default; the assembly's joint values are
// the trial values). The band fit uses every frequency of the data, or `band_hz` when given.
// Several measured set-ups (e.g. the seed's three overhangs) are fitted together; the seed's
// read-out and the forward check use the first.
//
// Forward check (forward_check.hpp): the identified constants back into the forward model with
// the measured B11, against the measured G11, each set-up on all its frequencies, mode by mode,
// each difference judged against what the noise makes (a Monte Carlo test with a stated false-alarm
// probability). Verdict: fail when the result cannot be a passive joint reproducing the data (a
// negative diagonal stiffness; a diagonal damping negative beyond its noise; the forward check
// failing; residuals far beyond what the noise explains; G11 identical to B11; a fit that did not
// converge), doubtful when something deserves a look (residuals beyond what the noise explains,
// a joint that does not transfer between set-ups, a stiffness left undetermined, no mode to
// check), pass otherwise. (Noise that does not look white is a warning only: low noise on sharp
// peaks looks so too, and a noise estimate that is too small shows in the residual ratio.)
// Units: SI; frequencies in Hz; errors as fractions (reports show %).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/identify/forward_check.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/identify/joint_fit.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/study.hpp"

namespace toolpoint {

enum class IdentificationMethod { Fit, Seed };
const char* to_string(IdentificationMethod m);  // "fit", "seed"
const char* to_string(Route r);                 // "Eq. (6)", "Eq. (15)", "Eq. (18)"

// One measured set-up.
struct IdentificationData {
  std::string label;                 // names it in reports ("overhang 49.0 mm"); default: from the overhang
  std::optional<double> overhang_m;  // the tool overhang of this set-up [m]; default: the assembly's
  BlockSeries G11;                   // SHT11 (Eq. 6, 18) or SH11 (Eq. 15), measured
  std::string g_name;                // e.g. the file name
  std::optional<BlockSeries> B11;    // SH11 (Eq. 6: required) or S11 (Eq. 15, 18: default the model's)
  std::string b_name;
  // The coherence γ² of each series' H entry (a file's coherence column), or empty. Used with
  // NoiseSpec::averages (noise.hpp's apply_coherence).
  std::vector<double> g_coherence, b_coherence;
};

// The noise of the measured series (noise.hpp): estimated from the data (multiplicative and, by
// default, an additive floor) or stated; the calibration is always stated (no data reveal it); a
// coherence column counts when the number of averages behind it is given.
struct NoiseSpec {
  enum class Source { Estimated, Stated };
  Source source = Source::Estimated;
  NoiseEstimateOptions estimate;  // Estimated: how
  double magnitude_sigma = 0.0;   // Stated: relative magnitude σ (0.05 = 5 %)
  double phase_sigma_rad = 0.0;   // Stated: phase σ [rad]
  double floor = 0.0;             // Stated: additive floor, σ per part relative to each entry's peak (0.01 = 1 %)
  // σ of each measured FRF's calibration factor (0.02 = 2 %; a standard uncertainty, not a
  // bound), carried into every interval; 0: the sensors are taken as exact.
  double calibration = 0.0;
  bool calibration_shared = false;  // one sensor chain for every measured FRF: one factor for all
  int averages = 0;                 // averages behind a coherence column (0: the coherence is not used)
  // Throws InvalidArgument naming `NoiseSpec::<field>`: the ranges of noise_spec_fields() (a σ in
  // per cent refused as cannot be meant), the estimate's options, stated noise all zero.
  void check() const;
  StatedNoise stated() const { return {magnitude_sigma, phase_sigma_rad, floor}; }
};
// NoiseSpec's scalar fields (option_fields.hpp): magnitude_sigma (identify --sigma), phase_sigma_rad
// (--phase-sigma, in degrees), floor (--floor; NoiseOptions' range), calibration (--calibration,
// NoiseOptions'), averages (--averages). `source`, `estimate` and `calibration_shared` beside it.
const std::vector<OptionField<NoiseSpec>>& noise_spec_fields();

struct VerdictOptions {
  // The forward check: its false-alarm probability, material tolerances, replicates. Its smoothing,
  // seed and threads are the study's (IdentificationOptions::filter, IdentificationOptions::fit).
  ForwardCheckOptions forward;
  // The band fit's residual ratio (JointFit::residual_ratio) above which the verdict is doubtful,
  // and fail: residuals that far beyond the noise are a model that does not describe the data.
  double residual_doubt = 1.5, residual_fail = 3.0;
  // Throws InvalidArgument naming `VerdictOptions::<field>`: the forward check's, the ranges of
  // verdict_fields(), or residual_doubt above residual_fail.
  void check() const;
};

/// \brief VerdictOptions' scalar fields defined once (option_fields.hpp): check() and the
/// attributes of Python's VerdictOptions derive from this table (`forward` has its own check();
/// residual_doubt ≤ residual_fail is checked beside the table).
/// \return the table, in the order of the fields
const std::vector<OptionField<VerdictOptions>>& verdict_fields();

struct IdentificationOptions {
  Route route = Route::HolderTool;
  IdentificationMethod method = IdentificationMethod::Fit;  // which result is `identified`
  // The seed's read-out band (see above); `band_hz` also bounds the fit.
  std::optional<std::pair<double, double>> band_hz;
  std::optional<double> at_hz;
  double width = 0.02;                   // ± relative around the mode (0.02 = ±2 %)
  std::vector<FrfSeries> overhang_frfs;  // tool point FRFs at other overhangs (mode choice, Fig. 10)
  // Savitzky–Golay filter: the seed's read-out reads filtered data (as the seed did); the fit
  // filters G11 and its model alike (joint_fit.hpp). Default: none.
  std::optional<SavgolOptions> filter;
  NoiseSpec noise;      // of every measured series (the fit needs it)
  JointFitOptions fit;  // its `filter` is set from `filter` above
  ReadoutOptions readout;
  VerdictOptions verdict;
  void check() const;  // throws InvalidArgument naming the field
};

/// \brief IdentificationOptions' scalar field (width), defined once (option_fields.hpp): its range
/// and help, check(), `toolpoint identify --width` and the Python class's docstring derive from it.
/// \return the table
const std::vector<OptionField<IdentificationOptions>>& identification_fields();

// The band and how it was chosen.
struct ModeChoice {
  std::string
      method;  // "band given", "frequency given", "mode that moves most with the overhang", "effect analysis on the model"
  double center_hz = 0.0, lo_hz = 0.0, hi_hz = 0.0;
  std::optional<EffectAnalysis> effect;   // when by effect analysis
  std::optional<OverhangModes> overhang;  // when by overhang FRFs
};

enum class Verdict { Pass, Doubtful, Fail };
const char* to_string(Verdict v);  // "pass", "doubtful", "fail"

struct IdentificationVerdict {
  Verdict verdict = Verdict::Pass;
  std::vector<std::string> reasons;  // why it is not a pass (empty for a pass)
};

struct Identification {
  Route route = Route::HolderTool;
  IdentificationMethod method = IdentificationMethod::Fit;
  std::string equation;     // which equation, which data
  JointSeries closed_form;  // K(ω) by the closed form on the first set-up (filtered if filtering)
  ModeChoice mode;
  JointReadout seed;            // the seed's read-out in mode's band
  std::optional<JointFit> fit;  // the band fit (method Fit)
  std::pair<double, double> fit_band_hz{0.0, 0.0};
  std::vector<BlockNoise> g_noise, b_noise;   // per set-up, as used
  JointParameters identified;                 // the method's result (fit estimates or the read-out's medians)
  std::vector<ForwardCheck> forward_checks;  // per set-up, all its frequencies
  IdentificationVerdict verdict;
  std::vector<std::string> warnings;  // everything worth reading, with the noise models' and the read-out's
};

// Runs the study. Throws InvalidArgument (options; a rigid trial joint where effect analysis needs
// values; a band without data), InputError (data: grids, NaN, too few points, a missing B11 for
// Eq. 6), NumericalError (a singular inversion, a parameter the data do not determine at all).
Identification run_identification_study(const Assembly& assembly, const std::vector<IdentificationData>& data,
                                        const IdentificationOptions& options = {}, const ProgressCallback& progress = {});

// The identified joint as a joint file: the method's constants, the fit's uncertainty (a band fit
// only: the seed's read-out has no interval to carry), and how it was identified, with `inputs`
// (e.g. the data files) listed in [identification].
JointFile joint_file_of(const Identification& id, const std::vector<std::string>& inputs = {});

// ---- Figures -------------------------------------------------------------------------------------

// The stiffness/damping pair of the entry (row, column) of an identified K(ω) ((0, 0) yf, (0, 1) ym,
// (1, 0) θf, (1, 1) θm) as a joint-figure curve (plot::joint_figure; units JointParameters::unit),
// with optional reference and identified values drawn as lines. With `fit`, the identified
// values' intervals and verdicts; with `seed` (a read-out), a value the read-out left
// undetermined (ParameterReadout::determined) is said so.
plot::JointParameterCurve joint_curve(const JointSeries& series, int row, int column,
                                      const std::optional<JointParameters>& reference,
                                      const std::optional<JointParameters>& identified, const JointFit* fit = nullptr,
                                      const JointReadout* seed = nullptr);

// The study's figure (the seed's Fig. 11–12): k(f) and c(f) of the four pairs yf, ym, θf, θm by the
// closed form, the read-out band shaded, the identified values as lines with the fit's intervals.
plot::Figure identification_figure(const Identification& id);

// Starting values for the fit from a closed-form series: the median of each parameter over the
// points in [lo, hi], each point weighted by 1/gain² of that parameter (a weighted median: robust
// to the wild values where the inversion amplifies noise).
JointParameters weighted_median_parameters(const JointSeries& series, double lo_hz, double hi_hz);

}  // namespace toolpoint
