#include "orbis/scene/ClipmapTerrain.h"

#include "ClipmapTiles.h"
#include "DepthPrograms.h"
#include "VectorSupport.h"

#include "orbis/scene/Effect.h"

#include <orbis/core/ClipmapLayout.h>
#include <orbis/core/ClipmapUpsampling.h>
#include <orbis/core/Error.h>
#include <orbis/core/Intersect.h>
#include <orbis/core/IntersectionTests.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/core/ToroidalGrid.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/IndexBuffer.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/ShaderCache.h>
#include <orbis/renderer/ShaderProgram.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/renderer/VertexBuffer.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TerrainSampler.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <array>
#include <ctime>
#include <cmath>
#include <cstring>
#include <iostream>
#include <list>
#include <set>
#include <unordered_map>
#include <unordered_set>

namespace orbis::scene {

namespace {

using detail::ImageryContent;
using detail::ImageTexels;
using detail::KeyHash;
using detail::TerrainContent;
using detail::TerrainGrid;
using detail::TileCache;
using detail::TileFinder;
using detail::ticketFor;

/// How far the viewer may stray from the grid's equator before the grid changes.
const double kSwitchSine = std::sin(toRadians(40.0));
const double kReturnSine = std::sin(toRadians(30.0));
/// The coarsest level's half-width at most: 40 + 48 keeps every post 2 degrees off the grid's pole.
constexpr double kMaximumHalfWidthRadians = 48.0 * kPi / 180.0;

/// Earth-fixed direction of a direction in the coordinates of parameterisation `frame`: 0 the
/// geodetic one, 1 with its pole on +x, 2 with its pole on +y (cyclic permutations: rotations).
glm::dvec3 toEarth(int frame, const glm::dvec3& u) noexcept
{
    switch (frame) {
    case 1: return {u.z, u.x, u.y};
    case 2: return {u.y, u.z, u.x};
    default: return u;
    }
}
glm::dvec3 toFrame(int frame, const glm::dvec3& e) noexcept
{
    switch (frame) {
    case 1: return {e.y, e.z, e.x};
    case 2: return {e.z, e.x, e.y};
    default: return e;
    }
}
/// The geodetic position of an Earth-fixed unit normal.
Geodetic2D geodetic(const glm::dvec3& normal) noexcept
{
    return {std::atan2(normal.y, normal.x), std::asin(std::clamp(normal.z, -1.0, 1.0))};
}

/// The rotated grids' posts have their geodetic positions worked out exactly at every 16th post
/// of a row (whatever strip is written, so a post always gets the same doubles) and stepped to
/// from there.
constexpr std::int64_t kStepAnchor = 16;

glm::mat3 frameMatrix(int frame) noexcept
{
    const glm::dvec3 x = toEarth(frame, {1, 0, 0}), y = toEarth(frame, {0, 1, 0}), z = toEarth(frame, {0, 0, 1});
    return glm::mat3(glm::vec3(x), glm::vec3(y), glm::vec3(z));
}

constexpr std::uint32_t kLevelPalette[8] = {0xff3030e0u, 0xff30c030u, 0xffe07020u, 0xff20c0e0u,
                                            0xffc030c0u, 0xff20e0e0u, 0xff808080u, 0xffe0e0e0u}; // ABGR

glm::vec4 unpack(std::uint32_t abgr) noexcept
{
    return {static_cast<float>(abgr & 0xffu) / 255.0f, static_cast<float>((abgr >> 8) & 0xffu) / 255.0f,
            static_cast<float>((abgr >> 16) & 0xffu) / 255.0f, 1.0f};
}
std::uint32_t pack(const glm::vec4& color) noexcept
{
    auto byte = [](float v) { return static_cast<std::uint32_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
    return byte(color.r) | (byte(color.g) << 8) | (byte(color.b) << 16) | (byte(color.a) << 24);
}

/// This thread's CPU time: the writes' cost whoever else runs on the machine.
double threadCpuMilliseconds() noexcept
{
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

// The batched loops below are a level's write's inner loops: compiled twice more, for AVX-512
// and for AVX2, whose vectors take eight or four posts' arithmetic at a time (their lookups'
// loads stay one by one: GCC's generic tuning emits no gather instructions, and forcing them was
// slower), the processor choosing at load time. All give the same values: neither brings a fused
// multiply-add to contract to (AVX-512F implies no FMA in GCC).
#if defined(__x86_64__) && defined(__GNUC__)
#define ORBIS_BATCHED __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define ORBIS_BATCHED
#endif

/// The Earth-fixed unit normals of a row's posts from their grid longitudes' cosines and sines
/// and the row's latitude's (gridX, gridY, gridZ: where toEarth puts the grid's components).
ORBIS_BATCHED void rowNormals(double cosLatitude, double sinLatitude, const double* __restrict cosLongitude,
                              const double* __restrict sinLongitude, std::size_t count, double* __restrict gridX,
                              double* __restrict gridY, double* __restrict gridZ)
{
    for (std::size_t k = 0; k < count; ++k) {
        gridX[k] = cosLatitude * cosLongitude[k];
        gridY[k] = cosLatitude * sinLongitude[k];
        gridZ[k] = sinLatitude;
    }
}

/// The length of each normal's projection on the equator's plane: the cosine of its latitude.
ORBIS_BATCHED void equatorialLengths(const double* __restrict x, const double* __restrict y, std::size_t count,
                                     double* __restrict equatorial)
{
    for (std::size_t k = 0; k < count; ++k) {
        equatorial[k] = std::sqrt(x[k] * x[k] + y[k] * y[k]);
    }
}

/// The steps in longitude and latitude from each normal (from the second on) to the next: the
/// small angles between the two, their tangent and sine series to the seventh power (exact to
/// 1e-18 rad for steps under 0.01 rad), instead of an arc tangent and an arc sine a post; too
/// large beyond that (near the Earth's poles).
ORBIS_BATCHED void stepsBetween(const double* __restrict x, const double* __restrict y, const double* __restrict z,
                                const double* __restrict equatorial, std::size_t count, double* __restrict longitudeStep,
                                double* __restrict latitudeStep, std::uint64_t* __restrict tooLarge)
{
    for (std::size_t k = 1; k < count; ++k) {
        const double cross = x[k - 1] * y[k] - y[k - 1] * x[k];
        const double dot = x[k - 1] * x[k] + y[k - 1] * y[k];
        const double sinStep = z[k] * equatorial[k - 1] - z[k - 1] * equatorial[k]; // sin(latitude step)
        tooLarge[k] = !(std::abs(cross) < 0.01 * dot) || !(std::abs(sinStep) < 0.01);
        const double t = cross / dot; // tan(longitude step)
        const double t2 = t * t;
        const double s2 = sinStep * sinStep;
        longitudeStep[k] = t * (1.0 - t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 / 7.0)));
        latitudeStep[k] = sinStep * (1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0))));
    }
}

/// A row of a rotated grid's posts, in vectorizable passes: their Earth-fixed unit normals, then
/// the steps in longitude and latitude between them.
struct RotatedRow {
    std::vector<double> x, y, z, equatorial, longitudeStep, latitudeStep;
    std::vector<std::uint64_t> stepTooLarge; ///< words as wide as the doubles: bytes cost the vectorized loop a third more

    void compute(int frame, double cosLatitude, double sinLatitude, const std::vector<double>& cosLongitude,
                 const std::vector<double>& sinLongitude)
    {
        const std::size_t count = cosLongitude.size();
        for (std::vector<double>* v : {&x, &y, &z, &equatorial, &longitudeStep, &latitudeStep}) {
            v->resize(count);
        }
        stepTooLarge.resize(count);
        // The frames permute the axes: the Earth's axis that each of the grid's lands on.
        double* const earth[3] = {x.data(), y.data(), z.data()};
        auto axis = [&](const glm::dvec3& gridAxis) {
            const glm::dvec3 e = toEarth(frame, gridAxis);
            return earth[e.x != 0.0 ? 0 : (e.y != 0.0 ? 1 : 2)];
        };
        rowNormals(cosLatitude, sinLatitude, cosLongitude.data(), sinLongitude.data(), count, axis({1, 0, 0}),
                   axis({0, 1, 0}), axis({0, 0, 1}));
        equatorialLengths(x.data(), y.data(), count, equatorial.data());
        stepsBetween(x.data(), y.data(), z.data(), equatorial.data(), count, longitudeStep.data(), latitudeStep.data(),
                     stepTooLarge.data());
    }
};

/// Bilinear heights of a tile's lattice at `count` points (u 0 west .. 1 east, v 0 south .. 1
/// north, clamped).
ORBIS_BATCHED void sampleLattice(const TerrainGrid& grid, const double* u, const double* v, std::size_t count,
                                 float* __restrict heights)
{
    constexpr int size = TerrainGrid::kSize;
    const float* __restrict lattice = grid.heights.data();
    for (std::size_t k = 0; k < count; ++k) {
        const double row = (1.0 - std::clamp(v[k], 0.0, 1.0)) * (size - 1);
        const int r = std::min(static_cast<int>(row), size - 2);
        const double fr = row - r;
        const double column = std::clamp(u[k], 0.0, 1.0) * (size - 1);
        const int c = std::min(static_cast<int>(column), size - 2);
        const double fc = column - c;
        const int nw = r * size + c, sw = nw + size;
        const double north = (1.0 - fc) * static_cast<double>(lattice[nw]) + fc * static_cast<double>(lattice[nw + 1]);
        const double south = (1.0 - fc) * static_cast<double>(lattice[sw]) + fc * static_cast<double>(lattice[sw + 1]);
        heights[k] = static_cast<float>((1.0 - fr) * north + fr * south);
    }
}

/// A texel row's slopes east and north (per metre) at texels first .. last - 1 from central
/// differences: its neighbours in the row (eastSpan: metres between two posts) and the rows north
/// and south (northSpan: metres between those), as float pairs.
ORBIS_BATCHED void centralDifferences(const float* __restrict row, const float* __restrict north,
                                      const float* __restrict south, std::size_t first, std::size_t last, double eastSpan,
                                      double northSpan, float* __restrict slopes)
{
    for (std::size_t t = first; t < last; ++t) {
        const double dx = (static_cast<double>(row[t + 1]) - static_cast<double>(row[t - 1])) / (2.0 * eastSpan);
        const double dy = (static_cast<double>(north[t]) - static_cast<double>(south[t])) / northSpan;
        slopes[2 * t] = static_cast<float>(dx);
        slopes[2 * t + 1] = static_cast<float>(dy);
    }
}

/// Widens [lowest, highest] to `count` heights: in eight lanes, whose minima and maxima are
/// independent and vectorize, where one running minimum would wait on the last.
ORBIS_BATCHED void widenRange(const float* __restrict heights, std::size_t count, float& lowest, float& highest)
{
    constexpr std::size_t kLanes = 8;
    std::array<float, kLanes> low, high;
    low.fill(lowest);
    high.fill(highest);
    std::size_t k = 0;
    for (; k + kLanes <= count; k += kLanes) {
        for (std::size_t j = 0; j < kLanes; ++j) {
            low[j] = heights[k + j] < low[j] ? heights[k + j] : low[j];
            high[j] = heights[k + j] > high[j] ? heights[k + j] : high[j];
        }
    }
    for (; k < count; ++k) {
        low[0] = heights[k] < low[0] ? heights[k] : low[0];
        high[0] = heights[k] > high[0] ? heights[k] : high[0];
    }
    lowest = *std::min_element(low.begin(), low.end());
    highest = *std::max_element(high.begin(), high.end());
}

