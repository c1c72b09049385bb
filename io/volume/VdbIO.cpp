#include "io/volume/VdbIO.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <istream>
#include <mutex>
#include <new>
#include <optional>
#include <sstream>
#include <streambuf>

#include <openvdb/io/Archive.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/LevelSetUtil.h>

#include "io/files/CompressedContent.h"
#include "io/files/ForeignContent.h"
#include "io/files/IsolatedCall.h"
#include "io/files/OutputDirectory.h"
#include "io/files/TextFile.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

void initializeOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

/// Exception text on one line (the CLI prints what() as a single line).
std::string oneLine(const char* text) {
    std::string line = text ? text : "";
    std::replace(line.begin(), line.end(), '\n', ' ');
    std::replace(line.begin(), line.end(), '\r', ' ');
    for (char& c : line)  // other control characters (from names in the file)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return line;
}

/// A read-only std::streambuf over a memory block, so that
/// openvdb::io::Stream reads the caller's bytes without a copy.
class MemoryStreamBuffer : public std::streambuf {
public:
    MemoryStreamBuffer(const std::uint8_t* bytes, std::size_t size) {
        char* begin = const_cast<char*>(reinterpret_cast<const char*>(bytes));
        setg(begin, begin, begin + size);
    }

protected:
    pos_type seekoff(off_type offset, std::ios_base::seekdir direction,
                     std::ios_base::openmode which) override {
        if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
        off_type base = 0;
        if (direction == std::ios_base::cur)
            base = gptr() - eback();
        else if (direction == std::ios_base::end)
            base = egptr() - eback();
        const off_type target = base + offset;
        if (target < 0 || target > egptr() - eback()) return pos_type(off_type(-1));
        setg(eback(), eback() + target, egptr());
        return pos_type(target);
    }
    pos_type seekpos(pos_type position, std::ios_base::openmode which) override {
        return seekoff(off_type(position), std::ios_base::beg, which);
    }
};

VolumeGeometry geometryAt(const openvdb::math::Transform& transform,
                          const openvdb::Coord& indexMin) {
    const openvdb::Vec3d base(indexMin.x(), indexMin.y(), indexMin.z());
    const openvdb::Vec3d origin = transform.indexToWorld(base);
    VolumeGeometry geometry;
    geometry.origin = {origin.x(), origin.y(), origin.z()};
    for (int axis = 0; axis < 3; ++axis) {
        openvdb::Vec3d step = base;
        step[axis] += 1.0;
        const openvdb::Vec3d direction = transform.indexToWorld(step) - origin;
        geometry.directions[axis] = {direction.x(), direction.y(), direction.z()};
    }
    return geometry;
}

/// The dense mask of the active voxels and tiles of `grid`, covering their
/// bounding box; `transform` places it in world space.
template <typename GridT>
MaskVolume denseFromActive(const std::string& name, const GridT& grid,
                           const openvdb::math::Transform& transform,
                           const VolumeReadGuards& guards) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty()) {
        MaskVolume empty(Dims{1, 1, 1});
        empty.geometry = geometryAt(transform, openvdb::Coord(0, 0, 0));
        return empty;
    }
    const openvdb::Coord min = box.min();
    const auto extent = [&](int axis) {
        return std::int64_t(box.max()[axis]) - std::int64_t(min[axis]) + 1;
    };
    const Dims dims = Dims::checked(extent(0), extent(1), extent(2), name);
    if (guards.checkGrid) guards.checkGrid(dims);
    MaskVolume mask(dims);
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        if (it.isVoxelValue()) {
            const openvdb::Coord c = it.getCoord() - min;
            mask(c.x(), c.y(), c.z()) = 1;
            continue;
        }
        openvdb::CoordBBox tile;
        it.getBoundingBox(tile);
        tile.intersect(box);
        for (int z = tile.min().z(); z <= tile.max().z(); ++z)
            for (int y = tile.min().y(); y <= tile.max().y(); ++y)
                for (int x = tile.min().x(); x <= tile.max().x(); ++x)
                    mask(x - min.x(), y - min.y(), z - min.z()) = 1;
    }
    mask.geometry = geometryAt(transform, min);
    return mask;
}

