// checkMesh, canonicalVertices and meshTopology count edges and positions in
// sorted lists; the oracles below are the hash-map versions they replaced, and
// must agree with them on every mesh, shared files included.
#include "io/mesh/MeshCheck.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "io/mesh/MeshGenus.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

struct PositionHash {
    std::size_t operator()(const std::array<double, 3>& p) const noexcept {
        std::uint64_t h = 1469598103934665603ull;
        for (double c : p) {
            std::uint64_t bits;
            std::memcpy(&bits, &c, 8);
            h = (h ^ bits) * 1099511628211ull + (h >> 29);
        }
        return std::size_t(h);
    }
};

std::vector<std::uint32_t> hashedCanonicalVertices(const TriangleMesh& mesh) {
    std::vector<std::uint32_t> canonical(mesh.vertices.size());
    std::unordered_map<std::array<double, 3>, std::uint32_t, PositionHash> first;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        std::array<double, 3> p = mesh.vertices[v];
        for (double& c : p)
            if (c == 0.0) c = 0.0;
        canonical[v] = first.emplace(p, std::uint32_t(v)).first->second;
    }
    return canonical;
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

/// Boundary edges, non-manifold edges, closed and pieces, with a hash map.
MeshDiagnostics hashedEdgeDiagnostics(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = hashedCanonicalVertices(mesh);
    MeshDiagnostics d;
    std::unordered_map<std::uint64_t, std::uint32_t> uses, directedUses;
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<char> used(mesh.vertices.size(), 0);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = canonical[t[std::size_t(k)]],
                          b = canonical[t[std::size_t(k + 1) % 3]];
            used[a] = 1;
            if (a == b) continue;
            const std::uint32_t ra = findRoot(parent, a), rb = findRoot(parent, b);
            if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
            ++directedUses[(std::uint64_t(a) << 32) | b];
            if (a > b) std::swap(a, b);
            ++uses[(std::uint64_t(a) << 32) | b];
        }
    bool even = true;
    for (const auto& [edge, n] : uses) {
        // Two uses the same way round: one a->b twice, or b->a twice.
        const std::uint64_t reversed = (edge << 32) | (edge >> 32);
        d.misorientedEdges +=
            n == 2 && (directedUses.count(edge) == 0 || directedUses.count(reversed) == 0);
        d.boundaryEdges += n == 1;
        d.nonManifoldEdges += n > 2;
        even = even && n % 2 == 0;
    }
    d.closed = even && !uses.empty();
    for (std::uint32_t v = 0; v < std::uint32_t(mesh.vertices.size()); ++v)
        d.pieces += used[v] && findRoot(parent, v) == v;
    return d;
}

/// Genus and pieces with hash maps (meshTopology as it was).
MeshTopology hashedTopology(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = hashedCanonicalVertices(mesh);
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        triangles.push_back(c);
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t a = findRoot(parent, c[0]), b = findRoot(parent, c[std::size_t(k)]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    struct Counts {
        std::int64_t v = 0, e = 0, f = 0;
        bool manifold = true;
    };
    std::unordered_map<std::uint32_t, Counts> pieces;
    std::vector<char> used(mesh.vertices.size(), 0);
    std::unordered_map<std::uint64_t, std::uint32_t> uses;
    for (const auto& t : triangles) {
        ++pieces[findRoot(parent, t[0])].f;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = t[std::size_t(k)], b = t[std::size_t(k + 1) % 3];
            if (!used[a]) {
                used[a] = 1;
                ++pieces[findRoot(parent, a)].v;
            }
            if (a > b) std::swap(a, b);
            ++uses[(std::uint64_t(a) << 32) | b];
        }
    }
    for (const auto& [edge, n] : uses) {
        Counts& piece = pieces[findRoot(parent, std::uint32_t(edge >> 32))];
        ++piece.e;
        if (n != 2) piece.manifold = false;
    }
    MeshTopology topology;
    for (const auto& [root, piece] : pieces) {
        (void)root;
        const std::int64_t chi = piece.v - piece.e + piece.f;
        if (!piece.manifold || chi % 2 != 0) {
            ++topology.otherPieces;
            continue;
        }
        ++topology.closedPieces;
        topology.eulerCharacteristic += chi;
        topology.genus += (2 - chi) / 2;
    }
    return topology;
}

