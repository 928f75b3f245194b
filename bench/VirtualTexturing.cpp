// Virtual texturing on the globe (Mayer's thesis, course chapter 6), measured as the thesis
// measures it: fallback pixels after convergence and through a flight with a fixed loader
// budget, the frame time against the same view with per-tile imagery, the upload per frame and
// the memory; then his comparisons on the globe: page size, priorities, feedback resolution,
// physical texture size. Everything runs with deterministic loader timing, so the figures but the
// times are the same every run.

#include "Report.h"
#include "SyntheticImagery.h"

#include <orbis/core/Transforms.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/Scene.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/scene/VirtualTextureGlobe.h>
#include <orbis/world/TileSource.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::bench {
namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::shared_ptr<world::TileSource> blueMarble()
{
    static const std::shared_ptr<world::TileSource> source =
        world::openTileSource(std::string(ORBIS_SOURCE_DIR) + "/data/imagery/BlueMarble");
    return source;
}

struct ViewPoint {
    const char* name;
    Geodetic3D position;
    double headingDegrees;
    double pitchDegrees;
};

void place(Camera& camera, const ViewPoint& view)
{
    const glm::dvec3 eye = kEarth.toCartesian(view.position);
    const ViewOrientation orientation =
        headingPitchRollToView(kEarth, eye, toRadians(view.headingDegrees), toRadians(view.pitchDegrees), 0.0);
    camera.lookAt(eye, eye + orientation.direction * glm::length(eye), orientation.up);
}

/// The base configuration: Mayer's (256-texel pages, quarter-resolution feedback, priorities),
/// idTech 5's 4-texel border, the loader's budget 8 pages a frame and two frames of latency.
VirtualTextureGlobeOptions baseOptions()
{
    VirtualTextureGlobeOptions options;
    options.source = blueMarble();
    options.loader.workerThreads = 2;
    options.loader.latencyFrames = 2;
    options.loader.maximumStartsPerFrame = 8;
    options.virtualTexture.physicalPages = 256;
    return options;
}

/// A framebuffer of the size, current on the context while the object lives.
struct Target {
    Target(Context& context_, int width, int height)
        : context(context_), framebuffer(context_.createFramebuffer(width, height))
    {
        context.setFramebuffer(&framebuffer);
    }
    ~Target() { context.setFramebuffer(nullptr); }
    Context& context;
    Framebuffer framebuffer;
};

/// Frames until the scene's tiles say converged, at most `limit`; the last frame's statistics.
FrameStatistics converge(Scene& scene, Context& context, int limit, int& frames)
{
    FrameStatistics statistics;
    for (frames = 1; frames <= limit; ++frames) {
        statistics = scene.render(context);
        if (statistics.tiles && statistics.tiles->converged) {
            break;
        }
    }
    return statistics;
}

/// Whole frames (update, feedback pass, draw, GPU finished) of two scenes timed in turn, so that
/// both see the same load on a shared machine: each one's median, and the median of the ratios
/// of the pairs, ms.
struct FrameTimes {
    double first = 0.0;
    double second = 0.0;
    double ratio = 0.0;
};

/// `beforeFrame(i)` places the cameras for frame pair i.
FrameTimes compareFrameTimes(Scene& first, Scene& second, Context& context, int frames,
                             const std::function<void(int)>& beforeFrame)
{
    std::vector<double> a, b, ratios;
    auto time = [&](Scene& scene) {
        const auto start = std::chrono::steady_clock::now();
        scene.render(context);
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    };
    for (int i = 0; i < frames; ++i) {
        beforeFrame(i);
        a.push_back(time(first));
        b.push_back(time(second));
        ratios.push_back(a.back() / b.back());
    }
    auto median = [](std::vector<double> values) {
        std::sort(values.begin(), values.end());
        return values[values.size() / 2];
    };
    return {median(a), median(b), median(ratios)};
}

/// Two scenes' frames timed in turn on a view: still, then moving (both cameras a metre higher
/// every other frame, so that a virtual texture draws its feedback pass every frame, as in
/// flight; a still one draws none once its feedback stands).
std::pair<FrameTimes, FrameTimes> stillAndMoving(Scene& first, Scene& second, Context& context, int frames,
                                                 const ViewPoint& view)
{
    const FrameTimes still = compareFrameTimes(first, second, context, frames, [](int) {});
    ViewPoint higher = view;
    higher.position.height += 1.0;
    const FrameTimes moving = compareFrameTimes(first, second, context, frames, [&](int frame) {
        const ViewPoint& at = frame % 2 == 0 ? higher : view;
        place(first.camera(), at);
        place(second.camera(), at);
    });
    return {still, moving};
}

