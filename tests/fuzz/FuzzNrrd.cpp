// libFuzzer target: the NRRD reader (io/volume/NrrdIO.h), both as a mask and as
// labels. Seeds: tests/fuzz/corpus/nrrd/.
#include "io/volume/NrrdIO.h"
#include "tests/fuzz/FuzzCommon.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace skelseg;
    fuzz::expectOnlyInputErrors([&] {
        const MaskVolume mask = readNrrdMaskFromMemory(fuzz::inputName(), data, size);
        if (mask.size() != mask.dims().voxelCount()) __builtin_trap();
        for (std::uint8_t v : mask.values())
            if (v > 1) __builtin_trap();
    });
    fuzz::expectOnlyInputErrors([&] {
        const LabelVolume labels = readNrrdLabelsFromMemory(fuzz::inputName(), data, size);
        if (labels.size() != labels.dims().voxelCount()) __builtin_trap();
    });
    return 0;
}
