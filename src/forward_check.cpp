// toolpoint: the forward check of an identified joint (forward_check.hpp).
#include "toolpoint/identify/forward_check.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/statistics.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint {

namespace {


struct Window {
  double model_hz = 0.0, lo_hz = 0.0, hi_hz = 0.0;
  double valley_lo_hz = 0.0, valley_hi_hz = 0.0;  // the valleys to the neighbouring modes (the widest it may be)
};

// What one data set (measured or a replicate) shows, mode by mode.
struct Observation {
  std::vector<std::optional<Peak>> measured, predicted;  // the highest prominent peak in each window
  std::vector<double> window_prominence;                 // the most prominent local maximum of the measured data there (0: none)
  std::vector<Peak> extra;                               // prominent measured peaks in no window
  double max_extra = 0.0;                                // the largest prominence among them (0: none)
};

FrfSeries smoothed_h(const std::vector<double>& f, const std::vector<Block>& g, const std::optional<SavgolOptions>& s) {
  FrfSeries h;
  h.frequency_hz = f;
  h.values.reserve(g.size());
  for (const Block& b : g) h.values.push_back(b(0, 0));
  if (s && h.size() >= static_cast<std::size_t>(s->window)) h = savgol_filter(h, *s, "forward check").series;
  return h;
}

std::vector<Block> predicted(const JointFitData& d, const std::vector<Block>& B, const std::vector<Block>& K) {
  std::vector<Block> out(B.size());
  for (std::size_t i = 0; i < B.size(); ++i) out[i] = forward_g11(d.A[i], B[i], K[i]);
  return out;
}

// The windows of G_ref's modes (forward_check.hpp): ± twice the half-power half-width, at least
// three grid steps, never past the valleys between neighbouring modes.
std::vector<Window> windows_of(const FrfSeries& ref, const std::vector<Peak>& modes) {
  const std::size_t n = ref.size();
  std::vector<double> m(n);
  for (std::size_t i = 0; i < n; ++i) m[i] = std::abs(ref.values[i]);
  std::vector<Window> out;
  for (std::size_t k = 0; k < modes.size(); ++k) {
    const std::size_t i = modes[k].index;
    // Valleys: the minimum between this mode and each neighbour (or the end of the band).
    const std::size_t left_end = k > 0 ? modes[k - 1].index : 0, right_end = k + 1 < modes.size() ? modes[k + 1].index : n - 1;
    std::size_t vl = i, vr = i;
    for (std::size_t j = i; j-- > left_end;)
      if (m[j] < m[vl]) vl = j;
    for (std::size_t j = i + 1; j <= right_end; ++j)
      if (m[j] < m[vr]) vr = j;
    // Half-power points, walking out from the peak no further than the valleys.
    const double half = m[i] / std::sqrt(2.0);
    std::size_t a = i, b = i;
    while (a > vl && m[a] > half) --a;
    while (b < vr && m[b] > half) ++b;
    const double step = ref.frequency_hz[std::min(i + 1, n - 1)] - ref.frequency_hz[i > 0 ? i - 1 : 0];
    const double w = std::max(ref.frequency_hz[b] - ref.frequency_hz[a], 1.5 * step);
    Window win;
    win.model_hz = modes[k].frequency_hz;
    win.valley_lo_hz = ref.frequency_hz[vl];
    win.valley_hi_hz = ref.frequency_hz[vr];
    win.lo_hz = std::max(win.model_hz - w, win.valley_lo_hz);
    win.hi_hz = std::min(win.model_hz + w, win.valley_hi_hz);
    out.push_back(win);
  }
  return out;
}

Observation observe(const FrfSeries& meas, const FrfSeries& pred, const std::vector<Window>& win, double min_prominence) {
  const std::vector<Peak> mp = find_peaks(meas, PeakOptions{min_prominence});
  const std::vector<Peak> pp = find_peaks(pred, PeakOptions{min_prominence});
  const std::vector<Peak> all = find_peaks(meas, PeakOptions{0.0});
  Observation o;
  auto highest_in = [](const std::vector<Peak>& peaks, const Window& w) {
    std::optional<Peak> best;
    for (const Peak& p : peaks)
      if (p.frequency_hz >= w.lo_hz && p.frequency_hz <= w.hi_hz && (!best || p.magnitude > best->magnitude)) best = p;
    return best;
  };
  for (const Window& w : win) {
    o.measured.push_back(highest_in(mp, w));
    o.predicted.push_back(highest_in(pp, w));
    double prom = 0.0;
    for (const Peak& p : all)
      if (p.frequency_hz >= w.lo_hz && p.frequency_hz <= w.hi_hz) prom = std::max(prom, p.prominence);
    o.window_prominence.push_back(prom);
  }
  for (const Peak& p : mp) {
    const bool inside = std::any_of(win.begin(), win.end(),
                                    [&](const Window& w) { return p.frequency_hz >= w.lo_hz && p.frequency_hz <= w.hi_hz; });
    if (inside) continue;
    o.extra.push_back(p);
    o.max_extra = std::max(o.max_extra, p.prominence);
  }
  return o;
}

// The modes of G_ref: its peaks of at least `min_prominence` that also stand clear of the ripple
// B11's noise leaves in G_ref. B̄11 keeps part of the measured noise (the 7-point cubic passes a
// third of its variance); carried through the forward model and the smoothing it makes ripples
// that are no modes — where the model amplifies B11's noise (rotational entries from finite
// differences carry 10 % and more; an additive floor makes B11 noisier than its value away from
// its peaks) they exceed any fixed prominence. The ripple's size at each frequency, σ_i, is the
// rms deviation from G_ref of predictions from B̄11 with fresh noise (`ripple` replicates; this is
// more than the part left in B̄11, and it holds where the model is far from linear in B11). A
// peak counts when its height above its higher valley exceeds kModeClearance √2 σ at the peak.
// Weak modes count too: a peak down to kWeakMode × min_prominence that stands clear of the ripple
// is a mode of the model (the example's 1.6 kHz mode stands 4 % above its valley). It gets a
// window like any other, so data that show it are explained by it; the noise usually hides it
// (not resolved, not judged). Without its window, noisy data that happened to show it more
// prominently than any replicate failed the rank test below: 4 of 400 data sets from the true
// joint at 5 % noise (twice the rate the test allows), none with it (docs/noise-and-verdict.md).
constexpr double kWeakMode = 0.2;
constexpr std::size_t kRippleReplicates = 50;

std::vector<Peak> reference_modes(const JointFitData& d, const BlockSeries& B_ref, const std::vector<Block>& K,
                                  const FrfSeries& ref, const std::optional<SavgolOptions>& smoothing, double min_prominence,
                                  std::uint64_t seed, const ParallelOptions& parallel) {
  std::vector<Peak> peaks = find_peaks(ref, PeakOptions{min_prominence});
  if (d.b_noise.exact() || peaks.empty()) return peaks;
  const std::size_t n = ref.size();
  std::vector<std::vector<double>> dev(kRippleReplicates);
  parallel_for(kRippleReplicates, parallel, [&](std::size_t r) {
    const BlockSeries Bs = draw_block_noise(B_ref, d.b_noise, stream_seed(seed, 0x919E + r), false);
    const FrfSeries h = smoothed_h(ref.frequency_hz, predicted(d, Bs.blocks, K), smoothing);
    dev[r].resize(n);
    for (std::size_t i = 0; i < n; ++i) dev[r][i] = std::norm(h.values[i] - ref.values[i]);
  });
  std::vector<Peak> out;
  for (const Peak& p : peaks) {
    double ms = 0.0;
    for (const auto& v : dev) ms += v[p.index];
    const double sigma = std::sqrt(ms / static_cast<double>(dev.size()));
    if (p.prominence * std::abs(ref.values[p.index]) > kModeClearance * std::sqrt(2.0) * sigma) out.push_back(p);
  }
  return out;
}

double relative(double predicted, double measured) { return (predicted - measured) / measured; }

// Each mode's ModeCheck::clearance: its height above its higher valley in G_ref over √2 σ, σ the
// standard deviation G11's own noise leaves in H at the peak after the check's smoothing (the
// noise taken white over the smoother's window, whose centre weights c_j pass Σ c_j² of its
// variance). B11's noise is the ripple's business (reference_modes); the two are not added, as a
// mode must clear each.
std::vector<double> clearances(const JointFitData& d, const BlockSeries& G_ref, const FrfSeries& ref,
                               const std::vector<Peak>& modes, const std::optional<SavgolOptions>& smoothing) {
  if (d.g_noise.exact()) return std::vector<double>(modes.size(), std::numeric_limits<double>::infinity());
  double gain = 1.0;
  if (smoothing) {
    gain = 0.0;
    for (double c : savgol_coefficients(*smoothing)) gain += c * c;
  }
  std::vector<double> out;
  for (const Peak& p : modes) {
    // H is the block's first entry: the real and imaginary parts are the first two of the eight.
    const Cov8 S = d.g_noise.absolute(p.index, G_ref.blocks[p.index]);
    const double sigma = std::sqrt(0.5 * (S(0, 0) + S(1, 1)) * gain);
    out.push_back(p.prominence * std::abs(ref.values[p.index]) / (std::sqrt(2.0) * sigma));
  }
  return out;
}

}  // namespace

