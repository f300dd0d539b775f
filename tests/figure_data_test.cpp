// Tests of the figure data the library builds for its results (what the CLI only draws): the
// filter's and the modal fit's figures. Each figure must hold the curves of the result it is built from — the
// values themselves, in the unit its axis label names — not merely have the right shape.
// Units: SI; frequencies in Hz.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/modal_fit.hpp"
#include "toolpoint/plot.hpp"

using namespace toolpoint;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The magnitudes of an FRF as a figure's curve holds them.
void expect_magnitudes(const plot::Curve& curve, const FrfSeries& frf) {
  ASSERT_EQ(curve.x, frf.frequency_hz);
  ASSERT_EQ(curve.y.size(), frf.size());
  for (std::size_t i = 0; i < frf.size(); ++i) EXPECT_EQ(curve.y[i], std::abs(frf.values[i])) << i;
}

}  // namespace

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
