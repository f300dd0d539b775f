// Tests of frequency grids (conventions module).
#include <gtest/gtest.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

using namespace toolpoint;

TEST(Conventions, GridIncludesBothEnds) {
  const auto f = FrequencyGrid{10.0, 20.0, 2.5}.values();
  ASSERT_EQ(f.size(), 5u);
  EXPECT_DOUBLE_EQ(f.front(), 10.0);
  EXPECT_DOUBLE_EQ(f.back(), 20.0);
  // 0.1 steps are not exact in binary; the end point still belongs to the grid.
  EXPECT_EQ((FrequencyGrid{1.0, 2.0, 0.1}.values().size()), 11u);
}

TEST(Conventions, InvalidGridsAreRejected) {
  for (const FrequencyGrid& bad : {FrequencyGrid{10, 20, 0}, FrequencyGrid{10, 5, 1}, FrequencyGrid{0, 10, 1},
                                   FrequencyGrid{-5, 10, 1}, FrequencyGrid{10, 20, -1}, FrequencyGrid{1, 1e9, 1e-3}})
    EXPECT_THROW(bad.values(), InvalidArgument) << bad.start_hz << ":" << bad.stop_hz << ":" << bad.step_hz;
}
