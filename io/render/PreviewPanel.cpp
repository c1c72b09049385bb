#include "io/render/PreviewPanel.h"

#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/render/Palette.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg::preview {

namespace {

constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();
/// Vertices and triangles per task when threaded.
constexpr std::size_t kChunk = 65536;

const Colour kSkeletonColour = {15.0f, 15.0f, 20.0f};
const Colour kCutOutlineColour = {0.0f, 0.0f, 0.0f};
const Colour kCutCoreColour = {255.0f, 225.0f, 25.0f};
constexpr double kAmbient = 0.36;

Eigen::Vector3d point(const std::array<double, 3>& p) {
    return {p[0], p[1], p[2]};
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
        mLight = (-towardScene() + 0.45 * up() - 0.30 * right()).normalized();
        mHalfway = (mLight - towardScene()).normalized();
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

    Eigen::Vector3d right() const { return mView.worldToCamera.row(0).transpose(); }
    Eigen::Vector3d up() const { return mView.worldToCamera.row(1).transpose(); }
    Eigen::Vector3d towardScene() const { return mView.worldToCamera.row(2).transpose(); }

    ScreenPoint project(const std::array<double, 3>& world) const {
        const Eigen::Vector3d camera = mView.worldToCamera * (point(world) - mPrepared.centre);
        return {mOriginX + camera.x() * mScale, mOriginY - camera.y() * mScale, camera.z()};
    }

    /// Scale and offset so the projection of every scene point fits the panel
    /// with a margin, above the caption line.
    void frame(int captionSpace) {
        double minX = 0.0, maxX = 0.0, minY = 0.0, maxY = 0.0;
        bool first = true;
        for (const auto& world : mPrepared.framingPoints) {
            const Eigen::Vector3d camera = mView.worldToCamera * (world - mPrepared.centre);
            const double x = camera.x(), y = camera.y();
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
        parallelForEach(
            count, [&](std::size_t v) { mScreen[v] = project(mScene.vertices[v]); }, mThreaded,
            kChunk);
        // Rows each triangle may touch, then the triangles of each band of
        // rows (CSR, in index order): a band reads only its own triangles.
        const std::size_t triangles = mScene.triangles.size();
        std::vector<std::array<int, 2>> rowRange(triangles);
        parallelFor(
            triangles,
            [&](std::size_t begin, std::size_t end) {
                for (std::size_t t = begin; t < end; ++t) {
                    const auto& tri = mScene.triangles[t];
                    const double lo =
                        std::min({mScreen[tri[0]].y, mScreen[tri[1]].y, mScreen[tri[2]].y});
                    const double hi =
                        std::max({mScreen[tri[0]].y, mScreen[tri[1]].y, mScreen[tri[2]].y});
                    const double left =
                        std::min({mScreen[tri[0]].x, mScreen[tri[1]].x, mScreen[tri[2]].x});
                    const double right =
                        std::max({mScreen[tri[0]].x, mScreen[tri[1]].x, mScreen[tri[2]].x});
                    if (!(lo <= hi) || !(left <= right) || hi < 0.0 || lo >= mHeight ||
                        right < 0.0 || left >= mWidth) {
                        rowRange[t] = {1, 0};  // off the panel, or NaN
                        continue;
                    }
                    rowRange[t] = {int(std::max(0.0, std::floor(lo))),
                                   int(std::min(double(mHeight - 1), std::ceil(hi)))};
                }
            },
            mThreaded, kChunk);
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
        parallelForEach(
            bands,
            [&](int band) {
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
                        // Only the row's span inside the triangle, widened by
                        // a pixel for rounding; the exact test below still
                        // decides, so the pixels are those of a scan of the
                        // whole box. A thin triangle across the picture (the
                        // sides of a cone round a vertex of 100,000 faces)
                        // took the whole box's tests per row.
                        int spanBegin = x0, spanEnd = x1;
                        double low = -HUGE_VAL, high = HUGE_VAL;
                        const ScreenPoint* corners[3][2] = {{&b, &c}, {&c, &a}, {&a, &b}};
                        for (const auto& side : corners) {
                            const ScreenPoint& p = *side[0];
                            const ScreenPoint& q = *side[1];
                            const double dy = q.y - p.y, reach = (q.x - p.x) * (sy - p.y);
                            if (dy > 0.0)
                                high = std::min(high, p.x + reach / dy);
                            else if (dy < 0.0)
                                low = std::max(low, p.x + reach / dy);
                        }
                        // Clamped before the conversion: a bound far off the
                        // picture (a nearly horizontal side) overflows int.
                        if (std::isfinite(low))
                            spanBegin =
                                std::max(x0, int(std::clamp(std::floor(low), -1e9, 1e9)) - 1);
                        if (std::isfinite(high))
                            spanEnd = std::min(x1, int(std::clamp(std::ceil(high), -1e9, 1e9)) + 1);
                        for (int x = spanBegin; x <= spanEnd; ++x) {
                            const double sx = x + 0.5;
                            const double w0 = edge(b, c, sx, sy), w1 = edge(c, a, sx, sy),
                                         w2 = edge(a, b, sx, sy);
                            if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
                            const auto depth =
                                float((w0 * a.depth + w1 * b.depth + w2 * c.depth) * inverseArea);
                            const std::size_t i =
                                std::size_t(y) * std::size_t(mWidth) + std::size_t(x);
                            if (depth < mDepth[i]) {
                                mDepth[i] = depth;
                                mTriangle[i] = t;
                            }
                        }
                    }
                }
            },
            mThreaded);
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
        Eigen::Vector3d cornerNormals[3] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                            Eigen::Vector3d::Zero()};
        Colour base{};
    };

    void setUp(TriangleShading& shading, std::uint32_t t) const {
        const auto& tri = mScene.triangles[t];
        shading.triangle = t;
        shading.a = mScreen[tri[0]], shading.b = mScreen[tri[1]], shading.c = mScreen[tri[2]];
        shading.inverseArea = 1.0 / edge(shading.a, shading.b, shading.c.x, shading.c.y);
        const auto& f = mPrepared.faceNormals[t];
        const Eigen::Vector3d faceNormal{double(f[0]), double(f[1]), double(f[2])};
        // Two-sided: turn the normals towards the camera.
        const double facing = faceNormal.dot(towardScene()) > 0.0 ? -1.0 : 1.0;
        // Per-corner normal: the vertex's smooth normal unless the surface
        // bends by more than 45 degrees there (a crease, or a neighbour wound
        // the other way), where the face's own normal keeps the edge sharp.
        for (std::size_t k = 0; k < 3; ++k) {
            const auto& vn = mPrepared.vertexNormals[tri[k]];
            const Eigen::Vector3d vertexNormal{double(vn[0]), double(vn[1]), double(vn[2])};
            shading.cornerNormals[k] =
                facing * (vertexNormal.dot(faceNormal) > 0.7071 ? vertexNormal : faceNormal);
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
        const Eigen::Vector3d normal =
            (w0 * shading.cornerNormals[0] + w1 * shading.cornerNormals[1] +
             w2 * shading.cornerNormals[2])
                .normalized();
        const double diffuse = std::max(0.0, normal.dot(mLight));
        const double h = std::max(0.0, normal.dot(mHalfway));
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
        parallelForEach(
            (mHeight + rowsPerTask - 1) / rowsPerTask,
            [&](int task) {
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
            },
            mThreaded);
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
    Eigen::Vector3d mLight = Eigen::Vector3d::UnitZ(), mHalfway = Eigen::Vector3d::UnitZ();
    std::vector<float> mDepth;
    std::vector<std::uint32_t> mTriangle;
    std::vector<ScreenPoint> mScreen;
    static constexpr int kBandRows = 32;
    std::vector<std::size_t> mBandStart;        // bands + 1 offsets into mBandTriangles
    std::vector<std::uint32_t> mBandTriangles;  // triangles touching each band, in index order
};

}  // namespace

