// The mesh fuzz targets (FuzzOff, FuzzObj, FuzzStl, FuzzPly) share this body:
// read, then check the invariants io/mesh/MeshIO.h promises for every mesh it
// returns, and those of the mesh's checks and genus (io/mesh/MeshCheck.h,
// io/mesh/MeshGenus.h, io/mesh/FlippedFaces.h, io/mesh/MeshFins.h,
// io/mesh/MeshHoles.h, io/mesh/MeshFinsAndHoles.h) on whatever geometry the
// bytes make.
#pragma once

#include <algorithm>
#include <cmath>

#include "io/mesh/FlippedFaces.h"
#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshFins.h"
#include "io/mesh/MeshFinsAndHoles.h"
#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshHoles.h"
#include "io/mesh/MeshIO.h"
#include "tests/fuzz/FuzzCommon.h"

namespace skelseg::fuzz {

inline void readMeshChecked(MeshFormat format, const std::uint8_t* data, std::size_t size) {
    expectOnlyInputErrors([&] {
        const TriangleMesh mesh = readMeshFromMemory(inputName(), format, data, size);
        if (mesh.faceCount == 0 || mesh.triangles.empty()) __builtin_trap();
        if (mesh.triangleFace.size() != mesh.triangles.size()) __builtin_trap();
        for (const auto& v : mesh.vertices)
            for (double c : v)
                if (!std::isfinite(c)) __builtin_trap();
        for (const auto& t : mesh.triangles)
            for (std::uint32_t i : t)
                if (i >= mesh.vertices.size()) __builtin_trap();
        std::uint32_t previous = 0;
        for (std::uint32_t f : mesh.triangleFace) {
            // in range, and triangles of one face consecutive (non-decreasing)
            if (f >= mesh.faceCount || f < previous) __builtin_trap();
            previous = f;
        }
        const MeshDiagnostics diagnostics = checkMesh(mesh);
        if (diagnostics.degenerateFaces > mesh.faceCount) __builtin_trap();
        // Every closed piece is a connected closed surface once its pinched
        // vertices and paired edges are pulled apart: V - E + F <= 2 each.
        const MeshTopology topology = meshTopology(mesh);
        if (topology.genus < 0 ||
            topology.eulerCharacteristic > 2 * std::int64_t(topology.closedPieces) ||
            topology.closedPieces + topology.otherPieces > mesh.triangles.size())
            __builtin_trap();
        // Turning flipped faces keeps the vertices, faces and corners (each
        // triangle as read or reversed), leaves fewer edges wound against
        // each other, and turns at most half of any sheet's area.
        if (const auto turned = withFlippedFacesTurned(mesh)) {
            const TriangleMesh& out = turned->mesh;
            if (out.vertices != mesh.vertices || out.triangleFace != mesh.triangleFace ||
                out.faceCount != mesh.faceCount || out.triangles.size() != mesh.triangles.size() ||
                turned->turnedFaces == 0 || turned->turnedFaces > mesh.faceCount ||
                !(turned->diagnostics.misorientedEdges < checkMesh(mesh).misorientedEdges) ||
                turned->turnedAreaShare > 0.5 + 1e-9)
                __builtin_trap();
            for (std::size_t t = 0; t < out.triangles.size(); ++t) {
                const auto &a = out.triangles[t], &b = mesh.triangles[t];
                if (a != b && !(a[0] == b[0] && a[1] == b[2] && a[2] == b[1])) __builtin_trap();
            }
        }
        // A mesh without its fins is closed, has at most the faces that are
        // not fins, and numbers them within its face count.
        if (const auto withoutFins = closedWithoutFins(mesh)) {
            const TriangleMesh& rest = withoutFins->mesh;
            if (!checkMesh(rest).closed ||
                rest.faceCount + withoutFins->finFaces > mesh.faceCount ||
                rest.triangleFace.size() != rest.triangles.size() ||
                !(withoutFins->finAreaShare <= kMaxFinAreaShare))
                __builtin_trap();
            for (std::uint32_t f : rest.triangleFace)
                if (f >= rest.faceCount) __builtin_trap();
        }
        // A mesh with its holes capped is closed, keeps every input
        // triangle in place, adds one face per hole and one vertex per hole,
        // and its caps hold at most their share of the area.
        if (const auto capped = closedWithHolesCapped(mesh)) {
            const TriangleMesh& whole = capped->mesh;
            if (!checkMesh(whole).closed || capped->holes == 0 ||
                whole.faceCount != mesh.faceCount + capped->holes ||
                whole.vertices.size() != mesh.vertices.size() + capped->holes ||
                whole.triangleFace.size() != whole.triangles.size() ||
                whole.triangles.size() <= mesh.triangles.size() ||
                !std::equal(mesh.triangles.begin(), mesh.triangles.end(),
                            whole.triangles.begin()) ||
                !(capped->capAreaShare <= kMaxHoleCapAreaShare))
                __builtin_trap();
            for (std::size_t t = 0; t < whole.triangles.size(); ++t) {
                if (whole.triangleFace[t] >= whole.faceCount) __builtin_trap();
                for (std::uint32_t i : whole.triangles[t])
                    if (i >= whole.vertices.size()) __builtin_trap();
            }
        }
        // The two rules together: only where neither takes the mesh alone;
        // the capped mesh is closed, holds the faces not dropped plus one per
        // hole, and both shares are within their limits.
        if (const auto both = closedWithoutFinsAndHoles(mesh)) {
            const TriangleMesh& whole = both->capped.mesh;
            const TriangleMesh& rest = both->withoutFins.mesh;
            if (closedWithoutFins(mesh) || closedWithHolesCapped(mesh) ||
                !checkMesh(whole).closed || both->capped.holes == 0 ||
                rest.triangles.size() >= mesh.triangles.size() ||
                rest.faceCount + both->withoutFins.finFaces > mesh.faceCount ||
                whole.faceCount != rest.faceCount + both->capped.holes ||
                whole.triangles.size() <= rest.triangles.size() ||
                !(both->withoutFins.finAreaShare <= kMaxFinAreaShare) ||
                !(both->capped.capAreaShare <= kMaxHoleCapAreaShare))
                __builtin_trap();
            for (std::size_t t = 0; t < whole.triangles.size(); ++t) {
                if (whole.triangleFace[t] >= whole.faceCount) __builtin_trap();
                for (std::uint32_t i : whole.triangles[t])
                    if (i >= whole.vertices.size()) __builtin_trap();
            }
        }
    });
}

}  // namespace skelseg::fuzz
