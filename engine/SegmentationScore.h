// skelseg: comparing mesh segmentations (Princeton benchmark measures).
//
// Measures of Chen, Golovinskiy, Funkhouser, "A Benchmark for 3D Mesh
// Segmentation", SIGGRAPH 2009, between a candidate segmentation S1 and a
// reference S2 (a human one), both given as one label per face. All are in
// [0, 1], 0 = identical partitions, and do not depend on the label values.
//
// Rand Index error: 1 - RI, the fraction of face pairs on which the two
//   segmentations disagree (same segment in one, different in the other).
//   Computed from the contingency table in linear time:
//   error = (sum_i C(a_i,2) + sum_j C(b_j,2) - 2 sum_ij C(n_ij,2)) / C(N,2).
// Hamming distance: directional D_H(S1 => S2) = sum over segments R2 of S2 of
//   |R2 \ R1*|, R1* the segment of S1 overlapping R2 most. As in the
//   benchmark's code (and its paper, with S2 the ground truth):
//     missingRate    Rm = D_H(candidate => reference) / |S|
//     falseAlarmRate Rf = D_H(reference => candidate) / |S|
//     hammingDistance   = (Rm + Rf) / 2.
//   Mind the names: over-segmenting raises Rm (every reference segment is
//   split, so its best candidate match misses most of it); under-segmenting
//   raises Rf. Baselines: one segment for the whole mesh has Rm = 0 and
//   Rf = 1 - (largest reference segment)/|S|; every face its own segment has
//   Rm = 1 - (segments)/|S| (about 1) and Rf = 0.
//
// Weights: every face counts once, or with its area (pass faceAreas). With
// weights w, |R| is the summed weight and C(n,2) becomes the weight of the
// pairs inside a set, ((sum w)^2 - sum w^2) / 2, which is C(n,2) for w = 1.
// The Princeton benchmark's own code counts faces for the Rand Index and
// weights by area for the Hamming distance; ScoreWeighting::Benchmark does the
// same so that scores compare with the published numbers (and is what
// `skelseg score` uses).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace skelseg {

struct PartitionScore {
    double randIndexError = 0.0;
    double hammingDistance = 0.0;
    double missingRate = 0.0;
    double falseAlarmRate = 0.0;
};

enum class ScoreWeighting {
    Faces,     ///< every face counts once in every measure
    Areas,     ///< every face counts with its area in every measure
    Benchmark  ///< as the Princeton benchmark: Rand Index by faces, Hamming by area
};

/// Compares two segmentations of the same mesh (one label per face, any
/// integers). faceAreas: null = every face counts once; otherwise one
/// non-negative weight per face, used as `weighting` says.
/// @throw UsageError when the sizes differ, there are no faces, a weight is
/// negative or not finite, or all weights are zero.
PartitionScore comparePartitions(const std::vector<std::int64_t>& candidate,
                                 const std::vector<std::int64_t>& reference,
                                 const std::vector<double>* faceAreas = nullptr,
                                 ScoreWeighting weighting = ScoreWeighting::Areas);

struct ScoreSummary {
    /// One score per human segmentation, in the order given.
    std::vector<PartitionScore> perHuman;
    /// Mean of each measure over perHuman (the benchmark's per-model score).
    PartitionScore mean;
};

/// Scores a candidate against every human segmentation of the mesh and
/// averages. Defaults to the benchmark's convention (needs faceAreas; without
/// them every face counts once).
/// @throw UsageError as comparePartitions, or when `humans` is empty.
ScoreSummary scoreAgainstHumans(const std::vector<std::int64_t>& candidate,
                                const std::vector<std::vector<std::int64_t>>& humans,
                                const std::vector<double>* faceAreas,
                                ScoreWeighting weighting = ScoreWeighting::Benchmark);

}  // namespace skelseg
