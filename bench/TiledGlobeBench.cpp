// The streamed globe (book chapter 12, course chapter 3): the screen-space error setting against
// loads, bytes and frames to converge; the selection's own cost; convergence after a jump with a
// loader of fixed latency and loads per frame; the decode-and-upload pipeline against decoding
// alone; a 2,000-frame flight under the cache's cap; the streamed frame against the fill floor.

#include "GlMeasurements.h"
#include "Report.h"
#include "SyntheticImagery.h"

#include <orbis/core/Error.h>
#include <orbis/core/ImageMipmaps.h>
#include <orbis/core/IntersectionTests.h>
#include <orbis/core/TileMesh.h>
#include <orbis/core/Transforms.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/scene/Camera.h>
#include <orbis/scene/Scene.h>
#include <orbis/world/TerrainSampler.h>
#include <orbis/scene/ClipmapTerrain.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/scene/TileQuadtree.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/FunctionTerrainSource.h>
#include <orbis/world/TerrainHeight.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TileLoader.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <random>
#include <ctime>
#include <thread>

using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::bench {
namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
const std::filesystem::path kBlueMarble = std::filesystem::path(ORBIS_SOURCE_DIR) / "data/imagery/BlueMarble";

struct View {
    Geodetic3D position;
    double headingDegrees;
    double pitchDegrees;
};

const View kOrbit{Geodetic3D::fromDegrees(10.0, 40.0, 2.0e7), 0.0, -90.0};
const View kAlps{Geodetic3D::fromDegrees(7.6, 45.6, 10000.0), 40.0, -20.0};

Camera cameraAt(const View& view)
{
    const glm::dvec3 eye = kEarth.toCartesian(view.position);
    const ViewOrientation orientation =
        headingPitchRollToView(kEarth, eye, toRadians(view.headingDegrees), toRadians(view.pitchDegrees), 0.0);
    return Camera(eye, eye + orientation.direction * glm::length(eye), orientation.up, toRadians(45.0));
}

/// A scene with one streamed globe over `source`, deterministic loads.
struct StreamedScene {
    std::shared_ptr<TiledGlobe> globe;
    Scene scene{kEarth};

    StreamedScene(std::shared_ptr<world::TileSource> source, const TiledGlobeOptions& base)
    {
        TiledGlobeOptions options = base;
        options.imagery.push_back({std::move(source), {}});
        globe = std::make_shared<TiledGlobe>(kEarth, options);
        scene.add(globe);
    }
    void look(const View& view) { scene.camera() = cameraAt(view); }
};

/// Renders until the tiles converge; frames rendered and loads started on the way.
struct Convergence {
    int frames = 0;
    std::size_t loads = 0;
    bool converged = false;
    FrameStatistics last;
};

Convergence converge(StreamedScene& streamed, Context& context, int maximumFrames)
{
    Convergence result;
    while (result.frames < maximumFrames) {
        result.last = streamed.scene.render(context);
        ++result.frames;
        result.loads += streamed.globe->loadsStarted().size();
        if (result.last.tiles->converged) {
            result.converged = true;
            break;
        }
    }
    return result;
}

/// Tiles of data the converged view reads: surface meshes and imagery tiles.
std::size_t tilesInView(const FrameStatistics& statistics)
{
    return statistics.tiles->drawn + statistics.tiles->imageryDrawn;
}

// ---- Screen-space error against loads and time -----------------------------------------------

Table errorTable(const Options& options, Device& device, Context& context)
{
    Table table;
    table.title = "Streamed globe: screen-space error against loads and frame time";
    table.description =
        "10 km over the Alps looking 20 degrees down, 1280x720, from a cold start: synthetic imagery 18 levels "
        "deep (one real 256x256 JPEG for every tile: real fetches and decodes), deterministic loader (1 frame of "
        "latency, 64 loads a frame, 2 threads). Loads: surface meshes and imagery tiles started until the view "
        "converged; frame time: the converged view, average of 5 frames.";
    table.columns = {"max SSE (px)", "loads", "MB read", "frames to converge", "tiles drawn", "deepest level",
                     "largest SSE drawn", "ms per frame"};
    const std::vector<double> errors = options.quick ? std::vector<double>{8.0} : std::vector<double>{1.0, 2.0, 4.0, 8.0};
    for (const double error : errors) {
        auto source = std::make_shared<SyntheticImagery>(18);
        TiledGlobeOptions tiled;
        tiled.lighting = true;
        tiled.maximumScreenSpaceError = error;
        tiled.loader.latencyFrames = 1;
        tiled.loader.maximumStartsPerFrame = 64;
        tiled.loader.maximumInFlight = 128;
        tiled.cacheBytes = std::size_t{1} << 30;
        tiled.uploadBytesPerFrame = std::size_t{64} << 20;
        StreamedScene streamed(source, tiled);
        streamed.look(kAlps);
        const Convergence convergence = converge(streamed, context, 600);
        const double ms = millisecondsPerFrame(streamed.scene, context, options.quick ? 1 : 5);
        const TileStatistics& tiles = *convergence.last.tiles;
        table.rows.push_back({formatNumber(error, 2), std::to_string(convergence.loads),
                              formatNumber(static_cast<double>(source->bytesRead) / 1e6, 3),
                              convergence.converged ? std::to_string(convergence.frames) : "not converged",
                              std::to_string(tiles.drawn), std::to_string(tiles.deepestLevelDrawn),
                              formatNumber(tiles.largestScreenSpaceErrorDrawn, 3), formatNumber(ms, 3)});
    }
    (void)device;
    table.notes = "Halving the error asks for about twice as many tiles in each direction near the eye; the "
                  "frame time follows the tiles drawn.";
    return table;
}

// ---- Selection cost ------------------------------------------------------------------------

Table selectionTable(const Options& options)
{
    // Every tile drawable: the traversal alone, GL-free, as a converged frame runs it.
    TileQuadtree quadtree(kEarth, TilingScheme::geographic(), 64, [](QuadtreeTile& tile) {
        tile.renderable = true;
        tile.wantsLoad = false;
    });
    TileSelectionOptions selectionOptions;
    selectionOptions.maximumLevel = 18;
    constexpr int kWidth = 1920;
    constexpr int kHeight = 1080;
    std::mt19937_64 random(12);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<View> views{kAlps, kOrbit, {Geodetic3D::fromDegrees(86.9, 27.9, 300000.0), 0.0, -30.0}};
    const int randomViews = options.quick ? 10 : 200;
    for (int i = 0; i < randomViews; ++i) {
        const double height = std::exp(std::log(200.0) + unit(random) * (std::log(2.0e7) - std::log(200.0)));
        views.push_back({Geodetic3D(kPi * (2.0 * unit(random) - 1.0), std::asin(2.0 * unit(random) - 1.0), height),
                         360.0 * unit(random), -90.0 + 85.0 * unit(random)});
    }
    TileSelection selection;
    std::vector<double> milliseconds;
    std::size_t visited = 0;
    double total = 0.0;
    std::uint64_t frame = 1;
    for (const View& view : views) {
        const Camera camera = cameraAt(view);
        TileView tileView;
        tileView.eye = camera.eye();
        tileView.direction = camera.direction();
        const double height = std::max(1.0, view.position.height);
        tileView.frustum = Frustum::fromViewProjection(
            camera.projectionMatrix(static_cast<double>(kWidth) / kHeight, std::max(1.0, 0.5 * height),
                                    2.0 * glm::length(camera.eye()) + 1e7) *
            camera.viewMatrix());
        tileView.viewportHeightPixels = kHeight;
        tileView.fieldOfViewY = camera.fieldOfViewY();
        quadtree.select(tileView, selectionOptions, frame++, selection); // makes the tiles: not timed
        const int repeats = options.quick ? 1 : 20;
        double best = 1e30;
        for (int r = 0; r < repeats; ++r) {
            const auto start = std::chrono::steady_clock::now();
            quadtree.select(tileView, selectionOptions, frame++, selection);
            best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        }
        milliseconds.push_back(best);
        visited += selection.visited;
        total += best;
    }
    std::vector<double> sorted = milliseconds;
    std::sort(sorted.begin(), sorted.end());
    Table table;
    table.title = "Streamed globe: the selection's cost";
    table.description =
        "TileQuadtree::select at 1920x1080, maximum screen-space error 2 px, every tile resident (a converged "
        "frame), best of 20 runs per view: the Alps at 10 km, the whole Earth, Everest at 300 km and " +
        std::to_string(randomViews) +
        " random views from 200 m to 20,000 km (straight down to 5 degrees below the horizon). Targets: at most "
        "150 ns per visited tile and 0.3 ms per frame.";
    table.columns = {"views", "tiles visited per view", "ns per visited tile", "ms per frame (Alps)",
                     "ms per frame (median)", "ms per frame (max)"};
    const double viewCount = static_cast<double>(views.size());
    table.rows.push_back({std::to_string(views.size()), formatNumber(static_cast<double>(visited) / viewCount, 3),
                          formatNumber(total * 1e6 / static_cast<double>(visited), 3), formatNumber(milliseconds[0], 3),
                          formatNumber(sorted[sorted.size() / 2], 3), formatNumber(sorted.back(), 3)});
    return table;
}

// ---- After a jump ----------------------------------------------------------------------------

Table jumpTable(const Options& options, Context& context)
{
    Table table;
    table.title = "Streamed globe: convergence after a jump";
    table.description =
        "Converged on the whole Earth from 20,000 km, then the camera jumps to 10 km over the Alps (1280x720, "
        "maximum screen-space error 2 px). The loader has a fixed latency L (frames from start to arrival) and "
        "starts at most B loads a frame (2 threads; deterministic timing, so every run loads the same tiles in "
        "the same order). N: the tiles of data the converged view reads (surface meshes and imagery tiles). "
        "Targets: frames to converge <= ceil(N / B) + L + 2, loads <= 1.25 N.";
    table.columns = {"L (frames)", "B (loads a frame)", "N", "frames to converge", "target", "loads", "loads / N"};
    const std::vector<std::pair<int, int>> settings =
        options.quick ? std::vector<std::pair<int, int>>{{1, 16}} : std::vector<std::pair<int, int>>{{1, 8}, {2, 8}, {2, 16}, {4, 32}};
    for (const auto& [latency, perFrame] : settings) {
        TiledGlobeOptions tiled;
        tiled.lighting = true;
        tiled.loader.latencyFrames = latency;
        tiled.loader.maximumStartsPerFrame = static_cast<std::size_t>(perFrame);
        tiled.loader.maximumInFlight = static_cast<std::size_t>(perFrame * (latency + 1));
        tiled.cacheBytes = std::size_t{1} << 30;
        tiled.uploadBytesPerFrame = std::size_t{64} << 20;
        StreamedScene streamed(std::make_shared<SyntheticImagery>(18), tiled);
        streamed.look(kOrbit);
        converge(streamed, context, 600);
        streamed.look(kAlps);
        const Convergence jump = converge(streamed, context, 2000);
        const std::size_t n = tilesInView(jump.last);
        const int target = static_cast<int>((n + perFrame - 1) / perFrame) + latency + 2;
        table.rows.push_back({std::to_string(latency), std::to_string(perFrame), std::to_string(n),
                              jump.converged ? std::to_string(jump.frames) : "not converged", std::to_string(target),
                              std::to_string(jump.loads),
                              formatNumber(static_cast<double>(jump.loads) / static_cast<double>(n), 3)});
    }
    return table;
}

// ---- The pipeline against decoding alone ------------------------------------------------------

/// A decoded tile with its mipmap levels, made on the worker as TiledGlobe makes them.
struct Decoded final : world::TileContent {
    explicit Decoded(Image image_) : image(std::move(image_)), mipmaps(mipmapChain(image)) {}
    std::size_t byteSize() const noexcept override { return image.pixels.size() * 4 / 3; }
    Image image;
    std::vector<Image> mipmaps;
};

/// CPU time of the whole process (every thread, the GL driver's too), milliseconds.
double processCpuMilliseconds()
{
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) / 1e6;
}