/// The converged views' tables: a device with a framebuffer of the frames' size current on it,
/// and how many frame pairs to time.
struct ViewBench {
    explicit ViewBench(const Options& options)
        : width(options.quick ? 320 : 1280)
        , height(options.quick ? 180 : 720)
        , timed(options.quick ? 3 : 15)
        , target(device.context(), width, height)
    {
    }
    Device device;
    int width;
    int height;
    int timed;
    Target target;
};

std::string percent(double fraction)
{
    return formatNumber(100.0 * fraction, 3) + "%";
}

std::string mebibytes(double bytes)
{
    return formatNumber(bytes / 1048576.0, 3) + " MiB";
}

// ---- Convergence and frame time against per-tile imagery ------------------------------------

const ViewPoint kViews[] = {
    {"Alps, oblique from 300 km", Geodetic3D::fromDegrees(8.0, 43.5, 300000.0), 10.0, -35.0},
    {"Paris from 10 km", Geodetic3D::fromDegrees(2.35, 48.75, 10000.0), 0.0, -60.0},
    {"antimeridian from 150 km", Geodetic3D::fromDegrees(177.0, -17.5, 150000.0), 90.0, -45.0},
    {"whole Earth from 20,000 km", Geodetic3D::fromDegrees(15.0, 30.0, 2.0e7), 0.0, -90.0},
};

Table convergenceTable(const Options& options)
{
    ViewBench bench(options);
    Context& context = bench.device.context();
    const int timed = bench.timed;

    Table table;
    table.title = "Virtual texture against per-tile imagery, converged views";
    table.description =
        "The Blue Marble (levels 0-4) at " + std::to_string(bench.width) + " x " + std::to_string(bench.height) +
        " as one virtual texture (base configuration: 256-texel pages with a 4-texel border, 256 slots, feedback at "
        "quarter resolution read back a frame late, 8 page loads a frame arriving 2 frames after they start) and, "
        "beside it, the same tiles with per-tile imagery (TiledGlobe, the same source, screen-space error 2 px). "
        "Frames are timed whole (update, for the virtual texture with its feedback pass; draw; GPU finished), the "
        "two scenes in turn, " +
        std::to_string(timed) +
        " pairs: the medians, and the median of the pairs' ratios; still, and moving (the cameras a metre higher every "
        "other frame, so that the virtual texture draws its feedback pass every frame, as in flight; a still view draws "
        "none once its feedback stands). Targets: fallback pixels <= 0.01% after convergence; virtual texture frame "
        "time <= 1.5 x per-tile.";
    table.columns = {"view", "frames to converge", "pages resident", "fallback after convergence", "VT ms/frame",
                     "per-tile ms/frame", "VT / per-tile", "VT ms/frame, moving", "per-tile ms/frame, moving",
                     "VT / per-tile, moving", "VT GPU memory"};
    for (const ViewPoint& view : kViews) {
        Scene virtualScene(kEarth);
        virtualScene.add(std::make_shared<VirtualTextureGlobe>(kEarth, baseOptions()));
        place(virtualScene.camera(), view);
        int frames = 0;
        const FrameStatistics converged = converge(virtualScene, context, 200, frames);
        const VirtualTextureStatistics& vt = *converged.virtualTexture;

        TiledGlobeOptions tiledOptions;
        tiledOptions.imagery.push_back({blueMarble(), {}});
        Scene tiled(kEarth);
        tiled.add(std::make_shared<TiledGlobe>(kEarth, tiledOptions));
        place(tiled.camera(), view);
        int tiledFrames = 0;
        converge(tiled, context, 200, tiledFrames);
        const auto [still, moving] = stillAndMoving(virtualScene, tiled, context, timed, view);

        table.rows.push_back({view.name, vt.converged ? std::to_string(frames) : "not in " + std::to_string(frames),
                              std::to_string(vt.pagesResident), percent(vt.fallbackFraction), formatNumber(still.first, 3),
                              formatNumber(still.second, 3), formatNumber(still.ratio, 3), formatNumber(moving.first, 3),
                              formatNumber(moving.second, 3), formatNumber(moving.ratio, 3),
                              mebibytes(static_cast<double>(vt.gpuBytes))});
    }
    table.notes = "Fallback pixels are counted in the feedback pass (the pixels whose texels came from a coarser page "
                  "than they asked for). The memory is fixed by the physical texture (256 slots of 264 x 264 texels and the "
                  "mip tail's strip below them), "
                  "the page table and the feedback buffers, whatever the view.";
    return table;
}

