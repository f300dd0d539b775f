// toolpoint study: milling stability lobes (studies/lobes.hpp). Units: SI, Hz, rpm.
#include "toolpoint/studies/lobes.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/QR>
#include <fmt/format.h>
#include <limits>
#include <string>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/plausibility.hpp"
#include "toolpoint/io/uncertainty_io.hpp"

namespace toolpoint {

const char* to_string(LobesMethod m) {
  return m == LobesMethod::ZeroOrder ? "zoa" : m == LobesMethod::FullDiscretization ? "fd" : "sd";
}

std::optional<LobesMethod> lobes_method_from(const std::string& name) {
  for (LobesMethod m : {LobesMethod::ZeroOrder, LobesMethod::FullDiscretization, LobesMethod::SemiDiscretization})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

namespace {


// ‖Σ modes − G‖/‖G‖ over the FRF points inside `band` (all when none).
double modal_residual(const FrfSeries& frf, const std::vector<Mode>& modes,
                      const std::optional<std::pair<double, double>>& band) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < frf.size(); ++i) {
    const double f = frf.frequency_hz[i];
    if (band && (f < band->first || f > band->second)) continue;
    num += std::norm(modal_receptance(modes, f) - frf.values[i]);
    den += std::norm(frf.values[i]);
  }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

// The top of a lobes figure's depth axis: 5× the shallowest envelope depth (the plot module's own
// default), so lobe points far above it can be left out of the figure's data.
double figure_top_m(const std::vector<EnvelopePoint>& envelope) {
  double floor = std::numeric_limits<double>::infinity();
  for (const EnvelopePoint& e : envelope)
    if (std::isfinite(e.depth_m) && e.depth_m > 0.0) floor = std::min(floor, e.depth_m);
  return 5.0 * floor;
}

void set_envelope(plot::LobesFigureData& d, const std::vector<EnvelopePoint>& envelope) {
  for (const EnvelopePoint& e : envelope) {
    d.envelope_rpm.push_back(e.speed_rpm);
    d.envelope_depth_m.push_back(e.depth_m);
  }
}

// The depth axis: 5× the shallowest depth, raised to cover the whole envelope (the best speeds
// are read off the figure, and so is a rise at the range's ends, e.g. process damping at low
// speed) up to 50× it; deeper parts are left above the frame, and the title says so.
struct DepthAxis {
  double top_m;
  bool clipped;
};

DepthAxis depth_axis(const std::vector<EnvelopePoint>& envelope) {
  const double floor = figure_top_m(envelope) / 5.0;
  DepthAxis axis{5.0 * floor, false};
  for (const EnvelopePoint& p : envelope) {
    if (!std::isfinite(p.depth_m) || p.depth_m * 1.1 <= axis.top_m) continue;
    if (p.depth_m * 1.1 <= 50.0 * floor) axis.top_m = p.depth_m * 1.1;
    else axis.clipped = true;
  }
  if (axis.clipped) axis.top_m = 50.0 * floor;
  return axis;
}

void set_depth_axis(plot::LobesFigureData& d, const DepthAxis& axis) {
  d.depth_max_m = axis.top_m;
  if (axis.clipped) d.title += fmt::format(" (depths above {:.3g} mm clipped)", axis.top_m * 1e3);
}

// Zero-order lobes for the figure: one polyline per lobe, broken (NaN) between its two roots and
// wherever grid frequencies are skipped (speed out of range, no positive depth, or deeper than
// twice the axis top: such points only thin the data, the visible part stays whole).
plot::LobesFigureData zero_order_figure(const ZeroOrderResult& r, double keep_below_m) {
  plot::LobesFigureData d;
  set_envelope(d, r.envelope);
  const std::vector<double>& grid = r.table.chatter_hz;
  std::size_t last_index = grid.size();
  int last_root = -1;
  r.for_each_point([&](const LobePoint& p) {
    if (!(p.depth_m <= keep_below_m)) return;
    if (d.lobes.empty() || d.lobes.back().number != p.lobe) {
      d.lobes.push_back({p.lobe, {}, {}, {}});
      last_index = grid.size();
    }
    plot::Lobe& l = d.lobes.back();
    const auto index = static_cast<std::size_t>(std::lower_bound(grid.begin(), grid.end(), p.chatter_hz) - grid.begin());
    if (!l.depth_m.empty() && (p.root != last_root || index != last_index + 1)) {
      l.spindle_speed_rpm.push_back(kNaN);
      l.depth_m.push_back(kNaN);
      l.chatter_frequency_hz.push_back(kNaN);
    }
    l.spindle_speed_rpm.push_back(p.speed_rpm);
    l.depth_m.push_back(p.depth_m);
    l.chatter_frequency_hz.push_back(p.chatter_hz);
    last_index = index;
    last_root = p.root;
  });
  d.title = fmt::format("Zero-order stability lobes, k = 0…{}: limit {:.4g} mm at {:.0f} Hz", r.lobes, r.floor_depth_m * 1e3,
                        r.floor_chatter_hz);
  return d;
}

// The time-domain boundary for the figure: one curve per lobe number over the speed grid (NaN at
// speeds another lobe limits), speeds with no instability left to the envelope alone.
plot::LobesFigureData boundary_figure(const BoundaryResult& r) {
  plot::LobesFigureData d;
  set_envelope(d, boundary_envelope(r));
  std::vector<int> numbers;
  for (const BoundaryPoint& b : r.boundary)
    if (b.kind != BoundaryKind::None && std::find(numbers.begin(), numbers.end(), b.lobe) == numbers.end())
      numbers.push_back(b.lobe);
  std::sort(numbers.begin(), numbers.end());
  for (int k : numbers) {
    plot::Lobe l{k, {}, {}, {}};
    for (const BoundaryPoint& b : r.boundary) {
      const bool mine = b.kind != BoundaryKind::None && b.lobe == k;
      l.spindle_speed_rpm.push_back(b.speed_rpm);
      l.depth_m.push_back(mine ? b.depth_m : kNaN);
      l.chatter_frequency_hz.push_back(mine ? b.chatter_hz : kNaN);
    }
    d.lobes.push_back(std::move(l));
  }
  d.title = fmt::format("Stability boundary, {}-discretization (error ≤ {:.2g} % estimated)",
                        r.scheme == Discretization::Semi ? "semi" : "full", 100.0 * r.worst_relative_error());
  return d;
}

BoundaryOptions boundary_options(const LobesStudyOptions& options, const SpeedRange& speeds, const ProgressCallback& progress);

}  // namespace

MillingFrfs milling_frfs(const AssemblyModel& model, const std::vector<double>& frequency_hz, bool rigid_y) {
  MillingFrfs f;
  f.xx = entry(model.tool_point(frequency_hz), 0);
  f.rigid_y = rigid_y;
  f.check();
  return f;
}

const char* to_string(SpeedModel m) {
  switch (m) {
    case SpeedModel::Standstill: return "standstill";
    case SpeedModel::Bearings: return "bearings";
    case SpeedModel::Spinning: return "spinning";
    default: return "auto";
  }
}

std::optional<SpeedModel> speed_model_from(const std::string& name) {
  for (SpeedModel m : {SpeedModel::Automatic, SpeedModel::Standstill, SpeedModel::Bearings, SpeedModel::Spinning})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

bool lobes_at_speed(const Assembly& assembly, SpeedModel model) {
  if (model == SpeedModel::Standstill) return false;
  if (model != SpeedModel::Automatic) return true;
  return has_speed_tables(assembly) || !std::all_of(assembly.spindle.bearings.begin(), assembly.spindle.bearings.end(),
                                                    [](const Bearing& b) { return b.isotropic(); });
}

SpeedDependentFrfs milling_frfs_at_speeds(const Assembly& assembly, const std::vector<double>& frequency_hz,
                                          const std::vector<double>& speeds_rpm, bool spin, bool extrapolate_bearings,
                                          bool rigid_y, const ParallelOptions& parallel) {
  SpeedDependentFrfs s;
  s.speed_rpm = speeds_rpm;
  s.frfs.resize(speeds_rpm.size());
  const bool tables = has_speed_tables(assembly);
  parallel_for(speeds_rpm.size(), parallel, [&](std::size_t j) {
    const AssemblyModel model(tables ? at_speed(assembly, speeds_rpm[j], extrapolate_bearings) : assembly);
    const BlockSeries4 b = model.tool_point_two_plane(frequency_hz, spin ? rad_s_of_rpm(speeds_rpm[j]) : 0.0);
    const auto part = [&](int r, int c) {
      FrfSeries f;
      f.frequency_hz = frequency_hz;
      f.values.reserve(b.blocks.size());
      for (const Block4& x : b.blocks) f.values.push_back(x(r, c));
      return f;
    };
    MillingFrfs& g = s.frfs[j];
    g.xx = part(0, 0);
    g.rigid_y = rigid_y;
    if (!rigid_y) {
      g.yy = part(2, 2);
      g.xy = part(0, 2);
      g.yx = part(2, 0);
    }
  });
  return s;
}

void LobesStudyOptions::check() const {
  cutting.check();
  if (speeds.points != 0) speeds.check();
  else SpeedRange{speeds.min_rpm, speeds.max_rpm, 2}.check();
  fit.check();
  parallel.check();
  // Degree 0 means something only to the semi-discretization (its zeroth order); the fields' range
  // below admits it for every method.
  if (degree == 0 && method != LobesMethod::SemiDiscretization)
    throw InvalidArgument(
        fmt::format("LobesStudyOptions::degree {} must be 1, 2 or 3 (0 or more with the semi-discretization "
                    "method: 0 its zeroth order, else the first)",
                    degree));
  if (time_domain(method)) {
    BoundaryOptions b = boundary_options(*this, {speeds.min_rpm, speeds.max_rpm, 200}, {});
    b.check();
  }
  // The scalar fields' ranges (lobes_study_fields); tolerance, steps and degree whatever the method.
  check_fields(lobes_study_fields(), *this, "LobesStudyOptions");
}

const std::vector<OptionField<LobesStudyOptions>>& lobes_study_fields() {
  using O = LobesStudyOptions;
  using K = FieldKind;
  // The fields that go to the zero-order lobes (ZeroOrderOptions), the boundary (BoundaryOptions)
  // and the modal fit (ModalFitOptions) are those types' own fields, in the study's words and with
  // the plan file's keys.
  const auto field = [](const auto& table, const char* name, const char* help, const char* plan_key = nullptr) {
    FieldSpec s = with_help(option_field(table, name).spec, help);
    s.plan_key = plan_key;
    return s;
  };
  static const FieldSpec max_modes =
      field(modal_fit_fields(), "max_modes",
            "time domain, modes fitted: at most this many modes per FRF (the fewest that meet the fit target are used)",
            "max_modes");
  static const FieldSpec max_depth = [&] {
    FieldSpec s = field(boundary_fields(), "max_depth_m",
                        "largest axial depth: the zero-order method drops deeper lobe points, the time domain searches up "
                        "to it");
    s.note = "0: zero-order all, time domain 10 × the zero-order floor";
    return s;
  }();
  // The time domain's fields say so first: "time domain: " and the boundary's own help.
  static const std::string tolerance_help = std::string("time domain: ") + option_field(boundary_fields(), "tolerance").spec.help,
                           steps_help = std::string("time domain: ") + option_field(boundary_fields(), "steps").spec.help,
                           degree_help = std::string("time domain: ") + option_field(boundary_fields(), "degree").spec.help;
  static const FieldSpec steps = study_steps_field(steps_help.c_str());
  static const std::vector<OptionField<O>> fields = {
      {max_depth, [](O& o) -> double& { return o.max_depth_m; }},
      {field(zero_order_fields(), "lobes", "zero-order: lobes k = 0…K", "lobes"), nullptr, [](O& o) -> int& { return o.lobes; }},
      {field(boundary_fields(), "tolerance", tolerance_help.c_str(), "tolerance"), [](O& o) -> double& { return o.tolerance; }},
      {steps, nullptr, [](O& o) -> int& { return o.steps; }},
      {field(boundary_fields(), "degree", degree_help.c_str()), nullptr, [](O& o) -> int& { return o.degree; }},
      {max_modes, nullptr, [](O& o) -> int& { return o.fit.max_modes; }},
      {{.name = "fit_target",
        .kind = K::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "time domain, modes fitted: the modal model's misfit to the FRF aimed at, relative to the FRF",
        .cli_name = "fit-target",
        .cli_unit = "%",
        .cli_per_unit = 100.0,
        .plan_key = "fit_target"},
       [](O& o) -> double& { return o.fit_target; }},
      {{.name = "pocket_prominence",
        .kind = K::Real,
        .min = 0.0,
        .max = 1.0,
        .max_open = true,
        .help = "best speeds: envelope maxima rising at least this much (relative to their depth) above the valleys beside them",
        .cli_name = "pocket-prominence",
        .cli_unit = "%",
        .cli_per_unit = 100.0,
        .plan_key = "pocket_prominence"},
       [](O& o) -> double& { return o.pocket_prominence; }},
      {{.name = "pockets", .kind = K::Integer, .min = 0.0, .max = 1000.0, .help = "best speeds: at most this many"},
       nullptr,
       [](O& o) -> int& { return o.pockets; }},
      {{.name = "speed_nodes",
        .kind = K::Integer,
        .min = 2.0,
        .max = 1000.0,
        .automatic = 0.0,
        .note = "0: 17",
        .help = "at speed: speeds over the speed range where the FRF is evaluated, plus the midpoints between them",
        .cli_name = "speed-nodes",
        .plan_key = "speed_nodes"},
       nullptr,
       [](O& o) -> int& { return o.speed_nodes; }},
      {{.name = "extrapolate_bearings",
        .kind = K::Flag,
        .help = "at speed: extend a bearing's speed table beyond its rows (linearly) instead of refusing a speed outside it",
        .cli_name = "extrapolate-bearings",
        .plan_key = "extrapolate_bearings"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.extrapolate_bearings; }},
  };
  return fields;
}

FieldSpec fitted_modes_field(const char* name) {
  FieldSpec s = option_field(lobes_study_fields(), name).spec;
  s.plan_key = nullptr;
  return s;
}

std::vector<Mode> fit_milling_modes(const FrfSeries& frf, const std::string& what, const ModalFitOptions& options, double target,
                                    ModalFitSummary& summary, std::vector<std::string>& warnings) {
  summary = {};
  summary.what = what;
  std::vector<Mode> best;
  double best_residual = std::numeric_limits<double>::infinity();
  std::vector<std::string> best_warnings;
  std::size_t last_count = 0;
  for (int k = 1; k <= options.max_modes; ++k) {
    ModalFitOptions o = options;
    o.max_modes = k;
    o.residual_terms = false;  // the time-domain model has no residual terms: fit what it will use
    const ModalFitResult r = fit_modes(frf, o, what);
    if (k > 1 && r.modes.size() == last_count) break;  // no further resonance peak to fit
    last_count = r.modes.size();
    std::vector<Mode> modes;
    try {
      modes = r.modal_model();
    } catch (const NumericalError&) {
      if (best.empty() && k == options.max_modes) throw;
      continue;  // a mode without positive mass at this count: try another
    }
    const double residual = modal_residual(frf, modes, options.band_hz);
    if (residual < best_residual) {
      best = modes;
      best_residual = residual;
      best_warnings = r.warnings;
      summary.band_low_hz = r.band_low_hz;
      summary.band_high_hz = r.band_high_hz;
    }
    if (residual <= target) break;
  }
  if (best.empty())
    throw InputError(fmt::format("{}: no modal model with positive modal masses could be fitted", what),
                     "fit a point (direct) FRF, narrow the band to the modes that matter, or give the modes");
  summary.modes = static_cast<int>(best.size());
  summary.residual = best_residual;
  summary.target_met = best_residual <= target;
  for (const std::string& w : best_warnings)
    if (w.find("peaks found") == std::string::npos && w.find("overall fit residual") == std::string::npos)
      warnings.push_back(what + ": " + w);
  if (!summary.target_met) {
    // Why: too few modes allowed, or else what is left once every peak has its mode. Refitting
    // the same modes with residual terms (−L/ω² + U, the flexibility of modes outside the band)
    // tells whether that is what the time-domain model misses, or the peaks' shape itself.
    std::string why;
    if (static_cast<int>(best.size()) >= options.max_modes) {
      why = fmt::format("it uses the most modes allowed (ModalFitOptions::max_modes = {})", options.max_modes);
    } else {
      ModalFitOptions o = options;
      o.max_modes = static_cast<int>(best.size());
      o.residual_terms = true;
      const double with_residuals = fit_modes(frf, o, what).normalised_residual;
      why = fmt::format("the FRF has {} resonance peak(s) rising {:g} dB or more, one mode each; ", best.size(),
                        options.min_prominence_db);
      why += with_residuals <= target
                 ? fmt::format(
                       "the rest is the flexibility of modes outside the band (with residual terms for it the same "
                       "modes leave {:.2f} %), which the time-domain model cannot carry",
                       100.0 * with_residuals)
                 : fmt::format(
                       "the flexibility of modes outside the band is not what is missing (with residual terms for "
                       "it the same modes still leave {:.2f} %); what is missing is in the peaks' shape, which modes "
                       "with real modal constants cannot match (complex modes, from non-proportional damping), "
                       "or in peaks lower than {:g} dB, which get no mode",
                       100.0 * with_residuals, options.min_prominence_db);
    }
    warnings.push_back(fmt::format(
        "{}: the best modal model represents the FRF within {:.1f} % over {:g}–{:g} Hz, not the {:.3g} % aimed at: {}. The lobes "
        "are those of this model. Narrow the fitted band to the modes that matter, or give the modes (LobesInput::x_modes)",
        what, 100.0 * best_residual, summary.band_low_hz, summary.band_high_hz, 100.0 * target, why));
  }
  return best;
}

ModalModel time_domain_modes(const LobesInput& input, const ModalFitOptions& fit, double fit_target,
                             std::vector<ModalFitSummary>& fits, std::vector<std::string>& warnings, bool uses_cross) {
  if (!input.frfs && input.assembly && input.x_modes.empty()) {
    LobesInput with_frfs = input;
    const AssemblyModel model(*input.assembly);
    with_frfs.frfs = milling_frfs(model, input.assembly->grid.values(), input.rigid_y);
    warnings.insert(warnings.end(), model.warnings().begin(), model.warnings().end());
    return time_domain_modes(with_frfs, fit, fit_target, fits, warnings, uses_cross);
  }
  if (input.rigid_y && !input.y_modes.empty())
    throw InvalidArgument("LobesInput: rigid_y and y modes contradict each other", "drop one of them");
  ModalModel modes;
  modes.x = input.x_modes;
  modes.y = input.y_modes;
  if (modes.x.empty()) {
    if (!input.frfs)
      throw InvalidArgument("the time-domain method needs modes (LobesInput::x_modes) or the FRFs to fit them from",
                            "give the x modes or the tool point FRF");
    input.frfs->check(input.frf_name, input.frf_y_name);
    ModalFitSummary s;
    modes.x = fit_milling_modes(input.frfs->xx, input.frf_name, fit, fit_target, s, warnings);
    fits.push_back(s);
  }
  if (modes.y.empty() && !input.rigid_in_y()) {
    if (input.frfs && input.frfs->yy) {
      ModalFitSummary s;
      modes.y = fit_milling_modes(*input.frfs->yy, input.frf_y_name, fit, fit_target, s, warnings);
      fits.push_back(s);
    } else {
      modes.y = modes.x;  // a symmetric tool
    }
  }
  if (input.frfs && input.frfs->xy && !uses_cross)
    warnings.push_back("the time-domain method uses uncoupled x and y modes: the cross FRFs are ignored");
  return modes;
}

std::vector<ResidueTerm> fit_residue_terms(const MillingFrfs& frfs, const ModalModel& modes, const std::vector<Mode>& pole_modes,
                                           double band_low_hz, double band_high_hz, double& residual) {
  residual = 0.0;
  std::vector<ResidueTerm> terms;
  const bool two = frfs.yy && !frfs.rigid_y && !modes.y.empty();
  std::vector<Complex> poles;
  for (const Mode& m : pole_modes) {
    const double w = omega_of(m.frequency_hz), z = m.damping_ratio;
    const Complex pole(-z * w, w * std::sqrt(std::max(0.0, 1.0 - z * z)));
    // One pole per mode seen in several FRFs (a symmetric tool's x and y, a whirl's): poles within a
    // tenth of the half-power half-width ζω are one, as a near-repeated column would leave the
    // residues all but undetermined.
    if (std::none_of(poles.begin(), poles.end(), [&](Complex p) { return std::abs(p - pole) <= 0.1 * std::abs(pole.real()); }))
      poles.push_back(pole);
  }
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < frfs.xx.size(); ++i) {
    const double f = frfs.xx.frequency_hz[i];
    if (f > 0.0 && f >= band_low_hz && f <= band_high_hz) rows.push_back(i);
  }
  double direct = 0.0;  // ‖G_xx‖² (+ ‖G_yy‖²) over the band
  for (std::size_t i : rows) direct += std::norm(frfs.xx.values[i]) + (two ? std::norm(frfs.yy->values[i]) : 0.0);
  if (rows.empty() || poles.empty() || !(direct > 0.0)) return terms;
  const Eigen::Index m = static_cast<Eigen::Index>(rows.size()), np = static_cast<Eigen::Index>(poles.size());
  const auto at = [&](Eigen::Index r) { return Complex(0.0, omega_of(frfs.xx.frequency_hz[rows[static_cast<std::size_t>(r)]])); };
  // Columns: Re R and Im R of each pole, R/(iω − λ) + R̄/(iω − λ̄) = Re R (e + ē') + Im R i(e − ē'),
  // e = 1/(iω − λ), ē' = 1/(iω − λ̄); real and imaginary parts of the FRF stacked as rows.
  Eigen::MatrixXd a(2 * m, 2 * np);
  for (Eigen::Index r = 0; r < m; ++r)
    for (Eigen::Index k = 0; k < np; ++k) {
      const Complex pole = poles[static_cast<std::size_t>(k)];
      const Complex e = 1.0 / (at(r) - pole), eb = 1.0 / (at(r) - std::conj(pole));
      const Complex re = e + eb, im = Complex(0.0, 1.0) * (e - eb);
      a(r, 2 * k) = re.real();
      a(m + r, 2 * k) = re.imag();
      a(r, 2 * k + 1) = im.real();
      a(m + r, 2 * k + 1) = im.imag();
    }
  const Eigen::VectorXd scale = a.colwise().norm().transpose().cwiseMax(std::numeric_limits<double>::min());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a * scale.cwiseInverse().asDiagonal());
  // What the real modes leave of a direct FRF: G − Σ 1/(m_r(ω_r² − ω² + 2iζ_rω_rω)) (Mode).
  const auto modal = [&](const std::vector<Mode>& list, Complex s) {
    Complex g = 0.0;
    for (const Mode& q : list) {
      const double w = omega_of(q.frequency_hz);
      g += 1.0 / (q.mass_kg * (s * s + 2.0 * q.damping_ratio * w * s + w * w));
    }
    return g;
  };
  double misfit = 0.0;
  for (int entry = 0; entry < (two ? 4 : 1); ++entry) {  // xx, yy, xy, yx
    const int to = entry == 0 || entry == 2 ? 0 : 1, from = entry == 0 || entry == 3 ? 0 : 1;
    const std::optional<FrfSeries>& cross = entry == 2 ? frfs.xy : frfs.yx;
    const FrfSeries* g = entry == 0 ? &frfs.xx : entry == 1 ? &*frfs.yy : cross ? &*cross : nullptr;
    if (!g) continue;
    Eigen::VectorXd b(2 * m);
    for (Eigen::Index r = 0; r < m; ++r) {
      Complex v = g->values[rows[static_cast<std::size_t>(r)]];
      if (to == from) v -= modal(to == 0 ? modes.x : modes.y, at(r));
      b(r) = v.real();
      b(m + r) = v.imag();
    }
    if (b.isZero(0.0)) continue;  // nothing left to fit (no coupling this way): no terms
    const Eigen::VectorXd x = scale.cwiseInverse().asDiagonal() * qr.solve(b);
    misfit += (a * x - b).squaredNorm();
    for (Eigen::Index k = 0; k < np; ++k)
      terms.push_back({to, from, poles[static_cast<std::size_t>(k)], Complex(x(2 * k), x(2 * k + 1))});
  }
  residual = std::sqrt(misfit / direct);
  return terms;
}

