#include "engine/SequenceCommand.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/SegmentInput.h"
#include "engine/SequenceConsensus.h"
#include "engine/batch/Manifest.h"
#include "io/files/OutputDirectory.h"
#include "io/files/ReplacedOutputs.h"
#include "io/files/TextFile.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/SegFile.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace fs = std::filesystem;

const OutputLayout& sequenceOutputLayout() {
    static const OutputLayout layout = [] {
        auto frames = std::make_shared<OutputLayout>();
        const auto isFrameName = [](const std::string& name) {
            return name.find_first_not_of('.') != std::string::npos;
        };
        frames->folders.push_back(
            {"", isFrameName, std::make_shared<OutputLayout>(segmentOutputLayout())});
        OutputLayout top{"segmentation.seg", "sequence.json"};
        top.folders.push_back({"frames", {}, frames});
        return top;
    }();
    return layout;
}

const std::vector<std::string>& sequenceOutputNames() {
    static const std::vector<std::string> names = sequenceOutputLayout().names();
    return names;
}

namespace {

/// Whether the file's faces name their vertices (every format but STL,
/// whose facets carry their corners' positions).
bool hasSharedVertices(const fs::path& frame) {
    return meshFormatFromPath(frame) != MeshFormat::Stl;
}

/// The frames' names (their stems, told apart by their folders as a batch
/// tells its inputs apart) and the check that they share their faces: the
/// consensus labels faces, so it means something only where every frame has
/// the same faces in the same order.
std::vector<std::string> checkFrames(const SequenceCommandOptions& options) {
    if (options.frames.size() < 2)
        throw UsageError("sequence: give at least two frames of one mesh (got " +
                         std::to_string(options.frames.size()) + ")");
    std::vector<fs::path> absolutePaths;
    ReplacedOutputs replaced;
    replaced.add(options.outdir, sequenceOutputNames());
    for (const fs::path& frame : options.frames) {
        // A folder first: "in/" was told it is not a mesh format.
        std::error_code ec;
        if (fs::is_directory(frame, ec))
            throw InputError(frame.string(), "is a directory, not a file");
        try {
            meshFormatFromPath(frame);
        } catch (const Error&) {  // what is not a mesh: the format of an unknown extension
            throw UsageError(frame.string() +
                             ": the frames of a sequence are meshes (.off, .obj, .stl or .ply) "
                             "that share their faces");
        }
        const std::string name = frame.stem().string();
        // "..off" has the stem ".", "...off" "..": frames/NAME would be the
        // frames folder itself or OUTDIR's staging folder, whose outputs the
        // frame's would replace.
        if (name.find_first_not_of('.') == std::string::npos)
            throw UsageError(frame.string() + ": the frame's name has nothing but dots before " +
                             frame.extension().string() +
                             ", so its outputs would have no folder of their own (frames/" + name +
                             "); rename the file");
        std::string output = outputReplacing(frame, options.outdir, sequenceOutputNames());
        // Another name of an output (a hard link, OUTDIR through a bind mount).
        if (const ReplacedOutputs::Entry* entry = output.empty() ? replaced.find(frame) : nullptr)
            output = entry->output;
        if (!output.empty())
            throw UsageError(frame.string() + ": the frame lies in the output directory's " +
                             output + " and would be replaced; choose another output directory");
        // The same file twice (f.off and ./f.off, a link to it) would vote
        // twice in the consensus; it was refused as two frames of one name.
        for (std::size_t earlier = 0; earlier < absolutePaths.size(); ++earlier)
            if (fs::equivalent(options.frames[earlier], frame, ec))
                throw UsageError(frame.string() + ": is frame " + std::to_string(earlier + 1) +
                                 " again (" + options.frames[earlier].string() +
                                 "); give each frame once");
        std::error_code absoluteError;
        const fs::path absolute = fs::absolute(frame, absoluteError);
        absolutePaths.push_back(absoluteError ? frame : absolute.lexically_normal());
    }
    // Frames exported one per folder share their file name
    // (take_001/mesh.obj, take_002/mesh.obj): they were refused as two frames
    // of one name, and now get the folder in front that tells them apart.
    const std::vector<std::string> names = uniqueOutputNames(absolutePaths);
    // STL has no shared vertices: the reader makes one vertex of the corners
    // at one position, so corners that touch in one pose only (hands
    // together) are one vertex in that frame alone and its triangle list is
    // not the others'. An STL frame's faces are its facets in file order:
    // their count and corners are compared, vertex indices only between
    // frames whose files have them. Nothing downstream depends on which
    // corners a file shares (the mesh checks, the genus and the contacts
    // count corners at one position as one vertex in every format:
    // canonicalVertices, io/mesh/MeshCheck.h), so each frame is segmented as
    // `segment` reads it.
    const TriangleMesh first = readMesh(options.frames.front());
    // The first frame with shared vertices, which the others with them match.
    std::optional<TriangleMesh> laterIndexed;
    const TriangleMesh* indexed = hasSharedVertices(options.frames.front()) ? &first : nullptr;
    std::size_t indexedFrame = 0;
    for (std::size_t f = 1; f < options.frames.size(); ++f) {
        TriangleMesh mesh = readMesh(options.frames[f]);
        if (mesh.faceCount != first.faceCount)
            throw InputError(options.frames[f].string(),
                             "has " + std::to_string(mesh.faceCount) + " faces, " +
                                 options.frames.front().string() + " has " +
                                 std::to_string(first.faceCount) +
                                 "; the frames of a sequence share their faces");
        std::size_t reference = 0;
        bool differ = mesh.triangleFace != first.triangleFace;
        if (!differ && indexed && hasSharedVertices(options.frames[f])) {
            reference = indexedFrame;
            differ = mesh.triangles != indexed->triangles;
        }
        if (differ)
            throw InputError(options.frames[f].string(),
                             "its faces differ from those of " +
                                 options.frames[reference].string() +
                                 "; the frames of a sequence share their faces (same faces in "
                                 "the same order)");
        if (!indexed && hasSharedVertices(options.frames[f])) {
            laterIndexed = std::move(mesh);
            indexed = &*laterIndexed;
            indexedFrame = f;
        }
    }
    return names;
}

/// How many handles more than its mesh the voxel model of a frame has, as
/// handlesTheMeshLacks() decided it in the frame's run (read back from its
/// report.json).
std::int64_t handlesBeyondTheMesh(const fs::path& report) {
    const nlohmann::json document = nlohmann::json::parse(readFileBytes(report));
    const nlohmann::json& input = document.at("input");
    if (!input.value("mesh_closed", false)) return 0;
    MeshTopology mesh;
    mesh.genus = input.at("mesh_genus").get<std::int64_t>();
    mesh.otherPieces = input.value("mesh_pieces_without_genus", std::size_t(0));
    VoxelTopology voxels;
    voxels.genus = input.at("voxel_genus").get<std::int64_t>();
    return handlesTheMeshLacks(true, mesh, voxels);
}

}  // namespace

