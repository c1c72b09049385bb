#include "kernels/JointDetection.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace skelseg {

namespace {

constexpr double kPi = 3.14159265358979323846;

double radiusOf(double rhoS) {
    return std::max(loopRadius(rhoS), 0.5);
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

std::array<double, 3> position(const Coord& c) {
    return {double(c.x), double(c.y), double(c.z)};
}

/// Index of the sample whose arc length is closest to `arc`.
std::size_t sampleAt(const std::vector<double>& arcs, double arc) {
    const auto it = std::lower_bound(arcs.begin(), arcs.end(), arc);
    if (it == arcs.end()) return arcs.size() - 1;
    const std::size_t i = std::size_t(it - arcs.begin());
    if (i > 0 && arc - arcs[i - 1] < arcs[i] - arc) return i - 1;
    return i;
}

/// Distances inside one branch from `source` (Dijkstra over Euclidean steps).
/// Ties are settled by node id, so the result does not depend on memory order.
void branchDistances(const SkeletonGraph& g, const std::vector<std::uint32_t>& nodeBranch,
                     std::uint32_t branch, std::uint32_t source, std::vector<double>& dist) {
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    dist[source] = 0.0;
    heap.push({0.0, source});
    while (!heap.empty()) {
        const auto [d, n] = heap.top();
        heap.pop();
        if (d > dist[n]) continue;
        for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
            const std::uint32_t m = g.neighbour[e];
            if (nodeBranch[m] != branch) continue;
            const double nd = d + distance(position(g.coord[n]), position(g.coord[m]));
            if (nd < dist[m]) dist[m] = nd, heap.push({nd, m});
        }
    }
}

double median(std::vector<double>& values) {
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(mid), values.end());
    double m = values[mid];
    if (values.size() % 2 == 0) {
        const double lower =
            *std::max_element(values.begin(), values.begin() + std::ptrdiff_t(mid));
        m = 0.5 * (m + lower);
    }
    return m;
}

}  // namespace

BranchProfile smoothProfile(const BranchProfile& profile, const JointOptions& options) {
    const std::size_t count = profile.arc.size();
    BranchProfile out = profile;
    for (std::size_t i = 0; i < count; ++i) {
        const double width = std::max(options.smoothingScale * radiusOf(profile.rhoS[i]), 1.0);
        double weightSum = 0.0, rho = 0.0;
        std::array<double, 3> p{0, 0, 0};
        const std::size_t first = sampleAt(profile.arc, profile.arc[i] - 3.0 * width);
        for (std::size_t j = first; j < count && profile.arc[j] <= profile.arc[i] + 3.0 * width;
             ++j) {
            const double t = (profile.arc[j] - profile.arc[i]) / width;
            if (std::fabs(t) > 3.0) continue;
            const double w = std::exp(-0.5 * t * t);
            weightSum += w;
            rho += w * profile.rhoS[j];
            for (int k = 0; k < 3; ++k)
                p[std::size_t(k)] += w * profile.position[j][std::size_t(k)];
        }
        out.rhoS[i] = rho / weightSum;
        for (int k = 0; k < 3; ++k) out.position[i][std::size_t(k)] = p[std::size_t(k)] / weightSum;
    }
    return out;
}

std::vector<ProfileJoint> findProfileJoints(const BranchProfile& profile,
                                            const JointOptions& options) {
    std::vector<ProfileJoint> joints;
    const std::size_t count = profile.arc.size();
    if (count < 3) return joints;
    const BranchProfile smooth = smoothProfile(profile, options);
    const std::vector<double>& rho = smooth.rhoS;

    // Turning angle per sample; -1 where the window does not fit.
    std::vector<double> angle(count, -1.0);
    for (std::size_t i = 0; i < count; ++i) {
        const double window = options.bendWindow * radiusOf(rho[i]);
        const double s = profile.arc[i];
        if (s - window < profile.arc.front() || s + window > profile.arc.back()) continue;
        const auto& before = smooth.position[sampleAt(profile.arc, s - window)];
        const auto& here = smooth.position[i];
        const auto& after = smooth.position[sampleAt(profile.arc, s + window)];
        std::array<double, 3> u{}, v{};
        for (std::size_t k = 0; k < 3; ++k) u[k] = here[k] - before[k], v[k] = after[k] - here[k];
        const double nu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        const double nv = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (nu <= 0.0 || nv <= 0.0) continue;
        const double c = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (nu * nv);
        angle[i] = std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi;
    }

    for (std::size_t i = 1; i + 1 < count; ++i) {
        const double radius = radiusOf(rho[i]);
        // Narrowing: the first sample of a minimum (plateaus count once).
        if (rho[i] < rho[i - 1] && rho[i] <= rho[i + 1]) {
            const double s = profile.arc[i], window = options.sideWindow * radius;
            double leftMax = 0.0, rightMax = 0.0;
            std::size_t leftAt = i, rightAt = i;
            for (std::size_t j = 0; j < count; ++j) {
                if (profile.arc[j] < s - window || profile.arc[j] > s + window) continue;
                if (j < i && rho[j] > leftMax) leftMax = rho[j], leftAt = j;
                if (j > i && rho[j] > rightMax) rightMax = rho[j], rightAt = j;
            }
            // The ratio's reference on each side is the limb's typical
            // thickness there (the median within sideMedianWindow * r), not
            // its widest point: the widest point next to a joint is where a
            // neighbouring joint bends or an end part (a foot, a hand) is not
            // resolved, and both move with the pose (docs/algorithm.md §14.5).
            const double medianWindow = options.sideMedianWindow * radius;
            std::vector<double> left, right;
            for (std::size_t j = 0; j < count; ++j) {
                if (j < i && profile.arc[j] >= s - medianWindow) left.push_back(rho[j]);
                if (j > i && profile.arc[j] <= s + medianWindow) right.push_back(rho[j]);
            }
            if (left.empty() || right.empty()) continue;
            const double ratio = rho[i] / std::max(std::min(median(left), median(right)), 1e-9);
            if (ratio <= options.reportRatio) {
                ProfileJoint joint;
                joint.kind = JointKind::Narrowing;
                joint.sample = i;
                joint.ratio = ratio;
                joint.radius = radius;
                joint.wideBefore = leftAt;
                joint.wideAfter = rightAt;
                const double side = options.minSideLength * radius;
                joint.passes = ratio <= options.narrowingRatio && s - profile.arc.front() >= side &&
                               profile.arc.back() - s >= side;
                joints.push_back(joint);
            }
        }
        // Bend: the first sample of a maximum of the turning angle.
        if (angle[i] >= 0.0 && angle[i] > angle[i - 1] && angle[i] >= angle[i + 1] &&
            angle[i] >= options.reportAngleDegrees) {
            ProfileJoint joint;
            joint.kind = JointKind::Bend;
            joint.sample = i;
            joint.angleDegrees = angle[i];
            joint.radius = radius;
            joint.passes = angle[i] >= options.bendAngleDegrees;
            joints.push_back(joint);
        }
    }
    return joints;
}