namespace {

// A lowest stable depth beyond any cutting edge (plausibility.hpp's kDepth) is not a result but
// a unit slip in what made it: said, since the lobes themselves are computed correctly.
void judge_lowest_depth(LobesStudyResult& res) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const EnvelopePoint& e : res.envelope)
    if (std::isfinite(e.depth_m)) lowest = std::min(lowest, e.depth_m);
  if (std::isfinite(lowest) && lowest > plausible::kDepth.high)
    res.warnings.push_back(fmt::format(
        "the lowest stable depth is {:.4g} mm, beyond any cutting edge (usually up to {:g} mm): the FRF or modes are far too "
        "stiff or the cutting coefficients far too small for a real cut; check their units (receptance m/N, modal mass kg, "
        "frequency Hz, K_t N/m²)",
        lowest * 1e3, plausible::kDepth.high * 1e3));
}

ZeroOrderOptions zero_order_options(const LobesStudyOptions& options, const SpeedRange& speeds) {
  ZeroOrderOptions zo;
  zo.lobes = options.lobes;
  zo.speeds = speeds;
  zo.max_depth_m = options.max_depth_m;
  return zo;
}

// The zero-order result's warnings, envelope, best speeds, figure and depth judgement.
void finish_zero_order(LobesStudyResult& res, const LobesStudyOptions& options) {
  res.warnings.insert(res.warnings.end(), res.zero_order->warnings.begin(), res.zero_order->warnings.end());
  res.envelope = res.zero_order->envelope;
  res.pockets = stability_pockets(res.envelope, options.pockets, options.pocket_prominence);
  res.pocket_depth_error_m.assign(res.pockets.size(), kNaN);
  const DepthAxis axis = depth_axis(res.envelope);
  res.figure = zero_order_figure(*res.zero_order, 2.0 * axis.top_m);
  set_depth_axis(res.figure, axis);
  judge_lowest_depth(res);
}

