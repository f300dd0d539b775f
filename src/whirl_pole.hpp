// toolpoint: the stencil near a free piece's conical whirl pole (AssemblyModel::tool_point with a
// whirl, tool_point_two_plane; assembly.hpp's WhirlPole), shared by the per-frequency functions
// (assembly.cpp) and the lanes' sweep (sweep.cpp).
#pragma once

#include "toolpoint/model/assembly.hpp"

namespace toolpoint::detail {

// The stencil's value at f for the window W: `eval(x, out)` fills out[k] with the tool point at
// x[k] = f (1 + kWhirlPoleOffsets[k] W) (returns false where it cannot), combined by Richardson
// with kWhirlPoleWeights. The stencil must see G smooth: with A(h) the symmetric means,
// A(2W) − A(4W) = −12 c₂W², and Richardson's remaining error is about 64 c₄W⁴ ≈ 0.44 r² with
// r = |A(2W) − A(4W)|/|A(2W)| (taking c₄W⁴ ~ (c₂W²)²/|G|); r ≤ 3e-5 keeps it near
// kWhirlPoleTolerance. Where r is larger (an assembly resonance within the stencil's reach) W is
// halved, up to 12 times (the points come nearer the pole, whose rounding grows as (W₀/W)²);
// false if no W passes or `eval` fails (the caller then evaluates directly at f).
template <class M, class Eval>
bool whirl_pole_stencil(double f, double W, Eval eval, M& value) {
  for (int halving = 0; halving <= 12; ++halving, W *= 0.5) {
    double x[4];
    for (int k = 0; k < 4; ++k) x[k] = f * (1.0 + kWhirlPoleOffsets[k] * W);
    M g[4];
    if (!eval(x, g)) return false;
    const M a1 = 0.5 * (g[0] + g[1]), a2 = 0.5 * (g[2] + g[3]);
    if (!((a1 - a2).norm() <= 3e-5 * a1.norm())) continue;
    value = kWhirlPoleWeights[0] * g[0];
    for (int k = 1; k < 4; ++k) value += kWhirlPoleWeights[k] * g[k];
    return true;
  }
  return false;
}

}  // namespace toolpoint::detail
