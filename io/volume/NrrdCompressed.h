// skelseg: the compressed NRRD encodings, gzip and bzip2 (internal to io/volume/).
//
// decompress() inflates the data that follows a header (gzip or zlib
// streams, or bzip2 streams; concatenated members or streams too, as gzip
// and pbzip2 write them) into a ByteSink, checking its length as it goes:
// it never produces more than one byte past the most the header allows, so
// a stream that is too long is detected without unbounded memory or time.
// maxDecompressedBytes() is the bound NrrdIO.cpp checks a header's claim
// against before it allocates anything.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/volume/NrrdHeader.h"

namespace skelseg::nrrd {

/// How long the decompressed data must be: between atLeast and atMost bytes
/// (equal unless the header has byte skip -1, whose samples are the data's
/// last bytes after a prefix of unknown length).
struct DecompressedLength {
    std::uint64_t atLeast = 0;
    std::uint64_t atMost = 0;
};

/// The most bytes that `size` bytes of `encoding` (Gzip or Bzip2) can
/// decompress to. Deflate expands at most 1032:1. A bzip2 block holds at
/// most 900000 symbols of run-length code, each 5 of which give at most 259
/// bytes (46.62 MB), and takes at least 173 bits (magic, CRC, origin
/// pointer, symbol map, two coding tables, one selector, end of block).
std::uint64_t maxDecompressedBytes(Encoding encoding, std::uint64_t size);

/// Decompresses `size` bytes of `encoding` (Gzip or Bzip2) into `sink`.
/// @throw InputError(name, ...) for data that is corrupt, truncated, or
/// decompresses to fewer than length.atLeast or more than length.atMost
/// bytes ("data is too short/long: ...").
void decompress(const std::string& name, Encoding encoding, const std::uint8_t* data,
                std::size_t size, DecompressedLength length, ByteSink& sink);

}  // namespace skelseg::nrrd
