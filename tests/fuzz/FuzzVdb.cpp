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
//      are a recipe for one or two grids (type, class, transform, name,
//      voxels, tiles, far-away coordinates), which OpenVDB writes to memory,
//      optionally truncated at a fuzzed length, and the reader reads back.
// Seeds: tests/fuzz/corpus/vdb/.
#include <fuzzer/FuzzedDataProvider.h>

#include <openvdb/io/Stream.h>
#include <openvdb/math/Maps.h>
#include <openvdb/openvdb.h>
#include <tbb/global_control.h>
#include <cstring>
#include <sstream>

#include "io/volume/VdbIO.h"
#include "tests/fuzz/FuzzCommon.h"

namespace {

constexpr std::uint8_t kMagic[8] = {0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};

openvdb::math::Transform::Ptr makeTransform(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 3)) {
        case 0:
            return openvdb::math::Transform::createLinearTransform(
                in.ConsumeFloatingPointInRange(1e-3, 10.0));
        case 1: {
            openvdb::Mat4d m = openvdb::Mat4d::identity();
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 3; ++c)
                    m[r][c] = double(in.ConsumeIntegralInRange<int>(-4, 4)) * 0.5;
            return openvdb::math::Transform::createLinearTransform(m);
        }
        case 2:
            return openvdb::math::Transform::createFrustumTransform(
                openvdb::BBoxd(openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(10, 10, 10)), 0.5, 2.0, 1.0);
        default:
            return openvdb::math::Transform::createLinearTransform(1.0);
    }
}

template <typename GridT>
typename GridT::Ptr makeGrid(FuzzedDataProvider& in, typename GridT::ValueType on,
                             typename GridT::ValueType off) {
    auto grid = GridT::create(off);
    const int farAway =
        in.ConsumeIntegralInRange<int>(0, 7);  // occasionally a far coordinate: bbox over the cap
    const int voxels = in.ConsumeIntegralInRange<int>(0, 64);
    auto accessor = grid->getAccessor();
    for (int i = 0; i < voxels && in.remaining_bytes() > 0; ++i) {
        const int range = farAway == 0 ? 1000000 : 40;
        const openvdb::Coord c(in.ConsumeIntegralInRange<int>(-range, range),
                               in.ConsumeIntegralInRange<int>(-range, range),
                               in.ConsumeIntegralInRange<int>(-range, range));
        if (in.ConsumeBool())
            accessor.setValueOn(c, on);
        else
            accessor.setValueOff(c, off);
    }
    const int tiles = in.ConsumeIntegralInRange<int>(0, 2);
    for (int i = 0; i < tiles; ++i) {
        // Level 1: 8^3 voxels; rarely level 2: 128^3 voxels (a 2M-voxel mask
        // is slow; coordinates stay near the origin to keep the box small).
        const unsigned level = in.ConsumeIntegralInRange<int>(0, 7) == 0 ? 2 : 1;
        const openvdb::Coord c(in.ConsumeIntegralInRange<int>(-40, 40),
                               in.ConsumeIntegralInRange<int>(-40, 40),
                               in.ConsumeIntegralInRange<int>(-40, 40));
        grid->tree().addTile(level, c, in.ConsumeBool() ? on : off, in.ConsumeBool());
    }
    return grid;
}

openvdb::GridBase::Ptr makeAnyGrid(FuzzedDataProvider& in) {
    openvdb::GridBase::Ptr grid;
    switch (in.ConsumeIntegralInRange<int>(0, 5)) {
        case 0:
            grid = makeGrid<openvdb::BoolGrid>(in, true, false);
            break;
        case 1:
            grid = makeGrid<openvdb::MaskGrid>(in, true, false);
            break;
        case 2:
            grid =
                makeGrid<openvdb::FloatGrid>(in, in.ConsumeFloatingPointInRange(-3.0f, 3.0f), 1.0f);
            break;
        case 3:
            grid =
                makeGrid<openvdb::DoubleGrid>(in, in.ConsumeFloatingPointInRange(-3.0, 3.0), -1.0);
            break;
        case 4:
            grid = makeGrid<openvdb::Int32Grid>(in, 1, 0);
            break;  // unsupported type
        default:
            grid = makeGrid<openvdb::Vec3SGrid>(in, openvdb::Vec3s(1, 0, 0), openvdb::Vec3s(0));
            break;
    }
    switch (in.ConsumeIntegralInRange<int>(0, 2)) {
        case 0:
            grid->setGridClass(openvdb::GRID_LEVEL_SET);
            break;
        case 1:
            grid->setGridClass(openvdb::GRID_FOG_VOLUME);
            break;
        default:
            break;
    }
    grid->setTransform(makeTransform(in));
    grid->setName(in.ConsumeRandomLengthString(12));
    return grid;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    openvdb::initialize();
    // One thread: OpenVDB's parallel loops on tiny grids cost more in thread
    // wake-ups than they save, and a serial run is reproducible.
    static tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
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
    openvdb::GridPtrVec grids;
    try {
        const int count = in.ConsumeIntegralInRange<int>(0, 2);
        for (int i = 0; i < count; ++i) grids.push_back(makeAnyGrid(in));
        std::ostringstream out(std::ios::binary);
        openvdb::io::Stream(out).write(grids);
        bytes = out.str();
    } catch (const std::exception&) {
        return 0;  // OpenVDB refused to write this recipe (e.g. a singular transform)
    }
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
