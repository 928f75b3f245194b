#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

TEST_CASE("Drawing the same command again issues only the draw call", "[renderer][context][shadowing]")
{
    test::QuadFixture quad(16);
    auto& [device, context, framebuffer, program, array] = quad;
    DrawCommand command = test::makeCommand(array, program, framebuffer, {1.0f, 0.0f, 0.0f, 1.0f});

    context.draw(command);
    context.resetStatistics();
    context.draw(command);
    const RenderStatistics second = context.statistics();
    CHECK(second.drawCalls == 1);
    CHECK(second.primitives == 2);
    CHECK(second.stateChangesMade == 0);
    CHECK(second.stateChangesAvoided > 10);
    CHECK(second.programBinds == 0);
    CHECK(second.vertexArrayBinds == 0);
    CHECK(second.framebufferBinds == 0);
    CHECK(second.bindsAvoided == 3);
    CHECK(second.uniformUploads == 0);
    CHECK(second.uniformUploadsAvoided >= 2); // u_color and the model-view-projection matrix
    CHECK(second.glCalls == 1);               // glDrawElements, nothing else
}

TEST_CASE("Changing one part of the render state changes only that part", "[renderer][context][shadowing]")
{
    test::QuadFixture quad(16);
    auto& [device, context, framebuffer, program, array] = quad;
    DrawCommand opaque = test::makeCommand(array, program, framebuffer, {1.0f, 0.0f, 0.0f, 1.0f});
    DrawCommand blended = opaque;
    blended.renderState.blending = Blending::alphaBlending();

    context.draw(opaque);
    context.resetStatistics();
    context.draw(blended);
    RenderStatistics statistics = context.statistics();
    CHECK(statistics.stateChangesMade == 2); // glEnable(GL_BLEND), glBlendFuncSeparate
    CHECK(statistics.glCalls == 3);          // and the draw

    // Back to opaque: only glDisable(GL_BLEND); the blend function stays as it is, unused.
    context.resetStatistics();
    context.draw(opaque);
    statistics = context.statistics();
    CHECK(statistics.stateChangesMade == 1);
    CHECK(statistics.glCalls == 2);

    // A new uniform value is one upload.
    context.resetStatistics();
    opaque.uniforms.set("u_color", glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
    context.draw(opaque);
    statistics = context.statistics();
    CHECK(statistics.uniformUploads == 1);
    CHECK(statistics.glCalls == 2);
}

TEST_CASE("Drawing with no program or no vertex array is a clear error", "[renderer][context][errors]")
{
    test::QuadFixture quad(8);
    auto& [device, context, framebuffer, program, array] = quad;

    DrawCommand command;
    command.debugName = "empty";
    command.framebuffer = &framebuffer;
    REQUIRE_THROWS_WITH(context.draw(command), Contains("'empty'") && Contains("no shader program"));
    ShaderProgram moved = std::move(program);
    command.shaderProgram = &program; // moved from: empty
    REQUIRE_THROWS_WITH(context.draw(command), Contains("no shader program"));
    command.shaderProgram = &moved;
    REQUIRE_THROWS_WITH(context.draw(command), Contains("no vertex array"));
}

TEST_CASE("Uniforms never set, unknown or of the wrong type are clear errors", "[renderer][context][errors]")
{
    test::QuadFixture quad(8);
    auto& [device, context, framebuffer, program, array] = quad;

    DrawCommand command;
    command.debugName = "unset";
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.framebuffer = &framebuffer;
    REQUIRE_THROWS_WITH(context.draw(command), Contains("'unset'") && Contains("never given a value: u_color (vec4)"));

    command.uniforms.set("u_colour", glm::vec4(1.0f));
    REQUIRE_THROWS_WITH(context.draw(command), Contains("no active uniform u_colour") && Contains("active: "));
    command.uniforms.clear();
    command.uniforms.set("u_color", 1.0f);
    REQUIRE_THROWS_WITH(context.draw(command), Contains("u_color is vec4 but the value is float"));
    command.uniforms.set("u_color", glm::vec4(1.0f));
    context.draw(command);
}

TEST_CASE("Statistics count draws, primitives by type and clears until reset", "[renderer][context][statistics]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    Mesh mesh;
    mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}, {1, 1, 0}, {0, 0, 0}, {0.5, 0.5, 0}};
    const VertexArray array = context.createVertexArray(mesh, program);
    DrawCommand command = test::makeCommand(array, program, framebuffer, glm::vec4(1.0f));
    command.renderState.facetCulling.enabled = false;

    context.resetStatistics();
    context.clear(ClearState{}, &framebuffer);
    const std::pair<PrimitiveType, std::uint64_t> cases[] = {
        {PrimitiveType::Triangles, 2}, {PrimitiveType::TriangleStrip, 4}, {PrimitiveType::Lines, 3},
        {PrimitiveType::LineStrip, 5}, {PrimitiveType::Points, 6}};
    std::uint64_t primitives = 0;
    for (const auto& [type, count] : cases) {
        command.primitiveType = type;
        context.draw(command);
        primitives += count;
    }
    command.count = 0; // nothing to draw: not a draw call
    context.draw(command);
    RenderStatistics statistics = context.statistics();
    CHECK(statistics.drawCalls == 5);
    CHECK(statistics.primitives == primitives);
    CHECK(statistics.vertices == 30);
    CHECK(statistics.clears == 1);
    CHECK(statistics.glCalls > 5);

    context.resetStatistics();
    statistics = context.statistics();
    CHECK(statistics.drawCalls == 0);
    CHECK(statistics.primitives == 0);
    CHECK(statistics.glCalls == 0);
}

TEST_CASE("After resetState the next draw sets every state item and binding again", "[renderer][context][shadowing]")
{
    test::QuadFixture quad(8);
    auto& [device, context, framebuffer, program, array] = quad;
    const DrawCommand command = test::makeCommand(array, program, framebuffer, {0, 1, 0, 1});
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);

    context.resetState();
    context.resetStatistics();
    context.draw(command);
    const RenderStatistics statistics = context.statistics();
    CHECK(statistics.stateChangesMade >= 30);
    CHECK(statistics.programBinds == 1);
    CHECK(statistics.vertexArrayBinds == 1);
    CHECK(statistics.framebufferBinds == 1);
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 4, 4, {0, 255, 0, 255}));
}