/// Where t (0..1 across `size` texels) lies, in 1/256 of a texel from the first texel's centre,
/// rounded, clamped to the outer texels' centres (where one texel gives the colour): the first
/// texel of the pair to blend and the second's weight, of 256. The constants are worked out once
/// for a batch.
struct TexelAxis {
    explicit TexelAxis(int size)
        : scale(256.0 * size)
        , limit(256.0 * (size - 1))
        , lastPair(std::max(size - 2, 0))
    {
    }
    std::pair<int, std::uint32_t> at(double t) const noexcept
    {
        const int q = static_cast<int>(std::clamp(t * scale - 127.5, 0.0, limit));
        const int first = std::min(q >> 8, lastPair);
        return {first, static_cast<std::uint32_t>(q - (first << 8))};
    }
    /// The same, not clamped: near an edge the pair reaches a texel beyond it (-1 or size).
    std::pair<int, std::uint32_t> beyond(double t) const noexcept
    {
        const int q = static_cast<int>(std::floor(t * scale - 127.5));
        return {q >> 8, static_cast<std::uint32_t>(q & 255)};
    }
    double scale, limit;
    int lastPair;
};

/// Which of `count` points (u 0 west .. 1 east, v 0 south .. 1 north) of a tile of width x height
/// texels lie within half a texel of its edge, where sampleImage holds to the edge texels: their
/// flags (1; words, as wide as the doubles, for the loop to vectorize) and their number.
ORBIS_BATCHED std::size_t nearImageEdges(const double* __restrict u, const double* __restrict v, std::size_t count, int width,
                                         int height, std::uint64_t* __restrict nearEdge)
{
    const double nearU = 0.5 / width, farU = 1.0 - nearU, nearV = 0.5 / height, farV = 1.0 - nearV;
    std::uint64_t found = 0;
    for (std::size_t k = 0; k < count; ++k) {
        nearEdge[k] = (u[k] < nearU) | (u[k] > farU) | (v[k] < nearV) | (v[k] > farV);
        found += nearEdge[k];
    }
    return found;
}

/// Four packed texels (a north-west, b north-east, c south-west, d south-east) blended by the
/// weights of the eastern and southern ones, of 256: the four weighted at once, two channels a
/// multiply (the red and blue, then the green and alpha bytes apart in one word).
inline std::uint32_t blendTexels(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d, std::uint32_t fx,
                                 std::uint32_t fy) noexcept
{
    // Weights of 256 in all; the south-east one rounded, the others what remains of theirs.
    const std::uint32_t wse = (fx * fy + 128) >> 8, wne = fx - wse, wsw = fy - wse, wnw = 256 - fx - fy + wse;
    constexpr std::uint32_t kPairs = 0x00ff00ffu;
    const std::uint32_t redBlue =
        (((a & kPairs) * wnw + (b & kPairs) * wne + (c & kPairs) * wsw + (d & kPairs) * wse + 0x00800080u) >> 8) & kPairs;
    const std::uint32_t greenAlpha = (((a >> 8) & kPairs) * wnw + ((b >> 8) & kPairs) * wne + ((c >> 8) & kPairs) * wsw +
                                      ((d >> 8) & kPairs) * wse + 0x00800080u) &
                                     ~kPairs;
    return redBlue | greenAlpha;
}

/// An image's bilinear samples at `count` points (u 0 west .. 1 east, v 0 south .. 1 north,
/// clamped), packed: positions and weights in 1/256 of a texel (blendTexels).
ORBIS_BATCHED void sampleImage(const detail::ImageTexels& image, const double* u, const double* v, std::size_t count,
                               std::uint32_t* __restrict colors)
{
    const TexelAxis columns(image.width), rows(image.height);
    const int east = image.width > 1 ? 1 : 0;
    const int south = image.height > 1 ? image.width : 0;
    const std::uint32_t* __restrict texels = image.texels.data();
    for (std::size_t k = 0; k < count; ++k) {
        const auto [ix, fx] = columns.at(u[k]);
        const auto [iy, fy] = rows.at(1.0 - v[k]);
        const int nw = iy * image.width + ix;
        colors[k] = blendTexels(texels[nw], texels[nw + east], texels[nw + south], texels[nw + south + east], fx, fy);
    }
}


} // namespace

struct ClipmapTerrain::Impl {
    struct Level {
        ToroidalGrid<float> heights;
        ToroidalGrid<glm::vec2> gradients;
        ToroidalGrid<std::uint32_t> colors;
        std::vector<GridRegion> pending; ///< came into view, not written: the level is not drawn
        std::vector<GridRegion> refresh; ///< written from coarser data than has arrived since: drawn as it is
        double minimumHeight = 0.0, maximumHeight = 0.0;
        std::uint32_t terrainLevel = 0; ///< the terrain tiles matching its spacing
        std::uint32_t imageryLevel = 0;
        bool needed = false;
        GeodeticExtent bounds = GeodeticExtent::maximum(); ///< geodetic rectangle holding the level
        renderer::Texture2D heightTexture, gradientTexture, colorTexture;

        explicit Level(int size)
            : heights(size)
            , gradients(size)
            , colors(size)
        {
        }
    };

    Ellipsoid ellipsoid;
    const ClipmapTerrainOptions& options;
    ClipmapBlockLayout layout;
    int size;          ///< texels a side of each level's textures: n + 1
    double spacing0;   ///< radians between level 0's posts
    std::vector<Level> levels;
    int frame = -1;    ///< the parameterisation in use
    double viewerLongitude = 0.0; ///< in the grid's coordinates, followed continuously
    double viewerLatitude = 0.0;

    std::shared_ptr<world::TerrainSource> terrain;
    std::shared_ptr<world::TileSource> imagery;
    world::TileLoader loader;
    TileCache<std::shared_ptr<const TerrainGrid>> terrainTiles;
    TileCache<std::shared_ptr<const ImageTexels>> imageryTiles;
    std::unordered_set<std::uint64_t> failedOrMissing;
    std::set<std::string> warned;

    // GPU resources, made at the first update.
    bool created = false;
    renderer::VertexBuffer postBuffer;
    renderer::IndexBuffer indexBuffer;
    std::optional<renderer::VertexArray> vertexArray;
    std::optional<renderer::Sampler> nearest;
    std::optional<renderer::Sampler> repeatLinear;
    detail::DepthPrograms programs{[this](DepthStrategy, Pass) { return programDescription(); }};
    std::vector<std::byte> scratch;

    /// The globe beyond the coarsest level, which reaches at most 48 degrees from the viewer
    /// (the grid's pole keeps it there): a geodetic grid of 1 degree cells on the terrain's
    /// coarsest tiles, coloured by an equirectangular texture of the imagery's coarse tiles, made
    /// once; drawn where no level is.
    struct Backdrop {
        static constexpr int kColumns = 360, kRows = 180, kTextureWidth = 1024;
        std::uint32_t terrainLevel = 0, imageryLevel = 0;
        std::vector<TileKey> terrainKeys, imageryKeys;
        bool tilesChosen = false, built = false;
        double lowest = 0.0, highest = 0.0; ///< of its vertices, exaggeration included
        renderer::VertexBuffer positions, texels;
        renderer::IndexBuffer indices;
        std::optional<renderer::VertexArray> vertexArray;
        renderer::Texture2D colors;
        std::optional<renderer::Sampler> sampler; ///< repeating across the antimeridian, not over the poles
    };
    Backdrop backdrop;
    detail::DepthPrograms backdropPrograms{
        [this](DepthStrategy, Pass) { return surfaceDescription("clipmap backdrop", "scene/clipmap/backdrop"); }};

    // For drawnTriangles: what the last frame drew.
    struct Drawn {
        int level;
        std::size_t firstIndex, indexCount;
        renderer::DrawCommand command; ///< as the renderer got it, for captureDrawnClipPositions
    };
    std::vector<Drawn> drawn;
    int drawnFinest = 0;
    DepthStrategy drawnDepthStrategy = DepthStrategy::MultiFrustum;
    int lastFinestDrawn = -1;

    Impl(const Ellipsoid& e, const ClipmapTerrainOptions& o, double spacing, int levelCount)
        : ellipsoid(e)
        , options(o)
        , layout(o.posts)
        , size(o.posts + 1)
        , spacing0(spacing)
        , terrain(o.terrain)
        , imagery(o.imagery.empty() ? nullptr : o.imagery.front().source)
        , loader(o.loader)
    {
        for (int l = 0; l < levelCount; ++l) {
            levels.emplace_back(size);
            Level& level = levels.back();
            const double s = spacing0 * std::ldexp(1.0, l);
            if (terrain) {
                const world::TerrainSourceInfo& info = terrain->info();
                const int samples = info.gridSize > 0 ? info.gridSize - 1 : 64;
                std::uint32_t z = info.minimumLevel;
                while (z < info.maximumLevel && kPi / std::ldexp(1.0, static_cast<int>(z)) / samples > s) {
                    ++z;
                }
                level.terrainLevel = z;
            }
            if (imagery) {
                const world::TileSourceInfo& info = imagery->info();
                std::uint32_t z = info.minimumLevel;
                const double across = info.scheme.projection() == TilingProjection::WebMercator ? 2.0 * kPi : kPi;
                while (z < info.maximumLevel && across / std::ldexp(1.0, static_cast<int>(z)) / info.tileWidth > s) {
                    ++z;
                }
                level.imageryLevel = z;
            }
        }
    }

    double levelSpacing(int l) const noexcept { return spacing0 * std::ldexp(1.0, l); }
    int centerPost() const noexcept { return (options.posts - 1) / 2; }

    /// The Earth-fixed unit normal at a post of the grid (global post numbers of level l).
    glm::dvec3 postNormal(int l, std::int64_t x, std::int64_t y) const noexcept
    {
        const double s = levelSpacing(l);
        const double longitude = static_cast<double>(x) * s, latitude = static_cast<double>(y) * s;
        return toEarth(frame, {std::cos(latitude) * std::cos(longitude), std::cos(latitude) * std::sin(longitude),
                               std::sin(latitude)});
    }

    glm::dvec3 surfacePoint(const glm::dvec3& normal, double height) const noexcept
    {
        const glm::dvec3 r2 = ellipsoid.radii() * ellipsoid.radii();
        const glm::dvec3 k = r2 * normal;
        return k / std::sqrt(glm::dot(normal, k)) + height * normal;
    }


    /// What the vertex shader computes a level's posts from: its centre post's grid angles, normal,
    /// surface point relative to the eye and radius of curvature, as floats.
    struct Reference {
        float spacing;
        glm::vec4 trig;
        glm::vec3 normal;
        glm::vec3 relativeToEye;
        float radius;
    };
    Reference reference(int l, const glm::dvec3& eye, float referenceHeight) const noexcept
    {
        const std::int64_t cx = originX(l) + centerPost(), cy = originY(l) + centerPost();
        const double s = levelSpacing(l);
        const double longitude = static_cast<double>(cx) * s, latitude = static_cast<double>(cy) * s;
        const glm::dvec3 normal = postNormal(l, cx, cy);
        const double a = ellipsoid.radii().x;
        const double e2 = 1.0 - (ellipsoid.radii().z * ellipsoid.radii().z) / (a * a);
        return {static_cast<float>(s),
                glm::vec4(static_cast<float>(std::cos(latitude)), static_cast<float>(std::sin(latitude)),
                          static_cast<float>(std::cos(longitude)), static_cast<float>(std::sin(longitude))),
                glm::vec3(normal), glm::vec3(surfacePoint(normal, static_cast<double>(referenceHeight)) - eye),
                static_cast<float>(a / std::sqrt(1.0 - e2 * normal.z * normal.z))};
    }

    /// A post's height (x, y: posts of level l's window) as the vertex shader draws it: its own,
    /// blended towards the coarser level's over the window's outer band; without exaggeration.
    double drawnHeight(int l, int x, int y) const noexcept
    {
        const Level& level = levels[static_cast<std::size_t>(l)];
        const std::int64_t X = originX(l) + x, Y = originY(l) + y;
        double height = static_cast<double>(level.heights.at(X, Y));
        if (l + 1 < static_cast<int>(levels.size())) {
            const int c = centerPost();
            const double blendWidth = std::max(2, options.posts / 10);
            const double distance = std::max(std::abs(x - c), std::abs(y - c));
            const double alpha = std::clamp((distance - (c - blendWidth)) / blendWidth, 0.0, 1.0);
            const Level& coarser = levels[static_cast<std::size_t>(l) + 1];
            const std::int64_t cx = X >> 1, cy = Y >> 1;
            const double coarse = 0.5 * (static_cast<double>(coarser.heights.at(cx, cy)) +
                                         static_cast<double>(coarser.heights.at(cx + (X & 1), cy + (Y & 1))));
            height += alpha * (coarse - height);
        }
        return height;
    }

