// Book chapter 5: the same checkerboard, 2 m below the eye at Earth's surface and part of a mesh
// whose centre is 100 km away, drawn under each vertex transform, side by side, each with the
// window-position error measured on the GPU (transform feedback against double precision).
// Usage: ch05_jitter [--out file.png] [--width W] [--height H]   (W x H: one tile)
#include "../common/PrecisionScenes.h"
#include "../common/SceneExample.h"

#include "PrecisionMeasurement.h"

#include <orbis/renderer/Context.h>

#include <cstdio>
#include <iterator>
#include <utility>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::renderer;
    using namespace orbis::scene;
    using namespace orbis::bench;
    const VertexTransform transforms[] = {VertexTransform::RelativeToWorld,  VertexTransform::RelativeToCenter,
                                          VertexTransform::RelativeToEyeGpu, VertexTransform::RelativeToEyeDsfun90,
                                          VertexTransform::RelativeToEyeCpu, VertexTransform::Automatic};
    auto renderTile = [&](Context& context, std::size_t tile, const examples::ExampleSettings& settings) {
        const VertexTransform transform = transforms[tile];
        if (tile == 0) { // the console table's heading, before its first row
            std::printf("%-42s %12s %12s\n", "vertex transform (eye 2 m away)", "max px", "max mm");
        }
        Scene scene;
        examples::buildJitterScene(scene, transform);
        scene.render(context);
        Image image = context.readPixels();
        JitterOptions options;
        options.width = settings.width;
        options.height = settings.height;
        const JitterResult error = measureVertexJitter(context, transform, examples::jitterSceneTarget(),
                                                       examples::kJitterSceneEyeDistance, options);
        char caption[256];
        std::snprintf(caption, sizeof caption, "%s\nmeasured: %.3g px, %.3g mm", vertexTransformName(transform),
                      error.maxPixels, 1e3 * error.maxMeters);
        std::printf("%-42s %12.4g %12.4g\n", vertexTransformName(transform), error.maxPixels, 1e3 * error.maxMeters);
        return examples::ExampleTile{std::move(image), caption};
    };
    return examples::runTiledExample(argc, argv, {"ch05_jitter.png", 320, 240}, std::size(transforms), renderTile);
}