/// Float or double grid: a level set unless its class says fog volume.
template <typename GridT>
MaskVolume denseFromReal(const std::string& name, const GridT& grid,
                         const VolumeReadGuards& guards) {
    if (grid.getGridClass() == openvdb::GRID_FOG_VOLUME) {
        // Fog: active values above zero are the object.
        openvdb::BoolGrid object(false);
        auto accessor = object.getAccessor();
        for (auto it = grid.cbeginValueOn(); it; ++it) {
            if (!(*it > 0)) continue;
            if (it.isVoxelValue()) {
                accessor.setValueOn(it.getCoord(), true);
            } else {
                openvdb::CoordBBox tile;
                it.getBoundingBox(tile);
                object.fill(tile, true, true);
            }
        }
        return denseFromActive(name, object, grid.transform(), guards);
    }
    const openvdb::BoolGrid::Ptr interior = openvdb::tools::sdfInteriorMask(grid);
    return denseFromActive(name, *interior, grid.transform(), guards);
}

MaskVolume maskFromLinearGrid(const std::string& name, const openvdb::GridBase::Ptr& grid,
                              const VolumeReadGuards& guards) {
    if (auto boolGrid = openvdb::GridBase::grid<openvdb::BoolGrid>(grid))
        return denseFromActive(name, *boolGrid, boolGrid->transform(), guards);
    if (auto maskGrid = openvdb::GridBase::grid<openvdb::MaskGrid>(grid))
        return denseFromActive(name, *maskGrid, maskGrid->transform(), guards);
    if (auto floatGrid = openvdb::GridBase::grid<openvdb::FloatGrid>(grid))
        return denseFromReal(name, *floatGrid, guards);
    if (auto doubleGrid = openvdb::GridBase::grid<openvdb::DoubleGrid>(grid))
        return denseFromReal(name, *doubleGrid, guards);
    throw InputError(name, "unsupported grid type " + grid->valueType() + " (grid " +
                               quote(grid->getName()) + "; supported: bool, mask, float, double)");
}

MaskVolume maskFromGrid(const std::string& name, const openvdb::GridBase::Ptr& grid,
                        const VolumeReadGuards& guards) {
    if (!grid->transform().isLinear())
        throw InputError(name, "grid " + quote(grid->getName()) + " has a non-linear (" +
                                   grid->transform().mapType() +
                                   ") transform, which is not supported");
    MaskVolume mask = maskFromLinearGrid(name, grid, guards);
    // OpenVDB bounds the voxel size, not how far out the grid lies: the same
    // geometry rule as the NRRD and binvox headers.
    if (const std::string problem = mask.geometry.problemOver(mask.dims()); !problem.empty())
        throw InputError(name, "grid " + quote(grid->getName()) + ": " + problem);
    return mask;
}

openvdb::math::Transform::Ptr transformFor(const VolumeGeometry& geometry) {
    const auto& d = geometry.directions;
    const double size = d[0][0];
    const bool uniform = size > 0.0 && d[1][1] == size && d[2][2] == size && d[0][1] == 0.0 &&
                         d[0][2] == 0.0 && d[1][0] == 0.0 && d[1][2] == 0.0 && d[2][0] == 0.0 &&
                         d[2][1] == 0.0;
    openvdb::math::Transform::Ptr transform;
    if (uniform) {
        transform = openvdb::math::Transform::createLinearTransform(size);
        transform->postTranslate(
            openvdb::Vec3d(geometry.origin[0], geometry.origin[1], geometry.origin[2]));
        return transform;
    }
    // OpenVDB maps row vectors: world = (i, j, k, 1) * M, so row a is the
    // world step along axis a and row 3 the origin.
    openvdb::Mat4d matrix = openvdb::Mat4d::identity();
    for (int axis = 0; axis < 3; ++axis)
        for (int c = 0; c < 3; ++c) matrix[axis][c] = d[axis][c];
    for (int c = 0; c < 3; ++c) matrix[3][c] = geometry.origin[c];
    return openvdb::math::Transform::createLinearTransform(matrix);
}