const char* to_string(ModeAgreement a) {
  switch (a) {
    case ModeAgreement::Agrees: return "agrees";
    case ModeAgreement::WithinTolerance: return "within tolerance";
    case ModeAgreement::Differs: return "differs";
    case ModeAgreement::NotResolved: return "not resolved";
    case ModeAgreement::Missing: return "missing";
  }
  return "?";
}

void ForwardCheckOptions::check() const {
  if (smoothing) {
    try {
      smoothing->check();
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(fmt::format("ForwardCheckOptions::smoothing: {}", e.what()), e.hint());
    }
  }
  check_fields(forward_check_fields(), *this, "ForwardCheckOptions");  // the scalar fields' ranges
  if (1.0 / (1.0 + replicates) > 0.5 * false_alarm)
    throw InvalidArgument(fmt::format("ForwardCheckOptions::replicates = {} are too few for a false-alarm probability of {}: "
                                      "the rank test needs 1/(1 + replicates) ≤ false_alarm/2",
                                      replicates, false_alarm),
                          fmt::format("use at least {} replicates", static_cast<int>(std::ceil(2.0 / false_alarm - 1.0))));
  parallel.check();
}

const std::vector<OptionField<ForwardCheckOptions>>& forward_check_fields() {
  using O = ForwardCheckOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "min_prominence",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "a peak counts when it stands this fraction above its valleys (0.1: 10 %)"},
       [](O& o) -> double& { return o.min_prominence; }},
      {{.name = "replicates",
        .kind = FieldKind::Integer,
        .min = 50.0,
        .max = 100000.0,
        .help = "Monte Carlo replicates of the noise (the rank test needs 1/(1 + replicates) ≤ false_alarm/2)"},
       nullptr,
       [](O& o) -> int& { return o.replicates; }},
      {{.name = "false_alarm",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 0.5,
        .min_open = true,
        .max_open = true,
        .help = "P(fail) for data made by the identified model with the stated noise (0.01: one data set in a hundred)"},
       [](O& o) -> double& { return o.false_alarm; }},
      {{.name = "frequency_tolerance",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 1.0,
        .min_open = true,
        .max_open = true,
        .help = "relative natural-frequency error that matters (a fraction)"},
       [](O& o) -> double& { return o.frequency_tolerance; }},
      {{.name = "peak_tolerance",
        .kind = FieldKind::Real,
        .min = 0.0,
        .max = 10.0,
        .min_open = true,
        .max_open = true,
        .help = "relative peak-height error that matters (a fraction)"},
       [](O& o) -> double& { return o.peak_tolerance; }},
      {{.name = "shared_calibration",
        .kind = FieldKind::Flag,
        .help = "B11 and G11 share one calibration factor (one sensor chain)"},
       nullptr,
       nullptr,
       [](O& o) -> bool& { return o.shared_calibration; }},
  };
  return fields;
}

