#include "io/mesh/VoxelObjectPieces.h"

#include <algorithm>
#include <utility>

#include "io/mesh/MeshCheck.h"
#include "kernels/ConnectedObjects.h"
#include "kernels/DisjointSets.h"

namespace skelseg {

std::vector<ObjectSource> voxelObjectPieces(const TriangleMesh& mesh, const MaskVolume& mask,
                                            const std::vector<std::int32_t>& nearestTriangle,
                                            bool threaded, Interrupter& interrupter) {
    if (nearestTriangle.size() != mask.size()) return {};
    const ConnectedObjects found = findConnectedObjects(mask, {threaded}, interrupter);
    const std::size_t objectCount = found.objects.size();
    if (objectCount < 2) return {};

    // Pieces as checkMesh counts them: triangles joined through vertices at
    // the same position.
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    DisjointSets sets(mesh.vertices.size());
    for (const auto& t : mesh.triangles) {
        sets.unite(canonical[t[0]], canonical[t[1]]);
        sets.unite(canonical[t[0]], canonical[t[2]]);
    }
    std::vector<std::uint32_t> pieceOfTriangle(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        pieceOfTriangle[t] = sets.find(canonical[mesh.triangles[t][0]]);

    // Votes per object and piece, from every object voxel with a nearest
    // triangle (the band around the surface), in scan order. An object is
    // near one piece or two: a short list each.
    using Votes = std::vector<std::pair<std::uint32_t, std::uint64_t>>;  // piece, voxels
    std::vector<Votes> votes(objectCount);
    std::vector<std::array<int, 3>> firstVoxel(objectCount, {-1, -1, -1});
    const VoxelRuns& runs = found.runs;
    const Dims d = mask.dims();
    for (int z = 0; z < d.z; ++z) {
        throwIfInterrupted(interrupter, double(z) / double(d.z));
        for (int y = 0; y < d.y; ++y) {
            const std::size_t row = runs.rowOf(y, z);
            for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k) {
                const VoxelRun& run = runs.runs[k];
                const std::uint32_t object = found.objectOfRun[k];
                if (firstVoxel[object][0] < 0) firstVoxel[object] = {run.x0, y, z};
                Votes& mine = votes[object];
                for (int x = run.x0; x <= run.x1; ++x) {
                    const std::int32_t t = nearestTriangle[mask.index(x, y, z)];
                    if (t < 0 || std::size_t(t) >= pieceOfTriangle.size()) continue;
                    const std::uint32_t piece = pieceOfTriangle[std::size_t(t)];
                    auto vote = std::find_if(mine.begin(), mine.end(),
                                             [&](const auto& v) { return v.first == piece; });
                    if (vote == mine.end()) vote = mine.insert(mine.end(), {piece, 0});
                    ++vote->second;
                }
            }
        }
    }
    std::vector<ObjectSource> sources;
    for (std::size_t o = 0; o < objectCount; ++o) {
        if (votes[o].empty()) continue;
        // The piece of most votes; ties to the lower piece.
        auto best = votes[o].begin();
        for (auto it = votes[o].begin(); it != votes[o].end(); ++it)
            if (it->second > best->second ||
                (it->second == best->second && it->first < best->first))
                best = it;
        sources.push_back({firstVoxel[o], best->first});
    }
    return sources;
}

}  // namespace skelseg
