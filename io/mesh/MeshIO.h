// skelseg: reading and writing polygon meshes (OFF, OBJ, STL, PLY).
//
// The readers are written by hand (see docs/meshes.md): a segmentation is
// reported per INPUT face (the Princeton .seg convention: line i = face i of the
// file), so the reader must keep the file's face order and map every triangle
// back to the polygon it came from. Polygons are fan-triangulated:
// polygon (v0 v1 ... vn-1) becomes (v0 v1 v2), (v0 v2 v3), ..., all tagged with
// the polygon's index in triangleFace.
//
// Every reader works on a memory buffer (the file readers load the file and call
// it), so the same code is fuzzed. Malformed input throws InputError(file, problem)
// with a one-line problem; the readers never abort and refuse absurd counts
// before allocating for them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace skelseg {

/// A triangle mesh that remembers which input face each triangle came from.
struct TriangleMesh {
    /// #vertices positions, in the file's units.
    std::vector<std::array<double, 3>> vertices;
    /// #triangles vertex index triples (indices into `vertices`).
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// #triangles: index of the input face (polygon) each triangle belongs to,
    /// in [0, faceCount). Triangles of one face are consecutive.
    std::vector<std::uint32_t> triangleFace;
    /// Number of faces in the input file (= lines of its .seg file).
    std::size_t faceCount = 0;
};

enum class MeshFormat { Off, Obj, Stl, Ply };

/// Format from the file name's extension (.off .obj .stl .ply, any case).
/// Throws InputError(path, ...) for any other extension.
MeshFormat meshFormatFromPath(const std::filesystem::path& path);

/// Short lower-case name of a format ("off", "obj", "stl", "ply").
const char* meshFormatName(MeshFormat format) noexcept;

/// Reads a mesh file; the format comes from the extension.
/// Supported: OFF (also COFF, NOFF, STOFF... variants; extra per-vertex and
/// per-face values are ignored), OBJ (v and f statements, f with v, v/vt,
/// v//vn, v/vt/vn and negative indices; every other statement is ignored),
/// STL (ASCII and binary; a file is binary when its size is 84 + 50 n for the
/// triangle count n in its header, whatever its first bytes say; STL vertices
/// at identical positions are merged because STL repeats them per facet),
/// PLY (ascii, binary_little_endian, binary_big_endian; vertex x, y, z of any
/// numeric type; face list "vertex_indices" or "vertex_index"; other elements
/// and properties are skipped).
/// @throw InputError naming the file: unreadable, malformed, truncated, an
/// index out of range, a count larger than the file can hold, a non-finite
/// coordinate, a face with fewer than 3 vertices, or no face at all.
TriangleMesh readMesh(const std::filesystem::path& path);

/// Same as readMesh on `size` bytes at `data`; `name` is used in error
/// messages only.
TriangleMesh readMeshFromMemory(const std::string& name, MeshFormat format,
                                const std::uint8_t* data, std::size_t size);

/// Writes an ASCII OFF file (17 significant digits, so coordinates read back
/// exactly). Triangles of one input face that form a fan (as readMesh makes
/// them) are written back as that polygon, so writing and reading again keeps
/// faceCount and triangleFace; any other face is written as separate triangles.
/// Atomic: a temporary file renamed into place. @throw OutputError.
void writeOff(const std::filesystem::path& path, const TriangleMesh& mesh);

/// The edges b - a and c - a of triangle t (corners a, b, c) times
/// 2^-exponent, where exponent is the binary exponent of their largest
/// component (0 when that is not finite): products of the scaled edges
/// neither overflow nor underflow at any scale the readers accept, and the
/// scaling is exact. `zero`: every component is 0 (the edges are left so).
struct ScaledTriangleEdges {
    std::array<double, 3> u, v;
    int exponent;
    bool zero;
};
ScaledTriangleEdges scaledTriangleEdges(const TriangleMesh& mesh, std::size_t t);

/// Area of triangle t (half the length of its edges' cross product).
double triangleArea(const TriangleMesh& mesh, std::size_t t);

/// The box of the vertices faces use (vertices no face uses do not count):
/// low and high per axis; low above high when there are no faces.
struct VertexBox {
    std::array<double, 3> low, high;
};
VertexBox usedVertexBox(const TriangleMesh& mesh);

/// The surface's area projected on the three axis planes and summed
/// (|n_x| + |n_y| + |n_z| per unit of area), in units of the square of the
/// longest side of the box of its vertices: digitised at resolution r
/// (voxels along that side), the surface exposes about this times r^2 voxel
/// faces, a bound of its boundary voxels that memory estimates use. 0 for
/// an empty or pointlike mesh.
double axisProjectedArea(const TriangleMesh& mesh);

/// Area of every input face (sum of its triangles' areas): faceCount entries.
/// Used to weight faces when scoring segmentations.
std::vector<double> faceAreas(const TriangleMesh& mesh);

}  // namespace skelseg