namespace {

// K(ω) of `joint` on the grid.
std::vector<Block> stiffness_on(const JointParameters& joint, const std::vector<double>& f) {
  std::vector<Block> k(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) k[i] = joint.stiffness(f[i]);
  return k;
}

// Each mode's window made at least 4 standard deviations of its frequency wide over the drawn
// joints `thetas`, within its valleys: each mode followed as the highest peak between its valleys
// (noise ripple on its flanks is lower), over up to 40 of them.
void widen_windows(std::vector<Window>& win, const JointFitData& d, const BlockSeries& B_ref,
                   const std::vector<JointParameters>& thetas, const std::optional<SavgolOptions>& smoothing,
                   double min_prominence) {
  const std::vector<double>& f = d.G11.frequency_hz;
  std::vector<std::vector<double>> fm(win.size());
  for (std::size_t r = 0; r < std::min<std::size_t>(thetas.size(), 40); ++r) {
    const std::vector<Peak> pk = find_peaks(smoothed_h(f, predicted(d, B_ref.blocks, stiffness_on(thetas[r], f)), smoothing),
                                            PeakOptions{min_prominence});
    for (std::size_t m = 0; m < win.size(); ++m) {
      const Peak* best = nullptr;
      for (const Peak& p : pk)
        if (p.frequency_hz >= win[m].valley_lo_hz && p.frequency_hz <= win[m].valley_hi_hz &&
            (!best || p.magnitude > best->magnitude))
          best = &p;
      if (best) fm[m].push_back(best->frequency_hz);
    }
  }
  for (std::size_t m = 0; m < win.size(); ++m) {
    const MeanSd ms = mean_sd(fm[m]);
    if (!std::isfinite(ms.sd)) continue;
    win[m].lo_hz = std::max(std::min(win[m].lo_hz, win[m].model_hz - 4.0 * ms.sd), win[m].valley_lo_hz);
    win[m].hi_hz = std::min(std::max(win[m].hi_hz, win[m].model_hz + 4.0 * ms.sd), win[m].valley_hi_hz);
  }
}

// The replicates: data drawn around the reference world (B̄11 and G_ref, or G from a drawn joint),
// each observed as the measured data are (o.replicates of them, in parallel, identical for any
// thread count).
std::vector<Observation> replicate_observations(const JointFitData& d, const BlockSeries& B_ref, const BlockSeries& G_ref,
                                                const std::vector<Block>& K, const std::vector<JointParameters>& thetas,
                                                const std::vector<Window>& win, const std::optional<SavgolOptions>& smoothing,
                                                const ForwardCheckOptions& o) {
  const std::vector<double>& f = d.G11.frequency_hz;
  std::vector<Observation> reps(static_cast<std::size_t>(o.replicates));
  parallel_for(reps.size(), o.parallel, [&](std::size_t r) {
    const std::uint64_t base = stream_seed(o.seed, r);
    const bool shared = o.shared_calibration;
    // The world's truth: the joint is the identified one give or take its uncertainty (θ* drawn),
    // so the data may show the modes where such joints put them; the prediction is made with
    // the identified joint, as for the measured data.
    BlockSeries truth;
    if (!thetas.empty()) {
      truth.frequency_hz = f;
      truth.blocks = predicted(d, B_ref.blocks, stiffness_on(thetas[r], f));
    }
    BlockSeries Bs = draw_block_noise(B_ref, d.b_noise, stream_seed(base, 1), !shared);
    BlockSeries Gs = draw_block_noise(thetas.empty() ? G_ref : truth, d.g_noise, stream_seed(base, 2), !shared);
    if (shared) {
      const double sigma = std::max(d.b_noise.calibration, d.g_noise.calibration);
      const double scale = 1.0 + sigma * calibration_normal(stream_seed(base, 3));
      for (Block& x : Bs.blocks) x *= scale;
      for (Block& x : Gs.blocks) x *= scale;
    }
    reps[r] = observe(smoothed_h(f, Gs.blocks, smoothing), smoothed_h(f, predicted(d, Bs.blocks, K), smoothing), win,
                      o.min_prominence);
  });
  return reps;
}

// Each mode's ModeCheck from the observation and the replicates' statistics, into out.modes;
// returns the number of z-tests they will take (two per mode seen, one per mode that may be missing).
int tally_modes(ForwardCheck& out, const std::vector<Window>& win, const std::vector<double>& clearance, const Observation& obs,
                const std::vector<Observation>& reps, bool exact) {
  const std::size_t M = win.size();
  int tests = 0;
  for (std::size_t m = 0; m < M; ++m) {
    ModeCheck c;
    c.model_hz = win[m].model_hz;
    c.lo_hz = win[m].lo_hz;
    c.hi_hz = win[m].hi_hz;
    c.measured_hz = obs.measured[m] ? obs.measured[m]->frequency_hz : kNaN;
    c.measured_peak = obs.measured[m] ? obs.measured[m]->magnitude : kNaN;
    c.predicted_hz = obs.predicted[m] ? obs.predicted[m]->frequency_hz : kNaN;
    c.predicted_peak = obs.predicted[m] ? obs.predicted[m]->magnitude : kNaN;
    c.frequency_error = relative(c.predicted_hz, c.measured_hz);
    c.magnitude_error = relative(c.predicted_peak, c.measured_peak);
    std::vector<double> ef, ep;
    for (const Observation& r : reps)
      if (r.measured[m] && r.predicted[m]) {
        ef.push_back(relative(r.predicted[m]->frequency_hz, r.measured[m]->frequency_hz));
        ep.push_back(relative(r.predicted[m]->magnitude, r.measured[m]->magnitude));
      }
    const MeanSd sf = mean_sd(ef), sp = mean_sd(ep);
    auto rank_p = [](const std::vector<double>& e, double mean, double x) {
      if (e.empty() || !std::isfinite(x)) return kNaN;
      const double d = std::abs(x - mean);
      const auto count = std::count_if(e.begin(), e.end(), [&](double v) { return std::abs(v - mean) >= d; });
      return (1.0 + static_cast<double>(count)) / (1.0 + static_cast<double>(e.size()));
    };
    c.frequency_rank_p = rank_p(ef, sf.mean, c.frequency_error);
    c.magnitude_rank_p = rank_p(ep, sp.mean, c.magnitude_error);
    c.frequency_mean = sf.mean;
    c.frequency_sd = sf.sd;
    c.magnitude_mean = sp.mean;
    c.magnitude_sd = sp.sd;
    c.resolved_fraction = exact ? 1.0 : static_cast<double>(ef.size()) / static_cast<double>(reps.size());
    c.clearance = clearance[m];
    const bool seen = obs.measured[m] && obs.predicted[m];
    c.frequency_z = c.magnitude_z = kNaN;  // set where judged
    if (!exact && !(c.clearance >= kModeClearance)) {
      // Under the noise: the window's highest peak is as likely a noise peak as the mode, in the
      // data and in the replicates alike (a weak mode of the stiff joint's assembly, at 1.6 % of
      // the peak under a 1 % floor, was "found" 10 % off at its window's edge). Neither judged
      // nor missing.
      c.agreement = ModeAgreement::NotResolved;
    } else if (seen && (exact || c.resolved_fraction >= 0.5)) {
      tests += 2;
      c.agreement = ModeAgreement::Agrees;
    } else if (!obs.measured[m] && !exact) {
      tests += 1;  // a candidate for "missing"
      c.agreement = ModeAgreement::NotResolved;
    } else {
      c.agreement = ModeAgreement::NotResolved;
    }
    out.modes.push_back(c);
  }
  return tests;
}

// Each mode judged: a frequency or peak error beyond what the noise makes (|z| > out.z) and beyond
// the tolerances fails, within them is a note; a mode the noise would hardly hide (probability <
// alpha) that the data lack is missing.
void judge_modes(ForwardCheck& out, const Observation& obs, const std::vector<Observation>& reps, bool exact, double alpha,
                 const ForwardCheckOptions& o) {
  for (std::size_t m = 0; m < out.modes.size(); ++m) {
    ModeCheck& c = out.modes[m];
    const std::string where = fmt::format("the mode at {:.1f} Hz", c.model_hz);
    if (c.agreement == ModeAgreement::Agrees) {
      const bool f_material = std::abs(c.frequency_error) > o.frequency_tolerance;
      const bool p_material = std::abs(c.magnitude_error) > o.peak_tolerance;
      bool f_beyond = f_material, p_beyond = p_material;  // exact data: the tolerances decide
      if (!exact) {
        c.frequency_z = std::abs(c.frequency_error - c.frequency_mean) / c.frequency_sd;
        c.magnitude_z = std::abs(c.magnitude_error - c.magnitude_mean) / c.magnitude_sd;
        // A spread of zero (every replicate alike): any difference is beyond it. Beyond also
        // needs the data's error to be more extreme than every replicate's (heavy tails).
        const double resolved = std::round(c.resolved_fraction * static_cast<double>(reps.size()));
        const double most_extreme = 1.0 / (1.0 + resolved);
        f_beyond = !(c.frequency_z <= out.z) && !(c.frequency_rank_p > most_extreme);
        p_beyond = !(c.magnitude_z <= out.z) && !(c.magnitude_rank_p > most_extreme);
      }
      const std::string what =
          fmt::format("{} comes back at {:.1f} Hz against {:.1f} Hz measured ({:+.2g} %) with its peak {:+.2g} %", where,
                      c.predicted_hz, c.measured_hz, 100 * c.frequency_error, 100 * c.magnitude_error);
      if ((f_beyond && f_material) || (p_beyond && p_material)) {
        c.agreement = ModeAgreement::Differs;
        out.failures.push_back(
            exact ? fmt::format("{} (tolerances {:g} % / {:g} %)", what, 100 * o.frequency_tolerance, 100 * o.peak_tolerance)
                  : fmt::format("{}: beyond what the noise makes (|z| {:.3g} and {:.3g} > {:.3g}) and beyond the tolerances "
                                "{:g} % / {:g} %",
                                what, c.frequency_z, c.magnitude_z, out.z, 100 * o.frequency_tolerance, 100 * o.peak_tolerance));
      } else if (f_beyond || p_beyond) {
        c.agreement = ModeAgreement::WithinTolerance;
        out.notes.push_back(fmt::format("{}: beyond what the noise makes, within the tolerances {:g} % / {:g} %", what,
                                        100 * o.frequency_tolerance, 100 * o.peak_tolerance));
      }
    } else if (!std::isfinite(c.measured_hz) && !exact && c.clearance >= kModeClearance) {
      // How often the noise hides the mode: the replicates that do not show it, or when every one
      // shows it, the normal tail of their prominence below the threshold. Measured side for the
      // test; predicted side for whether G_ref's peak is a mode at all: where B11's noise, carried
      // through the model, hides it in more than 1 % of replicates, the rest of that noise left in
      // B̄11 may as well have made it.
      auto hide = [&](bool measured_side) {
        std::vector<double> prom;
        std::size_t hidden = 0;
        for (const Observation& r : reps) {
          const std::optional<Peak>& pk = measured_side ? r.measured[m] : r.predicted[m];
          if (pk) prom.push_back(pk->prominence);
          else ++hidden;
        }
        const MeanSd sp = mean_sd(prom);
        const double p = hidden > 0 ? static_cast<double>(hidden) / static_cast<double>(reps.size())
                                    : 0.5 * std::erfc((sp.mean - o.min_prominence) / (sp.sd * std::sqrt(2.0)));
        return std::pair{p, sp};
      };
      const auto [p_hide, sp] = hide(true);
      const bool model_mode = hide(false).first < 0.01;
      if (p_hide < alpha && model_mode) {
        c.agreement = ModeAgreement::Missing;
        out.failures.push_back(fmt::format(
            "{} of the identified model is missing from the data (prominence {:.2g}, below {:g}, where the noise leaves "
            "{:.2g} ± {:.2g}: it hides the mode with probability {:.2g})",
            where, obs.window_prominence[m], o.min_prominence, sp.mean, sp.sd, p_hide));
      }
    }
  }
}

// Peaks of the data no mode of the model explains, against the most prominent unexplained peak of
// each replicate (a rank test at half the false-alarm probability).
void judge_extra_peaks(ForwardCheck& out, const Observation& obs, const std::vector<Observation>& reps, bool exact,
                       double false_alarm) {
  for (const Peak& p : obs.extra) {
    ExtraPeak e;
    e.frequency_hz = p.frequency_hz;
    e.prominence = p.prominence;
    if (exact) {
      e.significant = true;
      e.p_value = 0.0;
    } else {
      std::size_t count = 0;
      for (const Observation& r : reps) count += r.max_extra >= p.prominence;
      e.p_value = (1.0 + static_cast<double>(count)) / (1.0 + static_cast<double>(reps.size()));
      e.significant = e.p_value <= 0.5 * false_alarm;
    }
    if (e.significant)
      out.failures.push_back(
          fmt::format("the data have a peak at {:.1f} Hz (prominence {:.2g}) that no mode of the identified "
                      "model explains{}",
                      e.frequency_hz, e.prominence,
                      exact ? "" : fmt::format(" and the noise does not make (p = {:.2g})", e.p_value)));
    out.extra.push_back(e);
  }
}

}  // namespace

