// Implementation of tests/fuzz/VdbRecipe.h (see there why it is a separate,
// uninstrumented translation unit).
#include "tests/fuzz/VdbRecipe.h"

#include <openvdb/io/Stream.h>
#include <openvdb/math/Maps.h>
#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <exception>
#include <sstream>

namespace skelseg::fuzz {

namespace {

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

void initialiseVdbRecipes() {
    openvdb::initialize();
    static tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
}

bool writeVdbRecipe(FuzzedDataProvider& in, std::string& bytes) {
    openvdb::GridPtrVec grids;
    try {
        const int count = in.ConsumeIntegralInRange<int>(0, 2);
        for (int i = 0; i < count; ++i) grids.push_back(makeAnyGrid(in));
        std::ostringstream out(std::ios::binary);
        openvdb::io::Stream(out).write(grids);
        bytes = out.str();
    } catch (const std::exception&) {
        return false;
    }
    return true;
}

}  // namespace skelseg::fuzz
