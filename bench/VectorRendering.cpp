// Polylines and polygons on the GPU (book chapters 7 and 8): what the granularity of Natural Earth's
// country borders and fills buys (how far the drawn geometry strays from the surface, in metres and
// pixels) against its vertices and the time to build and upload the primitives; and the frame
// time of the ch07 and ch08 example scenes. The CPU-only costs (computeCurve, triangulatePolygon)
// are in the curves and polygons sections.

#include "Report.h"

#include <orbis/core/ScreenSpaceError.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/FeaturePrimitives.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/Scene.h>
#include <orbis/world/GeoJson.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>

using namespace orbis::world;
using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::bench {
namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
constexpr int kWidth = 1280;
constexpr int kHeight = 720;
const double kFieldOfView = toRadians(45.0);

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Greatest distance, above or below, of the drawn borders from the surface: each segment sampled
/// at 16 points with the exact Ellipsoid::toGeodetic3D.
double deviation(const PolylineCollection& borders)
{
    double largest = 0.0;
    for (std::size_t i = 0; i < borders.size(); ++i) {
        const auto p = borders.positions(i);
        if (p.size() < 2) {
            continue;
        }
        const std::size_t segments = borders.isLoop(i) ? p.size() : p.size() - 1;
        for (std::size_t s = 0; s < segments; ++s) {
            for (int k = 0; k <= 16; k += 2) {
                const glm::dvec3 q = glm::mix(p[s], p[(s + 1) % p.size()], k / 16.0);
                largest = std::max(largest, std::abs(kEarth.toGeodetic3D(q).height));
            }
        }
    }
    return largest;
}

/// Greatest height of the fills' triangles above the surface (at their corners, the highest
/// points: the triangles are flat and the lift puts their lowest points at about the surface).
double deviation(const PolygonCollection& fills)
{
    double largest = 0.0;
    for (std::size_t i = 0; i < fills.size(); ++i) {
        for (const glm::dvec3& position : fills.mesh(i).positions) {
            largest = std::max(largest, std::abs(kEarth.toGeodetic3D(position).height));
        }
    }
    return largest;
}

/// What the tables count beside the vertices: the borders' segments, the fills' triangles.
std::size_t elementCount(const PolylineCollection& borders)
{
    return borders.segmentCount();
}

std::size_t elementCount(const PolygonCollection& fills)
{
    return fills.triangleCount();
}

/// A scene with only `primitive`, looked at from 20,000 km over (20 E, 20 N): the time its first
/// update() takes (buffers, groups and their culling volumes made), in milliseconds.
double uploadMilliseconds(Context& context, const std::shared_ptr<Primitive>& primitive)
{
    Scene scene(kEarth);
    scene.add(primitive);
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(20, 20, 2e7)), glm::dvec3(0), {0, 0, 1});
    return scene.render(context).updateMilliseconds;
}