BoundaryOptions boundary_options(const LobesStudyOptions& options, const SpeedRange& speeds, const ProgressCallback& progress) {
  BoundaryOptions bo;
  bo.speeds = speeds;
  bo.tolerance = options.tolerance;
  bo.steps = options.steps;
  bo.degree = options.degree;
  if (options.method == LobesMethod::SemiDiscretization) {  // its order: 0 or 1 (LobesStudyOptions::degree)
    bo.scheme = Discretization::Semi;
    bo.degree = std::min(options.degree, 1);
  }
  bo.max_depth_m = options.max_depth_m;
  bo.parallel = options.parallel;
  if (progress) bo.progress = progress;
  return bo;
}

// The time-domain result's warnings, envelope, best speeds (with their error estimates), figure
// and depth judgement.
void finish_boundary(LobesStudyResult& res, const LobesStudyOptions& options) {
  res.warnings.insert(res.warnings.end(), res.boundary->warnings.begin(), res.boundary->warnings.end());
  res.envelope = boundary_envelope(*res.boundary);
  // Speeds stable up to the ceiling form a plateau at the ceiling: a pocket at least that deep
  // (lobe −1, reported as "≥").
  res.pockets = stability_pockets(res.envelope, options.pockets, options.pocket_prominence);
  for (const EnvelopePoint& p : res.pockets) {
    double error = kNaN;
    if (p.lobe >= 0)
      for (const BoundaryPoint& b : res.boundary->boundary)
        if (b.speed_rpm == p.speed_rpm) error = b.depth_error_m;
    res.pocket_depth_error_m.push_back(error);
  }
  res.figure = boundary_figure(*res.boundary);
  set_depth_axis(res.figure, depth_axis(res.envelope));
  judge_lowest_depth(res);
}

