// skelseg: Geomview's OFF header keyword, [ST][C][N][4][n]OFF, read one way
// by the OFF reader (io/mesh/OffReader.cpp) and by the check that names an
// OFF file given where another format was expected (ForeignContent.cpp).
#pragma once

#include <cstddef>
#include <string_view>

namespace skelseg {

/// Length of `token` up to the end of its "OFF" (any case) when what follows
/// is empty or digits (the first count glued to it, "OFF8": Geomview matches
/// the keyword's letters and then reads numbers), 0 when it has no such OFF.
std::size_t offKeywordEnd(std::string_view token);

/// Whether `prefix`, the letters before "OFF", are Geomview's: S, T, C, N,
/// 4 and n, case-sensitive ('N' says normals, 'n' a coordinate count).
bool isOffKeywordPrefix(std::string_view prefix);

/// `token` is an OFF keyword: an "OFF" with a Geomview prefix before it and
/// nothing but digits after it.
bool isOffKeyword(std::string_view token);

}  // namespace skelseg
