// skelseg: what a killed run leaves behind, and removing it.
//
// OutputDirectory stages a run's files in OUTDIR/.skelseg-staging-PID-N and
// writeFileAtomically() writes through OUTDIR/.NAME.tmp-PID-N; both are
// renamed or removed when the run ends, but SIGKILL or a node failure leaves
// them. They never sit under a final name, so they are only clutter; the next
// batch run over the same input removes them before it starts the input, but
// only once it holds the folder's lock (io/files/DirectoryLock.h): another
// batch of another share, or a `segment` run, may be writing there. Even
// then a staging directory goes only when isLeftoverStagingDirectory()
// proves it a dead run's, and a temporary only when the process its name
// names (".NAME.tmp-PID-N") is not alive. OutputDirectory itself removes
// only staging directories: a `segment` OUTDIR may be the user's folder,
// where a hidden ".x.tmp-y" could be the user's file.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace skelseg {

/// True for the names of staging directories and atomic-write temporaries.
bool isStagingLeftoverName(const std::string& fileName);

/// Removes the staging leftovers of runs no longer alive directly in
/// `directory` (see above); returns how many. A missing directory has none.
/// The caller holds `directory`'s lock, or the batch's lock for OUTROOT.
std::size_t removeStagingLeftovers(const std::filesystem::path& directory);

}  // namespace skelseg