void runSequenceCommand(const SequenceCommandOptions& options, ProgressReporter& progress) {
    const std::vector<std::string> names = checkFrames(options);
    OutputDirectory out(options.outdir, options.segment.force, sequenceOutputLayout());
    try {
        const fs::path staged = out.stagingPath("frames");
        // Named by where the folder ends up: the staging folder is gone when
        // the error is read.
        std::error_code ec;
        fs::create_directories(staged, ec);
        if (ec)
            throw OutputError((options.outdir / "frames").string() +
                              ": cannot create directory: " + describeErrno(ec.value()));

        std::vector<std::vector<std::int64_t>> labels;
        std::vector<std::int64_t> extraHandles;
        for (std::size_t f = 0; f < options.frames.size(); ++f) {
            SegmentCommandOptions frame = options.segment;
            frame.input = options.frames[f];
            frame.outdir = staged / names[f];
            frame.force = false;
            frame.budgetFromProcessStart = options.segment.budgetFromProcessStart && f == 0;
            if (options.announceFrames)
                progress.message("skelseg sequence: frame " + std::to_string(f + 1) + " of " +
                                 std::to_string(options.frames.size()) + ": " +
                                 frame.input.string());
            ProgressReporter frameProgress(options.display, frame.timeLimitSeconds);
            runSegmentCommand(frame, frameProgress);
            labels.push_back(readSeg(frame.outdir / "segmentation.seg"));
            extraHandles.push_back(handlesBeyondTheMesh(frame.outdir / "report.json"));
        }
        std::vector<bool> trusted;
        for (std::int64_t extra : extraHandles) trusted.push_back(extra == 0);
        const SequenceConsensus consensus = chooseSequenceConsensus(labels, trusted);

        const std::vector<std::int64_t>& chosen = labels[consensus.reference];
        writeSeg(out.stagingPath("segmentation.seg"),
                 std::vector<std::uint32_t>(chosen.begin(), chosen.end()));

        nlohmann::json document;
        document["faces"] = chosen.size();
        document["reference_frame"] = consensus.reference;
        document["reference_input"] = options.frames[consensus.reference].string();
        document["modal_parts"] = consensus.modalParts;
        document["mean_rand_index_error"] = consensus.meanPairError;
        document["rule"] =
            "the frame with the least mean Rand Index error to the others, among the frames "
            "with the part count most frames have; frames whose voxel model has handles their "
            "mesh lacks neither vote nor are chosen, unless every frame has such handles";
        nlohmann::json frames = nlohmann::json::array();
        for (std::size_t f = 0; f < options.frames.size(); ++f) {
            nlohmann::json errors = nlohmann::json::array();
            for (std::size_t g = 0; g < options.frames.size(); ++g)
                errors.push_back(consensus.pairErrors[f * options.frames.size() + g]);
            frames.push_back(
                {{"input", options.frames[f].string()},
                 {"outputs", "frames/" + names[f]},
                 {"parts", consensus.parts[f]},
                 {"voxel_handles_beyond_mesh", extraHandles[f]},
                 {"voted", bool(consensus.voted[f])},
                 {"mean_rand_index_error_to_others", consensus.meanErrorToOthers[f]},
                 {"rand_index_error_to_consensus",
                  consensus.pairErrors[f * options.frames.size() + consensus.reference]},
                 {"rand_index_errors", std::move(errors)}});
        }
        document["frames"] = std::move(frames);
        writeFileAtomically(out.stagingPath("sequence.json"), document.dump(2) + "\n");
    } catch (const OutputError& error) {
        // A frame's run names its files in the frames folder being staged.
        throw OutputError(out.withFinalPaths(error.what()));
    }
    out.commit();
}

}  // namespace skelseg
