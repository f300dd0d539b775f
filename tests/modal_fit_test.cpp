// Tests of the modal fit (modal_fit module). Synthetic FRFs from known modes, summed in closed
// form, are fitted back; noise is seeded so every run sees the same data. Single-mode closed
// forms (static flexibility 1/k, the resonance value −i/(2kζ)) check the synthesis itself.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/stability/modal_fit.hpp"
#include "toolpoint/studies/modal_fit.hpp"

using namespace toolpoint;

namespace {

// Three modes like a tool point: a holder/spindle mode, the dominant tool mode, a higher mode.
const std::vector<Mode> kModes = {{0.8, 0.03, 650.0}, {0.05, 0.011, 922.0}, {0.12, 0.02, 2400.0}};

std::vector<double> grid(double lo, double hi, double step) {
  std::vector<double> f;
  for (int i = 0; lo + i * step <= hi; ++i) f.push_back(lo + i * step);
  return f;
}

// Complex Gaussian noise proportional to the response, σ relative (like a measurement whose
// error is a fixed fraction of the signal).
FrfSeries with_noise(FrfSeries s, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (auto& v : s.values) v *= 1.0 + sigma * Complex(n(rng), n(rng)) / std::sqrt(2.0);
  return s;
}

}  // namespace

// G(ω → 0) = 1/k and G(ω_n) = −i/(2kζ) for one mode (1e-6: the 1e-3 Hz "static" point leaves a
// (f/f_n)² ≈ 1e-12 dynamic part; the resonance value is exact to round-off).
TEST(ModalFit, SynthesisClosedForms) {
  const Mode m{0.05, 0.02, 1000.0};
  EXPECT_NEAR(modal_receptance({m}, 1e-3).real() * m.stiffness(), 1.0, 1e-6);
  const Complex at_res = modal_receptance({m}, m.frequency_hz);
  EXPECT_NEAR(at_res.real() * m.stiffness(), 0.0, 1e-12);
  EXPECT_NEAR(at_res.imag() * 2.0 * m.stiffness() * m.damping_ratio, -1.0, 1e-12);
}

// Noise-free data: every parameter back to 1e-9 relative (the fit reaches round-off, ~1e-14, the
// tolerance leaves room for other compilers), residual terms ~0, overall residual < 1e-10.
TEST(ModalFit, RecoversThreeModesExactly) {
  const FrfSeries frf = modal_frf(kModes, grid(100.0, 4000.0, 1.0));
  const ModalFitResult r = fit_modes(frf);
  ASSERT_EQ(r.modes.size(), 3u);
  EXPECT_TRUE(r.converged);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.modes[i].mode.frequency_hz / kModes[i].frequency_hz, 1.0, 1e-9) << i;
    EXPECT_NEAR(r.modes[i].mode.damping_ratio / kModes[i].damping_ratio, 1.0, 1e-9) << i;
    EXPECT_NEAR(r.modes[i].mode.mass_kg / kModes[i].mass_kg, 1.0, 1e-9) << i;
    EXPECT_LT(r.modes[i].normalised_residual, 1e-10);
    EXPECT_GT(r.modes[i].points_in_half_power_band, 10);
  }
  EXPECT_LT(r.normalised_residual, 1e-10);
  EXPECT_NEAR(r.lower_residual, 0.0, 1e-9);  // [1/kg]; the residues are ~20 1/kg
  EXPECT_NEAR(r.upper_residual * kModes[1].stiffness(), 0.0, 1e-9);
  EXPECT_TRUE(r.warnings.empty());
  const std::vector<Mode> model = r.modal_model();
  EXPECT_NEAR(std::abs(modal_receptance(model, 922.0) / modal_receptance(kModes, 922.0) - 1.0), 0.0, 1e-9);
}

