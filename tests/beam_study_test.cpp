// Tests of run_beam_study (studies/beam.hpp) against closed forms: the section's formulas, the
// Euler–Bernoulli free–free frequencies of a slender beam, the rigid-body receptance far below the
// first mode; and its receptance against beam.hpp's functions called directly.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "toolpoint/error.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/studies/beam.hpp"

namespace toolpoint {
namespace {

constexpr double kPi = std::numbers::pi;

BeamStudyOptions steel_rod(double length, double diameter, double inner = 0.0) {
  BeamStudyOptions o;
  o.length = length;
  o.outer_diameter = diameter;
  o.inner_diameter = inner;
  return o;  // the default material: E 2e11 Pa, ν 0.3, ρ 7800 kg/m³, η 0
}

// The section by its textbook formulas (Hutchinson's κ for a hollow circle, G = E/(2(1+ν))).
// Tolerance 1e-14 relative: the same few operations, in another order.
TEST(BeamStudy, SectionByItsFormulas) {
  const double D = 0.016, d = 0.006, E = 2.0e11, nu = 0.3, rho = 7800.0;
  const BeamStudy r = run_beam_study(steel_rod(0.1, D, d));
  const double A = kPi * (D * D - d * d) / 4.0, I = kPi * (D * D * D * D - d * d * d * d) / 64.0;
  const double a = D / 2.0, b = d / 2.0, a2 = a * a, b2 = b * b;
  const double kappa = 6.0 * (a2 + b2) * (a2 + b2) * (1.0 + nu) * (1.0 + nu) /
                       (7.0 * a2 * a2 + 34.0 * a2 * b2 + 7.0 * b2 * b2 + nu * (12.0 * a2 * a2 + 48.0 * a2 * b2 + 12.0 * b2 * b2) +
                        nu * nu * (4.0 * a2 * a2 + 16.0 * a2 * b2 + 4.0 * b2 * b2));
  const double G = E / (2.0 * (1.0 + nu));
  EXPECT_NEAR(r.section.area / A, 1.0, 1e-14);
  EXPECT_NEAR(r.section.second_moment / I, 1.0, 1e-14);
  EXPECT_NEAR(r.section.shear_coefficient / kappa, 1.0, 1e-14);
  EXPECT_NEAR(r.section.rhoA / (rho * A), 1.0, 1e-14);
  EXPECT_NEAR(r.section.rhoI / (rho * I), 1.0, 1e-14);
  EXPECT_NEAR(r.section.cutoff_frequency_hz / (std::sqrt(kappa * G * A / (rho * I)) / (2.0 * kPi)), 1.0, 1e-14);
  EXPECT_EQ(r.modes.size(), 5u);  // the default count; no grid, no receptance
  EXPECT_EQ(r.receptance.size(), 0u);
  EXPECT_EQ(r.method, "exact");
  // A κ given is the κ used.
  BeamStudyOptions o = steel_rod(0.1, D, d);
  o.shear_coefficient = 0.7;
  EXPECT_EQ(run_beam_study(o).section.shear_coefficient, 0.7);
}

// A slender free–free rod tends to Euler–Bernoulli: f_n = (β_n L)²/(2πL²) sqrt(EI/ρA), β_n L the
// roots of cos βL cosh βL = 1. Shear and rotary inertia lower a Timoshenko frequency, by about
// (β_n r)²(1 + E/(κG))/2 to first order (r = sqrt(I/A), the radius of gyration); the test asks
// for a frequency below Euler–Bernoulli's by less than twice that estimate, (β_n r)²(1 + E/(κG)):
// 1e-4…5e-4 here, so a wrong root or a lost factor would show.
TEST(BeamStudy, SlenderRodTendsToEulerBernoulli) {
  const double L = 4.0, D = 0.016, E = 2.0e11, nu = 0.3, rho = 7800.0;
  BeamStudyOptions o = steel_rod(L, D);
  o.modes = 3;
  const BeamStudy r = run_beam_study(o);
  ASSERT_EQ(r.modes.size(), 3u);
  const double A = kPi * D * D / 4.0, I = kPi * D * D * D * D / 64.0, radius = std::sqrt(I / A);
  const double E_over_kG = E / (r.section.shear_coefficient * E / (2.0 * (1.0 + nu)));
  const double betaL[] = {4.730040744862704, 7.853204624095838, 10.995607838001671};
  for (int n = 0; n < 3; ++n) {
    const double beta = betaL[n] / L;
    const double eb = betaL[n] * betaL[n] / (2.0 * kPi * L * L) * std::sqrt(E * I / (rho * A));
    const double lowered = 1.0 - r.modes[static_cast<std::size_t>(n)].frequency_hz / eb;
    const double bound = beta * beta * radius * radius * (1.0 + E_over_kG);
    EXPECT_GT(lowered, 0.0) << "mode " << n + 1;
    EXPECT_LT(lowered, bound) << "mode " << n + 1;
    EXPECT_FALSE(r.modes[static_cast<std::size_t>(n)].above_cutoff);
  }
}

// Far below the first mode (7 kHz here, at 1 and 2 Hz) a free–free segment moves as a rigid body: a
// force at end 1 translates the mass m and turns the body about its centre against
// J = ρA L³/12 + ρI L (rotary inertia included), so T11's H = −(1/m + (L/2)²/J)/ω² and
// P = −(1/J)/ω². The elastic part adds the static flexibility under the inertia loads: about
// (f/f₁)² ≈ 2e-8 of H, and for P, where a moment bends the whole length, about J ω² L/EI ≈ 8e-7 at
// 1 Hz. Tolerances: 1e-6 on H; on P three times J ω² L/EI, and the departure must grow as ω²
// (within 1 %: it is the elastic part, not an error in the rigid-body terms).
TEST(BeamStudy, RigidBodyReceptanceFarBelowTheFirstMode) {
  const double L = 0.1, E = 2.0e11;
  BeamStudyOptions o = steel_rod(L, 0.016);
  o.frequency_hz = {1.0, 2.0};
  const BeamStudy r = run_beam_study(o);
  ASSERT_EQ(r.receptance.size(), 2u);
  const double m = r.section.rhoA * L, J = r.section.rhoA * L * L * L / 12.0 + r.section.rhoI * L;
  double departure[2];
  for (std::size_t i = 0; i < 2; ++i) {
    const double w = 2.0 * kPi * o.frequency_hz[i];
    const Block& b = r.receptance.blocks[i];
    EXPECT_NEAR(b(0, 0).real() / (-(1.0 / m + L * L / 4.0 / J) / (w * w)), 1.0, 1e-6);
    departure[i] = 1.0 - b(1, 1).real() / (-(1.0 / J) / (w * w));
    EXPECT_LT(std::abs(departure[i]), 3.0 * J * w * w * L / (E * r.section.second_moment)) << o.frequency_hz[i];
  }
  EXPECT_NEAR(departure[1] / departure[0], 4.0, 0.04);
}

// The receptance is beam.hpp's, by the method asked for: the same values as exact_receptance and
// ModalBeam::receptance called directly (exactly: the same computation), the method said, and the
// truncated modal sum flagged where the grid passes its highest mode.
TEST(BeamStudy, ReceptanceIsBeamHppsByEitherMethod) {
  BeamStudyOptions o = steel_rod(0.123, 0.016, 0.004);
  o.material.loss_factor = 0.002;
  o.modes = 0;
  o.frequency_hz = {500.0, 5000.0, 20000.0};
  o.block = EndBlock::T12;
  const BeamStudy exact = run_beam_study(o);
  EXPECT_TRUE(exact.modes.empty());
  const SectionProperties sp = exact.segment.properties();
  const BlockSeries direct = exact_receptance(sp, o.length, o.frequency_hz, EndBlock::T12);
  ASSERT_EQ(exact.receptance.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(exact.receptance.blocks[i], direct.blocks[i]);
  EXPECT_TRUE(exact.warnings.empty());

  o.method = BeamMethod::Modal;
  o.modal = {2, true};
  const BeamStudy modal = run_beam_study(o);
  EXPECT_EQ(modal.method, "modal (2 modes + static residual)");
  const BlockSeries summed = ModalBeam(sp, o.length, o.modal).receptance(o.frequency_hz, EndBlock::T12);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(modal.receptance.blocks[i], summed.blocks[i]);
  ASSERT_EQ(modal.warnings.size(), 1u);  // the 2nd mode of this 123 mm tube is near 13 kHz, below 20 kHz
  EXPECT_NE(modal.warnings[0].find("BeamStudyOptions::modal.modes"), std::string::npos) << modal.warnings[0];

  const nlohmann::json j = modal;
  EXPECT_EQ(j["method"], modal.method);
  EXPECT_EQ(j["section"]["shear_coefficient"], modal.section.shear_coefficient);
  EXPECT_TRUE(j["modes"].empty());
}

TEST(BeamStudy, OptionsNameTheirFields) {
  BeamStudyOptions o = steel_rod(0.1, 0.016);
  o.modes = -1;
  EXPECT_THROW(
      {
        try {
          run_beam_study(o);
        } catch (const InvalidArgument& e) {
          EXPECT_NE(std::string(e.what()).find("BeamStudyOptions::modes"), std::string::npos) << e.what();
          throw;
        }
      },
      InvalidArgument);
  o.modes = 1;
  o.frequency_hz = {0.0};
  EXPECT_THROW(run_beam_study(o), InvalidArgument);
  o.frequency_hz = {};
  o.length = -0.1;  // the segment's own check
  EXPECT_THROW(run_beam_study(o), InvalidArgument);
}

// The study at speed is beam.hpp's whirl functions called directly (the oracle of those is
// tests/spin_test.cpp's finite-element rotor): the same frequencies to round-off (1e-14), the
// receptance the x–x part (F + B)/2 of spinning_receptance; at speed 0 the standstill study; the
// Campbell diagram one whirl list per speed, forward rising and backward falling.
TEST(BeamStudy, SpinningIsBeamHppsWhirls) {
  BeamStudyOptions o = steel_rod(0.15, 0.04);
  o.modes = 3;
  const BeamStudy still = run_beam_study(o);
  EXPECT_FALSE(still.whirl.has_value());
  o.speed_rpm = 30000.0;
  o.frequency_hz = {500.0, 7000.0};
  o.campbell_rpm = {0.0, 20000.0, 40000.0};
  const BeamStudy r = run_beam_study(o);
  ASSERT_TRUE(r.whirl.has_value());
  const double spin = 30000.0 * 2.0 * kPi / 60.0;
  const WhirlFrequencies w = whirl_frequencies(r.properties, 0.15, spin, 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(r.whirl->forward_hz[k], w.forward_hz[k], 1e-14 * w.forward_hz[k]);
    EXPECT_NEAR(r.whirl->backward_hz[k], w.backward_hz[k], 1e-14 * w.backward_hz[k]);
  }
  for (std::size_t i = 0; i < 2; ++i) {
    const Block4 b = spinning_receptance(r.properties, 0.15, o.frequency_hz[i], spin).b11;
    EXPECT_LE((r.receptance.blocks[i] - b.topLeftCorner<2, 2>()).norm(), 1e-14 * b.norm());
  }
  ASSERT_EQ(r.campbell.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(r.campbell[0].forward_hz[k], still.modes[k].frequency_hz, 1e-9 * still.modes[k].frequency_hz);
    EXPECT_GT(r.campbell[2].forward_hz[k], r.campbell[1].forward_hz[k]);
    EXPECT_LT(r.campbell[2].backward_hz[k], r.campbell[1].backward_hz[k]);
  }
  const nlohmann::json j = r;
  EXPECT_EQ(j["whirl"]["forward_hz"].size(), 3u);
  EXPECT_EQ(j["whirl"]["backward_hz"].size(), 3u);
  EXPECT_EQ(j["campbell"].size(), 3u);
  EXPECT_TRUE(j["campbell"][0]["conical_hz"] == 0.0);
  const plot::Figure fig = campbell_figure(r, "Campbell");
  EXPECT_NO_THROW(fig.check());
  EXPECT_EQ(fig.panels[0].curves.size(), 2u * 3u + 2u);  // forward and backward per mode, conical, 1× line
}

// Bad speeds: negative, rad/s-sized slips far below any spindle (impossible), the modal method at
// speed, a Campbell list that is not increasing; a speed below 1000 rpm only warns (likely rad/s).
TEST(BeamStudy, SpeedsAreChecked) {
  auto message = [](const BeamStudyOptions& o) {
    try {
      run_beam_study(o);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  BeamStudyOptions o = steel_rod(0.15, 0.04);
  o.speed_rpm = -100.0;
  EXPECT_NE(message(o).find("BeamStudyOptions::speed_rpm"), std::string::npos);
  o.speed_rpm = 10.0;  // below 1000/40 rpm
  EXPECT_NE(message(o).find("BeamStudyOptions::speed_rpm"), std::string::npos);
  o.speed_rpm = 20000.0;
  o.method = BeamMethod::Modal;
  EXPECT_NE(message(o).find("BeamStudyOptions::method"), std::string::npos);
  o.method = BeamMethod::Exact;
  o.campbell_rpm = {0.0, 30000.0, 20000.0};
  EXPECT_NE(message(o).find("BeamStudyOptions::campbell_rpm"), std::string::npos);
  o.campbell_rpm = {};
  o.speed_rpm = 300.0;  // 300 rad/s would be 2865 rpm: plausible as rpm only barely — said
  const BeamStudy r = run_beam_study(o);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("rad/s"), std::string::npos) << r.warnings[0];
}

}  // namespace
}  // namespace toolpoint
