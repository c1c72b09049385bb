// skelseg: the whole method on one binary volume.
//
// segmentVolume() finds the objects (26-connected components) of a mask
// (stage "objects"), segments each on its own in a crop padded by one
// background voxel (engine/SegmentationStages.h: crop -> feature transform ->
// boundary graph -> candidates -> landmarks -> path sets, rims, areas, sigma
// -> skeleton graph -> cut placement -> labelling -> interior labels), then
// gives every segment of every object one global label 1..K by decreasing
// boundary area (ties: object order, then segment order; stage "label
// volume"). Every stage polls the interrupter and is timed in the StageTimer.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/StageTimer.h"
#include "kernels/CutPlacement.h"
#include "kernels/Islands.h"
#include "kernels/JointDetection.h"
#include "kernels/SkeletonBand.h"
#include "kernels/SkeletonCandidates.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/SurfaceLabelling.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// tau, as an area in voxels or as a percentage of the object's boundary area.
struct TauSpec {
    double value = 3.0;
    bool percent = true;
    /// Parses "250" (voxels) or "2.5%" (of the boundary area). Throws UsageError.
    static TauSpec parse(const std::string& text);
    std::string toString() const;
    double areaFor(std::uint64_t boundaryArea) const {
        return percent ? value * 0.01 * double(boundaryArea) : value;
    }
};

/// How the measures stage finds the curve skeleton C.
enum class SkeletonSearch {
    /// Measure every candidate: the reference the tests compare with.
    Exhaustive,
    /// Measure only a band around the skeleton (kernels/SkeletonBand.h), the
    /// default: the same C_tau on every shape measured (docs/performance.md).
    Band,
};

/// "exhaustive" or "band", as on the command line and in report.json.
const char* skeletonSearchName(SkeletonSearch search);

/// Parses a --tau list such as "1%,3%,9%": one or more values as
/// TauSpec::parse takes them, all percentages or all voxel areas, no value
/// twice; returns them sorted, smallest (finest level) first.
/// @throw UsageError naming the list and the problem.
std::vector<TauSpec> parseTauList(const std::string& text);