    std::int64_t originX(int l) const noexcept { return levels[static_cast<std::size_t>(l)].heights.originX(); }
    std::int64_t originY(int l) const noexcept { return levels[static_cast<std::size_t>(l)].heights.originY(); }

    void warn(const std::string& message)
    {
        if (!warned.insert(message).second) {
            return;
        }
        if (options.onWarning) {
            options.onWarning(message);
        } else {
            std::cerr << "warning: " << message << "\n";
        }
    }

    /// Chooses the parameterisation and follows the viewer in it; true when it changed.
    bool followViewer(const glm::dvec3& eye)
    {
        const glm::dvec3 normal = ellipsoid.geodeticSurfaceNormal(eye);
        // The geodetic grid while the viewer is within 40 degrees of the equator; past that, the
        // rotated grid whose pole is farthest from the viewer (then within 32.8 degrees of its
        // equator); back to the geodetic one under 30 degrees.
        int wanted = frame;
        if (frame < 0 || std::abs(toFrame(frame, normal).z) > kSwitchSine ||
            (frame != 0 && std::abs(normal.z) < kReturnSine)) {
            wanted = std::abs(normal.z) <= kSwitchSine ? 0 : (std::abs(normal.x) <= std::abs(normal.y) ? 1 : 2);
        }
        const bool switched = wanted != frame;
        frame = wanted;
        const glm::dvec3 u = toFrame(frame, normal);
        const double longitude = std::atan2(u.y, u.x);
        viewerLatitude = std::asin(std::clamp(u.z, -1.0, 1.0));
        if (switched) {
            viewerLongitude = longitude;
        } else {
            // The nearest turn to where it was: crossing the antimeridian moves nothing.
            viewerLongitude = longitude + kTwoPi * std::round((viewerLongitude - longitude) / kTwoPi);
        }
        return switched;
    }

    /// The geodetic rectangle around a level's window, from posts every eighth of it.
    GeodeticExtent levelBounds(int l) const noexcept
    {
        const int n = options.posts;
        double west = kPi, east = -kPi, south = kHalfPi, north = -kHalfPi;
        double minimumLongitude = 10.0, maximumLongitude = -10.0;
        for (int j = 0; j <= 8; ++j) {
            for (int i = 0; i <= 8; ++i) {
                const Geodetic2D g = geodetic(postNormal(l, originX(l) + i * (n - 1) / 8, originY(l) + j * (n - 1) / 8));
                south = std::min(south, g.latitude);
                north = std::max(north, g.latitude);
                minimumLongitude = std::min(minimumLongitude, g.longitude);
                maximumLongitude = std::max(maximumLongitude, g.longitude);
            }
        }
        // A pole inside the window, or a window across the antimeridian: all longitudes (the
        // rectangle only decides which tiles to ask for and which arrivals concern the level).
        const double margin = 2.0 * levelSpacing(l) * (n - 1) / 8;
        west = minimumLongitude - margin;
        east = maximumLongitude + margin;
        south = std::max(-kHalfPi, south - margin);
        north = std::min(kHalfPi, north + margin);
        for (const double pole : {-1.0, 1.0}) {
            const glm::dvec3 u = toFrame(frame, {0.0, 0.0, pole});
            const double latitude = std::asin(std::clamp(u.z, -1.0, 1.0)) / levelSpacing(l);
            double longitude = std::atan2(u.y, u.x) / levelSpacing(l);
            const double turn = kTwoPi / levelSpacing(l);
            longitude += turn * std::round((static_cast<double>(originX(l)) + 0.5 * (n - 1) - longitude) / turn);
            if (longitude >= static_cast<double>(originX(l)) && longitude <= static_cast<double>(originX(l) + n) &&
                latitude >= static_cast<double>(originY(l)) && latitude <= static_cast<double>(originY(l) + n)) {
                (pole > 0 ? north : south) = pole * kHalfPi;
                west = -kPi;
                east = kPi;
            }
        }
        if (east - west >= kTwoPi - 1e-9 || maximumLongitude - minimumLongitude > kPi) {
            west = -kPi;
            east = kPi;
        }
        return {west, south, east, north};
    }

    /// Offers the tiles a level wants that are not loaded.
    /// Starts loading a terrain (kind 0) or imagery (kind 1) tile unless it is loaded, loading,
    /// missing or failed; true if it started.
    bool offerTile(int kind, const TileKey& key, double priority)
    {
        const std::uint64_t ticket = ticketFor(kind, key);
        if (failedOrMissing.contains(ticket) || loader.isLoading(ticket)) {
            return false;
        }
        if (kind == 0) {
            if (terrainTiles.contains(key) || !terrain->hasTile(key)) {
                return false;
            }
            std::shared_ptr<world::TerrainSource> source = terrain;
            loader.request(ticket, priority, [source, key]() -> std::unique_ptr<world::TileContent> {
                world::TerrainFetch fetched = source->load(key);
                if (fetched.status == world::TerrainFetch::Status::Failed) {
                    throw Error(fetched.message);
                }
                if (fetched.status == world::TerrainFetch::Status::Missing) {
                    return nullptr;
                }
                auto sampler = std::make_shared<const world::TerrainSampler>(
                    std::make_shared<const world::TerrainTileData>(std::move(fetched.tile)));
                auto grid = std::make_shared<TerrainGrid>();
                grid->heights = sampler->latticeHeights(key, TerrainGrid::kSamplesLog2);
                if (sampler->data().isMesh()) {
                    grid->mesh = std::move(sampler);
                }
                return std::make_unique<TerrainContent>(std::move(grid));
            });
        } else {
            if (imageryTiles.contains(key)) {
                return false;
            }
            std::shared_ptr<world::TileSource> source = imagery;
            loader.request(ticket, priority, [source, key]() -> std::unique_ptr<world::TileContent> {
                world::TileFetch fetched = source->fetch(key);
                if (fetched.status == world::TileFetch::Status::Failed) {
                    throw Error(fetched.message);
                }
                if (fetched.status == world::TileFetch::Status::Missing) {
                    return nullptr;
                }
                return std::make_unique<ImageryContent>(world::decodeImage(fetched.bytes, source->locate(key), 4));
            });
        }
        return true;
    }

    std::size_t requestTiles(int l)
    {
        const int n = options.posts;
        const Level& level = levels[static_cast<std::size_t>(l)];
        std::set<std::uint64_t> offered;
        std::size_t requests = 0;
        auto offer = [&](int kind, const TileKey& key) {
            if (offered.insert(ticketFor(kind, key)).second &&
                offerTile(kind, key, static_cast<double>(static_cast<int>(levels.size()) - l) + 0.5 * kind)) {
                ++requests;
            }
        };
        for (int j = 0; j <= 16; ++j) {
            for (int i = 0; i <= 16; ++i) {
                const Geodetic2D g = geodetic(postNormal(l, originX(l) + i * (n - 1) / 16, originY(l) + j * (n - 1) / 16));
                if (terrain) {
                    if (const auto key = terrain->info().scheme.tileAt(g, level.terrainLevel)) {
                        offer(0, *key);
                    }
                }
                if (imagery) {
                    if (const auto key = imagery->info().scheme.tileAt(g, level.imageryLevel)) {
                        offer(1, *key);
                    }
                }
            }
        }
        return requests;
    }

    /// A tile arrived: the levels that would read it are rewritten (drawn meanwhile as they are).
    /// Offers the backdrop's tiles (every tile of one coarse level of each source) until it is
    /// made; true once every one is loaded, missing or failed.
    bool requestBackdropTiles()
    {
        if (!backdrop.tilesChosen) {
            backdrop.tilesChosen = true;
            // A few tiles at most: a source that starts finer leaves the backdrop flat, or plain.
            auto allTiles = [](const TilingScheme& scheme, std::uint32_t level) {
                std::vector<TileKey> keys;
                if (static_cast<std::uint64_t>(scheme.tilesX(level)) * scheme.tilesY(level) > 64) {
                    return keys;
                }
                for (std::uint32_t y = 0; y < scheme.tilesY(level); ++y) {
                    for (std::uint32_t x = 0; x < scheme.tilesX(level); ++x) {
                        keys.push_back({level, x, y});
                    }
                }
                return keys;
            };
            if (terrain) {
                backdrop.terrainLevel = terrain->info().minimumLevel;
                backdrop.terrainKeys = allTiles(terrain->info().scheme, backdrop.terrainLevel);
            }
            if (imagery) {
                // About two of the texture's texels a pixel: 2,048 x 1,024 pixels in the geographic scheme.
                const world::TileSourceInfo& info = imagery->info();
                backdrop.imageryLevel = std::clamp<std::uint32_t>(2, info.minimumLevel, info.maximumLevel);
                backdrop.imageryKeys = allTiles(info.scheme, backdrop.imageryLevel);
            }
        }
        bool ready = true;
        const double first = static_cast<double>(levels.size()) + 1.0; // before every level's
        for (int kind = 0; kind < 2; ++kind) {
            for (const TileKey& key : kind == 0 ? backdrop.terrainKeys : backdrop.imageryKeys) {
                const bool loaded = kind == 0 ? terrainTiles.contains(key) || !terrain->hasTile(key) : imageryTiles.contains(key);
                if (!loaded && !failedOrMissing.contains(ticketFor(kind, key))) {
                    offerTile(kind, key, first);
                    ready = false;
                }
            }
        }
        return ready;
    }

