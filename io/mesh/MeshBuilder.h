// skelseg: the part every mesh reader shares (internal to io/mesh/).
//
// A reader parses its format and hands vertices and polygons to a
// MeshBuilder, which checks them (finite coordinates, indices in range, at
// least 3 corners, element counts that fit 32-bit indices), fan-triangulates
// the polygons and keeps the input face of every triangle (MeshIO.h says why).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "kernels/base/Error.h"

namespace skelseg {

/// Vertex and face indices are stored as uint32; keep one value free.
constexpr std::uint64_t kMaxElementCount = 0xFFFFFFFEull;
/// MeshBuilder::addFace: the vertex count is not known yet, check in finish().
constexpr std::uint64_t kCheckLater = ~std::uint64_t(0);

/// Collects vertices and polygons, validates them and fan-triangulates.
class MeshBuilder {
public:
    /// indexBase: how the format numbers vertices in messages (OBJ from 1).
    MeshBuilder(const std::string& name, int indexBase) : mName(name), mIndexBase(indexBase) {}

    [[noreturn]] void fail(const std::string& problem) const { throw InputError(mName, problem); }

    /// Reserves only for counts already checked against the bytes available.
    void reserve(std::uint64_t vertices, std::uint64_t faces) {
        mMesh.vertices.reserve(std::size_t(vertices));
        mMesh.triangles.reserve(std::size_t(faces));
        mMesh.triangleFace.reserve(std::size_t(faces));
    }

    void addVertex(double x, double y, double z) {
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            fail("vertex " + std::to_string(mMesh.vertices.size() + std::size_t(mIndexBase)) +
                 " has a non-finite coordinate");
        if (mMesh.vertices.size() >= kMaxElementCount) fail("too many vertices");
        mMesh.vertices.push_back({x, y, z});
    }

    std::size_t vertexCount() const noexcept { return mMesh.vertices.size(); }
    std::size_t faceCount() const noexcept { return mMesh.faceCount; }

    /// Adds one polygon of 0-based vertex indices. vertexLimit: the number of
    /// vertices the indices must stay below, or kCheckLater to check in
    /// finish() (formats whose faces may come before their vertices).
    void addFace(const std::vector<std::int64_t>& polygon, std::uint64_t vertexLimit) {
        const std::size_t face = mMesh.faceCount;
        if (polygon.size() < 3)
            fail("face " + std::to_string(face) + " has " + std::to_string(polygon.size()) +
                 " vertices; a face needs at least 3");
        if (face >= kMaxElementCount) fail("too many faces");
        for (std::int64_t index : polygon) {
            if (index < 0)
                fail("face " + std::to_string(face) + " references vertex " +
                     std::to_string(index + mIndexBase) + ", which does not exist");
            // Checked later: only an index no mesh can reach is refused here,
            // and the count the vertices will have is not known yet.
            if (vertexLimit == kCheckLater && std::uint64_t(index) >= kMaxElementCount)
                fail("face " + std::to_string(face) + " references vertex " +
                     std::to_string(std::uint64_t(index) + std::uint64_t(mIndexBase)) +
                     ", beyond the " + std::to_string(kMaxElementCount) +
                     " vertices a mesh may have");
            if (vertexLimit != kCheckLater && std::uint64_t(index) >= vertexLimit)
                failIndex(face, std::uint64_t(index), vertexLimit);
        }
        for (std::size_t corner = 1; corner + 1 < polygon.size(); ++corner) {
            mMesh.triangles.push_back({std::uint32_t(polygon[0]), std::uint32_t(polygon[corner]),
                                       std::uint32_t(polygon[corner + 1])});
            mMesh.triangleFace.push_back(std::uint32_t(face));
        }
        ++mMesh.faceCount;
    }

    TriangleMesh finish() {
        if (mMesh.faceCount == 0) fail("the mesh has no faces");
        const std::uint64_t vertexLimit = mMesh.vertices.size();
        for (std::size_t t = 0; t < mMesh.triangles.size(); ++t)
            for (std::uint32_t index : mMesh.triangles[t])
                if (index >= vertexLimit) failIndex(mMesh.triangleFace[t], index, vertexLimit);
        return std::move(mMesh);
    }

private:
    [[noreturn]] void failIndex(std::size_t face, std::uint64_t index,
                                std::uint64_t vertexLimit) const {
        fail("face " + std::to_string(face) + " references vertex " +
             std::to_string(index + std::uint64_t(mIndexBase)) + " but there are " +
             std::to_string(vertexLimit) + " vertices");
    }

    const std::string& mName;
    int mIndexBase;
    TriangleMesh mMesh;
};

}  // namespace skelseg