Table pipelineTable(const Options& options, Device& device)
{
    // The Blue Marble's level-4 tiles (or a part), in memory.
    std::vector<std::vector<std::uint8_t>> tiles;
    const std::uint32_t columns = options.quick ? 4 : 32;
    for (std::uint32_t x = 0; x < columns; ++x) {
        for (std::uint32_t y = 0; y < 16; ++y) {
            tiles.push_back(world::readFileBytes(kBlueMarble / "4" / std::to_string(x) / (std::to_string(y) + ".jpg"), "tile"));
        }
    }
    const double decodeCpuStart = processCpuMilliseconds();
    const auto decodeStart = std::chrono::steady_clock::now();
    for (const auto& tile : tiles) {
        doNotOptimize(world::decodeImage(tile, "tile", 4).pixels.data());
    }
    const double decodeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - decodeStart).count();
    const double decodeCpu = processCpuMilliseconds() - decodeCpuStart;

    Table table;
    table.title = "Streamed globe: decode and upload against decoding alone";
    table.description =
        "The Blue Marble's level-4 JPEG tiles (" + std::to_string(tiles.size()) +
        ", 256x256, in memory): decoded to RGBA one after another on one thread (TurboJPEG through "
        "world::decodeImage), against the streaming pipeline: a TileLoader decoding and making the mipmap levels on "
        "worker threads, and the render thread uploading each result with its levels at the next frame boundary, "
        "16 loads a frame. "
        "Wall-clock throughput on this 2-core machine, and CPU time (all threads, the driver's included) per tile, "
        "which other load on the machine disturbs less. The pipeline also makes each tile's mipmap levels (a third "
        "of a decode) and uploads them. Target: the pipeline within 20% of decoding alone.";
    table.columns = {"workers", "decode alone (tiles/s)", "pipeline (tiles/s)", "pipeline / decode alone",
                     "CPU ms a tile, decode alone", "CPU ms a tile, pipeline"};
    for (const int workers : {1, 2}) {
        world::TileLoaderOptions loaderOptions;
        loaderOptions.workerThreads = workers;
        loaderOptions.latencyFrames = 0;
        loaderOptions.maximumStartsPerFrame = 16;
        loaderOptions.maximumInFlight = 32;
        world::TileLoader loader(loaderOptions);
        std::vector<Texture2D> textures;
        std::size_t next = 0;
        std::size_t arrived = 0;
        const double cpuStart = processCpuMilliseconds();
        const auto start = std::chrono::steady_clock::now();
        for (std::uint64_t frame = 0; arrived < tiles.size(); ++frame) {
            for (world::TileLoadResult& result : loader.beginFrame(frame)) {
                const Decoded& decoded = static_cast<Decoded&>(*result.content);
                textures.push_back(device.createTexture2D(decoded.image, decoded.mipmaps));
                ++arrived;
            }
            // The next 16 tiles are offered; those the in-flight limit holds back are offered again.
            for (std::size_t i = next; i < std::min(next + 16, tiles.size()); ++i) {
                const std::vector<std::uint8_t>* bytes = &tiles[i];
                loader.request(i, static_cast<double>(i), [bytes] {
                    return std::unique_ptr<world::TileContent>(std::make_unique<Decoded>(world::decodeImage(*bytes, "tile", 4)));
                });
            }
            loader.endFrame();
            next += loader.startedLastFrame();
            if (loader.inFlight() >= 16) {
                std::this_thread::yield();
            }
        }
        device.context().finish();
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double cpu = processCpuMilliseconds() - cpuStart;
        const double count = static_cast<double>(tiles.size());
        table.rows.push_back({std::to_string(workers), formatNumber(count / decodeSeconds, 4),
                              formatNumber(count / seconds, 4), formatNumber(decodeSeconds / seconds, 3),
                              formatNumber(decodeCpu / count, 3), formatNumber(cpu / count, 3)});
    }
    return table;
}

