// skelseg: Princeton .seg segmentation files.
//
// A .seg file holds one integer segment label per line; line i belongs to face
// i of the mesh file (in the mesh file's face order). The benchmark ships them
// gzipped (.seg.gz). Readers accept plain or gzip data whatever the name says
// (detected by the gzip magic bytes); a blank last line is fine, any other
// line that is not one integer is an error naming its line number.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace skelseg {

/// Labels of a .seg or .seg.gz file, one per line.
/// @throw InputError naming the file: unreadable, corrupt gzip data, a line
/// that is not one integer (with its line number), no labels at all, or more
/// than 1 GiB of decompressed text.
std::vector<std::int64_t> readSeg(const std::filesystem::path& path);

/// readSeg on `size` bytes at `data` (plain or gzip); `name` is for messages.
std::vector<std::int64_t> readSegFromMemory(const std::string& name, const std::uint8_t* data,
                                            std::size_t size);

/// Writes one label per line; gzip-compressed when the name ends in ".gz".
/// Atomic (temporary file + rename). @throw OutputError.
void writeSeg(const std::filesystem::path& path, const std::vector<std::uint32_t>& labels);

}  // namespace skelseg
