#include "SceneTestSupport.h"

#include <orbis/core/Transforms.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

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