bool same_frfs(const MillingFrfs& a, const MillingFrfs& b) {
  const auto same = [](const std::optional<FrfSeries>& p, const std::optional<FrfSeries>& q) {
    return p.has_value() == q.has_value() && (!p || p->values == q->values);
  };
  return a.xx.values == b.xx.values && same(a.yy, b.yy) && same(a.xy, b.xy) && same(a.yx, b.yx);
}

// One speed's modal model for the time domain: the x and y modes fitted to G_xx and G_yy as
// time_domain_modes does and, where x and y are coupled, residue terms (fit_residue_terms) for the
// whole block over the fits' bands.
struct SpeedModes {
  ModalModel model;
  std::vector<ModalFitSummary> fits;
  std::vector<std::string> warnings;
  double residual = 0.0;        // the direct real-mode fits' largest residual
  double block_residual = 0.0;  // the whole model's against the block (fit_residue_terms'; uncoupled: `residual`)
};

SpeedModes speed_modes(const MillingFrfs& g, const LobesStudyOptions& options, const std::string& name) {
  SpeedModes out;
  LobesInput in;
  in.frfs = g;
  in.frf_name = name + " x–x";
  in.frf_y_name = name + " y–y";
  out.model = time_domain_modes(in, options.fit, options.fit_target, out.fits, out.warnings, true);
  double low = std::numeric_limits<double>::infinity(), high = 0.0;
  for (const ModalFitSummary& f : out.fits) {
    out.residual = std::max(out.residual, f.residual);
    low = std::min(low, f.band_low_hz);
    high = std::max(high, f.band_high_hz);
  }
  const bool coupled = g.xy && g.yx && g.yy && !g.rigid_y &&
                       (std::any_of(g.xy->values.begin(), g.xy->values.end(), [](Complex v) { return v != 0.0; }) ||
                        std::any_of(g.yx->values.begin(), g.yx->values.end(), [](Complex v) { return v != 0.0; }));
  out.block_residual = out.residual;
  if (!coupled) return out;
  // The poles: the whirls' first. A forward and a backward whirl closer than their damping look like
  // one mode in G_xx and G_yy, but the cross FRF is their difference, which one pole cannot give;
  // G_± = ½(G_xx + G_yy) ± ½i(G_xy − G_yx) hold one whirl each (exactly so for an axisymmetric
  // spindle, where G_xy = −G_yx = ∓½i(G_f − G_b)), so their fitted modes separate them.
  std::vector<Mode> poles;
  for (const double sign : {1.0, -1.0}) {
    FrfSeries whirl = g.xx;
    for (std::size_t i = 0; i < whirl.size(); ++i)
      whirl.values[i] = 0.5 * (g.xx.values[i] + g.yy->values[i]) +
                        sign * 0.5 * Complex(0.0, 1.0) * (g.xy->values[i] - g.yx->values[i]);
    try {
      ModalFitSummary s;
      std::vector<std::string> ignored;  // the whirl fits only place poles: the residues are fitted below
      const std::vector<Mode> m = fit_milling_modes(whirl, name + (sign > 0 ? " G+" : " G-"), options.fit, options.fit_target, s,
                                                    ignored);
      poles.insert(poles.end(), m.begin(), m.end());
    } catch (const InputError&) {
      // not a passive whirl FRF (strongly anisotropic): the direct modes' poles alone
    } catch (const NumericalError&) {}
  }
  poles.insert(poles.end(), out.model.x.begin(), out.model.x.end());
  poles.insert(poles.end(), out.model.y.begin(), out.model.y.end());
  out.model.terms = fit_residue_terms(g, out.model, poles, low, high, out.block_residual);
  // The real modes' shortfall is what the terms complete: judged on the whole model instead.
  out.warnings.erase(std::remove_if(out.warnings.begin(), out.warnings.end(),
                                    [](const std::string& w) {
                                      return w.find("fitted poorly") != std::string::npos ||
                                             w.find("the best modal model represents") != std::string::npos;
                                    }),
                     out.warnings.end());
  if (out.block_residual > options.fit_target)
    out.warnings.push_back(fmt::format(
        "{}: the modal model with its pole-residue terms represents the x–y block within {:.1f} % over {:g}–{:g} Hz, not "
        "the {:.3g} % aimed at. The lobes are those of this model. Narrow the fitted band to the modes that matter "
        "(LobesStudyOptions::fit)",
        name, 100.0 * out.block_residual, low, high, 100.0 * options.fit_target));
  return out;
}

