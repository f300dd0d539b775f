// toolpoint study: the plan's figures — the stable-depth map and the tuning curve (studies/plan.hpp).
// Plotted units: overhang mm, spindle speed rpm, depth mm, MRR cm³/min.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/studies/plan.hpp"

namespace toolpoint {

namespace {


// The reach in a title (shorter overhangs are not planned, so the axes start at or above it).
std::string reach_text(const PlanOptions& o) {
  return o.machine.min_overhang_m > 0.0 ? fmt::format("; overhangs ≥ {:g} mm", 1e3 * o.machine.min_overhang_m) : std::string();
}

// The overall best set-up's index in result.best for candidate c, or npos.
const PlanSetup* best_of(const PlanResult& r, std::size_t c) {
  for (const PlanSetup& s : r.best)
    if (s.candidate == c) return &s;
  return nullptr;
}

// The type-7 quantile of the finite values at level p (NaN when none).
double finite_quantile(std::vector<double> v, double p) {
  std::erase_if(v, [](double x) { return !std::isfinite(x); });
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double h = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(h);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace

plot::Figure plan_map_figure(const PlanResult& r) {
  const PlanHeader& h = r.header;
  if (r.jobs.empty()) throw InvalidArgument("plan map figure: the plan has no jobs");
  plot::Figure fig;
  fig.title = fmt::format("Allowed depth: {}{}", safety_rule_text(h.options.safety), reach_text(h.options));
  fig.x.label = "Spindle speed [rpm]";
  fig.width_px = 1200;
  fig.height_px = static_cast<int>(std::min<std::size_t>(20000, 200 + 500 * h.candidates.size()));
  // One colour scale for every panel, so candidates compare by colour: 0 to the 99th percentile of
  // the allowed depths (pockets far above the rest would leave everything else dark).
  std::vector<double> all;
  for (const PlanJob& job : r.jobs)
    for (double d : job.safe_depth_m) all.push_back(1e3 * d);
  const double top = finite_quantile(all, 0.99);
  std::size_t j0 = 0;
  for (std::size_t c = 0; c < h.candidates.size(); ++c) {
    const PlanCandidateSummary& cs = h.candidates[c];
    const std::size_t nj = cs.overhangs_m.size();
    plot::Panel p;
    p.y.label = h.candidates.size() > 1 ? fmt::format("{}: overhang [mm]", plot::literal(cs.name)) : std::string("Overhang [mm]");
    plot::Map m;
    m.x = h.speeds_rpm;
    for (double L : cs.overhangs_m) m.y.push_back(1e3 * L);
    m.z.reserve(nj * m.x.size());
    plot::Curve best;
    best.style = plot::CurveStyle::Points;
    best.label = "most MRR at each overhang";
    best.series = 0;
    for (std::size_t i = 0; i < nj; ++i) {
      const PlanJob& job = r.jobs[j0 + i];
      for (double d : job.safe_depth_m) m.z.push_back(std::isfinite(d) ? 1e3 * d : kNaN);
      best.x.push_back(job.best.speed_rpm);
      best.y.push_back(1e3 * job.overhang_m);
    }
    m.colour.label = "Allowed depth [mm]";
    m.colour.min = 0.0;
    if (std::isfinite(top) && top > 0.0) m.colour.max = top;
    p.map = std::move(m);
    if (nj > 1) p.curves.push_back(std::move(best));
    // The best set-up as a marker of its own, described in the legend (a label would run off the
    // frame when the best speed is the top one).
    if (const PlanSetup* s = best_of(r, c))
      p.curves.push_back({{s->speed_rpm},
                          {1e3 * s->overhang_m},
                          fmt::format("best: {:.1f} mm, {:.0f} rpm, {:.0f} cm^3/min", 1e3 * s->overhang_m, s->speed_rpm,
                                      kCubicCentimetresPerMinute * s->mrr_m3_per_s),
                          plot::CurveStyle::Points,
                          1});
    p.legend = plot::Legend::TopLeft;
    fig.panels.push_back(std::move(p));
    j0 += nj;
  }
  return fig;
}

plot::Figure plan_tuning_figure(const PlanResult& r) {
  const PlanHeader& h = r.header;
  if (r.jobs.empty()) throw InvalidArgument("plan tuning figure: the plan has no jobs");
  plot::Figure fig;
  fig.title = fmt::format("Best MRR at each overhang ({}{})", safety_rule_text(h.options.safety), reach_text(h.options));
  fig.x.label = "Overhang [mm]";
  plot::Panel mrr, speed;
  mrr.y.label = "Best MRR [cm^3/min]";
  mrr.y.min = 0.0;
  mrr.height = 1.6;
  speed.y.label = "Its spindle speed [rpm]";
  mrr.legend = speed.legend = h.candidates.size() > 1 ? plot::Legend::Outside : plot::Legend::Hidden;
  std::size_t j0 = 0;
  for (std::size_t c = 0; c < h.candidates.size(); ++c) {
    const PlanCandidateSummary& cs = h.candidates[c];
    plot::Curve a, n;
    a.label = n.label = plot::literal(cs.name);
    a.style = n.style = plot::CurveStyle::LinePoints;
    a.series = n.series = static_cast<int>(c);
    for (std::size_t i = 0; i < cs.overhangs_m.size(); ++i) {
      const PlanSetup& s = r.jobs[j0 + i].best;
      a.x.push_back(1e3 * s.overhang_m);
      // No set-up (nothing stable at any speed) removes nothing: 0 on the curve, no speed below.
      a.y.push_back(std::isfinite(s.mrr_m3_per_s) ? kCubicCentimetresPerMinute * s.mrr_m3_per_s : 0.0);
      n.x.push_back(1e3 * s.overhang_m);
      n.y.push_back(s.speed_rpm);
    }
    if (const PlanSetup* s = best_of(r, c))
      mrr.labels.push_back({1e3 * s->overhang_m, kCubicCentimetresPerMinute * s->mrr_m3_per_s,
                            fmt::format("{:.1f} mm, {:.0f} rpm", 1e3 * s->overhang_m, s->speed_rpm), true});
    mrr.curves.push_back(std::move(a));
    speed.curves.push_back(std::move(n));
    j0 += cs.overhangs_m.size();
  }
  double top = 0.0;  // room above the highest point for its label
  for (const plot::Curve& a : mrr.curves)
    for (double v : a.y)
      if (std::isfinite(v)) top = std::max(top, v);
  if (top > 0.0) mrr.y.max = 1.15 * top;
  fig.panels = {std::move(mrr), std::move(speed)};
  return fig;
}

}  // namespace toolpoint
