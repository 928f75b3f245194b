// Book chapter 14 (and chapter 12's figures): chunked LOD on the globe. The Alps looking
// north from 800 km over real heights (ETOPO5, exaggerated 3 times so that 9 km of sample spacing shows):
// tiles coloured by level with the selection's statistics, then the Blue Marble on the same tiles
// at 2 pixels of screen-space error, where the switching is hidden, and at 16, where it shows.
// Usage: ch14_chunked_lod [--out file.png] [--width W] [--height H]
#include "../common/SceneExample.h"

#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/core/Math.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Context.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <cstdio>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::scene;
    const std::string terrainFolder = (examples::dataDirectory() / "terrain/etopo5").string();
    const std::string imageryFolder = (examples::dataDirectory() / "imagery/BlueMarble").string();
    struct Panel {
        bool levels;
        double screenSpaceError;
    };
    static constexpr Panel kPanels[] = {{true, 2.0}, {false, 2.0}, {false, 16.0}};
    examples::ExampleSettings defaults;
    defaults.output = "ch14_chunked_lod.png";
    defaults.width = 480;
    defaults.height = 360;
    return examples::runTiledExample(
        argc, argv, defaults, std::size(kPanels),
        [&](renderer::Context& context, std::size_t index, const examples::ExampleSettings&) {
            const Panel& panel = kPanels[index];
            TiledGlobeOptions options;
            options.lighting = true;
            options.terrain = world::openTerrainSource(terrainFolder);
            options.terrainExaggeration = 3.0;
            options.maximumScreenSpaceError = panel.screenSpaceError;
            options.colorByLevel = panel.levels;
            if (!panel.levels) {
                options.imagery.push_back({world::openTileSource(imageryFolder), {}});
            }
            Scene scene;
            scene.add(std::make_shared<TiledGlobe>(scene.ellipsoid(), options));
            scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T09:00:00Z")));
            scene.camera().setView(scene.ellipsoid(), Geodetic3D::fromDegrees(10.0, 36.0, 800000.0),
                                   HeadingPitchRoll{0.0, toRadians(-40.0), 0.0});
            const auto [statistics, frames] = examples::renderUntilTilesConverge(scene, context);
            const TileStatistics& tiles = *statistics.tiles;
            char caption[256];
            std::snprintf(caption, sizeof caption, "%s, SSE %.0f px\n%zu tiles, levels to %u, %d frames",
                          panel.levels ? "levels" : "Blue Marble", panel.screenSpaceError, tiles.drawn,
                          tiles.deepestLevelDrawn, frames);
            return examples::ExampleTile{context.readPixels(), caption};
        });
}
