#include "engine/SegmentViews.h"

#include <tbb/parallel_invoke.h>

#include "io/render/GltfWriter.h"
#include "io/render/SegmentMeshes.h"
#include "io/render/ViewerWriter.h"

namespace skelseg {

void writeSegmentViews(OutputDirectory& out, const SegmentViewInputs& inputs) {
    const auto writeGlb = [&] {
        GltfScene scene;
        scene.segments =
            splitSegmentMeshes(*inputs.vertices, *inputs.triangles, *inputs.triangleLabels);
        for (const auto& p : *inputs.skeletonPoints) scene.skeletonPoints.push_back(p.position);
        scene.skeletonEdges = *inputs.skeletonEdges;
        scene.cutLoops = *inputs.cutLoops;
        writeSegmentsGlb(out.stagingPath("segments.glb"), scene);
    };
    const auto writeViewer = [&] {
        ViewerScene scene;
        scene.title = inputs.title;
        scene.facts = inputs.facts;
        scene.vertices = *inputs.vertices;
        scene.triangles = *inputs.triangles;
        scene.skeletonPoints = *inputs.skeletonPoints;
        scene.skeletonEdges = *inputs.skeletonEdges;
        const SegmentationResult& result = *inputs.result;
        if (inputs.levelTriangleLabels.empty()) {
            ViewerLevel level;
            level.tau = inputs.tau;
            level.triangleLabels = *inputs.triangleLabels;
            for (const SegmentInfo& s : result.segments)
                level.segments.push_back({s.label, s.voxelCount, 0});
            level.cutLoops = *inputs.cutLoops;
            scene.levels.push_back(std::move(level));
        } else {
            for (std::size_t k = 0; k < inputs.levelTriangleLabels.size(); ++k) {
                ViewerLevel level;
                level.tau = result.isCoarsestLevel(k) && result.topIsCoarsestLevel
                                ? inputs.tau
                                : result.levelTau(k).toString();
                if (result.levelIsJoints(k)) level.tau += " + joints";
                level.triangleLabels = inputs.levelTriangleLabels[k];
                for (const SegmentInfo& s : result.levelSegments(k))
                    level.segments.push_back(
                        {s.label, s.voxelCount, std::uint32_t(result.parentLabel(k, s.label))});
                level.cutLoops = (*inputs.levelCutLoops)[k];
                scene.levels.push_back(std::move(level));
            }
            // --joints with one tau: open at the joint level, the top-level files'.
            if (!result.topIsCoarsestLevel) scene.openLevel = 0;
        }
        writeViewerHtml(out.stagingPath("viewer.html"), scene);
    };
    tbb::parallel_invoke(writeGlb, writeViewer);
}

}  // namespace skelseg