void expectSameAsHashed(const TriangleMesh& mesh, const std::string& name) {
    EXPECT_EQ(canonicalVertices(mesh), hashedCanonicalVertices(mesh)) << name;
    const MeshDiagnostics sorted = checkMesh(mesh), hashed = hashedEdgeDiagnostics(mesh);
    EXPECT_EQ(sorted.boundaryEdges, hashed.boundaryEdges) << name;
    EXPECT_EQ(sorted.nonManifoldEdges, hashed.nonManifoldEdges) << name;
    EXPECT_EQ(sorted.misorientedEdges, hashed.misorientedEdges) << name;
    EXPECT_EQ(sorted.closed, hashed.closed) << name;
    EXPECT_EQ(sorted.pieces, hashed.pieces) << name;
    const MeshTopology topology = meshTopology(mesh), expected = hashedTopology(mesh);
    EXPECT_EQ(topology.closedPieces, expected.closedPieces) << name;
    EXPECT_EQ(topology.otherPieces, expected.otherPieces) << name;
    EXPECT_EQ(topology.genus, expected.genus) << name;
    EXPECT_EQ(topology.eulerCharacteristic, expected.eulerCharacteristic) << name;
}

TriangleMesh meshOf(std::vector<std::array<double, 3>> vertices,
                    std::vector<std::array<std::uint32_t, 3>> triangles) {
    TriangleMesh mesh;
    mesh.vertices = std::move(vertices);
    mesh.triangles = std::move(triangles);
    mesh.triangleFace.resize(mesh.triangles.size());
    std::iota(mesh.triangleFace.begin(), mesh.triangleFace.end(), 0u);
    mesh.faceCount = mesh.triangles.size();
    return mesh;
}

TEST(MeshCheck, DuplicatedAndSignedZeroVerticesAreOneVertex) {
    // A tetrahedron whose apex is written three times (once as -0) and one
    // base corner twice: closed once duplicates are merged.
    const TriangleMesh mesh =
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-0.0, 0, 1}, {0, -0.0, 1}, {1, 0, 0}},
               {{0, 2, 1}, {0, 1, 3}, {6, 2, 4}, {0, 5, 2}});
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    EXPECT_EQ(canonical, (std::vector<std::uint32_t>{0, 1, 2, 3, 3, 3, 1}));
    const MeshDiagnostics d = checkMesh(mesh);
    EXPECT_TRUE(d.closed);
    EXPECT_EQ(d.boundaryEdges, 0u);
    EXPECT_EQ(d.pieces, 1u);
    expectSameAsHashed(mesh, "tetrahedron");
}

TEST(MeshCheck, OpenNonManifoldAndSeveralPiecesAgreeWithTheHashedCount) {
    // Three triangles on one edge (non-manifold), a lone open triangle, and a
    // degenerate triangle whose corners coincide.
    const TriangleMesh mesh = meshOf({{0, 0, 0},
                                      {1, 0, 0},
                                      {0, 1, 0},
                                      {0, -1, 0},
                                      {0, 0, 1},
                                      {5, 5, 5},
                                      {6, 5, 5},
                                      {5, 6, 5},
                                      {9, 9, 9}},
                                     {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}, {5, 6, 7}, {8, 8, 8}});
    const MeshDiagnostics d = checkMesh(mesh);
    EXPECT_FALSE(d.closed);
    EXPECT_EQ(d.nonManifoldEdges, 1u);
    EXPECT_EQ(d.boundaryEdges, 9u);
    EXPECT_EQ(d.pieces, 3u);
    EXPECT_EQ(d.degenerateFaces, 1u);
    expectSameAsHashed(mesh, "open");
}

