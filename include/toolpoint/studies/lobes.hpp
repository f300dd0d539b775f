// toolpoint study: milling stability lobes from the tool point dynamics — the procedure behind
// `toolpoint lobes`, as one library call.
//
// In: the tool point FRFs (measured, or of an assembly model: milling_frfs below) and/or modes,
// the cutting conditions, the method. Out: the zero-order lobes or the time-domain boundary with
// its error estimate, the stable envelope, the best spindle speeds, the modal model used (fitted
// with as many modes as the FRF needs, reported with its residual), the data of the figure, and
// every warning. Units: SI (m, N, s), frequencies in Hz, spindle speeds in rpm (stability.hpp).
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/option_fields.hpp"
#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/joint_file.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/study.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint {

// The tool point FRF of an assembly model (SHT11's H, seed Eq. 5) on `frequency_hz`, for x and y
// (a round tool on a round spindle), or x alone when `rigid_y`.
MillingFrfs milling_frfs(const AssemblyModel& model, const std::vector<double>& frequency_hz, bool rigid_y = false);

// Which tool point dynamics the lobes of an assembly use (docs/spindle-at-speed.md).
enum class SpeedModel {
  Automatic,   // Spinning when the assembly's bearings carry speed tables or differ in x and y; Standstill otherwise
  Standstill,  // the standstill single-plane FRF, bearings at their constants and x values (as before issue 28)
  Bearings,    // at each speed the x–y FRF with the bearings at that speed (tables, x and y values), no spin
  Spinning,    // as Bearings, with the spindle spinning at that speed (gyroscopic moments: whirl, H_xy)
};
const char* to_string(SpeedModel m);  // "auto", "standstill", "bearings", "spinning" (the CLI's --speed-model)
// The model named by to_string's name; nullopt for any other name.
std::optional<SpeedModel> speed_model_from(const std::string& name);

// Whether the lobes of `assembly` under `model` use the FRF at each speed (SpeedDependentFrfs):
// Bearings and Spinning always, Automatic with speed tables or bearings that differ in x and y.
bool lobes_at_speed(const Assembly& assembly, SpeedModel model);

// The tool point FRFs of an assembly at spindle speeds [rpm] on `frequency_hz` [Hz]: per speed the
// bearings there (at_speed, refused outside a table unless `extrapolate_bearings`) and the two-plane
// tool point (AssemblyModel::tool_point_two_plane) spinning at that speed when `spin` (at rest
// otherwise): G_xx, G_yy, G_xy, G_yx, or G_xx alone when `rigid_y`. Speeds on `parallel` threads
// (identical results for any count). Throws InvalidArgument (a speed outside a bearing's table,
// naming it), NumericalError as the model's sweeps.
SpeedDependentFrfs milling_frfs_at_speeds(const Assembly& assembly, const std::vector<double>& frequency_hz,
                                          const std::vector<double>& speeds_rpm, bool spin, bool extrapolate_bearings,
                                          bool rigid_y = false, const ParallelOptions& parallel = {});

enum class LobesMethod {
  ZeroOrder,           // Altintas & Budak 1995, directly from the FRFs
  FullDiscretization,  // the time-domain boundary of a modal model (stability_boundary)
  SemiDiscretization,  // the same boundary by semi-discretization (Discretization::Semi)
};
const char* to_string(LobesMethod m);  // "zoa", "fd", "sd" (as the CLI's --method and a study file's options.method)
// The method a name gives ("zoa", "fd", "sd"); nullopt for any other name.
std::optional<LobesMethod> lobes_method_from(const std::string& name);
// The time-domain methods (fd, sd) use a modal model and stability_boundary.
inline bool time_domain(LobesMethod m) { return m != LobesMethod::ZeroOrder; }

