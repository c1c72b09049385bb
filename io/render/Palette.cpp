#include "io/render/Palette.h"

#include <cmath>

namespace skelseg {

namespace {

// tab20's strong colours, then its light ones, in matplotlib's tab10 order.
// The grey pair (127,127,127)/(199,199,199) is replaced by tab20b's indigo
// pair: grey segments would be mistaken for background or unlabelled faces.
constexpr std::array<std::uint8_t, 3> kFixedTable[kFixedPaletteSize] = {
    {31, 119, 180},  {255, 127, 14},  {44, 160, 44},   {214, 39, 40},   {148, 103, 189},
    {140, 86, 75},   {227, 119, 194}, {57, 59, 121},   {188, 189, 34},  {23, 190, 207},
    {174, 199, 232}, {255, 187, 120}, {152, 223, 138}, {255, 152, 150}, {197, 176, 213},
    {196, 156, 148}, {247, 182, 210}, {156, 158, 222}, {219, 219, 141}, {158, 218, 229},
};

std::array<std::uint8_t, 3> fromHsv(double hue, double saturation, double value) noexcept {
    const double h = (hue - std::floor(hue)) * 6.0;
    const int sector = int(h) % 6;
    const double f = h - std::floor(h);
    const double p = value * (1.0 - saturation);
    const double q = value * (1.0 - saturation * f);
    const double t = value * (1.0 - saturation * (1.0 - f));
    double r = value, g = t, b = p;
    switch (sector) {
        case 0:
            r = value, g = t, b = p;
            break;
        case 1:
            r = q, g = value, b = p;
            break;
        case 2:
            r = p, g = value, b = t;
            break;
        case 3:
            r = p, g = q, b = value;
            break;
        case 4:
            r = t, g = p, b = value;
            break;
        default:
            r = value, g = p, b = q;
            break;
    }
    auto toByte = [](double c) {
        return std::uint8_t(std::lround(std::fmin(std::fmax(c, 0.0), 1.0) * 255.0));
    };
    return {toByte(r), toByte(g), toByte(b)};
}

}  // namespace

std::array<std::uint8_t, 3> segmentColour(std::uint32_t label) noexcept {
    if (label == 0) return {128, 128, 128};
    if (label <= kFixedPaletteSize) return kFixedTable[label - 1];
    // Golden-ratio hue steps never repeat and put consecutive labels far apart
    // on the colour wheel; the saturation/value cycles (of coprime lengths 3
    // and 2) separate labels whose hues happen to come close. Value stays in
    // [0.70, 0.92] so no segment is as dark as the skeleton lines or as pale as
    // the picture's background.
    const std::uint32_t step = label - kFixedPaletteSize - 1;
    const double hue = 0.11 + double(step) * 0.6180339887498949;
    static constexpr double kSaturations[3] = {0.72, 0.50, 0.88};
    static constexpr double kValues[2] = {0.92, 0.72};
    return fromHsv(hue, kSaturations[step % 3], kValues[step % 2]);
}

}  // namespace skelseg
