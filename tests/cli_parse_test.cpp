// Tests of the CLI's option-text parsers (apps/toolpoint/parse.hpp), compiled into the suite.
#include <gtest/gtest.h>

#include "parse.hpp"
#include "toolpoint/error.hpp"

using namespace toolpoint;
using toolpoint::cli::parse_frequency_grid;
using toolpoint::cli::parse_range;

TEST(CliParse, GridIncludesBothEnds) {
  const auto f = parse_frequency_grid("10:20:2.5", "--f").values();
  ASSERT_EQ(f.size(), 5u);
  EXPECT_DOUBLE_EQ(f.front(), 10.0);
  EXPECT_DOUBLE_EQ(f.back(), 20.0);
  EXPECT_EQ(parse_frequency_grid("1:2:0.1", "--f").values().size(), 11u);
}

TEST(CliParse, MalformedGridsAreRejectedWithTheOptionName) {
  for (const char* bad : {"10:20", "a:20:1", "10:20:0", "10:5:1", "0:10:1", "-5:10:1", "10:20:-1", "1:2:3:4", ""}) {
    try {
      parse_frequency_grid(bad, "--frequencies");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("--frequencies"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_frequency_grid("1:1e9:1e-3", "--f").values(), InvalidArgument);
}

TEST(CliParse, RangeParsing) {
  const auto [a, b] = parse_range("100:250.5", "--band");
  EXPECT_DOUBLE_EQ(a, 100.0);
  EXPECT_DOUBLE_EQ(b, 250.5);
  EXPECT_THROW(parse_range("100", "--band"), InvalidArgument);
  EXPECT_THROW(parse_range("x:1", "--band"), InvalidArgument);
}
