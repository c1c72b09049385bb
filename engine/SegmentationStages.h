// skelseg: the stages that segment one object, one function each.
//
// segmentVolume() (Segmenter.h) finds the objects of a mask and runs, for
// each, these stages in order over one ObjectState:
//
//   stage function               report.json stage               kernel(s)
//   cropObject                   "crop"                          (here)
//   computeObjectFeatureTransform "feature transform"            FeatureTransform.h
//   buildObjectBoundaryGraph     "boundary graph"                BoundaryGraph.h
//   selectObjectCandidates       "skeleton candidates"           SkeletonCandidates.h
//   computeObjectLandmarks       "landmarks"                     PathSearch.h
//   measureObjectSkeleton        "path sets, rims, areas, sigma" SkeletonMeasures.h,
//                                                                 SkeletonBand.h (band search)
//   buildObjectSkeletonGraph     "skeleton graph"                SkeletonGraph.h
//   placeObjectCuts              "cut placement"                 CutPlacement.h, CutLoopOrder.h
//   placeJointCuts (--joints)    "joint cuts"                    JointDetection.h, CutLoopOrder.h
//   labelObjectSurface           "labelling"                     SurfaceLabelling.h
//   labelObjectInterior          "interior labels"               SurfaceLabelling.h
//
// Each stage function runs under one Stage (engine/Stage.h): its time goes
// to the StageTimer and the interrupter hears its name. Objects smaller than
// SegmentationParameters::minObjectVoxels skip the skeleton stages (from the
// candidates to the cuts) and become one segment each. A stage reads what
// the stages before it left in the state and fills its own fields; it throws
// InterruptedError when the interrupter asks to stop.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/Segmenter.h"
#include "engine/StageTimer.h"
#include "kernels/BoundaryGraph.h"
#include "kernels/Cavities.h"
#include "kernels/ConnectedObjects.h"
#include "kernels/CutPlacement.h"
#include "kernels/NarrowTunnels.h"
#include "kernels/PathSearch.h"
#include "kernels/SkeletonCandidates.h"
#include "kernels/SkeletonGraph.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/SurfaceLabelling.h"
#include "kernels/TunnelPlugs.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// One level of a hierarchy run other than the top-level one, for one
/// object (engine/SegmentationLevels.h).
struct ObjectLevelWork {
    double tauArea = 0.0;
    double noiseArea = 0.0;
    /// The level's cut loops: its own cuts and every coarser level's, each once.
    std::vector<std::vector<std::uint32_t>> cutLoops;
    SurfaceSegments segments;           // nested in the next coarser level's
    std::vector<std::uint32_t> parent;  // per segment: segment at the next coarser level
                                        // (empty at the coarsest)
    std::uint64_t movedNodes = 0;       // nodes the nesting repair moved
    Volume<std::uint16_t> localLabels;  // as ObjectState::localLabels
    LevelSeconds seconds;
};

/// Everything known about one object, filled in stage order. Volumes and
/// boundary nodes are in the object's crop: its bounding box padded by one
/// background voxel on every side (so an object touching the grid border
/// sees background beyond it).
struct ObjectState {
    ObjectState(const SegmentationParameters& runParameters, Interrupter& runInterrupter,
                StageTimer& runTimer, const ObjectExtent& objectExtent)
        : parameters(runParameters),
          interrupter(runInterrupter),
          timer(runTimer),
          extent(objectExtent) {}
    ObjectState(const ObjectState&) = delete;
    ObjectState& operator=(const ObjectState&) = delete;

    // The run: fixed for every stage.
    const SegmentationParameters& parameters;
    Interrupter& interrupter;
    StageTimer& timer;
    const ObjectExtent extent;  // in the input grid

