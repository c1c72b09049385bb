// The mesh fuzz targets (FuzzOff, FuzzObj, FuzzStl, FuzzPly) share this body:
// read, then check the invariants io/mesh/MeshIO.h promises for every mesh it
// returns.
#pragma once

#include <cmath>

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
    });
}

}  // namespace skelseg::fuzz