std::vector<std::uint32_t> jointBranches(const SkeletonGraph& g, std::uint32_t& branchCount) {
    // Union-find over pieces, joined through two-branch junctions.
    std::vector<std::uint32_t> parent(g.pieceCount);
    for (std::uint32_t p = 0; p < g.pieceCount; ++p) parent[p] = p;
    const auto find = [&](std::uint32_t p) {
        while (parent[p] != p) p = parent[p] = parent[parent[p]];
        return p;
    };
    std::vector<std::uint32_t> throughPiece(g.junctions.size(), kNoJunction);
    for (std::uint32_t j = 0; j < g.junctions.size(); ++j) {
        const std::vector<std::uint32_t> pieces = junctionBranches(g, j);
        if (pieces.size() != 2) continue;
        const std::uint32_t a = find(pieces[0]), b = find(pieces[1]);
        if (a == b) continue;  // the two ends of one loop: not a limb
        parent[std::max(a, b)] = std::min(a, b);
        throughPiece[j] = pieces[0];
    }
    // Branch ids in order of their smallest piece.
    std::vector<std::uint32_t> id(g.pieceCount, kNoJunction);
    branchCount = 0;
    for (std::uint32_t p = 0; p < g.pieceCount; ++p)
        if (find(p) == p) id[p] = branchCount++;
    std::vector<std::uint32_t> nodeBranch(g.nodeCount(), kNoJunction);
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
        if (g.pieceOf[n] != kNoJunction)
            nodeBranch[n] = id[find(g.pieceOf[n])];
        else if (g.junctionOf[n] != kNoJunction && throughPiece[g.junctionOf[n]] != kNoJunction)
            nodeBranch[n] = id[find(throughPiece[g.junctionOf[n]])];
    }
    return nodeBranch;
}

BranchProfile branchProfile(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                            const std::vector<std::uint32_t>& nodeBranch, std::uint32_t branch,
                            std::vector<double>* nodeArc) {
    BranchProfile profile;
    std::vector<std::uint32_t> nodes;
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
        if (nodeBranch[n] == branch) nodes.push_back(n);
    if (nodeArc) nodeArc->assign(g.nodeCount(), -1.0);
    if (nodes.empty()) return profile;
    // One end of the branch: the node farthest from its first node; the arc
    // length of every node is its distance from that end.
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> dist(g.nodeCount(), inf);
    branchDistances(g, nodeBranch, branch, nodes.front(), dist);
    std::uint32_t end = nodes.front();
    for (std::uint32_t n : nodes)
        if (dist[n] != inf && dist[n] > dist[end]) end = n;
    for (std::uint32_t n : nodes) dist[n] = inf;
    branchDistances(g, nodeBranch, branch, end, dist);

    // Bins of one voxel of arc length (a node not reached cannot occur in a
    // connected branch; it would be left out).
    double maxArc = 0.0;
    for (std::uint32_t n : nodes)
        if (dist[n] != inf) maxArc = std::max(maxArc, dist[n]);
    const std::size_t binCount = std::size_t(maxArc) + 1;
    std::vector<std::vector<std::uint32_t>> bins(binCount);
    for (std::uint32_t n : nodes)
        if (dist[n] != inf) bins[std::size_t(dist[n])].push_back(n);
    std::vector<double> values;
    for (const auto& bin : bins) {
        if (bin.empty()) continue;
        double arc = 0.0;
        std::array<double, 3> p{0, 0, 0};
        values.clear();
        for (std::uint32_t n : bin) {
            arc += dist[n];
            const auto q = position(g.coord[n]);
            for (std::size_t k = 0; k < 3; ++k) p[k] += q[k];
            values.push_back(double(points[g.point[n]].rhoS));
        }
        const double size = double(bin.size());
        profile.arc.push_back(arc / size);
        profile.rhoS.push_back(median(values));
        profile.position.push_back({p[0] / size, p[1] / size, p[2] / size});
    }
    if (nodeArc)
        for (std::uint32_t n : nodes) (*nodeArc)[n] = dist[n] == inf ? -1.0 : dist[n];
    return profile;
}