// ---- A long flight under the cap -------------------------------------------------------------

/// True when a pixel that looks at the globe shows the (magenta) background: the globe has a hole
/// there. Every second pixel in each direction is checked, those whose ray passes inside the
/// ellipsoid's inscribed sphere by more than two pixels: the tiles' facets may stand inside the
/// true limb by their geometric error (what the screen-space error allows), which is no hole.
bool hasHole(const Image& image, const Camera& camera)
{
    const double distance = glm::length(camera.eye());
    const double limb = std::asin(std::min(1.0, kEarth.minimumRadius() / distance));
    const double margin = 2.0 * camera.fieldOfViewY() / image.height;
    const glm::dvec3 toCentre = -camera.eye() / distance;
    for (int y = 0; y < image.height; y += 2) {
        for (int x = 0; x < image.width; x += 2) {
            const std::uint8_t* p = image.pixel(x, y);
            if (!(p[0] == 255 && p[1] == 0 && p[2] == 255)) {
                continue;
            }
            const glm::dvec3 direction = camera.pickRay({x + 0.5, y + 0.5}, image.width, image.height).direction;
            const double offCentre = std::acos(std::clamp(glm::dot(direction, toCentre), -1.0, 1.0));
            if (offCentre < limb - margin) {
                return true;
            }
        }
    }
    return false;
}

/// Terrain grids of levels 0 to 14 (65 samples a side): ridges 70 km apart, 37 m higher at each
/// level, as the filtered levels of a pyramid disagree, so that stitching has work to do:
/// metres at a longitude and latitude (radians), at the finest level.
double ridges(double longitude, double latitude)
{
    // Five octaves, 70 km to 4.4 km, each half as high as the one before: rough at every scale
    // the levels draw. cos(latitude) keeps one height at each pole.
    double height = 1500.0;
    double amplitude = 1200.0;
    double frequency = 400.0;
    for (int octave = 0; octave < 5; ++octave) {
        height += amplitude * std::sin(frequency * longitude + octave) * std::cos(latitude) *
                  std::cos(0.75 * frequency * latitude + 0.5 * octave);
        amplitude *= 0.5;
        frequency *= 2.0;
    }
    return height;
}

