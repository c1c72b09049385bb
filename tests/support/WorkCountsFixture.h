// Work counters for the time budget's tests (TestTimeBudget.cpp,
// TestBudgetCalibration.cpp): a probe's or a run's WorkCounts from numbers.
#pragma once

#include <array>

#include "engine/TimeBudget.h"

namespace skelseg::test {

/// The counters of a grid of gridSides[0] x [1] x [2] voxels; meshFaces 0
/// for a volume.
inline WorkCounts workCounts(const std::array<double, 3>& gridSides, double objectVoxels,
                             double boundaryVoxels, double candidates, double meshFaces) {
    WorkCounts w;
    w.gridVoxels = gridSides[0] * gridSides[1] * gridSides[2];
    w.objectVoxels = objectVoxels;
    w.boundaryVoxels = boundaryVoxels;
    w.candidates = candidates;
    w.meshFaces = meshFaces;
    return w;
}

}  // namespace skelseg::test
