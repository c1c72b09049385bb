// skelseg: the files `skelseg segment` writes, from the segmented shape.
//
// Every writer stages its file(s) in the OutputDirectory (io/files), which
// moves them into OUTDIR only when the whole run succeeded; the writers are
// independent of each other and run concurrently in the command's flow
// graph, each as one Stage (its report.json name in brackets):
//   writeLabelNrrd          labels.nrrd                  ("write labels.nrrd")
//   writeLabelVdb           labels.vdb                   ("write labels.vdb")
//   writeSkeletonAndCuts    skeleton.ply, cuts.ply       ("write skeleton.ply, cuts.ply")
//   writeLevels             levels/, hierarchy.json      ("write levels, hierarchy.json";
//                           hierarchy runs only)
//   writeSurfacesAndPreview segments.ply, segments.glb, viewer.html, preview.png,
//                           and for meshes segmentation.seg
//                           ("segment surfaces and preview", within it
//                           "write segments.glb, viewer.html")
// report.json is written last, by SegmentReport.h. Positions are in the
// world frame of the input (docs/outputs.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/LevelOutputs.h"
#include "engine/SegmentCommand.h"
#include "engine/SegmentInput.h"
#include "engine/Segmenter.h"
#include "engine/StageTimer.h"
#include "io/files/OutputDirectory.h"
#include "io/render/PlyWriter.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

/// Skeleton and cut loops of every object in world coordinates, as the PLY
/// files and the preview draw them.
struct WorldGeometry {
    std::vector<SkeletonPointRecord> skeletonPoints;
    std::vector<std::array<std::uint32_t, 2>> skeletonEdges;  // into skeletonPoints
    std::vector<std::vector<std::array<double, 3>>> cutLoops;
};

/// What the writers and the report read: the input, the segmentation, the
/// mesh's face labels (mesh inputs) and the world geometry.
struct SegmentedShape {
    std::shared_ptr<const SegmentMask> input;
    SegmentationResult result;
    std::vector<std::uint32_t> faceLabels;  // per input face, 0-based segment
    /// The voxel label (1..K) of each face label (mesh inputs).
    std::vector<std::uint32_t> voxelLabelOfFaceLabel;
    WorldGeometry world;
    /// Hierarchy runs (result.finerLevels not empty): every level's faces and cuts.
    LevelOutputs levels;
};

/// Skeleton points, edges and cut loops of `result` in world coordinates
/// (objects in order; a handle loop's rho_C is its object's boundary area).
WorldGeometry gatherWorldGeometry(const SegmentationResult& result);

void writeLabelNrrd(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                    Interrupter& interrupter);
void writeLabelVdb(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                   Interrupter& interrupter);
void writeSkeletonAndCuts(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                          Interrupter& interrupter);
/// Hierarchy runs: levels/k/ (labels.nrrd, cuts.ply, for meshes
/// segmentation.seg) for every level k, finest 0, and hierarchy.json; nothing
/// for a single level.
void writeLevels(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                 Interrupter& interrupter);
/// segments.ply (a mesh input's own triangles, else the smoothed surfaces of
/// the label volume), segmentation.seg for meshes, segments.glb and
/// viewer.html of the same surface (engine/SegmentViews.h), and preview.png
/// when `writePreview` (options.writePreview, unless --time-budget left no
/// time for it).
void writeSurfacesAndPreview(OutputDirectory& out, const SegmentedShape& shape,
                             const SegmentCommandOptions& options, bool writePreview,
                             StageTimer& timer, Interrupter& interrupter);

}  // namespace skelseg
