// libFuzzer target: the OpenVDB reader (io/volume/VdbIO.h), structure-aware.
//
// Mutated .vdb bytes are NOT handed to OpenVDB: OpenVDB 10's own parser
// trusts the sizes in the file and, on some mutated files, corrupts the heap
// and aborts inside the library ("malloc(): invalid size"), which no caller
// can catch (see docs/robustness.md). This target therefore checks what
// skelseg itself adds around OpenVDB:
//   1. the pre-validation of raw bytes: inputs that do not start with the VDB
//      magic number go to readVdbMaskFromMemory() unchanged and must be
//      refused with an InputError (empty, short, wrong magic);
//   2. the conversion of grids to a mask: inputs that start with the magic
//      are a recipe for one or two grids (tests/fuzz/VdbRecipe.h), which
//      OpenVDB writes to memory, optionally truncated at a fuzzed length, and
//      the reader reads back.
// Seeds: tests/fuzz/corpus/vdb/.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstring>
#include <string>

#include "io/volume/VdbIO.h"
#include "tests/fuzz/FuzzCommon.h"
#include "tests/fuzz/VdbRecipe.h"

namespace {

constexpr std::uint8_t kMagic[8] = {0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    skelseg::fuzz::initialiseVdbRecipes();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace skelseg;
    if (size < sizeof kMagic || std::memcmp(data, kMagic, sizeof kMagic) != 0) {
        // 1. Pre-validation: never reaches OpenVDB, must be refused.
        try {
            readVdbMaskFromMemory(fuzz::inputName(), data, size);
        } catch (const InputError& error) {
            fuzz::checkMessage(error);
            return 0;
        }
        __builtin_trap();  // bytes without the magic number were accepted
    }

    // 2. A recipe for a file OpenVDB writes itself.
    FuzzedDataProvider in(data + sizeof kMagic, size - sizeof kMagic);
    std::string bytes;
    if (!fuzz::writeVdbRecipe(in, bytes)) return 0;  // OpenVDB refused to write this recipe
    const bool truncate = in.ConsumeIntegralInRange<int>(0, 3) == 0;
    if (truncate && !bytes.empty())
        bytes.resize(in.ConsumeIntegralInRange<std::size_t>(0, bytes.size() - 1));
    const std::string gridName =
        in.ConsumeBool() ? std::string() : in.ConsumeRandomLengthString(12);
    fuzz::expectOnlyInputErrors([&] {
        const MaskVolume mask = readVdbMaskFromMemory(
            fuzz::inputName(), reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
            gridName);
        if (mask.size() != mask.dims().voxelCount() || mask.size() == 0) __builtin_trap();
    });
    return 0;
}