/// The ridges as a terrain source, each level levelOffset metres above the one before.
std::shared_ptr<world::TerrainSource> syntheticTerrain(double levelOffset = 37.0)
{
    return std::make_shared<world::FunctionTerrainSource>(
        [](const Geodetic2D& g) { return ridges(g.longitude, g.latitude); }, 14, levelOffset);
}

/// The first point where a ray meets the surface `height` (metres above the ellipsoid, within
/// lowest..highest): steps no longer than the height gap allows if no slope is steeper than
/// slopeBound (the ground rises at most slopeBound per metre along the ray, the ray falls at most
/// one), then bisects to 0.1 mm. The distance along the ray; empty when it misses.
std::optional<double> castRayIntoTerrain(const Ray& ray, const std::function<double(const Geodetic2D&)>& height,
                                         double lowest, double highest, double slopeBound)
{
    const std::optional<RayInterval> shell = intersectRayEllipsoid(ray, Ellipsoid(kEarth.radii() + glm::dvec3(highest)));
    if (!shell) {
        return std::nullopt;
    }
    double end = shell->farDistance;
    if (const std::optional<RayInterval> floor = intersectRayEllipsoid(ray, Ellipsoid(kEarth.radii() + glm::dvec3(lowest)))) {
        end = std::min(end, floor->nearDistance + 1.0); // the ground is above the floor: hit by then
    }
    const auto gapAt = [&](double t) {
        const Geodetic3D g = kEarth.toGeodetic3D(ray.origin + t * ray.direction);
        return g.height - height(Geodetic2D(g.longitude, g.latitude));
    };
    double before = std::max(0.0, shell->nearDistance);
    double gap = gapAt(before);
    if (gap <= 0.0) {
        return before; // the eye is under the ground
    }
    for (int step = 0; step < 200000; ++step) {
        const double rise = glm::dot(ray.direction, kEarth.geodeticSurfaceNormal(ray.origin + before * ray.direction));
        const double after = std::min(end, before + std::max(0.05, gap / std::max(slopeBound - rise, 1e-6)));
        const double gapAfter = gapAt(after);
        if (gapAfter > 0.0 && after == end) {
            return std::nullopt;
        }
        if (gapAfter <= 0.0) {
            double above = before;
            double below = after;
            while (below - above > 1e-4) {
                const double middle = 0.5 * (above + below);
                (gapAt(middle) > 0.0 ? above : below) = middle;
            }
            return below;
        }
        before = after;
        gap = gapAfter;
    }
    return std::nullopt;
}

/// A view of a terrain for the pixel-error tables, and the surface the drawn one stands for.
struct PixelErrorView {
    std::string name;
    View view;
    std::function<std::shared_ptr<world::TerrainSource>()> openTerrain; ///< a fresh source for each globe
    std::function<double(const Geodetic2D&)> trueHeight;
    double lowest;     ///< metres: bounds of trueHeight where the view's rays go
    double highest;
    double slopeBound; ///< steepest slope of trueHeight (rise over run)
};

