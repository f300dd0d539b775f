// Tests of the CLI's option-text parsers (apps/toolpoint/parse.hpp), compiled into the suite.
#include <gtest/gtest.h>

#include "parse.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/uff.hpp"

using namespace toolpoint;
using toolpoint::cli::parse_frequency_grid;
using toolpoint::cli::parse_frf_format;
using toolpoint::cli::parse_frf_ordinate;
using toolpoint::cli::parse_frf_value_format;
using toolpoint::cli::parse_interpolation;
using toolpoint::cli::parse_range;
using toolpoint::cli::parse_uff_direction;

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

TEST(CliParse, UffDirections) {
  EXPECT_EQ(parse_uff_direction("+X", "--d"), 1);
  EXPECT_EQ(parse_uff_direction("z", "--d"), 3);
  EXPECT_EQ(parse_uff_direction("-ry", "--d"), -5);
  EXPECT_EQ(parse_uff_direction("Y-", "--d"), -2);
  EXPECT_EQ(parse_uff_direction("-6", "--d"), -6);
  EXPECT_EQ(parse_uff_direction("+3", "--d"), 3);
  EXPECT_EQ(parse_uff_direction(" scalar ", "--d"), 0);
  for (const char* bad : {"7", "+W", "", "+", "x+y", "99999999999999999999"})
    EXPECT_THROW(parse_uff_direction(bad, "--d"), InvalidArgument) << bad;
  // The library's names read back (uff_direction_name is the inverse).
  for (int d = -6; d <= 6; ++d) EXPECT_EQ(parse_uff_direction(uff_direction_name(d), "--d"), d);
}

TEST(CliParse, FrfFormatsOrdinatesAndValueFormats) {
  EXPECT_EQ(parse_frf_format("CSV", "--from"), FrfFormat::Csv);
  EXPECT_EQ(parse_frf_format("unv", "--from"), FrfFormat::Uff);
  EXPECT_EQ(parse_frf_format("58b", "--from"), FrfFormat::UffBinary);
  EXPECT_EQ(parse_frf_format("cutpro", "--from"), FrfFormat::Frf);
  EXPECT_EQ(parse_frf_ordinate(" Inertance", "--ordinate"), FrfOrdinate::Accelerance);
  for (FrfOrdinate o : {FrfOrdinate::Receptance, FrfOrdinate::Mobility, FrfOrdinate::Accelerance})
    EXPECT_EQ(parse_frf_ordinate(frf_ordinate_name(o), "--ordinate"), o);
  EXPECT_THROW(parse_frf_ordinate("velocity", "--ordinate"), InvalidArgument);
  EXPECT_EQ(parse_frf_value_format("ReIm", "--format"), FrfValueFormat::ReIm);
  EXPECT_EQ(parse_frf_value_format("db-phase-deg", "--format"), FrfValueFormat::DbPhaseDeg);
  // The library's names read back.
  for (FrfFormat f : {FrfFormat::Auto, FrfFormat::Csv, FrfFormat::Uff, FrfFormat::UffBinary, FrfFormat::Frf})
    EXPECT_EQ(parse_frf_format(frf_format_name(f), "--from"), f);
  for (FrfValueFormat f : {FrfValueFormat::ReIm, FrfValueFormat::MagPhaseDeg, FrfValueFormat::MagPhaseRad,
                           FrfValueFormat::DbPhaseDeg, FrfValueFormat::DbPhaseRad})
    EXPECT_EQ(parse_frf_value_format(frf_value_format_name(f), "--format"), f);
  try {
    parse_frf_value_format("polar", "--format");
    ADD_FAILURE() << "accepted 'polar'";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("--format 'polar'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_frf_format("xlsx", "--from"), InvalidArgument);
}

TEST(CliParse, Interpolations) {
  EXPECT_EQ(parse_interpolation("Linear", "--method"), Interpolation::Linear);
  EXPECT_EQ(parse_interpolation(" cubic", "--method"), Interpolation::Cubic);
  EXPECT_EQ(parse_interpolation("spline", "--method"), Interpolation::Cubic);
  EXPECT_THROW(parse_interpolation("akima", "--method"), InvalidArgument);
}