struct SegmentationParameters {
    /// The coarsest level's tau: the only one without finerTaus.
    TauSpec tau;
    /// Hierarchy runs (--tau 1%,3%,9%; engine/SegmentationLevels.h): the
    /// finer levels' taus, finest first; `tau` is the coarsest. Empty: one
    /// level, exactly the run without levels.
    std::vector<TauSpec> finerTaus;
    /// Every junction-rule level's tau, finest first (finerTaus, then tau).
    std::vector<TauSpec> levelTaus() const;
    /// Every level of the run: the junction-rule levels, and with `joints`
    /// the joint level below the finest of them.
    std::size_t levelCount() const { return finerTaus.size() + 1 + (joints ? 1 : 0); }
    /// The taus as the command line takes them, finest first: "1%,3%,9%";
    /// "3%" for a single level.
    std::string tauListString() const;
    double sigmaMin = 0.8;
    double bodyRatio = 0.6;
    CutMode mode = CutMode::JunctionRule;
    /// The cut placement's other rules (kernels/CutPlacement.h): sibling
    /// tolerance, limb taper, corner length and reach, passages, the run below
    /// sigmaMin. Its sigmaMin, bodyRatio, consecutiveLevels and mode are
    /// replaced by the fields of these parameters (cutOptions()).
    CutOptions cutRules;
    /// The options the cut placement runs with: cutRules with sigmaMin,
    /// bodyRatio, consecutiveLevels and mode from these parameters.
    CutOptions cutOptions() const;
    bool threaded = true;
    /// A hierarchy (finerTaus) always runs the exhaustive search: the band is
    /// found at one tau.
    SkeletonSearch skeletonSearch = SkeletonSearch::Band;
    /// Components below this never make a rim count: max(noiseAreaMin,
    /// noiseAreaFraction * boundary area), and at most tau.
    double noiseAreaMin = 10.0;
    double noiseAreaFraction = 0.002;
    /// The noise area of an object whose boundary area is `boundaryArea`.
    double noiseAreaFor(double boundaryArea) const { return noiseAreaFor(boundaryArea, tau); }
    /// The same at a level whose tau is `levelTau`.
    double noiseAreaFor(double boundaryArea, const TauSpec& levelTau) const {
        return std::min(std::max(noiseAreaMin, noiseAreaFraction * boundaryArea),
                        std::max(levelTau.areaFor(std::uint64_t(boundaryArea)), 1.0));
    }
    int regionRadius = 3;
    double bridgeGap = 4.0;
    /// Branchings of C_tau are junctions too (SkeletonGraphOptions::forkJunctions).
    bool forkJunctions = true;
    /// On an object of genus 0 too, rims that meet mark a handle point
    /// (SkeletonMeasureOptions::surfaceHasGenusZero off).
    bool handleFlagOnGenusZero = false;
    /// A closed mesh whose voxel model has handles the mesh lacks is cut with
    /// CutOptions::handleLoopsCarryNoArea (engine/SegmentSteps.h,
    /// parametersFor); false (--keep-handle-areas): as any other input.
    bool artefactHandlesCarryNoArea = true;
    /// Tunnels one voxel wide are closed, and those two voxels wide plugged,
    /// in objects of genus above 0 (kernels/NarrowTunnels.h,
    /// kernels/TunnelPlugs.h): true for volumes; parametersFor() turns it
    /// off for a mesh's voxel model, whose handles are checked against the
    /// mesh's genus instead.
    bool closeNarrowTunnels = true;
    /// Regions grow to their branches' split (SkeletonGraphOptions::growRegionsToSplits).
    bool growRegionsToSplits = true;
    /// Touching junction regions are one junction only within this many part
    /// radii (SkeletonGraphOptions::junctionMergeRadii).
    double junctionMergeRadii = 0.8;
    int consecutiveLevels = 3;
    /// Objects with fewer voxels are one segment without a skeleton.
    std::uint64_t minObjectVoxels = 27;
    /// Also cut inside parts at joints (kernels/JointDetection.h): one more
    /// level, below the finest junction-rule level, whose cuts are that
    /// level's and the joint cuts found on its skeleton. With a single tau
    /// the top-level result is the joint level (SegmentationResult::
    /// topIsCoarsestLevel). jointOptions.sigmaMin is replaced by sigmaMin.
    bool joints = false;
    JointOptions jointOptions;
    /// A voxelised mesh: the mesh piece of each object of the mask (the
    /// voxeliser's, io/mesh/VoxelObjectPieces.h). Objects broken off a piece
    /// and smaller than a part of it at the finest tau are no segments
    /// (kernels/Islands.h, findFragments). Empty: every object counts.
    std::vector<ObjectSource> objectSources;
};

/// The search a run with `parameters` uses: the band is found at one tau
/// (kernels/SkeletonBand.h) and would miss branches only a finer tau keeps, so
/// a hierarchy (finerTaus) runs the exhaustive search whatever was asked (the
/// CLI refuses an explicit band with a list before any work).
SkeletonSearch skeletonSearchToRun(const SegmentationParameters& parameters);

struct SkeletonVertex {
    std::array<int, 3>
        voxel{};  // in the input grid (may be -1 or dims for border-touching objects)
    float rhoS = 0.0f;
    double rhoC = 0.0;  // +inf for handle loops
    float sigma = -1.0f;
    bool junction = false;
    bool critical = false;
};

struct JunctionInfo {
    std::array<int, 3> voxel{};
    std::uint32_t branches = 0;
    std::uint32_t cuts = 0;
    float rhoS = 0.0f;
    std::uint32_t coreVoxels = 0;
    std::uint32_t forkVoxels = 0;  // core voxels that are forks, not J_tau points
};

struct CriticalPointInfo {
    std::array<int, 3> voxel{};
    std::uint32_t junction = 0;
    float sigma = 0.0f;
    float rhoS = 0.0f;
    float limbRhoS = 0.0f;  // the circumference the body test compared
    double rhoC = 0.0;
    float similarity = 0.0f;
    bool isCorner = false;         // a corner of a flat end, not cut (CutCandidate::isCorner)
    bool belowSigmaMin = false;    // found by a run below sigma_min (CutCandidate::belowSigmaMin)
    bool stubLimb = false;         // found by the stub rule (CutCandidate::stubLimb)
    bool loopSeparates = true;     // CutCandidate::loopSeparates
    bool movedToSeparate = false;  // CutCandidate::movedToSeparate
    bool isCut = false;
};

/// Wall and CPU seconds of the stages that run once per level (skeleton
/// graph, cut placement, labelling, interior labels, nesting), summed over
/// the objects.
struct LevelSeconds {
    double wall = 0.0;
    double cpu = 0.0;
};

