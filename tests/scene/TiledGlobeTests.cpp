#include "SceneTestSupport.h"

#include <orbis/core/Transforms.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace orbis;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::string dataPath(const std::string& relative)
{
    return std::string(ORBIS_SOURCE_DIR) + "/data/" + relative;
}

/// A camera at a geodetic position looking along a heading and pitch (degrees).
void place(Scene& scene, const Geodetic3D& position, double headingDegrees, double pitchDegrees)
{
    const glm::dvec3 eye = kEarth.toCartesian(position);
    const ViewOrientation view = headingPitchRollToView(kEarth, eye, toRadians(headingDegrees), toRadians(pitchDegrees), 0.0);
    scene.camera().lookAt(eye, eye + view.direction * glm::length(eye), view.up);
}

/// Renders until the tiles converge (at most maxFrames); returns the last frame.
RenderedFrame renderConverged(Scene& scene, int width, int height, int maxFrames = 200)
{
    RenderedFrame frame;
    for (int i = 0; i < maxFrames; ++i) {
        frame = renderFrame(scene, width, height);
        if (frame.statistics.tiles && frame.statistics.tiles->converged) {
            break;
        }
    }
    return frame;
}

} // namespace

TEST_CASE("A tiled globe over the Alps converges to the Blue Marble's deepest level", "[scene][tiles][gl]")
{
    TiledGlobeOptions options;
    options.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    options.lighting = false;
    Scene scene(kEarth);
    scene.add(std::make_shared<TiledGlobe>(kEarth, options));
    place(scene, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
    const RenderedFrame frame = renderConverged(scene, 640, 360);
    REQUIRE(frame.statistics.tiles);
    INFO(frame.statistics.toText());
    world::writePng(frame.image, "/tmp/tiled-alps.png");
    CHECK(frame.statistics.tiles->converged);
    CHECK(frame.statistics.tiles->deepestLevelDrawn == 4);
}

namespace {

/// FNV-1a of an image's bytes: frames compared exactly.
std::uint64_t hashOf(const Image& image)
{
    std::uint64_t hash = 1469598103934665603ull;
    for (const std::uint8_t byte : image.pixels) {
        hash = (hash ^ byte) * 1099511628211ull;
    }
    return hash;
}

/// A descent over the Alps while turning: from 20,000 km to 40 km in `frames` frames.
void descend(Scene& scene, int frame, int frames)
{
    const double t = static_cast<double>(frame) / (frames - 1);
    const double height = std::exp(std::log(2.0e7) * (1.0 - t) + std::log(4.0e4) * t);
    place(scene, Geodetic3D::fromDegrees(7.0 + 3.0 * t, 46.0, height), 360.0 * t, -90.0 + 50.0 * t);
}

struct Flight {
    std::vector<std::uint64_t> frames;
    std::vector<TiledGlobe::Load> loads;
    bool operator==(const Flight&) const = default;
};

Flight flyWith(int threads)
{
    TiledGlobeOptions options;
    options.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    options.imagery.push_back({world::openTileSource(dataPath("imagery/NaturalEarthII")), {0.5, 1.2, 1.1, 1.0, {}}});
    options.lighting = false;
    options.loader.workerThreads = threads;
    options.loader.latencyFrames = 2;
    options.loader.maximumStartsPerFrame = 5;
    options.loader.maximumInFlight = 9;
    auto globe = std::make_shared<TiledGlobe>(kEarth, options);
    Scene scene(kEarth);
    scene.add(globe);
    Flight flight;
    constexpr int kFrames = 120;
    for (int frame = 0; frame < kFrames; ++frame) {
        descend(scene, frame, kFrames);
        flight.frames.push_back(hashOf(renderFrame(scene, 96, 64).image));
        flight.loads.insert(flight.loads.end(), globe->loadsStarted().begin(), globe->loadsStarted().end());
    }
    return flight;
}

} // namespace

TEST_CASE("A camera path gives the same frames and the same loads with 0, 1, 2 and 4 loader threads",
          "[scene][tiles][gl]")
{
    const Flight reference = flyWith(0);
    CHECK(reference.loads.size() > 60);
    for (int threads : {1, 2, 4}) {
        INFO("threads " << threads);
        const Flight flight = flyWith(threads);
        CHECK(flight.loads == reference.loads);
        CHECK(flight.frames == reference.frames);
    }
}

TEST_CASE("Streaming never leaves a hole: a nadir flight across the antimeridian and a pole while tiles load",
          "[scene][tiles][gl]")
{
    TiledGlobeOptions options;
    options.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    options.lighting = false;
    options.baseColor = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
    options.loader.workerThreads = 2;
    options.loader.latencyFrames = 3;
    options.loader.maximumStartsPerFrame = 2; // slow loading: parents stand in often
    Scene scene(kEarth);
    scene.options().background = glm::vec4(1.0f, 0.0f, 1.0f, 1.0f); // magenta shows a hole
    auto globe = std::make_shared<TiledGlobe>(kEarth, options);
    scene.add(globe);
    std::size_t standIns = 0;
    constexpr int kFrames = 160;
    for (int frame = 0; frame < kFrames; ++frame) {
        // 600 km to 60 km high, from 170 E across the antimeridian, then north over the pole.
        const double t = static_cast<double>(frame) / (kFrames - 1);
        const double height = 6.0e5 * std::pow(0.1, std::min(1.0, 2.0 * t));
        const Geodetic3D position = t < 0.5 ? Geodetic3D::fromDegrees(170.0 + 40.0 * t, 60.0, height)
                                            : Geodetic3D::fromDegrees(-170.0, 60.0 + 60.0 * (t - 0.5), height);
        place(scene, Geodetic3D(position.longitude, std::min(position.latitude, toRadians(89.999)), height), 0.0, -90.0);
        const RenderedFrame rendered = renderFrame(scene, 64, 64);
        standIns += rendered.statistics.tiles->standIns;
        int holes = 0;
        for (int y = 0; y < 64; ++y) {
            for (int x = 0; x < 64; ++x) {
                const std::uint8_t* p = rendered.image.pixel(x, y);
                holes += (p[0] == 255 && p[1] == 0 && p[2] == 255) ? 1 : 0;
            }
        }
        INFO("frame " << frame << "\n" << rendered.statistics.toText());
        REQUIRE(holes == 0);
    }
    CHECK(standIns > 20); // the flight did outrun the loads
}

TEST_CASE("A scene without tiled imagery does none of the tile work", "[scene][tiles][gl]")
{
    Scene plain(kEarth);
    plain.add(std::make_shared<Globe>(kEarth, GlobeOptions{}));
    place(plain, Geodetic3D::fromDegrees(0.0, 0.0, 1.0e7), 0.0, -90.0);
    const RenderedFrame frame = renderFrame(plain, 64, 64);
    CHECK_FALSE(frame.statistics.tiles);
    const std::vector<std::string> effects = frame.statistics.effectsRun();
    CHECK(std::find(effects.begin(), effects.end(), "tiled imagery") == effects.end());
    CHECK(frame.statistics.toJson().find("\"tiles\"") == std::string::npos);

    Scene tiled(kEarth);
    tiled.add(std::make_shared<TiledGlobe>(kEarth, TiledGlobeOptions{}));
    place(tiled, Geodetic3D::fromDegrees(0.0, 0.0, 1.0e7), 0.0, -90.0);
    const RenderedFrame tiledFrame = renderFrame(tiled, 64, 64);
    REQUIRE(tiledFrame.statistics.tiles);
    CHECK(tiledFrame.statistics.tiles->drawn == 2); // the roots: no imagery asks for more
    CHECK(tiledFrame.statistics.toJson().find("\"tiles\"") != std::string::npos);
}
