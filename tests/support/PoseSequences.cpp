#include "tests/support/PoseSequences.h"

#include <algorithm>
#include <cctype>
#include <utility>

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

}  // namespace skelseg::test