/// One object at one level of a hierarchy run other than the top-level one.
struct ObjectLevel {
    double tauArea = 0.0;
    double noiseArea = 0.0;
    /// The level's cut loops (its own and every coarser level's), as cutLoops below.
    std::vector<std::vector<std::array<int, 3>>> cutLoops;
    std::vector<std::uint16_t> labels;  // global labels of the object's segments at this level
};

/// Which rule placed a cut.
enum class CutKind : std::uint8_t { Junction, Joint };

/// One cut of cutLoops (same order), as report.json lists it.
struct CutInfo {
    CutKind kind = CutKind::Junction;
    std::array<int, 3> voxel{};  // the skeleton point whose loop is the cut
    float sigma = 0.0f;
    float rhoS = 0.0f;
    /// The loop borders two or more pieces once every cut's band is removed
    /// (SurfaceSegments::loopSeparates).
    bool separates = true;
};

/// A joint candidate found along a branch (kernels/JointDetection.h), kept
/// or not; the report lists them so that thresholds can be checked.
struct JointCandidateInfo {
    std::array<int, 3> voxel{};
    JointKind kind = JointKind::Narrowing;
    JointStatus status = JointStatus::BelowThreshold;
    double ratio = 1.0;
    double angleDegrees = 0.0;
    double radius = 0.0;
    float sigma = -1.0f;
};

struct ObjectSegmentation {
    std::uint64_t voxelCount = 0;
    std::uint64_t boundaryArea = 0;
    std::uint64_t boundaryComponents = 0;
    /// Cavities filled before the skeleton was computed, and their voxels
    /// (kernels/Cavities.h): background in the input, unlabelled.
    std::uint64_t cavities = 0, cavityVoxels = 0;
    /// Voxels set to close tunnels one voxel wide (kernels/NarrowTunnels.h)
    /// and to plug those two voxels wide (kernels/TunnelPlugs.h): background
    /// in the input, unlabelled.
    std::uint64_t tunnelVoxels = 0;
    /// Total genus of the object's boundary surfaces (kernels/VoxelGenus.h).
    std::int64_t genus = 0;
    std::array<int, 3> bboxMin{}, bboxMax{};
    double tauArea = 0.0;
    double noiseArea = 0.0;
    CandidateStats candidateStats;
    SkeletonMeasureStats measureStats;
    SkeletonBandStats bandStats;                 // exhaustive: every candidate measured
    std::uint64_t curveSkeletonPoints = 0;       // |C|
    std::uint64_t simplifiedSkeletonPoints = 0;  // |C_tau|
    std::uint64_t junctionVoxels = 0;            // |J_tau|
    std::uint64_t handlePoints = 0;
    std::uint32_t skeletonBridges = 0;
    std::uint32_t skeletonBridgesAlongObject = 0;
    std::vector<SkeletonVertex> skeleton;
    std::vector<std::array<std::uint32_t, 2>> skeletonEdges;
    std::vector<JunctionInfo> junctions;
    std::vector<CriticalPointInfo> criticalPoints;
    /// Cut loops as ordered voxel polylines (closed where a second arc was found).
    std::vector<std::vector<std::array<int, 3>>> cutLoops;
    std::vector<CutInfo> cuts;  // one per cut loop
    std::vector<JointCandidateInfo> jointCandidates;
    std::vector<std::uint16_t> labels;  // global labels of this object's segments
    /// The pieces the cuts left before the small-segment merge (top level).
    std::vector<SegmentMeasure> segmentsBeforeMerge;
    /// Hierarchy runs: the object at each level of SegmentationResult::
    /// finerLevels, finest first.
    std::vector<ObjectLevel> finerLevels;
    /// Level k's cut loops and tau area (k past finerLevels: the top level's).
    const std::vector<std::vector<std::array<int, 3>>>& levelCutLoops(std::size_t k) const {
        return k < finerLevels.size() ? finerLevels[k].cutLoops : cutLoops;
    }
    double levelTauArea(std::size_t k) const {
        return k < finerLevels.size() ? finerLevels[k].tauArea : tauArea;
    }
};

struct SegmentInfo {
    std::uint16_t label = 0;
    std::uint32_t object = 0;
    std::uint64_t voxelCount = 0;
    std::uint64_t boundaryArea = 0;
};

