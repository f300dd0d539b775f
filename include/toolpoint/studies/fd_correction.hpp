// toolpoint: the finite-difference error of a tap test, estimated on the model, to be subtracted
// from the rotational block measured by finite differences (a model-based truncation correction).
//
// Why. Differences of translational FRFs at points s apart give the rotational entries L, N, P with
// an error of O(s²) (N, L) to O(s) (P) (signal.hpp) — far above what a band fit resolves. On the
// example, SH11 from the holder at s = 20 mm, second order, moves the fitted k_yf by +11 % and k_θm
// by +8 % where the noise alone would allow 0.1 %; the closed form suffers the same. The same
// differences applied to the model's own FRFs at the same points, against the model's exact tip
// block, estimate that error:
//     E(f) = FD[model's H_ij at the points](f) − model's tip block(f)
// and measured − E removes it to the extent the model is right near the tip: what remains is of
// first order in the model's error times the truncation error. On the example with the model's
// spindle–holder joint twice too stiff: k_yf +11 % → −3.5 %, k_θm +8 % → −1.6 % (docs/correctness.md, Findings).
// The model's H_ij are the station receptances AssemblyModel::tool_stations / holder_stations
// (the tool of the whole assembly; the holder with the tool outside removed), the points at
// i·s from the tip, exactly the slots the measurement has (so reciprocity fills and the P method
// are the measurement's), differenced with the same RotationalOptions.
// Units: SI (H m/N, L 1/N, N rad/N, P rad/(N·m)); frequencies in Hz; s in m.
#pragma once

#include <array>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/tap_test.hpp"

namespace toolpoint {

struct FiniteDifferenceError {
  BlockSeries error;                     // E per frequency (H's entry is 0: H00 is measured, not differenced)
  BlockSeries exact;                     // the model's tip block
  std::array<double, 4> max_relative{};  // max over f of |E_e| / max over f of |exact_e|, e = H, L, N, P
  std::vector<std::string> warnings;
};

// E on `frequency_hz` (> 0, increasing) for the points of `layout` (which H_ij exist: the measured
// set) on `side`, differenced by `options` (its spacing is the points' spacing). Throws
// InvalidArgument (options; points that do not fit on the tool's overhang or the holder) and what
// the model throws.
FiniteDifferenceError finite_difference_error(const Assembly& assembly, TapSide side, const std::vector<double>& frequency_hz,
                                              const PointFrfs& layout, const RotationalOptions& options);

// The measured tip block with the estimated error removed: measured − E at every frequency (H is
// left as measured: E's H entry is 0). Throws InvalidArgument when the two are not on one grid
// (E must be computed on the measurement's own frequencies).
BlockSeries remove_finite_difference_error(const BlockSeries& measured, const FiniteDifferenceError& error);

}  // namespace toolpoint