    /// The backdrop's grid and texture from the tiles requestBackdropTiles waited for.
    void buildBackdrop(FrameState& frameState)
    {
        TileFinder<std::shared_ptr<const TerrainGrid>> terrainFinder(
            &terrainTiles, terrain ? terrain->info().scheme : TilingScheme::geographic(), backdrop.terrainLevel);
        TileFinder<std::shared_ptr<const ImageTexels>> imageryFinder(
            &imageryTiles, imagery ? imagery->info().scheme : TilingScheme::geographic(), backdrop.imageryLevel);
        constexpr int columns = Backdrop::kColumns, rows = Backdrop::kRows;
        std::vector<float> positions, texels;
        for (int j = 0; j <= rows; ++j) {
            for (int i = 0; i <= columns; ++i) {
                const Geodetic2D g{-kPi + kTwoPi * i / columns, -kHalfPi + kPi * j / rows};
                double height = 0.0;
                glm::dvec2 uv;
                if (const auto* grid = terrain ? terrainFinder.find(g, backdrop.terrainLevel, uv) : nullptr) {
                    float lattice = 0.0f;
                    sampleLattice(**grid, &uv.x, &uv.y, 1, &lattice);
                    height = static_cast<double>(lattice);
                }
                backdrop.lowest = std::min(backdrop.lowest, options.exaggeration * height);
                backdrop.highest = std::max(backdrop.highest, options.exaggeration * height);
                const glm::vec3 p(surfacePoint(Ellipsoid::geodeticSurfaceNormal(g), options.exaggeration * height));
                positions.insert(positions.end(), {p.x, p.y, p.z});
                texels.insert(texels.end(), {static_cast<float>(i) / columns, static_cast<float>(j) / rows, static_cast<float>(height)});
            }
        }
        // Counter-clockwise from outside: east, then north.
        static_assert((columns + 1) * (rows + 1) <= 65536, "16-bit indices");
        std::vector<std::uint16_t> indices;
        for (int j = 0; j < rows; ++j) {
            for (int i = 0; i < columns; ++i) {
                const auto a = static_cast<std::uint16_t>(j * (columns + 1) + i), b = static_cast<std::uint16_t>(a + 1);
                const auto d = static_cast<std::uint16_t>(a + columns + 1), c = static_cast<std::uint16_t>(d + 1);
                indices.insert(indices.end(), {a, b, c, a, c, d});
            }
        }
        constexpr int width = Backdrop::kTextureWidth, height = width / 2;
        const std::uint32_t baseColor = pack(options.baseColor);
        std::vector<std::uint32_t> colors(static_cast<std::size_t>(width) * height, baseColor);
        for (int y = 0; y < height && imagery; ++y) {
            for (int x = 0; x < width; ++x) {
                const Geodetic2D g{-kPi + kTwoPi * (x + 0.5) / width, -kHalfPi + kPi * (y + 0.5) / height};
                glm::dvec2 uv;
                if (const auto* image = imageryFinder.find(g, backdrop.imageryLevel, uv)) {
                    sampleImage(**image, &uv.x, &uv.y, 1, &colors[static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x)]);
                }
            }
        }
        backdrop.positions = frameState.device.createVertexBuffer(std::as_bytes(std::span(positions)));
        backdrop.texels = frameState.device.createVertexBuffer(std::as_bytes(std::span(texels)));
        backdrop.indices = frameState.device.createIndexBuffer(std::span(indices));
        backdrop.vertexArray = frameState.context.createVertexArray();
        backdrop.vertexArray->setAttribute("position", backdrop.positions, {renderer::ComponentType::Float, 3});
        backdrop.vertexArray->setAttribute("textureCoordinate", backdrop.texels, {renderer::ComponentType::Float, 3});
        backdrop.vertexArray->setIndexBuffer(&backdrop.indices);
        backdrop.colors = frameState.device.createTexture2D({width, height, renderer::TextureFormat::RGBA8});
        backdrop.colors.copyFromSystemMemory(std::as_bytes(std::span(colors)), {0, 0, width, height});
        SamplerDescription wrapEastWest;
        wrapEastWest.wrapS = TextureWrap::Repeat;
        backdrop.sampler = frameState.device.createSampler(wrapEastWest);
        backdrop.built = true;
    }

    std::size_t backdropBytes() const noexcept
    {
        return backdrop.built ? backdrop.positions.sizeInBytes() + backdrop.texels.sizeInBytes() +
                                    backdrop.indices.count() * sizeof(std::uint16_t) +
                                    static_cast<std::size_t>(backdrop.colors.width()) * backdrop.colors.height() * 4
                              : 0;
    }

    /// Whether the ground the eye can see (to its horizon, and mountains beyond it up to the
    /// highest height) reaches outside the coarsest level's extent (grid angles, centre and half
    /// width): tested at 32 points of the visible cap's rim, whose inside lies within theirs.
    bool backdropVisible(const glm::dvec3& eye, const glm::dvec2& center, double halfWidth, double exaggeration) const
    {
        const double radius = ellipsoid.minimumRadius(); // the smaller sphere sees the farther horizon
        const double eyeHeight = std::max(glm::length(eye) - radius, 0.0);
        const double highest = std::max(exaggeration * levels.back().maximumHeight, 0.0);
        const double reach = std::acos(radius / (radius + eyeHeight)) + std::acos(radius / (radius + highest));
        if (reach >= kHalfPi) {
            return true;
        }
        const glm::dvec3 up = glm::normalize(eye);
        const glm::dvec3 side = glm::normalize(glm::cross(std::abs(up.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0), up));
        const glm::dvec3 other = glm::cross(up, side);
        for (int k = 0; k < 32; ++k) {
            const double a = kTwoPi * k / 32;
            const glm::dvec3 rim = toFrame(frame, std::cos(reach) * up + std::sin(reach) * (std::cos(a) * side + std::sin(a) * other));
            const double longitude = std::remainder(std::atan2(rim.y, rim.x) - center.x, kTwoPi);
            const double latitude = std::asin(std::clamp(rim.z, -1.0, 1.0)) - center.y;
            if (std::abs(longitude) >= halfWidth || std::abs(latitude) >= halfWidth) {
                return true;
            }
        }
        return false;
    }

    void arrived(int kind, const TileKey& key, const GeodeticExtent& extent)
    {
        for (std::size_t l = 0; l < levels.size(); ++l) {
            Level& level = levels[l];
            const std::uint32_t wants = kind == 0 ? level.terrainLevel : level.imageryLevel;
            if (!level.heights.placed() || key.level > wants) {
                continue;
            }
            const GeodeticExtent& b = level.bounds;
            const bool overlaps = extent.south <= b.north && extent.north >= b.south &&
                                  ((b.east - b.west >= kTwoPi - 1e-9) || (extent.west <= b.east && extent.east >= b.west) ||
                                   (extent.west + kTwoPi <= b.east) || (extent.east - kTwoPi >= b.west));
            if (overlaps) {
                level.refresh = {{originX(static_cast<int>(l)), originY(static_cast<int>(l)), size, size}};
            }
        }
    }

    /// An imagery tile with the tiles beside it at its level, looked up when a post first needs
    /// them: where a post's bilinear footprint crosses the tile's edge (within half a texel of it)
    /// the texels beyond come from the neighbour where it is loaded, else from the tile's own edge
    /// (as sampleImage clamps), so that no line shows at the boundary where imagery is magnified.
    class ImageAcrossEdges {
    public:
        ImageAcrossEdges(Impl& impl, const TileKey& key, const ImageTexels& own)
            : _impl(impl)
            , _key(key)
            , _own(own)
            , _columns(own.width)
            , _rows(own.height)
        {
        }

        const TileKey& key() const noexcept { return _key; }

        /// The colour at (u, v) of the tile (0..1 west to east, south to north).
        std::uint32_t at(double u, double v)
        {
            const auto [ix, fx] = _columns.beyond(u);
            const auto [iy, fy] = _rows.beyond(1.0 - v); // rows from the north
            return blendTexels(texel(ix, iy), texel(ix + 1, iy), texel(ix, iy + 1), texel(ix + 1, iy + 1), fx, fy);
        }

    private:
        std::uint32_t texel(int x, int y)
        {
            const int east = x < 0 ? -1 : (x >= _own.width ? 1 : 0), south = y < 0 ? -1 : (y >= _own.height ? 1 : 0);
            const ImageTexels* tile = &_own;
            if (const ImageTexels* next = east != 0 || south != 0 ? beside(east, south) : nullptr) {
                tile = next;
                x -= east * _own.width;
                y -= south * _own.height;
            }
            x = std::clamp(x, 0, tile->width - 1);
            y = std::clamp(y, 0, tile->height - 1);
            return tile->texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(tile->width) + static_cast<std::size_t>(x)];
        }

        /// The loaded tile of the same size beside this one, `east` and `south` tiles on; null where none.
        const ImageTexels* beside(int east, int south)
        {
            const std::size_t slot = static_cast<std::size_t>(3 * (south + 1) + east + 1);
            if (!_looked[slot]) {
                _looked[slot] = true;
                const TilingScheme& scheme = _impl.imagery->info().scheme;
                // A quarter of the tile beyond its edge lies inside the neighbour in either scheme
                // (a Web Mercator tile's neighbours are nearly as tall as it).
                const GeodeticExtent e = scheme.tileExtent(_key);
                const double across = 0.25 * (e.east - e.west), up = 0.25 * (e.north - e.south);
                const double longitude = east > 0 ? e.east + across : (east < 0 ? e.west - across : 0.5 * (e.west + e.east));
                const double latitude = south > 0 ? e.south - up : (south < 0 ? e.north + up : 0.5 * (e.south + e.north));
                const std::optional<TileKey> key = scheme.tileAt({std::remainder(longitude, kTwoPi), latitude}, _key.level);
                const std::shared_ptr<const ImageTexels>* found = key && *key != _key ? _impl.imageryTiles.find(*key) : nullptr;
                if (found && (*found)->width == _own.width && (*found)->height == _own.height) {
                    _beside[slot] = found->get();
                }
            }
            return _beside[slot];
        }

        Impl& _impl;
        TileKey _key;
        const ImageTexels& _own;
        TexelAxis _columns, _rows;
        std::array<const ImageTexels*, 9> _beside{};
        std::array<bool, 9> _looked{};
    };

    /// Heights, colours and then normals of a region's posts (inside the window), and their upload.
    std::size_t write(int l, GridRegion region, TileFinder<std::shared_ptr<const TerrainGrid>>& terrainFinder,
                      TileFinder<std::shared_ptr<const ImageTexels>>& imageryFinder)
    {
        Level& level = levels[static_cast<std::size_t>(l)];
        // Clip to the window (a region pending from an earlier move may have left it in part).
        const std::int64_t x0 = std::max(region.x, originX(l)), y0 = std::max(region.y, originY(l));
        const std::int64_t x1 = std::min(region.x + region.width, originX(l) + size);
        const std::int64_t y1 = std::min(region.y + region.height, originY(l) + size);
        if (x0 >= x1 || y0 >= y1) {
            return 0;
        }
        const double s = levelSpacing(l);
        const bool hasCoarser = l + 1 < static_cast<int>(levels.size());
        const std::uint32_t coarserTerrainLevel = hasCoarser ? levels[static_cast<std::size_t>(l) + 1].terrainLevel : 0;
        const Level* coarser = hasCoarser ? &levels[static_cast<std::size_t>(l) + 1] : nullptr;
        auto coarse = [&](std::int64_t X, std::int64_t Y) { return static_cast<double>(coarser->heights.at(X, Y)); };
        const std::uint32_t baseColor = pack(options.baseColor);
        // Per column and per row once: the grid's longitude (wrapped, for the geodetic grid) and
        // its sine and cosine.
        // In the rotated grids from the anchor post at or before x0 (kStepAnchor).
        const std::int64_t xa = frame == 0 ? x0 : x0 - (((x0 % kStepAnchor) + kStepAnchor) % kStepAnchor);
        std::vector<double> cosLongitude(static_cast<std::size_t>(x1 - xa)), sinLongitude(cosLongitude.size()),
            wrappedLongitude(cosLongitude.size());
        for (std::int64_t x = xa; x < x1; ++x) {
            cosLongitude[static_cast<std::size_t>(x - xa)] = std::cos(static_cast<double>(x) * s);
            sinLongitude[static_cast<std::size_t>(x - xa)] = std::sin(static_cast<double>(x) * s);
            wrappedLongitude[static_cast<std::size_t>(x - xa)] = std::remainder(static_cast<double>(x) * s, kTwoPi);
        }
        // The mesh tile and triangle the last post was in, and those of each post a row before:
        // a post is mostly in one of the two.
        struct MeshHint {
            const TerrainGrid* tile = nullptr;
            std::uint32_t triangle = ~0u;
        };
        MeshHint left;
        // The heights' range, kept in registers rather than in the level while its posts are written.
        float lowest = static_cast<float>(level.minimumHeight), highest = static_cast<float>(level.maximumHeight);
        std::vector<Geodetic2D> row(static_cast<std::size_t>(x1 - x0));
        std::vector<MeshHint> below(row.size());
        std::vector<double> rowU(row.size()), rowV(row.size()); ///< a batch's places in its tile
        std::vector<std::uint64_t> rowNearEdge(row.size());      ///< and which lie near its edge (nearImageEdges)
        RotatedRow rotated;
        // Each imagery tile met at an edge, with its neighbours once looked up, for the whole write
        // (a column of rows crosses the same edge).
        std::vector<ImageAcrossEdges> edges;
        auto edgesOf = [&](const TileKey& key, const ImageTexels& image) -> ImageAcrossEdges& {
            const auto found = std::find_if(edges.begin(), edges.end(), [&](const ImageAcrossEdges& e) { return e.key() == key; });
            return found != edges.end() ? *found : edges.emplace_back(*this, key, image);
        };
        // Most of a lattice met is read, by many rows: its lines are fetched in one sweep when the
        // write first meets it, streaming in rather than each post waiting for its own (a rotated
        // level 0.15 ms faster; the imagery's larger tiles gain nothing from it).
        std::vector<const TerrainGrid*> warmed;
        auto warm = [&](const TerrainGrid& grid) {
            if (std::find(warmed.begin(), warmed.end(), &grid) == warmed.end()) {
                warmed.push_back(&grid);
                const char* bytes = reinterpret_cast<const char*>(grid.heights.data());
                for (std::size_t b = 0; b < grid.heights.size() * sizeof(float); b += 64) {
                    __builtin_prefetch(bytes + b);
                }
            }
        };
        for (std::int64_t y = y0; y < y1; ++y) {
            // The row's geodetic positions: the grid's own in the geodetic grid.
            const double latitude = static_cast<double>(y) * s;
            if (frame == 0) {
                for (std::size_t i = 0; i < row.size(); ++i) {
                    row[i] = {wrappedLongitude[i], latitude};
                }
            } else {
                rotated.compute(frame, std::cos(latitude), std::sin(latitude), cosLongitude, sinLongitude);
                Geodetic2D position{};
                for (std::int64_t x = xa; x < x1; ++x) {
                    const std::size_t k = static_cast<std::size_t>(x - xa);
                    if (k % kStepAnchor == 0 || rotated.stepTooLarge[k]) {
                        position = geodetic({rotated.x[k], rotated.y[k], rotated.z[k]});
                    } else {
                        const double longitude = position.longitude + rotated.longitudeStep[k];
                        position = {longitude > kPi ? longitude - kTwoPi : (longitude < -kPi ? longitude + kTwoPi : longitude),
                                    position.latitude + rotated.latitudeStep[k]};
                    }
                    if (x >= x0) {
                        row[static_cast<std::size_t>(x - x0)] = position;
                    }
                }
            }
            // The posts over one tile are looked up in a batch: their places in it, then its
            // samples, written straight into the level's texels (a batch ends where they wrap).
            float* const heightTexels = &level.heights.at(0, y);
            std::uint32_t* const colorTexels = &level.colors.at(0, y);
            auto texel = [&](std::size_t i) { return static_cast<std::size_t>((x0 + static_cast<std::int64_t>(i)) & (size - 1)); };
            const std::size_t wrap = static_cast<std::size_t>(size) - texel(0);
            auto runEnd = [&](const auto& finder, std::size_t i) {
                const std::size_t limit = i < wrap ? std::min(wrap, row.size()) : row.size();
                std::size_t end = i + 1;
                while (end < limit && finder.holds(row[end])) {
                    ++end;
                }
                return end;
            };
            for (std::size_t i = 0; i < row.size();) {
                glm::dvec2 uv;
                const auto* grid = terrain ? terrainFinder.find(row[i], level.terrainLevel, uv) : nullptr;
                // A grid tile no finer than the coarser level's data gives nothing the coarser
                // level has not: the four-point filter of it is smoother. A mesh tile's triangles
                // are its surface at any spacing.
                if (grid && (!hasCoarser || terrainFinder.lastKey().level > coarserTerrainLevel)) {
                    warm(**grid);
                    const std::size_t end = runEnd(terrainFinder, i);
                    terrainFinder.positionsInLast(&row[i], end - i, &rowU[i], &rowV[i]);
                    sampleLattice(**grid, &rowU[i], &rowV[i], end - i, heightTexels + texel(i));
                    i = end;
                    continue;
                }
                if (grid && (*grid)->mesh) {
                    const TerrainGrid* tile = grid->get();
                    const std::size_t end = runEnd(terrainFinder, i);
                    terrainFinder.positionsInLast(&row[i], end - i, &rowU[i], &rowV[i]);
                    for (; i < end; ++i) {
                        MeshHint& before = below[i];
                        std::array<std::uint32_t, 2> hints{left.tile == tile ? left.triangle : ~0u,
                                                           before.tile == tile ? before.triangle : ~0u};
                        heightTexels[texel(i)] = static_cast<float>(tile->mesh->height(rowU[i], rowV[i], hints));
                        left = before = {tile, hints[0]};
                    }
                    continue;
                }
                heightTexels[texel(i)] = hasCoarser ? static_cast<float>(fourPointUpsample(coarse, x0 + static_cast<std::int64_t>(i), y)) : 0.0f;
                ++i;
            }
            for (std::size_t i = 0; i < row.size();) {
                glm::dvec2 uv;
                if (const auto* image = imagery ? imageryFinder.find(row[i], level.imageryLevel, uv) : nullptr) {
                    const std::size_t end = runEnd(imageryFinder, i);
                    imageryFinder.positionsInLast(&row[i], end - i, &rowU[i], &rowV[i]);
                    sampleImage(**image, &rowU[i], &rowV[i], end - i, colorTexels + texel(i));
                    // Within half a texel of the tile's edge sampleImage held to its edge texels.
                    if (std::size_t toMend = nearImageEdges(&rowU[i], &rowV[i], end - i, (*image)->width, (*image)->height,
                                                          &rowNearEdge[i]);
                        toMend > 0) {
                        ImageAcrossEdges& acrossEdges = edgesOf(imageryFinder.lastKey(), **image);
                        for (std::size_t k = i; toMend > 0; ++k) {
                            if (rowNearEdge[k] != 0) {
                                colorTexels[texel(k)] = acrossEdges.at(rowU[k], rowV[k]);
                                --toMend;
                            }
                        }
                    }
                    i = end;
                    continue;
                }
                const std::int64_t x = x0 + static_cast<std::int64_t>(i);
                colorTexels[texel(i)] = imagery && hasCoarser ? coarser->colors.at(x >> 1, y >> 1) : baseColor;
                ++i;
            }
            widenRange(heightTexels + texel(0), std::min(wrap, row.size()), lowest, highest);
            if (wrap < row.size()) {
                widenRange(heightTexels, row.size() - wrap, lowest, highest);
            }
        }
        level.minimumHeight = static_cast<double>(lowest);
        level.maximumHeight = static_cast<double>(highest);
        // Normals from central differences (one-sided at the window's edges, where the blend
        // takes the coarser level's anyway), for the region and the posts next to it.
        const std::int64_t gx0 = std::max(x0 - 1, originX(l)), gy0 = std::max(y0 - 1, originY(l));
        const std::int64_t gx1 = std::min(x1 + 1, originX(l) + size), gy1 = std::min(y1 + 1, originY(l) + size);
        const double radius = ellipsoid.maximumRadius();
        const std::int64_t firstX = originX(l), lastX = originX(l) + size - 1;
        const std::int64_t firstY = originY(l), lastY = originY(l) + size - 1;
        const std::size_t mask = static_cast<std::size_t>(size - 1);
        const std::size_t first = static_cast<std::size_t>(gx0) & mask, count = static_cast<std::size_t>(gx1 - gx0);
        for (std::int64_t y = gy0; y < gy1; ++y) {
            const std::int64_t ys = std::max(y - 1, firstY), yn = std::min(y + 1, lastY);
            const double north = radius * s * static_cast<double>(yn - ys);
            const double east = std::max(radius * s * std::cos(static_cast<double>(y) * s), 1e-3);
            auto slopeAt = [&](std::int64_t x) {
                const std::int64_t xw = std::max(x - 1, firstX), xe = std::min(x + 1, lastX);
                const double dx = (static_cast<double>(level.heights.at(xe, y)) - static_cast<double>(level.heights.at(xw, y))) / (static_cast<double>(xe - xw) * east);
                const double dy = (static_cast<double>(level.heights.at(x, yn)) - static_cast<double>(level.heights.at(x, ys))) / north;
                level.gradients.at(x, y) = glm::vec2(static_cast<float>(dx), static_cast<float>(dy));
            };
            // The posts whose neighbours lie beside them in the row's texels in a batch (the
            // region's texels: one run, or two where they wrap); then one by one those at the
            // texels' ends, whose neighbours lie across the wrap, and at the window's, one-sided.
            float* const slopes = reinterpret_cast<float*>(&level.gradients.at(0, y));
            const std::size_t wrapped = first + count > mask + 1 ? first + count - mask - 1 : 0;
            for (const auto& [begin, end] : {std::pair{first, first + count - wrapped}, std::pair{std::size_t{0}, wrapped}}) {
                if (std::min(end, mask) > std::max<std::size_t>(begin, 1)) {
                    centralDifferences(&level.heights.at(0, y), &level.heights.at(0, yn), &level.heights.at(0, ys),
                                       std::max<std::size_t>(begin, 1), std::min(end, mask), east, north, slopes);
                }
            }
            for (const std::size_t t : {std::size_t{0}, mask}) {
                if (const std::int64_t x = gx0 + static_cast<std::int64_t>((t - first) & mask); x < gx1) {
                    slopeAt(x);
                }
            }
            for (const std::int64_t x : {firstX, lastX}) {
                if (x >= gx0 && x < gx1) {
                    slopeAt(x);
                }
            }
        }
        const GridRegion written{gx0, gy0, static_cast<int>(gx1 - gx0), static_cast<int>(gy1 - gy0)};
        return upload(level.heightTexture, level.heights, written) + upload(level.gradientTexture, level.gradients, written) +
               upload(level.colorTexture, level.colors, written);
    }

    template <typename T>
    std::size_t upload(renderer::Texture2D& texture, const ToroidalGrid<T>& grid, GridRegion region)
    {
        // A region as wide as the window covers whole rows of texels, which go up as they lie
        // (its start moved to a multiple of the size names the same texels); narrower ones'
        // rows are gathered first.
        if (region.width >= size) {
            region.x &= ~static_cast<std::int64_t>(size - 1);
        }
        std::size_t bytes = 0;
        for (const TexelRectangle& r : grid.texelRectangles(region)) {
            const std::size_t count = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
            const T* first = &grid.texels()[static_cast<std::size_t>(r.y) * static_cast<std::size_t>(size) + static_cast<std::size_t>(r.x)];
            std::span<const T> texels(first, count);
            if (r.width != size) {
                scratch.resize(count * sizeof(T));
                T* out = reinterpret_cast<T*>(scratch.data());
                for (int y = 0; y < r.height; ++y) {
                    const T* row = first + static_cast<std::size_t>(y) * static_cast<std::size_t>(size);
                    std::copy(row, row + r.width, out + static_cast<std::size_t>(y) * static_cast<std::size_t>(r.width));
                }
                texels = {out, count};
            }
            texture.copyFromSystemMemory(std::as_bytes(texels), {r.x, r.y, r.width, r.height});
            bytes += texels.size_bytes();
        }
        return bytes;
    }

    void createResources(FrameState& frameState)
    {
        const int n = options.posts;
        std::vector<float> posts;
        posts.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * 2);
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
                posts.push_back(static_cast<float>(x));
                posts.push_back(static_cast<float>(y));
            }
        }
        postBuffer = frameState.device.createVertexBuffer(std::as_bytes(std::span(posts)));
        indexBuffer = frameState.device.createIndexBuffer(std::span(layout.indices()));
        vertexArray = frameState.context.createVertexArray();
        vertexArray->setAttribute("position", postBuffer, {renderer::ComponentType::Float, 2});
        vertexArray->setIndexBuffer(&indexBuffer);
        SamplerDescription point;
        point.minificationFilter = TextureMinificationFilter::Nearest;
        point.magnificationFilter = TextureMagnificationFilter::Nearest;
        nearest = frameState.device.createSampler(point);
        SamplerDescription repeat;
        repeat.wrapS = TextureWrap::Repeat;
        repeat.wrapT = TextureWrap::Repeat;
        repeatLinear = frameState.device.createSampler(repeat);
        for (Level& level : levels) {
            level.heightTexture = frameState.device.createTexture2D({size, size, renderer::TextureFormat::R32F});
            level.gradientTexture = frameState.device.createTexture2D({size, size, renderer::TextureFormat::RG32F});
            level.colorTexture = frameState.device.createTexture2D({size, size, renderer::TextureFormat::RGBA8});
        }
        created = true;
    }

    /// A program of one of the two surfaces (`path`.vert.glsl and .frag.glsl, the latter after
    /// surface_color.glsl), with the options' shading, imagery and lighting defines, before the
    /// depth strategy's (DepthPrograms adds them).
    renderer::ShaderProgramDescription surfaceDescription(const char* name, const std::string& path) const
    {
        renderer::ShaderProgramDescription description;
        description.name = name;
        description.vertex = renderer::ShaderSource::embedded(path + ".vert.glsl");
        description.fragment = renderer::ShaderSource::embedded(path + ".frag.glsl");
        description.fragment.text.insert(0, renderer::ShaderSource::embedded("scene/clipmap/surface_color.glsl").text);
        if (options.shading.any()) {
            description.fragment.text.insert(0, terrainShadingSource());
            addTerrainShadingDefines(options.shading, description.defines);
        }
        if (imagery) {
            description.defines.push_back({"IMAGERY"});
        }
        if (options.lighting) {
            description.defines.push_back({"LIGHTING"});
        }
        return description;
    }

    /// The levels' program.
    renderer::ShaderProgramDescription programDescription() const
    {
        renderer::ShaderProgramDescription description = surfaceDescription("clipmap terrain", "scene/clipmap/clipmap");
        if (options.colorByLevel) {
            description.defines.push_back({"COLOR_BY_LEVEL"});
        }
        return description;
    }

    /// A bounding sphere of a piece of level l, from 3 x 3 of its posts at the level's lowest and
    /// highest heights, grown by the bulge of the ellipsoid between them.
    BoundingSphere pieceSphere(int l, const ClipmapPiece& piece, double exaggeration) const
    {
        std::array<glm::dvec3, 18> points;
        std::size_t count = 0;
        const Level& level = levels[static_cast<std::size_t>(l)];
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < 3; ++i) {
                const std::int64_t x = originX(l) + piece.minimumX + (piece.maximumX - piece.minimumX) * i / 2;
                const std::int64_t y = originY(l) + piece.minimumY + (piece.maximumY - piece.minimumY) * j / 2;
                const glm::dvec3 normal = postNormal(l, x, y);
                points[count++] = surfacePoint(normal, exaggeration * level.minimumHeight);
                points[count++] = surfacePoint(normal, exaggeration * level.maximumHeight);
            }
        }
        BoundingSphere sphere = BoundingSphere::fromPoints(points);
        const double halfAngle = 0.25 * levelSpacing(l) * std::max(piece.maximumX - piece.minimumX, piece.maximumY - piece.minimumY);
        sphere.radius += ellipsoid.maximumRadius() * (1.0 - std::cos(halfAngle)) + 1.0;
        return sphere;
    }
};

