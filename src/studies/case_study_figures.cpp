// toolpoint: the figures of the seed's case study (case_study.hpp) — the seed's Fig. 2–5 and the
// forward check. Units: frequency Hz, FRFs m/N, joint parameters SI (JointParameters::unit).
#include <fmt/format.h>

#include "toolpoint/studies/case_study.hpp"

namespace toolpoint {

namespace {

// Two panels (|H| [m/N], phase [deg]) over frequency [Hz], the first trace's peaks labelled.
plot::Figure frf_panels(const std::vector<plot::FrfTrace>& traces, const std::string& title, const std::string& symbol) {
  plot::FrfFigureOptions fo;
  fo.title = title;
  fo.symbol = symbol;
  fo.mode_labels = 6;
  fo.peak_trace = 0;
  return plot::frf_figure(traces, fo);
}

// H of a block series: the model's, its noisy copy, the filtered copy.
std::vector<plot::FrfTrace> measured_traces(const BlockSeries& truth, const BlockSeries& noisy, const BlockSeries& filtered,
                                            double sigma) {
  return {{entry(truth, 0), "model (noise-free)", plot::CurveStyle::Line},
          {entry(noisy, 0), fmt::format("{:g} % noise", 100 * sigma), plot::CurveStyle::Points},
          {entry(filtered, 0), "Savitzky-Golay filtered", plot::CurveStyle::Dashed}};
}

}  // namespace

CaseStudyFigures case_study_figures(const CaseStudy& cs, const CaseStudyOptions& o) {
  CaseStudyFigures figs;
  figs.tool_point_frf = frf_panels(measured_traces(cs.sht_true, cs.sht_noisy, cs.sht_filtered, o.noise_sigma),
                                   "Tool point FRF H_{11}^{sht} (seed Fig. 2a, 4b)", "H^{sht}_{11}");
  figs.holder_tip_frf = frf_panels(measured_traces(cs.sh_true, cs.sh_noisy, cs.sh_filtered, o.noise_sigma),
                                   "Holder tip FRF H_{11}^{sh}, tool outside removed (seed Fig. 2b, 4a)", "H^{sh}_{11}");

  plot::JointFigureData clean;
  clean.frequency_hz = cs.sht_true.frequency_hz;
  clean.title = "Holder-tool joint from noise-free FRFs, Eq. (6) (seed Fig. 3)";
  for (int row = 0; row < 2; ++row)
    for (int column = 0; column < 2; ++column)
      clean.parameters.push_back(joint_curve(cs.clean, row, column, cs.reference, std::nullopt));
  figs.joint_noise_free = plot::joint_figure(clean);

  plot::JointFigureData noisy;
  noisy.frequency_hz = cs.sht_true.frequency_hz;
  noisy.title = cs.fitted ? fmt::format("k_{{yf}}, c_{{yf}} at {:g} % noise: seed read-out and band fit (seed Fig. 5)",
                                        100 * o.noise_sigma)
                          : fmt::format("k_{{yf}}, c_{{yf}} from {:g} % noise, filtered; read at the tool mode (seed Fig. 5)",
                                        100 * o.noise_sigma);
  plot::JointParameterCurve yf = cs.fitted ? joint_curve(cs.filtered, 0, 0, cs.reference, cs.fitted->identified, &*cs.fitted->fit)
                                           : joint_curve(cs.filtered, 0, 0, cs.reference, cs.filtered_readout.medians(), nullptr,
                                                         &cs.filtered_readout);
  if (cs.fitted) {
    yf.other_stiffness = cs.filtered_readout.parameters[static_cast<std::size_t>(JointParameter::k_yf)].median;
    yf.other_damping = cs.filtered_readout.parameters[static_cast<std::size_t>(JointParameter::c_yf)].median;
    yf.identified_label = "band fit";
  }
  noisy.parameters.push_back(yf);
  noisy.band_hz = std::make_pair(cs.filtered_readout.band_lo_hz, cs.filtered_readout.band_hi_hz);
  figs.joint_filtered = plot::joint_figure(noisy);

  std::vector<plot::FrfTrace> check{{entry(cs.sht_true, 0), "true tool point FRF", plot::CurveStyle::Line},
                                    {entry(cs.sht_verified, 0), "Eq. (5), joint by the seed's read-out",
                                     plot::CurveStyle::Dashed}};
  if (cs.fitted) check.push_back({entry(cs.sht_fitted, 0), "Eq. (5), joint by the band fit", plot::CurveStyle::Points});
  figs.verification = frf_panels(check, "Forward check: identified holder-tool joint coupled back", "H^{sht}_{11}");
  return figs;
}

}  // namespace toolpoint