PreparedScene prepareScene(const PreviewScene& scene, bool threaded) {
    PreparedScene prepared;
    prepared.scene = &scene;
    const std::size_t triangleCount = scene.triangles.size();

    prepared.faceNormals.resize(triangleCount);
    std::vector<Eigen::Vector3d> weightedNormals(triangleCount);
    parallelFor(
        triangleCount,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t t = begin; t < end; ++t) {
                const auto& tri = scene.triangles[t];
                const Eigen::Vector3d corner = point(scene.vertices[tri[0]]);
                const Eigen::Vector3d n = (point(scene.vertices[tri[1]]) - corner)
                                              .cross(point(scene.vertices[tri[2]]) - corner);
                weightedNormals[t] = n.allFinite() ? n : Eigen::Vector3d::Zero();
                const Eigen::Vector3d unit = weightedNormals[t].normalized();
                prepared.faceNormals[t] = {float(unit[0]), float(unit[1]), float(unit[2])};
            }
        },
        threaded, kChunk);
    // Serial sum: floating-point addition order must not depend on threads.
    std::vector<Eigen::Vector3d> vertexSums(scene.vertices.size(), Eigen::Vector3d::Zero());
    for (std::size_t t = 0; t < triangleCount; ++t)
        for (std::uint32_t corner : scene.triangles[t]) vertexSums[corner] += weightedNormals[t];
    prepared.vertexNormals.resize(scene.vertices.size());
    for (std::size_t v = 0; v < vertexSums.size(); ++v) {
        const Eigen::Vector3d unit = vertexSums[v].normalized();
        prepared.vertexNormals[v] = {float(unit[0]), float(unit[1]), float(unit[2])};
    }

    auto addPoint = [&](const std::array<double, 3>& p) {
        if (point(p).allFinite()) prepared.framingPoints.push_back(point(p));
    };
    prepared.framingPoints.reserve(scene.vertices.size() + scene.skeletonPoints.size());
    // Only vertices a triangle uses: a stray vertex of a mesh file, far away,
    // would shrink the shape to a dot.
    std::vector<char> isUsed(scene.vertices.size(), 0);
    for (const auto& triangle : scene.triangles)
        for (std::uint32_t corner : triangle) isUsed[corner] = 1;
    for (std::size_t v = 0; v < scene.vertices.size(); ++v)
        if (isUsed[v]) addPoint(scene.vertices[v]);
    for (const auto& p : scene.skeletonPoints) addPoint(p);
    for (const auto& loop : scene.cutLoops)
        for (const auto& p : loop) addPoint(p);
    if (!prepared.framingPoints.empty()) {
        Eigen::Vector3d lo = prepared.framingPoints.front(), hi = lo;
        for (const auto& p : prepared.framingPoints) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        prepared.centre = 0.5 * (lo + hi);
        prepared.extent = hi - lo;
        prepared.diagonal = prepared.extent.norm();
        if (!(prepared.diagonal > 0.0)) prepared.diagonal = 1.0;
    }

    std::vector<std::uint32_t> labels(scene.triangleLabels);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    if (!labels.empty() && labels.front() == 0) labels.erase(labels.begin());
    prepared.labels = std::move(labels);
    return prepared;
}