/// OpenVDB's file layout (grid offsets, for reading one grid without the
/// others) written into any seekable stream. openvdb::io::File::write() writes
/// through a std::ofstream of its own and never checks it: on a full disk it
/// left an empty labels.vdb and the run exited 0.
class SeekableArchiveWriter : public openvdb::io::Archive {
public:
    void writeTo(std::ostream& stream, const openvdb::GridCPtrVec& grids) const {
        Archive::write(stream, grids, /*seekable=*/true);
    }
};

/// Replaces the random file ID OpenVDB's writer puts in the header (a UUID
/// as 36 characters, after the magic number, the three version numbers and
/// the grid-offsets flag) with one derived from the rest of the file, so that
/// the same labels give the same bytes (every other output is byte-identical
/// between runs and thread counts). Leaves the bytes alone when the header
/// is not laid out that way (another OpenVDB).
void makeFileIdDeterministic(std::string& bytes) {
    constexpr std::size_t kIdOffset = 8 + 4 + 4 + 4 + 1, kIdLength = 36;
    if (bytes.size() < kIdOffset + kIdLength) return;
    for (std::size_t i = 0; i < kIdLength; ++i) {
        const char c = bytes[kIdOffset + i];
        const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
        if (dash ? c != '-' : !std::isxdigit(static_cast<unsigned char>(c))) return;
    }
    // Two FNV-1a hashes of everything but the ID: 128 bits.
    std::uint64_t halves[2] = {0xcbf29ce484222325ull, 0x84222325cbf29ce4ull};
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (i >= kIdOffset && i < kIdOffset + kIdLength) continue;
        for (std::uint64_t& h : halves)
            h = (h ^ static_cast<unsigned char>(bytes[i])) * 0x100000001b3ull;
        halves[1] = (halves[1] << 1) | (halves[1] >> 63);
    }
    unsigned char id[16];
    for (int i = 0; i < 16; ++i) id[i] = static_cast<unsigned char>(halves[i / 8] >> (8 * (i % 8)));
    id[6] = static_cast<unsigned char>((id[6] & 0x0f) | 0x80);  // RFC 9562 version 8: custom
    id[8] = static_cast<unsigned char>((id[8] & 0x3f) | 0x80);  // RFC 4122 variant
    static const char* const kHex = "0123456789abcdef";
    std::string text;
    for (int i = 0; i < 16; ++i) {
        if (i == 4 || i == 6 || i == 8 || i == 10) text += '-';
        text += kHex[id[i] >> 4];
        text += kHex[id[i] & 15];
    }
    bytes.replace(kIdOffset, kIdLength, text);
}

void checkVdbMagic(const std::string& name, const std::uint8_t* bytes, std::size_t size) {
    if (size == 0) throw InputError(name, "file is empty");
    // Every VDB file starts with the 64-bit magic number 0x56444220 ("VDB ").
    const std::uint8_t magic[8] = {0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};
    if (size < 8 || std::memcmp(bytes, magic, 8) != 0) {
        const std::string_view content(reinterpret_cast<const char*>(bytes), size);
        refuseCompressedContent(name, content);
        refuseForeignContent(name, content, "OpenVDB");
        throw InputError(name, "not an OpenVDB file: wrong magic number");
    }
}

/// OpenVDB's registries of grid, metadata and map types are locked while a
/// file is parsed; a parse forked while another thread held one of those
/// locks would wait for ever. Every parse of ours holds this mutex, so none
/// runs in another thread at a fork.
std::mutex& parseMutex() {
    static std::mutex mutex;
    return mutex;
}

/// The grids of the VDB stream in `bytes`; errors as OpenVDB throws them.
openvdb::GridPtrVecPtr parseGrids(const std::uint8_t* bytes, std::size_t size) {
    MemoryStreamBuffer buffer(bytes, size);
    std::istream in(&buffer);
    // A short read then throws instead of leaving OpenVDB with garbage.
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    return stream.getGrids();
}

