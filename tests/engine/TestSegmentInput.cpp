// The mask of an input under --time-budget (engine/SegmentInput.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "engine/SegmentInput.h"
#include "engine/SegmentSteps.h"
#include "engine/StageTimer.h"
#include "io/files/TextFile.h"
#include "io/mesh/MeshCheck.h"
#include "io/shapes/SyntheticShapes.h"
#include "kernels/BoundaryGraph.h"
#include "tests/support/CurledTube.h"
#include "tests/support/LargeGridShapes.h"
#include "tests/support/MaskCounts.h"
#include "tests/support/MeshEdits.h"

namespace skelseg {
namespace {

// A small closed mesh: what these tests check is the plan's choice and when
// it stops, which any mesh shows (a larger one only lengthens the runs, most
// of all under the sanitizers).
std::shared_ptr<SegmentSource> sphereSource() {
    auto source = std::make_shared<SegmentSource>();
    source->file = "sphere.off";
    source->mesh = test::sphereMesh({0, 0, 0}, 10.0);
    source->meshDiagnostics = checkMesh(*source->mesh);
    return source;
}

SegmentInputOptions budgetOptions(double seconds) {
    SegmentInputOptions options;
    options.resolution = 64;
    options.memoryLimit = std::uint64_t(1) << 34;
    options.timeBudgetSeconds = seconds;
    options.start = std::chrono::steady_clock::now();
    return options;
}

bool hasStage(const StageTimer& timer, const std::string& name) {
    const auto timings = timer.timings();
    return std::any_of(timings.begin(), timings.end(),
                       [&](const StageTiming& t) { return t.name == name; });
}

// A budget spent before the plan is made: nothing can fit, so the run stops
// at the budget as --time-limit does, before voxelising at any resolution
// (the caller's limit alone would only stop it after the whole mask).
TEST(SegmentInput, ABudgetSpentDuringTheProbeStopsBeforeVoxelising) {
    const SegmentInputOptions options = budgetOptions(1e-9);
    StageTimer timer;
    try {
        maskSegmentSource(sphereSource(), options, timer, nullInterrupter(),
                          [](const std::string&) {});
        ADD_FAILURE() << "a spent budget produced a mask";
    } catch (const InterruptedError& e) {
        EXPECT_EQ(e.reason(), InterruptedError::Reason::TimeLimit);
    }
    EXPECT_FALSE(hasStage(timer, "voxelise"));
}

// A choice that fits is voxelised whatever the clock says after the plan:
// the budget is then no limit (a late answer rather than none).
TEST(SegmentInput, AnAmpleBudgetGivesTheMaskOfTheChosenResolution) {
    const SegmentInputOptions options = budgetOptions(1000.0);
    StageTimer timer;
    const SegmentMask mask = maskSegmentSource(sphereSource(), options, timer, nullInterrupter(),
                                               [](const std::string&) {});
    ASSERT_TRUE(mask.budget.has_value());
    EXPECT_TRUE(mask.budget->fits);
    EXPECT_EQ(mask.resolution, 64);
    EXPECT_TRUE(hasStage(timer, "voxelise"));
    EXPECT_GT(mask.mask.dims().voxelCount(), 0u);
}

TEST(SegmentInput, AVolumesMemoryCapsAreTheFinestCoarseningsWhoseEstimatesFit) {
    const MaskVolume mask = test::figureInALargeGrid();
    SegmentInputOptions options;
    options.threads = 1;
    const std::uint64_t boundary = countBoundaryVoxels(mask);
    std::uint64_t needs[3];  // the volume 1, 2 and 4 times coarser
    for (int i = 0; i < 3; ++i) {
        const MaskVolume coarse = i == 0 ? mask : coarsenMask(mask, 1 << i);
        needs[i] = volumeRunMemory(coarse.dims(), test::countNonzero(coarse), mask.dims(), boundary,
                                   options);
    }
    ASSERT_GT(needs[0], needs[1]);
    ASSERT_GT(needs[1], needs[2]);
    const auto capsAt = [&](std::uint64_t limit) {
        options.memoryLimit = limit;
        return finestCoarseningsWithinMemory(mask, boundary, options);
    };
    // Each estimate is the least limit of its coarsening.
    EXPECT_EQ(capsAt(needs[0]).firstPass, 1);
    EXPECT_EQ(capsAt(needs[0] - 1).firstPass, 2);
    EXPECT_EQ(capsAt(needs[1]).firstPass, 2);
    EXPECT_EQ(capsAt(needs[1] - 1).firstPass, 4);
    EXPECT_EQ(capsAt(needs[2]).firstPass, 4);
    EXPECT_EQ(capsAt(needs[2] - 1).firstPass, 0);
    // A finer pass runs beside a coarsened first pass's result.
    const std::uint64_t held = heldResultBytes(mask.dims(), 1, true);
    EXPECT_EQ(capsAt(needs[0] + held).finerPass, 1);
    EXPECT_EQ(capsAt(needs[0] + held - 1).finerPass, 2);
    EXPECT_EQ(capsAt(needs[0]).finerPass, needs[1] + held <= needs[0] ? 2 : 4);
    EXPECT_EQ(capsAt(needs[2] + held - 1).finerPass, 0);
}

TEST(SegmentInput, TheOutputsSurfacesCountInAVolumesEstimate) {
    // A coarsened grid's segmentation shrinks; the outputs drawn on the
    // input's grid do not: the estimate never falls below their share.
    const MaskVolume mask = test::figureInALargeGrid();
    SegmentInputOptions options;
    const std::uint64_t boundary = countBoundaryVoxels(mask);
    const MaskVolume coarse = coarsenMask(mask, 4);
    const std::uint64_t segmenting =
        estimateSegmentationMemory(coarse.dims(), test::countNonzero(coarse), 1, 1) +
        mask.dims().voxelCount();
    const auto writing = [&](std::uint64_t surfaceVoxels) {
        return mask.dims().voxelCount() * 3 + coarse.dims().voxelCount() * 3 +
               surfaceVoxels * kOutputBytesPerBoundaryVoxel;
    };
    EXPECT_EQ(
        volumeRunMemory(coarse.dims(), test::countNonzero(coarse), mask.dims(), boundary, options),
        std::max(segmenting, writing(boundary)));
    // A surface four times larger (a rougher shape on the same grid): the
    // writing phase is the larger, and the estimate.
    ASSERT_GT(writing(4 * boundary), segmenting);
    EXPECT_EQ(volumeRunMemory(coarse.dims(), test::countNonzero(coarse), mask.dims(), 4 * boundary,
                              options),
              writing(4 * boundary));
    // A mesh's grid (no boundary given) keeps the segmentation's estimate.
    EXPECT_EQ(volumeRunMemory(mask.dims(), test::countNonzero(mask), mask.dims(), 0, options),
              estimateSegmentationMemory(mask.dims(), test::countNonzero(mask), 1, 1));
}

TEST(SegmentInput, APreviewCountsInTheEstimateOfAMeshAndOfAVolume) {
    // preview.png's picture, panels and normals are held while the outputs
    // are written: with a preview the writing phase counts previewRunMemory,
    // for a mesh's triangles and for a volume's surface; without one nothing.
    SegmentInputOptions options = budgetOptions(0.0);
    options.threads = 2;
    options.levels = 1;
    std::vector<std::string> warnings;
    const auto meshMask = [&](bool preview) {
        options.preview = preview;
        StageTimer timer;
        return maskSegmentSource(sphereSource(), options, timer, nullInterrupter(),
                                 [&](const std::string& w) { warnings.push_back(w); });
    };
    const TriangleMesh sphere = *sphereSource()->mesh;
    const std::uint64_t meshPreview =
        previewRunMemory(true, sphere.triangles.size(), sphere.vertices.size(), 2);
    EXPECT_EQ(previewRunMemory(false, sphere.triangles.size(), sphere.vertices.size(), 2), 0u);
    EXPECT_GT(meshPreview, std::uint64_t(20) << 20);  // its picture and two panels at least
    const SegmentMask without = meshMask(false), with = meshMask(true);
    // The sphere's grid is small: writing with the preview is the larger phase.
    EXPECT_EQ(with.estimatedMemory, with.mask.dims().voxelCount() * 3 + meshPreview);
    EXPECT_GT(with.estimatedMemory, without.estimatedMemory);
    EXPECT_FALSE(with.previewOverMemory);
    EXPECT_TRUE(warnings.empty());

    // Between the two: the run goes on without its preview, and says so.
    options.memoryLimit = with.estimatedMemory - 1;
    const SegmentMask skipped = meshMask(true);
    EXPECT_TRUE(skipped.previewOverMemory);
    EXPECT_EQ(skipped.estimatedMemory, without.estimatedMemory);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("preview.png skipped to fit --max-memory"), std::string::npos)
        << warnings[0];
    EXPECT_EQ(skipped.warnings, warnings);
    // Below what the run needs without it: refused, naming that need.
    options.memoryLimit = without.estimatedMemory - 1;
    try {
        meshMask(true);
        ADD_FAILURE() << "a mesh over the limit without its preview was not refused";
    } catch (const MemoryLimitError& e) {
        EXPECT_NE(std::string(e.what()).find(formatBytes(without.estimatedMemory)),
                  std::string::npos)
            << e.what();
    }

