// Book chapter 5: the same checkerboard, 2 m below the eye at Earth's surface and part of a mesh
// whose centre is 100 km away, drawn under each vertex transform, side by side, each with the
// window-position error measured on the GPU (transform feedback against double precision).
// Usage: ch05_jitter [--out file.png] [--width W] [--height H]   (W x H: one tile)
#include "../common/PrecisionScenes.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/PrecisionMeasurement.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv)
{
    using namespace orbis;
    std::string output = "ch05_jitter.png";
    int width = 320;
    int height = 240;
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
        const VertexTransform transforms[] = {VertexTransform::RelativeToWorld,  VertexTransform::RelativeToCenter,
                                              VertexTransform::RelativeToEyeGpu, VertexTransform::RelativeToEyeDsfun90,
                                              VertexTransform::RelativeToEyeCpu, VertexTransform::Automatic};
        std::vector<Image> tiles;
        std::printf("%-42s %12s %12s\n", "vertex transform (eye 2 m away)", "max px", "max mm");
        for (const VertexTransform transform : transforms) {
            Scene scene;
            examples::buildJitterScene(scene, transform);
            context.setFramebuffer(&framebuffer);
            scene.render(context);
            Image tile = context.readPixels();
            JitterOptions options;
            options.width = width;
            options.height = height;
            const JitterResult error = measureVertexJitter(context, transform, examples::jitterSceneTarget(),
                                                           examples::kJitterSceneEyeDistance, options);
            char caption[256];
            std::snprintf(caption, sizeof caption, "%s\nmeasured: %.3g px, %.3g mm", vertexTransformName(transform),
                          error.maxPixels, 1e3 * error.maxMeters);
            // Captions scale with the tile, up to 13 pixels.
            const float captionSize = std::clamp(std::min(static_cast<float>(width) / 25.0f, static_cast<float>(height) / 18.0f), 6.5f, 13.0f);
            examples::drawCaption(tile, 4, 3, caption, captionSize);
            tiles.push_back(std::move(tile));
            std::printf("%-42s %12.4g %12.4g\n", vertexTransformName(transform), error.maxPixels, 1e3 * error.maxMeters);
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
