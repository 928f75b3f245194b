#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

TEST_CASE("A command's uniform map keeps every value type, replaces and erases", "[renderer][uniforms]")
{
    UniformValues values;
    CHECK(values.empty());
    const glm::mat4 matrix(1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f, 9.0f, 10.0f, 11.0f, 12.0f, 13.0f, 14.0f,
                           15.0f, 16.0f);
    values.set("u_bool", true);
    values.set("u_int", -7);
    values.set("u_ivec3", glm::ivec3(1, -2, 3));
    values.set("u_float", 0.25f);
    values.set("u_vec4", glm::vec4(1.0f, 2.0f, 3.0f, 4.0f));   // the fifth: beyond the inline entries
    values.set("u_mat3", glm::mat3(matrix));
    values.set("u_mat4", matrix);
    values.set("u_mat2", glm::mat2(9.0f));
    REQUIRE(values.size() == 8);
    CHECK(std::get<bool>(*values.find("u_bool")));
    CHECK(std::get<int>(*values.find("u_int")) == -7);
    CHECK(std::get<glm::ivec3>(*values.find("u_ivec3")) == glm::ivec3(1, -2, 3));
    CHECK(std::get<float>(*values.find("u_float")) == 0.25f);
    CHECK(std::get<glm::vec4>(*values.find("u_vec4")) == glm::vec4(1.0f, 2.0f, 3.0f, 4.0f));
    CHECK(std::get<glm::mat3>(*values.find("u_mat3")) == glm::mat3(matrix));
    CHECK(std::get<glm::mat4>(*values.find("u_mat4")) == matrix);
    CHECK(std::get<glm::mat2>(*values.find("u_mat2")) == glm::mat2(9.0f));
    CHECK_FALSE(values.find("u_missing"));
    CHECK(values.name(4) == "u_vec4");

    values.set("u_mat4", glm::vec2(5.0f, 6.0f)); // a large value replaced by a small one
    CHECK(std::get<glm::vec2>(*values.find("u_mat4")) == glm::vec2(5.0f, 6.0f));
    values.set("u_mat3", glm::mat3(2.0f));
    CHECK(std::get<glm::mat3>(*values.find("u_mat3")) == glm::mat3(2.0f));
    CHECK(values.size() == 8);

    CHECK(values.erase("u_int"));
    CHECK_FALSE(values.erase("u_int"));
    CHECK(values.size() == 7);
    CHECK(values.name(3) == "u_vec4"); // later entries move up, across the inline boundary
    CHECK(std::get<glm::vec4>(values.value(3)) == glm::vec4(1.0f, 2.0f, 3.0f, 4.0f));
    CHECK(std::get<glm::mat3>(*values.find("u_mat3")) == glm::mat3(2.0f));
    values.clear();
    CHECK(values.empty());
}

TEST_CASE("A program with more uniforms than fit inline gets them all from the command", "[renderer][uniforms]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgramDescription description = test::solidColorDescription();
    description.fragment = ShaderSource::fromText("many.frag.glsl", R"(
out vec4 fragmentColor;
uniform float u_a; uniform float u_b; uniform float u_c; uniform float u_d; uniform float u_e; uniform vec4 u_color;
void main() { fragmentColor = u_color * (u_a + u_b + u_c + u_d + u_e); }
)");
    ShaderProgram program = device.createShaderProgram(description);
    const VertexArray array = context.createVertexArray(test::fullScreenQuad(), program);
    Framebuffer framebuffer = context.createFramebuffer(4, 4);
    DrawCommand command = test::makeCommand(array, program, framebuffer, {1.0f, 0.5f, 0.25f, 1.0f});
    for (const char* name : {"u_a", "u_b", "u_c", "u_d", "u_e"}) {
        command.uniforms.set(name, 0.2f);
    }
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 1, 1, {255, 128, 64, 255}, 1));
}

TEST_CASE("A list of commands draws in order and stops at the first error", "[renderer][context]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    const VertexArray left = context.createVertexArray(test::quad(-1.0, -1.0, 0.0, 1.0), program);
    const VertexArray right = context.createVertexArray(test::quad(0.0, -1.0, 1.0, 1.0), program);
    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    std::vector<DrawCommand> commands = {test::makeCommand(left, program, framebuffer, {1, 0, 0, 1}, "left"),
                                         test::makeCommand(right, program, framebuffer, {0, 0, 1, 1}, "right")};
    context.clear(ClearState{}, &framebuffer);
    context.resetStatistics();
    context.draw(commands, SceneState{});
    CHECK(context.statistics().drawCalls == 2);
    Image image = context.readPixels(&framebuffer);
    CHECK(test::pixelNear(image, 1, 4, {255, 0, 0, 255}));
    CHECK(test::pixelNear(image, 6, 4, {0, 0, 255, 255}));

    commands[1].shaderProgram = nullptr;
    commands[0].uniforms.set("u_color", glm::vec4(0, 1, 0, 1));
    context.clear(ClearState{}, &framebuffer);
    REQUIRE_THROWS_WITH(context.draw(commands, SceneState{}), Contains("'right'") && Contains("no shader program"));
    image = context.readPixels(&framebuffer);
    CHECK(test::pixelNear(image, 1, 4, {0, 255, 0, 255})); // the first was drawn
    CHECK(test::pixelNear(image, 6, 4, {0, 0, 0, 255}));
}
