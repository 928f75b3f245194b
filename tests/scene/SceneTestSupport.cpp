#include "SceneTestSupport.h"

#include "RendererTestSupport.h"

#include <orbis/core/Transforms.h>
#include <orbis/renderer/Device.h>

#include <cmath>

using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::test {

Mesh horizontalSquare(const Ellipsoid& ellipsoid, const Geodetic3D& centre, double halfSize)
{
    const glm::dmat4 frame = eastNorthUpToFixedFrame(ellipsoid, ellipsoid.toCartesian(centre));
    Mesh mesh;
    for (const glm::dvec2 corner : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1)}) {
        mesh.positions.push_back(glm::dvec3(frame * glm::dvec4(corner * halfSize, 0.0, 1.0)));
    }
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

RenderedFrame renderFrame(Scene& scene, int width, int height)
{
    Context& context = sharedDevice().context();
    Framebuffer framebuffer = context.createFramebuffer(width, height);
    context.setFramebuffer(&framebuffer);
    RenderedFrame frame;
    frame.statistics = scene.render(context);
    frame.image = context.readPixels();
    context.setFramebuffer(nullptr);
    return frame;
}

void placeCamera(Scene& scene, const Geodetic3D& position, double headingDegrees, double pitchDegrees)
{
    scene.camera().setView(scene.ellipsoid(), position,
                           HeadingPitchRoll{toRadians(headingDegrees), toRadians(pitchDegrees), 0.0});
}

RenderedFrame renderUntilTilesConverge(Scene& scene, int width, int height, int maxFrames)
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

glm::ivec2 projectToPixel(const Scene& scene, const glm::dvec3& position, int width, int height)
{
    const Camera& camera = scene.camera();
    const glm::dvec4 clip = camera.projectionMatrix(static_cast<double>(width) / height, 1.0, 1e8) *
                            camera.viewMatrix() * glm::dvec4(position, 1.0);
    const glm::dvec2 window = clipToWindow(clip, width, height);
    return {static_cast<int>(std::floor(window.x)), static_cast<int>(std::floor(height - window.y))};
}

} // namespace orbis::test
