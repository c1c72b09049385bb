// skelseg: the text NRRD encodings, ascii and hex (internal to io/volume/).
//
// decodeAscii() reads numbers separated by whitespace or commas (teem
// passes over commas too) and hands each sample's bytes, in the host's byte
// order, to a ByteSink; decodeHex() reads two hex digits per byte, either
// case, whitespace anywhere between. Both want exactly the header's count:
// too few, too many and anything that is not a sample are refused with the
// line it is on. minimumTextBytes() lets NrrdIO.cpp refuse a claim the data
// cannot hold before it allocates the volume.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/volume/NrrdHeader.h"

namespace skelseg::nrrd {

/// Where decoded text starts, for messages: `source` is "" for data after
/// the header, or "data file 'NAME', " for a detached data file; `firstLine`
/// the 1-based line number of the text's first byte in that file.
struct TextOrigin {
    std::string source;
    std::size_t firstLine = 1;
};

/// The fewest bytes that `samples` samples of `sampleSize` bytes take in
/// `encoding` (Ascii: a digit each and a separator between; Hex: two digits
/// per byte).
std::uint64_t minimumTextBytes(Encoding encoding, std::uint64_t samples, std::size_t sampleSize);

/// How many whitespace- or comma-separated words `text` holds: what a
/// too-short ascii block holds, told in the unit the header counts in.
std::uint64_t countAsciiWords(const char* text, std::size_t size);

/// Decodes `samples` ascii numbers of `type` into `sink`. An integer type
/// takes any number whose value is an integer in its range ("7", "+7",
/// "7.0", "7e0", as pynrrd's %.17g writes them); a float type any number,
/// nan and inf included. @throw InputError(name, ...).
void decodeAscii(const std::string& name, const char* text, std::size_t size, SampleType type,
                 std::uint64_t samples, const TextOrigin& origin, ByteSink& sink);

/// Decodes `bytes` bytes of hex digits into `sink`. @throw InputError(name, ...).
void decodeHex(const std::string& name, const char* text, std::size_t size, std::uint64_t bytes,
               const TextOrigin& origin, ByteSink& sink);

}  // namespace skelseg::nrrd