// Noisy data, σ = 1 % and 3 % of the response (one fixed seed). A least-squares estimate's
// relative error is about σ/sqrt(n), n the points in a mode's half-power band (21…96 here): for
// n = 21 that is 0.22σ. Tolerances: ζ_r and m_r within 0.5σ (observed ≤ 0.25σ), f_r within 5e-4
// (observed ≤ 1.6e-4). The reported residuals must tell the truth: overall ≈ σ (within ±30 %),
// per mode within ±50 %.
TEST(ModalFit, RecoversModesFromNoisyData) {
  const FrfSeries clean = modal_frf(kModes, grid(100.0, 4000.0, 1.0));
  for (double sigma : {0.01, 0.03}) {
    const ModalFitResult r = fit_modes(with_noise(clean, sigma, 7));
    ASSERT_EQ(r.modes.size(), 3u) << sigma;
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(r.modes[i].mode.frequency_hz / kModes[i].frequency_hz, 1.0, 5e-4) << sigma << " mode " << i;
      EXPECT_NEAR(r.modes[i].mode.damping_ratio / kModes[i].damping_ratio, 1.0, 0.5 * sigma) << sigma << " mode " << i;
      EXPECT_NEAR(r.modes[i].mode.mass_kg / kModes[i].mass_kg, 1.0, 0.5 * sigma) << sigma << " mode " << i;
      EXPECT_NEAR(r.modes[i].normalised_residual / sigma, 1.0, 0.5) << sigma << " mode " << i;
    }
    EXPECT_NEAR(r.normalised_residual / sigma, 1.0, 0.3) << sigma;
  }
}

// A band around one mode: the residual terms stand in for the modes outside it. With them the
// 922 Hz mode comes back within 2e-3 (observed 7e-4) and the fit is closer than without them.
TEST(ModalFit, BandWithResidualTerms) {
  const FrfSeries frf = modal_frf(kModes, grid(100.0, 4000.0, 1.0));
  ModalFitOptions with;
  with.band_hz = std::pair{850.0, 1000.0};
  ModalFitOptions without = with;
  without.residual_terms = false;
  const ModalFitResult a = fit_modes(frf, with), b = fit_modes(frf, without);
  ASSERT_EQ(a.modes.size(), 1u);
  EXPECT_EQ(a.points, 151u);
  EXPECT_NEAR(a.modes[0].mode.frequency_hz / 922.0, 1.0, 2e-5);
  EXPECT_NEAR(a.modes[0].mode.damping_ratio / 0.011, 1.0, 2e-3);
  EXPECT_NEAR(a.modes[0].mode.mass_kg / 0.05, 1.0, 2e-3);
  EXPECT_LT(a.normalised_residual, b.normalised_residual);
}

// max_modes keeps the most prominent peaks (here 922 and 2400 Hz) and says so.
TEST(ModalFit, KeepsTheMostProminentPeaks) {
  ModalFitOptions o;
  o.max_modes = 2;
  const ModalFitResult r = fit_modes(modal_frf(kModes, grid(100.0, 4000.0, 1.0)), o);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_NEAR(r.modes[0].mode.frequency_hz, 922.0, 1.0);
  EXPECT_NEAR(r.modes[1].mode.frequency_hz, 2400.0, 1.0);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("ModalFitOptions::max_modes"), std::string::npos);
}

// A negated FRF (wrong sign convention) fits with negative residues: warned, and no modal mass.
TEST(ModalFit, NegativeResidueHasNoModalMass) {
  FrfSeries frf = modal_frf({kModes[1]}, grid(700.0, 1200.0, 0.5));
  for (auto& v : frf.values) v = -v;
  const ModalFitResult r = fit_modes(frf);
  ASSERT_EQ(r.modes.size(), 1u);
  EXPECT_LT(r.modes[0].residue, 0.0);
  EXPECT_FALSE(r.warnings.empty());
  EXPECT_THROW(r.modal_model(), NumericalError);
}

