// toolpoint: independent work items on every core, with results identical for any thread count.
//
// The rule that makes results reproducible: item i writes only to its own slot i (and draws its
// random numbers from a seed derived from i, never from a shared generator); the caller combines
// the slots in index order afterwards. Which thread runs which item then cannot change a bit of
// the result. std::thread only (no pool kept between calls: the work items here are
// milliseconds to seconds, so starting a few threads per call is noise).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "toolpoint/option_fields.hpp"

namespace toolpoint {

struct ParallelOptions {
  int threads = 0;  // worker threads; 0: every core (std::thread::hardware_concurrency), 1: none
  // Throws InvalidArgument naming `ParallelOptions::threads` outside parallel_fields()' 0…1024.
  void check() const;
  // The number of threads to use for `count` items: min(count, threads or the core count), ≥ 1.
  int resolved(std::size_t count) const;
};

// ParallelOptions' fields (option_fields.hpp): threads, 0…1024 (0: every core), flag --threads. The
// Options types that run on threads take this field for theirs (UncertaintyOptions::parallel, …).
const std::vector<OptionField<ParallelOptions>>& parallel_fields();

// Runs body(i) for every i in [0, count), on ParallelOptions::resolved(count) threads (the
// calling thread is one of them). Items are claimed one at a time in index order.
// `progress`, if given, is called with the fraction of items done (0…1], one call at a time
// (under a lock), from whichever thread finished an item.
// If items throw, every item below the lowest failing index still runs, items above it are
// skipped, and the exception of the lowest failing index is rethrown: the same exception
// whatever the thread count.
void parallel_for(std::size_t count, const ParallelOptions& options, const std::function<void(std::size_t)>& body,
                  const std::function<void(double)>& progress = {});

}  // namespace toolpoint
