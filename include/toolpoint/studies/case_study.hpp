// toolpoint: the seed's analytical case study (Section 3), end to end — and beyond it, the band fit
// side by side with the seed's read-out.
//
// On an assembly with a known holder–tool joint: predict SH11 and SHT11 (Eq. 1–5) → identify
// K_ht over the whole band (Eq. 6; flat and equal to the input, the seed's Fig. 3) → distort SH11
// and SHT11 with multiplicative noise (every FRF entry by its own random factors of mean 1 and
// standard deviation σ, as the seed did) → Savitzky–Golay filter → read the parameters at the
// tool mode found by effect analysis (the seed's Fig. 5), and fit the joint's constants to the
// raw noisy data with intervals (joint_fit.hpp) → couple each result back (Eq. 5) and compare
// with the true tool point FRF. Both identifications go through run_identification_study
// (studies/identification.hpp): one rule for the band, one verdict.
// Units: SI; frequencies in Hz.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/identification.hpp"

namespace toolpoint {

struct CaseStudyOptions {
  double noise_sigma = 0.05;    // σ of the multiplicative noise (0.05 = 5 %, the seed's)
  std::uint64_t seed = 1;       // SH11 uses `seed`, SHT11 `seed + 1`
  SavgolOptions filter{81, 2};  // window in frequency points (81 Hz on a 1 Hz grid), order
  bool apply_filter = true;
  double band_width = 0.02;     // read-out band: tool mode × (1 ± band_width)
  bool fit = true;              // also fit the joint to the raw noisy data (the band fit)
  JointFitOptions fit_options;  // its intervals (bootstrap by default), threads, seed
  // Throws InvalidArgument naming `CaseStudyOptions::<field>` (case_study_fields' ranges), then the
  // filter's and the fit's checks.
  void check() const;
};

/// \brief CaseStudyOptions' scalar fields defined once (option_fields.hpp): check(), `toolpoint
/// demo`'s `--sigma` and `--width` and Python's CaseStudyOptions attributes derive from this table
/// (seed, filter and fit_options have their own definitions; `--no-fit` sets fit by hand).
/// \return the table, in the order of the fields
const std::vector<OptionField<CaseStudyOptions>>& case_study_fields();

struct CaseStudy {
  Assembly assembly;
  JointParameters reference;  // the assembly's holder–tool joint (Table 1 in the example)
  BlockSeries sh_true, sht_true, sh_noisy, sht_noisy, sh_filtered, sht_filtered;
  JointSeries clean, noisy, filtered;                           // K_ht(ω) from true, noisy and filtered data
  std::array<double, 8> clean_max_deviation{};                  // max over the band of |p(ω)/p_ref − 1|
  EffectAnalysis effect;                                        // which mode the holder–tool joint controls
  double mode_hz = 0.0;                                         // that mode in the (filtered) measured SHT11
  JointReadout clean_readout, noisy_readout, filtered_readout;  // read in the band at the mode
  BlockSeries sht_verified;                                     // SHT11 with the filtered read-out constants
  std::vector<ModeComparison> verification;                     // true SHT11 against sht_verified
  Identification seed;                                          // the seed's procedure on the noisy, filtered data
  std::optional<Identification> fitted;                         // the band fit on the raw noisy data (options.fit)
  BlockSeries sht_fitted;                                       // SHT11 with the fitted constants
  std::vector<ModeComparison> fit_verification;                 // true SHT11 against sht_fitted
  std::vector<std::string> warnings;                            // every one, the identifications' included
};

// Runs the case study on `assembly` (its holder–tool joint must be elastic: it is the reference).
// `progress` follows the band fit's identification (the study's long part; none without
// options.fit). Throws InvalidArgument for a rigid reference joint or bad options.
CaseStudy run_case_study(const Assembly& assembly, const CaseStudyOptions& options = {}, const ProgressCallback& progress = {});

// The case study's figures (plot.hpp): frequency in Hz, FRFs in m/N, the joint's parameters in
// their SI units (JointParameters::unit). `options` as the study ran (its noise level is in the
// legends and titles).
struct CaseStudyFigures {
  plot::Figure tool_point_frf;    // seed Fig. 2a, 4b: H of SHT11 noise-free, noisy, filtered
  plot::Figure holder_tip_frf;    // seed Fig. 2b, 4a: H of SH11 likewise
  plot::Figure joint_noise_free;  // seed Fig. 3: the eight parameters from noise-free FRFs (Eq. 6), the reference as lines
  plot::Figure joint_filtered;    // seed Fig. 5: k_yf, c_yf from the filtered noisy FRFs, the read-out (and the band fit)
  plot::Figure verification;      // the true H of SHT11 and the identified joints coupled back (Eq. 5)
};
CaseStudyFigures case_study_figures(const CaseStudy& study, const CaseStudyOptions& options);

}  // namespace toolpoint