/// Rows of the pixel-error tables, one per screen-space error setting of chunked LOD, then one
/// for clipmaps (n = 255) when `withClipmap`: every fourth pixel's ray (sixteenth when quick) is
/// cast into the true surface in doubles; at the point it meets, the drawn surface's height (the
/// primitive's groundHeight: the triangle drawn) and the true height are projected, and their
/// distance on screen is the pixel error. The same ray cast into the drawn surface gives the depth
/// the frame has there.
void addPixelErrorRows(Table& table, const PixelErrorView& view, const Options& options, Context& context,
                       bool withClipmap = false)
{
    constexpr int kWidth = 640;
    constexpr int kHeight = 360;
    const int stride = options.quick ? 16 : 4;
    const Camera camera = cameraAt(view.view);
    struct Sample {
        Ray ray;
        double distance;
        Geodetic2D position;
    };
    std::vector<Sample> samples;
    for (int y = stride / 2; y < kHeight; y += stride) {
        for (int x = stride / 2; x < kWidth; x += stride) {
            const Ray ray = camera.pickRay({x + 0.5, y + 0.5}, kWidth, kHeight);
            if (const std::optional<double> hit =
                    castRayIntoTerrain(ray, view.trueHeight, view.lowest, view.highest, view.slopeBound)) {
                const Geodetic3D g = kEarth.toGeodetic3D(ray.origin + *hit * ray.direction);
                samples.push_back({ray, *hit, Geodetic2D(g.longitude, g.latitude)});
            }
        }
    }
    // Renders the primitive until `converged` says so, then measures the surface it drew.
    const auto measure = [&](const std::shared_ptr<Primitive>& ground, const std::function<bool(const FrameStatistics&)>& converged,
                             const std::string& setting, const std::function<std::vector<std::string>(const FrameStatistics&)>& tail) {
        Scene scene(kEarth);
        scene.add(ground);
        scene.camera() = camera;
        Framebuffer framebuffer = context.createFramebuffer(kWidth, kHeight);
        context.setFramebuffer(&framebuffer);
        FrameStatistics statistics;
        for (int frame = 0; frame < 400 && (frame == 0 || !converged(statistics)); ++frame) {
            statistics = scene.render(context);
        }
        context.setFramebuffer(nullptr);
        std::vector<double> errors;
        std::size_t depthsApart = 0;
        for (const Sample& sample : samples) {
            const std::optional<double> drawn = ground->groundHeight(sample.position);
            const std::optional<double> drawnDistance = castRayIntoTerrain(
                sample.ray, [&](const Geodetic2D& g) { return ground->groundHeight(g).value_or(view.lowest); }, view.lowest,
                view.highest, view.slopeBound);
            if (!drawnDistance || std::abs(*drawnDistance - sample.distance) > 0.01 * sample.distance) {
                ++depthsApart;
            }
            if (!drawn) {
                continue;
            }
            const Geodetic2D& g = sample.position;
            const auto a = camera.worldToWindow(kEarth.toCartesian(Geodetic3D(g.longitude, g.latitude, *drawn)), kWidth, kHeight);
            const auto b = camera.worldToWindow(
                kEarth.toCartesian(Geodetic3D(g.longitude, g.latitude, view.trueHeight(g))), kWidth, kHeight);
            if (a && b) {
                errors.push_back(glm::distance(*a, *b));
            }
        }
        std::sort(errors.begin(), errors.end());
        const auto percentile = [&](double p) {
            return errors.empty() ? 0.0 : errors[std::min(errors.size() - 1, static_cast<std::size_t>(p * static_cast<double>(errors.size())))];
        };
        std::vector<std::string> row{view.name, setting, std::to_string(errors.size()),
                                     formatNumber(percentile(0.999), 3), formatNumber(errors.empty() ? 0.0 : errors.back(), 3),
                                     formatNumber(100.0 * static_cast<double>(depthsApart) / static_cast<double>(std::max<std::size_t>(samples.size(), 1)), 3)};
        for (std::string& cell : tail(statistics)) {
            row.push_back(std::move(cell));
        }
        table.rows.push_back(std::move(row));
    };
    // Loads arrive in the frame they start: each view converges on the data, not the loader.
    world::TileLoaderOptions loader;
    loader.workerThreads = 0;
    loader.latencyFrames = 0;
    loader.maximumStartsPerFrame = 256;
    for (const double setting : {1.0, 2.0, 4.0, 8.0}) {
        if (options.quick && setting != 2.0) {
            continue;
        }
        TiledGlobeOptions tiled;
        tiled.lighting = true;
        tiled.terrain = view.openTerrain();
        tiled.maximumScreenSpaceError = setting;
        tiled.loader = loader;
        measure(std::make_shared<TiledGlobe>(kEarth, tiled), [](const FrameStatistics& s) { return s.tiles && s.tiles->converged; },
                formatNumber(setting, 2), [](const FrameStatistics& s) {
                    return std::vector<std::string>{std::to_string(s.tiles->drawn), std::to_string(s.tiles->deepestLevelDrawn),
                                                    s.tiles->converged ? "yes" : "no", s.tiles->memoryLimited ? "yes" : "no"};
                });
    }
    if (withClipmap) {
        ClipmapTerrainOptions clipmap;
        clipmap.lighting = true;
        clipmap.terrain = view.openTerrain();
        clipmap.posts = 255;
        clipmap.loader = loader;
        clipmap.loader.maximumInFlight = 512;
        measure(std::make_shared<ClipmapTerrain>(kEarth, clipmap), [](const FrameStatistics& s) { return s.clipmap && s.clipmap->converged; },
                "clipmap, n = 255", [](const FrameStatistics& s) {
                    return std::vector<std::string>{std::to_string(s.clipmap->levels - s.clipmap->finestLevelDrawn) + " levels",
                                                    "finest " + std::to_string(s.clipmap->finestLevelDrawn),
                                                    s.clipmap->converged ? "yes" : "no", "-"};
                });
    }
}

const std::vector<std::string> kPixelErrorColumns = {
    "view", "max SSE (px)", "points", "99.9th percentile px", "max px", "depth > 1% apart (% of points)",
    "tiles drawn", "deepest level", "converged", "cap bound"};

constexpr const char* kPixelErrorMethod =
    "640x360, converged (at most 400 frames). Every fourth pixel's ray is cast into the true surface in doubles "
    "(steps bounded by the height gap and the surface's steepest slope, then bisection); where it meets, the drawn "
    "surface's height (the globe's groundHeight, the triangle drawn) and the true one are projected, and their distance "
    "on screen is the pixel error. Depth: the same ray cast into the drawn surface meets it more than 1% of the "
    "distance away from the true one: silhouettes moved, ridges hiding other ground. Cap bound: the 256 MiB "
    "cache could not hold the selection, which was made coarser. Targets: 99.9th percentile <= the setting, maximum "
    "<= 1.5 x the setting.";

Table syntheticPixelErrorTable(const Options& options, Context& context)
{
    Table table;
    table.title = "Terrain: the screen-space error asked for against the pixel error drawn, synthetic terrain";
    table.description =
        std::string("Synthetic terrain (five octaves of ridges, 1.2 km high and 70 km apart down to 75 m and 4.4 km "
                    "apart; 65 x 65 grids to level 14, levels agreeing), against the function itself. The geometric "
                    "error of a level is the ellipsoid estimate of 65-sample grids (course 3.2). ") + kPixelErrorMethod;
    table.columns = kPixelErrorColumns;
    const auto ridgeHeight = [](const Geodetic2D& g) { return ridges(g.longitude, g.latitude); };
    const std::pair<const char*, View> views[] = {
        {"Alps-like ridges, 8 km, 20 degrees down", {Geodetic3D::fromDegrees(7.6, 45.6, 8000.0), 40.0, -20.0}},
        {"5 km up, 3 degrees down, to the horizon", {Geodetic3D::fromDegrees(-84.2, 36.6, 5000.0), 0.0, -3.0}},
        {"North Pole, 30 km, 45 degrees down", {Geodetic3D::fromDegrees(0.0, 89.5, 30000.0), 0.0, -45.0}},
    };
    for (const auto& [name, view] : views) {
        addPixelErrorRows(table, {name, view, [] { return syntheticTerrain(0.0); }, ridgeHeight, -1000.0, 4000.0, 1.0},
                          options, context);
    }
    return table;
}