ClipmapTerrain::ClipmapTerrain(const Ellipsoid& ellipsoid, ClipmapTerrainOptions options)
    : _options(std::move(options))
{
    const int n = _options.posts;
    if (n < 15 || n > 1023 || ((n + 1) & n) != 0) {
        throw Error("ClipmapTerrain: posts must be 2^k - 1 from 15 to 1023, not " + std::to_string(n));
    }
    if (_options.levels < 0 || _options.levels > 24) {
        throw Error("ClipmapTerrain: levels must be 0 (automatic) to 24, not " + std::to_string(_options.levels));
    }
    if (!std::isfinite(_options.finestSpacingDegrees) || _options.finestSpacingDegrees < 0.0) {
        throw Error("ClipmapTerrain: the finest spacing must be a finite number of degrees >= 0");
    }
    if (!std::isfinite(_options.exaggeration) || _options.exaggeration < 0.0) {
        throw Error("ClipmapTerrain: the exaggeration must be finite and >= 0");
    }
    if (ellipsoid.radii().x != ellipsoid.radii().y) {
        throw Error("ClipmapTerrain: the ellipsoid must be one of revolution (equal x and y radii)");
    }
    for (const ImageryLayer& layer : _options.imagery) {
        if (!layer.source) {
            throw Error("ClipmapTerrain: an imagery layer has no source");
        }
    }
    validateTerrainShading(_options.shading, "ClipmapTerrain");
    // The coarsest spacing that keeps the grid clear of its pole.
    const double coarsest = kMaximumHalfWidthRadians / (0.5 * (n - 1));
    double finest = toRadians(_options.finestSpacingDegrees);
    if (finest == 0.0) {
        if (_options.terrain) {
            const world::TerrainSourceInfo& info = _options.terrain->info();
            const int samples = info.gridSize > 0 ? info.gridSize - 1 : 64;
            finest = kPi / std::ldexp(1.0, static_cast<int>(info.maximumLevel)) / samples / 8.0;
        } else {
            finest = toRadians(1.0 / 64.0);
        }
    }
    int levels = _options.levels;
    if (levels == 0) {
        levels = 1;
        while (levels < 24 && finest * std::ldexp(1.0, levels) <= coarsest) {
            ++levels;
        }
    } else if (finest * std::ldexp(1.0, levels - 1) > coarsest) {
        // As many levels as asked, the finest made finer so that the coarsest still fits.
        finest = coarsest / std::ldexp(1.0, levels - 1);
    }
    finest = std::min(finest, coarsest);
    _impl = std::make_unique<Impl>(ellipsoid, _options, finest, levels);
    _statistics.levels = levels;
}

