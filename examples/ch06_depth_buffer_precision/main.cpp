// Book chapter 6 and the SIGGRAPH 2013 course: an aircraft 2,500 m over mountains with snow 5 m
// thick on the peaks, the globe, and a satellite 36,000 km away, drawn under each depth strategy,
// side by side, each captioned with what ran (frustums and draw calls; times are printed).
// Usage: ch06_depth_buffer_precision [--out file.png] [--width W] [--height H]   (W x H: one tile)
#include "../common/PrecisionScenes.h"
#include "../common/SceneExample.h"

#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Context.h>

#include <cstdio>
#include <iterator>
#include <string>
#include <utility>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::renderer;
    using namespace orbis::scene;
    const DepthStrategy strategies[] = {DepthStrategy::Single,        DepthStrategy::MultiFrustum,
                                        DepthStrategy::LogarithmicVertex, DepthStrategy::Logarithmic,
                                        DepthStrategy::Complementary, DepthStrategy::Automatic};
    auto renderTile = [&](Context& context, std::size_t tile, const examples::ExampleSettings&) {
        const DepthStrategy strategy = strategies[tile];
        Scene scene;
        scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T08:30:00Z")));
        scene.options().depthStrategy = strategy;
        examples::buildDepthScene(scene);
        scene.render(context); // compiles the variants
        const FrameStatistics statistics = scene.render(context);
        Image image = context.readPixels();
        char caption[256];
        // Times go to the console, not into the image, so that the image is the same every run.
        const std::string chosen = strategy == DepthStrategy::Automatic
                                       ? std::string(" -> ") + depthStrategyName(statistics.depthStrategy)
                                       : std::string();
        std::snprintf(caption, sizeof caption, "%s%s\n%zu frustum%s, %zu draw calls", depthStrategyName(strategy),
                      chosen.c_str(), statistics.frustums.size(), statistics.frustums.size() == 1 ? "" : "s",
                      statistics.commandsExecuted);
        std::printf("== %s\n%s", depthStrategyName(strategy), statistics.toText().c_str());
        return examples::ExampleTile{std::move(image), caption};
    };
    return examples::runTiledExample(argc, argv, {"ch06_depth_buffer_precision.png", 400, 300}, std::size(strategies),
                                     renderTile);
}
