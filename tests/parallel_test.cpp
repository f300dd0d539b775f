// Tests of parallel_for: every item once, results independent of the thread count, the same
// exception whatever the thread count, progress monotone and complete.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/parallel.hpp"

using namespace toolpoint;

TEST(Parallel, EveryItemRunsOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> hits(1000);
    parallel_for(hits.size(), ParallelOptions{threads}, [&](std::size_t i) { hits[i]++; });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "item " << i << ", " << threads << " threads";
  }
}

TEST(Parallel, SlotResultsAreBitIdenticalForAnyThreadCount) {
  // Each item does floating-point work of its own; summed in index order afterwards, the total
  // must not depend on the thread count (an independent serial loop is the reference).
  auto item = [](std::size_t i) {
    double s = 0.0;
    for (int k = 1; k < 200; ++k) s += std::sin(static_cast<double>(i * 31 + static_cast<std::size_t>(k))) / k;
    return s;
  };
  double serial = 0.0;
  for (std::size_t i = 0; i < 500; ++i) serial += item(i);
  for (int threads : {1, 2, 4}) {
    std::vector<double> slot(500);
    parallel_for(slot.size(), ParallelOptions{threads}, [&](std::size_t i) { slot[i] = item(i); });
    double total = 0.0;
    for (double v : slot) total += v;
    EXPECT_EQ(total, serial) << threads << " threads";
  }
}

TEST(Parallel, TheLowestFailingItemsExceptionIsRethrownForAnyThreadCount) {
  for (int threads : {1, 2, 4}) {
    std::atomic<int> ran_below{0};
    try {
      parallel_for(200, ParallelOptions{threads}, [&](std::size_t i) {
        if (i < 37) ran_below++;
        if (i == 37 || i == 120 || i == 150) throw std::runtime_error("item " + std::to_string(i));
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 37") << threads << " threads";
    }
    EXPECT_EQ(ran_below.load(), 37) << "every item below the failing one runs";
  }
}

TEST(Parallel, ProgressIsMonotoneAndEndsAtOne) {
  std::vector<double> seen;
  parallel_for(
      64, ParallelOptions{2}, [](std::size_t) {}, [&](double f) { seen.push_back(f); });
  ASSERT_EQ(seen.size(), 64u);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
}

TEST(Parallel, OptionsAreChecked) {
  EXPECT_THROW(ParallelOptions{-1}.check(), InvalidArgument);
  EXPECT_THROW(ParallelOptions{5000}.check(), InvalidArgument);
  EXPECT_EQ(ParallelOptions{8}.resolved(3), 3);
  EXPECT_EQ(ParallelOptions{1}.resolved(100), 1);
  EXPECT_GE(ParallelOptions{0}.resolved(100), 1);
  parallel_for(0, ParallelOptions{}, [](std::size_t) { FAIL(); });
}