ClipmapTerrain::~ClipmapTerrain() = default;

int ClipmapTerrain::levels() const noexcept
{
    return static_cast<int>(_impl->levels.size());
}

double ClipmapTerrain::finestSpacing() const noexcept
{
    return _impl->spacing0;
}

std::optional<BoundingSphere> ClipmapTerrain::boundingSphere() const
{
    return BoundingSphere{glm::dvec3(0.0), _impl->ellipsoid.maximumRadius() + 10000.0 * std::max(1.0, _options.exaggeration)};
}

void ClipmapTerrain::update(FrameState& frameState, CommandList& commands)
{
    Impl& impl = *_impl;
    ClipmapStatistics statistics;
    statistics.levels = static_cast<int>(impl.levels.size());
    const int n = _options.posts;
    const int L = static_cast<int>(impl.levels.size());

    if (!impl.created) {
        impl.createResources(frameState);
    }
    // Arrivals first: they enter at the frame boundary.
    for (world::TileLoadResult& result : impl.loader.beginFrame(frameState.frameNumber)) {
        const int kind = static_cast<int>(result.ticket >> 62);
        const TileKey key{static_cast<std::uint32_t>((result.ticket >> 56) & 0x3f),
                          static_cast<std::uint32_t>((result.ticket >> 28) & 0xfffffff),
                          static_cast<std::uint32_t>(result.ticket & 0xfffffff)};
        if (result.status == world::TileLoadResult::Status::Failed) {
            impl.warn(result.message);
        }
        if (result.status != world::TileLoadResult::Status::Loaded) {
            impl.failedOrMissing.insert(result.ticket);
            continue;
        }
        ++statistics.tilesLoaded;
        if (kind == 0) {
            auto* content = static_cast<TerrainContent*>(result.content.get());
            impl.terrainTiles.insert(key, content->grid, content->byteSize(), _options.cacheBytes / 2);
            impl.arrived(0, key, impl.terrain->info().scheme.tileExtent(key));
        } else {
            auto* content = static_cast<ImageryContent*>(result.content.get());
            const std::size_t bytes = content->byteSize();
            impl.imageryTiles.insert(key, content->image, bytes, _options.cacheBytes / 2);
            impl.arrived(1, key, impl.imagery->info().scheme.tileExtent(key));
        }
    }

    // Place the levels around the viewer.
    if (impl.followViewer(frameState.camera.eye())) {
        for (Impl::Level& level : impl.levels) {
            level.heights.invalidate();
            level.gradients.invalidate();
            level.colors.invalidate();
            level.pending.clear();
            level.refresh.clear();
        }
    }
    statistics.parameterization = impl.frame;
    const std::vector<std::int64_t> origins =
        clipmapOrigins(impl.viewerLongitude / impl.spacing0, impl.viewerLatitude / impl.spacing0, L, n);
    // Levels finer than the eye's height needs are neither updated nor drawn (Losasso and Hoppe:
    // a level is useful while the eye is lower than 0.4 of its width).
    auto finestLevelNeeded = [&] {
        const double eyeHeight = std::max(1.0, impl.ellipsoid.toGeodetic3D(frameState.camera.eye()).height -
                                                   _options.exaggeration * impl.levels.back().maximumHeight);
        int finest = 0;
        while (finest < L - 1 && eyeHeight > 0.4 * (n - 1) * impl.levelSpacing(finest) * impl.ellipsoid.maximumRadius()) {
            ++finest;
        }
        return finest;
    };
    const int finestNeeded = finestLevelNeeded();
    for (int l = 0; l < L; ++l) {
        Impl::Level& level = impl.levels[static_cast<std::size_t>(l)];
        level.needed = l >= finestNeeded;
        if (!level.needed) {
            // Rewritten whole when it is needed again.
            level.heights.invalidate();
            level.gradients.invalidate();
            level.colors.invalidate();
            level.pending.clear();
            level.refresh.clear();
            continue;
        }
        const std::int64_t x = origins[2 * static_cast<std::size_t>(l)], y = origins[2 * static_cast<std::size_t>(l) + 1];
        const bool wasPlaced = level.heights.placed();
        std::vector<GridRegion> regions = level.heights.moveTo(x, y);
        level.gradients.moveTo(x, y);
        level.colors.moveTo(x, y);
        if (!wasPlaced) {
            level.minimumHeight = 0.0;
            level.maximumHeight = 0.0;
            level.pending.clear();
            level.refresh.clear();
        }
        if (!regions.empty()) {
            level.pending.insert(level.pending.end(), regions.begin(), regions.end());
            level.bounds = impl.levelBounds(l);
            // A refresh under way starts again over the window as it is now.
            if (!level.refresh.empty()) {
                level.refresh = {{x, y, impl.size, impl.size}};
            }
        }
    }
    if (!impl.backdrop.built && impl.requestBackdropTiles()) {
        impl.buildBackdrop(frameState);
    }
    for (int l = L - 1; l >= finestNeeded; --l) {
        statistics.tilesRequested += (impl.terrain || impl.imagery) ? impl.requestTiles(l) : 0;
    }
    impl.loader.endFrame();

    // Writes, coarse levels first, within the budget; pending moves before refreshes.
    TileFinder<std::shared_ptr<const TerrainGrid>> terrainFinder{&impl.terrainTiles,
                                                                    impl.terrain ? impl.terrain->info().scheme : TilingScheme::geographic(),
                                                                    impl.terrain ? impl.terrain->info().minimumLevel : 0};
    TileFinder<std::shared_ptr<const ImageTexels>> imageryFinder{&impl.imageryTiles,
                                                          impl.imagery ? impl.imagery->info().scheme : TilingScheme::geographic(),
                                                          impl.imagery ? impl.imagery->info().minimumLevel : 0};
    const double writesStarted = threadCpuMilliseconds();
    std::size_t budget = std::max<std::size_t>(_options.postsPerFrame, static_cast<std::size_t>(impl.size));
    for (const bool refreshing : {false, true}) {
        for (int l = L - 1; l >= finestNeeded; --l) {
            Impl::Level& level = impl.levels[static_cast<std::size_t>(l)];
            std::vector<GridRegion>& queue = refreshing ? level.refresh : level.pending;
            // A refresh waits for the coarser level's moves (it may upsample from them).
            if (refreshing && l + 1 < L && !impl.levels[static_cast<std::size_t>(l) + 1].pending.empty()) {
                continue;
            }
            while (!queue.empty() && budget > 0) {
                GridRegion& region = queue.front();
                const std::size_t rowPosts = static_cast<std::size_t>(std::max(region.width, 1));
                const int rows = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(region.height),
                                                                        std::max<std::size_t>(1, budget / rowPosts)));
                const GridRegion part{region.x, region.y, region.width, rows};
                statistics.bytesUploaded += impl.write(l, part, terrainFinder, imageryFinder);
                const std::size_t posts = rowPosts * static_cast<std::size_t>(rows);
                statistics.postsUpdated += posts;
                budget -= std::min(budget, posts);
                region.y += rows;
                region.height -= rows;
                if (region.height <= 0) {
                    queue.erase(queue.begin());
                }
            }
            if (!refreshing && !queue.empty()) {
                // Finer levels upsample from this one: they wait.
                break;
            }
        }
    }
    statistics.updateMilliseconds = threadCpuMilliseconds() - writesStarted;
    // The finest level drawn: the finest one with every coarser level complete; none (L) while
    // the coarsest has strips left to write.
    int finestDrawn = L;
    for (int l = L - 1; l >= finestNeeded; --l) {
        const Impl::Level& level = impl.levels[static_cast<std::size_t>(l)];
        if (!level.pending.empty() || !level.heights.placed()) {
            break;
        }
        finestDrawn = l;
    }
    for (int l = finestNeeded; l < L; ++l) {
        const Impl::Level& level = impl.levels[static_cast<std::size_t>(l)];
        for (const GridRegion& region : level.pending) {
            statistics.postsPending += static_cast<std::size_t>(region.width) * static_cast<std::size_t>(region.height);
        }
        for (const GridRegion& region : level.refresh) {
            statistics.postsPending += static_cast<std::size_t>(region.width) * static_cast<std::size_t>(region.height);
        }
        statistics.levelsPending += (!level.pending.empty() || !level.refresh.empty()) ? 1 : 0;
    }
    statistics.tilesPending = impl.loader.inFlight();
    statistics.finestLevelDrawn = finestDrawn;
    // Heights written this frame may move the level the eye needs (it is measured from the terrain).
    statistics.converged = statistics.postsPending == 0 && statistics.tilesPending == 0 &&
                           statistics.tilesRequested == 0 && finestLevelNeeded() == finestNeeded && impl.backdrop.built;

    renderer::ShaderProgram& program = impl.programs.get(frameState);
    statistics.gpuBytes = static_cast<std::size_t>(L) * static_cast<std::size_t>(impl.size) * static_cast<std::size_t>(impl.size) * (4 + 8 + 4) +
                          impl.layout.indices().size() * 4 + static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * 8 +
                          impl.backdropBytes();

    // The commands: per level one arc of its pieces (two ranges where the arc wraps), the finest
    // drawn level's interior besides.
    impl.drawn.clear();
    impl.drawnFinest = finestDrawn;
    impl.drawnDepthStrategy = frameState.depthStrategy;
    const glm::dvec3 eye = frameState.camera.eye();
    const glm::mat3 frameRotation = frameMatrix(impl.frame);
    const double a = impl.ellipsoid.radii().x;
    const double e2 = 1.0 - (impl.ellipsoid.radii().z * impl.ellipsoid.radii().z) / (a * a);
    const int c = impl.centerPost();
    const float blendWidth = static_cast<float>(std::max(2, n / 10));
    // The height the centres' references stand at: the eye's, so that the vertex shader's
    // height differences from it are small where precision shows (0.44 px at 1 m from heights of
    // 5 km, 0.013 px with them).
    const auto referenceHeight = static_cast<float>(impl.ellipsoid.toGeodetic3D(eye).height);
    for (int l = finestDrawn; l < L; ++l) {
        const Impl::Level& level = impl.levels[static_cast<std::size_t>(l)];
        const bool finest = l == finestDrawn;
        const bool hasCoarser = l + 1 < L;
        ClipmapTrim trim = ClipmapTrim::SouthWest;
        if (!finest) {
            trim = ClipmapBlockLayout::trimFor(static_cast<int>(impl.originX(l - 1) / 2 - impl.originX(l)),
                                               static_cast<int>(impl.originY(l - 1) / 2 - impl.originY(l)),
                                               impl.layout.blockPosts());
        }
        const std::vector<ClipmapPiece>& ring = impl.layout.ring(trim);
        std::vector<char> visible(ring.size(), 0);
        std::vector<BoundingSphere> spheres(ring.size());
        for (std::size_t p = 0; p < ring.size(); ++p) {
            spheres[p] = impl.pieceSphere(l, ring[p], _options.exaggeration);
            visible[p] = frameState.cullingVolume.intersect(spheres[p]) != Intersect::Outside;
            statistics.piecesCulled += visible[p] ? 0 : 1;
        }
        // The longest circular run of culled pieces is left out; the rest is drawn as one arc.
        std::vector<std::pair<std::size_t, std::size_t>> ranges; // piece index ranges [first, last]
        const std::size_t count = ring.size();
        if (std::count(visible.begin(), visible.end(), 1) == static_cast<std::ptrdiff_t>(count)) {
            ranges.push_back({0, count - 1});
        } else if (std::count(visible.begin(), visible.end(), 1) > 0) {
            std::size_t bestStart = 0, bestLength = 0;
            for (std::size_t start = 0; start < count; ++start) {
                if (visible[start] || !visible[(start + count - 1) % count]) {
                    continue; // runs start after a visible piece
                }
                std::size_t length = 0;
                while (length < count && !visible[(start + length) % count]) {
                    ++length;
                }
                if (length > bestLength) {
                    bestLength = length;
                    bestStart = start;
                }
            }
            const std::size_t first = (bestStart + bestLength) % count;
            const std::size_t last = (bestStart + count - 1) % count;
            if (first <= last) {
                ranges.push_back({first, last});
            } else {
                ranges.push_back({first, count - 1});
                ranges.push_back({0, last});
            }
        }
        std::vector<std::tuple<std::size_t, std::size_t, BoundingSphere>> draws;
        for (const auto& [first, last] : ranges) {
            BoundingSphere sphere = spheres[first];
            for (std::size_t p = first + 1; p <= last; ++p) {
                sphere = BoundingSphere::merge(sphere, spheres[p]);
            }
            draws.emplace_back(ring[first].firstIndex, ring[last].firstIndex + ring[last].indexCount - ring[first].firstIndex, sphere);
        }
        if (finest) {
            const ClipmapPiece& interior = impl.layout.interior();
            const BoundingSphere sphere = impl.pieceSphere(l, interior, _options.exaggeration);
            if (frameState.cullingVolume.intersect(sphere) != Intersect::Outside) {
                draws.emplace_back(interior.firstIndex, interior.indexCount, sphere);
            } else {
                ++statistics.piecesCulled;
            }
        }
        if (draws.empty()) {
            continue;
        }
        const std::int64_t wrap = 2 * static_cast<std::int64_t>(impl.size) - 1;
        const Impl::Level& coarserLevel = impl.levels[static_cast<std::size_t>(hasCoarser ? l + 1 : l)];
        const Impl::Reference reference = impl.reference(l, eye, referenceHeight);
        const Impl::Reference coarserReference = impl.reference(hasCoarser ? l + 1 : l, eye, referenceHeight);
        for (const auto& [first, indexCount, sphere] : draws) {
            SceneCommand command;
            command.draw.debugName = "clipmap terrain level " + std::to_string(l);
            // The globe's surface, as the tiles' is.
            command.tags = Effect::Globe | Effect::Terrain | Effect::ClipmapTerrain;
            command.ground = true;
            if (_options.lighting) {
                command.tags = command.tags | Effect::Lighting;
            }
            if (_options.shading.any()) {
                command.tags = command.tags | Effect::TerrainShading;
                setTerrainShadingUniforms(_options.shading, command.draw.uniforms);
            }
            command.draw.vertexArray = &*impl.vertexArray;
            command.draw.shaderProgram = &program;
            command.draw.first = first;
            command.draw.count = indexCount;
            command.boundingSphere = sphere;
            const double distance = glm::length(sphere.centre - eye);
            command.nearestDistance = std::max(0.0, distance - sphere.radius);
            command.farthestDistance = distance + sphere.radius;
            auto set = [&](std::string_view name, const renderer::UniformValue& value) {
                if (program.hasUniform(name)) {
                    command.draw.uniforms.set(name, value);
                }
            };
            set("u_levelOrigin", glm::ivec2(static_cast<int>(impl.originX(l) & wrap), static_cast<int>(impl.originY(l) & wrap)));
            set("u_textureSize", impl.size);
            set("u_centerPost", static_cast<float>(c));
            set("u_spacing", reference.spacing);
            set("u_centerTrig", reference.trig);
            set("u_centerNormal", reference.normal);
            set("u_centerRelativeToEye", reference.relativeToEye);
            set("u_centerRadius", reference.radius);
            set("u_referenceHeight", referenceHeight);
            set("u_coarserSpacing", coarserReference.spacing);
            set("u_coarserCenterTrig", coarserReference.trig);
            set("u_coarserCenterNormal", coarserReference.normal);
            set("u_coarserCenterRelativeToEye", coarserReference.relativeToEye);
            set("u_coarserCenterRadius", coarserReference.radius);
            set("u_hasCoarser", hasCoarser);
            set("u_originOnCoarser", hasCoarser ? glm::ivec2(static_cast<int>(impl.originX(l) / 2 - impl.originX(l + 1)),
                                                             static_cast<int>(impl.originY(l) / 2 - impl.originY(l + 1)))
                                                : glm::ivec2(0));
            set("u_eccentricitySquared", static_cast<float>(e2));
            set("u_frame", frameRotation);
            set("u_blend", glm::vec2(hasCoarser ? static_cast<float>(c) - blendWidth : 1e9f, blendWidth));
            set("u_exaggeration", static_cast<float>(_options.exaggeration));
            set("u_levelColor", unpack(kLevelPalette[l % 8]));
            set("u_coarserLevelColor", unpack(kLevelPalette[(hasCoarser ? l + 1 : l) % 8]));
            command.draw.textures.push_back({0, &level.heightTexture, &*impl.nearest});
            command.draw.textures.push_back({1, &level.gradientTexture, &*impl.nearest});
            command.draw.textures.push_back({2, &level.colorTexture, &*impl.repeatLinear});
            command.draw.textures.push_back({3, &coarserLevel.heightTexture, &*impl.nearest});
            command.draw.textures.push_back({4, &coarserLevel.gradientTexture, &*impl.nearest});
            command.draw.textures.push_back({5, &coarserLevel.colorTexture, &*impl.repeatLinear});
            impl.drawn.push_back({l, first, indexCount, command.draw});
            commands.push_back(std::move(command));
            ++statistics.drawCalls;
            statistics.trianglesSubmitted += indexCount / 3;
        }
    }
    const int coarsest = L - 1;
    const bool anyDrawn = finestDrawn < L;
    // The coarsest level's extent in the grid, less its outer two posts (where both draw).
    const double coarsestSpacing = impl.levelSpacing(coarsest);
    const glm::dvec2 coarsestCenter(static_cast<double>(impl.originX(coarsest) + c) * coarsestSpacing,
                                    static_cast<double>(impl.originY(coarsest) + c) * coarsestSpacing);
    const double coarsestHalfWidth = anyDrawn ? (c - 2) * coarsestSpacing : 0.0;
    if (impl.backdrop.built && impl.backdropVisible(eye, coarsestCenter, coarsestHalfWidth, _options.exaggeration)) {
        // The rest of the globe, where no level is (all of it while none is drawn).
        renderer::ShaderProgram& backdropProgram = impl.backdropPrograms.get(frameState);
        SceneCommand command;
        command.draw.debugName = "clipmap terrain backdrop";
        command.tags = Effect::Globe | Effect::Terrain | Effect::ClipmapTerrain;
        command.ground = true;
        if (_options.lighting) {
            command.tags = command.tags | Effect::Lighting;
        }
        command.draw.vertexArray = &*impl.backdrop.vertexArray;
        command.draw.shaderProgram = &backdropProgram;
        const BoundingSphere globe = *boundingSphere();
        command.boundingSphere = globe;
        const double distance = glm::length(eye);
        command.nearestDistance = std::max(0.0, distance - globe.radius);
        command.farthestDistance = distance + globe.radius;
        if (_options.shading.any()) {
            command.tags = command.tags | Effect::TerrainShading;
            setTerrainShadingUniforms(_options.shading, command.draw.uniforms);
        }
        command.draw.uniforms.set("u_toGrid", glm::transpose(frameRotation));
        command.draw.uniforms.set("u_coarsestCenter", glm::vec2(coarsestCenter));
        command.draw.uniforms.set("u_coarsestHalfWidth", static_cast<float>(coarsestHalfWidth));
        command.draw.textures.push_back({0, &impl.backdrop.colors, &*impl.backdrop.sampler});
        commands.push_back(std::move(command));
        ++statistics.drawCalls;
        statistics.trianglesSubmitted += impl.backdrop.indices.count() / 3;
        statistics.backdropDrawn = true;
    }
    _statistics = statistics;
}

