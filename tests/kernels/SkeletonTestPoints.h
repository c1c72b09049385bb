// Hand-built skeleton point sets for the skeleton-graph and cut-placement
// tests: voxel chains with chosen measures, and the graph node of a voxel.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <map>
#include <vector>

#include "kernels/SkeletonGraph.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/base/Volume.h"

namespace skelseg::test {

/// Builds a SkeletonPoint list on a grid; points are kept in voxel order
/// (like measureSkeleton's candidate order).
class SkeletonPointSet {
public:
    explicit SkeletonPointSet(Dims dims) : mDims(dims) {}

    const Dims& dims() const { return mDims; }

    /// Adds (or overwrites) a point; returns its voxel index.
    std::uint32_t add(std::array<int, 3> p, float rhoS = 10.0f, double rhoC = 1000.0,
                      std::uint8_t robustRims = 2, float sigma = 0.5f) {
        const std::uint32_t v = voxelIndex(p);
        SkeletonPoint& s = mPoints[v];
        s.voxel = v;
        s.rhoS = rhoS;
        s.rhoC = rhoC;
        s.rims = std::max<std::uint8_t>(robustRims, 2);
        s.robustRims = robustRims;
        s.sigma = sigma;
        return v;
    }
    /// A straight chain of `length` voxels from `start` in steps of `step`
    /// (26-connected when each step is in {-1,0,1}^3); returns the voxels.
    std::vector<std::uint32_t> chain(std::array<int, 3> start, std::array<int, 3> step, int length,
                                     float rhoS = 10.0f, double rhoC = 1000.0) {
        std::vector<std::uint32_t> voxels;
        for (int i = 0; i < length; ++i)
            voxels.push_back(
                add({start[0] + i * step[0], start[1] + i * step[1], start[2] + i * step[2]}, rhoS,
                    rhoC));
        return voxels;
    }
    SkeletonPoint& point(std::uint32_t voxel) { return mPoints.at(voxel); }
    std::uint32_t voxelIndex(std::array<int, 3> p) const {
        return std::uint32_t(p[0]) +
               std::uint32_t(mDims.x) *
                   (std::uint32_t(p[1]) + std::uint32_t(mDims.y) * std::uint32_t(p[2]));
    }

    /// The list in voxel order, with `candidate` set to the list position.
    std::vector<SkeletonPoint> points() const {
        std::vector<SkeletonPoint> out;
        for (const auto& [voxel, p] : mPoints) {
            out.push_back(p);
            out.back().candidate = std::uint32_t(out.size() - 1);
        }
        return out;
    }
    /// Position of `voxel` in points().
    std::uint32_t pointIndex(std::uint32_t voxel) const {
        return std::uint32_t(std::distance(mPoints.begin(), mPoints.find(voxel)));
    }

private:
    Dims mDims;
    std::map<std::uint32_t, SkeletonPoint> mPoints;
};

/// A junction (rho_S 40 s) between a straight body of 30 s voxels and a
/// straight limb of `limbLength` voxels along x, the body at rho_S 40 s and
/// the limb at 20 s (loop radius 6.4 s), sigma 0.9 on both, at scale s:
/// lengths and loops grow together, as with the resolution. The limb starts
/// at x = 30 s + 3; the grid leaves three voxels past its end.
inline SkeletonPointSet bodyWithOneLimb(int scale, int limbLength) {
    const int bodyLength = 30 * scale;
    SkeletonPointSet set{Dims{bodyLength + limbLength + 6, 5, 3}};
    set.add({bodyLength + 2, 2, 1}, 40.0f * float(scale), 5000.0, 3);
    for (std::uint32_t v :
         set.chain({bodyLength + 1, 2, 1}, {-1, 0, 0}, bodyLength, 40.0f * float(scale)))
        set.point(v).sigma = 0.9f;
    for (std::uint32_t v :
         set.chain({bodyLength + 3, 2, 1}, {1, 0, 0}, limbLength, 20.0f * float(scale)))
        set.point(v).sigma = 0.9f;
    return set;
}

/// Graph node of a voxel (or kNoJunction).
inline std::uint32_t nodeOf(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                            std::uint32_t voxel) {
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
        if (points[g.point[n]].voxel == voxel) return n;
    return kNoJunction;
}

}  // namespace skelseg::test
