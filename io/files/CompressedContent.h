// skelseg: telling a compressed file or archive by its first bytes.
//
// Users compress meshes and volumes to ship them and then pass the file on
// under the name of what it holds ("cube.off" that is gzip data, an NRRD
// saved by a tool that gzips everything). Each reader then refused it for a
// wrong reason: the text readers said the lines end in a carriage return
// alone (a gzip header holds one), the STL reader "not an STL file", NRRD
// "wrong magic". Every format we read starts with something no compressor
// writes first, so the compressors' signatures are checked where a reader
// would otherwise give up, and the message says what to do: the one the
// extension check gives for "cube.off.gz" (unknownInputFormatProblem in
// engine/SegmentInput.h builds it from compressedFileProblem too).
#pragma once

#include <string>
#include <string_view>

namespace skelseg {

/// The compression or archive format whose signature `bytes` start with:
/// "gzip" (1f 8b), "bzip2" ("BZh", a block size digit, then a block or
/// end-of-stream magic), "xz" (fd '7zXZ' 00), "zstd" (28 b5 2f fd), "zip"
/// ("PK" 03 04, or 05 06 for an empty archive), "7-Zip", "RAR", "lz4", or
/// "tar" ("ustar" at byte 257); empty when none.
std::string_view compressionFormatOf(std::string_view bytes) noexcept;

/// "is a compressed file or archive (HOW); unpack it first": the problem of
/// an input that must be unpacked before skelseg reads it. `how` says how it
/// was recognised (a quoted extension, or "its bytes are gzip data").
std::string compressedFileProblem(std::string_view how);

/// Throws InputError(name, compressedFileProblem(...)) when `bytes` start
/// with the signature of a compression or archive format; returns otherwise.
void refuseCompressedContent(const std::string& name, std::string_view bytes);

}  // namespace skelseg
