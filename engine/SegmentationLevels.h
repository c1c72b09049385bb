// skelseg: the finer levels of a hierarchy run (--tau 1%,3%,9%).
//
// tau only thresholds measures that do not depend on it, so the stages up to
// the measures run once per object (SegmentationStages.h) and only the
// tau-dependent stages run per level, coarsest first:
//   placeFinerLevelCuts  skeleton graph C_tau and cut placement per finer
//                        level, on a copy of the shared points whose
//                        junction test is re-decided at the level's tau
//                        (SkeletonPoint::junctionArea); a level's cut set is
//                        its own cuts plus every coarser level's; with
//                        --joints the joint level's cut set is the finest
//                        level's plus the joint cuts on its skeleton
//   labelFinerLevels     labelling with that cut set, the nesting repair
//                        (kernels/SegmentNesting.h) against the next coarser
//                        level, and interior labels
// The shared measures are taken at the coarsest tau (the growth cap decides
// every smaller tau exactly) with sigma down to the finest; so the coarsest
// level is the run with that tau alone, byte for byte. A level whose noise
// area differs from the coarsest's (tau below noiseAreaFraction of the
// boundary area) is measured again on its own. Why and how the levels nest:
// docs/algorithm.md "Levels".
#pragma once

#include <chrono>

#include "engine/SegmentationStages.h"

namespace skelseg {

/// Skeleton graph and cuts of every finer junction-rule level, from the
/// coarsest finer level down, and with --joints the joint level's below
/// the finest (placeJointLevelCuts); fills each ObjectLevelWork's cutLoops
/// and the object's out.finerLevels cut polylines. Needs the skeleton data
/// (before it is released) and the coarsest level's cuts.
void placeFinerLevelCuts(ObjectState& state);

/// The joint level of a list (--joints --tau 1%,3%): the finest level's cut
/// set (state.cutLoops, on its skeleton) plus the joint cuts found on that
/// skeleton, away from its own cuts and from the skeleton nodes at
/// `coarserCutVoxels` (crop voxels of the coarser levels' cut points).
/// Leaves state.cutLoops and the reported cuts as it found them.
void placeJointLevelCuts(ObjectState& state, const std::vector<std::uint32_t>& coarserCutVoxels);

/// --joints with a single tau: the top-level cuts (the junction rule's, then
/// the joint cuts) are the joint level's; the junction rule's alone are the
/// junction-rule level's.
void splitSingleTauJointLevels(ObjectState& state);

/// Surface segments, nesting and interior labels of every level below the
/// top, from the coarsest down; needs the top level's segments. The joint
/// level's smallest segment is a fraction of tau (as labelObjectSurface's
/// with one tau, whose labelling it then reuses before the nesting).
void labelFinerLevels(ObjectState& state);

/// Adds the wall and CPU time of its scope to a LevelSeconds.
class LevelClock {
public:
    explicit LevelClock(LevelSeconds& seconds);
    ~LevelClock();
    LevelClock(const LevelClock&) = delete;
    LevelClock& operator=(const LevelClock&) = delete;

private:
    LevelSeconds& mSeconds;
    std::chrono::steady_clock::time_point mStart;
    double mCpuStart;
};

}  // namespace skelseg
