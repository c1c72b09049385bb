#include "io/render/PreviewRenderer.h"

// stb in "static" mode: its functions stay private to this file, so another
// file of the project (or a test) may include its own copy without clashes.
#include <zlib.h>

#include <cstdlib>

namespace {
/// zlib's deflate for stb's PNG writer: faster than stb's own and smaller
/// files (docs/performance.md). Returns a malloc'ed buffer (stb frees it), or null.
unsigned char* zlibCompressForStb(unsigned char* data, int length, int* outLength,
                                  int /*quality*/) {
    uLongf size = compressBound(uLong(length));
    auto* out = static_cast<unsigned char*>(std::malloc(size));
    if (out == nullptr) return nullptr;
    if (compress2(out, &size, data, uLong(length), 6) != Z_OK) {
        std::free(out);
        return nullptr;
    }
    *outLength = int(size);
    return out;
}
}  // namespace

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBIW_ZLIB_COMPRESS zlibCompressForStb
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>

#include "io/files/OutputDirectory.h"
#include "io/render/Palette.h"
#include "io/render/PreviewCanvas.h"
#include "io/render/PreviewPanel.h"
#include "kernels/base/Error.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

using namespace preview;

void validate(const PreviewScene& scene, const PreviewOptions& options) {
    if (options.width < 256 || options.width > 16384 || options.height < 128 ||
        options.height > 16384)
        throw Error("preview: picture size " + std::to_string(options.width) + "x" +
                    std::to_string(options.height) + " is outside 256..16384 x 128..16384");
    if (options.upAxis < -1 || options.upAxis > 2)
        throw Error("preview: up axis " + std::to_string(options.upAxis) + " is not -1, 0, 1 or 2");
    if (!scene.triangleLabels.empty() && scene.triangleLabels.size() != scene.triangles.size())
        throw Error("preview: " + std::to_string(scene.triangles.size()) + " triangles but " +
                    std::to_string(scene.triangleLabels.size()) + " triangle labels");
    for (std::size_t t = 0; t < scene.triangles.size(); ++t)
        for (std::uint32_t corner : scene.triangles[t])
            if (corner >= scene.vertices.size())
                throw Error("preview: triangle " + std::to_string(t) + " refers to vertex " +
                            std::to_string(corner) + " of " +
                            std::to_string(scene.vertices.size()));
    for (std::size_t e = 0; e < scene.skeletonEdges.size(); ++e)
        for (std::uint32_t end : scene.skeletonEdges[e])
            if (end >= scene.skeletonPoints.size())
                throw Error("preview: skeleton edge " + std::to_string(e) + " refers to point " +
                            std::to_string(end) + " of " +
                            std::to_string(scene.skeletonPoints.size()));
}

/// Title at the left, then one swatch + label number per segment, right
/// aligned; as many as fit, then "+N".
void drawTitleBar(Canvas& canvas, const std::string& title,
                  const std::vector<std::uint32_t>& labels, int barHeight, int textScale) {
    fillRectangle(canvas, 0, 0, canvas.width, barHeight, kTitleBackground);
    fillRectangle(canvas, 0, barHeight - 1, canvas.width, barHeight, kSeparator);
    const int margin = 6 * textScale;
    const int textTop = (barHeight - 1 - 7 * textScale) / 2;  // centre the cap height (7 units)
    const int titleWidth = textWidth(title, textScale);

    const int swatch = 7 * textScale;
    const int gap = 3 * textScale, entryGap = 7 * textScale;
    auto entryWidth = [&](std::uint32_t label) {
        return swatch + gap + textWidth(std::to_string(label), textScale);
    };
    int legendWidth = 0;
    std::size_t shown = 0;
    const int available = canvas.width - 2 * margin - titleWidth - 4 * entryGap;
    for (; shown < labels.size(); ++shown) {
        const int width = entryWidth(labels[shown]) + (shown > 0 ? entryGap : 0);
        const std::string more = "+" + std::to_string(labels.size() - shown - 1);
        const int reserve = shown + 1 < labels.size() ? entryGap + textWidth(more, textScale) : 0;
        if (legendWidth + width + reserve > std::max(0, available)) break;
        legendWidth += width;
    }
    const std::string more =
        shown < labels.size() ? "+" + std::to_string(labels.size() - shown) : "";
    if (!more.empty()) legendWidth += (shown > 0 ? entryGap : 0) + textWidth(more, textScale);

    int x = canvas.width - margin - legendWidth;
    drawText(canvas, margin, textTop, title, textScale, kTextColour,
             std::max(margin, x - 2 * entryGap));
    for (std::size_t k = 0; k < shown; ++k) {
        fillRectangle(canvas, x, textTop, x + swatch, textTop + swatch, kOutlineColour);
        fillRectangle(canvas, x + 1, textTop + 1, x + swatch - 1, textTop + swatch - 1,
                      toColour(segmentColour(labels[k])));
        x += swatch + gap;
        const std::string number = std::to_string(labels[k]);
        drawText(canvas, x, textTop, number, textScale, kTextColour);
        x += textWidth(number, textScale) + entryGap;
    }
    if (!more.empty()) drawText(canvas, x, textTop, more, textScale, kCaptionColour);
}

}  // namespace

