// Tests for io/files/CsvRecords.h: RFC 4180 records for CSV batch manifests.
#include "io/files/CsvRecords.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "kernels/base/Error.h"
#include "tests/support/ThrownMessage.h"

namespace skelseg {
namespace {

using Fields = std::vector<std::string>;

TEST(CsvRecords, SplitsFieldsAndRecordsWithTheLineEachStartsOn) {
    const auto records = readCsvRecords("m.csv", "path,label\r\na.off,3\n\nb c.off, 4\n");
    ASSERT_EQ(records.size(), 4u);
    EXPECT_EQ(records[0].fields, (Fields{"path", "label"}));
    EXPECT_EQ(records[1].fields, (Fields{"a.off", "3"}));
    EXPECT_EQ(records[1].line, 2);
    EXPECT_EQ(records[2].fields, (Fields{""})) << "a blank line is one empty field";
    EXPECT_EQ(records[3].fields, (Fields{"b c.off", " 4"})) << "unquoted blanks are kept";
    EXPECT_EQ(records[3].line, 4);
}

TEST(CsvRecords, QuotedFieldsHoldCommasQuotesAndLineBreaks) {
    const auto records =
        readCsvRecords("m.csv", "\"a,b.off\",\"say \"\"x\"\"\"\n  \"two\nlines.off\"  ,x\nlast");
    ASSERT_EQ(records.size(), 3u);
    EXPECT_EQ(records[0].fields, (Fields{"a,b.off", "say \"x\""}));
    EXPECT_EQ(records[1].fields, (Fields{"two\nlines.off", "x"}));
    EXPECT_EQ(records[1].line, 2);
    EXPECT_EQ(records[2].fields, (Fields{"last"})) << "no line break at the end";
    EXPECT_EQ(records[2].line, 4) << "the quoted line break counts";
}

TEST(CsvRecords, AQuoteThatNeverClosesNamesTheFileAndTheLine) {
    const std::string message = test::thrownMessage<InputError>(
        [] { readCsvRecords("m.csv", "path\nok.off\n\"open.off\n"); });
    EXPECT_EQ(message, "m.csv: line 3: a quoted field never closes (a '\"' is missing)");
    EXPECT_THROW(readCsvRecords("m.csv", "\""), InputError);
}

}  // namespace
}  // namespace skelseg
