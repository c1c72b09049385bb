// Tests for engine/NumberText.h: the decimal forms every numeric option takes.
#include "engine/NumberText.h"

#include <gtest/gtest.h>

namespace skelseg {
namespace {

TEST(NumberText, DecimalNumbersWithSignPointAndExponent) {
    for (const char* text : {"0", "48", "+48", "-3", "0.5", ".5", "5.", "1e3", "1E-3", "2.5e+2",
                             "inf", "-Infinity", "NaN"})
        EXPECT_TRUE(isDecimalNumberText(text)) << text;
    for (const char* text : {"", "+", ".", "e3", "1e", "1e+", "0x10", "0x1p4", "1.2.3", "1,5",
                             "12a", " 12", "12 ", "--1", "infinite", "0b1"})
        EXPECT_FALSE(isDecimalNumberText(text)) << text;
}

TEST(NumberText, IntegersLoseTheirLeadingZerosAndPlus) {
    EXPECT_EQ(decimalIntegerText("48"), "48");
    EXPECT_EQ(decimalIntegerText("048"), "48");
    EXPECT_EQ(decimalIntegerText("+0100"), "100");
    EXPECT_EQ(decimalIntegerText("-007"), "-7");
    EXPECT_EQ(decimalIntegerText("000"), "0");
    EXPECT_EQ(decimalIntegerText("-0"), "0");
    EXPECT_EQ(decimalIntegerText("99999999999999999999"), "99999999999999999999");
    for (const char* text : {"", "+", "-", "0x30", "0o60", "0b11", "1e2", "48.0", "4 8", "48 "})
        EXPECT_FALSE(decimalIntegerText(text).has_value()) << text;
}

}  // namespace
}  // namespace skelseg