// A point mobility Y = iωH read as a receptance (a file without its units) fits to negative or
// meaningless masses; it is refused, naming what it looks like and the option that converts it,
// with 2 % noise too. The receptance with the same noise fits.
TEST(ModalFit, AMobilityIsRefused) {
  const FrfSeries h = with_noise(modal_frf(kModes, grid(300.0, 3000.0, 1.0)), 0.02, 7);
  FrfSeries y = h;
  for (std::size_t i = 0; i < y.size(); ++i) y.values[i] *= Complex(0.0, 2.0 * kPi * y.frequency_hz[i]);
  try {
    fit_modes(y, {}, "mobility.csv");
    ADD_FAILURE() << "a mobility was fitted as a receptance";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mobility.csv: Re G ≥ 0 at 99 % of its points"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("point mobility"), std::string::npos) << e.what();
    EXPECT_NE(e.hint().find("FrfReadOptions::units"), std::string::npos) << e.hint();
  }
  EXPECT_NO_THROW(fit_modes(h));
}

TEST(ModalFit, BadInputIsRejected) {
  // 25 Hz steps against a 20 Hz half-power band (ζ = 0.011 at 922 Hz): no FRF points near the mode.
  try {
    fit_modes(modal_frf({kModes[1]}, grid(500.0, 1500.0, 25.0)));
    ADD_FAILURE() << "accepted an under-resolved mode";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("half-power band"), std::string::npos) << e.what();
  }
  const FrfSeries frf = modal_frf(kModes, grid(100.0, 4000.0, 1.0));
  ModalFitOptions narrow;
  narrow.band_hz = std::pair{1000.0, 1005.0};
  EXPECT_THROW(fit_modes(frf, narrow), InputError);  // 6 points in the band
  FrfSeries flat;
  flat.frequency_hz = grid(100.0, 200.0, 1.0);
  flat.values.assign(flat.frequency_hz.size(), Complex(1e-7, 0.0));
  EXPECT_THROW(fit_modes(flat), InputError);  // no resonance
  ModalFitOptions o;
  o.max_modes = 0;
  EXPECT_THROW(fit_modes(frf, o), InvalidArgument);
  o = {};
  o.band_hz = std::pair{2000.0, 1000.0};
  EXPECT_THROW(fit_modes(frf, o), InvalidArgument);
  FrfSeries nan = frf;
  nan.values[3] = Complex(0.0, std::nan(""));
  EXPECT_THROW(fit_modes(nan), InputError);
  EXPECT_THROW((Mode{0.05, 1.2, 900.0}).check(), InvalidArgument);
  EXPECT_THROW((Mode{0.05, 0.01, -900.0}).check(), InvalidArgument);
}

// Scale-aware fitting (issue 13): the same single-DOF receptance (f_n = 916 Hz, ζ = 0.02,
// k = 1e6 N/m) multiplied by 1e300 or 1e-300 gives the same frequency and damping and the modal
// mass divided by the factor (closed form m = k/ω_n², to 1e-6); one scaled into the subnormal
// range, whose mass would exceed double precision, is a NumericalError, never an infinite mass.
TEST(ModalFit, AnyScaleFitsOrIsNamedOutOfRange) {
  const double m_closed = 1e6 / std::pow(2.0 * 3.141592653589793 * 916.0, 2);
  const auto sdof = [](double scale) {
    toolpoint::FrfSeries s;
    for (double f = 700.0; f < 1150.0; f += 1.0) {
      const double r = f / 916.0;
      s.frequency_hz.push_back(f);
      s.values.push_back(scale * 1e-6 / toolpoint::Complex(1.0 - r * r, 0.04 * r));
    }
    return s;
  };
  for (const double scale : {1.0, 1e300, 1e-300}) {
    const toolpoint::ModalFitResult r = toolpoint::fit_modes(sdof(scale), {}, "sdof");
    ASSERT_EQ(r.modes.size(), 1u) << scale;
    EXPECT_NEAR(r.modes[0].mode.frequency_hz, 916.0, 1e-6) << scale;
    EXPECT_NEAR(r.modes[0].mode.damping_ratio, 0.02, 1e-8) << scale;
    EXPECT_NEAR(r.modes[0].mode.mass_kg * scale / m_closed, 1.0, 1e-6) << scale;
  }
  EXPECT_THROW(toolpoint::fit_modes(sdof(1e-312), {}, "sdof"), toolpoint::NumericalError);
}

