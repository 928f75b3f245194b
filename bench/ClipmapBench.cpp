// Geometry clipmapping (book chapter 13): the cost of one full level update, and the clipmap beside
// chunked LOD (the streamed tile quadtree) on the same views and data (book 14.9 made numeric).

#include "GlMeasurements.h"
#include "Plot.h"
#include "PrecisionMeasurement.h"
#include "Report.h"

#include <orbis/core/Transforms.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/scene/ClipmapTerrain.h>
#include <orbis/scene/Scene.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::bench {
namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
const std::filesystem::path kData = std::filesystem::path(ORBIS_SOURCE_DIR) / "data";

struct View {
    const char* name;
    Geodetic3D position;
    double headingDegrees;
    double pitchDegrees;
};

Camera cameraAt(const View& view)
{
    const glm::dvec3 eye = kEarth.toCartesian(view.position);
    const ViewOrientation orientation =
        headingPitchRollToView(kEarth, eye, toRadians(view.headingDegrees), toRadians(view.pitchDegrees), 0.0);
    return Camera(eye, eye + orientation.direction * glm::length(eye), orientation.up, toRadians(45.0));
}

world::TileLoaderOptions deterministicLoader()
{
    world::TileLoaderOptions loader;
    loader.workerThreads = 0;
    loader.latencyFrames = 1;
    loader.maximumStartsPerFrame = 256;
    loader.maximumInFlight = 512;
    return loader;
}

/// The comparison's heights as they are: at 20 times the eye at 5 or 8 km would be inside the Alps.
ClipmapTerrainOptions etopo5Clipmap(int posts, double exaggeration = 1.0)
{
    ClipmapTerrainOptions options;
    options.lighting = true;
    options.terrain = world::openTerrainSource((kData / "terrain/etopo5").string());
    options.imagery.push_back({world::openTileSource((kData / "imagery/BlueMarble").string()), {}});
    options.posts = posts;
    options.exaggeration = exaggeration;
    options.loader = deterministicLoader();
    return options;
}

