// Book chapter 11: a height map rendered and shaded. The Cumberland Mountains (an 80 m DEM of the
// Jacksboro fault, read by GDAL through data/terrain/cumberland/jacksboro_fault.vrt), exaggerated
// twice, from 10 km looking north (the view stays on the DEM), four ways: lit by a morning Sun through the normals computed
// from the heights, coloured by height with 100 m contours, coloured by slope, and hillshaded.
// Usage: ch11_terrain_shading [--out file.png] [--width W] [--height H]
#include "../common/SceneExample.h"

#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/core/Math.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Context.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TerrainSource.h>

#include <cstdio>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::scene;
    const std::string dem = (examples::dataDirectory() / "terrain/cumberland/jacksboro_fault.vrt").string();
    struct Panel {
        const char* caption;
        bool sun;
        TerrainShading shading;
    };
    TerrainShading byHeight;
    byHeight.color = TerrainShading::Color::Height;
    byHeight.minimumHeight = 200.0;
    byHeight.maximumHeight = 1100.0;
    byHeight.contourInterval = 100.0;
    byHeight.contourColor = glm::vec3(0.15f);
    TerrainShading bySlope;
    bySlope.color = TerrainShading::Color::Slope;
    TerrainShading hillshade;
    hillshade.hillshade = true;
    const Panel panels[] = {{"Sun on the normals", true, {}},
                            {"height, 100 m contours", false, byHeight},
                            {"slope", false, bySlope},
                            {"hillshade from the north-west", false, hillshade}};
    examples::ExampleSettings defaults;
    defaults.output = "ch11_terrain_shading.png";
    defaults.width = 480;
    defaults.height = 320;
    return examples::runTiledExample(
        argc, argv, defaults, std::size(panels),
        [&](renderer::Context& context, std::size_t index, const examples::ExampleSettings&) {
            const Panel& panel = panels[index];
            TiledGlobeOptions options;
            options.terrain = world::openTerrainSource(dem);
            options.terrainExaggeration = 2.0;
            options.lighting = panel.sun;
            options.shading = panel.shading;
            options.baseColor = glm::vec4(0.55f, 0.6f, 0.45f, 1.0f);
            Scene scene;
            scene.options().background = glm::vec4(0.53f, 0.66f, 0.82f, 1.0f);
            scene.add(std::make_shared<TiledGlobe>(scene.ellipsoid(), options));
            scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-06-20T12:30:00Z")));
            scene.camera().setView(scene.ellipsoid(), Geodetic3D::fromDegrees(-84.245, 36.44, 10000.0),
                                   HeadingPitchRoll{0.0, toRadians(-45.0), 0.0});
            const FrameStatistics statistics = examples::renderUntilTilesConverge(scene, context).statistics;
            char caption[128];
            std::snprintf(caption, sizeof caption, "%s\n%zu tiles, levels to %u", panel.caption,
                          statistics.tiles->drawn, statistics.tiles->deepestLevelDrawn);
            return examples::ExampleTile{context.readPixels(), caption};
        });
}
