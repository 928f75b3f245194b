// The scene layer's costs: culling and binning many commands, and the globe's geometric error
// against its frame time, with the fill floor (a full-screen textured quad) measured in the same run.

#include "GlMeasurements.h"
#include "Report.h"

#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/ScreenSpaceError.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/CommandBinner.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/Scene.h>
#include <orbis/world/ImageFile.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <random>

using namespace orbis::world;
using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::bench {
namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

// ---- Culling and binning -------------------------------------------------------------------

/// Commands like a terrain and vector scene's: tiles on the surface with horizon occlusion points
/// (their sizes from 1 km to 500 km), and objects in space up to GEO, without.
std::vector<SceneCommand> makeCommands(std::size_t count)
{
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const EllipsoidalOccluder occluder(kEarth, glm::dvec3(0.0));
    std::vector<SceneCommand> commands(count);
    for (std::size_t i = 0; i < count; ++i) {
        const Geodetic3D where(kPi * (2 * unit(random) - 1), std::asin(2 * unit(random) - 1), 0.0);
        SceneCommand& command = commands[i];
        if (i % 4 != 0) {
            const double radius = std::pow(10.0, 3.0 + 2.7 * unit(random));
            const glm::dvec3 centre = kEarth.toCartesian(where);
            command.boundingSphere = BoundingSphere{centre, radius};
            const glm::dvec3 up = kEarth.geodeticSurfaceNormal(centre);
            const glm::dvec3 corners[] = {centre + radius * up, centre - radius * up};
            command.horizonOcclusionPoint = occluder.horizonOcclusionPoint(glm::normalize(centre), corners);
        } else {
            const double height = std::pow(10.0, 5.0 + 2.6 * unit(random));
            command.boundingSphere = BoundingSphere{kEarth.toCartesian(Geodetic3D(where.longitude, where.latitude, height)),
                                                    1e3 * unit(random)};
        }
        command.pass = i % 10 == 0 ? Pass::Translucent : Pass::Opaque;
    }
    return commands;
}

Table binningTable(const Options& options)
{
    const std::size_t count = options.quick ? 10000 : 100000;
    const std::vector<SceneCommand> commands = makeCommands(count);
    Camera camera;
    camera.lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(10, 45, 2e6)),
                  kEarth.toCartesian(Geodetic3D::fromDegrees(10, 60, 0)), {0, 0, 1});
    const Frustum cullingVolume = Frustum::fromViewProjection(camera.projectionMatrix(16.0 / 9.0, 1.0, 1e10) *
                                                              camera.viewMatrix());
    const EllipsoidalOccluder occluder(kEarth, camera.eye());
    CommandBinner binner;
    FrameStatistics first;
    const auto start = std::chrono::steady_clock::now();
    const double cosHalfDiagonal = 0.9; // 45 degrees vertical at 16:9
    binner.cullAndBin(commands, cullingVolume, occluder, camera.eye(), camera.direction(), cosHalfDiagonal, first);
    const double firstNs =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
        static_cast<double>(count);
    FrameStatistics steady;
    const double steadyNs = nanosecondsPerItem(count, [&] {
        steady = FrameStatistics();
        binner.cullAndBin(commands, cullingVolume, occluder, camera.eye(), camera.direction(), cosHalfDiagonal,
                          steady);
    });

    Table table;
    table.title = "Culling and binning";
    table.description = std::to_string(count) +
                        " commands (three quarters surface tiles 1 to 500 km across with horizon occlusion points, a "
                        "quarter objects up to GEO), a camera 2,000 km over Europe looking north: frustum culling, "
                        "horizon culling, near/far and multi-frustum binning (CommandBinner::cullAndBin). Target: "
                        "100 ns per command.";
    table.columns = {"frame", "ns per command", "culled by frustum", "culled by horizon", "frustums",
                     "in several frustums"};
    auto row = [&](const char* name, double ns, const FrameStatistics& s) {
        table.rows.push_back({name, formatNumber(ns, 3), std::to_string(s.commandsCulledByFrustum),
                              std::to_string(s.commandsCulledByHorizon), std::to_string(s.frustums.size()),
                              std::to_string(s.commandsExecutedMoreThanOnce)});
    };
    row("first (frustums computed, two passes)", firstNs, first);
    row(steady.frustumsReused ? "steady (last frame's frustums reused, one pass)" : "steady (recomputed)", steadyNs,
        steady);
    return table;
}

// ---- Globe: error against frame time ---------------------------------------------------------

struct GlobeConfiguration {
    std::string name;
    GlobeOptions options;
};

