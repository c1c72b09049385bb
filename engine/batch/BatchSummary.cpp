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
#include "engine/batch/JsonFields.h"
#include "io/files/OutputDirectory.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace skelseg {

namespace {

json entryJson(const BatchEntry& e) {
    return {{"name", e.name},
            {"input", e.input.string()},
            {"line", e.line},
            {"status", e.status},
            {"parts", e.parts},
            {"wall_seconds", e.wallSeconds},
            {"cpu_seconds", e.cpuSeconds},
            {"peak_memory_bytes", e.peakMemoryBytes},
            {"estimated_memory_bytes", e.estimatedMemoryBytes},
            {"error", e.error},
            {"finished_at", e.finishedAt}};
}

BatchEntry entryFromJson(const JsonFields& j) {
    BatchEntry e;
    e.name = j.text("name");
    e.input = j.text("input");
    e.line = int(j.count("line", 0));  // 0 in summaries that predate it
    e.status = j.text("status");
    e.parts = j.count("parts", 0);
    e.wallSeconds = j.number("wall_seconds", 0.0);
    e.cpuSeconds = j.number("cpu_seconds", 0.0);
    e.peakMemoryBytes = j.count("peak_memory_bytes", 0);
    e.estimatedMemoryBytes = j.count("estimated_memory_bytes", 0);
    e.error = j.text("error", std::string());
    e.finishedAt = j.text("finished_at", std::string());
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

/// The manifest paths name one file: the same text, or paths to the same
/// file from here (the tasks of one job may spell it differently).
bool isSameManifest(const fs::path& a, const fs::path& b) {
    if (a.lexically_normal() == b.lexically_normal()) return true;
    std::error_code ec;
    return fs::equivalent(a, b, ec) && !ec;
}

/// The first option in which the options texts `a` and `b` (JSON objects)
/// differ: "tau is \"5%\", not \"3%\"", "grid is missing".
std::string optionDifference(const std::string& a, const std::string& b) {
    const json first = json::parse(a), second = json::parse(b);
    auto show = [](const json& options, const std::string& key) {
        return options.contains(key) ? options.at(key).dump() : std::string("unset");
    };
    std::set<std::string> keys;
    for (const json* options : {&first, &second})
        if (options->is_object())
            for (const auto& item : options->items()) keys.insert(item.key());
    for (const auto& key : keys)
        if (show(first, key) != show(second, key))
            return key + " is " + show(first, key) + ", not " + show(second, key);
    return "written differently";
}

/// Throws InputError naming `file` when its summary is of another batch than
/// `reference`'s (the newest file's): another manifest (path or names), other
/// options or another skelseg. Combined, one input's record would stand for
/// another's results, made another way: the second of two manifests sharing
/// an output name replaced the first's folder, and the merge called it done.
void refuseAnotherBatch(const fs::path& file, const BatchSummary& summary,
                        const fs::path& referenceFile, const BatchSummary& reference) {
    std::string difference;
    if (!isSameManifest(summary.manifest, reference.manifest))
        difference =
            "its manifest is " + summary.manifest.string() + ", not " + reference.manifest.string();
    else if (summary.manifestNames != reference.manifestNames)
        difference = "its manifest lists other inputs (manifest_names)";
    else if (summary.options != reference.options)
        difference =
            "its options differ (" + optionDifference(summary.options, reference.options) + ")";
    else if (summary.skelsegVersion != reference.skelsegVersion)
        difference = "it was written by skelseg " + summary.skelsegVersion + ", not " +
                     reference.skelsegVersion;
    else if (summary.skelsegBuild != reference.skelsegBuild) {
        const auto named = [](const std::string& build) {
            return build.empty() ? std::string("a build it does not name") : "build " + build;
        };
        difference = "it was written by " + named(summary.skelsegBuild) + ", not " +
                     named(reference.skelsegBuild);
    }
    if (difference.empty()) return;
    throw InputError(file.string(), "is of another batch than " + referenceFile.string() + ": " +
                                        difference +
                                        "; merge only the shards of one batch (same manifest, "
                                        "options and skelseg build)");
}

}  // namespace

std::string nameAndLine(const BatchEntry& entry) {
    return entry.line > 0 ? entry.name + " (line " + std::to_string(entry.line) + ")" : entry.name;
}

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
        {"skelseg_build", summary.skelsegBuild},
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
    const std::string prefix = "not a skelseg batch summary: ";
    const json document = readJsonFile(file, prefix);
    const JsonFields j(document, file.string(), prefix);
    BatchSummary s;
    s.skelsegVersion = j.text("skelseg_version");
    s.skelsegBuild = j.text("skelseg_build", std::string());
    s.manifest = j.text("manifest");
    const JsonFields shard = j.object("shard");
    s.shard.index = shard.integer("index");
    s.shard.count = shard.integer("count");
    s.options = j.any("options").dump();
    s.run = j.text("run", std::string());
    s.startedAt = j.text("started_at", std::string());
    s.updatedAt = j.text("updated_at", std::string());
    s.complete = j.flag("complete", false);
    s.wallSeconds = j.number("wall_seconds", 0.0);
    s.manifestNames = j.texts("manifest_names");
    std::size_t number = 0;
    for (const auto& e : j.array("entries"))
        s.entries.push_back(entryFromJson(
            JsonFields(e, file.string(), prefix, "entry " + std::to_string(++number) + ": ")));
    return s;
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
    for (const auto& [path, summary] : shards)
        if (summary.shard.count == shardCount)
            refuseAnotherBatch(path, summary, newest->first, newest->second);
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
