// statistics.hpp against printed tables (Abramowitz & Stegun 26.2 and 26.4; values to the digits
// the tables give): the normal quantile to 1e-9, χ² exact for 1 and 2 degrees of freedom (1e-6
// against the six printed digits), the others to the six printed
// digits (5e-4 absolute, their rounding).
#include <gtest/gtest.h>

#include "toolpoint/error.hpp"
#include "toolpoint/statistics.hpp"

using namespace toolpoint;

TEST(Statistics, QuantilesAgainstTables) {
  EXPECT_NEAR(normal_quantile(0.975), 1.959963985, 1e-9);
  EXPECT_NEAR(normal_quantile(0.995), 2.575829304, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.99, 1), 6.634897, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841459, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.99, 2), 9.210340, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.95, 10), 18.307, 5e-4);
  EXPECT_NEAR(chi_square_quantile(0.999, 30), 59.703, 5e-4);
  EXPECT_NEAR(chi_square_quantile(0.999, 3), 16.266, 5e-4);
  EXPECT_NEAR(chi_square_quantile(0.001, 5), 0.210213, 5e-7);
  EXPECT_THROW(chi_square_quantile(0.5, 0), InvalidArgument);
  EXPECT_DOUBLE_EQ(quantile({3.0, 1.0, 2.0}, 0.5), 2.0);
}
