// Tests of the figure data the library builds for its results (what the CLI only draws): the
// identification's K(ω) figure, the case study's Fig. 2–5 and forward check, the filter's and the
// modal fit's figures. Each figure must hold the curves of the result it is built from — the
// values themselves, in the unit its axis label names — not merely have the right shape.
// Units: SI; frequencies in Hz.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "support/joint_data.hpp"
#include "toolpoint/studies/case_study.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/modal_fit.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/studies/identification.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// `curve` draws `values` (against `x`) in the unit `label` names: values × 10^(−e) with e a
// multiple of 3 (the SI prefix on the unit), and the label ends in "<unit>]".
void expect_scaled(const plot::Curve& curve, const std::string& label, const std::vector<double>& x,
                   const std::vector<double>& values, const std::string& unit) {
  ASSERT_EQ(curve.x, x);
  ASSERT_EQ(curve.y.size(), values.size());
  double factor = 0.0;
  for (std::size_t i = 0; i < values.size() && factor == 0.0; ++i)
    if (std::isfinite(values[i]) && values[i] != 0.0) factor = curve.y[i] / values[i];
  ASSERT_GT(factor, 0.0);
  const double e = -std::log10(factor);
  EXPECT_NEAR(e, 3.0 * std::round(e / 3.0), 1e-9) << label;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(values[i])) EXPECT_NEAR(curve.y[i], values[i] * factor, 1e-12 * std::abs(values[i] * factor)) << i;
  EXPECT_TRUE(label.ends_with(unit + "]")) << label << " vs " << unit;
}

// The joint figure's panels: k_yf, k_ym, k_tf, k_tm, then the dampings (JointParameters' indices).
constexpr int kPanelOrder[8] = {0, 2, 4, 6, 1, 3, 5, 7};

// The magnitudes of an FRF as a figure's curve holds them.
void expect_magnitudes(const plot::Curve& curve, const FrfSeries& frf) {
  ASSERT_EQ(curve.x, frf.frequency_hz);
  ASSERT_EQ(curve.y.size(), frf.size());
  for (std::size_t i = 0; i < frf.size(); ++i) EXPECT_EQ(curve.y[i], std::abs(frf.values[i])) << i;
}

// The horizontal line of `panel` whose label starts with `label`, or nullptr.
const plot::HorizontalLine* line_labelled(const plot::Panel& panel, const std::string& label) {
  for (const auto& l : panel.horizontal_lines)
    if (l.label.starts_with(label)) return &l;
  return nullptr;
}

}  // namespace

// The identification's figure: k(f), c(f) of the four pairs of the closed form (stiffness panels,
// then damping, each in its SI unit), the read-out band shaded, the identified values as lines.
TEST(FigureData, IdentificationFigureHoldsTheClosedFormAndTheResult) {
  const Assembly a = example_assembly();
  const RouteData d = route_data(a, Route::HolderTool, FrequencyGrid{10.0, 5000.0, 5.0}.values());
  const JointFitData x = noisy_fit_data(d, 0.02, 3);
  IdentificationOptions o;
  o.fit.uncertainty = UncertaintyMethod::Linearised;
  const Identification id = run_identification_study(a, {IdentificationData{"", std::nullopt, x.G11, "SHT11", x.B11, "SH11", {}, {}}}, o);
  ASSERT_TRUE(id.fit);
  const plot::Figure fig = identification_figure(id);
  EXPECT_TRUE(contains(fig.title, "Holder–tool joint, Eq. (6)")) << fig.title;
  EXPECT_EQ(fig.x.label, "Frequency [Hz]");
  ASSERT_EQ(fig.panels.size(), 8u);
  for (std::size_t p = 0; p < 8; ++p) {
    const int k = kPanelOrder[p];
    std::vector<double> values;
    for (const JointParameters& q : id.closed_form.parameters) values.push_back(q[k]);
    SCOPED_TRACE(JointParameters::name(k));
    expect_scaled(fig.panels[p].curves.at(0), fig.panels[p].y.label, id.closed_form.frequency_hz, values,
                  JointParameters::unit(k));
    const double factor = fig.panels[p].curves[0].y[0] / values[0];
    const plot::HorizontalLine* identified = line_labelled(fig.panels[p], "identified");
    ASSERT_NE(identified, nullptr);
    EXPECT_NEAR(identified->y, id.identified[k] * factor, 1e-12 * std::abs(id.identified[k] * factor));
    ASSERT_EQ(fig.panels[p].bands.size(), 1u);
    EXPECT_EQ(fig.panels[p].bands[0].from, id.seed.band_lo_hz);
    EXPECT_EQ(fig.panels[p].bands[0].to, id.seed.band_hi_hz);
  }
  // joint_curve alone: the pair's values and units, the reference and the read-out's verdicts.
  const plot::JointParameterCurve c = joint_curve(id.closed_form, 1, 1, a.holder_tool.parameters, std::nullopt, nullptr,
                                                  &id.seed);
  EXPECT_EQ(c.stiffness_unit, JointParameters::unit(JointParameter::k_tm));
  EXPECT_EQ(c.damping_unit, JointParameters::unit(JointParameter::c_tm));
  EXPECT_EQ(c.stiffness[7], id.closed_form.parameters[7].k_tm);
  EXPECT_EQ(c.reference_stiffness.value(), a.holder_tool.parameters.k_tm);
  EXPECT_FALSE(c.identified_stiffness);
  EXPECT_EQ(c.damping_undetermined, !id.seed.parameters[7].determined);
}

