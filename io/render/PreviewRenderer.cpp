#include "io/render/PreviewRenderer.h"

// stb in "static" mode: its functions stay private to this file, so another
// file of the project (or a test) may include its own copy without clashes.
#include <zlib.h>

#include <cstdlib>

namespace {
/// zlib's deflate for stb's PNG writer: several times faster than stb's own
/// and smaller files. Returns a malloc'ed buffer (stb frees it), or null.
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
#include <stb_easy_font.h>
#include <stb_image_write.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "io/files/OutputDirectory.h"
#include "io/render/Palette.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

// ---------------------------------------------------------------- vectors --

using Vec3 = std::array<double, 3>;
using Colour = std::array<float, 3>;  // 0..255 per channel while compositing

Vec3 operator+(const Vec3& a, const Vec3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3 operator-(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 operator*(double s, const Vec3& a) {
    return {s * a[0], s * a[1], s * a[2]};
}
double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 normalised(const Vec3& a) {
    const double length = std::sqrt(dot(a, a));
    return length > 0.0 ? (1.0 / length) * a : Vec3{0.0, 0.0, 0.0};
}
bool isFinite(const Vec3& a) {
    return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}

Colour mix(const Colour& a, const Colour& b, float t) {
    return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}
Colour toColour(const std::array<std::uint8_t, 3>& rgb) {
    return {float(rgb[0]), float(rgb[1]), float(rgb[2])};
}

// ------------------------------------------------------------- constants --

constexpr int kSupersample = 2;  // 2x2 samples per output pixel
constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

const Colour kTitleBackground = {255.0f, 255.0f, 255.0f};
const Colour kPanelTop = {250.0f, 250.0f, 251.0f};
const Colour kPanelBottom = {228.0f, 230.0f, 235.0f};
const Colour kSeparator = {205.0f, 207.0f, 212.0f};
const Colour kTextColour = {35.0f, 35.0f, 40.0f};
const Colour kCaptionColour = {110.0f, 112.0f, 120.0f};
const Colour kOutlineColour = {25.0f, 25.0f, 30.0f};
const Colour kSkeletonColour = {15.0f, 15.0f, 20.0f};
const Colour kCutOutlineColour = {0.0f, 0.0f, 0.0f};
const Colour kCutCoreColour = {255.0f, 225.0f, 25.0f};
constexpr double kAmbient = 0.36;

/// Runs body(i) for i in [0, count): TBB with grain 1 when threaded. Every
/// caller writes disjoint pixels per i, so the order never matters.
template <typename Body>
void forEachIndex(int count, bool threaded, const Body& body) {
    if (!threaded) {
        for (int i = 0; i < count; ++i) body(i);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, count, 1),
                      [&](const tbb::blocked_range<int>& range) {
                          for (int i = range.begin(); i != range.end(); ++i) body(i);
                      });
}

// ----------------------------------------------------------------- image --

/// Float RGB canvas used while compositing (both for the supersampled panels
/// and the final picture), so blends do not round at every step.
struct Canvas {
    int width = 0, height = 0;
    std::vector<Colour> pixels;
    Canvas(int w, int h, Colour fill)
        : width(w), height(h), pixels(std::size_t(w) * std::size_t(h), fill) {}
    Colour& at(int x, int y) {
        return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

void fillRectangle(Canvas& canvas, int x0, int y0, int x1, int y1, const Colour& colour,
                   float opacity = 1.0f) {
    x0 = std::max(x0, 0), y0 = std::max(y0, 0);
    x1 = std::min(x1, canvas.width), y1 = std::min(y1, canvas.height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) canvas.at(x, y) = mix(canvas.at(x, y), colour, opacity);
}

// ------------------------------------------------------------------ text --

std::string printable(const std::string& text) {
    std::string result = text;
    // stb_easy_font indexes a table by (char - 32) for chars 32..126 only.
    for (char& c : result)
        if (c < 32 || c > 126) c = '?';
    return result;
}

/// Width in pixels of `text` at integer `scale`.
int textWidth(const std::string& text, int scale) {
    std::string copy = printable(text);
    return stb_easy_font_width(copy.data()) * scale;
}

/// Draws one line of text with its top-left corner at (x, y). stb_easy_font
/// gives axis-aligned unit quads; at an integer scale they fill whole pixels,
/// which keeps the text crisp without anti-aliasing. Pixels right of
/// `clipRight` are left alone.
void drawText(Canvas& canvas, int x, int y, const std::string& text, int scale,
              const Colour& colour, int clipRight = std::numeric_limits<int>::max()) {
    std::string copy = printable(text);
    // Up to 11 quads of 64 bytes per character (the "X"); stb truncates silently.
    std::vector<char> vertexBuffer(copy.size() * 12 * 64 + 64);
    const int quads = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, vertexBuffer.data(),
                                          int(vertexBuffer.size()));
    constexpr std::size_t kVertexBytes = 16;  // x, y, z float + 4 colour bytes
    for (int q = 0; q < quads; ++q) {
        float minX = std::numeric_limits<float>::max(), minY = minX;
        float maxX = std::numeric_limits<float>::lowest(), maxY = maxX;
        for (int v = 0; v < 4; ++v) {
            float xy[2];
            std::memcpy(xy,
                        vertexBuffer.data() + (std::size_t(q) * 4 + std::size_t(v)) * kVertexBytes,
                        sizeof(xy));
            minX = std::min(minX, xy[0]), maxX = std::max(maxX, xy[0]);
            minY = std::min(minY, xy[1]), maxY = std::max(maxY, xy[1]);
        }
        const int x0 = x + int(std::lround(minX * float(scale))),
                  x1 = x + int(std::lround(maxX * float(scale)));
        const int y0 = y + int(std::lround(minY * float(scale))),
                  y1 = y + int(std::lround(maxY * float(scale)));
        fillRectangle(canvas, x0, y0, std::min(x1, clipRight), y1, colour);
    }
}

// ----------------------------------------------------------------- scene --

/// What every view shares: validated input, normals, extent.
struct PreparedScene {
    const PreviewScene* scene = nullptr;
    std::vector<std::array<float, 3>> faceNormals;    // unit, from the winding; zero if degenerate
    std::vector<std::array<float, 3>> vertexNormals;  // unit, area-weighted face normals
    std::vector<Vec3> framingPoints;                  // every finite point of the scene
    Vec3 centre{0.0, 0.0, 0.0};
    Vec3 extent{0.0, 0.0, 0.0};  // bounding box size
    double diagonal = 1.0;
    std::vector<std::uint32_t> labels;  // distinct nonzero triangle labels, increasing
};

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

PreparedScene prepare(const PreviewScene& scene, bool threaded) {
    PreparedScene prepared;
    prepared.scene = &scene;
    const std::size_t triangleCount = scene.triangles.size();

    prepared.faceNormals.resize(triangleCount);
    std::vector<Vec3> weightedNormals(triangleCount);
    const int chunks = int((triangleCount + 65535) / 65536);
    forEachIndex(chunks, threaded, [&](int chunk) {
        const std::size_t end = std::min(triangleCount, std::size_t(chunk + 1) * 65536);
        for (std::size_t t = std::size_t(chunk) * 65536; t < end; ++t) {
            const auto& tri = scene.triangles[t];
            const Vec3 n = cross(scene.vertices[tri[1]] - scene.vertices[tri[0]],
                                 scene.vertices[tri[2]] - scene.vertices[tri[0]]);
            weightedNormals[t] = isFinite(n) ? n : Vec3{0.0, 0.0, 0.0};
            const Vec3 unit = normalised(weightedNormals[t]);
            prepared.faceNormals[t] = {float(unit[0]), float(unit[1]), float(unit[2])};
        }
    });
    // Serial sum: floating-point addition order must not depend on threads.
    std::vector<Vec3> vertexSums(scene.vertices.size(), Vec3{0.0, 0.0, 0.0});
    for (std::size_t t = 0; t < triangleCount; ++t)
        for (std::uint32_t corner : scene.triangles[t])
            vertexSums[corner] = vertexSums[corner] + weightedNormals[t];
    prepared.vertexNormals.resize(scene.vertices.size());
    for (std::size_t v = 0; v < vertexSums.size(); ++v) {
        const Vec3 unit = normalised(vertexSums[v]);
        prepared.vertexNormals[v] = {float(unit[0]), float(unit[1]), float(unit[2])};
    }

    auto addPoint = [&](const Vec3& p) {
        if (isFinite(p)) prepared.framingPoints.push_back(p);
    };
    prepared.framingPoints.reserve(scene.vertices.size() + scene.skeletonPoints.size());
    for (const auto& p : scene.vertices) addPoint(p);
    for (const auto& p : scene.skeletonPoints) addPoint(p);
    for (const auto& loop : scene.cutLoops)
        for (const auto& p : loop) addPoint(p);
    if (!prepared.framingPoints.empty()) {
        Vec3 lo = prepared.framingPoints.front(), hi = lo;
        for (const auto& p : prepared.framingPoints)
            for (int a = 0; a < 3; ++a)
                lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
        prepared.centre = 0.5 * (lo + hi);
        prepared.extent = hi - lo;
        prepared.diagonal = std::sqrt(dot(hi - lo, hi - lo));
        if (!(prepared.diagonal > 0.0)) prepared.diagonal = 1.0;
    }

    std::vector<std::uint32_t> labels(scene.triangleLabels);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    if (!labels.empty() && labels.front() == 0) labels.erase(labels.begin());
    prepared.labels = std::move(labels);
    return prepared;
}

// ------------------------------------------------------------------ views --

struct View {
    std::string caption;
    Vec3 right, up, towardScene;  // orthonormal; towardScene = viewing direction
};

/// Front, side and 3/4-above views (see PreviewOptions::upAxis). `extent`:
/// size of the scene's bounding box, used by the automatic choice.
std::array<View, 3> makeViews(int upAxis, const Vec3& extent) {
    int upIndex = upAxis, frontIndex = 0, sideIndex = 0;
    if (upAxis < 0) {
        // Longest axis up (the panels are taller than wide), shortest axis
        // towards the camera (the front view shows the broadest outline).
        // Stable order y, z, x decides ties, so a cube keeps y up.
        std::array<int, 3> axes{1, 2, 0};
        std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) {
            return extent[std::size_t(a)] > extent[std::size_t(b)];
        });
        upIndex = axes[0], sideIndex = axes[1], frontIndex = axes[2];
    } else {
        frontIndex = upAxis == 2 ? 1 : 2;
        sideIndex = upAxis == 0 ? 1 : 0;
    }
    Vec3 up{0, 0, 0}, front{0, 0, 0}, side{0, 0, 0};
    up[std::size_t(upIndex)] = 1.0;
    front[std::size_t(frontIndex)] = 1.0;
    side[std::size_t(sideIndex)] = 1.0;
    const char axisNames[3] = {'x', 'y', 'z'};
    const std::string upText = std::string(", ") + axisNames[upIndex] + " up";
    auto viewFrom = [&](const std::string& caption, const Vec3& cameraSide) {
        View view;
        view.caption = caption;
        view.towardScene = normalised(-1.0 * cameraSide);
        view.right = normalised(cross(view.towardScene, up));
        view.up = cross(view.right, view.towardScene);
        return view;
    };
    // 3/4 view: azimuth half way between front and side, 30 degrees up.
    const double elevation = 30.0 * 3.14159265358979323846 / 180.0;
    const Vec3 oblique = std::cos(elevation) * normalised(front + side) + std::sin(elevation) * up;
    return {viewFrom(std::string("front: from +") + axisNames[frontIndex] + upText, front),
            viewFrom(std::string("side: from +") + axisNames[sideIndex] + upText, side),
            viewFrom("3/4 from above", oblique)};
}

/// One view rendered at kSupersample times the panel's resolution.
class PanelRenderer {
public:
    PanelRenderer(const PreparedScene& prepared, const View& view, int panelWidth, int panelHeight,
                  int captionSpace, double lineScale, bool threaded)
        : mPrepared(prepared),
          mScene(*prepared.scene),
          mView(view),
          mWidth(panelWidth * kSupersample),
          mHeight(panelHeight * kSupersample),
          mLineScale(lineScale * kSupersample),
          mThreaded(threaded),
          mDepth(std::size_t(mWidth) * std::size_t(mHeight),
                 std::numeric_limits<float>::infinity()),
          mTriangle(std::size_t(mWidth) * std::size_t(mHeight), kNoTriangle) {
        frame(captionSpace * kSupersample);
        // Key light just above-left of the camera: a pure headlight makes every
        // face pointing at the viewer equally bright and the shape looks flat.
        mLight = normalised(-1.0 * mView.towardScene + 0.45 * mView.up - 0.30 * mView.right);
        mHalfway = normalised(mLight - mView.towardScene);
    }

