// skelseg: the colour of each segment, shared by every picture and coloured mesh.
//
// One function so that segments.ply, preview.png and any later figure show a
// segment in the same colour. Labels follow the label volume: 0 is the
// background (never drawn; it gets a neutral grey so that a mistake shows as
// grey rather than as a segment colour), 1..K are segments. A caller holding
// 0-based segment indices (mesh face labels) passes index + 1.
#pragma once

#include <array>
#include <cstdint>

namespace skelseg {

/// Colour of segment `label` as 8-bit sRGB.
///
/// Labels 1..20 take a fixed qualitative table: the ten strong colours of
/// matplotlib's "tab20" (its grey pair replaced by indigo, because grey reads
/// as background) first, then their ten light companions, so the first ten
/// segments are as far apart as possible. Labels above 20 step the hue by the
/// golden ratio and alternate saturation and value, which keeps neighbouring
/// labels apart for any count. Deterministic: the same label always gets the
/// same colour. Label 0 gives the neutral grey (128, 128, 128).
std::array<std::uint8_t, 3> segmentColour(std::uint32_t label) noexcept;

/// Number of entries of the fixed table (labels 1..kFixedPaletteSize).
constexpr std::uint32_t kFixedPaletteSize = 20;

}  // namespace skelseg