double median(std::vector<double> values)
{
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

Table levelUpdateTable(const Options& options, Context& context)
{
    Table table;
    table.title = "Clipmap: one full level update, n = 255";
    table.description =
        "ETOPO5 (quantized-mesh, levels 0-5) and the Blue Marble on 255 x 255 posts a level (a 256 x 256 window: "
        "65,536 heights, normals and colours written, then uploaded as three textures), one level a frame "
        "(ClipmapTerrain's budget at 65,536 posts). After converging at one view the camera jumps between two "
        "views 3 km up and more than 97 degrees apart, so every level is written whole, coarse first, with the tiles it reads already in "
        "the cache (after the first round trip); the time is the writes' and uploads' "
        "(ClipmapStatistics::updateMilliseconds: the render thread's CPU time). A level at or above the data's spacing reads "
        "the terrain tiles as 129 x 129 lattices made on the loader's workers; one below it, the mesh tiles' own "
        "triangles (ETOPO5's TINs, the triangle found from the last post's); both read the imagery tiles bilinearly. "
        "The first level below the data (both grids) and the coarsest at it (the rotated grids), each the first "
        "after a jump to read the tiles the levels after it read too, take about 1.3 times as long as those.";
    table.columns = {"grid", "posts written a frame", "ms, at the data (median)", "ms, at the data (best)",
                     "ms, below the data (median)", "ms, below the data (best)", "frames"};
    struct Pair {
        const char* name;
        View a, b;
    };
    // Each pair farther apart than the coarsest level's window (97 degrees): every level is
    // written whole after each jump.
    const Pair pairs[] = {
        {"geodetic (Himalaya and Andes)", {"", Geodetic3D::fromDegrees(86.9, 27.9, 3000.0), 0.0, -30.0},
         {"", Geodetic3D::fromDegrees(-68.0, -16.0, 3000.0), 0.0, -30.0}},
        {"rotated (Alps and New Zealand)", {"", Geodetic3D::fromDegrees(8.0, 46.0, 3000.0), 0.0, -30.0},
         {"", Geodetic3D::fromDegrees(170.0, -46.0, 3000.0), 0.0, -30.0}},
    };
    // Twelve round trips: 69 writes at the data and 69 below it a grid, so that a median outlasts
    // the other work on a shared machine (four gave medians 1.7 to 2.5 ms from run to run, their
    // best the same).
    const int roundTrips = options.quick ? 1 : 12;
    for (const Pair& pair : pairs) {
        if (options.quick && &pair != &pairs[0]) {
            continue;
        }
        ClipmapTerrainOptions clipmapOptions = etopo5Clipmap(255, 20.0);
        clipmapOptions.postsPerFrame = 256 * 256;
        auto terrain = std::make_shared<ClipmapTerrain>(kEarth, clipmapOptions);
        Scene scene(kEarth);
        scene.add(terrain);
        const double dataSpacing = kPi / 32.0 / 64.0;
        std::vector<double> fromTiles, upsampled;
        int frames = 0;
        for (int trip = 0; trip <= 2 * roundTrips; ++trip) {
            scene.camera() = cameraAt(trip % 2 == 0 ? pair.a : pair.b);
            int level = terrain->levels() - 1;
            for (int frame = 0; frame < 200; ++frame) {
                const FrameStatistics statistics = scene.render(context);
                ++frames;
                const ClipmapStatistics& clipmap = *statistics.clipmap;
                // A frame that wrote one level whole, from tiles already loaded (the second
                // visit on), before any arrival made a level write again.
                if (trip >= 2 && clipmap.postsUpdated == 256 * 256 && clipmap.tilesLoaded == 0 && level >= 0) {
                    const double spacing = terrain->finestSpacing() * std::ldexp(1.0, level);
                    (spacing < dataSpacing ? upsampled : fromTiles).push_back(clipmap.updateMilliseconds);
                }
                level -= clipmap.postsUpdated == 256 * 256 ? 1 : 0;
                if (terrain->converged()) {
                    break;
                }
            }
        }
        auto best = [](const std::vector<double>& values) {
            return values.empty() ? 0.0 : *std::min_element(values.begin(), values.end());
        };
        table.rows.push_back({pair.name, "65,536", formatNumber(median(fromTiles)), formatNumber(best(fromTiles)),
                              formatNumber(median(upsampled)), formatNumber(best(upsampled)), std::to_string(frames)});
    }
    table.notes = "Target: 2 ms for a full n = 255 level.";
    return table;
}

struct MethodFigures {
    double drawCalls = 0, triangles = 0, updateMs = 0, frameMs = 0, gpuMiB = 0;
    int framesToConverge = 0;
    bool converged = false;
};

/// Converges, then renders `frames` more frames of the same view: their means.
MethodFigures measure(Scene& scene, Context& context, const std::function<bool(const FrameStatistics&)>& converged,
                      const std::function<double(const FrameStatistics&)>& gpuBytes, int frames)
{
    MethodFigures figures;
    FrameStatistics statistics;
    while (figures.framesToConverge < 400) {
        statistics = scene.render(context);
        ++figures.framesToConverge;
        if (converged(statistics)) {
            figures.converged = true;
            break;
        }
    }
    for (int frame = 0; frame < frames; ++frame) {
        const auto started = std::chrono::steady_clock::now();
        statistics = scene.render(context);
        context.finish();
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
        figures.drawCalls += static_cast<double>(statistics.renderer.drawCalls) / frames;
        figures.triangles += static_cast<double>(statistics.renderer.primitives) / frames;
        figures.updateMs += statistics.updateMilliseconds / frames;
        figures.frameMs += ms / frames;
    }
    figures.gpuMiB = gpuBytes(statistics) / 1048576.0;
    return figures;
}

Table comparisonTable(const Options& options, Device& device, Context& context)
{
    Table table;
    table.title = "Clipmap against chunked LOD on the same views and data";
    table.description =
        "ETOPO5 (heights as they are) and the Blue Marble, 640x360, each method converged from a cold start with the "
        "deterministic loader (one frame of latency), then 10 frames of the same view averaged. "
        "Chunked LOD: TiledGlobe at 2 px of screen-space error with 65 x 65 tile meshes; clipmap: ClipmapTerrain, "
        "n = 255, the levels the eye's height needs. Triangles and draw calls as the renderer counted them; update: "
        "the primitives' update() (selection or level writes); frame: render and glFinish, wall clock on llvmpipe; "
        "GPU: the tiles' resident vertex buffers and textures, or the clipmap's level textures and shared buffers; "
        "against the fill floor: the frame over a full-screen quad reading one mipmapped texture a pixel, at the same "
        "size in the same run.";
    table.columns = {"view", "method", "draw calls", "triangles", "update ms", "frame ms", "frame / fill floor", "GPU MiB",
                     "frames to converge"};
    const View views[] = {
        {"Alps oblique, 8 km, 20 degrees down", Geodetic3D::fromDegrees(7.6, 45.6, 8000.0), 40.0, -20.0},
        {"Cumberland Mountains to the horizon, 5 km, 3 degrees down", Geodetic3D::fromDegrees(-84.2, 36.6, 5000.0), 0.0, -3.0},
        {"North Pole, 30 km, 45 degrees down", Geodetic3D::fromDegrees(0.0, 89.5, 30000.0), 0.0, -45.0},
    };
    const int frames = options.quick ? 1 : 10;
    // --quick: one view, a quarter of the pixels (a smoke run).
    Framebuffer framebuffer = options.quick ? context.createFramebuffer(160, 90) : context.createFramebuffer(640, 360);
    context.setFramebuffer(&framebuffer);
    const double floorMs = fillFloorMilliseconds(device, context, frames);
    auto addRow = [&](const View& view, const char* method, const MethodFigures& f) {
        table.rows.push_back({view.name, method, formatNumber(f.drawCalls), formatNumber(f.triangles), formatNumber(f.updateMs),
                              formatNumber(f.frameMs), formatNumber(f.frameMs / floorMs), formatNumber(f.gpuMiB),
                              f.converged ? std::to_string(f.framesToConverge) : "no"});
    };
    for (const View& view : views) {
        if (options.quick && &view != &views[0]) {
            continue;
        }
        {
            TiledGlobeOptions tiled;
            tiled.lighting = true;
            tiled.terrain = world::openTerrainSource((kData / "terrain/etopo5").string());
            tiled.imagery.push_back({world::openTileSource((kData / "imagery/BlueMarble").string()), {}});
            tiled.loader = deterministicLoader();
            Scene scene(kEarth);
            scene.add(std::make_shared<TiledGlobe>(kEarth, tiled));
            scene.camera() = cameraAt(view);
            const MethodFigures f = measure(
                scene, context, [](const FrameStatistics& s) { return s.tiles && s.tiles->converged; },
                [](const FrameStatistics& s) { return static_cast<double>(s.tiles->residentBytesGpu); }, frames);
            addRow(view, "chunked LOD", f);
        }
        {
            Scene scene(kEarth);
            scene.add(std::make_shared<ClipmapTerrain>(kEarth, etopo5Clipmap(255)));
            scene.camera() = cameraAt(view);
            const MethodFigures f = measure(
                scene, context, [](const FrameStatistics& s) { return s.clipmap && s.clipmap->converged; },
                [](const FrameStatistics& s) { return static_cast<double>(s.clipmap->gpuBytes); }, frames);
            addRow(view, "clipmap", f);
        }
    }
    context.setFramebuffer(nullptr);
    table.notes = "Fill floor: " + formatNumber(floorMs) + " ms. Pixel error against the CPU ray cast: section \"terrain pixel "
                  "error\", the clipmap rows; the 2,000-frame flight: the table \"Clipmap against chunked LOD in flight\".";
    return table;
}

/// Background pixels (magenta) in the lower half of an image (the flight looks 20 degrees down
/// from 8 km: the lower half is ground, the background there is a hole).
std::size_t holePixels(const Image& image)
{
    std::size_t count = 0;
    for (int y = image.height / 2; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = &image.pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                                   static_cast<std::size_t>(x)) * 4];
            count += (p[0] == 255 && p[1] == 0 && p[2] == 255) ? 1 : 0;
        }
    }
    return count;
}