// The time-domain boundary with speed-dependent FRFs: at each speed n of the grid a modal model
// fitted to G(·; n) (SpeedDependentFrfs::at; speed_modes: real modes and pole-residue terms), the
// boundary from each speed's own model (stability_boundary of models per speed), the starting guesses
// from the zero-order lobes of the same FRFs. FRFs that do not change with speed are fitted once,
// and without terms the boundary is stability_boundary of that one model (today's).
void speed_dependent_boundary(LobesStudyResult& res, const SpeedDependentFrfs& frfs, const LobesStudyOptions& options,
                              const std::string& name, const ProgressCallback& progress) {
  const std::vector<double> speeds = res.speeds.values();
  bool constant = true;
  for (const MillingFrfs& g : frfs.frfs) constant = constant && same_frfs(g, frfs.frfs.front());
  std::vector<SpeedModes> fitted(constant ? 1 : speeds.size());
  parallel_for(fitted.size(), options.parallel,
               [&](std::size_t i) { fitted[i] = speed_modes(frfs.at(speeds[i]), options, name); });
  if (progress) progress(0.1);
  std::size_t worst = 0, worst_block = 0;
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    if (fitted[i].residual > fitted[worst].residual) worst = i;
    if (fitted[i].block_residual > fitted[worst_block].block_residual) worst_block = i;
  }
  const std::string where = constant ? "" : fmt::format(" at {:.0f} rpm", speeds[worst]);
  for (const std::string& w : fitted[worst].warnings) res.warnings.push_back(w + where);
  res.modes = fitted[worst].model;
  res.fits = fitted[worst].fits;
  res.fit_residual = fitted[worst].residual;
  res.block_fit_residual = fitted[worst_block].block_residual;
  res.warnings.push_back(fmt::format(
      "the time-domain model at speed: {} modal model(s) fitted to the x–y tool point FRF{} (real modes to G_xx and G_yy, "
      "and where x and y couple, pole-residue terms with complex residues to the whole 2×2 block); largest residual of the "
      "real modes {:.2g} % of the direct FRF{}, of the whole model against the block {:.2g} % of the direct FRFs{}",
      fitted.size(), constant ? " (the same at every speed)" : ", one per speed of the grid", 100.0 * res.fit_residual, where,
      100.0 * res.block_fit_residual, constant ? "" : fmt::format(" at {:.0f} rpm", speeds[worst_block])));
  const ProgressCallback rest = [&](double f) {
    if (progress) progress(0.1 + 0.9 * f);
  };
  if (constant && fitted.front().model.terms.empty()) {
    res.boundary = stability_boundary(fitted.front().model, options.cutting, boundary_options(options, res.speeds, rest));
  } else {
    std::vector<ModalModel> models;
    models.reserve(speeds.size());
    for (std::size_t i = 0; i < speeds.size(); ++i) models.push_back(fitted[constant ? 0 : i].model);
    CuttingConditions even = options.cutting;  // the guesses: the even tool's zero-order lobes (stability_boundary)
    even.pitch_rad.clear();
    even.runout_m.clear();
    even.process_damping_n_per_m = 0.0;
    even.helix_rad.clear();
    ZeroOrderOptions zo;
    zo.speeds = res.speeds;
    const ZeroOrderResult guesses = zero_order_lobes(frfs, even, zo, options.parallel);
    res.boundary = stability_boundary(models, guesses, options.cutting, boundary_options(options, res.speeds, rest));
  }
  finish_boundary(res, options);
}