/// Rethrows the exception being handled as an InputError naming `name`
/// (ours pass through).
[[noreturn]] void rethrowAsInputError(const std::string& name) {
    try {
        throw;
    } catch (const Error&) {
        throw;
    } catch (const std::ios_base::failure&) {
        throw InputError(name, "truncated or corrupt OpenVDB file (read past the end of the data)");
    } catch (const openvdb::Exception& error) {
        throw InputError(name, "cannot read OpenVDB data: " + oneLine(error.what()));
    } catch (const std::bad_alloc&) {
        throw InputError(name, "corrupt OpenVDB file (implausible allocation while reading)");
    } catch (const std::exception& error) {
        throw InputError(name, "cannot read OpenVDB data: " + oneLine(error.what()));
    } catch (...) {
        throw InputError(name, "cannot read OpenVDB data");
    }
}

/// The grids of the file as OpenVDB writes them again after parsing it in a
/// child process: OpenVDB trusts the sizes stored in a file, and on some
/// damaged files corrupts the heap and aborts, or allocates far more than the
/// file could hold. This process then parses only bytes OpenVDB's writer
/// made. nullopt when the parse could not be isolated (the caller parses the
/// file itself, as it did before).
std::optional<std::string> reserializeInChildProcess(const std::string& name,
                                                     const std::uint8_t* bytes, std::size_t size,
                                                     const VolumeReadGuards& guards) {
    IsolatedCallOptions options;
    options.memoryLimit = guards.memoryLimit;
    options.interrupter = guards.interrupter;
    const IsolatedCallOutcome outcome = runIsolated(
        [&] {
            try {
                const openvdb::GridPtrVecPtr grids = parseGrids(bytes, size);
                std::ostringstream out;
                openvdb::io::Stream stream(out);
                // No parallel work in a forked child (the statistics use
                // oneTBB), and no compression to undo.
                stream.setGridStatsMetadataEnabled(false);
                stream.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);
                if (grids) stream.write(openvdb::GridCPtrVec(grids->begin(), grids->end()));
                // A string stream that cannot grow sets its badbit and keeps
                // what it has.
                if (!out) throw std::bad_alloc();
                return out.str();
            } catch (const std::bad_alloc&) {
                throw;  // the child's memory limit, told apart by runIsolated()
            } catch (...) {
                rethrowAsInputError(name);
            }
        },
        options);
    using Ending = IsolatedCallOutcome::Ending;
    switch (outcome.ending) {
        case Ending::Finished:
            return outcome.output;
        case Ending::NotIsolated:
            return std::nullopt;
        case Ending::Threw:
            throw InputError(
                name, outcome.message.empty() ? "cannot read OpenVDB data" : outcome.message);
        case Ending::OutOfMemory:
            if (guards.memoryLimit > 0 && outcome.reachedMemoryLimit)
                throw MemoryLimitError(name +
                                       ": reading its OpenVDB grids needs more than the "
                                       "limit of " +
                                       formatBytes(guards.memoryLimit) + " (--max-memory)");
            throw InputError(name, "corrupt OpenVDB file (implausible allocation while reading)");
        case Ending::Crashed:
            throw InputError(name, "corrupt OpenVDB file: OpenVDB's reader crashed on it (" +
                                       signalName(outcome.signal) + ")");
        case Ending::Interrupted:
            throwInterrupted(*guards.interrupter);
    }
    return std::nullopt;
}

MaskVolume readParsedMask(const std::string& name, const std::uint8_t* bytes, std::size_t size,
                          const std::string& gridName, const VolumeReadGuards& guards) {
    try {
        openvdb::GridPtrVecPtr grids;
        {
            const std::lock_guard<std::mutex> lock(parseMutex());
            grids = parseGrids(bytes, size);
        }
        if (!grids || grids->empty()) throw InputError(name, "the file holds no grids");
        openvdb::GridBase::Ptr chosen;
        if (gridName.empty()) {
            chosen = grids->front();
        } else {
            for (const auto& grid : *grids)
                if (grid && grid->getName() == gridName) {
                    chosen = grid;
                    break;
                }
            if (!chosen) {
                std::string available;
                for (const auto& grid : *grids)
                    if (grid) available += (available.empty() ? "" : ", ") + quote(grid->getName());
                throw InputError(
                    name, "no grid named " + quote(gridName) + "; grids in the file: " + available);
            }
        }
        if (!chosen) throw InputError(name, "the file holds no grids");
        return maskFromGrid(name, chosen, guards);
    } catch (...) {
        rethrowAsInputError(name);
    }
}

}  // namespace

