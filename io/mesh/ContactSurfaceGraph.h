// skelseg: a triangle mesh as a graph over its canonical vertices, in the
// voxel index space of the grid it is voxelised on: what contact separation
// (ContactSeparation.h) and its patch seams (ContactPatchSeams.h) walk along
// the mesh with. Vertices at one position are one (canonicalVertices), every
// triangle knows its piece (connected along edges) and which way its normal
// points (triangleOrientation).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "io/mesh/Vec3Arithmetic.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// The mesh as a graph over canonical vertices, in voxel index space.
struct SurfaceGraph {
    std::vector<vec3::Vec3> points;  // per vertex
    std::vector<std::array<std::uint32_t, 3>>
        triangles;                     // canonical corners, smallest position first
    std::vector<std::uint32_t> piece;  // per triangle
    /// Per triangle: +1 when its normal (right hand rule) points out of the
    /// solid, -1 when in, 0 when its piece is not consistently oriented.
    std::vector<std::int8_t> orientation;
    std::vector<std::uint32_t> firstNeighbour, neighbours;  // CSR
    /// CSR: the triangles at each vertex, in ascending order (nearestOfTied
    /// relies on it).
    std::vector<std::uint32_t> firstTriangle, vertexTriangles;

    bool adjacent(std::uint32_t u, std::uint32_t v) const {
        return std::binary_search(neighbours.begin() + firstNeighbour[u],
                                  neighbours.begin() + firstNeighbour[u + 1], v);
    }

    /// The triangle that stands for the surface point nearest to p, given
    /// `t`, one triangle at the smallest distance from p. Where that point is
    /// a vertex or an edge, every triangle around it is as near, and which
    /// one a search returns depends on the order of the faces in the file;
    /// their normals differ, so the choice decides which side of the surface
    /// p is found on. Chosen from the geometry alone: the triangle whose
    /// plane p lies most squarely above (largest |cos| between its normal and
    /// p minus the point), then the smallest corners (sorted positions,
    /// lexicographic), so a mesh gives the same answer whatever its face
    /// order. Returns t where the nearest point is inside t or p lies on it.
    std::int32_t nearestOfTied(std::int32_t t, const vec3::Vec3& p) const;

    /// True when pa (on triangle ta) and pb (on tb) are joined by a path
    /// along mesh edges no longer than `limit`.
    bool nearOnMesh(std::int32_t ta, const vec3::Vec3& pa, std::int32_t tb, const vec3::Vec3& pb,
                    double limit) const;
};

/// The graph of `mesh` with its points in the index space of `geometry`.
SurfaceGraph buildSurfaceGraph(const TriangleMesh& mesh, const VolumeGeometry& geometry);

}  // namespace skelseg