// Where the dynamics come from. The zero-order method needs `frfs` (or `assembly`, whose tool point
// FRF milling_frfs gives on its grid when `frfs` is empty); the time-domain method takes the modes
// given, or fits them to `frfs` (x from G_xx, y from G_yy, or the x modes for a symmetric tool,
// none when rigid in y).
struct LobesInput {
  std::optional<MillingFrfs> frfs;
  std::string frf_name = "tool point FRF";  // names G_xx in messages (a file name, "the tool point FRF of X.toml")
  std::string frf_y_name = "y FRF";         // names G_yy
  std::vector<Mode> x_modes, y_modes;
  bool rigid_y = false;  // with modes given: the tool is rigid in y
  // An assembly model: the tool point FRF when `frfs` is empty (milling_frfs on its grid, for x and
  // y, x alone when rigid_y), and the model each joint sample goes into. With the joint uncertain:
  // a joint file with [uncertainty] whose joint is drawn (needs `assembly`); its joint is the
  // nominal one, in place of the assembly's (given `frfs` must be the FRFs of that assembly).
  std::optional<Assembly> assembly;
  std::optional<JointFile> uncertain_joint;
  // FRFs at several speeds (measured or computed): used in place of `frfs` and of the assembly's
  // FRF, interpolated between their speeds (zero_order_lobes; the time domain fits a modal model
  // (and pole-residue terms) at each speed of the grid, LobesStudyResult::fit_residual).
  std::optional<SpeedDependentFrfs> speed_frfs;
  // Rigid in y: said here, or by the FRFs (MillingFrfs::rigid_y).
  bool rigid_in_y() const { return rigid_y || (frfs && frfs->rigid_y); }
};

struct LobesStudyOptions {
  LobesMethod method = LobesMethod::ZeroOrder;
  CuttingConditions cutting;
  SpeedRange speeds{0.0, 0.0, 0};  // points 0: 2000 (zero-order envelope) or 200 (time domain)
  double max_depth_m = 0.0;        // zero-order: lobe points deeper are left out; time domain: search ceiling (0: automatic)
  int lobes = -1;                  // zero-order: lobes 0…K (−1: enough to cover speeds.min_rpm)
  // Time domain: the error target and discretization (BoundaryOptions). `degree`: fd's interpolation
  // degree 1…3; sd runs first-order semi-discretization for any degree ≥ 1 (the default 2 included)
  // and the zeroth order for 0.
  double tolerance = 0.01;
  int steps = 0;
  int degree = 2;
  // Time domain, modes fitted: at most fit.max_modes per FRF (the fewest whose modal model — no
  // residual terms — represents the FRF within `fit_target` over fit.band_hz or the whole FRF).
  ModalFitOptions fit = [] {
    ModalFitOptions o;
    o.max_modes = 8;
    return o;
  }();
  double fit_target = 0.02;
  // The best spindle speeds: envelope maxima rising `pocket_prominence` × their depth above the
  // valleys beside them, at most `pockets`.
  double pocket_prominence = 0.02;
  int pockets = 5;
  ParallelOptions parallel;
  // With LobesInput::uncertain_joint: the samples, seed, quantile levels and threads of the draws
  // (its progress unused: the study's covers them). The probability map's depths: 201 from 0 to
  // 1.5 × the nominal envelope's highest point.
  UncertaintyOptions uncertainty;
  // With LobesInput::assembly (and no `frfs`): which dynamics (SpeedModel). At speed (Bearings,
  // Spinning; Automatic when the bearings ask for it) the x–y FRF is evaluated at `speed_nodes`
  // speeds evenly over the range and at the midpoints between them, interpolated linearly in speed
  // between these, and the error of interpolating between the nodes alone is reported
  // (LobesStudyResult::frf_interpolation_error, envelope_interpolation_error). 0: 17 nodes.
  SpeedModel speed_model = SpeedModel::Automatic;
  int speed_nodes = 0;                // 0 (automatic) or 2…1000
  bool extrapolate_bearings = false;  // a speed outside a bearing's table: extend its end rows (else refused)
  void check() const;                 // throws InvalidArgument naming the field
};

/// \brief The scalar fields of LobesStudyOptions, defined once (option_fields.hpp): their units,
/// ranges and help, the `toolpoint lobes` flags, the plan file's [lobes] keys, the JSON echo and
/// the keywords of Python's run_lobes_study derive from this table (method, cutting, speeds,
/// speed_model, parallel and uncertainty have their own definitions).
/// \return the table, in the order of the fields
const std::vector<OptionField<LobesStudyOptions>>& lobes_study_fields();