/// Objects too small to be parts (kernels/Islands.h): not segmented, label 0.
struct IslandSummary {
    std::uint64_t count = 0;
    std::uint64_t voxels = 0;
    double noiseArea = 0.0;  // the island threshold: the largest object's noise area
    /// Objects broken off a mesh piece too small to be a part of it
    /// (kernels/Islands.h, findFragments): treated as islands, counted here.
    std::uint64_t fragments = 0;
    std::uint64_t fragmentVoxels = 0;
};

/// A level of a hierarchy run other than the top-level one: its labels nest
/// in the next coarser level's (every segment inside exactly one coarser
/// segment).
struct SegmentationLevel {
    /// The joint level's tau is the finest junction-rule level's.
    TauSpec tau;
    bool joints = false;                // the joint level (--joints), the finest
    LabelVolume labels;                 // same grid and geometry as the input
    std::vector<SegmentInfo> segments;  // by label
    /// By label - 1: the label of the segment at the next coarser level
    /// that holds this one; empty at the coarsest level.
    std::vector<std::uint16_t> parentLabel;
    LevelSeconds seconds;
    std::uint64_t nestingMovedNodes = 0;  // boundary nodes the nesting repair moved
};

struct SegmentationResult {
    LabelVolume labels;  // same grid and geometry as the input
    /// Hierarchy runs: the levels below the top-level result, finest first;
    /// `labels` and `segments` are the coarsest level's.
    std::vector<SegmentationLevel> finerLevels;
    /// false for --joints with a single tau: the top-level fields are then
    /// the joint level labelled as a run without levels labels it (before
    /// the nesting repair), and finerLevels holds every level of the
    /// hierarchy, the joint level (nested) first and the junction-rule level
    /// last (docs/outputs.md).
    bool topIsCoarsestLevel = true;
    LevelSeconds coarsestLevelSeconds;  // the top-level result's per-level stages
    TauSpec tau;                        // the top-level result's tau

    /// The levels of the hierarchy, finest first: 1 without levels.
    std::size_t levelCount() const { return finerLevels.size() + (topIsCoarsestLevel ? 1 : 0); }
    bool isCoarsestLevel(std::size_t k) const { return k + 1 == levelCount(); }
    /// Level k's data; the coarsest is the top-level result unless
    /// topIsCoarsestLevel is false.
    const TauSpec& levelTau(std::size_t k) const {
        return k < finerLevels.size() ? finerLevels[k].tau : tau;
    }
    const LabelVolume& levelLabels(std::size_t k) const {
        return k < finerLevels.size() ? finerLevels[k].labels : labels;
    }
    const std::vector<SegmentInfo>& levelSegments(std::size_t k) const {
        return k < finerLevels.size() ? finerLevels[k].segments : segments;
    }
    const LevelSeconds& levelSeconds(std::size_t k) const {
        return k < finerLevels.size() ? finerLevels[k].seconds : coarsestLevelSeconds;
    }
    bool levelIsJoints(std::size_t k) const {
        return k < finerLevels.size() && finerLevels[k].joints;
    }
    /// The label at level k + 1 of level k's segment `label`; 0 at the coarsest.
    std::uint16_t parentLabel(std::size_t k, std::uint32_t label) const {
        return isCoarsestLevel(k) ? 0 : finerLevels[k].parentLabel[label - 1u];
    }
    std::vector<ObjectSegmentation> objects;  // islands excluded
    IslandSummary islands;
    std::vector<SegmentInfo> segments;  // by label
    std::vector<std::string> warnings;
};

/// Rough peak memory of segmentVolume() on a grid of `dims` with
/// `objectVoxels` object voxels, bytes (for --max-memory checks).
/// `levels`: the levels of a hierarchy run (each finer one keeps a label
/// volume and its objects' crop labels, about 4 bytes per grid voxel).
/// `boundaryVoxels`: what the caller knows of the boundary graph's size (a
/// volume's boundary voxels, a mesh's axis-projected area in voxels); the
/// estimate takes at least that many nodes. Without it a sixth of the
/// object voxels is assumed, which a plate a few voxels thick or a noisy
/// volume (every voxel on the boundary) exceeds several times over.
std::uint64_t estimateSegmentationMemory(const Dims& dims, std::uint64_t objectVoxels, int threads,
                                         int levels = 1, std::uint64_t boundaryVoxels = 0);

SegmentationResult segmentVolume(const MaskVolume& mask, const SegmentationParameters& parameters,
                                 Interrupter& interrupter = nullInterrupter(),
                                 StageTimer* timer = nullptr);

}  // namespace skelseg