// ---- Flights with a fixed loader budget (Mayer 5.3) ------------------------------------------

/// A flyover: from 4,000 km down to `lowest` metres over the Atlantic while travelling east over
/// Europe, weaving in latitude and heading, always needing new pages. t in [0, 1].
ViewPoint flightView(double t, double lowest)
{
    const double descent = std::min(1.0, 4.0 * t);
    const double height = std::exp(std::log(4.0e6) + (std::log(lowest) - std::log(4.0e6)) * descent);
    const double pi = 3.14159265358979323846;
    return {"", Geodetic3D::fromDegrees(-20.0 + 60.0 * t, 44.0 + 6.0 * std::sin(2.0 * pi * t), height),
            90.0 + 35.0 * std::sin(4.0 * pi * t), -40.0};
}

/// What a flight measured: the fallback pixels of each frame's feedback, the pages moved, the
/// upload and the frame times.
struct FlightResult {
    double meanFallback = 0.0;  ///< fraction of the feedback's pixels, averaged over the frames
    double worstFallback = 0.0; ///< the worst frame's fraction
    int framesAbovePercent = 0; ///< frames with more than 1% fallback pixels
    std::size_t pagesLoaded = 0;
    std::size_t pagesEvicted = 0;
    std::size_t maximumUploadBytes = 0; ///< in one frame
    double uploadedBytes = 0.0;
    bool biasRaised = false;
    double millisecondsPerFrame = 0.0; ///< median of the whole frames
    std::size_t gpuBytes = 0;
    bool gpuBytesFixed = true;
};

FlightResult fly(Context& context, const VirtualTextureGlobeOptions& options, int frames, double lowest)
{
    Scene scene(kEarth);
    scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
    // The flight starts from its first view converged, as a flight does that follows a jump.
    place(scene.camera(), flightView(0.0, lowest));
    int startFrames = 0;
    converge(scene, context, 200, startFrames);
    FlightResult result;
    std::vector<double> times;
    double fallbackSum = 0.0;
    for (int frame = 0; frame < frames; ++frame) {
        place(scene.camera(), flightView(static_cast<double>(frame) / (frames - 1), lowest));
        const auto start = std::chrono::steady_clock::now();
        const FrameStatistics statistics = scene.render(context); // returns with the GPU done
        times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        const VirtualTextureStatistics& vt = *statistics.virtualTexture;
        fallbackSum += vt.fallbackFraction;
        result.worstFallback = std::max(result.worstFallback, vt.fallbackFraction);
        result.framesAbovePercent += vt.fallbackFraction > 0.01 ? 1 : 0;
        result.pagesLoaded += vt.pagesLoaded;
        result.pagesEvicted += vt.pagesEvicted;
        result.uploadedBytes += static_cast<double>(vt.uploadedBytes);
        result.maximumUploadBytes = std::max(result.maximumUploadBytes, vt.uploadedBytes);
        result.biasRaised = result.biasRaised || vt.lodBiasRaised;
        if (frame == 0) {
            result.gpuBytes = vt.gpuBytes;
        } else {
            result.gpuBytesFixed = result.gpuBytesFixed && vt.gpuBytes == result.gpuBytes;
        }
    }
    result.meanFallback = fallbackSum / frames;
    std::sort(times.begin(), times.end());
    result.millisecondsPerFrame = times[times.size() / 2];
    return result;
}