    /// Renders and returns the supersampled canvas.
    Canvas render() {
        projectVertices();
        rasteriseTriangles();
        Canvas canvas(mWidth, mHeight, kPanelTop);
        shade(canvas);
        drawLines(canvas);
        return canvas;
    }

private:
    struct ScreenPoint {
        double x, y, depth;
    };

    ScreenPoint project(const Vec3& world) const {
        const Vec3 p = world - mPrepared.centre;
        return {mOriginX + dot(p, mView.right) * mScale, mOriginY - dot(p, mView.up) * mScale,
                dot(p, mView.towardScene)};
    }

    /// Scale and offset so the projection of every scene point fits the panel
    /// with a margin, above the caption line.
    void frame(int captionSpace) {
        double minX = 0.0, maxX = 0.0, minY = 0.0, maxY = 0.0;
        bool first = true;
        for (const auto& world : mPrepared.framingPoints) {
            const Vec3 p = world - mPrepared.centre;
            const double x = dot(p, mView.right), y = dot(p, mView.up);
            if (first) minX = maxX = x, minY = maxY = y, first = false;
            minX = std::min(minX, x), maxX = std::max(maxX, x);
            minY = std::min(minY, y), maxY = std::max(maxY, y);
        }
        const double margin = 0.06 * std::min(mWidth, mHeight);
        const double usableWidth = std::max(1.0, mWidth - 2.0 * margin);
        const double usableHeight = std::max(1.0, mHeight - 2.0 * margin - captionSpace);
        const double extentX = std::max(maxX - minX, 1e-9 * mPrepared.diagonal);
        const double extentY = std::max(maxY - minY, 1e-9 * mPrepared.diagonal);
        mScale = std::min(usableWidth / extentX, usableHeight / extentY);
        if (!std::isfinite(mScale) || mScale <= 0.0) mScale = 1.0;
        mOriginX = 0.5 * mWidth - 0.5 * (minX + maxX) * mScale;
        mOriginY = margin + 0.5 * usableHeight + 0.5 * (minY + maxY) * mScale;
    }