/// The unit cube as 12 triangles, outward orientation.
TriangleMesh unitCube() {
    return meshOf(
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
        {{0, 2, 1},
         {0, 3, 2},
         {4, 5, 6},
         {4, 6, 7},
         {0, 1, 5},
         {0, 5, 4},
         {1, 2, 6},
         {1, 6, 5},
         {2, 3, 7},
         {2, 7, 6},
         {3, 0, 4},
         {3, 4, 7}});
}

TEST(MeshCheck, VertexNoFaceUsesDoesNotScaleTheZeroAreaCheck) {
    // The unit cube plus a vertex no face uses: from 1e7 away on, the area
    // tolerance (which grew with the box of every vertex) called all 12
    // faces of area 0.5 zero, and the CLI refused the cube.
    for (const double far : {1e6, 1e7, 1e11, 1e20, -1e300}) {
        TriangleMesh mesh = unitCube();
        mesh.vertices.push_back({far, 0, 0});
        const MeshDiagnostics d = checkMesh(mesh);
        EXPECT_EQ(d.degenerateFaces, 0u) << far;
        EXPECT_TRUE(d.closed) << far;
        EXPECT_EQ(d.pieces, 1u) << far;
    }
    // Faces that have no area still count, next to a vertex no face uses.
    TriangleMesh flat = meshOf({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1e7, 0}}, {{0, 1, 2}});
    EXPECT_EQ(checkMesh(flat).degenerateFaces, 1u);
}

/// `mesh` turned about the axis (1, 2, 3) / |(1, 2, 3)| by 0.7 rad and moved
/// by `offset`: a plane that no axis or diagonal of the grid lies in.
TriangleMesh turnedAndMoved(TriangleMesh mesh, double offset) {
    const double a = 0.7, n = std::sqrt(14.0), k[3] = {1 / n, 2 / n, 3 / n};
    for (auto& v : mesh.vertices) {
        const double dot = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
        const double cross[3] = {k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2],
                                 k[0] * v[1] - k[1] * v[0]};
        std::array<double, 3> turned{};
        for (int i = 0; i < 3; ++i)
            turned[std::size_t(i)] = v[std::size_t(i)] * std::cos(a) + cross[i] * std::sin(a) +
                                     k[i] * dot * (1 - std::cos(a)) + offset;
        v = turned;
    }
    return mesh;
}

