#include "tests/support/PoseSequences.h"

#include <algorithm>
#include <cctype>
#include <utility>

#include <gtest/gtest.h>

#include "tests/support/CliRunner.h"

namespace skelseg::test {

namespace fs = std::filesystem;

std::map<std::string, std::vector<fs::path>> poseSequences(const fs::path& poses) {
    std::map<std::string, std::vector<std::pair<long, fs::path>>> frames;
    for (const auto& entry : fs::directory_iterator(poses)) {
        const std::string stem = entry.path().stem().string();
        const auto cut = stem.rfind('_');
        if (cut == std::string::npos || entry.path().extension() != ".obj") continue;
        const std::string frame = stem.substr(cut + 1);
        if (frame.empty() || !std::all_of(frame.begin(), frame.end(), ::isdigit)) continue;
        frames[stem.substr(0, cut)].emplace_back(std::stol(frame), entry.path());
    }
    std::map<std::string, std::vector<fs::path>> sequences;
    for (auto& [name, list] : frames) {
        std::sort(list.begin(), list.end());
        for (const auto& f : list) sequences[name].push_back(f.second);
    }
    return sequences;
}

std::map<std::string, std::vector<fs::path>> segmentPoseFrames(
    const fs::path& poses, const fs::path& outRoot,
    const std::vector<std::string>& extraArguments) {
    std::map<std::string, std::vector<fs::path>> outputs;
    for (const auto& [name, frames] : poseSequences(poses)) {
        for (const auto& frame : frames) {
            const fs::path out = outRoot / frame.stem();
            std::vector<std::string> arguments{"segment",    frame.string(), "-o",
                                               out.string(), "--resolution", "192",
                                               "-q",         "--no-preview"};
            arguments.insert(arguments.end(), extraArguments.begin(), extraArguments.end());
            const CliResult run = runSkelseg(arguments);
            if (run.exitCode != 0) {
                ADD_FAILURE() << frame << ": " << run.describe();
                continue;
            }
            outputs[name].push_back(out);
        }
    }
    return outputs;
}

std::string countList(const std::vector<std::size_t>& counts) {
    std::string list;
    for (std::size_t c : counts) list += (list.empty() ? "" : ", ") + std::to_string(c);
    return list;
}

}  // namespace skelseg::test