Table realPixelErrorTable(const Options& options, Context& context)
{
    Table table;
    table.title = "Terrain: the screen-space error asked for against the pixel error drawn, real data";
    table.description =
        std::string("ETOPO5 (data/terrain/etopo5: quantized-mesh, levels 0-5, each tile's measured error in "
                    "layer.json) and the 80 m Cumberland DEM (data/terrain/cumberland, cut into 65 x 65 grids by "
                    "GDAL), against the source's most detailed surface (world::TerrainHeightQuery: ETOPO5's level 5 "
                    "tiles, the DEM's deepest grids). Finer than the data the tiles are cut from the deepest, so the "
                    "error is that of the coarser levels the view draws far away. ") + kPixelErrorMethod;
    table.columns = kPixelErrorColumns;
    struct RealView {
        const char* name;
        const char* terrain;
        View view;
        double lowest;
        double highest;
        double slopeBound; ///< ETOPO5's samples are 9 km apart; the DEM's edge drops to 0 m within a sample
    };
    const RealView views[] = {
        {"Everest from 57 km SSW, 15 km up", "terrain/etopo5", {Geodetic3D::fromDegrees(86.75, 27.5, 15000.0), 17.0, -10.0}, -1000.0, 7000.0, 1.0},
        {"Alps, 8 km, 20 degrees down", "terrain/etopo5", {Geodetic3D::fromDegrees(7.6, 45.6, 8000.0), 40.0, -20.0}, -4000.0, 5000.0, 1.0},
        {"Cumberland Mountains, 2 km, to the horizon", "terrain/cumberland/jacksboro_fault.vrt",
         {Geodetic3D::fromDegrees(-84.40, 36.46, 2000.0), 45.0, -3.0}, -100.0, 1200.0, 4.0},
        {"North Pole beyond Greenland, 500 km", "terrain/etopo5", {Geodetic3D::fromDegrees(-40.0, 75.0, 500000.0), 0.0, -35.0}, -6000.0, 4000.0, 1.0},
        {"Fiji across the antimeridian, 150 km", "terrain/etopo5", {Geodetic3D::fromDegrees(177.0, -17.0, 150000.0), 110.0, -35.0}, -11000.0, 2000.0, 1.0},
    };
    for (const RealView& real : views) {
        const std::string path = std::string(ORBIS_DATA_DIR) + "/" + real.terrain;
        auto truthSource = std::shared_ptr<world::TerrainSource>(world::openTerrainSource(path));
        auto truth = std::make_shared<world::TerrainHeightQuery>(*truthSource);
        const auto trueHeight = [truthSource, truth](const Geodetic2D& g) {
            const std::optional<world::TerrainHeight> height = truth->at(g);
            return height ? height->height : 0.0;
        };
        addPixelErrorRows(table,
                          {real.name, real.view, [path] { return std::shared_ptr<world::TerrainSource>(world::openTerrainSource(path)); },
                           trueHeight, real.lowest, real.highest, real.slopeBound},
                          options, context, true);
    }
    return table;
}

std::vector<std::string> flightRow(int frames, bool terrain, Context& context);

Table flightTable(const Options& options, Context& context)
{
    const int frames = options.quick ? 60 : 2000;
    Table table;
    table.title = "Streamed globe: a " + std::to_string(frames) + "-frame flight under the cap";
    table.description =
        "Straight down from 20,000 km to 500 m and back up while travelling 90 degrees east along 45 N, 256x256, "
        "synthetic imagery 18 levels deep, cache cap 48 MiB, upload budget 1 MiB a frame, deterministic loader "
        "(2 frames of latency, 8 loads a frame), GL errors checked after every call (DeviceOptions::glChecks); "
        "on the ellipsoid, then on synthetic terrain (five octaves of ridges up to 1.2 km, each level 37 m above the one before, "
        "skirts off; the heights 4.5 km higher, above the highest ridge). A hole: a frame with a background pixel whose ray passes more than two pixels inside the "
        "globe's limb (every second pixel checked). Memory per resident tile: the peak's bytes (CPU and GPU) over the "
        "surface and imagery tiles held then; an imagery tile is 256x256 RGBA with its mipmaps (341 KiB), a surface "
        "tile its mesh (17 x 17 on the ellipsoid, 65 x 65 with normals on terrain) and what is kept for stitching. The first frame loads the roots whatever the budget and is "
        "left out of the upload column.";
    table.columns = {"surface", "frames", "max resident MiB", "cap MiB", "tiles resident then (surface + imagery)",
                     "KiB per resident tile", "max upload MiB a frame",
                     "budget MiB (+ one tile)", "frames with a hole", "GL errors", "cap bound", "s"};
    for (const bool terrain : {false, true}) {
        table.rows.push_back(flightRow(frames, terrain, context));
    }
    return table;
}