std::optional<double> ClipmapTerrain::groundHeight(const Geodetic2D& position) const
{
    const Impl& impl = *_impl;
    if (impl.drawn.empty() || !std::isfinite(position.longitude) || !std::isfinite(position.latitude)) {
        return std::nullopt;
    }
    const int n = _options.posts;
    const int c = impl.centerPost();
    const int L = static_cast<int>(impl.levels.size());
    // The point's angles in the grid's parameterisation.
    const glm::dvec3 u = toFrame(impl.frame, Ellipsoid::geodeticSurfaceNormal(position));
    const double gridLatitude = std::asin(std::clamp(u.z, -1.0, 1.0));
    const double gridLongitude = std::atan2(u.y, u.x);
    for (int l = impl.drawnFinest; l < L; ++l) {
        const double s = impl.levelSpacing(l);
        // The turn of longitude that puts the point nearest the level's window.
        const double turn = kTwoPi / s;
        const double centreX = static_cast<double>(impl.originX(l) + c);
        double x = gridLongitude / s;
        x += std::round((centreX - x) / turn) * turn;
        // A millionth of a post of slack: a point on the window's edge may round to either side.
        constexpr double kSlack = 1e-6;
        const double localX = x - static_cast<double>(impl.originX(l));
        const double localY = gridLatitude / s - static_cast<double>(impl.originY(l));
        if (!(localX >= -kSlack && localX <= n - 1.0 + kSlack && localY >= -kSlack && localY <= n - 1.0 + kSlack)) {
            continue;
        }
        const int px = std::clamp(static_cast<int>(localX), 0, n - 2), py = std::clamp(static_cast<int>(localY), 0, n - 2);
        const double fx = std::clamp(localX - px, 0.0, 1.0), fy = std::clamp(localY - py, 0.0, 1.0);
        // On the cell's triangle: every quad is cut from post (x, y) to (x + 1, y + 1), so the
        // third corner is (x + 1, y) below that diagonal and (x, y + 1) above it.
        const bool belowDiagonal = fx >= fy;
        const double h00 = impl.drawnHeight(l, px, py), h11 = impl.drawnHeight(l, px + 1, py + 1);
        const double third = belowDiagonal ? impl.drawnHeight(l, px + 1, py) : impl.drawnHeight(l, px, py + 1);
        const double height = belowDiagonal ? h00 + fx * (third - h00) + fy * (h11 - third)
                                            : h00 + fy * (third - h00) + fx * (h11 - third);
        return _options.exaggeration * height;
    }
    return std::nullopt;
}