// The largest |G − G_interpolated| of the midpoints' FRFs (odd indices of `fine`) against the
// interpolation of `coarse` (its even indices), relative to the largest |G| of the midpoint.
double frf_interpolation_error(const SpeedDependentFrfs& fine, const SpeedDependentFrfs& coarse) {
  double worst = 0.0;
  for (std::size_t j = 1; j < fine.speed_rpm.size(); j += 2) {
    const MillingFrfs direct = fine.frfs[j], interpolated = coarse.at(fine.speed_rpm[j]);
    double diff = 0.0, top = 0.0;
    const auto compare = [&](const std::optional<FrfSeries>& a, const std::optional<FrfSeries>& b) {
      if (!a) return;
      for (std::size_t i = 0; i < a->size(); ++i) {
        diff = std::max(diff, std::abs(a->values[i] - b->values[i]));
        top = std::max(top, std::abs(a->values[i]));
      }
    };
    compare(direct.xx, interpolated.xx);
    compare(direct.yy, interpolated.yy);
    compare(direct.xy, interpolated.xy);
    compare(direct.yx, interpolated.yx);
    if (top > 0.0) worst = std::max(worst, diff / top);
  }
  return worst;
}

// The zero-order lobes of an assembly at speed (LobesStudyOptions::speed_model): the x–y FRF at
// the nodes and their midpoints, the lobes from all of them, and from the nodes alone for the
// error estimate.
LobesStudyResult at_speed_lobes_study(const LobesInput& input, const LobesStudyOptions& options, SpeedModel model,
                                      const ProgressCallback& report) {
  LobesStudyResult res;
  res.method = options.method;
  res.cutting = options.cutting;
  res.speeds = options.speeds;
  const bool fd = time_domain(options.method);
  if (res.speeds.points == 0) res.speeds.points = fd ? 200 : 2000;
  res.speed_model = model;
  const Assembly& a = *input.assembly;
  const int nodes = options.speed_nodes > 0 ? options.speed_nodes : 17;
  std::vector<double> fine;
  const double lo = res.speeds.min_rpm, hi = res.speeds.max_rpm;
  for (int j = 0; j <= 2 * (nodes - 1); ++j) fine.push_back(j == 2 * (nodes - 1) ? hi : lo + (hi - lo) * j / (2.0 * (nodes - 1)));
  SpeedDependentFrfs all;
  try {
    all = milling_frfs_at_speeds(a, a.grid.values(), fine, model == SpeedModel::Spinning, options.extrapolate_bearings,
                                 input.rigid_y, options.parallel);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("LobesStudyOptions::speeds: {}", e.what()),
                          std::string(e.hint()).find("extrapolat") != std::string::npos
                              ? "narrow the speed range to the table's, extend the table, or set "
                                "LobesStudyOptions::extrapolate_bearings"
                              : e.hint());
  }
  if (report) report(fd ? 0.2 : 0.8);
  SpeedDependentFrfs coarse;
  for (std::size_t j = 0; j < fine.size(); j += 2) {
    coarse.speed_rpm.push_back(all.speed_rpm[j]);
    coarse.frfs.push_back(all.frfs[j]);
  }
  // The time domain: the envelope error of the interpolation estimated from the zero-order lobes of
  // the same FRFs (its sensitivity to the FRF is the same cut's; a second boundary would double the
  // work), with the even tool's cut (zero_order_lobes takes no pitch, runout, helix or process damping).
  CuttingConditions cut = options.cutting;
  if (fd) {
    cut.pitch_rad.clear();
    cut.runout_m.clear();
    cut.process_damping_n_per_m = 0.0;
    cut.helix_rad.clear();
  }
  // (On the zero-order method's fine grid: the boundary's few speeds may all be nodes, where the
  // interpolation has no error to show.)
  const ZeroOrderOptions zo = zero_order_options(options, fd ? SpeedRange{lo, hi, 2000} : res.speeds);
  const ZeroOrderResult from_all = zero_order_lobes(all, cut, zo, options.parallel);
  const ZeroOrderResult from_nodes = zero_order_lobes(coarse, cut, zo, options.parallel);
  res.frf_speeds_rpm = all.speed_rpm;
  res.frf_interpolation_error = frf_interpolation_error(all, coarse);
  res.envelope_interpolation_error = 0.0;
  for (std::size_t j = 0; j < from_all.envelope.size(); ++j) {
    const double d = from_all.envelope[j].depth_m, c = from_nodes.envelope[j].depth_m;
    if (std::isfinite(d) && std::isfinite(c) && d > 0.0)
      res.envelope_interpolation_error = std::max(res.envelope_interpolation_error, std::abs(d - c) / d);
  }
  if (!fd) res.zero_order = from_all;
  const AssemblyModel first(has_speed_tables(a) ? at_speed(a, lo, true) : a);
  res.warnings = first.warnings();
  res.warnings.push_back(fmt::format(
      "the lobes use the tool point FRF at each spindle speed ({}): in x and y (H_xx, H_xy, H_yx, H_yy){}{}, evaluated at {} "
      "speeds over {:g}–{:g} rpm and interpolated linearly in speed between them; interpolation error estimated at {:.2g} % "
      "of the FRF and {:.2g} % of the stable depth (the {}lobes from every other of these speeds against all of them)",
      to_string(model), model == SpeedModel::Spinning ? ", the spindle spinning (gyroscopic moments)" : ", at rest",
      has_speed_tables(a) ? ", the bearings' speed tables read at each speed" : "", fine.size(), lo, hi,
      100.0 * res.frf_interpolation_error, 100.0 * res.envelope_interpolation_error, fd ? "zero-order " : ""));
  if (res.envelope_interpolation_error > 0.01)
    res.warnings.push_back(fmt::format(
        "the stable depth changes by up to {:.2g} % between the lobes from every other speed and from all: the FRF changes "
        "fast with speed; raise LobesStudyOptions::speed_nodes (now {}) for a smaller error",
        100.0 * res.envelope_interpolation_error, nodes));
  if (fd) {
    speed_dependent_boundary(res, all, options, input.frf_name, [&](double f) {
      if (report) report(0.2 + 0.8 * f);
    });
    return res;
  }
  finish_zero_order(res, options);
  if (report) report(1.0);
  return res;
}

