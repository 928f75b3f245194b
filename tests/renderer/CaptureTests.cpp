// Context::captureVertexOutputs: transform feedback reads back what the vertex stage computed.

#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::renderer;

namespace {

ShaderProgramDescription capturingDescription()
{
    ShaderProgramDescription description = test::solidColorDescription();
    description.name = "capture";
    description.vertex = ShaderSource::fromText("capture.vert.glsl", R"(
in vec3 position;
out vec3 v_doubled;
uniform mat4 og_modelViewProjectionMatrix;
void main()
{
    v_doubled = 2.0 * position;
    gl_Position = og_modelViewProjectionMatrix * vec4(position, 1.0);
}
)");
    description.fragment = ShaderSource::fromText("capture.frag.glsl", R"(
in vec3 v_doubled;
out vec4 fragmentColor;
void main() { fragmentColor = vec4(1.0, 1.0, 1.0, 1.0) + 0.0 * vec4(v_doubled, 0.0); }
)");
    description.transformFeedbackVaryings = {"gl_Position", "v_doubled"};
    return description;
}

} // namespace

TEST_CASE("Transform feedback captures gl_Position and a varying per vertex, interleaved", "[renderer][capture]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(capturingDescription());
    REQUIRE(program.capturedComponents() == 7); // vec4 + vec3

    Mesh points;
    points.primitiveType = PrimitiveType::Points;
    points.positions = {{1, 2, 3}, {-4, 5.5, 0.25}, {1e6, -1e-3, 7}};
    const VertexArray array = context.createVertexArray(points, program);
    Framebuffer framebuffer = context.createFramebuffer(4, 4);
    DrawCommand command;
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.primitiveType = PrimitiveType::Points;
    command.framebuffer = &framebuffer;
    SceneState scene;
    scene.viewMatrix = glm::dmat4(2.0); // x, y and z doubled, w kept
    scene.viewMatrix[3][3] = 1.0;

    const std::vector<float> captured = context.captureVertexOutputs(command, scene);
    REQUIRE(captured.size() == 3 * 7);
    for (std::size_t i = 0; i < points.positions.size(); ++i) {
        const glm::vec3 p(points.positions[i]);
        INFO("vertex " << i);
        // Multiplying by 2 is exact in float, so the captured values are exact too.
        CHECK(captured[7 * i + 0] == 2.0f * p.x);
        CHECK(captured[7 * i + 1] == 2.0f * p.y);
        CHECK(captured[7 * i + 2] == 2.0f * p.z);
        CHECK(captured[7 * i + 3] == 1.0f);
        CHECK(captured[7 * i + 4] == 2.0f * p.x);
        CHECK(captured[7 * i + 5] == 2.0f * p.y);
        CHECK(captured[7 * i + 6] == 2.0f * p.z);
    }

    // Triangles: three records per triangle, in index order; nothing reaches the framebuffer.
    const Mesh square = test::quad(-0.5, -0.5, 0.5, 0.5);
    const VertexArray squareArray = context.createVertexArray(square, program);
    command.vertexArray = &squareArray;
    command.primitiveType = PrimitiveType::Triangles;
    context.clear(ClearState{}, &framebuffer);
    const std::vector<float> triangles = context.captureVertexOutputs(command, SceneState{});
    REQUIRE(triangles.size() == 6 * 7);
    for (std::size_t k = 0; k < 6; ++k) {
        const glm::vec3 p(square.positions[square.indices[k]]);
        CHECK(triangles[7 * k + 0] == p.x);
        CHECK(triangles[7 * k + 1] == p.y);
    }
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 2, 2, {0, 0, 0, 255})); // rasterisation was off

    // Rasterisation is back on for the next draw.
    context.draw(command);
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 2, 2, {255, 255, 255, 255}));
}

TEST_CASE("Capturing with a program built without transform feedback varyings throws, naming the program", "[renderer][capture]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    REQUIRE(program.capturedComponents() == 0);
    const Mesh square = test::quad(-0.5, -0.5, 0.5, 0.5);
    const VertexArray array = context.createVertexArray(square, program);
    Framebuffer framebuffer = context.createFramebuffer(4, 4);
    DrawCommand command = test::makeCommand(array, program, framebuffer, {1, 0, 0, 1}, "no capture");
    REQUIRE_THROWS_WITH(context.captureVertexOutputs(command, SceneState{}),
                        Catch::Matchers::Contains("captures nothing") && Catch::Matchers::Contains("no capture"));
}
