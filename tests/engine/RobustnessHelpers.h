// Helpers shared by the robustness tests (TestRobustness*.cpp,
// SlowRobustness.cpp): they run the skelseg CLI as a child process on files
// written into a TempDir and check what issue 5 promises.
#pragma once

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/SegmentCommand.h"
#include "io/volume/NrrdIO.h"
#include "kernels/base/Volume.h"
#include "tests/support/CliRunner.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg::test {

/// The smallest closed mesh, a tetrahedron, as OFF text: its vertex and face
/// lines, and the whole file. The input of tests that need any valid mesh,
/// and the file the bad cases damage.
inline const std::string kTetraBody =
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
inline const std::string kTetraOff = "OFF\n4 4 0\n" + kTetraBody;

/// zlib-compresses `bytes` with a gzip wrapper (windowBits 15 + 16).
inline std::string gzipBytes(const std::string& bytes) {
    z_stream stream{};
    if (deflateInit2(&stream, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
    std::string out(deflateBound(&stream, uLong(bytes.size())) + 64, '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = uInt(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = uInt(out.size());
    deflate(&stream, Z_FINISH);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

/// Runs `skelseg segment INPUT -o OUTDIR --quiet EXTRA...`.
inline CliResult runSegment(const std::filesystem::path& input, const std::filesystem::path& outdir,
                            const std::vector<std::string>& extra = {}) {
    std::vector<std::string> arguments = {"segment", input.string(), "-o", outdir.string(),
                                          "--quiet"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return runSkelseg(arguments);
}

/// The contract for every failure: exit code `code`, exactly one line on
/// stderr, which names `mention` (usually the file) and contains `problem`
/// (if not empty), and nothing on stdout.
inline ::testing::AssertionResult failsWithOneLine(const CliResult& result, int code,
                                                   const std::string& mention,
                                                   const std::string& problem = "") {
    if (result.signal != 0)
        return ::testing::AssertionFailure()
               << "killed by signal " << result.signal << ": " << result.describe();
    if (result.exitCode != code)
        return ::testing::AssertionFailure()
               << "expected exit " << code << ", got " << result.describe();
    const auto lines = result.errLines();
    if (lines.size() != 1 || result.err.back() != '\n')
        return ::testing::AssertionFailure() << "expected exactly one line on stderr, got "
                                             << lines.size() << ": " << result.describe();
    if (!mention.empty() && lines[0].find(mention) == std::string::npos)
        return ::testing::AssertionFailure()
               << "the message does not name '" << mention << "': " << lines[0];
    if (!problem.empty() && lines[0].find(problem) == std::string::npos)
        return ::testing::AssertionFailure()
               << "the message does not say '" << problem << "': " << lines[0];
    if (lines[0].rfind("skelseg: ", 0) != 0)
        return ::testing::AssertionFailure()
               << "the message does not start with 'skelseg: ': " << lines[0];
    if (!result.out.empty())
        return ::testing::AssertionFailure() << "unexpected stdout: " << result.out;
    return ::testing::AssertionSuccess();
}

/// Entries of OUTDIR a run may have written: final outputs, the staging
/// directory and temporary files.
inline std::vector<std::string> runOutputsIn(const std::filesystem::path& outdir) {
    std::vector<std::string> found;
    const auto& names = segmentOutputNames();
    for (const auto& entry : directoryEntries(outdir)) {
        const bool output = std::find(names.begin(), names.end(), entry) != names.end();
        const bool staging = entry.rfind(".skelseg-staging", 0) == 0;
        const bool temporary = entry.find(".tmp-") != std::string::npos;
        if (output || staging || temporary) found.push_back(entry);
    }
    return found;
}

/// A failed run leaves no trace: OUTDIR (which did not exist) is not created.
inline ::testing::AssertionResult leftNothing(const std::filesystem::path& outdir) {
    if (!std::filesystem::exists(outdir)) return ::testing::AssertionSuccess();
    std::string entries;
    for (const auto& e : directoryEntries(outdir)) entries += " " + e;
    return ::testing::AssertionFailure() << outdir << " was left behind, holding:" << entries;
}

/// Every file in a directory with its bytes (the staging directory included).
inline std::map<std::string, std::string> snapshot(const std::filesystem::path& directory) {
    std::map<std::string, std::string> files;
    for (const auto& name : directoryEntries(directory)) files[name] = fileBytes(directory / name);
    return files;
}

inline nlohmann::json readReport(const std::filesystem::path& outdir) {
    return nlohmann::json::parse(fileBytes(outdir / "report.json"));
}

/// A mask of `dims` with the voxels `inside(x, y, z)` set; unit voxels.
template <typename Inside>
MaskVolume makeMask(Dims dims, Inside inside) {
    MaskVolume mask(dims);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) mask(x, y, z) = inside(x, y, z) ? 1 : 0;
    return mask;
}

}  // namespace skelseg::test