std::vector<JointCandidate> detectJoints(const SkeletonGraph& g,
                                         const std::vector<SkeletonPoint>& points,
                                         const std::vector<std::uint32_t>& existingCuts,
                                         const JointOptions& options, Interrupter& interrupter) {
    std::vector<JointCandidate> candidates;
    std::uint32_t branchCount = 0;
    const std::vector<std::uint32_t> nodeBranch = jointBranches(g, branchCount);
    std::vector<std::vector<std::uint32_t>> branchNodes(branchCount);
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
        if (nodeBranch[n] != kNoJunction) branchNodes[nodeBranch[n]].push_back(n);
    std::vector<double> nodeArc, arcOfNode(g.nodeCount(), -1.0);
    for (std::uint32_t branch = 0; branch < branchCount; ++branch) {
        throwIfInterrupted(interrupter, double(branch) / double(branchCount));
        const BranchProfile profile = branchProfile(g, points, nodeBranch, branch, &nodeArc);
        for (std::uint32_t n : branchNodes[branch]) arcOfNode[n] = nodeArc[n];
        for (const ProfileJoint& joint : findProfileJoints(profile, options)) {
            JointCandidate c;
            c.kind = joint.kind;
            c.branch = branch;
            c.arc = profile.arc[joint.sample];
            c.wideBeforeArc = profile.arc[joint.wideBefore];
            c.wideAfterArc = profile.arc[joint.wideAfter];
            c.ratio = joint.ratio;
            c.angleDegrees = joint.angleDegrees;
            c.radius = joint.radius;
            // The smoothest loop near the extremum: best sigma, ties by node id.
            const double reach = std::max(options.snapDistance * joint.radius, 1.0);
            std::uint32_t best = kNoJunction, nearest = kNoJunction;
            double nearestGap = std::numeric_limits<double>::infinity();
            for (std::uint32_t n : branchNodes[branch]) {
                const double gap = std::fabs(nodeArc[n] - c.arc);
                if (nodeArc[n] < 0.0) continue;
                if (gap < nearestGap) nearestGap = gap, nearest = n;
                if (gap > reach) continue;
                if (best == kNoJunction || points[g.point[n]].sigma > points[g.point[best]].sigma)
                    best = n;
            }
            c.node = best != kNoJunction ? best : nearest;
            c.sigma = points[g.point[c.node]].sigma;
            if (!joint.passes)
                c.status = JointStatus::BelowThreshold;
            else if (points[g.point[c.node]].isHandle)
                c.status = JointStatus::Handle;
            else if (double(c.sigma) < options.sigmaMin)
                c.status = JointStatus::LowSigma;
            else
                c.status = JointStatus::Cut;  // provisional: the distance rule follows
            candidates.push_back(c);
        }
    }

    // Distance rule: narrowings first (deepest first), then bends (sharpest
    // first); ties by node id.
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < candidates.size(); ++i)
        if (candidates[i].status == JointStatus::Cut) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const JointCandidate &x = candidates[a], &y = candidates[b];
        if (x.kind != y.kind) return x.kind == JointKind::Narrowing;
        const double sx = x.kind == JointKind::Narrowing ? x.ratio : -x.angleDegrees;
        const double sy = y.kind == JointKind::Narrowing ? y.ratio : -y.angleDegrees;
        if (sx != sy) return sx < sy;
        return x.node < y.node;
    });
    std::vector<std::uint32_t> kept = existingCuts;
    for (std::size_t i : order) {
        JointCandidate& c = candidates[i];
        const auto here = position(g.coord[c.node]);
        bool near = false;
        for (std::uint32_t k : kept) {
            near = near || distance(here, position(g.coord[k])) < options.minCutDistance * c.radius;
            // A cut on the branch between the two wider stretches already
            // parts them: this narrowing adds only a sliver.
            if (c.kind == JointKind::Narrowing && nodeBranch[k] == c.branch &&
                arcOfNode[k] >= std::min(c.wideBeforeArc, c.wideAfterArc) &&
                arcOfNode[k] <= std::max(c.wideBeforeArc, c.wideAfterArc))
                near = true;
        }
        if (near) {
            c.status = JointStatus::NearCut;
        } else {
            kept.push_back(c.node);
        }
    }
    return candidates;
}

}  // namespace skelseg