// Areas and the flatness normal were products of fourth powers of the
// coordinates' scale: a sphere at 1e80 was refused as "flat" and one at
// 1e-90 as "all faces have zero area", inside the boxes the readers accept.
TEST(MeshCheck, ScalesFarFromOneKeepTheirAreasAndVolume) {
    const TriangleMesh unit = unitCube();
    const MeshDiagnostics reference = checkMesh(unit);
    ASSERT_FALSE(reference.flat);
    for (const double scale : {1e80, 1e99, 1e-90, 1e-99}) {
        SCOPED_TRACE(scale);
        TriangleMesh scaled = unit;
        for (auto& v : scaled.vertices)
            for (double& c : v) c *= scale;
        const MeshDiagnostics d = checkMesh(scaled);
        EXPECT_FALSE(d.flat);
        EXPECT_EQ(d.degenerateFaces, 0u);
        EXPECT_TRUE(d.closed);
        for (std::size_t t = 0; t < unit.triangles.size(); ++t)
            EXPECT_DOUBLE_EQ(triangleArea(scaled, t) / (scale * scale), triangleArea(unit, t));
    }
    // At ordinary scales the area is the unscaled formula's, bit for bit
    // (the scaling is by a power of two).
    TriangleMesh odd = meshOf({{0.1, 0.2, 0.3}, {1.7, -0.4, 2.9}, {-3.3, 0.25, 1.0}}, {{0, 1, 2}});
    const auto& a = odd.vertices[0];
    const auto& b = odd.vertices[1];
    const auto& c = odd.vertices[2];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
    EXPECT_EQ(triangleArea(odd, 0), 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
}

// Area and flatness both read the edges through scaledTriangleEdges: scaled
// back, they are the raw edges exactly, and their largest component lies in
// [1, 2) at any scale.
TEST(MeshCheck, ScaledTriangleEdgesAreTheEdgesTimesAPowerOfTwo) {
    for (const double scale : {1.0, 3.7e80, 1e-95, 0.3}) {
        SCOPED_TRACE(scale);
        const TriangleMesh mesh = meshOf({{0.1 * scale, 0.2 * scale, 0.3 * scale},
                                          {1.7 * scale, -0.4 * scale, 2.9 * scale},
                                          {-3.3 * scale, 0.25 * scale, 1.0 * scale}},
                                         {{0, 1, 2}});
        const ScaledTriangleEdges edges = scaledTriangleEdges(mesh, 0);
        ASSERT_FALSE(edges.zero);
        const auto& a = mesh.vertices[0];
        double largest = 0.0;
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(std::ldexp(edges.u[k], edges.exponent), mesh.vertices[1][k] - a[k]);
            EXPECT_EQ(std::ldexp(edges.v[k], edges.exponent), mesh.vertices[2][k] - a[k]);
            largest = std::max({largest, std::abs(edges.u[k]), std::abs(edges.v[k])});
        }
        EXPECT_GE(largest, 1.0);
        EXPECT_LT(largest, 2.0);
    }
    const TriangleMesh point =
        meshOf({{1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}}, {{0, 1, 2}});
    const ScaledTriangleEdges edges = scaledTriangleEdges(point, 0);
    EXPECT_TRUE(edges.zero);
    EXPECT_EQ(edges.exponent, 0);
    EXPECT_EQ(triangleArea(point, 0), 0.0);
}

TEST(MeshCheck, DegenerateTrianglesAreTheZeroAreaOnes) {
    TriangleMesh mesh = unitCube();
    const std::size_t cubeTriangles = mesh.triangles.size();
    // A face with a repeated corner across the cube, and a sliver of three
    // collinear corners.
    mesh.vertices.push_back({0.5, 0.5, 0.5});
    mesh.triangles.push_back({0, 0, 6});
    mesh.triangles.push_back({0, std::uint32_t(mesh.vertices.size() - 1), 6});
    for (int k = 0; k < 2; ++k) mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    const std::vector<char> degenerate = degenerateTriangles(mesh);
    ASSERT_EQ(degenerate.size(), cubeTriangles + 2);
    EXPECT_EQ(std::count(degenerate.begin(), degenerate.end(), 1), 2);
    EXPECT_EQ(degenerate[cubeTriangles], 1);
    EXPECT_EQ(degenerate[cubeTriangles + 1], 1);
    EXPECT_EQ(checkMesh(mesh).degenerateFaces, 2u);
}

// Digitised at resolution r, a surface exposes about its axis-projected
// area times r^2 voxel faces: the unit cube 6 r^2, the memory estimate's
// bound of the boundary voxels of a thin plate (a sixth of the object
// voxels, the rule without it, was a ninth of the plate's).
TEST(MeshCheck, AxisProjectedAreaCountsEveryFaceOnItsAxes) {
    const TriangleMesh cube = unitCube();
    EXPECT_DOUBLE_EQ(axisProjectedArea(cube), 6.0);
    TriangleMesh scaled = cube;
    for (auto& v : scaled.vertices)
        for (double& c : v) c *= 1e90;
    EXPECT_DOUBLE_EQ(axisProjectedArea(scaled), 6.0);
    // A plate 1 x 1 x 1e-6: both sides, 2 in units of its longest side.
    TriangleMesh plate = cube;
    for (auto& v : plate.vertices) v[2] *= 1e-6;
    EXPECT_NEAR(axisProjectedArea(plate), 2.0, 1e-5);
    // Turned off the axes, a face projects on all three planes: more than
    // its area (6 in all), at most sqrt(3) times it.
    const TriangleMesh turned = turnedAndMoved(cube, 0.0);
    double longest = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
        double low = HUGE_VAL, high = -HUGE_VAL;
        for (const auto& v : turned.vertices)
            low = std::min(low, v[c]), high = std::max(high, v[c]);
        longest = std::max(longest, high - low);
    }
    const double absolute = axisProjectedArea(turned) * longest * longest;
    EXPECT_GT(absolute, 6.0 * 1.01);
    EXPECT_LE(absolute, 6.0 * std::sqrt(3.0) + 1e-9);
    EXPECT_EQ(axisProjectedArea(meshOf({{0, 0, 0}}, {{0, 0, 0}})), 0.0);
}

