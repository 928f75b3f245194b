// SceneState::depthConvention: complementary (reversed) depth through glClipControl.

#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_clip_space.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;
using namespace orbis::renderer;

namespace {

constexpr double kFieldOfView = 0.7853981633974483; // 45 degrees

/// Eye looking down -z; window depth 1 at `nearDistance`, falling as nearDistance / w to 0 at
/// infinity (clip z = near, clip w = -z_eye).
glm::dmat4 complementaryProjection(double nearDistance)
{
    const double f = 1.0 / std::tan(0.5 * kFieldOfView);
    glm::dmat4 p(0.0);
    p[0][0] = f;
    p[1][1] = f;
    p[2][3] = -1.0;
    p[3][2] = nearDistance;
    return p;
}

/// Two squares facing the eye, `distance` and `distance + separation` away: the far one red and
/// drawn first, the near one green and drawn second with depth test Less, so that a tie leaves red
/// (counted as wrong). Returns the red pixels in the middle 16 x 16.
int wrongPixels(Framebuffer& framebuffer, const SceneState& scene, double distance, double separation,
                double clearDepth)
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    const double half = 0.4 * distance * std::tan(0.5 * kFieldOfView);
    const Mesh far = test::quad(-half, -half, half, half, -(distance + separation));
    const Mesh near = test::quad(-half, -half, half, half, -distance);
    const VertexArray farArray = context.createVertexArray(far, program);
    const VertexArray nearArray = context.createVertexArray(near, program);
    ClearState clear;
    clear.depth = clearDepth;
    context.clear(clear, &framebuffer);
    context.draw(test::makeCommand(farArray, program, framebuffer, {1, 0, 0, 1}, "far"), scene);
    context.draw(test::makeCommand(nearArray, program, framebuffer, {0, 1, 0, 1}, "near"), scene);
    const Image image = context.readPixels(&framebuffer);
    int wrong = 0;
    for (int y = 24; y < 40; ++y) {
        for (int x = 24; x < 40; ++x) {
            wrong += test::pixelNear(image, x, y, {0, 255, 0, 255}) ? 0 : 1;
        }
    }
    return wrong;
}

} // namespace

TEST_CASE("Complementary depth in a float buffer orders squares 1 m apart at 10,000 km; standard 24-bit depth cannot", "[renderer][depth]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    constexpr double kNear = 1.0;
    constexpr double kDistance = 1e7; // and 1e7 + 1: both exact floats, so only depth is tested

    FramebufferOptions fixed24;
    fixed24.depthFormat = TextureFormat::Depth24Stencil8;
    Framebuffer standardTarget = context.createFramebuffer(64, 64, fixed24);
    SceneState standard;
    standard.projectionMatrix = glm::perspective(kFieldOfView, 1.0, kNear, 1e8);
    // Window depths 1 - 1e-7 apart by 1e-14: far below the 2^-24 step, so every pixel ties.
    CHECK(wrongPixels(standardTarget, standard, kDistance, 1.0, 1.0) == 256);

    FramebufferOptions float32;
    float32.depthFormat = TextureFormat::Depth32F;
    Framebuffer complementaryTarget = context.createFramebuffer(64, 64, float32);
    SceneState complementary;
    complementary.projectionMatrix = complementaryProjection(kNear);
    complementary.depthConvention = DepthConvention::Complementary;
    if (!device.info().clipControl) {
        // A driver without glClipControl: the draw says what is missing rather than drawing wrongly.
        REQUIRE_THROWS_WITH(wrongPixels(complementaryTarget, complementary, kDistance, 1.0, 0.0),
                            Catch::Matchers::Contains("GL_ARB_clip_control"));
        return;
    }
    // Window depths 1e-7 and 1e-7 (1 - 1e-7): 1.7 float spacings apart, each exact from one division.
    CHECK(wrongPixels(complementaryTarget, complementary, kDistance, 1.0, 0.0) == 0);
    // The standard convention afterwards: the clip range went back to -1..1.
    CHECK(wrongPixels(standardTarget, standard, kDistance, 1.0, 1.0) == 256);
    CHECK(wrongPixels(standardTarget, standard, 10.0, 1.0, 1.0) == 0);
}

TEST_CASE("Complementary depth mirrors each command's comparison: Less keeps the nearer surface", "[renderer][depth]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    FramebufferOptions float32;
    float32.depthFormat = TextureFormat::Depth32F;
    Framebuffer target = context.createFramebuffer(64, 64, float32);
    SceneState scene;
    scene.projectionMatrix = complementaryProjection(0.1);
    scene.depthConvention = DepthConvention::Complementary;
    if (!device.info().clipControl) {
        REQUIRE_THROWS_WITH(wrongPixels(target, scene, 5.0, 1.0, 0.0), Catch::Matchers::Contains("GL_ARB_clip_control"));
        return;
    }
    CHECK(wrongPixels(target, scene, 5.0, 1.0, 0.0) == 0);
    CHECK(wrongPixels(target, scene, 5.0, -1.0, 0.0) == 256); // the "far" square is now in front
}
