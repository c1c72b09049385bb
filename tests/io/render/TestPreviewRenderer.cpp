#include "io/render/PreviewRenderer.h"

#include <gtest/gtest.h>

// Static so that another test file of this executable may also include its
// own stb_image implementation.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#include <malloc.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <new>

#include "io/render/Palette.h"
#include "kernels/base/Error.h"
#include "tests/support/FileBytes.h"
#include "tests/support/Pi.h"
#include "tests/support/TempDir.h"

// The bytes test_io holds on the C++ heap, and the most it held since a
// HeapPeak began: this file replaces test_io's global operator new and
// delete (they count each block's usable size, then call malloc and free),
// so that a test can hold a memory estimate to the allocations it
// measures. Blocks C libraries take from malloc directly (zlib, stb) are not
// counted.
namespace {

std::atomic<std::int64_t> gHeapHeld{0};
std::atomic<std::int64_t> gHeapPeak{0};

void countHeapBlock(void* block) noexcept {
    const auto bytes = std::int64_t(malloc_usable_size(block));
    const std::int64_t held = gHeapHeld.fetch_add(bytes, std::memory_order_relaxed) + bytes;
    std::int64_t peak = gHeapPeak.load(std::memory_order_relaxed);
    while (held > peak && !gHeapPeak.compare_exchange_weak(peak, held, std::memory_order_relaxed)) {
    }
}

// As the standard operator new: a failed allocation calls the new-handler
// (other tests of this binary install one) and tries again, or throws
// std::bad_alloc when there is none.
template <typename Allocate>
void* allocateCountedWith(Allocate allocate) {
    for (;;) {
        if (void* block = allocate()) {
            countHeapBlock(block);
            return block;
        }
        const std::new_handler handler = std::get_new_handler();
        if (!handler) throw std::bad_alloc();
        handler();
    }
}

void* allocateCounted(std::size_t bytes) {
    return allocateCountedWith([&] { return std::malloc(bytes ? bytes : 1); });
}

void* allocateCountedAligned(std::size_t bytes, std::align_val_t alignment) {
    const auto align = std::max(std::size_t(alignment), sizeof(void*));
    return allocateCountedWith([&] {
        return std::aligned_alloc(align, ((bytes ? bytes : 1) + align - 1) / align * align);
    });
}

void releaseCounted(void* block) noexcept {
    if (!block) return;
    gHeapHeld.fetch_sub(std::int64_t(malloc_usable_size(block)), std::memory_order_relaxed);
    std::free(block);
}

/// The most held at once since construction, above what was held then.
class HeapPeak {
public:
    HeapPeak() : mStart(gHeapHeld.load()) { gHeapPeak.store(mStart); }
    std::int64_t bytesAboveStart() const { return gHeapPeak.load() - mStart; }

private:
    std::int64_t mStart;
};

}  // namespace

