#include "cli/arguments.h"

#include <gtest/gtest.h>

namespace softwrist::cli {
namespace {

TEST(ParseAngleRange, InclusiveRangeOfThePapersAngles) {
  const auto angles = parse_angle_range_deg("-67.5:90:22.5", "--angles");
  ASSERT_EQ(angles.size(), 8u);
  EXPECT_DOUBLE_EQ(angles.front(), -67.5);
  EXPECT_DOUBLE_EQ(angles.back(), 90.0);
  EXPECT_EQ(parse_angle_range_deg("0:1:0.1", "--angles").size(), 11u);
  EXPECT_EQ(parse_angle_range_deg("5:5:1", "--angles").size(), 1u);
}

TEST(ParseAngleRange, RejectsMalformedRangesNamingTheOption) {
  for (const char* bad :
       {"", "1:2", "1:2:3:4", "a:2:1", "0:10:0", "0:10:-1", "10:0:1", "-200:0:1", "0:1:nan", "0:180:1e-9", "0:1:1x"}) {
    try {
      parse_angle_range_deg(bad, "--angles");
      FAIL() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("--angles"), std::string::npos) << e.what();
    }
  }
}

TEST(ParseNumbers, ExactCountOfFiniteNumbers) {
  EXPECT_EQ(parse_numbers("22, 3.5,9 ,1.5", 4, "--placement"), (std::vector<double>{22, 3.5, 9, 1.5}));
  EXPECT_THROW(parse_numbers("1,2,3", 4, "--placement"), UsageError);
  EXPECT_THROW(parse_numbers("1,2,3,4,5", 4, "--placement"), UsageError);
  EXPECT_THROW(parse_numbers("1,,3,4", 4, "--placement"), UsageError);
  EXPECT_THROW(parse_numbers("1,2,3,inf", 4, "--placement"), UsageError);
  EXPECT_THROW(parse_number("nan", "--x"), UsageError);
}

}  // namespace
}  // namespace softwrist::cli
