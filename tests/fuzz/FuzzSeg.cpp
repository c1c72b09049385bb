// libFuzzer target: the Princeton .seg reader (io/mesh/SegFile.h), plain and gzip.
// Seeds: tests/fuzz/corpus/seg/.
#include "io/mesh/SegFile.h"
#include "tests/fuzz/FuzzCommon.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace skelseg;
    fuzz::expectOnlyInputErrors([&] {
        const auto labels = readSegFromMemory(fuzz::inputName(), data, size);
        if (labels.empty()) __builtin_trap();
    });
    return 0;
}
