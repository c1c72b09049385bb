// bzip2 compression for tests that write NRRD files of encoding bzip2.
#pragma once

#include <bzlib.h>

#include <string>

namespace skelseg::test {

/// bzip2-compresses `bytes` (block size 9); empty if libbz2 fails.
inline std::string bzip2Bytes(const std::string& bytes) {
    // libbz2's documented bound: 1% larger plus 600 bytes.
    unsigned size = unsigned(bytes.size() + bytes.size() / 100 + 600);
    std::string out(size, '\0');
    if (BZ2_bzBuffToBuffCompress(out.data(), &size, const_cast<char*>(bytes.data()),
                                 unsigned(bytes.size()), 9, 0, 0) != BZ_OK)
        return {};
    out.resize(size);
    return out;
}

}  // namespace skelseg::test