std::optional<HeightInterval> ClipmapTerrain::drawnHeights(const GeodeticExtent& extent) const
{
    const Impl& impl = *_impl;
    const int n = _options.posts;
    const int c = impl.centerPost();
    const int L = static_cast<int>(impl.levels.size());
    const int finestDrawn = impl.drawnFinest;
    if (finestDrawn >= L && !_statistics.backdropDrawn) {
        return std::nullopt;
    }
    // The extent as a cap of unit normals (its farthest points from its centre are corners), and
    // the cap's half widths in the grid's angles: latitude by its radius, longitude by the widest
    // it gets, asin(sin r / cos latitude), or all round when it holds the grid's pole.
    const glm::dvec3 centre = Ellipsoid::geodeticSurfaceNormal(extent.centre());
    double radius = 0.0;
    for (const double longitude : {extent.west, extent.east}) {
        for (const double latitude : {extent.south, extent.north}) {
            radius = std::max(radius, detail::centralAngle(centre, Ellipsoid::geodeticSurfaceNormal(Geodetic2D{longitude, latitude})));
        }
    }
    const glm::dvec3 u = toFrame(impl.frame, centre);
    const double gridLatitude = std::asin(std::clamp(u.z, -1.0, 1.0));
    const double gridLongitude = std::atan2(u.y, u.x);
    const double halfLongitude = std::abs(gridLatitude) + radius < kHalfPi
                                     ? std::asin(std::min(1.0, std::sin(radius) / std::cos(gridLatitude)))
                                     : kPi;
    // The cap's box in level l's global post numbers: columns aligned with its window by turns.
    struct Box {
        double x0, x1, y0, y1;
    };
    auto boxIn = [&](int l) {
        const double s = impl.levelSpacing(l);
        const double turn = kTwoPi / s;
        double x = gridLongitude / s;
        x += std::round((static_cast<double>(impl.originX(l) + c) - x) / turn) * turn;
        return Box{x - halfLongitude / s, x + halfLongitude / s, (gridLatitude - radius) / s, (gridLatitude + radius) / s};
    };
    auto inside = [](const Box& box, double x0, double y0, double x1, double y1) {
        return box.x0 >= x0 && box.x1 <= x1 && box.y0 >= y0 && box.y1 <= y1;
    };
    const double exaggeration = _options.exaggeration;
    std::optional<HeightInterval> heights;
    for (int l = finestDrawn; l < L; ++l) {
        const Box box = boxIn(l);
        const auto x0 = static_cast<double>(impl.originX(l)), y0 = static_cast<double>(impl.originY(l));
        if (box.x1 < x0 || box.x0 > x0 + n - 1 || box.y1 < y0 || box.y0 > y0 + n - 1) {
            continue; // beyond its window
        }
        if (l > finestDrawn) {
            // Within the finer level's window, less a post: drawn by that level, not this one.
            const double fx = static_cast<double>(impl.originX(l - 1)) / 2.0, fy = static_cast<double>(impl.originY(l - 1)) / 2.0;
            const double half = (n - 1) / 2.0;
            if (inside(box, fx + 1.0, fy + 1.0, fx + half - 1.0, fy + half - 1.0)) {
                continue;
            }
        }
        // Its posts, blended over its outer band towards the coarser level's (heights the levels
        // have held since placed), less what its flat cells sag.
        const Impl::Level& level = impl.levels[static_cast<std::size_t>(l)];
        double lowest = level.minimumHeight, highest = level.maximumHeight;
        if (l + 1 < L) {
            const Impl::Level& coarser = impl.levels[static_cast<std::size_t>(l) + 1];
            lowest = std::min(lowest, coarser.minimumHeight);
            highest = std::max(highest, coarser.maximumHeight);
        }
        heights = enclose(heights, {exaggeration * lowest - detail::triangleSagBound(impl.ellipsoid, 2.0 * impl.levelSpacing(l)),
                                    exaggeration * highest});
    }
    if (_statistics.backdropDrawn) {
        // Drawn where no level is: beyond the coarsest level's window less its outer two posts.
        const int coarsest = L - 1;
        const auto x0 = static_cast<double>(impl.originX(coarsest)), y0 = static_cast<double>(impl.originY(coarsest));
        if (finestDrawn >= L || !inside(boxIn(coarsest), x0 + 2.0, y0 + 2.0, x0 + n - 3.0, y0 + n - 3.0)) {
            heights = enclose(heights, {impl.backdrop.lowest - detail::triangleSagBound(impl.ellipsoid, toRadians(2.0)),
                                        impl.backdrop.highest});
        }
    }
    return heights;
}

void ClipmapTerrain::forEachDrawnTriangle(bool withDegenerates,
                                          const std::function<void(const glm::dvec3&, const glm::dvec3&, const glm::dvec3&)>& visit) const
{
    const Impl& impl = *_impl;
    const int n = _options.posts;
    // The vertex shader's position of a post, in double.
    auto position = [&](int l, int x, int y) {
        return impl.surfacePoint(impl.postNormal(l, impl.originX(l) + x, impl.originY(l) + y),
                                 _options.exaggeration * impl.drawnHeight(l, x, y));
    };
    for (const Impl::Drawn& d : impl.drawn) {
        for (std::size_t i = d.firstIndex; i < d.firstIndex + d.indexCount; i += 3) {
            std::array<glm::ivec2, 3> posts;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t index = impl.layout.indices()[i + static_cast<std::size_t>(k)];
                posts[static_cast<std::size_t>(k)] = {static_cast<int>(index % static_cast<std::uint32_t>(n)),
                                                      static_cast<int>(index / static_cast<std::uint32_t>(n))};
            }
            const glm::ivec2 e1 = posts[1] - posts[0], e2 = posts[2] - posts[0];
            if (!withDegenerates && e1.x * e2.y - e1.y * e2.x == 0) {
                continue;
            }
            visit(position(d.level, posts[0].x, posts[0].y), position(d.level, posts[1].x, posts[1].y),
                  position(d.level, posts[2].x, posts[2].y));
        }
    }
}

std::vector<glm::vec4> ClipmapTerrain::captureDrawnClipPositions(renderer::Context& context,
                                                                 const renderer::SceneState& sceneState) const
{
    Impl& impl = *_impl;
    renderer::ShaderProgramDescription description = impl.programDescription();
    for (renderer::ShaderDefine& define : depthStrategyDefines(impl.drawnDepthStrategy, Pass::Opaque)) {
        description.defines.push_back(std::move(define));
    }
    description.transformFeedbackVaryings = {"gl_Position"};
    const std::shared_ptr<renderer::ShaderProgram> capturing = context.device().shaderCache().get(description);
    // Rasterisation is off while capturing; the draw needs a target all the same.
    renderer::Framebuffer target = context.createFramebuffer(1, 1);
    std::vector<glm::vec4> clip;
    for (const Impl::Drawn& d : impl.drawn) {
        renderer::DrawCommand command = d.command;
        command.shaderProgram = capturing.get();
        command.framebuffer = &target;
        const std::vector<float> captured = context.captureVertexOutputs(command, sceneState);
        for (std::size_t i = 0; i + 4 <= captured.size(); i += 4) {
            clip.emplace_back(captured[i], captured[i + 1], captured[i + 2], captured[i + 3]);
        }
    }
    return clip;
}

std::vector<glm::dvec3> ClipmapTerrain::drawnTriangles(bool withDegenerates) const
{
    std::vector<glm::dvec3> triangles;
    forEachDrawnTriangle(withDegenerates, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        triangles.insert(triangles.end(), {a, b, c});
    });
    return triangles;
}

std::optional<double> ClipmapTerrain::pickGround(const Ray& ray) const
{
    // Every drawn triangle whose bounding sphere the ray enters nearer than the nearest hit so far.
    std::optional<double> nearest;
    forEachDrawnTriangle(false, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        const glm::dvec3 centre = (a + b + c) / 3.0;
        const double radius = std::max({glm::distance(a, centre), glm::distance(b, centre), glm::distance(c, centre)});
        const std::optional<RayInterval> inside = intersectRaySphere(ray, BoundingSphere{centre, radius});
        if (!inside || (nearest && inside->nearDistance > *nearest)) {
            return;
        }
        if (const std::optional<RayTriangleHit> hit = intersectRayTriangle(ray, a, b, c)) {
            if (!nearest || hit->distance < *nearest) {
                nearest = hit->distance;
            }
        }
    });
    return nearest;
}

} // namespace orbis::scene