std::vector<Table> run(const Options& options)
{
    Device device;
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(kWidth, kHeight);
    context.setFramebuffer(&framebuffer);
    const FeatureCollection countries =
        loadGeoJson(std::filesystem::path(ORBIS_SOURCE_DIR) / "data/natural-earth/countries-110m.geojson");
    const int repeats = options.quick ? 1 : 3;

    // Compile the programs once, so that upload times do not include them.
    {
        FeatureStyle warm;
        warm.granularityRadians = toRadians(10.0);
        const FeaturePrimitives primitives = buildFeaturePrimitives(kEarth, countries, warm);
        uploadMilliseconds(context, primitives.fills);
        uploadMilliseconds(context, primitives.borders);
    }

    const std::vector<double> degrees =
        options.quick ? std::vector<double>{5.0, 1.0} : std::vector<double>{5.0, 2.0, 1.0, 0.5, 0.25, 0.1};
    auto pixels = [](double meters, double distance) {
        return formatNumber(screenSpaceError(meters, distance, kWidth, kFieldOfView), 2);
    };
    // The columns of either table, `elements` naming what granularityRow counts beside the vertices.
    auto granularityColumns = [](const char* elements) {
        return std::vector<std::string>{"granularity",     "vertices",       elements,   "max deviation",
                                        "px at 20,000 km", "px at 2,000 km", "build ms", "upload ms"};
    };
    // A row of either table: the countries built with `style` at granularity g, then the part of
    // them that `part` names (&FeaturePrimitives::borders or ::fills) measured and uploaded.
    auto granularityRow = [&](double g, FeatureStyle style, auto part) {
        style.granularityRadians = toRadians(g);
        FeaturePrimitives primitives;
        const double buildNs = nanosecondsPerItem(
            1, [&] { primitives = buildFeaturePrimitives(kEarth, countries, style); }, repeats);
        const auto& collection = primitives.*part;
        const double drawnDeviation = deviation(*collection);
        const double upload = uploadMilliseconds(context, collection);
        return std::vector<std::string>{formatNumber(g, 3) + " deg", std::to_string(collection->vertexCount()),
                                        std::to_string(elementCount(*collection)), formatLength(drawnDeviation),
                                        pixels(drawnDeviation, 2e7), pixels(drawnDeviation, 2e6),
                                        formatNumber(1e-6 * buildNs, 3), formatNumber(upload, 3)};
    };

    Table borders;
    borders.title = "Country borders as polylines: granularity, deviation and build time";
    borders.description =
        "Every ring of countries-110m as one PolylineCollection (buildFeaturePrimitives, plane sections, relative to "
        "the eye). Deviation: the greatest distance of the drawn segments from the ellipsoid (16 samples a "
        "segment, exact toGeodetic3D): the lift that keeps chords above the surface, the true curve lying on it; in "
        "pixels at 1280x720 with a 45 degree field of view for a viewer 20,000 km and 2,000 km away. Build: "
        "subdivision and lift on the CPU, best of " + std::to_string(repeats) +
        " runs. Upload: the first update() (groups by region and their culling volumes, vertex encoding, buffers "
        "handed to GL), programs compiled beforehand.";
    borders.columns = granularityColumns("segments");
    FeatureStyle bordersOnly;
    bordersOnly.fill = false;
    for (const double g : degrees) {
        borders.rows.push_back(granularityRow(g, bordersOnly, &FeaturePrimitives::borders));
    }
    borders.notes = "The deviation is the lift, a (a / b)^2 (1 - cos(g / 2)): it falls as the square of the "
                    "granularity while the vertices grow as its inverse (once the granularity is finer than the "
                    "data's own spacing, about 2 degrees here). Under a pixel from 2,000 km takes 2 degrees; from "
                    "200 km, 0.5.";

    Table fills;
    fills.title = "Country fills as one PolygonCollection: granularity, deviation and build time";
    fills.description =
        "Every polygon of countries-110m (buildFeaturePrimitives: triangulatePolygon, lift, regions, relative to "
        "the eye). Deviation: the greatest height of a drawn vertex above the ellipsoid, the lift that keeps the "
        "flat triangles above the surface; in pixels as above. Build and upload as above.";
    fills.columns = granularityColumns("triangles");
    FeatureStyle fillsOnly;
    fillsOnly.borders = false;
    for (const double g : degrees) {
        if (g < 0.25) {
            continue; // 1.4 million triangles at 0.1 degree: the polygons section has the trend
        }
        fills.rows.push_back(granularityRow(g, fillsOnly, &FeaturePrimitives::fills));
    }
    fills.notes = "Fills are subdivided inside as well as along their edges: triangles grow as the inverse square "
                  "of the granularity, four times the borders' cost for the same deviation in pixels, which is a "
                  "third larger (a triangle's centre sags deeper than a chord's midpoint).";

    // --- Frame time of the example scenes ---------------------------------------------------------
    Table frames;
    frames.title = "Vector scenes: frame time at 1280x720";
    const int frameCount = options.quick ? 1 : 10;
    frames.description =
        "The ch07_vector_data scene (day globe, every border at 0.5 degree, 1.5 px wide with a 0.75 px outline) and "
        "the ch08_polygons scene (plain globe, every country filled at 1 degree, translucent, with 1 px borders), "
        "seen whole as the examples see them, and the ch08 scene from 2,000 km over Europe; against the globe "
        "alone from the same place. Average of " + std::to_string(frameCount) +
        " frames after one (Scene::render, GPU finished), on this machine's GL. Draws and vertices: what the "
        "renderer counted (vertices: indices read, so a line strip counts its restarts and adjacency).";
    frames.columns = {"scene", "view", "draw calls", "culled by horizon", "vertices drawn", "ms per frame",
                      "globe alone ms"};
    struct Setup {
        const char* name;
        bool textured;
        bool fill;
        double granularityDegrees;
        PolylineStyle border;
        Geodetic3D eye;
        const char* view;
    };
    const Setup setups[] = {
        {"ch07: borders", true, false, 0.5, {glm::vec4(1, 0.85f, 0.2f, 1), 1.5f, glm::vec4(0.1f, 0.1f, 0.1f, 1), 0.75f, true},
         Geodetic3D::fromDegrees(-170, 30, 1.6e7), "North Pacific, 16,000 km"},
        {"ch08: fills and borders", false, true, 1.0, {glm::vec4(1), 1.0f, glm::vec4(0, 0, 0, 1), 0.0f, true},
         Geodetic3D::fromDegrees(140, 40, 1.4e7), "East Asia, 14,000 km"},
        {"ch08: fills and borders", false, true, 1.0, {glm::vec4(1), 1.0f, glm::vec4(0, 0, 0, 1), 0.0f, true},
         Geodetic3D::fromDegrees(10, 50, 2e6), "Europe, 2,000 km"},
    };
    for (const Setup& setup : setups) {
        GlobeOptions globe;
        globe.lighting = true;
        if (setup.textured) {
            globe.dayTexture = "/usr/share/xplanet/images/earth.jpg";
        }
        auto measure = [&](bool withVectors, FrameStatistics& statistics) {
            Scene scene(kEarth);
            scene.add(std::make_shared<Globe>(kEarth, globe));
            if (withVectors) {
                FeatureStyle style;
                style.fill = setup.fill;
                style.fillColor = {0.9f, 0.6f, 0.3f, 0.8f};
                style.border = setup.border;
                style.granularityRadians = toRadians(setup.granularityDegrees);
                buildFeaturePrimitives(kEarth, countries, style).addTo(scene);
            }
            scene.setSunDirection(glm::normalize(kEarth.toCartesian(Geodetic2D{setup.eye.longitude, setup.eye.latitude})));
            scene.camera().lookAt(kEarth.toCartesian(setup.eye), glm::dvec3(0), {0, 0, 1});
            scene.render(context);
            double total = 0.0;
            for (int i = 0; i < frameCount; ++i) {
                const auto start = std::chrono::steady_clock::now();
                statistics = scene.render(context);
                total += millisecondsSince(start);
            }
            return total / frameCount;
        };
        FrameStatistics statistics;
        FrameStatistics globeStatistics;
        const double ms = measure(true, statistics);
        const double globeMs = measure(false, globeStatistics);
        frames.rows.push_back({setup.name, setup.view, std::to_string(statistics.renderer.drawCalls),
                               std::to_string(statistics.commandsCulledByHorizon),
                               std::to_string(statistics.renderer.vertices), formatNumber(ms, 3),
                               formatNumber(globeMs, 3)});
    }
    frames.notes = "Each collection draws one command per region and pass; regions behind the globe are culled by "
                   "their horizon occlusion points before they cost a draw.";
    return {borders, fills, frames};
}

const SectionRegistration registration("polylines and polygons", 75, run);

} // namespace
} // namespace orbis::bench