std::array<View, 3> makeViews(int upAxis, const Eigen::Vector3d& extent) {
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
    const Eigen::Vector3d up = Eigen::Vector3d::Unit(upIndex);
    const Eigen::Vector3d front = Eigen::Vector3d::Unit(frontIndex);
    const Eigen::Vector3d side = Eigen::Vector3d::Unit(sideIndex);
    const char axisNames[3] = {'x', 'y', 'z'};
    const std::string upText = std::string(", ") + axisNames[upIndex] + " up";
    auto viewFrom = [&](const std::string& caption, const Eigen::Vector3d& cameraSide) {
        View view;
        view.caption = caption;
        const Eigen::Vector3d towardScene = (-cameraSide).normalized();
        const Eigen::Vector3d right = towardScene.cross(up).normalized();
        view.worldToCamera.row(0) = right;
        view.worldToCamera.row(1) = right.cross(towardScene);
        view.worldToCamera.row(2) = towardScene;
        return view;
    };
    // 3/4 view: azimuth half way between front and side, 30 degrees up.
    const double elevation = 30.0 * 3.14159265358979323846 / 180.0;
    const Eigen::Vector3d oblique =
        std::cos(elevation) * (front + side).normalized() + std::sin(elevation) * up;
    return {viewFrom(std::string("front: from +") + axisNames[frontIndex] + upText, front),
            viewFrom(std::string("side: from +") + axisNames[sideIndex] + upText, side),
            viewFrom("3/4 from above", oblique)};
}

Canvas renderPanel(const PreparedScene& prepared, const View& view, int panelWidth, int panelHeight,
                   int captionSpace, double lineScale, bool threaded) {
    return PanelRenderer(prepared, view, panelWidth, panelHeight, captionSpace, lineScale, threaded)
        .render();
}

}  // namespace skelseg::preview