    const MaskVolume mask = test::figureInALargeGrid();
    const MaskVolume coarse = coarsenMask(mask, 4);  // whose writing phase is the larger
    // A surface of 50,000 voxels on its grid, so that writing is the larger phase.
    const std::uint64_t surface = 50000;
    const auto volumeEstimate = [&](bool preview) {
        options.preview = preview;
        return volumeRunMemory(coarse.dims(), test::countNonzero(coarse), mask.dims(), surface,
                               options);
    };
    ASSERT_GT(volumeEstimate(false),
              estimateSegmentationMemory(coarse.dims(), test::countNonzero(coarse), 2, 1) +
                  mask.dims().voxelCount());
    EXPECT_EQ(volumeEstimate(true),
              volumeEstimate(false) + previewRunMemory(true, 2 * surface, surface, 2));
    // More threads render more panels at once (up to the three views).
    EXPECT_LT(previewRunMemory(true, 1000, 500, 1), previewRunMemory(true, 1000, 500, 2));
    EXPECT_LT(previewRunMemory(true, 1000, 500, 2), previewRunMemory(true, 1000, 500, 3));
    EXPECT_EQ(previewRunMemory(true, 1000, 500, 3), previewRunMemory(true, 1000, 500, 8));
}

// A closed mesh whose voxel model keeps handles the mesh lacks is named in a
// warning with the count, and is cut with loops round handles carrying no
// area (unless --keep-handle-areas); one whose model has the mesh's genus is
// neither. The
// curled tube's end sinks into its beginning: with the self-overlap clearing
// held to 2 voxels the crossing stays fused at some of these shapes and
// resolutions, with the default (up to 4) it is separated.
TEST(SegmentInput, HandlesTheMeshLacksAreWarnedAbout) {
    int warned = 0;
    int quiet = 0;
    for (double extraAngle : {1.2, 2.0}) {
        test::CurledTube tube;
        tube.endRadius = 0.3;
        tube.extraAngle = extraAngle;
        auto source = std::make_shared<SegmentSource>();
        source->file = "curled-tube.off";
        source->mesh = tube.mesh();
        source->meshDiagnostics = checkMesh(*source->mesh);
        ASSERT_TRUE(source->meshDiagnostics.closed);
        for (int resolution : {64, 96}) {
            for (int clearance : {2, 4}) {
                SegmentInputOptions options;
                options.resolution = resolution;
                options.selfOverlapClearance = clearance;
                options.memoryLimit = std::uint64_t(1) << 34;
                StageTimer timer;
                std::vector<std::string> printed;
                const SegmentMask mask =
                    maskSegmentSource(source, options, timer, nullInterrupter(),
                                      [&](const std::string& w) { printed.push_back(w); });
                EXPECT_EQ(printed, mask.warnings);
                const auto handles = std::find_if(
                    mask.warnings.begin(), mask.warnings.end(),
                    [](const std::string& w) { return w.find("handle") != std::string::npos; });
                const std::int64_t extra = mask.voxelGenus.genus - mask.meshGenus.genus;
                SegmentationParameters requested;
                EXPECT_EQ(parametersFor(mask, requested).cutRules.handleLoopsCarryNoArea,
                          extra > 0);
                requested.artefactHandlesCarryNoArea = false;  // --keep-handle-areas
                EXPECT_FALSE(parametersFor(mask, requested).cutRules.handleLoopsCarryNoArea);
                if (extra > 0) {
                    ++warned;
                    ASSERT_NE(handles, mask.warnings.end())
                        << "no warning for " << extra << " extra handles at " << resolution;
                    EXPECT_EQ(handles->rfind("curled-tube.off: ", 0), 0u) << *handles;
                    EXPECT_NE(handles->find(" has " + std::to_string(extra) + " handle"),
                              std::string::npos)
                        << *handles;
                } else {
                    ++quiet;
                    EXPECT_EQ(handles, mask.warnings.end()) << *handles;
                }
            }
        }
    }
    // Both kinds must occur, or the test checks only one side.
    EXPECT_GE(warned, 1);
    EXPECT_GE(quiet, 1);
}

// A plate 2048 voxels wide and a voxel or two thick was estimated at 0.88
// GB (its boundary taken as a sixth of a quarter of the grid) and took 1.78
// GB; the boundary a mesh exposes now bounds the graph's share.
TEST(SegmentInput, AMeshRunEstimateCountsTheBoundaryItsSurfaceExposes) {
    TriangleMesh plate;
    plate.vertices = {{0, 0, 0},    {1, 0, 0},    {1, 1, 0},    {0, 1, 0},
                      {0, 0, 1e-6}, {1, 0, 1e-6}, {1, 1, 1e-6}, {0, 1, 1e-6}};
    plate.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                       {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
    for (std::uint32_t t = 0; t < 12; ++t) plate.triangleFace.push_back(t);
    plate.faceCount = 12;
    // Both sides of the plate, 2048^2 each (its thin sides add about 4e-6).
    EXPECT_NEAR(double(meshBoundaryVoxels(plate, 2048)), 2.0 * 2048 * 2048, 100.0);
    const Dims grid{2052, 2052, 5};
    EXPECT_EQ(meshRunMemory(grid, 1, false, 0), meshRunMemory(grid, 1, false, 1000));
    EXPECT_GT(meshRunMemory(grid, 1, false, meshBoundaryVoxels(plate, 2048)),
              meshRunMemory(grid, 1, false, 0) + std::uint64_t(1.2e9));
}

// Every other triangle along a hole's border wound the wrong way: the border
// then runs both ways round the hole and cannot be chained into a loop, so
// the hole rule alone refuses the mesh. Turned first, the hole is capped.
TEST(SegmentInput, FlippedFacesAlongAHoleAreTurnedBeforeTheHoleIsCapped) {
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    TriangleMesh mesh = test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return test::centroidZ(sphere, t) > 0.99; });
    const std::uint32_t firstRing = 1, ringSize = 32;  // sphereMesh's vertices after the pole
    const auto onFirstRing = [&](std::uint32_t v) {
        return v >= firstRing && v < firstRing + ringSize;
    };
    std::size_t flipped = 0;
    for (auto& t : mesh.triangles)
        if (onFirstRing(t[0]) && onFirstRing(t[1]) && t[0] % 2 == 0) {
            std::swap(t[1], t[2]);
            ++flipped;
        }
    ASSERT_EQ(flipped, ringSize / 2);
    ASSERT_FALSE(closedWithHolesCapped(mesh).has_value());

    SegmentSource source;
    source.file = "sphere.off";
    source.mesh = mesh;
    checkSourceMesh(source);
    ASSERT_TRUE(source.flippedFacesTurned.has_value());
    EXPECT_EQ(source.flippedFacesTurned->turnedFaces, flipped);
    ASSERT_TRUE(source.withHolesCapped.has_value());
    EXPECT_EQ(source.withHolesCapped->holes, 1u);
    EXPECT_TRUE(source.meshDiagnostics.closed);
    EXPECT_EQ(source.meshDiagnostics.misorientedEdges, 0u);
    EXPECT_EQ(&source.voxelisedMesh(), &source.withHolesCapped->mesh);
}

}  // namespace
}  // namespace skelseg
