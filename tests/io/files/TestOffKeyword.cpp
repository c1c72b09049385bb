// Tests for io/files/OffKeyword.h: the one reading of Geomview's OFF keyword
// that the OFF reader and the foreign-content check share.
#include "io/files/OffKeyword.h"

#include <gtest/gtest.h>

#include <string>

#include "io/files/ForeignContent.h"

namespace skelseg {
namespace {

TEST(OffKeyword, EndsAfterOffWhenOnlyDigitsFollow) {
    EXPECT_EQ(offKeywordEnd("OFF"), 3u);
    EXPECT_EQ(offKeywordEnd("off"), 3u);
    EXPECT_EQ(offKeywordEnd("STCNOFF"), 7u);
    EXPECT_EQ(offKeywordEnd("OFF8"), 3u);  // the first count glued to it
    EXPECT_EQ(offKeywordEnd("OFFBINARY"), 0u);
    EXPECT_EQ(offKeywordEnd("OFFICE"), 0u);
    EXPECT_EQ(offKeywordEnd("OF"), 0u);
    EXPECT_EQ(offKeywordEnd(""), 0u);
}

TEST(OffKeyword, PrefixLettersAreGeomviewsAndCaseSensitive) {
    EXPECT_TRUE(isOffKeywordPrefix(""));
    EXPECT_TRUE(isOffKeywordPrefix("STCN4n"));
    EXPECT_FALSE(isOffKeywordPrefix("st"));
    EXPECT_FALSE(isOffKeywordPrefix("X"));
    EXPECT_TRUE(isOffKeyword("4nOFF"));
    EXPECT_TRUE(isOffKeyword("COFF12"));
    EXPECT_FALSE(isOffKeyword("XOFF"));
    EXPECT_FALSE(isOffKeyword("v"));
}

// A file the OFF reader takes is named as OFF when given as another format,
// and a word it refuses is not.
TEST(OffKeyword, ForeignContentNamesAFileAsOffByTheReadersKeyword) {
    const std::string tetrahedron = "4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n";
    EXPECT_NE(foreignContentProblem("off " + tetrahedron, "OBJ").find("OFF"), std::string::npos);
    EXPECT_NE(foreignContentProblem("NOFF8 " + tetrahedron, "OBJ").find("OFF"), std::string::npos);
    EXPECT_EQ(foreignContentProblem("XOFF " + tetrahedron, "OBJ").find("OFF"), std::string::npos);
}

}  // namespace
}  // namespace skelseg