    void projectVertices() {
        const std::size_t count = mScene.vertices.size();
        mScreen.resize(count);
        const int chunks = int((count + 65535) / 65536);
        forEachIndex(chunks, mThreaded, [&](int chunk) {
            const std::size_t end = std::min(count, std::size_t(chunk + 1) * 65536);
            for (std::size_t v = std::size_t(chunk) * 65536; v < end; ++v)
                mScreen[v] = project(mScene.vertices[v]);
        });
        // Rows each triangle may touch, then the triangles of each band of
        // rows (CSR, in index order): a band reads only its own triangles.
        const std::size_t triangles = mScene.triangles.size();
        std::vector<std::array<int, 2>> rowRange(triangles);
        const int triangleChunks = int((triangles + 65535) / 65536);
        forEachIndex(triangleChunks, mThreaded, [&](int chunk) {
            const std::size_t end = std::min(triangles, std::size_t(chunk + 1) * 65536);
            for (std::size_t t = std::size_t(chunk) * 65536; t < end; ++t) {
                const auto& tri = mScene.triangles[t];
                const double lo =
                    std::min({mScreen[tri[0]].y, mScreen[tri[1]].y, mScreen[tri[2]].y});
                const double hi =
                    std::max({mScreen[tri[0]].y, mScreen[tri[1]].y, mScreen[tri[2]].y});
                const double left =
                    std::min({mScreen[tri[0]].x, mScreen[tri[1]].x, mScreen[tri[2]].x});
                const double right =
                    std::max({mScreen[tri[0]].x, mScreen[tri[1]].x, mScreen[tri[2]].x});
                if (!(lo <= hi) || !(left <= right) || hi < 0.0 || lo >= mHeight || right < 0.0 ||
                    left >= mWidth) {
                    rowRange[t] = {1, 0};  // off the panel, or NaN
                    continue;
                }
                rowRange[t] = {int(std::max(0.0, std::floor(lo))),
                               int(std::min(double(mHeight - 1), std::ceil(hi)))};
            }
        });
        const int bands = (mHeight + kBandRows - 1) / kBandRows;
        mBandStart.assign(std::size_t(bands) + 1, 0);
        for (const auto& rows : rowRange)
            if (rows[0] <= rows[1])
                for (int band = rows[0] / kBandRows; band <= rows[1] / kBandRows; ++band)
                    ++mBandStart[std::size_t(band) + 1];
        for (std::size_t band = 0; band < std::size_t(bands); ++band)
            mBandStart[band + 1] += mBandStart[band];
        mBandTriangles.resize(mBandStart.back());
        std::vector<std::size_t> next(mBandStart.begin(), mBandStart.end() - 1);
        for (std::size_t t = 0; t < triangles; ++t) {
            const auto& rows = rowRange[t];
            if (rows[0] <= rows[1])
                for (int band = rows[0] / kBandRows; band <= rows[1] / kBandRows; ++band)
                    mBandTriangles[next[std::size_t(band)]++] = std::uint32_t(t);
        }
    }

