// toolpoint: what every study shares. A study is one of the seed's procedures as a library call,
// the public API of that procedure (the CLI, the C++ examples and the Python package call it):
//
//     Result run_<x>_study(inputs, const <X>Options& options = {}, const ProgressCallback& progress = {});
//
//   * inputs are value types: an Assembly (with its joints: replace `assembly.holder_tool` to
//     study another joint), measured series (BlockSeries, FrfSeries) on their own grids;
//   * `<X>Options` has defaults and check(), which run_* calls first; its messages name the
//     option as `<X>Options::field` (the CLI adds its flag's spelling when it rethrows);
//   * the result carries everything computed and its `warnings` (nothing fatal; fatal problems
//     throw the typed exceptions of error.hpp), never prints, never writes files;
//   * `progress`, if given, is called with the fraction of the work done (0…1], one call at a
//     time, possibly from worker threads; it must not throw.
// Results convert to JSON with toolpoint/json.hpp (one spelling per field: the member's name).
// Units: SI; frequencies in Hz.
#pragma once

#include <functional>

namespace toolpoint {

// Fraction of a study's work done, 0…1 (see above).
using ProgressCallback = std::function<void(double fraction)>;

}  // namespace toolpoint