// A fitted mode that is overdamped (ζ ≥ 1: the fit spent a mode on the background, as on the
// example's FRF at 110 mm in review) is no resonance: the modal model refuses it as a fit's
// NumericalError (which the lobes study's mode-count search steps over), not as the caller's bad
// Mode (InvalidArgument "give ζ as a fraction", which blamed the user for the fit's result).
TEST(ModalFit, AnOverdampedFittedModeIsTheFitsNotTheCallers) {
  ModalFitResult r;
  FittedMode m;
  m.mode = {0.5, 1.65, 700.0};
  m.residue = 2.0;
  r.modes = {m};
  try {
    r.modal_model();
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("overdamped"), std::string::npos) << e.what();
  }
}

// The study (run_modal_fit_study) on noise-free modes: its model is the modes given (1e-9 relative,
// as RecoversThreeModesExactly), and its fitted series is the given FRF on the band's grid (1e-9
// of the largest response: the fit reproduces round-off-exact data) — the same values as
// fit_modes + fitted_frf called directly.
TEST(ModalFitStudy, ModelAndFittedSeriesFromTheGivenModes) {
  const FrfSeries frf = modal_frf(kModes, grid(100.0, 4000.0, 1.0));
  ModalFitOptions o;
  o.band_hz = std::make_pair(500.0, 3000.0);
  const ModalFitStudy s = run_modal_fit_study(frf, o, "three modes");
  ASSERT_EQ(s.model.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.model[i].frequency_hz / kModes[i].frequency_hz, 1.0, 1e-9) << i;
    EXPECT_NEAR(s.model[i].damping_ratio / kModes[i].damping_ratio, 1.0, 1e-9) << i;
    EXPECT_NEAR(s.model[i].mass_kg / kModes[i].mass_kg, 1.0, 1e-9) << i;
  }
  ASSERT_EQ(s.fitted.frequency_hz, grid(500.0, 3000.0, 1.0));
  double top = 0.0;
  for (const Complex& v : frf.values) top = std::max(top, std::abs(v));
  for (std::size_t i = 0; i < s.fitted.size(); ++i)
    EXPECT_LT(std::abs(s.fitted.values[i] - modal_receptance(kModes, s.fitted.frequency_hz[i])), 1e-9 * top) << i;
  const ModalFitResult direct = fit_modes(frf, o, "three modes");
  EXPECT_EQ(s.fitted.values, direct.fitted_frf(frf.frequency_hz).values);
  EXPECT_EQ(s.warnings, direct.warnings);
}

// One rule for what a modal model holds: a negated FRF's mode (negative residue) is left out of the
// study's model, and modal_model() refuses it; a positive residue with ζ < 1 is a resonance, ζ ≥ 1
// or a residue ≤ 0 is not.
TEST(ModalFitStudy, OneRuleForResonances) {
  FrfSeries frf = modal_frf({kModes[1]}, grid(700.0, 1200.0, 0.5));
  for (auto& v : frf.values) v = -v;
  const ModalFitStudy s = run_modal_fit_study(frf);
  ASSERT_EQ(s.fit.modes.size(), 1u);
  EXPECT_FALSE(s.fit.modes[0].is_resonance());
  EXPECT_TRUE(s.model.empty());
  EXPECT_THROW(s.fit.modal_model(), NumericalError);
  FittedMode m{};
  m.mode = {0.05, 0.5, 900.0};
  m.residue = 20.0;
  EXPECT_TRUE(m.is_resonance());
  m.mode.damping_ratio = 1.0;
  EXPECT_FALSE(m.is_resonance());
  m.mode.damping_ratio = 0.5;
  m.residue = 0.0;
  EXPECT_FALSE(m.is_resonance());
  m.residue = std::nan("");
  EXPECT_FALSE(m.is_resonance());
}