ForwardCheck check_forward(const JointFitData& d, const JointParameters& joint, const ForwardCheckOptions& o,
                           const std::optional<Eigen::Matrix<double, 8, 8>>& covariance) {
  o.check();
  const std::string label = d.label.empty() ? "set-up" : d.label;
  validate(d.G11, label + ": " + (d.g_name.empty() ? "G11" : d.g_name), 3);
  validate(d.B11, label + ": " + (d.b_name.empty() ? "B11" : d.b_name), 3);
  require_same_grid(d.B11.frequency_hz, d.b_name.empty() ? "B11" : d.b_name, d.G11.frequency_hz,
                    d.g_name.empty() ? "G11" : d.g_name);
  if (d.A.size() != d.G11.size())
    throw InputError(fmt::format("{}: {} model component blocks for {} frequencies", label, d.A.size(), d.G11.size()));
  const std::vector<double>& f = d.G11.frequency_hz;
  const std::size_t n = f.size();
  const SavgolOptions s = o.smoothing.value_or(SavgolOptions{15, 3});
  const std::optional<SavgolOptions> smoothing = n >= static_cast<std::size_t>(s.window) ? std::optional(s) : std::nullopt;

  const std::vector<Block> K = stiffness_on(joint, f);
  // The world the check assumes: the identified joint and B11 with its noise smoothed away.
  const BlockSeries B_ref = noise_free_estimate(d.B11, d.b_noise, d.b_name.empty() ? "B11" : d.b_name);
  BlockSeries G_ref;
  G_ref.frequency_hz = f;
  G_ref.blocks = predicted(d, B_ref.blocks, K);
  const FrfSeries ref = smoothed_h(f, G_ref.blocks, smoothing);
  const std::vector<Peak> model_modes = reference_modes(d, B_ref, K, ref, smoothing, kWeakMode * o.min_prominence,
                                                        stream_seed(o.seed, 0x919E), o.parallel);
  // The joint's uncertainty: each replicate's prediction takes a joint drawn from it, and each
  // window is at least 4 standard deviations of its mode's frequency over such joints wide.
  const bool exact = d.g_noise.exact() && d.b_noise.exact();
  std::vector<JointParameters> thetas;
  if (covariance && !exact) thetas = sample_joints(joint, *covariance, o.replicates, stream_seed(o.seed, 0x7E7A));
  std::vector<Window> win = windows_of(ref, model_modes);
  if (!thetas.empty()) widen_windows(win, d, B_ref, thetas, smoothing, o.min_prominence);

  const Observation obs = observe(smoothed_h(f, d.G11.blocks, smoothing), smoothed_h(f, predicted(d, d.B11.blocks, K), smoothing),
                                  win, o.min_prominence);

  ForwardCheck out;
  out.label = label;
  out.false_alarm = o.false_alarm;
  std::vector<Observation> reps;
  if (!exact) {
    out.replicates = o.replicates;
    reps = replicate_observations(d, B_ref, G_ref, K, thetas, win, smoothing, o);
  }

  // Per mode: the replicates' statistics, then the observed errors against them.
  const int tests = tally_modes(out, win, clearances(d, G_ref, ref, model_modes, smoothing), obs, reps, exact);
  // Bonferroni: half the false alarm to the z-tests, split evenly, two-sided.
  const double alpha = 0.5 * o.false_alarm / std::max(1, tests);
  out.z = normal_quantile(1.0 - 0.5 * alpha);
  judge_modes(out, obs, reps, exact, alpha, o);
  judge_extra_peaks(out, obs, reps, exact, o.false_alarm);
  if (model_modes.empty()) out.notes.push_back("the identified model has no mode in the band: nothing to compare");
  return out;
}

}  // namespace toolpoint