void* operator new(std::size_t bytes) {
    return allocateCounted(bytes);
}
void* operator new[](std::size_t bytes) {
    return allocateCounted(bytes);
}
void* operator new(std::size_t bytes, std::align_val_t alignment) {
    return allocateCountedAligned(bytes, alignment);
}
void* operator new[](std::size_t bytes, std::align_val_t alignment) {
    return allocateCountedAligned(bytes, alignment);
}
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept {
    try {
        return allocateCounted(bytes);
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void* operator new[](std::size_t bytes, const std::nothrow_t& tag) noexcept {
    return operator new(bytes, tag);
}
void operator delete(void* block) noexcept {
    releaseCounted(block);
}
void operator delete[](void* block) noexcept {
    releaseCounted(block);
}
void operator delete(void* block, std::size_t) noexcept {
    releaseCounted(block);
}
void operator delete[](void* block, std::size_t) noexcept {
    releaseCounted(block);
}
void operator delete(void* block, std::align_val_t) noexcept {
    releaseCounted(block);
}
void operator delete[](void* block, std::align_val_t) noexcept {
    releaseCounted(block);
}
void operator delete(void* block, std::size_t, std::align_val_t) noexcept {
    releaseCounted(block);
}
void operator delete[](void* block, std::size_t, std::align_val_t) noexcept {
    releaseCounted(block);
}
void operator delete(void* block, const std::nothrow_t&) noexcept {
    releaseCounted(block);
}
void operator delete[](void* block, const std::nothrow_t&) noexcept {
    releaseCounted(block);
}

namespace skelseg {
namespace {

using test::fileBytes;
using test::kPi;

using Vec3 = std::array<double, 3>;

/// Appends a UV sphere (closed, outward winding) with the given label.
void addSphere(PreviewScene& scene, const Vec3& centre, double radius, std::uint32_t label,
               int rings = 24, int sectors = 48) {
    const auto first = std::uint32_t(scene.vertices.size());
    for (int r = 0; r <= rings; ++r) {
        const double theta = kPi * r / rings;
        for (int s = 0; s < sectors; ++s) {
            const double phi = 2.0 * kPi * s / sectors;
            scene.vertices.push_back({centre[0] + radius * std::sin(theta) * std::cos(phi),
                                      centre[1] + radius * std::cos(theta),
                                      centre[2] + radius * std::sin(theta) * std::sin(phi)});
        }
    }
    auto index = [&](int r, int s) { return first + std::uint32_t(r * sectors + (s % sectors)); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < sectors; ++s) {
            scene.triangles.push_back({index(r, s), index(r, s + 1), index(r + 1, s)});
            scene.triangles.push_back({index(r + 1, s), index(r, s + 1), index(r + 1, s + 1)});
            scene.triangleLabels.push_back(label);
            scene.triangleLabels.push_back(label);
        }
}

/// Two touching spheres (labels 1 and 2), a skeleton through both and a cut
/// loop around the neck between them.
PreviewScene twoSpheresScene() {
    PreviewScene scene;
    addSphere(scene, {0.0, 0.0, 0.0}, 1.0, 1);
    addSphere(scene, {0.0, 1.6, 0.0}, 0.7, 2);
    for (int k = 0; k <= 10; ++k) scene.skeletonPoints.push_back({0.0, -0.8 + 0.23 * k, 0.0});
    for (std::uint32_t k = 0; k < 10; ++k) scene.skeletonEdges.push_back({k, k + 1});
    std::vector<Vec3> loop;
    for (int k = 0; k < 64; ++k) {
        const double phi = 2.0 * kPi * k / 64;
        loop.push_back({0.62 * std::cos(phi), 0.8, 0.62 * std::sin(phi)});
    }
    scene.cutLoops.push_back(loop);
    scene.title = "two spheres  parts: 2  tau: 3%";
    return scene;
}

/// Pixels whose colour is a shade of `colour`: a multiple s in [0.3, 1.15] of
/// it (shading scales the colour) within a small residual.
std::size_t countShadesOf(const Image& image, const std::array<std::uint8_t, 3>& colour,
                          int top = 0) {
    const double c[3] = {double(colour[0]), double(colour[1]), double(colour[2])};
    const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    std::size_t count = 0;
    for (int y = top; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p =
                &image.rgb[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3];
            const double s = (p[0] * c[0] + p[1] * c[1] + p[2] * c[2]) / cc;
            if (s < 0.3 || s > 1.15) continue;
            double residual = 0.0;
            for (int k = 0; k < 3; ++k) residual += (p[k] - s * c[k]) * (p[k] - s * c[k]);
            if (residual < 10.0 * 10.0) ++count;
        }
    return count;
}

std::size_t countNear(const Image& image, const std::array<int, 3>& colour, int tolerance, int x0,
                      int y0, int x1, int y1) {
    std::size_t count = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const std::uint8_t* p =
                &image.rgb[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3];
            if (std::abs(p[0] - colour[0]) <= tolerance &&
                std::abs(p[1] - colour[1]) <= tolerance && std::abs(p[2] - colour[2]) <= tolerance)
                ++count;
        }
    return count;
}

std::size_t countDark(const Image& image, int x0, int y0, int x1, int y1) {
    return countNear(image, {30, 30, 30}, 45, x0, y0, x1, y1);
}

TEST(PreviewRenderer, WritesAPngOfTheRequestedSize) {
    test::TempDir dir;
    PreviewOptions options;
    options.width = 1100;
    options.height = 500;
    renderPreviewPng(dir / "preview.png", twoSpheresScene(), options);
    const std::string bytes = fileBytes(dir / "preview.png");
    ASSERT_GT(bytes.size(), 8u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    int width = 0, height = 0, channels = 0;
    unsigned char* pixels =
        stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                              int(bytes.size()), &width, &height, &channels, 3);
    ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
    EXPECT_EQ(width, 1100);
    EXPECT_EQ(height, 500);
    EXPECT_EQ(channels, 3);
    // The decoded pixels are the raster.
    const Image image = renderPreview(twoSpheresScene(), options);
    EXPECT_TRUE(std::equal(image.rgb.begin(), image.rgb.end(), pixels));
    stbi_image_free(pixels);
}

TEST(PreviewRenderer, ShowsBothSegmentColours) {
    const Image image = renderPreview(twoSpheresScene());
    ASSERT_EQ(image.width, 1536);
    ASSERT_EQ(image.height, 640);
    ASSERT_EQ(image.rgb.size(), std::size_t(1536) * 640 * 3);
    const int titleBar = 60;  // skip the swatches
    const std::size_t first = countShadesOf(image, segmentColour(1), titleBar);
    const std::size_t second = countShadesOf(image, segmentColour(2), titleBar);
    EXPECT_GT(first, 20000u);
    EXPECT_GT(second, 8000u);
    EXPECT_GT(first, second);  // the bigger sphere covers more pixels
    // Nothing of a third segment's colour.
    EXPECT_LT(countShadesOf(image, segmentColour(3), titleBar), 200u);
}

TEST(PreviewRenderer, DrawsCutLoopAndSkeleton) {
    PreviewScene scene = twoSpheresScene();
    PreviewScene bare = scene;
    bare.cutLoops.clear();
    bare.skeletonPoints.clear();
    bare.skeletonEdges.clear();
    const Image withLines = renderPreview(scene), without = renderPreview(bare);
    // The loop's yellow core shows in every view.
    for (int view = 0; view < 3; ++view) {
        const int x0 = view * 512, x1 = x0 + 512;
        EXPECT_GT(countNear(withLines, {255, 225, 25}, 40, x0, 50, x1, 640), 100u)
            << "view " << view;
        EXPECT_EQ(countNear(without, {255, 225, 25}, 40, x0, 50, x1, 640), 0u) << "view " << view;
    }
    // The skeleton, inside the spheres, still darkens the middle of the front
    // view (hidden lines at partial opacity).
    std::size_t differing = 0;
    for (int y = 100; y < 600; ++y)
        for (int x = 200; x < 312; ++x) {
            const std::size_t i = (std::size_t(y) * 1536 + std::size_t(x)) * 3;
            const int before = without.rgb[i] + without.rgb[i + 1] + without.rgb[i + 2];
            const int after = withLines.rgb[i] + withLines.rgb[i + 1] + withLines.rgb[i + 2];
            if (after + 60 < before) ++differing;
        }
    EXPECT_GT(differing, 300u);
}

TEST(PreviewRenderer, ItsMemoryEstimateCoversWhatARenderHolds) {
    // previewMemoryBytes is what --max-memory counts for preview.png: it must
    // cover what rendering and encoding hold, serial and on every thread,
    // for few and many triangles and for a larger picture, and stay within
    // twice that (an estimate far above would refuse runs that fit).
    const PreviewScene few = twoSpheresScene();
    PreviewScene manyTriangles = few;
    addSphere(manyTriangles, {2.5, 0.0, 0.0}, 0.9, 3, 100, 200);  // 40,000 triangles more
    PreviewOptions large;
    large.width = 2000;
    large.height = 800;
    const int threads = tbb::this_task_arena::max_concurrency();
    int checked = 0;
    const PreviewScene& many = manyTriangles;
    for (const PreviewScene* scene : {&few, &many})
        for (const PreviewOptions& size : {PreviewOptions{}, large})
            for (bool threaded : {false, true}) {
                PreviewOptions options = size;
                options.threaded = threaded;
                HeapPeak peak;
                const std::string png = encodePng(renderPreview(*scene, options));
                const std::int64_t held = peak.bytesAboveStart();
                const std::uint64_t estimate = previewMemoryBytes(options, scene->triangles.size(),
                                                                  scene->vertices.size(), threads);
                SCOPED_TRACE(::testing::Message()
                             << scene->triangles.size() << " triangles, " << options.width << "x"
                             << options.height << (threaded ? ", threaded" : ", serial"));
                ASSERT_FALSE(png.empty());
                EXPECT_GT(held, 0);
                EXPECT_LE(std::uint64_t(held), estimate);
                EXPECT_LE(estimate, 2 * std::uint64_t(held));
                ++checked;
            }
    EXPECT_EQ(checked, 8);
}

TEST(PreviewRenderer, SerialAndParallelGiveTheSameBytes) {
    PreviewScene scene = twoSpheresScene();
    addSphere(scene, {2.0, 0.5, -1.0}, 0.5, 7, 60, 120);
    PreviewOptions parallel, serial;
    serial.threaded = false;
    const Image a = renderPreview(scene, parallel), b = renderPreview(scene, serial);
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_EQ(encodePng(a), encodePng(b));
}

TEST(PreviewRenderer, VertexNoTriangleUsesDoesNotFrameTheViews) {
    // A mesh file's stray vertex a million units away shrank the shape to a
    // dot in every view: the framing took every vertex of the scene.
    const PreviewScene scene = twoSpheresScene();
    PreviewScene stray = scene;
    stray.vertices.push_back({1e6, 0.0, 0.0});
    EXPECT_EQ(renderPreview(stray).rgb, renderPreview(scene).rgb);
}

TEST(PreviewRenderer, EmptySceneRendersTitleOnly) {
    PreviewScene scene;
    scene.title = "empty.nrrd  parts: 0";
    const Image image = renderPreview(scene);
    ASSERT_EQ(image.rgb.size(), std::size_t(1536) * 640 * 3);
    EXPECT_GT(countDark(image, 0, 0, 700, 40), 50u);  // title text
    // No segment colour anywhere (label 0's grey is the background's hue).
    for (std::uint32_t label = 1; label <= 3; ++label)
        EXPECT_LT(countShadesOf(image, segmentColour(label), 50), 50u) << label;

    scene.title.clear();
    const Image blank = renderPreview(scene);
    EXPECT_EQ(countDark(blank, 0, 0, 1536, 40), 0u);
    test::TempDir dir;
    EXPECT_NO_THROW(renderPreviewPng(dir / "empty.png", scene));
    EXPECT_TRUE(std::filesystem::exists(dir / "empty.png"));
}

TEST(PreviewRenderer, LegendHasOneSwatchPerSegment) {
    PreviewScene scene;
    addSphere(scene, {0, 0, 0}, 1.0, 4);
    addSphere(scene, {3, 0, 0}, 1.0, 9);
    const Image image = renderPreview(scene);
    // The swatches are the only place in the title bar with segment colours.
    EXPECT_GT(countNear(image, {segmentColour(4)[0], segmentColour(4)[1], segmentColour(4)[2]}, 2,
                        0, 0, 1536, 40),
              40u);
    EXPECT_GT(countNear(image, {segmentColour(9)[0], segmentColour(9)[1], segmentColour(9)[2]}, 2,
                        0, 0, 1536, 40),
              40u);
    EXPECT_EQ(countNear(image, {segmentColour(1)[0], segmentColour(1)[1], segmentColour(1)[2]}, 2,
                        0, 0, 1536, 40),
              0u);
}

TEST(PreviewRenderer, RejectsBadInput) {
    PreviewScene scene;
    scene.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    scene.triangles = {{0, 1, 3}};
    EXPECT_THROW(renderPreview(scene), Error);
    scene.triangles = {{0, 1, 2}};
    scene.triangleLabels = {1, 2};
    EXPECT_THROW(renderPreview(scene), Error);
    scene.triangleLabels.clear();
    PreviewOptions tiny;
    tiny.width = 10;
    EXPECT_THROW(renderPreview(scene, tiny), Error);
    EXPECT_NO_THROW(renderPreview(scene));  // unlabelled: grey
}

/// Appends an axis-aligned box (12 triangles, outward winding).
void addBox(PreviewScene& scene, const Vec3& lo, const Vec3& hi, std::uint32_t label) {
    const auto first = std::uint32_t(scene.vertices.size());
    for (int k = 0; k < 8; ++k)
        scene.vertices.push_back(
            {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
    const std::uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        scene.triangles.push_back({first + f[0], first + f[1], first + f[2]});
        scene.triangles.push_back({first + f[0], first + f[2], first + f[3]});
        scene.triangleLabels.push_back(label);
        scene.triangleLabels.push_back(label);
    }
}

/// Bounding box (width, height) of the pixels of `image` in [x0, x1) that
/// are shades of `colour`.
std::array<int, 2> extentOfShades(const Image& image, const std::array<std::uint8_t, 3>& colour,
                                  int x0, int x1) {
    int minX = image.width, maxX = -1, minY = image.height, maxY = -1;
    const double c[3] = {double(colour[0]), double(colour[1]), double(colour[2])};
    const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    for (int y = 60; y < image.height; ++y)
        for (int x = x0; x < x1; ++x) {
            const std::uint8_t* p =
                &image.rgb[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3];
            const double s = (p[0] * c[0] + p[1] * c[1] + p[2] * c[2]) / cc;
            double residual = 0.0;
            for (int k = 0; k < 3; ++k) residual += (p[k] - s * c[k]) * (p[k] - s * c[k]);
            if (s < 0.3 || s > 1.15 || residual > 100.0) continue;
            minX = std::min(minX, x), maxX = std::max(maxX, x), minY = std::min(minY, y),
            maxY = std::max(maxY, y);
        }
    return {maxX - minX + 1, maxY - minY + 1};
}

TEST(PreviewRenderer, AutomaticOrientationPutsTheLongestSideUp) {
    PreviewScene scene;
    addBox(scene, {0, 0, 0}, {2, 1, 10}, 3);  // long along z, thin along y
    const Image automatic = renderPreview(scene);
    const auto front = extentOfShades(automatic, segmentColour(3), 0, 512);
    EXPECT_GT(front[1], 3 * front[0]) << front[0] << "x" << front[1];  // tall: z up, 10 by 2
    PreviewOptions yUp;
    yUp.upAxis = 1;
    const Image fixed = renderPreview(scene, yUp);
    const auto fixedFront =
        extentOfShades(fixed, segmentColour(3), 0, 512);  // from +z: the 2 by 1 end
    EXPECT_GT(fixedFront[0], fixedFront[1]) << fixedFront[0] << "x" << fixedFront[1];
    PreviewOptions bad;
    bad.upAxis = 3;
    EXPECT_THROW(renderPreview(scene, bad), Error);
}

TEST(PreviewRenderer, TextGlyphsAreComplete) {
    // Regression: the glyph "8" needs 9 font quads; a vertex buffer sized by
    // stb_easy_font's average use per character dropped its left strokes.
    // Its ink is 14 font cells (3 bars of 2, 4 strokes of 2), 2x2 pixels each
    // at the default width's text scale of 2.
    PreviewScene scene;
    scene.title = "8";
    EXPECT_EQ(countDark(renderPreview(scene), 0, 0, 200, 40), 14u * 4u);
}

TEST(PreviewRenderer, NonAsciiTitleAndManyLabelsAreSafe) {
    PreviewScene scene;
    for (std::uint32_t label = 1; label <= 150; ++label)
        addSphere(scene, {double(label % 15), double(label / 15), 0.0}, 0.4, label, 6, 12);
    scene.title = "f\xc3\xbcr \x01 \x7f title";
    const Image image = renderPreview(scene);
    EXPECT_EQ(image.width, 1536);
    EXPECT_GT(countDark(image, 0, 0, 1536, 40), 50u);
}

}  // namespace
}  // namespace skelseg
