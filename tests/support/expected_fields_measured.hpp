// The option tables of the measured-data, identification read-out and verdict types
// (option_fields.hpp; issue 26), expected by hand: each field's range as the hand-written check()
// had it before its table (signal.cpp, peaks.cpp, noise.cpp, identify.cpp,
// studies/identification.cpp, studies/rotational.cpp at f7cd67b), and its CLI flag and unit as
// `toolpoint filter` and `toolpoint rotational` registered them — not read from the tables, so a
// table that drifts from them fails (expected_fields.hpp's expect_edges and expect_table).
#pragma once

#include <limits>
#include <vector>

#include "support/expected_fields.hpp"
#include "toolpoint/identify/identify.hpp"
#include "toolpoint/io/uff.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/measured/peaks.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/rotational.hpp"

namespace toolpoint::testing {

// Old SavgolOptions::check: window < 1 or even refused, order < 0 refused, order ≥ window refused.
// The filter's flags: --window [frequency points], --order [-].
inline std::vector<ExpectedField<SavgolOptions>> savgol_expected_fields() {
  using S = SavgolOptions;
  return {{"SavgolOptions", "window", true, 1.0, kInf, false, false, 11.0, "--window", "frequency points", 1.0, "",
           TOOLPOINT_MEMBER(S, window)},
          {"SavgolOptions", "order", true, 0.0, kInf, false, false, 2.0, "--order", "-", 1.0, "", TOOLPOINT_MEMBER(S, order)}};
}

// Old PeakChangeOptions::check: the fractions !(v > 0 && v < 1) refused; warn_above !(> 0) or not
// finite refused; noise_prominence !(≥ 0) or not finite refused. No CLI flags.
inline std::vector<ExpectedField<PeakChangeOptions>> peak_change_expected_fields() {
  using P = PeakChangeOptions;
  return {{"PeakChangeOptions", "min_prominence", false, 0.0, 1.0, true, true, 0.3, "", "", 1.0, "",
           TOOLPOINT_MEMBER(P, min_prominence)},
          {"PeakChangeOptions", "min_height", false, 0.0, 1.0, true, true, 0.1, "", "", 1.0, "", TOOLPOINT_MEMBER(P, min_height)},
          {"PeakChangeOptions", "warn_above", false, 0.0, kInf, true, false, 0.05, "", "", 1.0, "",
           TOOLPOINT_MEMBER(P, warn_above)},
          {"PeakChangeOptions", "noise_prominence", false, 0.0, kInf, false, false, 6.0, "", "", 1.0, "",
           TOOLPOINT_MEMBER(P, noise_prominence)}};
}

// Old RotationalOptions::check: order other than 1, 2 refused; spacing !(> 0) or not finite
// refused. `toolpoint rotational`: --order (IsMember 1, 2), --spacing [m], --symmetrise,
// --assume-reciprocity.
inline std::vector<ExpectedField<RotationalOptions>> rotational_expected_fields() {
  using R = RotationalOptions;
  return {{"RotationalOptions", "order", true, 1.0, 2.0, false, false, 1.0, "--order", "-", 1.0, "", TOOLPOINT_MEMBER(R, order)},
          {"RotationalOptions", "spacing", false, 0.0, kInf, true, false, 0.02, "--spacing", "m", 1.0, "",
           TOOLPOINT_MEMBER(R, spacing)},
          {"RotationalOptions", "symmetrise", false, -kInf, kInf, false, false, 1.0, "--symmetrise", "-", 1.0, "",
           TOOLPOINT_MEMBER(R, symmetrise)},
          {"RotationalOptions", "assume_reciprocity", false, -kInf, kInf, false, false, 1.0, "--assume-reciprocity", "-", 1.0, "",
           TOOLPOINT_MEMBER(R, assume_reciprocity)}};
}

// Old TapTestFileOptions::check: order other than 1, 2 refused (the nodes and direction beside it);
// `toolpoint rotational --uff` takes it from --order.
inline std::vector<ExpectedField<TapTestFileOptions>> tap_test_file_expected_fields() {
  using T = TapTestFileOptions;
  return {
      {"TapTestFileOptions", "order", true, 1.0, 2.0, false, false, 1.0, "--order", "-", 1.0, "", TOOLPOINT_MEMBER(T, order)}};
}

// Old PeakOptions::check: !(p ≥ 0 && p < 1) refused.
inline std::vector<ExpectedField<PeakOptions>> peak_expected_fields() {
  using P = PeakOptions;
  return {
      // `toolpoint couple --prominence` (its default 0.1, the field's 0.02).
      {"PeakOptions", "min_prominence", false, 0.0, 1.0, false, true, 0.1, "--prominence", "-", 1.0, "",
       TOOLPOINT_MEMBER(P, min_prominence)}};
}

// Old NoiseEstimateOptions::check: window < 21 or even refused (local by SavgolOptions::check);
// floor either way.
inline std::vector<ExpectedField<NoiseEstimateOptions>> noise_estimate_expected_fields() {
  using N = NoiseEstimateOptions;
  return {{"NoiseEstimateOptions", "window", true, 21.0, kInf, false, false, 101.0, "", "", 1.0, "", TOOLPOINT_MEMBER(N, window)},
          {"NoiseEstimateOptions", "floor", false, -kInf, kInf, false, false, 0.0, "", "", 1.0, "", TOOLPOINT_MEMBER(N, floor)}};
}

// Old ReadoutOptions::check: !(cond_warning > 1), !(gain_warning > 0), !(reciprocity_warning > 0)
// refused (so NaN refused, +∞ — never warn — accepted).
inline std::vector<ExpectedField<ReadoutOptions>> readout_expected_fields() {
  using R = ReadoutOptions;
  return {{"ReadoutOptions", "cond_warning", false, 1.0, kInf, true, false, 1e4, "", "", 1.0, "",
           TOOLPOINT_MEMBER(R, cond_warning)},
          {"ReadoutOptions", "reciprocity_warning", false, 0.0, kInf, true, false, 0.2, "", "", 1.0, "",
           TOOLPOINT_MEMBER(R, reciprocity_warning)},
          {"ReadoutOptions", "gain_warning", false, 0.0, kInf, true, false, 10.0, "", "", 1.0, "",
           TOOLPOINT_MEMBER(R, gain_warning)}};
}

// Old VerdictOptions::check: !(doubt > 1 && doubt ≤ fail && fail finite) refused, so each level
// > 1 on its own (the order between them checked beside the table).
inline std::vector<ExpectedField<VerdictOptions>> verdict_expected_fields() {
  using V = VerdictOptions;
  return {{"VerdictOptions", "residual_doubt", false, 1.0, kInf, true, false, 2.0, "", "", 1.0, "",
           TOOLPOINT_MEMBER(V, residual_doubt)},
          {"VerdictOptions", "residual_fail", false, 1.0, kInf, true, false, 4.0, "", "", 1.0, "",
           TOOLPOINT_MEMBER(V, residual_fail)}};
}

// Old UffWriteOptions::check: byte order other than 1, 2 refused; binary either way (`toolpoint
// taptest --binary`).
inline std::vector<ExpectedField<UffWriteOptions>> uff_write_expected_fields() {
  using U = UffWriteOptions;
  return {{"UffWriteOptions", "binary", false, -kInf, kInf, false, false, 1.0, "--binary", "-", 1.0, "",
           TOOLPOINT_MEMBER(U, binary)},
          {"UffWriteOptions", "byte_order", true, 1.0, 2.0, false, false, 2.0, "", "", 1.0, "", TOOLPOINT_MEMBER(U, byte_order)}};
}

// Old PlotOptions::check: timeout_s not finite or !(> 0) refused.
inline std::vector<ExpectedField<plot::PlotOptions>> plot_expected_fields() {
  using P = plot::PlotOptions;
  return {{"PlotOptions", "timeout_s", false, 0.0, kInf, true, false, 10.0, "", "", 1.0, "", TOOLPOINT_MEMBER(P, timeout_s)}};
}

// Old FrfFigureOptions::check: mode_labels < 0 refused; min_peak_ratio !(> 1) or not finite refused.
inline std::vector<ExpectedField<plot::FrfFigureOptions>> frf_figure_expected_fields() {
  using F = plot::FrfFigureOptions;
  return {{"FrfFigureOptions", "mode_labels", true, 0.0, kInf, false, false, 6.0, "", "", 1.0, "",
           TOOLPOINT_MEMBER(F, mode_labels)},
          {"FrfFigureOptions", "min_peak_ratio", false, 1.0, kInf, true, false, 1.5, "", "", 1.0, "",
           TOOLPOINT_MEMBER(F, min_peak_ratio)}};
}

}  // namespace toolpoint::testing