std::vector<Table> globeTables(const Options& options)
{
    const int width = 1280;
    const int height = 720;
    const int frames = options.quick ? 1 : 5;
    const double fieldOfView = toRadians(45.0);
    Device device;
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(width, height);
    context.setFramebuffer(&framebuffer);

    GlobeOptions textured;
    textured.lighting = true;
    textured.dayTexture = "/usr/share/xplanet/images/earth.jpg";
    textured.nightTexture = "/usr/share/xplanet/images/night.jpg";
    std::vector<GlobeConfiguration> configurations;
    configurations.push_back({"ray cast", textured});
    const std::vector<std::pair<GlobeTessellation, std::vector<int>>> levels = {
        {GlobeTessellation::CubeMap, options.quick ? std::vector<int>{16} : std::vector<int>{16, 32, 64, 128}},
        {GlobeTessellation::SubdivisionEllipsoid, options.quick ? std::vector<int>{4} : std::vector<int>{4, 5, 6, 7}},
        {GlobeTessellation::GeographicGrid, options.quick ? std::vector<int>{16} : std::vector<int>{32, 64, 128, 256}},
    };
    for (const auto& [tessellation, values] : levels) {
        for (const int level : values) {
            GlobeConfiguration configuration{"", textured};
            configuration.options.method = GlobeMethod::Tessellated;
            configuration.options.tessellation = tessellation;
            configuration.options.tessellationLevel = level;
            const char* name = tessellation == GlobeTessellation::CubeMap                ? "cube map"
                               : tessellation == GlobeTessellation::SubdivisionEllipsoid ? "subdivision"
                                                                                          : "geographic grid";
            configuration.name = std::string(name) + " " + std::to_string(level);
            configurations.push_back(configuration);
        }
    }

    const double heights[] = {2e7, 2e6, 2e5};
    Table globe;
    globe.title = "Globe: geometric error and frame time";
    globe.description =
        "Day/night globe at 1280x720 on this machine's GL (llvmpipe), eye 20,000 km over (10 E, 20 N) looking at "
        "the centre, average of " + std::to_string(frames) +
        " frames (Scene::render, GPU finished). Error: the mesh's maximum distance from WGS84 (sampled, "
        "Tessellation.h), and that error in pixels for an eye at 20,000, 2,000 and 200 km above it "
        "(screen-space error, 45 degree field of view). Ray casting meets the exact ellipsoid in every pixel: "
        "its error is float rounding of the ray, about 1e-7 of the distance.";
    globe.columns = {"method", "triangles", "max error", "px at 20,000 km", "px at 2,000 km", "px at 200 km",
                     "ms per frame"};
    double defaultViewMs = 0.0;
    for (const GlobeConfiguration& configuration : configurations) {
        Scene scene(kEarth);
        scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T12:00:00Z")));
        scene.add(std::make_shared<Globe>(kEarth, configuration.options));
        scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(10, 20, 2e7)), glm::dvec3(0), {0, 0, 1});
        const double ms = millisecondsPerFrame(scene, context, frames);
        std::vector<std::string> row{configuration.name};
        if (configuration.options.method == GlobeMethod::RayCast) {
            defaultViewMs = ms;
            row.insert(row.end(), {"12 (box)", "0 (exact)", "0", "0", "0"});
        } else {
            const TessellationResult mesh = Globe::tessellate(kEarth, configuration.options.tessellation,
                                                              configuration.options.tessellationLevel,
                                                              Deviation::Measure);
            const double error = mesh.maxDeviationMeters.value_or(0.0);
            row.push_back(std::to_string(mesh.mesh.triangleCount()));
            row.push_back(formatLength(error));
            for (const double h : heights) {
                row.push_back(formatNumber(screenSpaceError(error, h, height, fieldOfView), 2));
            }
        }
        row.push_back(formatNumber(ms, 3));
        globe.rows.push_back(row);
    }

    const double floorMs = fillFloorMilliseconds(device, context, options.quick ? 2 : 10);
    Table fill;
    fill.title = "Globe against the fill floor";
    fill.description = "The default view (the ray-cast day/night globe above) against a full-screen quad reading one "
                       "mipmapped texture per pixel at the same size, in the same run. Target: at most 1.5.";
    fill.columns = {"default view ms", "fill floor ms", "ratio"};
    fill.rows.push_back({formatNumber(defaultViewMs, 3), formatNumber(floorMs, 3), formatNumber(defaultViewMs / floorMs, 3)});
    return {globe, fill};
}

std::vector<Table> run(const Options& options)
{
    std::vector<Table> tables{binningTable(options)};
    for (Table& table : globeTables(options)) {
        tables.push_back(std::move(table));
    }
    return tables;
}

const SectionRegistration registration("scene", 70, run);

} // namespace
} // namespace orbis::bench