// The case study's figures: the measured FRFs (model, noisy, filtered), the noise-free joint with
// the reference as lines, k_yf and c_yf with the read-out band, the seed's read-out and the band
// fit, and the forward check — each the result's own series.
TEST(FigureData, CaseStudyFiguresHoldTheStudysSeries) {
  Assembly a = example_assembly();
  a.grid = FrequencyGrid{1000.0, 4000.0, 1.0};
  CaseStudyOptions o;
  o.noise_sigma = 0.03;
  o.fit_options.uncertainty = UncertaintyMethod::Linearised;
  const CaseStudy cs = run_case_study(a, o);
  ASSERT_TRUE(cs.fitted);
  const CaseStudyFigures figs = case_study_figures(cs, o);

  const auto expect_frfs = [](const plot::Figure& fig, const std::vector<FrfSeries>& frfs) {
    ASSERT_EQ(fig.panels.size(), 2u);
    ASSERT_EQ(fig.panels[0].curves.size(), frfs.size());
    for (std::size_t t = 0; t < frfs.size(); ++t) expect_magnitudes(fig.panels[0].curves[t], frfs[t]);
    EXPECT_TRUE(fig.panels[0].y.label.ends_with("[m/N]")) << fig.panels[0].y.label;
    EXPECT_EQ(fig.x.label, "Frequency [Hz]");
  };
  expect_frfs(figs.tool_point_frf, {entry(cs.sht_true, 0), entry(cs.sht_noisy, 0), entry(cs.sht_filtered, 0)});
  EXPECT_EQ(figs.tool_point_frf.panels[0].curves[1].label, "3 % noise");
  expect_frfs(figs.holder_tip_frf, {entry(cs.sh_true, 0), entry(cs.sh_noisy, 0), entry(cs.sh_filtered, 0)});
  expect_frfs(figs.verification, {entry(cs.sht_true, 0), entry(cs.sht_verified, 0), entry(cs.sht_fitted, 0)});

  ASSERT_EQ(figs.joint_noise_free.panels.size(), 8u);
  for (std::size_t p = 0; p < 8; ++p) {
    const int k = kPanelOrder[p];
    std::vector<double> values;
    for (const JointParameters& q : cs.clean.parameters) values.push_back(q[k]);
    SCOPED_TRACE(JointParameters::name(k));
    const plot::Panel& panel = figs.joint_noise_free.panels[p];
    expect_scaled(panel.curves.at(0), panel.y.label, cs.sht_true.frequency_hz, values, JointParameters::unit(k));
    const double factor = panel.curves[0].y[0] / values[0];
    const plot::HorizontalLine* reference = line_labelled(panel, "reference");
    ASSERT_NE(reference, nullptr);
    EXPECT_NEAR(reference->y, cs.reference[k] * factor, 1e-12 * std::abs(cs.reference[k] * factor));
  }

  const plot::Figure& yf = figs.joint_filtered;
  EXPECT_TRUE(contains(yf.title, "at 3 % noise: seed read-out and band fit")) << yf.title;
  ASSERT_EQ(yf.panels.size(), 2u);  // k_yf, c_yf
  for (int damping = 0; damping < 2; ++damping) {
    const auto k = static_cast<std::size_t>(damping ? JointParameter::c_yf : JointParameter::k_yf);
    std::vector<double> values;
    for (const JointParameters& q : cs.filtered.parameters) values.push_back(q[static_cast<int>(k)]);
    const plot::Panel& panel = yf.panels[static_cast<std::size_t>(damping)];
    expect_scaled(panel.curves.at(0), panel.y.label, cs.sht_true.frequency_hz, values,
                  JointParameters::unit(static_cast<int>(k)));
    const double factor = panel.curves[0].y[0] / values[0];
    const plot::HorizontalLine* fit = line_labelled(panel, "band fit");
    const plot::HorizontalLine* seed = line_labelled(panel, "seed read-out");
    ASSERT_NE(fit, nullptr);
    ASSERT_NE(seed, nullptr);
    EXPECT_NEAR(fit->y, cs.fitted->identified[static_cast<int>(k)] * factor, 1e-12 * std::abs(fit->y));
    EXPECT_NEAR(seed->y, cs.filtered_readout.parameters[k].median * factor, 1e-12 * std::abs(seed->y));
    ASSERT_EQ(panel.bands.size(), 1u);
    EXPECT_EQ(panel.bands[0].from, cs.filtered_readout.band_lo_hz);
    EXPECT_EQ(panel.bands[0].to, cs.filtered_readout.band_hi_hz);
  }
}

