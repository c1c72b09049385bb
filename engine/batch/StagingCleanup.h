// skelseg: what a killed run leaves behind, and removing it.
//
// OutputDirectory stages a run's files in OUTDIR/.skelseg-staging-PID-N and
// writeFileAtomically() writes through OUTDIR/.NAME.tmp-PID-N; both are
// renamed or removed when the run ends, but SIGKILL or a node failure leaves
// them. They never sit under a final name, so they are only clutter; the next
// batch run over the same input removes them before it starts the input
// (never while another process could be using them: each input belongs to
// one shard, and one shard runs in one process at a time). OutputDirectory
// itself removes only staging directories, and only once it holds OUTDIR's
// lock: a `segment` OUTDIR may be the user's folder, where a hidden
// ".x.tmp-y" could be the user's file.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace skelseg {

/// True for the names of staging directories and atomic-write temporaries.
bool isStagingLeftoverName(const std::string& fileName);

/// Removes the staging leftovers directly in `directory`; returns how many.
/// A missing directory has none.
std::size_t removeStagingLeftovers(const std::filesystem::path& directory);

}  // namespace skelseg
