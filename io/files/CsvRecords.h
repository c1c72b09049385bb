// skelseg: the records of a comma-separated file (RFC 4180), for batch
// manifests written by spreadsheets and scripts (engine/batch/Manifest.cpp).
// Fields are separated by commas; a field in double quotes may hold commas,
// line breaks and doubled quotes (""); a record ends at a line break outside
// quotes, and a carriage return before it is dropped. Blanks around a
// quoted field are dropped too; blanks inside an unquoted field are kept
// (the caller trims). Forty lines do not warrant a dependency: Debian's CSV
// libraries (libcsv, rapidcsv) would add a package for what this reads.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace skelseg {

struct CsvRecord {
    int line = 0;  // the line where the record starts, from 1
    std::vector<std::string> fields;
};

/// Splits `text` into records. Throws InputError naming `name` and the line
/// of a quoted field that never closes.
std::vector<CsvRecord> readCsvRecords(const std::string& name, std::string_view text);

}  // namespace skelseg