Table flightTable(const Options& options, Context& context)
{
    const int frames = options.quick ? 5 : 2000;
    Table table;
    table.title = "Clipmap against chunked LOD in flight";
    table.description =
        "A " + std::to_string(frames) + "-frame flight 8 km up from the Alps eastwards at 45.8 N looking east 20 degrees down, "
        "0.01 degrees (780 m) a frame, ETOPO5 and the Blue Marble, 320x180, from a cold start, "
        "deterministic loader (one frame of latency, 256 loads a frame), no waiting for convergence. Update: "
        "TiledGlobe's update() (selection, loads, uploads; wall clock) or the clipmap's level writes and uploads "
        "(its CPU time); bytes: what went to the GPU in the frame; holes: frames with a background pixel in the "
        "lower half (the ground).";
    table.columns = {"method", "mean update ms", "max update ms", "mean KiB uploaded", "max KiB uploaded",
                     "mean draw calls", "mean triangles", "frames with a hole", "frames with writes pending"};
    std::vector<Series> updatePlot, uploadPlot;
    Framebuffer framebuffer = context.createFramebuffer(320, 180);
    context.setFramebuffer(&framebuffer);
    for (const bool clipmap : {false, true}) {
        Scene scene(kEarth);
        scene.options().background = {1.0f, 0.0f, 1.0f, 1.0f};
        if (clipmap) {
            scene.add(std::make_shared<ClipmapTerrain>(kEarth, etopo5Clipmap(255)));
        } else {
            TiledGlobeOptions tiled;
            tiled.lighting = true;
            tiled.terrain = world::openTerrainSource((kData / "terrain/etopo5").string());
            tiled.imagery.push_back({world::openTileSource((kData / "imagery/BlueMarble").string()), {}});
            tiled.loader = deterministicLoader();
            scene.add(std::make_shared<TiledGlobe>(kEarth, tiled));
        }
        double updateSum = 0, updateMax = 0, bytesSum = 0, bytesMax = 0, draws = 0, triangles = 0;
        int holes = 0, waiting = 0;
        Series updates{clipmap ? "clipmap" : "chunked LOD", clipmap ? "#d62728" : "#1f77b4", false, {}};
        Series uploads = updates;
        for (int frame = 0; frame < frames; ++frame) {
            scene.camera() = cameraAt({"", Geodetic3D::fromDegrees(6.0 + 0.01 * frame, 45.8, 8000.0), 90.0, -20.0});
            const FrameStatistics statistics = scene.render(context);
            const double update = clipmap ? statistics.clipmap->updateMilliseconds : statistics.updateMilliseconds;
            const double bytes = static_cast<double>(clipmap ? statistics.clipmap->bytesUploaded : statistics.tiles->uploadedBytes);
            updateSum += update;
            updateMax = std::max(updateMax, update);
            bytesSum += bytes;
            bytesMax = std::max(bytesMax, bytes);
            draws += static_cast<double>(statistics.renderer.drawCalls);
            triangles += static_cast<double>(statistics.renderer.primitives);
            holes += holePixels(context.readPixels()) > 0 ? 1 : 0;
            waiting += clipmap && statistics.clipmap->levelsPending > 0 ? 1 : 0;
            updates.points.emplace_back(0.0, update);
            uploads.points.emplace_back(0.0, bytes / 1024.0);
        }
        // As distributions: each frame's value in order of size, against its percentile.
        for (Series* series : {&updates, &uploads}) {
            std::sort(series->points.begin(), series->points.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
            for (std::size_t k = 0; k < series->points.size(); ++k) {
                series->points[k].first = 100.0 * static_cast<double>(k + 1) / static_cast<double>(series->points.size());
            }
        }
        updatePlot.push_back(std::move(updates));
        uploadPlot.push_back(std::move(uploads));
        table.rows.push_back({clipmap ? "clipmap" : "chunked LOD", formatNumber(updateSum / frames),
                              formatNumber(updateMax), formatNumber(bytesSum / frames / 1024.0),
                              formatNumber(bytesMax / 1024.0), formatNumber(draws / frames),
                              formatNumber(triangles / frames), std::to_string(holes),
                              clipmap ? std::to_string(waiting) : "-"});
    }
    context.setFramebuffer(nullptr);
    if (!options.quick) {
        std::ostringstream svg;
        svg << "<svg xmlns='http://www.w3.org/2000/svg' width='1200' height='600' font-family='sans-serif'>\n"
            << "<rect width='1200' height='600' fill='white'/>\n";
        auto percent = [](double value) { return std::to_string(static_cast<int>(value)) + " %"; };
        auto number = [](double value) { return formatNumber(value); };
        const PlotAxis share{"frames at or below (of " + std::to_string(frames) + ")", 0.0, 100.0, false, 10.0, percent};
        plotPanel(svg, 0, 0, 600, 600, "Update a frame, in flight", share,
                  {"ms of CPU (shown at least 0.01)", 0.01, 100.0, true, 1.0, number}, updatePlot);
        plotPanel(svg, 600, 0, 600, 600, "Uploaded a frame, in flight", share, {"KiB (frames uploading nothing left out)", 0.1, 1e4, true, 1.0, number},
                  uploadPlot);
        svg << "</svg>\n";
        std::ofstream(std::string(ORBIS_SOURCE_DIR) + "/docs/clipmap-flight.svg") << svg.str();
        table.notes = "The frames' update and upload as distributions: docs/clipmap-flight.svg.";
    }
    return table;
}

Table jitterTable(Context& context)
{
    Table table;
    table.title = "Clipmap: window error at 1 m from the ground";
    table.description =
        "ETOPO5 and the Blue Marble, n = 255, level 0's posts 1e-5 degrees (1.1 m) apart, as a 1 m DEM would "
        "give; the eye 1 m above the drawn ground looking north 20 degrees down. Every drawn vertex in the view: "
        "its clip position read back from the clipmap's own vertex shader (transform feedback), projected to a "
        "1920x1080 window with a 45 degree field of view in double, against P V p of the same triangle computed "
        "in double (PrecisionMeasurement.h: measureClipmapJitter, as docs/precision.md measures transforms).";
    table.columns = {"place", "grid", "ground height m", "vertices in view", "within 10 m", "worst px", "worst mm"};
    struct Place {
        const char* name;
        const char* grid;
        Geodetic2D position;
    };
    for (const Place& place : {Place{"Himalaya (86.9 E, 27.9 N)", "geodetic", Geodetic2D::fromDegrees(86.9, 27.9)},
                               Place{"Norway (8 E, 61 N)", "rotated", Geodetic2D::fromDegrees(8.0, 61.0)}}) {
        ClipmapTerrainOptions options = etopo5Clipmap(255);
        options.finestSpacingDegrees = 1e-5;
        const ClipmapJitterResult measured = measureClipmapJitter(context, options, place.position, 1.0);
        table.rows.push_back({place.name, place.grid, formatNumber(measured.groundHeight), std::to_string(measured.vertices),
                              std::to_string(measured.within10m), formatNumber(measured.error.maxPixels),
                              formatNumber(measured.error.maxMeters * 1000.0)});
    }
    return table;
}

std::vector<Table> run(const Options& options)
{
    Device device;
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(640, 360);
    context.setFramebuffer(&framebuffer);
    std::vector<Table> tables;
    tables.push_back(levelUpdateTable(options, context));
    context.setFramebuffer(nullptr);
    tables.push_back(comparisonTable(options, device, context));
    tables.push_back(flightTable(options, context));
    tables.push_back(jitterTable(context));
    return tables;
}

const SectionRegistration registration("clipmap terrain", 73, run);

} // namespace
} // namespace orbis::bench