// The study with the joint's constants: the zero-order lobes or the time-domain boundary.
LobesStudyResult nominal_lobes_study(const LobesInput& input, const LobesStudyOptions& options, const ProgressCallback& report) {
  LobesStudyResult res;
  res.method = options.method;
  res.cutting = options.cutting;
  res.speeds = options.speeds;
  if (res.speeds.points == 0) res.speeds.points = options.method == LobesMethod::ZeroOrder ? 2000 : 200;
  if (input.frfs) input.frfs->check(input.frf_name, input.frf_y_name);
  auto progress = [&](double f) {
    if (report) report(f);
  };

  if (time_domain(options.method) && input.speed_frfs) {
    if (!input.x_modes.empty() || !input.y_modes.empty())
      throw InvalidArgument("LobesInput::speed_frfs and modes given (LobesInput::x_modes, y_modes) contradict each other",
                            "drop the modes (they are fitted at each speed), or the FRFs at several speeds");
    res.speed_model = SpeedModel::Bearings;
    res.frf_speeds_rpm = input.speed_frfs->speed_rpm;
    input.speed_frfs->check(input.frf_name);
    res.warnings.push_back(
        fmt::format("the lobes use the tool point FRFs given at {} speeds, interpolated linearly in speed "
                    "between them (LobesInput::speed_frfs)",
                    res.frf_speeds_rpm.size()));
    speed_dependent_boundary(res, *input.speed_frfs, options, input.frf_name, progress);
    return res;
  }
  if (options.method == LobesMethod::ZeroOrder && input.speed_frfs) {
    if (!input.x_modes.empty() || !input.y_modes.empty())
      res.warnings.push_back("the modes given are used by the time-domain method only");
    res.speed_model = SpeedModel::Bearings;
    res.frf_speeds_rpm = input.speed_frfs->speed_rpm;
    input.speed_frfs->check(input.frf_name);
    res.zero_order = zero_order_lobes(*input.speed_frfs, options.cutting, zero_order_options(options, res.speeds),
                                      options.parallel);
    res.warnings.push_back(
        fmt::format("the lobes use the tool point FRFs given at {} speeds, interpolated linearly in speed "
                    "between them (LobesInput::speed_frfs)",
                    res.frf_speeds_rpm.size()));
    finish_zero_order(res, options);
    progress(1.0);
    return res;
  }
  if (options.method == LobesMethod::ZeroOrder) {
    if (!input.frfs)
      throw InvalidArgument("the zero-order method needs the tool point FRFs (LobesInput::frfs)",
                            "give the FRFs, or use the time-domain method with modes");
    if (!input.x_modes.empty() || !input.y_modes.empty())
      res.warnings.push_back("the modes given are used by the time-domain method only");
    res.zero_order = zero_order_lobes(*input.frfs, options.cutting, zero_order_options(options, res.speeds));
    finish_zero_order(res, options);
    progress(1.0);
    return res;
  }

  // The time domain: modes given or fitted (20 % of the progress), then the boundary.
  res.modes = time_domain_modes(input, options.fit, options.fit_target, res.fits, res.warnings);
  progress(0.2);
  res.boundary = stability_boundary(res.modes, options.cutting,
                                    boundary_options(options, res.speeds, [&](double f) { progress(0.2 + 0.8 * f); }));
  finish_boundary(res, options);
  return res;
}

// A study's envelope as the uncertainty module takes it.
StabilityEnvelope envelope_of(const LobesStudyResult& r) {
  StabilityEnvelope e;  // speeds [rpm], depths [m]
  for (const EnvelopePoint& p : r.envelope) {
    e.first.push_back(p.speed_rpm);
    e.second.push_back(p.depth_m);
  }
  return e;
}