Table flightTable(const Options& options)
{
    Device device;
    Context& context = device.context();
    const int width = options.quick ? 160 : 640;
    const int height = options.quick ? 90 : 360;
    const int frames = options.quick ? 30 : 2000;
    Target target(context, width, height);
    const VirtualTextureGlobeOptions base = baseOptions();
    const FlightResult result = fly(context, base, frames, 1.5e5);

    Table table;
    table.title = "Virtual texture: a " + std::to_string(frames) + "-frame flight with a fixed loader budget";
    table.description =
        "The Blue Marble as one virtual texture in the base configuration, " + std::to_string(width) + " x " +
        std::to_string(height) +
        ", along a flyover from 4,000 km down to 150 km while travelling 60 degrees east over Europe, weaving 6 "
        "degrees in latitude and 35 in heading, starting from the first view converged. The loader starts at most 8 pages a frame, each arriving 2 frames "
        "later; uploads are capped at 4 MiB a frame (at least one page). Fallback pixels are counted in each "
        "frame's feedback (quarter resolution). Targets: <= 1% in every frame; the upload within its budget; the "
        "memory fixed.";
    table.columns = {"frames", "mean fallback", "worst frame", "frames above 1%", "pages loaded", "pages evicted",
                     "max upload a frame", "upload budget", "GPU memory", "memory fixed", "ms/frame (median)"};
    table.rows.push_back({std::to_string(frames), percent(result.meanFallback), percent(result.worstFallback),
                          std::to_string(result.framesAbovePercent), std::to_string(result.pagesLoaded),
                          std::to_string(result.pagesEvicted), mebibytes(static_cast<double>(result.maximumUploadBytes)),
                          mebibytes(static_cast<double>(base.virtualTexture.uploadBytesPerFrame)),
                          mebibytes(static_cast<double>(result.gpuBytes)), result.gpuBytesFixed ? "yes" : "no",
                          formatNumber(result.millisecondsPerFrame, 3)});
    table.notes = "The maximum upload is one frame's pages (up to the budget, and the last page that crosses it) "
                  "plus the page table's and LOD clamp's changed rectangles.";
    return table;
}

Table comparisonsTable(const Options& options)
{
    Device device;
    Context& context = device.context();
    const int width = options.quick ? 160 : 640;
    const int height = options.quick ? 90 : 360;
    const int frames = options.quick ? 20 : 500;
    Target target(context, width, height);

    struct Variant {
        std::string name;
        std::function<void(VirtualTextureGlobeOptions&)> change;
    };
    const std::vector<Variant> variants = {
        {"base: 256-texel pages, priorities, quarter-resolution feedback, 256 slots", [](auto&) {}},
        {"128-texel pages (1,024 slots: the same memory)",
         [](auto& o) {
             o.virtualTexture.pageSize = 128;
             o.virtualTexture.physicalPages = 1024;
         }},
        {"64-texel pages (4,096 slots: the same memory)",
         [](auto& o) {
             o.virtualTexture.pageSize = 64;
             o.virtualTexture.physicalPages = 4096;
         }},
        {"without priorities", [](auto& o) { o.virtualTexture.requestOrder = RequestOrder::Unsorted; }},
        {"feedback at half resolution", [](auto& o) { o.virtualTexture.feedbackDivisor = 2; }},
        {"feedback at full resolution", [](auto& o) { o.virtualTexture.feedbackDivisor = 1; }},
        {"64 slots", [](auto& o) { o.virtualTexture.physicalPages = 64; }},
        {"1,024 slots", [](auto& o) { o.virtualTexture.physicalPages = 1024; }},
    };
    Table table;
    table.title = "Virtual texture: Mayer's comparisons on the globe";
    table.description =
        "The flight of the table above in " + std::to_string(frames) + " frames (four times faster), down to 100 km, " +
        std::to_string(width) + " x " + std::to_string(height) +
        ", over synthetic imagery 9 levels deep (one real 256 x 256 JPEG served for every tile: real fetches, "
        "decodes and cuts; the Blue Marble's five levels give too few pages for the loader's budget to bind), "
        "each configuration changing one thing from the base. Every configuration loads at most 2 pages a frame "
        "(a budget that binds, as Mayer's disk did: he loaded a file per page); smaller pages bring fewer texels per load. The fallback pixels are "
        "counted in each configuration's own feedback, as a fraction of its pixels. ms/frame is the median whole frame, feedback pass included.";
    table.columns = {"configuration", "mean fallback", "x base", "worst frame", "pages loaded", "uploaded",
                     "LOD bias raised", "GPU memory", "ms/frame (median)"};
    double baseFallback = 0.0;
    // Imagery nine levels deep (one real JPEG for every tile), so that the flight, down to 100 km,
    // asks for level 9 pages of 256 texels (level 11 of 64), more than the loader's budget gives.
    const auto deep = std::make_shared<SyntheticImagery>(9);
    for (const Variant& variant : variants) {
        VirtualTextureGlobeOptions configured = baseOptions();
        configured.source = deep;
        configured.loader.maximumStartsPerFrame = 2;
        variant.change(configured);
        const FlightResult result = fly(context, configured, frames, 1.0e5);
        if (table.rows.empty()) {
            baseFallback = result.meanFallback;
        }
        table.rows.push_back({variant.name, percent(result.meanFallback),
                              baseFallback > 0.0 ? formatNumber(result.meanFallback / baseFallback, 3) : "-",
                              percent(result.worstFallback), std::to_string(result.pagesLoaded),
                              mebibytes(result.uploadedBytes), result.biasRaised ? "yes" : "no",
                              mebibytes(static_cast<double>(result.gpuBytes)),
                              formatNumber(result.millisecondsPerFrame, 3)});
    }
    table.notes = "Mayer found 5 and 25 times more fallbacks with 128- and 64-texel pages, and about 50 times more "
                  "without priorities.";
    return table;
}

