#include "engine/batch/BatchSummary.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "engine/Version.h"
#include "engine/batch/DoneMarker.h"
#include "io/files/OutputDirectory.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace skelseg {

namespace {

json entryJson(const BatchEntry& e) {
    return {{"name", e.name},
            {"input", e.input.string()},
            {"status", e.status},
            {"parts", e.parts},
            {"wall_seconds", e.wallSeconds},
            {"cpu_seconds", e.cpuSeconds},
            {"peak_memory_bytes", e.peakMemoryBytes},
            {"estimated_memory_bytes", e.estimatedMemoryBytes},
            {"error", e.error},
            {"finished_at", e.finishedAt}};
}

BatchEntry entryFromJson(const json& j) {
    BatchEntry e;
    e.name = j.at("name").get<std::string>();
    e.input = j.at("input").get<std::string>();
    e.status = j.at("status").get<std::string>();
    e.parts = j.value("parts", std::uint64_t(0));
    e.wallSeconds = j.value("wall_seconds", 0.0);
    e.cpuSeconds = j.value("cpu_seconds", 0.0);
    e.peakMemoryBytes = j.value("peak_memory_bytes", std::uint64_t(0));
    e.estimatedMemoryBytes = j.value("estimated_memory_bytes", std::uint64_t(0));
    e.error = j.value("error", std::string());
    e.finishedAt = j.value("finished_at", std::string());
    return e;
}

std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) {
        if (c == '"') quoted += '"';
        quoted += (c == '\n' || c == '\r') ? ' ' : c;
    }
    return quoted + "\"";
}

std::string formatSeconds(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", seconds);
    return text;
}

}  // namespace

std::size_t BatchSummary::count(const std::string& status) const {
    return std::size_t(std::count_if(entries.begin(), entries.end(),
                                     [&](const BatchEntry& e) { return e.status == status; }));
}

void writeBatchSummary(const fs::path& outroot, const std::string& stem,
                       const BatchSummary& summary) {
    json entries = json::array();
    for (const auto& e : summary.entries) entries.push_back(entryJson(e));
    json counts = json::object();
    for (const char* status : {"done", "skipped", "failed", "pending", "missing"})
        counts[status] = summary.count(status);
    const json j = {
        {"skelseg_version", summary.skelsegVersion},
        {"manifest", summary.manifest.string()},
        {"shard", {{"index", summary.shard.index}, {"count", summary.shard.count}}},
        {"options", summary.options.empty() ? json::object() : json::parse(summary.options)},
        {"run", summary.run},
        {"started_at", summary.startedAt},
        {"updated_at", summary.updatedAt},
        {"complete", summary.complete},
        {"wall_seconds", summary.wallSeconds},
        {"counts", counts},
        {"manifest_names", summary.manifestNames},
        {"entries", entries}};
    writeFileAtomically(outroot / (stem + ".json"),
                        j.dump(2, ' ', false, json::error_handler_t::replace) + "\n");

    std::ostringstream csv;
    csv << "name,input,status,parts,wall_seconds,cpu_seconds,peak_memory_bytes,"
           "estimated_memory_bytes,finished_at,error\n";
    for (const auto& e : summary.entries)
        csv << csvField(e.name) << ',' << csvField(e.input.string()) << ',' << e.status << ','
            << e.parts << ',' << formatSeconds(e.wallSeconds) << ',' << formatSeconds(e.cpuSeconds)
            << ',' << e.peakMemoryBytes << ',' << e.estimatedMemoryBytes << ',' << e.finishedAt
            << ',' << csvField(e.error) << '\n';
    writeFileAtomically(outroot / (stem + ".csv"), csv.str());
}

BatchSummary readBatchSummary(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot be read");
    try {
        const json j = json::parse(in);
        BatchSummary s;
        s.skelsegVersion = j.at("skelseg_version").get<std::string>();
        s.manifest = j.at("manifest").get<std::string>();
        s.shard.index = j.at("shard").at("index").get<int>();
        s.shard.count = j.at("shard").at("count").get<int>();
        s.options = j.at("options").dump();
        s.run = j.value("run", std::string());
        s.startedAt = j.value("started_at", std::string());
        s.updatedAt = j.value("updated_at", std::string());
        s.complete = j.value("complete", false);
        s.wallSeconds = j.value("wall_seconds", 0.0);
        s.manifestNames = j.at("manifest_names").get<std::vector<std::string>>();
        for (const auto& e : j.at("entries")) s.entries.push_back(entryFromJson(e));
        return s;
    } catch (const std::exception& error) {
        throw InputError(file.string(),
                         std::string("not a skelseg batch summary: ") + error.what());
    }
}