TEST(MeshCheck, AMeshInOnePlaneIsFlatAThinSolidIsNot) {
    // An open square sheet, and the sheet closed as two sides (the same
    // triangles with the other winding: every edge used twice).
    const TriangleMesh sheet = meshOf({{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}, {2, 1, 0}},
                                      {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
    TriangleMesh twoSided = sheet;
    for (const auto& t : sheet.triangles) twoSided.triangles.push_back({t[0], t[2], t[1]});
    twoSided.triangleFace.resize(twoSided.triangles.size());
    std::iota(twoSided.triangleFace.begin(), twoSided.triangleFace.end(), 0u);
    twoSided.faceCount = twoSided.triangles.size();
    for (const double offset : {0.0, 1e3, -1e6}) {
        SCOPED_TRACE("offset " + std::to_string(offset));
        const MeshDiagnostics open = checkMesh(turnedAndMoved(sheet, offset));
        EXPECT_TRUE(open.flat);
        EXPECT_FALSE(open.closed);
        EXPECT_EQ(open.degenerateFaces, 0u);
        const MeshDiagnostics closed = checkMesh(turnedAndMoved(twoSided, offset));
        EXPECT_TRUE(closed.flat);
        EXPECT_TRUE(closed.closed) << "closed, and still no volume";
        // A closed box of the sheet's size, 1e-6 of it thick: a solid.
        TriangleMesh plate = unitCube();
        for (auto& v : plate.vertices) v = {4 * v[0], 3 * v[1], 5e-6 * v[2]};
        EXPECT_FALSE(checkMesh(turnedAndMoved(plate, offset)).flat);
        // The sheet with one vertex lifted by 1e-6 of its size.
        TriangleMesh bent = sheet;
        bent.vertices[4][2] = 5e-6;
        EXPECT_FALSE(checkMesh(turnedAndMoved(bent, offset)).flat);
    }
    EXPECT_FALSE(checkMesh(unitCube()).flat);
    // A vertex no face uses takes no part in the shape.
    TriangleMesh withStray = sheet;
    withStray.vertices.push_back({0, 0, 9});
    EXPECT_TRUE(checkMesh(withStray).flat);
    // No face with area: not flat but degenerate (refused as such).
    const MeshDiagnostics line = checkMesh(meshOf({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}));
    EXPECT_FALSE(line.flat);
    EXPECT_EQ(line.degenerateFaces, 1u);
}

TEST(MeshCheck, VerticesNoFaceUsesAreCountedAndNamedInAWarning) {
    EXPECT_EQ(checkMesh(unitCube()).unusedVertices, 0u);
    EXPECT_TRUE(meshWarnings(checkMesh(unitCube()), "cube.off").empty());
    TriangleMesh mesh = unitCube();
    mesh.vertices.push_back({1e7, 0, 0});
    mesh.vertices.push_back(mesh.vertices[0]);  // at a used vertex's place, itself unused
    const MeshDiagnostics d = checkMesh(mesh);
    EXPECT_EQ(d.unusedVertices, 2u);
    EXPECT_EQ(
        meshWarnings(d, "stray.off"),
        std::vector<std::string>{"stray.off: 2 vertices are used by no face; they are ignored"});
    mesh.vertices.pop_back();
    EXPECT_EQ(meshWarnings(checkMesh(mesh), "stray.off"),
              std::vector<std::string>{"stray.off: 1 vertex is used by no face; it is ignored"});
}

// "1 edges are shared" read wrong on the meshes with one such edge.
TEST(MeshCheck, OneProblemIsNamedInTheSingular) {
    TriangleMesh fin = unitCube();  // a fin of two triangles on one edge of the cube
    const auto corner = fin.triangles[0];
    fin.vertices.push_back({-1, -1, -1});
    fin.triangles.push_back({corner[0], corner[1], std::uint32_t(fin.vertices.size() - 1)});
    fin.triangles.push_back({corner[1], corner[0], std::uint32_t(fin.vertices.size() - 1)});
    fin.triangleFace.push_back(std::uint32_t(fin.faceCount++));
    fin.triangleFace.push_back(std::uint32_t(fin.faceCount++));
    TriangleMesh degenerate = unitCube();
    degenerate.triangles.push_back({0, 0, 1});
    degenerate.triangleFace.push_back(std::uint32_t(degenerate.faceCount++));
    const MeshDiagnostics finCheck = checkMesh(fin), degenerateCheck = checkMesh(degenerate);
    ASSERT_EQ(finCheck.nonManifoldEdges, 1u);
    ASSERT_EQ(degenerateCheck.degenerateFaces, 1u);
    const auto has = [](const std::vector<std::string>& warnings, const std::string& text) {
        for (const std::string& w : warnings)
            if (w.find(text) != std::string::npos) return true;
        return false;
    };
    EXPECT_TRUE(has(meshWarnings(finCheck, "fin.off"),
                    "fin.off: 1 edge is shared by more than two faces (non-manifold)"));
    EXPECT_TRUE(has(meshWarnings(degenerateCheck, "flat.off"),
                    "flat.off: 1 face has zero area; it takes the label of the voxels or faces "
                    "around it"));
}

// One flipped face changed a shape's parts without a word (docs/meshes.md:
// pieces not consistently oriented lose the rules that need their outside).
TEST(MeshCheck, FlippedFacesAreCountedByTheirEdgesAndNamedInAWarning) {
    TriangleMesh mesh = unitCube();
    EXPECT_EQ(checkMesh(mesh).misorientedEdges, 0u);
    std::swap(mesh.triangles[0][1], mesh.triangles[0][2]);
    const MeshDiagnostics d = checkMesh(mesh);
    EXPECT_TRUE(d.closed);
    EXPECT_EQ(d.misorientedEdges, 3u);  // the flipped triangle's three edges
    EXPECT_EQ(meshWarnings(d, "flip.off"),
              std::vector<std::string>{
                  "flip.off: 3 edges join faces wound against each other (some faces are "
                  "flipped); where surfaces touch there, they may stay joined in the voxel "
                  "model"});
    expectSameAsHashed(mesh, "one flipped");
    // The whole cube flipped is consistent again.
    for (auto& triangle : mesh.triangles) std::swap(triangle[1], triangle[2]);
    std::swap(mesh.triangles[0][1], mesh.triangles[0][2]);
    EXPECT_EQ(checkMesh(mesh).misorientedEdges, 0u);
    expectSameAsHashed(mesh, "all flipped");
}

TEST(MeshCheck, EverySharedMeshAgreesWithTheHashedCount) {
    if (!test::hasSharedData()) GTEST_SKIP() << "no shared data at " << test::sharedDataDir();
    std::size_t meshes = 0;
    for (const char* folder : {"shapes", "psb/off"}) {
        const auto dir = test::sharedDataDir() / folder;
        if (!std::filesystem::is_directory(dir)) continue;
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            const std::string ext = entry.path().extension().string();
            if (ext != ".off" && ext != ".obj") continue;
            expectSameAsHashed(readMesh(entry.path()), entry.path().filename().string());
            ++meshes;
        }
    }
    if (meshes == 0) GTEST_SKIP() << "no shared meshes";
}

}  // namespace
}  // namespace skelseg