// The filter's figure: a block's four entries, the input's magnitude as points and the filtered
// one as a line, each panel in its entry's unit, and the phase of H [deg] last; a single FRF: |H|
// and its phase.
TEST(FigureData, FilterFigureHoldsInputAndFilteredOfEveryEntry) {
  BlockSeries raw, filtered;
  for (int i = 1; i <= 60; ++i) {
    const double f = 10.0 * i, r = f / 300.0;
    const Complex h = 1.0 / (1e6 * Complex(1.0 - r * r, 0.04 * r));
    raw.frequency_hz.push_back(f);
    raw.blocks.push_back(make_block(h, 2.0 * h, 2.0 * h, 5.0 * h));
    filtered.frequency_hz.push_back(f);
    filtered.blocks.push_back(make_block(0.9 * h, 1.8 * h, 1.8 * h, 4.5 * h));
  }
  const plot::Figure fig = plot::filter_figure(raw, filtered, "title");
  EXPECT_EQ(fig.title, "title");
  ASSERT_EQ(fig.panels.size(), 5u);
  const char* units[4] = {"[m/N]", "[1/N]", "[rad/N]", "[rad/(N·m)]"};
  for (int k = 0; k < 4; ++k) {
    const plot::Panel& p = fig.panels[static_cast<std::size_t>(k)];
    ASSERT_EQ(p.curves.size(), 2u) << k;
    EXPECT_EQ(p.curves[0].style, plot::CurveStyle::Points);
    expect_magnitudes(p.curves[0], entry(raw, k));
    expect_magnitudes(p.curves[1], entry(filtered, k));
    EXPECT_TRUE(p.y.label.starts_with(std::string("|") + "HLNP"[k] + "|")) << p.y.label;
    EXPECT_TRUE(p.y.label.ends_with(units[k])) << p.y.label;
  }
  EXPECT_EQ(fig.panels[4].y.label, "∠H [deg]");
  EXPECT_EQ(fig.height_px, 700 + 3 * 170);
  const plot::Figure one = plot::filter_figure(entry(raw, 0), entry(filtered, 0), "one");
  ASSERT_EQ(one.panels.size(), 2u);
  expect_magnitudes(one.panels[0].curves.at(1), entry(filtered, 0));
  EXPECT_EQ(one.panels[1].y.label, "∠H [deg]");
}

// The modal fit on the measured grid: a one-mode FRF (m = 0.5 kg, ζ = 2 %, 800 Hz) fitted in
// 600–1000 Hz gives back that oscillator's receptance (the closed form) on the band's points only,
// and the figure draws it with the mode labelled at its frequency on the fitted curve.
TEST(FigureData, ModalFitOnTheMeasuredGridAndItsFigure) {
  const Mode truth{0.5, 0.02, 800.0};
  FrfSeries measured;
  for (double f = 400.0; f <= 1200.0; f += 2.0) {
    measured.frequency_hz.push_back(f);
    measured.values.push_back(modal_receptance({truth}, f));
  }
  ModalFitOptions o;
  o.max_modes = 1;
  o.band_hz = std::make_pair(600.0, 1000.0);
  o.residual_terms = false;
  const ModalFitResult r = fit_modes(measured, o);
  const FrfSeries fitted = r.fitted_frf(measured.frequency_hz);
  ASSERT_EQ(fitted.size(), 201u);  // 600, 602, …, 1000
  EXPECT_EQ(fitted.frequency_hz.front(), 600.0);
  EXPECT_EQ(fitted.frequency_hz.back(), 1000.0);
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    const Complex want = 1.0 / (truth.mass_kg *
                                (std::pow(omega_of(truth.frequency_hz), 2) - std::pow(omega_of(fitted.frequency_hz[i]), 2) +
                                 Complex(0.0, 2.0 * truth.damping_ratio * omega_of(truth.frequency_hz) *
                                                  omega_of(fitted.frequency_hz[i]))));
    EXPECT_LT(std::abs(fitted.values[i] - want), 1e-6 * std::abs(want)) << fitted.frequency_hz[i];
  }
  const plot::Figure fig = modal_fit_figure(measured, r, "tip_H.csv");
  EXPECT_TRUE(contains(fig.title, "Modal fit of tip\\_H.csv: 1 mode(s)")) << fig.title;
  ASSERT_EQ(fig.panels[0].curves.size(), 2u);
  expect_magnitudes(fig.panels[0].curves[0], measured);
  expect_magnitudes(fig.panels[0].curves[1], fitted);
  ASSERT_EQ(fig.panels[0].labels.size(), 1u);
  EXPECT_NEAR(fig.panels[0].labels[0].x, 800.0, 1e-6 * 800.0);
  EXPECT_TRUE(contains(fig.panels[0].labels[0].text, "800.0 Hz, ζ 0.02")) << fig.panels[0].labels[0].text;
}
