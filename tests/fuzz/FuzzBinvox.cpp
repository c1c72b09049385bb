// libFuzzer target: the binvox reader (io/volume/BinvoxIO.h). Seeds:
// tests/fuzz/corpus/binvox/.
#include "io/volume/BinvoxIO.h"
#include "tests/fuzz/FuzzCommon.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace skelseg;
    fuzz::expectOnlyInputErrors([&] {
        const MaskVolume mask = readBinvoxFromMemory(fuzz::inputName(), data, size);
        if (mask.size() != mask.dims().voxelCount()) __builtin_trap();
        for (std::uint8_t v : mask.values())
            if (v > 1) __builtin_trap();
    });
    return 0;
}