std::vector<Table> run(const Options& options)
{
    return {convergenceTable(options), flightTable(options), comparisonsTable(options)};
}

// ---- The sparse path against the software path (course chapter 5) -----------------------------

std::vector<Table> runSparse(const Options& options)
{
    ViewBench bench(options);
    Device& device = bench.device;
    Context& context = device.context();
    const int timed = bench.timed;

    Table table;
    table.title = "Virtual texture: the sparse path against the software path";
    table.description =
        "The views of the first table at " + std::to_string(bench.width) + " x " + std::to_string(bench.height) +
        ", the base configuration drawn twice on the same device: through a sparse texture (\"sparse\": true; pages "
        "committed at their places, the hardware's filtering, the LOD clamped to resident pages) and the software way "
        "(physical texture, page table, borders). Frames timed whole, the two scenes in turn, " +
        std::to_string(timed) + " pairs, still and moving as in the first table. Device: " + device.info().renderer + ".";
    table.columns = {"view", "sparse: frames to converge", "fallback after convergence", "sparse ms/frame",
                     "software ms/frame", "sparse / software", "sparse ms/frame, moving", "software ms/frame, moving",
                     "sparse / software, moving", "sparse GPU memory", "software GPU memory"};
    if (!device.info().sparseTexture) {
        table.notes = "Not measured: this device lacks GL_ARB_sparse_texture. Run the section on zink over lavapipe "
                      "(docs/building.md): scripts/with-sparse-mesa.sh build/bin/orbis_bench --only \"sparse virtual "
                      "texture\".";
        return {table};
    }
    for (const ViewPoint& view : kViews) {
        auto scene = [&](bool sparse) {
            VirtualTextureGlobeOptions configured = baseOptions();
            configured.virtualTexture.sparse = sparse;
            auto made = std::make_unique<Scene>(kEarth);
            made->add(std::make_shared<VirtualTextureGlobe>(kEarth, configured));
            place(made->camera(), view);
            return made;
        };
        const std::unique_ptr<Scene> sparse = scene(true);
        const std::unique_ptr<Scene> software = scene(false);
        int frames = 0, softwareFrames = 0;
        const VirtualTextureStatistics vt = *converge(*sparse, context, 200, frames).virtualTexture;
        const VirtualTextureStatistics softwareVt = *converge(*software, context, 200, softwareFrames).virtualTexture;
        const auto [still, moving] = stillAndMoving(*sparse, *software, context, timed, view);
        table.rows.push_back({view.name,
                              vt.converged && vt.sparse ? std::to_string(frames) : "not in " + std::to_string(frames),
                              percent(vt.fallbackFraction), formatNumber(still.first, 3), formatNumber(still.second, 3),
                              formatNumber(still.ratio, 3), formatNumber(moving.first, 3), formatNumber(moving.second, 3),
                              formatNumber(moving.ratio, 3), mebibytes(static_cast<double>(vt.gpuBytes)),
                              mebibytes(static_cast<double>(softwareVt.gpuBytes))});
    }
    table.notes = "The sparse path's memory is the pages committed (at most the 256 of the physical texture) and the "
                  "levels below level 0; the software path's, the whole physical texture, whatever the view holds.";
    return {table};
}

const SectionRegistration registration("virtual texturing", 72, run);
const SectionRegistration sparseRegistration("sparse virtual texture", 73, runSparse);

} // namespace

} // namespace orbis::bench