/// \brief The lobes study's modal-fit field `name` (max_modes or fit_target) for another study
/// that fits modes as it does (pitch, simulation: time_domain_modes): the same range, unit, help
/// and flag (`--max-modes`, `--fit-target`), without the plan file's key.
/// \param name "max_modes" or "fit_target"
/// \return the field's description
FieldSpec fitted_modes_field(const char* name);

// How a modal model was fitted to one FRF.
struct ModalFitSummary {
  std::string what;  // the FRF's name
  int modes = 0;
  double residual = 0.0;  // ‖G_modes − G‖/‖G‖ over the band, residual terms excluded
  double band_low_hz = 0.0, band_high_hz = 0.0;
  bool target_met = false;
};

// The joint's uncertainty at one spindle speed: the nominal envelope's depth and each quantile
// level's [m] (StabilityUncertainty::levels; level q: stable with probability 1 − q).
struct SpeedQuantiles {
  double speed_rpm = 0.0;
  double nominal_depth_m = 0.0;
  std::vector<double> depth_m;
};

struct LobesStudyResult {
  LobesStudyOptions options;  // as given (the JSON echoes their scalar fields: lobes_study_fields)
  LobesMethod method = LobesMethod::ZeroOrder;
  CuttingConditions cutting;
  SpeedRange speeds;
  std::optional<ZeroOrderResult> zero_order;  // method ZeroOrder
  std::optional<BoundaryResult> boundary;     // methods FullDiscretization, SemiDiscretization
  ModalModel modes;                           // time domain: the modal model used
  std::vector<ModalFitSummary> fits;          // time domain: one per fitted FRF
  std::vector<EnvelopePoint> envelope;        // the stable envelope over speeds
  std::vector<EnvelopePoint> pockets;         // the best speeds, deepest first
  std::vector<double> pocket_depth_error_m;   // per best speed: the time domain's depth error estimate
                                              // (NaN for the zero-order method and a capped speed)
  plot::LobesFigureData figure;               // depth and chatter-frequency panels' data (with the
                                              // quantile envelopes when the joint is uncertain)
  // With LobesInput::uncertain_joint: the stable depth's quantiles per speed and the probability of
  // stability (stability_uncertainty below), the joint file they were drawn from, and the map's data.
  std::optional<StabilityUncertainty> uncertainty;
  std::string uncertain_joint;
  std::vector<SpeedQuantiles> pocket_quantiles;  // per best speed, at the nearest of the uncertainty's speeds
  std::optional<SpeedQuantiles> worst_speed;     // where the first level's depth (95 % sure) is lowest
  std::optional<plot::ProbabilityMapData> probability_figure;
  // The dynamics used: Standstill (one FRF for every speed), or at speed (Bearings, Spinning; given
  // speed-dependent FRFs: Bearings) with the speeds [rpm] where the FRF was evaluated, and the
  // estimated error of the interpolation between them: the largest |G − G_interpolated| of the
  // midpoints' direct FRFs against the nodes' interpolation, relative to the largest |G| there, and
  // the largest change of the envelope's depth (relative) between the lobes from the nodes alone
  // and from nodes and midpoints (the result; linear interpolation's error falls ~4× per halving,
  // so this overstates the result's own error about 3×). NaN when not at speed or not estimated.
  SpeedModel speed_model = SpeedModel::Standstill;
  std::vector<double> frf_speeds_rpm;
  double frf_interpolation_error = std::numeric_limits<double>::quiet_NaN();
  double envelope_interpolation_error = std::numeric_limits<double>::quiet_NaN();
  // The time domain at speed: a modal model per speed fitted to the FRF at that speed (real modes to
  // G_xx and G_yy; where x and y couple, pole-residue terms for the whole block, fit_residue_terms);
  // `modes` and `fits` are those of the speed with the largest real-mode fit residual. The largest
  // residuals over the speeds: of the real-mode fits (ModalFitSummary::residual) and of the whole
  // model against the 2×2 block relative to the direct FRFs (fit_residue_terms; without coupling,
  // the former). NaN otherwise. (envelope_interpolation_error is then estimated from the zero-order
  // lobes of the same FRFs.)
  double fit_residual = std::numeric_limits<double>::quiet_NaN();
  double block_fit_residual = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> warnings;
};