// The study with the joint drawn from `input.uncertain_joint` (needs `input.assembly`): the nominal
// study (the file's joint in place of the assembly's), then each sample's envelope on the same
// speeds (envelope_uncertainty), their quantile envelopes, the probability map and the pockets'
// quantiles. With `at_speed`, every envelope is the lobes at speed (at_speed_lobes_study: the
// assembly with the sample's joint evaluated at each speed node), as the nominal's.
LobesStudyResult sampled_lobes_study(const LobesInput& input, const LobesStudyOptions& options,
                                     std::optional<SpeedModel> at_speed, const ProgressCallback& progress) {
  options.uncertainty.check();
  // Each joint sample is one more study like the nominal one.
  const double share = 1.0 / (1.0 + options.uncertainty.samples);
  ProgressCallback nominal;
  if (progress) nominal = [&](double f) { progress(share * f); };
  LobesStudyResult res;
  if (at_speed) {
    // The file's joint is the nominal one (as milling_frfs' model below for the standstill).
    LobesInput n = input;
    n.assembly = with_joint(*input.assembly, *input.uncertain_joint);
    n.uncertain_joint.reset();
    res = at_speed_lobes_study(n, options, *at_speed, nominal);
  } else {
    res = nominal_lobes_study(input, options, nominal);
  }

  double top = 0.0;
  for (const EnvelopePoint& p : res.envelope)
    if (std::isfinite(p.depth_m)) top = std::max(top, p.depth_m);
  std::vector<double> depths;
  for (int j = 0; j <= 200; ++j) depths.push_back(1.5 * top * j / 200);
  UncertaintyOptions draws = options.uncertainty;
  draws.progress = {};
  if (progress) draws.progress = [&](double f) { progress(share + (1.0 - share) * f); };
  if (at_speed) {
    LobesStudyOptions inner = options;
    inner.parallel.threads = 1;  // the samples run on the threads
    const auto envelope = [&](const Assembly& a) {
      LobesInput in;
      in.assembly = a;
      in.rigid_y = input.rigid_y;
      return envelope_of(at_speed_lobes_study(in, inner, *at_speed, {}));
    };
    res.uncertainty = envelope_uncertainty(*input.assembly, *input.uncertain_joint, envelope, depths, draws);
  } else {
    res.uncertainty = stability_uncertainty(*input.assembly, *input.uncertain_joint, input.assembly->grid.values(), options,
                                            depths, draws, input.rigid_in_y());
  }
  res.uncertain_joint = input.uncertain_joint->source;
  const auto quantiles = quantile_envelopes(*res.uncertainty);
  res.figure.other_envelopes.insert(res.figure.other_envelopes.end(), quantiles.begin(), quantiles.end());
  res.probability_figure = probability_map(*res.uncertainty, res.uncertain_joint);
  const StabilityUncertainty& u = *res.uncertainty;
  const auto at = [&](std::size_t k) {
    SpeedQuantiles q{u.speed_rpm[k], u.nominal_depth_m[k], {}};
    for (const auto& level : u.depth_m) q.depth_m.push_back(level[k]);
    return q;
  };
  for (const EnvelopePoint& p : res.pockets) {
    const auto it = std::min_element(u.speed_rpm.begin(), u.speed_rpm.end(),
                                     [&](double a, double b) { return std::abs(a - p.speed_rpm) < std::abs(b - p.speed_rpm); });
    res.pocket_quantiles.push_back(at(static_cast<std::size_t>(it - u.speed_rpm.begin())));
  }
  if (!u.depth_m.empty() && !u.speed_rpm.empty()) {
    const auto& first = u.depth_m.front();
    res.worst_speed = at(static_cast<std::size_t>(std::min_element(first.begin(), first.end()) - first.begin()));
  }
  return res;
}

}  // namespace

namespace {

// run_lobes_study but for the echo of its options.
LobesStudyResult lobes_study_of(const LobesInput& input, const LobesStudyOptions& options, const ProgressCallback& progress) {
  options.check();
  if (input.uncertain_joint && !input.assembly)
    throw InvalidArgument("LobesInput::uncertain_joint needs LobesInput::assembly (the joint is sampled inside the model)",
                          "give the assembly whose tool point FRF LobesInput::frfs is");
  if (!input.assembly && (options.speed_model == SpeedModel::Bearings || options.speed_model == SpeedModel::Spinning))
    throw InvalidArgument(fmt::format("LobesStudyOptions::speed_model {} evaluates an assembly at each speed: it needs "
                                      "LobesInput::assembly",
                                      to_string(options.speed_model)),
                          "give the assembly, or SpeedModel::Automatic / Standstill for the FRFs given");
  if (input.speed_frfs && input.uncertain_joint)
    throw InvalidArgument("LobesInput::speed_frfs (FRFs at several speeds) are not for an uncertain joint",
                          "give one FRF (LobesInput::frfs), or drop LobesInput::uncertain_joint");
  if (!input.frfs && !input.speed_frfs && input.assembly && lobes_at_speed(*input.assembly, options.speed_model)) {
    const SpeedModel model = options.speed_model == SpeedModel::Automatic ? SpeedModel::Spinning : options.speed_model;
    if (input.uncertain_joint) return sampled_lobes_study(input, options, model, progress);
    return at_speed_lobes_study(input, options, model, progress);
  }
  if (!input.frfs && input.assembly) {
    LobesInput with_frfs = input;
    // A sampled joint file's joint is the nominal one, so the nominal envelope and the samples'
    // describe the same joint (each sample replaces the assembly's joint too).
    const AssemblyModel model(input.uncertain_joint ? with_joint(*input.assembly, *input.uncertain_joint) : *input.assembly);
    with_frfs.frfs = milling_frfs(model, input.assembly->grid.values(), input.rigid_y);
    LobesStudyResult r = run_lobes_study(with_frfs, options, progress);
    const std::vector<std::string> w = model.warnings();  // by value: one vector for both iterators
    r.warnings.insert(r.warnings.begin(), w.begin(), w.end());
    return r;
  }
  if (!input.uncertain_joint) return nominal_lobes_study(input, options, progress);
  return sampled_lobes_study(input, options, std::nullopt, progress);
}

}  // namespace

LobesStudyResult run_lobes_study(const LobesInput& input, const LobesStudyOptions& options, const ProgressCallback& progress) {
  LobesStudyResult r = lobes_study_of(input, options, progress);
  r.options = options;
  return r;
}

StabilityUncertainty stability_uncertainty(const Assembly& assembly, const JointFile& joint,
                                           const std::vector<double>& frequency_hz, const LobesStudyOptions& lobes,
                                           const std::vector<double>& depth_grid_m, const UncertaintyOptions& o, bool rigid_y) {
  o.check();
  lobes.check();
  LobesStudyOptions inner = lobes;
  inner.parallel.threads = 1;
  const auto envelope = [&](const Assembly& a) {
    LobesInput in;
    in.frfs = milling_frfs(AssemblyModel(a), frequency_hz, rigid_y);
    return envelope_of(nominal_lobes_study(in, inner, {}));
  };
  return envelope_uncertainty(assembly, joint, envelope, depth_grid_m, o);
}

}  // namespace toolpoint