    std::array<int, 3> origin{};  // crop: input-grid voxel of crop voxel (0,0,0)
    MaskVolume crop;              // crop: 1 on the object's voxels and cavities
    // crop: what was filled, to leave unlabelled: the cavities, the
    // tunnels one voxel wide closed (crop voxel indices) and the cavities
    // that closing them sealed.
    FilledCavities cavities, sealedCavities;
    std::vector<std::size_t> tunnelVoxels;
    Volume<std::uint32_t> featureTransform;            // feature transform: nearest boundary voxel
    BoundaryGraph graph;                               // boundary graph
    std::vector<SkeletonCandidate> candidates;         // skeleton candidates
    Landmarks landmarks;                               // landmarks
    std::vector<SkeletonPoint> points;                 // measures: the curve skeleton C
    SkeletonGraph skeleton;                            // skeleton graph: C_tau
    CutPlan plan;                                      // cut placement: the decisions
    std::vector<std::vector<std::uint32_t>> cutLoops;  // cut placement: Gamma of each cut
    SurfaceSegments segments;                          // labelling: boundary segments
    Volume<std::uint16_t> localLabels;  // interior labels: local segment + 1, 0 outside

    /// Hierarchy runs: one entry per level of SegmentationResult::
    /// finerLevels, finest first (empty otherwise): with --joints the joint
    /// level first, then the junction-rule levels finer than the top-level
    /// fields above (which are the coarsest level's; with --joints and a
    /// single tau they are the joint level, and the junction-rule level is
    /// the last entry).
    std::vector<ObjectLevelWork> finerLevels;
    /// Index in finerLevels of the finest junction-rule level below the top.
    std::size_t firstJunctionLevel() const { return parameters.joints ? 1 : 0; }
    /// One past the last junction-rule level below the top.
    std::size_t endJunctionLevels() const {
        return firstJunctionLevel() + parameters.finerTaus.size();
    }
    LevelSeconds coarsestSeconds;  // the coarsest level's per-level stages

    /// The object's part of the result (counts, skeleton, cuts; global
    /// labels are added by segmentVolume once every object is done).
    ObjectSegmentation out;

    /// Input-grid voxel of a linear crop voxel index.
    std::array<int, 3> toGrid(std::uint32_t cropVoxel) const;
    /// The measure options of this object: the same for the measures and
    /// the exact re-measures of cut placement.
    SkeletonMeasureOptions measureOptions() const;
};

/// Copies the object (the runs of `objects` with its id) out of the input
/// grid into `state.crop`, and fills its cavities there (and, where the
/// parameters ask for it, closes its tunnels one voxel wide).
void cropObject(ObjectState& state, const ConnectedObjects& objects);
/// Exact Euclidean feature transform of the crop's boundary voxels.
void computeObjectFeatureTransform(ObjectState& state);
/// The boundary graph; sets the boundary area, tau and the noise area.
void buildObjectBoundaryGraph(ObjectState& state);
/// Candidate voxels for the curve skeleton.
void selectObjectCandidates(ObjectState& state);
/// Landmark distances for the A* bounds of every later search.
void computeObjectLandmarks(ObjectState& state);
/// Path sets, rims, rho_S, rho_C and sigma of every candidate: the points of C.
void measureObjectSkeleton(ObjectState& state);
/// The simplified skeleton C_tau as a graph, its junctions and bridges.
void buildObjectSkeletonGraph(ObjectState& state);
/// The junction rule's cuts, each as its path set and as an ordered loop.
void placeObjectCuts(ObjectState& state);
/// Cuts at joints inside parts (narrowings and bends along a branch) on the
/// current skeleton, at least a few radii from the skeleton nodes
/// `existingCuts`; runs only when parameters.joints is set. Its cuts follow
/// the cuts already in cutLoops, with kind Joint.
void placeJointCuts(ObjectState& state, const std::vector<std::uint32_t>& existingCuts);
/// Boundary segments between the cut loops.
void labelObjectSurface(ObjectState& state);
/// Every object voxel takes the segment of its feature voxel.
void labelObjectInterior(ObjectState& state);
/// The object's voxels labelled by `segments` (local id + 1, 0 outside; the
/// work of labelObjectInterior, for any level).
Volume<std::uint16_t> objectInteriorLabels(const ObjectState& state,
                                           const SurfaceSegments& segments);

/// Runs every stage above in order (the skeleton stages only for objects of
/// at least minObjectVoxels voxels) and records skeleton, junctions and
/// critical points in `state.out`.
void runObjectStages(ObjectState& state, const ConnectedObjects& objects);

}  // namespace skelseg