// Runs the study. Throws InvalidArgument (bad options, no FRF for the zero-order method, no modes
// and no FRF, an uncertain joint without its assembly), InputError (bad FRFs, nothing to fit),
// NumericalError. Progress: the nominal study, then each joint sample. At speed, each joint sample
// is evaluated at speed too (the sampled assembly at each speed node, as the nominal).
LobesStudyResult run_lobes_study(const LobesInput& input, const LobesStudyOptions& options,
                                 const ProgressCallback& progress = {});

// Stability with the joint of `joint` uncertain (uncertainty.hpp) by this study with any of its
// methods: each sample's tool point FRF (x and y, milling_frfs) goes through run_lobes_study with
// `lobes` (one thread inside: the samples are what runs in parallel); the envelope is the study's
// (the time-domain boundary where the search reached its ceiling counts as that depth). Same
// errors as run_lobes_study, and envelope_uncertainty's.
// `rigid_y`: each sample's tool is rigid in y (milling_frfs).
StabilityUncertainty stability_uncertainty(const Assembly& assembly, const JointFile& joint,
                                           const std::vector<double>& frequency_hz, const LobesStudyOptions& lobes,
                                           const std::vector<double>& depth_grid_m, const UncertaintyOptions& options,
                                           bool rigid_y = false);

// The modal model of the time-domain method: the modes given (LobesInput::x_modes, y_modes), or
// fitted (fit_milling_modes) to the FRFs, or to the assembly's tool point FRF (milling_frfs): x from
// G_xx, y from G_yy, or the x modes for a symmetric tool, none when rigid in y. Appends the fits'
// summaries and the warnings (the model's, the fits', cross FRFs ignored unless `uses_cross`: the
// caller reads them itself). Throws InvalidArgument (no modes and nothing to fit, rigid_y with y
// modes), InputError (bad FRFs, nothing to fit).
ModalModel time_domain_modes(const LobesInput& input, const ModalFitOptions& fit, double fit_target,
                             std::vector<ModalFitSummary>& fits, std::vector<std::string>& warnings, bool uses_cross = false);

// Pole-residue terms (ResidueTerm) that complete the real modes of `modes` to the 2×2 block of
// `frfs`: with the poles of `pole_modes` (λ = ω(−ζ + i√(1 − ζ²)); poles within 0.1 ζω of an earlier
// one dropped), the complex residues R_k of
//     G_ij(iω) − G_ij,modes(iω) ≈ Σ_k R_k/(iω − λ_k) + R̄_k/(iω − λ̄_k)
// per entry (G_xx less the x modes' FRF, G_yy less the y modes', G_xy and G_yx whole; x alone when
// rigid in y or without y modes) by linear least squares over the frequencies in [band_low_hz,
// band_high_hz] (real and imaginary parts; columns scaled to unit norm; column-pivoting QR). An
// entry with nothing left (a cross FRF absent or exactly zero) gets no terms. `residual`: the
// misfit of all entries over the band relative to ‖G_xx‖ (+ ‖G_yy‖) there.
std::vector<ResidueTerm> fit_residue_terms(const MillingFrfs& frfs, const ModalModel& modes, const std::vector<Mode>& pole_modes,
                                           double band_low_hz, double band_high_hz, double& residual);

// The modal model of one point FRF for the time-domain method: 1, 2, … modes (up to
// options.max_modes) until the modes alone represent it within `target`; the best one otherwise,
// with a warning that says why. Warnings of the fit are prefixed with `what`.
std::vector<Mode> fit_milling_modes(const FrfSeries& frf, const std::string& what, const ModalFitOptions& options, double target,
                                    ModalFitSummary& summary, std::vector<std::string>& warnings);

}  // namespace toolpoint