std::vector<std::string> flightRow(int frames, bool terrain, Context& context)
{
    TiledGlobeOptions tiled;
    tiled.lighting = true;
    if (terrain) {
        tiled.terrain = syntheticTerrain();
    }
    tiled.loader.latencyFrames = 2;
    tiled.loader.maximumStartsPerFrame = 8;
    tiled.loader.maximumInFlight = 24;
    tiled.cacheBytes = std::size_t{48} << 20;
    tiled.uploadBytesPerFrame = std::size_t{1} << 20;
    tiled.baseColor = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
    StreamedScene streamed(std::make_shared<SyntheticImagery>(18), tiled);
    streamed.scene.options().background = glm::vec4(1.0f, 0.0f, 1.0f, 1.0f); // magenta: a hole
    std::size_t maximumResident = 0;
    std::size_t tilesAtMaximum = 0; // surface and imagery tiles resident when the bytes peaked
    std::size_t maximumUpload = 0;
    int framesWithHoles = 0;
    int glErrors = 0;
    bool limited = false;
    const auto start = std::chrono::steady_clock::now();
    for (int frame = 0; frame < frames; ++frame) {
        // Straight down from 20,000 km to 500 m and back, travelling east along 45 N: always new tiles.
        const double t = static_cast<double>(frame) / (frames - 1);
        const double height = std::exp(std::log(2.0e7) + (std::log(500.0) - std::log(2.0e7)) * (1.0 - std::abs(2.0 * t - 1.0)));
        // Over terrain, as high above its highest ridge (4.4 km) as over the ellipsoid.
        const double clearance = terrain ? 4500.0 : 0.0;
        streamed.look({Geodetic3D::fromDegrees(-30.0 + 90.0 * t, 45.0, height + clearance), 0.0, -90.0});
        try {
            const FrameStatistics statistics = streamed.scene.render(context);
            const TileStatistics& tiles = *statistics.tiles;
            if (tiles.residentBytesCpu + tiles.residentBytesGpu > maximumResident) {
                maximumResident = tiles.residentBytesCpu + tiles.residentBytesGpu;
                tilesAtMaximum = tiles.residentTiles + tiles.residentImageryTiles;
            }
            if (frame > 0) {
                maximumUpload = std::max(maximumUpload, tiles.uploadedBytes);
            }
            limited = limited || tiles.memoryLimited;
        } catch (const Error&) {
            ++glErrors; // with ORBIS_GL_CHECKS a GL error throws, naming the call
        }
        framesWithHoles += hasHole(context.readPixels(), streamed.scene.camera()) ? 1 : 0;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return {terrain ? "terrain" : "ellipsoid", std::to_string(frames),
            formatNumber(static_cast<double>(maximumResident) / 1048576.0, 3),
            formatNumber(static_cast<double>(tiled.cacheBytes) / 1048576.0, 3), std::to_string(tilesAtMaximum),
            formatNumber(static_cast<double>(maximumResident) / 1024.0 / static_cast<double>(std::max<std::size_t>(tilesAtMaximum, 1)), 3),
            formatNumber(static_cast<double>(maximumUpload) / 1048576.0, 3), "1 (+0.33)", std::to_string(framesWithHoles),
            std::to_string(glErrors), limited ? "yes" : "no", formatNumber(seconds, 3)};
}

// ---- Against the fill floor ------------------------------------------------------------------

Table fillTable(const Options& options, Device& device, Context& context)
{
    TiledGlobeOptions tiled;
    tiled.lighting = true;
    tiled.loader.latencyFrames = 1;
    tiled.loader.maximumStartsPerFrame = 64;
    StreamedScene streamed(world::openTileSource(kBlueMarble.string()), tiled);
    streamed.look({Geodetic3D::fromDegrees(9.5, 43.5, 350000.0), 10.0, -30.0});
    converge(streamed, context, 200);
    const int frames = options.quick ? 2 : 10;
    const double ms = millisecondsPerFrame(streamed.scene, context, frames);
    const double floorMs = fillFloorMilliseconds(device, context, frames);
    Table table;
    table.title = "Streamed globe against the fill floor";
    table.description =
        "The Blue Marble streamed at its deepest level over the Alps from 350 km looking 30 degrees down "
        "(converged, 1280x720), against a full-screen quad reading one mipmapped texture per pixel at the same "
        "size, in the same run. Target: at most 1.5.";
    table.columns = {"streamed view ms", "fill floor ms", "ratio"};
    table.rows.push_back({formatNumber(ms, 3), formatNumber(floorMs, 3), formatNumber(ms / floorMs, 3)});
    return table;
}

// ---- Terrain meshes --------------------------------------------------------------------------

/// Seconds of CPU time this thread has used.
double threadSeconds()
{
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

Table terrainMeshTable(const Options& options)
{
    // A data tile of 257 x 257 samples (as ETOPO5's level 3) with mountains, and its descendants.
    auto data = std::make_shared<world::TerrainTileData>();
    data->key = TileKey{3, 9, 5};
    data->size = 257;
    data->heights.resize(257 * 257);
    for (int j = 0; j < 257; ++j) {
        for (int i = 0; i < 257; ++i) {
            data->heights[static_cast<std::size_t>(j * 257 + i)] =
                static_cast<float>(2000.0 + 1500.0 * std::sin(0.11 * i) * std::cos(0.07 * j));
        }
    }
    const world::TerrainSampler sampler(data);
    const int tiles = options.quick ? 50 : 2000;
    std::vector<TileKey> keys;
    for (int t = 0; t < tiles; ++t) {
        const std::uint32_t depth = 1 + static_cast<std::uint32_t>(t % 4);
        keys.push_back({3 + depth, (9u << depth) + static_cast<std::uint32_t>(t * 7) % (1u << depth),
                        (5u << depth) + static_cast<std::uint32_t>(t * 3) % (1u << depth)});
    }
    Table table;
    table.title = "Terrain: a tile's mesh from heights";
    table.description =
        "CPU time on one thread per tile of 65 x 65 vertices cut from a 257 x 257 grid (levels 1 to 4 below it, " +
        std::to_string(tiles) +
        " tiles): sampling the heights on the tile's lattice (world::TerrainSampler::latticeHeights), the mesh with its "
        "skirts (TileMesh::build: positions split for the GPU, relative to the eye) and its normals "
        "(TileMesh::normals). Target: at most 0.3 ms a tile with skirts (CesiumJS takes about 1.6 ms).";
    table.columns = {"skirts", "heights ms", "mesh ms", "normals ms", "total ms a tile"};
    for (const bool skirts : {false, true}) {
        double sampling = 0.0;
        double building = 0.0;
        double normals = 0.0;
        volatile std::size_t kept = 0; // the normals are used: not optimised away
        for (const TileKey& key : keys) {
            const double t0 = threadSeconds();
            const std::vector<float> heights = sampler.latticeHeights(key, 6);
            const double t1 = threadSeconds();
            const TileMesh mesh = TileMesh::build(kEarth, TilingScheme::geographic(), key, 6, heights, skirts ? 500.0 : 0.0);
            const double t2 = threadSeconds();
            kept = kept + mesh.normals().size();
            const double t3 = threadSeconds();
            sampling += t1 - t0;
            building += t2 - t1;
            normals += t3 - t2;
        }
        const double perTile = 1e3 / static_cast<double>(keys.size());
        table.rows.push_back({skirts ? "yes" : "no", formatNumber(sampling * perTile, 3), formatNumber(building * perTile, 3),
                              formatNumber(normals * perTile, 3),
                              formatNumber((sampling + building + normals) * perTile, 3)});
    }
    return table;
}

std::vector<Table> run(const Options& options)
{
    std::vector<Table> tables;
    tables.push_back(terrainMeshTable(options));
    {
        Device device;
        Context& context = device.context();
        Framebuffer framebuffer = context.createFramebuffer(1280, 720);
        context.setFramebuffer(&framebuffer);
        tables.push_back(errorTable(options, device, context));
        tables.push_back(selectionTable(options));
        tables.push_back(jumpTable(options, context));
        tables.push_back(pipelineTable(options, device));
        tables.push_back(fillTable(options, device, context));
        context.setFramebuffer(nullptr);
    }
    // The flight checks for GL errors after every call: a device of its own, so that the timings
    // above do not pay for it.
    DeviceOptions checked;
    checked.glChecks = true;
    Device device(checked);
    Context& context = device.context();
    Framebuffer small = context.createFramebuffer(256, 256);
    context.setFramebuffer(&small);
    tables.push_back(flightTable(options, context));
    context.setFramebuffer(nullptr);
    return tables;
}

const SectionRegistration registration("streamed globe", 72, run);

// ---- Morphing between levels (book 14.4) ---------------------------------------------------

Table morphTable(const Options& options, Context& context)
{
    const int frames = options.quick ? 40 : 240;
    Table table;
    table.title = "Terrain: popping against morphing over frames";
    table.description =
        "Synthetic terrain (five octaves of ridges up to 1.2 km, each level 37 m above the one before, 65 x 65 grids) "
        "under synthetic imagery, 256x256, deterministic loader (2 frames of latency, 8 loads a frame): the eye descends "
        "from 60 km to 2 km over " + std::to_string(frames) + " frames looking 30 degrees down, rises back over as many, "
        "then stays until the view converges. A step: the change of the drawn surface's height (TiledGlobe::heightAt, "
        "the triangle drawn) from one frame to the next at one of 400 fixed probes on the ground the view crosses; the "
        "camera's motion does not move it, only the levels do. Update: the globe's update() a frame (selection, loads, "
        "morphs, stitching), mean over the flight; frame: render with glFinish. Frames after: from the end of the "
        "flight until converged.";
    table.columns = {"morph frames", "largest step m, descending", "largest step m, rising",
                     "probe-frames stepping > 50 m", "mean tiles morphing", "update ms", "frame ms", "frames after",
                     "frames with a hole"};
    std::vector<int> settings{0, 4, 8, 16, 32};
    if (options.quick) {
        settings = {0, 8};
    }
    for (const int morphFrames : settings) {
        TiledGlobeOptions tiled;
        tiled.lighting = true;
        tiled.terrain = syntheticTerrain();
        tiled.morphFrames = morphFrames;
        tiled.loader.latencyFrames = 2;
        tiled.loader.maximumStartsPerFrame = 8;
        StreamedScene streamed(std::make_shared<SyntheticImagery>(18), tiled);
        std::vector<Geodetic2D> probes;
        for (int row = 0; row < 20; ++row) {
            for (int column = 0; column < 20; ++column) {
                probes.push_back(Geodetic2D::fromDegrees(9.8 + 0.02 * column, 45.85 + 0.025 * row));
            }
        }
        std::vector<std::optional<double>> before(probes.size());
        std::array<double, 2> largestStep{}; // descending, rising
        std::size_t bigSteps = 0;
        std::size_t morphing = 0;
        double updateMs = 0.0;
        double frameMs = 0.0;
        int framesAfter = 0;
        int holes = 0;
        for (int frame = 0;; ++frame) {
            // Down over the first `frames` frames, back up over the next.
            const int flown = std::min(frame, 2 * frames - 1);
            const bool rising = flown >= frames;
            const double t = static_cast<double>(rising ? 2 * frames - 1 - flown : flown) / (frames - 1);
            const double height = std::exp(std::log(60000.0) + (std::log(2000.0) - std::log(60000.0)) * t);
            // Over the ridges' highest point (4.4 km) as high as the path says.
            streamed.look({Geodetic3D::fromDegrees(10.0, 45.7 + 0.2 * t, height + 4500.0), 0.0, -30.0});
            const auto start = std::chrono::steady_clock::now();
            const FrameStatistics statistics = streamed.scene.render(context);
            context.finish();
            const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            for (std::size_t p = 0; p < probes.size(); ++p) {
                const std::optional<double> now = streamed.globe->heightAt(probes[p]);
                if (now && before[p]) {
                    const double step = std::abs(*now - *before[p]);
                    largestStep[rising ? 1 : 0] = std::max(largestStep[rising ? 1 : 0], step);
                    bigSteps += step > 50.0;
                }
                before[p] = now;
            }
            holes += hasHole(context.readPixels(), streamed.scene.camera()) ? 1 : 0;
            if (frame < 2 * frames) {
                morphing += statistics.tiles->morphing;
                updateMs += statistics.updateMilliseconds;
                frameMs += ms;
            } else if (statistics.tiles->converged || ++framesAfter > 600) {
                break;
            }
        }
        const double flight = 2.0 * frames;
        table.rows.push_back({std::to_string(morphFrames), formatNumber(largestStep[0], 3), formatNumber(largestStep[1], 3),
                              std::to_string(bigSteps), formatNumber(static_cast<double>(morphing) / flight, 3),
                              formatNumber(updateMs / flight, 3), formatNumber(frameMs / flight, 3),
                              std::to_string(framesAfter), std::to_string(holes)});
    }
    table.notes = "A hole: a frame with a background pixel whose ray passes more than two pixels inside the globe's limb (every second pixel checked).";
    return table;
}

std::vector<Table> runMorph(const Options& options)
{
    Device device;
    Context& context = device.context();
    Framebuffer small = context.createFramebuffer(256, 256);
    context.setFramebuffer(&small);
    std::vector<Table> tables{morphTable(options, context)};
    context.setFramebuffer(nullptr);
    return tables;
}

const SectionRegistration morphRegistration("terrain morphing", 74, runMorph);

std::vector<Table> runPixelError(const Options& options)
{
    Device device;
    return {syntheticPixelErrorTable(options, device.context()), realPixelErrorTable(options, device.context())};
}

const SectionRegistration pixelErrorRegistration("terrain pixel error", 73, runPixelError);

} // namespace
} // namespace orbis::bench
