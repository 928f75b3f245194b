// Book chapter 12: the levels of detail a view selects and what culling leaves out. Left: the
// Alps from 120 km looking north, over ETOPO5 exaggerated 3 times, the tiles coloured by level.
// Middle and right: the same selection seen from outside, from above and from the south-west: each drawn
// tile's bounding box (the oriented box the frustum test uses) in its level's colour, and the
// view's frustum in white. Nothing behind the camera or beyond the horizon has a box: those tiles
// were culled, whole subtrees at once.
// Usage: ch12_levels_and_culling [--out file.png] [--width W] [--height H]
#include "../common/SceneExample.h"

#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/core/Math.h>
#include <orbis/renderer/Context.h>
#include <orbis/scene/PolylineCollection.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <array>
#include <cstdio>

namespace {

using namespace orbis;
using namespace orbis::scene;

/// Each drawn tile's oriented box as its twelve edges, in its level's colour.
void addBoxes(PolylineCollection& lines, const std::vector<TiledGlobe::DrawnTile>& tiles)
{
    for (const TiledGlobe::DrawnTile& tile : tiles) {
        const std::array<glm::dvec3, 8> corners = tile.region.orientedBox().corners();
        const PolylineStyle style{tileLevelColor(tile.key.level), 1.5f};
        // Corners differing in one bit of their index share an edge.
        for (int i = 0; i < 8; ++i) {
            for (const int bit : {1, 2, 4}) {
                if ((i & bit) == 0) {
                    const std::array<glm::dvec3, 2> edge{corners[i], corners[i | bit]};
                    lines.add(std::span<const glm::dvec3>(edge), style);
                }
            }
        }
    }
}

/// The camera's frustum, for a width x height view, as lines from the eye through the view's four
/// corners, `length` metres long, and the far rectangle joining their ends.
void addFrustum(PolylineCollection& lines, const Camera& camera, int width, int height, double length)
{
    std::array<glm::dvec3, 4> far;
    int i = 0;
    for (const glm::dvec2 corner : {glm::dvec2(0.0, 0.0), glm::dvec2(width, 0.0), glm::dvec2(width, height),
                                    glm::dvec2(0.0, height)}) {
        const Ray ray = camera.pickRay(corner, width, height);
        far[i++] = ray.origin + length * ray.direction;
    }
    const PolylineStyle white{glm::vec4(1.0f), 2.0f};
    for (const glm::dvec3& corner : far) {
        const std::array<glm::dvec3, 2> ray{camera.eye(), corner};
        lines.add(std::span<const glm::dvec3>(ray), white);
    }
    lines.add(std::span<const glm::dvec3>(far), white, true);
}

} // namespace

int main(int argc, char** argv)
{
    const std::string terrainFolder = (examples::dataDirectory() / "terrain/etopo5").string();
    const std::string imageryFolder = (examples::dataDirectory() / "imagery/BlueMarble").string();
    struct Outside {
        const char* caption;
        Geodetic3D position;
        double heading;
        double pitch;
    };
    // Looking back at the view's camera from above and from the south-west.
    static const Outside kOutside[] = {
        {"seen from above", Geodetic3D::fromDegrees(9.0, 47.0, 3.5e6), 0.0, -90.0},
        {"seen from the south-west", Geodetic3D::fromDegrees(-5.0, 33.0, 1.5e6), 45.0, -35.0},
    };
    examples::ExampleSettings defaults;
    defaults.output = "ch12_levels_and_culling.png";
    defaults.width = 480;
    defaults.height = 360;
    std::vector<TiledGlobe::DrawnTile> selected;
    Camera viewCamera;
    TileStatistics viewStatistics;
    return examples::runTiledExample(
        argc, argv, defaults, 1 + std::size(kOutside),
        [&](renderer::Context& context, std::size_t index, const examples::ExampleSettings& settings) {
            Scene scene;
            char caption[256];
            if (index == 0) {
                TiledGlobeOptions options;
                options.lighting = true;
                options.terrain = world::openTerrainSource(terrainFolder);
                options.terrainExaggeration = 3.0;
                options.colorByLevel = true;
                auto globe = std::make_shared<TiledGlobe>(scene.ellipsoid(), options);
                scene.add(globe);
                scene.camera().setView(scene.ellipsoid(), Geodetic3D::fromDegrees(9.0, 42.0, 120000.0),
                                       HeadingPitchRoll{0.0, toRadians(-25.0), 0.0});
                const auto [statistics, frames] = examples::renderUntilTilesConverge(scene, context);
                selected = globe->drawnTiles();
                viewCamera = scene.camera();
                viewStatistics = *statistics.tiles;
                std::snprintf(caption, sizeof caption, "levels, SSE 2 px: %zu tiles drawn, levels to %u\n%zu visited, "
                              "%zu culled by the frustum, %zu by the horizon",
                              viewStatistics.drawn, viewStatistics.deepestLevelDrawn, viewStatistics.visited,
                              viewStatistics.culledByFrustum, viewStatistics.culledByHorizon);
                return examples::ExampleTile{context.readPixels(), caption};
            }
            const Outside& outside = kOutside[index - 1];
            TiledGlobeOptions backdrop;
            backdrop.imagery.push_back({world::openTileSource(imageryFolder), {1.0, 0.6, 1.0, 1.0, {}}});
            scene.add(std::make_shared<TiledGlobe>(scene.ellipsoid(), backdrop));
            auto lines = std::make_shared<PolylineCollection>(scene.ellipsoid());
            addBoxes(*lines, selected);
            addFrustum(*lines, viewCamera, settings.width, settings.height, 1.3e6); // about the horizon's distance
            scene.add(lines);
            scene.camera().setView(scene.ellipsoid(), outside.position,
                                   HeadingPitchRoll{toRadians(outside.heading), toRadians(outside.pitch), 0.0});
            examples::renderUntilTilesConverge(scene, context);
            std::snprintf(caption, sizeof caption, "the %zu boxes and the frustum,\n%s", selected.size(), outside.caption);
            return examples::ExampleTile{context.readPixels(), caption};
        });
}
