// toolpoint: parallel_for over independent items (parallel.hpp).
#include "toolpoint/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <fmt/format.h>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#include "toolpoint/error.hpp"

namespace toolpoint {

void ParallelOptions::check() const { check_fields(parallel_fields(), *this, "ParallelOptions"); }

const std::vector<OptionField<ParallelOptions>>& parallel_fields() {
  using O = ParallelOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "threads",
        .kind = FieldKind::Integer,
        .min = 0.0,
        .max = 1024.0,
        .note = "0: every core",
        .help = "worker threads; results are identical for any number",
        .cli_name = "threads"},
       nullptr,
       [](O& o) -> int& { return o.threads; }}};
  return fields;
}

int ParallelOptions::resolved(std::size_t count) const {
  check();
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t wanted = threads > 0 ? static_cast<std::size_t>(threads) : cores;
  return static_cast<int>(std::max<std::size_t>(1, std::min(wanted, count)));
}

void parallel_for(std::size_t count, const ParallelOptions& options, const std::function<void(std::size_t)>& body,
                  const std::function<void(double)>& progress) {
  if (count == 0) return;
  const int workers = options.resolved(count);
  std::atomic<std::size_t> next{0};
  // The lowest index that failed so far; items above it are skipped, items below still run, so
  // the exception reported is the same for any number of threads.
  std::atomic<std::size_t> first_failure{std::numeric_limits<std::size_t>::max()};
  std::mutex lock;  // guards `failure` and the progress calls
  std::exception_ptr failure;
  std::size_t done = 0;
  auto work = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= count || i > first_failure.load()) return;
      try {
        body(i);
      } catch (...) {
        std::lock_guard<std::mutex> guard(lock);
        if (i < first_failure.load()) {
          first_failure = i;
          failure = std::current_exception();
        }
        continue;
      }
      if (progress) {
        std::lock_guard<std::mutex> guard(lock);
        progress(static_cast<double>(++done) / static_cast<double>(count));
      }
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(workers - 1));
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace toolpoint
