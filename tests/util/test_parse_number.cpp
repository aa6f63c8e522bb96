// util/parse_number.h: the whole text is the number (std::stod / std::stoi syntax), or there is none.
#include <gtest/gtest.h>

#include <cmath>

#include "util/parse_number.h"

namespace aovar::util {
namespace {

TEST(ParseNumber, TheWholeTextIsTheNumber) {
  EXPECT_EQ(whole_double("1.5"), 1.5);
  EXPECT_EQ(whole_double("-2e3"), -2000.0);
  EXPECT_EQ(whole_double(" 0.25"), 0.25);  // leading blanks: std::stod's syntax, which the inputs always had
  EXPECT_TRUE(std::isinf(*whole_double("inf")));
  EXPECT_EQ(whole_int("12"), 12);
  EXPECT_EQ(whole_int("-3"), -3);
}

TEST(ParseNumber, NothingWhenAnythingIsLeftOverOrItIsOutOfRange) {
  for (const char* bad : {"", " ", "x", "1.5x", "1.5 ", "1,5", "--1"}) {
    EXPECT_FALSE(whole_double(bad)) << bad;
    EXPECT_FALSE(whole_int(bad)) << bad;
  }
  EXPECT_FALSE(whole_int("1.5"));
  EXPECT_FALSE(whole_int("99999999999"));
  EXPECT_FALSE(whole_double("1e999"));
}

}  // namespace
}  // namespace aovar::util
