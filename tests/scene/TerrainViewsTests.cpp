#include "SceneTestSupport.h"

#include "GoldenImage.h"

#include <orbis/core/IntersectionTests.h>
#include <orbis/core/Transforms.h>
#include <orbis/scene/Effect.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

// The terrain issue's views of real data at 1280 x 720: ETOPO5 (or the Cumberland DEM) under the
// Blue Marble, lit by a low Sun, skirts off, each compared with its golden image and searched for
// holes.

using namespace orbis;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
constexpr int kWidth = 1280;
constexpr int kHeight = 720;

struct TerrainView {
    std::string name;
    std::string terrain; ///< under data/
    Geodetic3D position;
    double heading;
    double pitch;
};

/// A Sun 35 degrees above the horizon, from the camera's left, so that slopes facing it and facing
/// away differ.
glm::dvec3 lowSunFor(const TerrainView& view)
{
    const glm::dmat3 enu = eastNorthUpAxes(kEarth, kEarth.toCartesian(view.position));
    const double azimuth = toRadians(view.heading - 90.0);
    const double elevation = toRadians(35.0);
    return enu * glm::dvec3(std::sin(azimuth) * std::cos(elevation), std::cos(azimuth) * std::cos(elevation),
                            std::sin(elevation));
}

/// Background pixels whose ray meets the ellipsoid 11 km down: no ocean is deeper, so every such ray
/// crosses the terrain's surface, and showing the background there is a hole.
int holePixels(const Scene& scene, const Image& image)
{
    const Ellipsoid belowEveryOcean(kEarth.radii() - glm::dvec3(11000.0));
    int holes = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            if (p[0] != 255 || p[1] != 0 || p[2] != 255) {
                continue;
            }
            const Ray ray = scene.camera().pickRay({x + 0.5, y + 0.5}, image.width, image.height);
            holes += intersectRayEllipsoid(ray, belowEveryOcean).has_value();
        }
    }
    return holes;
}

void checkTerrainView(const TerrainView& view, std::uint32_t deepestLevelAtLeast)
{
    TiledGlobeOptions options;
    options.terrain = world::openTerrainSource(dataPath(view.terrain));
    options.lighting = true;
    options.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    options.loader.workerThreads = 0;
    options.loader.latencyFrames = 0;
    options.loader.maximumStartsPerFrame = 64;
    REQUIRE_FALSE(options.skirts);
    Scene scene(kEarth);
    scene.options().background = glm::vec4(1.0f, 0.0f, 1.0f, 1.0f); // magenta: the sky, or a hole
    scene.add(std::make_shared<TiledGlobe>(kEarth, options));
    scene.setSunDirection(lowSunFor(view));
    placeCamera(scene, view.position, view.heading, view.pitch);

    const RenderedFrame frame = renderUntilTilesConverge(scene, kWidth, kHeight, 300);
    INFO(view.name << "\n" << frame.statistics.toText());
    REQUIRE(frame.statistics.tiles);
    REQUIRE(frame.statistics.tiles->converged);
    CHECK(hasEffect(frame.statistics.effects, Effect::Terrain));
    CHECK(frame.statistics.tiles->deepestLevelDrawn >= deepestLevelAtLeast);
    CHECK(holePixels(scene, frame.image) == 0);
    // llvmpipe draws these exactly; the tolerance allows another rasteriser's edges, not a tile
    // missing, the imagery misplaced or the relief lit from elsewhere (thousands of pixels).
    ORBIS_REQUIRE_GOLDEN(frame.image, view.name, GoldenTolerance{3, 0.002});
}

} // namespace

TEST_CASE("Everest from 57 km south-south-west, 15 km up: ETOPO5 under the Blue Marble, no hole",
          "[scene][tiles][terrain][views][gl]")
{
    checkTerrainView({"terrain-everest", "terrain/etopo5", Geodetic3D::fromDegrees(86.75, 27.5, 15000.0), 17.0, -10.0},
                     5);
}

TEST_CASE("The Alps oblique from 8 km: ETOPO5 under the Blue Marble, no hole", "[scene][tiles][terrain][views][gl]")
{
    checkTerrainView({"terrain-alps-8km", "terrain/etopo5", Geodetic3D::fromDegrees(7.6, 45.6, 8000.0), 40.0, -20.0}, 5);
}

TEST_CASE("The Cumberland Mountains from 2 km, looking at the horizon: the 80 m DEM, no hole",
          "[scene][tiles][terrain][views][gl]")
{
    checkTerrainView({"terrain-cumberland-2km", "terrain/cumberland/jacksboro_fault.vrt",
                      Geodetic3D::fromDegrees(-84.40, 36.46, 2000.0), 45.0, -3.0},
                     8);
}

TEST_CASE("The North Pole from 500 km above Greenland: no hole at the pole",
          "[scene][tiles][terrain][views][gl]")
{
    checkTerrainView(
        {"terrain-north-pole", "terrain/etopo5", Geodetic3D::fromDegrees(-40.0, 75.0, 500000.0), 0.0, -35.0}, 4);
}

TEST_CASE("Fiji across the antimeridian from 150 km: ETOPO5 under the Blue Marble, no hole at 180 degrees",
          "[scene][tiles][terrain][views][gl]")
{
    checkTerrainView({"terrain-fiji", "terrain/etopo5", Geodetic3D::fromDegrees(177.0, -17.0, 150000.0), 110.0, -35.0},
                     4);
}
