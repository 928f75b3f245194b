// Book chapter 13: geometry clipmapping on the globe. The Alps looking north from 50 km over
// ETOPO5 (exaggerated 20 times, its 9 km spacing upsampled by the four-point filter below that):
// the levels coloured (figure 13.3), the same view shaded with the Blue Marble draped on the
// grids, and a view from near the North Pole to Greenland, where the grids are laid out in a rotated
// parameterisation so that no triangle collapses.
// Usage: ch13_clipmap [--out file.png] [--width W] [--height H]
#include "../common/SceneExample.h"

#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/core/Math.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Context.h>
#include <orbis/scene/ClipmapTerrain.h>
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
        const char* name;
        bool levels;
        Geodetic3D position;
        double headingDegrees, pitchDegrees;
    };
    static const Panel kPanels[] = {
        {"levels", true, Geodetic3D::fromDegrees(8.0, 44.3, 50000.0), 0.0, -25.0},
        {"shaded", false, Geodetic3D::fromDegrees(8.0, 44.3, 50000.0), 0.0, -25.0},
        {"North Pole", false, Geodetic3D::fromDegrees(-40.0, 87.0, 200000.0), 180.0, -35.0},
    };
    examples::ExampleSettings defaults;
    defaults.output = "ch13_clipmap.png";
    defaults.width = 480;
    defaults.height = 360;
    return examples::runTiledExample(
        argc, argv, defaults, std::size(kPanels),
        [&](renderer::Context& context, std::size_t index, const examples::ExampleSettings&) {
            const Panel& panel = kPanels[index];
            ClipmapTerrainOptions options;
            options.lighting = true;
            options.terrain = world::openTerrainSource(terrainFolder);
            options.exaggeration = 20.0;
            options.posts = 127;
            options.colorByLevel = panel.levels;
            if (!panel.levels) {
                options.imagery.push_back({world::openTileSource(imageryFolder), {}});
            }
            Scene scene;
            auto terrain = std::make_shared<ClipmapTerrain>(scene.ellipsoid(), options);
            scene.add(terrain);
            scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-06-21T09:00:00Z")));
            scene.camera().setView(scene.ellipsoid(), panel.position,
                                   HeadingPitchRoll{toRadians(panel.headingDegrees), toRadians(panel.pitchDegrees), 0.0});
            FrameStatistics statistics;
            int frames = 0;
            while (frames < 600 && !terrain->converged()) {
                statistics = scene.render(context);
                ++frames;
            }
            const ClipmapStatistics& clipmap = *statistics.clipmap;
            char caption[256];
            std::snprintf(caption, sizeof caption, "%s: %d levels of %d posts, finest drawn %d\n%zu draws, %zu triangles, %d frames",
                          panel.name, clipmap.levels, options.posts, clipmap.finestLevelDrawn, clipmap.drawCalls,
                          clipmap.trianglesSubmitted, frames);
            return examples::ExampleTile{context.readPixels(), caption};
        });
}
