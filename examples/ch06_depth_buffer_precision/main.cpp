// Book chapter 6 and the SIGGRAPH 2013 course: an aircraft 2,500 m over mountains with snow 5 m
// thick on the peaks, the globe, and a satellite 36,000 km away, drawn under each depth strategy,
// side by side, each captioned with what ran (frustums and draw calls; times are printed).
// Usage: ch06_depth_buffer_precision [--out file.png] [--width W] [--height H]   (W x H: one tile)
#include "../common/PrecisionScenes.h"

#include <orbis/core/Error.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Device.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv)
{
    using namespace orbis;
    std::string output = "ch06_depth_buffer_precision.png";
    int width = 400;
    int height = 300;
    for (int i = 1; i < argc; ++i) {
        const bool hasValue = i + 1 < argc;
        if (std::strcmp(argv[i], "--out") == 0 && hasValue) {
            output = argv[++i];
        } else if (std::strcmp(argv[i], "--width") == 0 && hasValue) {
            width = std::atoi(argv[++i]);
        } else if (std::strcmp(argv[i], "--height") == 0 && hasValue) {
            height = std::atoi(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: %s [--out file.png] [--width W] [--height H]\n", argv[0]);
            return 2;
        }
    }
    try {
        Device device;
        Context& context = device.context();
        Framebuffer framebuffer = context.createFramebuffer(width, height);
        const DepthStrategy strategies[] = {DepthStrategy::Single,        DepthStrategy::MultiFrustum,
                                            DepthStrategy::LogarithmicVertex, DepthStrategy::Logarithmic,
                                            DepthStrategy::Complementary, DepthStrategy::Automatic};
        std::vector<Image> tiles;
        for (const DepthStrategy strategy : strategies) {
            Scene scene;
            scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T08:30:00Z")));
            scene.options().depthStrategy = strategy;
            examples::buildDepthScene(scene);
            context.setFramebuffer(&framebuffer);
            scene.render(context); // compiles the variants
            const FrameStatistics statistics = scene.render(context);
            Image tile = context.readPixels();
            char caption[256];
            // Times go to the console, not into the image, so that the image is the same every run.
            const std::string chosen = strategy == DepthStrategy::Automatic
                                           ? std::string(" -> ") + depthStrategyName(statistics.depthStrategy)
                                           : std::string();
            std::snprintf(caption, sizeof caption, "%s%s\n%zu frustum%s, %zu draw calls", depthStrategyName(strategy),
                          chosen.c_str(), statistics.frustums.size(), statistics.frustums.size() == 1 ? "" : "s",
                          statistics.commandsExecuted);
            // Captions scale with the tile, up to 13 pixels.
            const float captionSize = std::clamp(std::min(static_cast<float>(width) / 25.0f, static_cast<float>(height) / 18.0f), 6.5f, 13.0f);
            examples::drawCaption(tile, 4, 3, caption, captionSize);
            tiles.push_back(std::move(tile));
            std::printf("== %s\n%s", depthStrategyName(strategy), statistics.toText().c_str());
        }
        context.setFramebuffer(nullptr);
        writePng(examples::composeTiles(tiles, 3), output);
        std::printf("%s: %d tiles of %dx%d\n", output.c_str(), static_cast<int>(tiles.size()), width, height);
        return 0;
    } catch (const Error& error) {
        std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
        return 1;
    }
}