MergeResult mergeBatchSummaries(const fs::path& outroot) {
    MergeResult result;
    std::vector<std::pair<fs::path, BatchSummary>> shards;
    const std::regex shardName(R"(summary\.shard-(\d+)-of-(\d+)\.json)");
    std::error_code ec;
    // The share a file holds must be the one its name says: a damaged file
    // claiming a count of 2^31 made the merge list two billion missing shares.
    auto readShare = [](const fs::path& file, const std::string& index, const std::string& count) {
        BatchSummary summary = readBatchSummary(file);
        const std::string share = summary.shard.toString();
        if (share != index + "/" + count)
            throw InputError(file.string(), "not a skelseg batch summary: it holds shard " + share +
                                                " but is named for " + index + "/" + count);
        return summary;
    };
    std::smatch match;
    for (const auto& item : fs::directory_iterator(outroot, ec)) {
        const std::string file = item.path().filename().string();
        if (std::regex_match(file, match, shardName))
            shards.emplace_back(item.path(), readShare(item.path(), match[1], match[2]));
    }
    if (ec) throw InputError(outroot.string(), "cannot list the directory: " + ec.message());
    if (shards.empty()) {
        const fs::path single = outroot / "summary.json";
        if (!fs::exists(single, ec))
            throw InputError(outroot.string(),
                             "holds no batch summary (summary.json or "
                             "summary.shard-I-of-N.json)");
        shards.emplace_back(single, readShare(single, "0", "1"));
    }
    // The split of the newest file; ties by name, so the choice is deterministic.
    std::sort(shards.begin(), shards.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const auto newest = std::max_element(
        shards.begin(), shards.end(),
        [](const auto& a, const auto& b) { return a.second.updatedAt < b.second.updatedAt; });
    const int shardCount = newest->second.shard.count;
    std::map<std::string, BatchEntry> byName;
    std::set<int> present;
    std::vector<std::string> names;
    std::set<std::string> known;
    BatchSummary& merged = result.merged;
    merged = newest->second;
    merged.entries.clear();
    merged.shard = ShardSpec{};
    merged.run = runIdentity();
    merged.startedAt = "";
    merged.complete = true;
    merged.wallSeconds = 0.0;
    for (const auto& [path, summary] : shards) {
        if (summary.shard.count != shardCount) continue;
        result.shardFiles.push_back(path.string());
        present.insert(summary.shard.index);
        merged.complete = merged.complete && summary.complete;
        merged.wallSeconds = std::max(merged.wallSeconds, summary.wallSeconds);
        if (merged.startedAt.empty() || summary.startedAt < merged.startedAt)
            merged.startedAt = summary.startedAt;
        for (const auto& name : summary.manifestNames)
            if (known.insert(name).second) names.push_back(name);
        for (const auto& entry : summary.entries) byName[entry.name] = entry;
    }
    // Runs of absent shares, one entry each: a split into 10^9 shares (a
    // Slurm array or --shard of that count over a few inputs) made a billion
    // lines, and a table of them that ran out of memory.
    int next = 0;  // the first share not yet accounted for
    auto addAbsent = [&](int end) {
        if (next >= end) return;
        result.missingShards.push_back(end - next == 1
                                           ? ShardSpec{next, shardCount}.toString()
                                           : std::to_string(next) + "-" + std::to_string(end - 1) +
                                                 "/" + std::to_string(shardCount));
        merged.complete = false;
    };
    for (const int index : present) {
        if (index < next || index >= shardCount) continue;
        addAbsent(index);
        next = index + 1;
    }
    addAbsent(shardCount);
    merged.manifestNames = names;
    for (const auto& name : names) {
        BatchEntry entry;
        const auto found = byName.find(name);
        if (found != byName.end())
            entry = found->second;
        else {
            entry.name = name;
            entry.status = "missing";
        }
        const auto marker = readDoneMarker(outroot / name);
        if (marker) {
            if (!entry.isDone()) {
                // Finished by a run whose summary was overwritten (a killed
                // task resubmitted): the marker has the figures.
                entry.status = "done";
                entry.input = marker->input;
                entry.parts = marker->parts;
                entry.wallSeconds = marker->wallSeconds;
                entry.cpuSeconds = marker->cpuSeconds;
                entry.peakMemoryBytes = marker->peakMemoryBytes;
                entry.finishedAt = marker->finishedAt;
                entry.error.clear();
            }
        } else {
            if (entry.status == "failed")
                result.failed.push_back(name);
            else if (entry.isDone() || entry.status == "pending")
                entry.status = "missing";
            result.missing.push_back(name);
        }
        merged.entries.push_back(entry);
    }
    merged.updatedAt = utcTimestamp();
    writeBatchSummary(outroot, "summary", merged);
    return result;
}

}  // namespace skelseg
