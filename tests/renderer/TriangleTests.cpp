// The book's first example (examples/ch03_triangle) as a test, on both backends, against a golden image.
#include "GoldenImage.h"
#include "RendererTestSupport.h"

#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace orbis;
using namespace orbis::renderer;

namespace {

Image renderTriangle(Device& device)
{
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(64, 64);
    context.setFramebuffer(&framebuffer);

    Mesh mesh;
    mesh.positions = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
    mesh.indices = {0, 1, 2};
    ShaderProgramDescription description;
    description.name = "triangle";
    description.vertex = ShaderSource::embedded("examples/triangle/triangle.vert.glsl");
    description.fragment = ShaderSource::embedded("examples/triangle/triangle.frag.glsl");
    ShaderProgram program = device.createShaderProgram(description);
    VertexArray array = context.createVertexArray(mesh, program);

    SceneState scene;
    scene.cameraEye = {0.3, -2.0, 0.3};
    scene.viewMatrix = glm::lookAt(scene.cameraEye, glm::dvec3(0.3, 0.0, 0.3), glm::dvec3(0.0, 0.0, 1.0));
    scene.projectionMatrix = glm::perspective(glm::radians(45.0), 1.0, 0.1, 10.0);

    DrawCommand command;
    command.debugName = "triangle";
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.uniforms.set("u_color", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    command.renderState.facetCulling.enabled = false;

    ClearState clear;
    clear.color = {1.0f, 1.0f, 1.0f, 1.0f};
    context.clear(clear);
    context.draw(command, scene);
    return context.readPixels();
}

} // namespace

TEST_CASE("The chapter 3 triangle renders the same on EGL and OSMesa and matches its golden image",
          "[renderer][triangle]")
{
    std::vector<Image> images;
    std::vector<bool> onLlvmpipe;
    for (const GlBackend backend : {GlBackend::Egl, GlBackend::OsMesa}) {
        DeviceOptions options;
        options.backend = backend;
        Device device(options);
        INFO(device.info().backendDescription);
        const Image image = renderTriangle(device);
        // The triangle (0,0,0), (1,0,0), (0,0,1) seen from -y: the right angle at the bottom left.
        CHECK(test::pixelNear(image, 24, 32, {255, 0, 0, 255}));     // inside, near the right angle
        CHECK(test::pixelNear(image, 44, 16, {255, 255, 255, 255})); // beyond the hypotenuse
        CHECK(test::pixelNear(image, 2, 2, {255, 255, 255, 255}));   // corner
        // Edge pixels may differ between rasterisers: 1 % of them beyond llvmpipe.
        ORBIS_REQUIRE_GOLDEN(image, "renderer/triangle", test::exactOnLlvmpipe(device, {2, 0.01}));
        images.push_back(image);
        onLlvmpipe.push_back(device.info().renderer.find("llvmpipe") != std::string::npos);
    }
    // The two backends against each other: the same rasteriser gives the same pixels.
    const test::ImageDifference difference = test::compareImages(images[0], images[1], 0);
    REQUIRE(difference.sameSize);
    INFO(difference.differingPixels << " pixels differ, by up to " << difference.maxChannelDifference);
    CHECK(difference.differingFraction <= (onLlvmpipe[0] && onLlvmpipe[1] ? 0.0 : 0.01));
}