std::uint64_t previewMemoryBytes(const PreviewOptions& options, std::uint64_t triangles,
                                 std::uint64_t vertices, int threads) {
    const std::uint64_t pixels =
        std::uint64_t(std::max(options.width, 0)) * std::uint64_t(std::max(options.height, 0));
    // The canvas (float RGB), the 8-bit image, and the PNG encoder's
    // filtered rows and compressed stream (each at most about the image).
    const std::uint64_t picture = pixels * (sizeof(Colour) + 3 + 3 + 3);
    // prepareScene: face normals and labels kept, area-weighted normals
    // while it sums them; vertex normals and framing points kept, vertex
    // sums and use marks while it sums.
    const std::uint64_t prepared =
        triangles * (3 * sizeof(float) + 3 * sizeof(double) + sizeof(std::uint32_t)) +
        vertices * (3 * sizeof(float) + 3 * sizeof(double) + 3 * sizeof(double) + 1);
    // One panel: a third of the width (rounded up), the full height (the
    // title bar is left in, an upper bound), kSupersample^2 samples per
    // pixel of depth, triangle id, colour and three line layers; per vertex
    // its projection, per triangle its row range and its entries in the row
    // bands (a triangle spans a few bands of 32 rows; 4 counted).
    const std::uint64_t panelPixels = (std::uint64_t(std::max(options.width, 0)) / 3 + 1) *
                                      std::uint64_t(std::max(options.height, 0));
    const std::uint64_t samples = panelPixels * std::uint64_t(kSupersample * kSupersample);
    const std::uint64_t panel =
        samples * (sizeof(float) + sizeof(std::uint32_t) + sizeof(Colour) + 3 * sizeof(float)) +
        vertices * 3 * sizeof(double) + triangles * (2 * sizeof(int) + 4 * sizeof(std::uint32_t));
    const std::uint64_t panelsAtOnce =
        options.threaded ? std::uint64_t(std::clamp(threads, 1, 3)) : 1;
    return picture + prepared + panelsAtOnce * panel;
}

Image renderPreview(const PreviewScene& scene, const PreviewOptions& options) {
    validate(scene, options);
    const PreparedScene prepared = prepareScene(scene, options.threaded);
    const std::array<View, 3> views = makeViews(options.upAxis, prepared.extent);

    // Sizes follow the width; text never below scale 2 (scale 1 is hard to read).
    const int textScale = std::max(2, int(std::lround(options.width / 768.0)));
    const double lineScale = std::max(0.75, options.width / 1536.0);
    const int barHeight = std::min(options.height / 3, 10 * textScale + 12 * textScale / 2 + 6);
    const int captionSpace = 12 * textScale;

    Canvas canvas(options.width, options.height, kPanelTop);
    drawTitleBar(canvas, scene.title, prepared.labels, barHeight, textScale);

    const int panelTop = barHeight, panelHeight = options.height - barHeight;
    std::array<int, 4> panelLeft{};
    for (int v = 0; v <= 3; ++v) panelLeft[std::size_t(v)] = v * options.width / 3;
    parallelForEach(
        3,
        [&](int v) {
            const int panelWidth = panelLeft[std::size_t(v) + 1] - panelLeft[std::size_t(v)];
            downsampleInto(renderPanel(prepared, views[std::size_t(v)], panelWidth, panelHeight,
                                       captionSpace, lineScale, options.threaded),
                           canvas, panelLeft[std::size_t(v)], panelTop);
        },
        options.threaded);
    for (int v = 0; v < 3; ++v) {
        const int left = panelLeft[std::size_t(v)];
        if (v > 0) fillRectangle(canvas, left, panelTop, left + 1, options.height, kSeparator);
        drawText(canvas, left + 6 * textScale, options.height - captionSpace + textScale,
                 views[std::size_t(v)].caption, textScale, kCaptionColour);
    }
    return toImage(canvas);
}

std::string encodePng(const Image& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != std::size_t(image.width) * std::size_t(image.height) * 3)
        throw Error("PNG: image of " + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + " has " + std::to_string(image.rgb.size()) +
                    " bytes");
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                   std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                                image.width * 3))
        throw Error("PNG: encoding failed");
    return bytes;
}

void renderPreviewPng(const std::filesystem::path& file, const PreviewScene& scene,
                      const PreviewOptions& options) {
    writeFileAtomically(file, encodePng(renderPreview(scene, options)));
}

}  // namespace skelseg