    static double edge(const ScreenPoint& a, const ScreenPoint& b, double x, double y) {
        return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
    }

    /// Z-buffer pass: nearest triangle index and depth per sample. Bands of
    /// rows run in parallel; within a band triangles go in index order and a
    /// tie keeps the earlier one, so the result does not depend on threads.
    /// Samples on a shared edge belong to both triangles (no cracks).
    void rasteriseTriangles() {
        const int bands = int(mBandStart.size()) - 1;
        forEachIndex(bands, mThreaded, [&](int band) {
            const int bandBegin = band * kBandRows,
                      bandEnd = std::min(mHeight, bandBegin + kBandRows);
            for (std::size_t k = mBandStart[std::size_t(band)];
                 k < mBandStart[std::size_t(band) + 1]; ++k) {
                const std::uint32_t t = mBandTriangles[k];
                const auto& tri = mScene.triangles[t];
                ScreenPoint a = mScreen[tri[0]], b = mScreen[tri[1]], c = mScreen[tri[2]];
                double area = edge(a, b, c.x, c.y);
                if (!(std::fabs(area) > 1e-12)) continue;  // degenerate or NaN
                if (area < 0.0) std::swap(b, c), area = -area;
                const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
                const int x1 = std::min(mWidth - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
                const int y0 = std::max(bandBegin, int(std::floor(std::min({a.y, b.y, c.y}))));
                const int y1 = std::min(bandEnd - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
                const double inverseArea = 1.0 / area;
                for (int y = y0; y <= y1; ++y) {
                    const double sy = y + 0.5;
                    for (int x = x0; x <= x1; ++x) {
                        const double sx = x + 0.5;
                        const double w0 = edge(b, c, sx, sy), w1 = edge(c, a, sx, sy),
                                     w2 = edge(a, b, sx, sy);
                        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
                        const auto depth =
                            float((w0 * a.depth + w1 * b.depth + w2 * c.depth) * inverseArea);
                        const std::size_t i = std::size_t(y) * std::size_t(mWidth) + std::size_t(x);
                        if (depth < mDepth[i]) {
                            mDepth[i] = depth;
                            mTriangle[i] = t;
                        }
                    }
                }
            }
        });
    }

    std::uint32_t labelOf(std::uint32_t triangle) const {
        return mScene.triangleLabels.empty() ? 0u : mScene.triangleLabels[triangle];
    }

    /// Per-triangle shading inputs, set up once per run of samples that hit
    /// the same triangle.
    struct TriangleShading {
        std::uint32_t triangle = kNoTriangle;
        ScreenPoint a{}, b{}, c{};
        double inverseArea = 0.0;
        Vec3 cornerNormals[3] = {};
        Colour base{};
    };

    void setUp(TriangleShading& shading, std::uint32_t t) const {
        const auto& tri = mScene.triangles[t];
        shading.triangle = t;
        shading.a = mScreen[tri[0]], shading.b = mScreen[tri[1]], shading.c = mScreen[tri[2]];
        shading.inverseArea = 1.0 / edge(shading.a, shading.b, shading.c.x, shading.c.y);
        const auto& f = mPrepared.faceNormals[t];
        const Vec3 faceNormal{double(f[0]), double(f[1]), double(f[2])};
        // Two-sided: turn the normals towards the camera.
        const double facing = dot(faceNormal, mView.towardScene) > 0.0 ? -1.0 : 1.0;
        // Per-corner normal: the vertex's smooth normal unless the surface
        // bends by more than 45 degrees there (a crease, or a neighbour wound
        // the other way), where the face's own normal keeps the edge sharp.
        for (std::size_t k = 0; k < 3; ++k) {
            const auto& vn = mPrepared.vertexNormals[tri[k]];
            const Vec3 vertexNormal{double(vn[0]), double(vn[1]), double(vn[2])};
            shading.cornerNormals[k] =
                facing * (dot(vertexNormal, faceNormal) > 0.7071 ? vertexNormal : faceNormal);
        }
        shading.base = toColour(segmentColour(labelOf(t)));
    }

    Colour shadeSample(const TriangleShading& shading, int x, int y) const {
        const double sx = x + 0.5, sy = y + 0.5;
        const double w0 =
            std::clamp(edge(shading.b, shading.c, sx, sy) * shading.inverseArea, 0.0, 1.0);
        const double w1 =
            std::clamp(edge(shading.c, shading.a, sx, sy) * shading.inverseArea, 0.0, 1.0);
        const double w2 =
            std::clamp(edge(shading.a, shading.b, sx, sy) * shading.inverseArea, 0.0, 1.0);
        const Vec3 normal =
            normalised(w0 * shading.cornerNormals[0] + w1 * shading.cornerNormals[1] +
                       w2 * shading.cornerNormals[2]);
        const double diffuse = std::max(0.0, dot(normal, mLight));
        const double h = std::max(0.0, dot(normal, mHalfway));
        const double h3 = h * h * h, h6 = h3 * h3, h12 = h6 * h6, h24 = h12 * h12;
        const double specular = h24 * h24;  // h^48: a small, tight highlight
        const auto intensity = float(kAmbient + (1.0 - kAmbient) * diffuse);
        const auto highlight = float(0.18 * 255.0 * specular);
        return {std::min(255.0f, shading.base[0] * intensity + highlight),
                std::min(255.0f, shading.base[1] * intensity + highlight),
                std::min(255.0f, shading.base[2] * intensity + highlight)};
    }

    /// Colours every sample from the z-buffer and outlines silhouettes, depth
    /// jumps (dark) and segment boundaries (lighter).
    void shade(Canvas& canvas) const {
        const double depthJump = 0.02 * mPrepared.diagonal;
        const int rowsPerTask = 32;
        forEachIndex((mHeight + rowsPerTask - 1) / rowsPerTask, mThreaded, [&](int task) {
            TriangleShading shading;
            const int yEnd = std::min(mHeight, (task + 1) * rowsPerTask);
            for (int y = task * rowsPerTask; y < yEnd; ++y) {
                const float rowFraction = float(y) / float(std::max(1, mHeight - 1));
                const Colour background = mix(kPanelTop, kPanelBottom, rowFraction);
                for (int x = 0; x < mWidth; ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(mWidth) + std::size_t(x);
                    const std::uint32_t t = mTriangle[i];
                    if (t == kNoTriangle) {
                        canvas.at(x, y) = background;
                        continue;
                    }
                    if (t != shading.triangle) setUp(shading, t);
                    const Colour colour = shadeSample(shading, x, y);
                    // Silhouettes and depth jumps look two samples out (one
                    // output pixel after downsampling), segment boundaries one.
                    float outline = 0.0f;
                    static constexpr int kOffsets[8][3] = {{-1, 0, 1}, {1, 0, 1},  {0, -1, 1},
                                                           {0, 1, 1},  {-2, 0, 2}, {2, 0, 2},
                                                           {0, -2, 2}, {0, 2, 2}};
                    for (const auto& offset : kOffsets) {
                        const int nx = x + offset[0], ny = y + offset[1];
                        if (nx < 0 || ny < 0 || nx >= mWidth || ny >= mHeight) continue;
                        const std::size_t j =
                            std::size_t(ny) * std::size_t(mWidth) + std::size_t(nx);
                        const std::uint32_t other = mTriangle[j];
                        if (other == t) continue;
                        if (other == kNoTriangle ||
                            double(mDepth[j]) < double(mDepth[i]) - depthJump)
                            outline = std::max(outline, 0.8f);
                        else if (offset[2] == 1 && labelOf(other) != labelOf(t))
                            outline = std::max(outline, 0.45f);
                    }
                    canvas.at(x, y) =
                        outline > 0.0f ? mix(colour, kOutlineColour, outline) : colour;
                }
            }
        });
    }

    /// Coverage of a round-capped segment of radius `radius` into `layer`
    /// (max, so joints of a polyline are not darkened twice). Samples where
    /// the segment lies behind the surface by more than `bias` get
    /// `hiddenOpacity` of the coverage.
    void drawSegment(std::vector<float>& layer, const ScreenPoint& a, const ScreenPoint& b,
                     double radius, double bias, float hiddenOpacity) const {
        if (!std::isfinite(a.x + a.y + a.depth + b.x + b.y + b.depth)) return;
        const int x0 = std::max(0, int(std::floor(std::min(a.x, b.x) - radius - 1.0)));
        const int x1 = std::min(mWidth - 1, int(std::ceil(std::max(a.x, b.x) + radius + 1.0)));
        const int y0 = std::max(0, int(std::floor(std::min(a.y, b.y) - radius - 1.0)));
        const int y1 = std::min(mHeight - 1, int(std::ceil(std::max(a.y, b.y) + radius + 1.0)));
        const double dx = b.x - a.x, dy = b.y - a.y;
        const double lengthSquared = dx * dx + dy * dy;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double px = x + 0.5 - a.x, py = y + 0.5 - a.y;
                const double t = lengthSquared > 1e-12
                                     ? std::clamp((px * dx + py * dy) / lengthSquared, 0.0, 1.0)
                                     : 0.0;
                const double ex = px - t * dx, ey = py - t * dy;
                const double coverage =
                    std::clamp(radius + 0.5 - std::sqrt(ex * ex + ey * ey), 0.0, 1.0);
                if (coverage <= 0.0) continue;
                const std::size_t i = std::size_t(y) * std::size_t(mWidth) + std::size_t(x);
                const double depth = a.depth + t * (b.depth - a.depth);
                const bool visible = depth <= double(mDepth[i]) + bias;
                const float opacity = float(coverage) * (visible ? 1.0f : hiddenOpacity);
                layer[i] = std::max(layer[i], opacity);
            }
    }

    void drawLines(Canvas& canvas) const {
        const bool hasSkeleton = !mScene.skeletonPoints.empty();
        const bool hasCuts = !mScene.cutLoops.empty();
        if (!hasSkeleton && !hasCuts) return;
        const std::size_t samples = std::size_t(mWidth) * std::size_t(mHeight);
        std::vector<float> skeleton(hasSkeleton ? samples : 0, 0.0f);
        std::vector<float> cutOutline(hasCuts ? samples : 0, 0.0f),
            cutCore(hasCuts ? samples : 0, 0.0f);

        if (hasSkeleton) {
            std::vector<ScreenPoint> points(mScene.skeletonPoints.size());
            std::vector<bool> onEdge(points.size(), false);
            for (std::size_t p = 0; p < points.size(); ++p)
                points[p] = project(mScene.skeletonPoints[p]);
            const double radius = 0.85 * mLineScale;
            // The skeleton is inside the shape: hidden parts are drawn at
            // partial opacity rather than not at all.
            for (const auto& e : mScene.skeletonEdges) {
                drawSegment(skeleton, points[e[0]], points[e[1]], radius, 0.0, 0.55f);
                onEdge[e[0]] = onEdge[e[1]] = true;
            }
            for (std::size_t p = 0; p < points.size(); ++p)
                if (!onEdge[p])
                    drawSegment(skeleton, points[p], points[p], 2.0 * radius, 0.0, 0.55f);
        }
        if (hasCuts) {
            // Loops lie on the surface (or half a voxel inside it): a bias of
            // 1.5% of the scene keeps their visible part from flickering
            // against the z-buffer, while loops on the far side stay hidden.
            const double bias = 0.015 * mPrepared.diagonal;
            const double outlineRadius = 3.2 * mLineScale, coreRadius = 1.7 * mLineScale;
            for (const auto& loop : mScene.cutLoops) {
                const std::size_t n = loop.size();
                for (std::size_t k = 0; k < n; ++k) {
                    if (n == 2 && k == 1) break;  // one segment, not the same one twice
                    const ScreenPoint a = project(loop[k]), b = project(loop[(k + 1) % n]);
                    drawSegment(cutOutline, a, b, outlineRadius, bias, 0.0f);
                    drawSegment(cutCore, a, b, coreRadius, bias, 0.0f);
                }
            }
        }
        for (std::size_t i = 0; i < samples; ++i) {
            Colour& colour = canvas.pixels[i];
            if (hasSkeleton && skeleton[i] > 0.0f)
                colour = mix(colour, kSkeletonColour, 0.9f * skeleton[i]);
            if (hasCuts && cutOutline[i] > 0.0f) {
                colour = mix(colour, kCutOutlineColour, cutOutline[i]);
                colour = mix(colour, kCutCoreColour, cutCore[i]);
            }
        }
    }

    const PreparedScene& mPrepared;
    const PreviewScene& mScene;
    View mView;
    int mWidth, mHeight;
    double mLineScale;
    bool mThreaded;
    double mScale = 1.0, mOriginX = 0.0, mOriginY = 0.0;
    Vec3 mLight{0.0, 0.0, 1.0}, mHalfway{0.0, 0.0, 1.0};
    std::vector<float> mDepth;
    std::vector<std::uint32_t> mTriangle;
    std::vector<ScreenPoint> mScreen;
    static constexpr int kBandRows = 32;
    std::vector<std::size_t> mBandStart;        // bands + 1 offsets into mBandTriangles
    std::vector<std::uint32_t> mBandTriangles;  // triangles touching each band, in index order
};

/// Averages each kSupersample^2 block of `panel` into `target` at (left, top).
void downsampleInto(const Canvas& panel, Canvas& target, int left, int top) {
    const int width = panel.width / kSupersample, height = panel.height / kSupersample;
    const float weight = 1.0f / float(kSupersample * kSupersample);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Colour sum{0.0f, 0.0f, 0.0f};
            for (int sy = 0; sy < kSupersample; ++sy)
                for (int sx = 0; sx < kSupersample; ++sx) {
                    const Colour& c =
                        panel.pixels[std::size_t(y * kSupersample + sy) * std::size_t(panel.width) +
                                     std::size_t(x * kSupersample + sx)];
                    sum = {sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]};
                }
            target.at(left + x, top + y) = {sum[0] * weight, sum[1] * weight, sum[2] * weight};
        }
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

Image toImage(const Canvas& canvas) {
    Image image;
    image.width = canvas.width;
    image.height = canvas.height;
    image.rgb.resize(canvas.pixels.size() * 3);
    for (std::size_t i = 0; i < canvas.pixels.size(); ++i)
        for (std::size_t c = 0; c < 3; ++c)
            image.rgb[3 * i + c] =
                std::uint8_t(std::clamp(canvas.pixels[i][c], 0.0f, 255.0f) + 0.5f);
    return image;
}

}  // namespace

Image renderPreview(const PreviewScene& scene, const PreviewOptions& options) {
    validate(scene, options);
    const PreparedScene prepared = prepare(scene, options.threaded);
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
    forEachIndex(3, options.threaded, [&](int v) {
        const int panelWidth = panelLeft[std::size_t(v) + 1] - panelLeft[std::size_t(v)];
        PanelRenderer renderer(prepared, views[std::size_t(v)], panelWidth, panelHeight,
                               captionSpace, lineScale, options.threaded);
        downsampleInto(renderer.render(), canvas, panelLeft[std::size_t(v)], panelTop);
    });
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
