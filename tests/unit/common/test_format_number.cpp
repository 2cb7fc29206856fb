// format_number (common/format_number.h): the numbers of every message, printf
// %g with a count of significant digits (10 by default).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/format_number.h"

namespace gdof {
namespace {

TEST(format_number, SignificantDigitsAsPrintfG) {
    EXPECT_EQ(format_number(0.5), "0.5");
    EXPECT_EQ(format_number(-2), "-2");
    EXPECT_EQ(format_number(1.0 / 3.0), "0.3333333333");
    EXPECT_EQ(format_number(1.0 / 3.0, 6), "0.333333");
    EXPECT_EQ(format_number(12.3456789, 6), "12.3457");
    EXPECT_EQ(format_number(2.0 / 3.0, 9), "0.666666667");
    EXPECT_EQ(format_number(1e30), "1e+30");
    EXPECT_EQ(format_number(123456789012.0), "1.23456789e+11");
}

TEST(format_number, NonFiniteValuesAreNamed) {
    EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity(), 6), "-inf");
    EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
}

}  // namespace
}  // namespace gdof