MaskVolume readVdbMaskFromMemory(const std::string& name, const std::uint8_t* bytes,
                                 std::size_t size, const std::string& gridName,
                                 const VolumeReadGuards& guards) {
    initializeOpenVdb();
    checkVdbMagic(name, bytes, size);
    return readParsedMask(name, bytes, size, gridName, guards);
}

MaskVolume readVdbMask(const fs::path& file, const std::string& gridName,
                       const VolumeReadGuards& guards) {
    const std::string bytes = readFileBytes(file);
    const std::string name = file.string();
    const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
    initializeOpenVdb();
    checkVdbMagic(name, data, bytes.size());
    std::optional<std::string> rewritten;
    {
        const std::lock_guard<std::mutex> lock(parseMutex());
        rewritten = reserializeInChildProcess(name, data, bytes.size(), guards);
    }
    if (!rewritten) return readParsedMask(name, data, bytes.size(), gridName, guards);
    return readParsedMask(name, reinterpret_cast<const std::uint8_t*>(rewritten->data()),
                          rewritten->size(), gridName, guards);
}

bool vdbCanHoldVoxelVolume(const Dims& dims, const VolumeGeometry& geometry) {
    initializeOpenVdb();
    // OpenVDB itself decides, rather than a formula on the directions:
    // writing a grid copies its transform, and OpenVDB rebuilds the copy of a
    // scale-and-translate map through an affine map whose scale depends
    // slightly on the translation, so the copy can be refused where the
    // original was accepted. Build the copy too.
    openvdb::math::Transform::Ptr transform;
    try {
        transform = transformFor(geometry)->copy();
    } catch (const openvdb::ArithmeticError&) {
        return false;
    }
    for (int corner = 0; corner < 8; ++corner) {
        const openvdb::Vec3d index((corner & 1) ? dims.x - 1 : 0, (corner & 2) ? dims.y - 1 : 0,
                                   (corner & 4) ? dims.z - 1 : 0);
        const openvdb::Vec3d world = transform->indexToWorld(index);
        if (!std::isfinite(world.x()) || !std::isfinite(world.y()) || !std::isfinite(world.z()))
            return false;
    }
    return true;
}

void writeVdbLabels(const fs::path& file, const LabelVolume& labels) {
    initializeOpenVdb();
    if (!vdbCanHoldVoxelVolume(labels.dims(), labels.geometry))
        throw OutputError(file.string() +
                          ": OpenVDB cannot hold this grid (a voxel volume under 3e-15 world "
                          "units cubed, or world positions that are not finite)");
    std::ostringstream bytes(std::ios::binary);
    try {
        openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
        grid->setName("labels");
        grid->setTransform(transformFor(labels.geometry));
        const Dims& dims = labels.dims();
        const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0),
                                     openvdb::Coord(dims.x - 1, dims.y - 1, dims.z - 1));
        // LayoutXYZ: x fastest, our layout. Dense only reads through the pointer here.
        openvdb::tools::Dense<std::uint16_t, openvdb::tools::LayoutXYZ> dense(
            box, const_cast<std::uint16_t*>(labels.data()));
        openvdb::tools::copyFromDense(dense, *grid, std::int32_t(0));
        SeekableArchiveWriter().writeTo(bytes, openvdb::GridCPtrVec{grid});
    } catch (const std::exception& error) {
        throw OutputError(file.string() + ": cannot write OpenVDB file: " + oneLine(error.what()));
    }
    if (!bytes) throw OutputError(file.string() + ": cannot write OpenVDB file");
    std::string content = bytes.str();
    makeFileIdDeterministic(content);
    // Through the checked writer: the system's reason on failure, and no
    // partial file under any name.
    writeFileAtomically(file, content);
}

}  // namespace skelseg
