#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

ShaderProgramDescription textureCoordinateDescription()
{
    ShaderProgramDescription description;
    description.name = "texture coordinates";
    description.vertex = ShaderSource::fromText("uv.vert.glsl", R"(
in vec4 position;
in vec2 textureCoordinate;
out vec2 v_textureCoordinate;
void main() { v_textureCoordinate = textureCoordinate; gl_Position = position; }
)");
    description.fragment = ShaderSource::fromText("uv.frag.glsl", R"(
in vec2 v_textureCoordinate;
out vec4 fragmentColor;
void main() { fragmentColor = vec4(v_textureCoordinate, 0.0, 1.0); }
)");
    return description;
}

} // namespace

TEST_CASE("A vertex array made from a mesh feeds the attributes the program reads, by name", "[renderer][vertexarray]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(64, 64);
    ShaderProgram program = device.createShaderProgram(textureCoordinateDescription());
    const VertexArray array = context.createVertexArray(test::fullScreenQuad(), program);
    CHECK(array.attributeMask() == ((1u << renderer::VertexAttributeLocation::Position) |
                                    (1u << renderer::VertexAttributeLocation::TextureCoordinate)));
    CHECK(array.indexed());
    CHECK(array.indexCount() == 6);
    CHECK(array.vertexCount() == 4);

    DrawCommand command;
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.framebuffer = &framebuffer;
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    const Image image = context.readPixels(&framebuffer);
    // Texture coordinates run 0..1 left to right and bottom to top (image rows are top down);
    // pixel centres sit half a pixel in: 0.5 / 64 * 255 = 2.
    INFO(test::describePixel(image, 0, 63) << ", " << test::describePixel(image, 63, 0));
    CHECK(test::pixelNear(image, 0, 63, {2, 2, 0, 255}, 1));
    CHECK(test::pixelNear(image, 63, 0, {253, 253, 0, 255}, 1));
    CHECK(test::pixelNear(image, 63, 63, {253, 2, 0, 255}, 1));
}

TEST_CASE("A program reading an attribute the mesh lacks is a clear error", "[renderer][vertexarray][errors]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgramDescription description;
    description.vertex = ShaderSource::fromText("n.vert.glsl", "in vec4 position;\nin vec3 normal;\nout vec3 v_n;\n"
                                                               "void main() { v_n = normal; gl_Position = position; }\n");
    description.fragment = ShaderSource::fromText("n.frag.glsl", "in vec3 v_n;\nout vec4 fragmentColor;\n"
                                                                 "void main() { fragmentColor = vec4(v_n, 1.0); }\n");
    description.name = "normals";
    ShaderProgram program = device.createShaderProgram(description);
    const Mesh mesh = test::fullScreenQuad(); // positions and texture coordinates, no normals
    REQUIRE_THROWS_WITH(context.createVertexArray(mesh, program),
                        Contains("'normals'") && Contains("'normal'") && Contains("no normals"));

    // An array made from the mesh alone lacks the normal too: drawing it names the attribute.
    const VertexArray array = context.createVertexArray(mesh);
    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    DrawCommand command;
    command.debugName = "lit quad";
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.framebuffer = &framebuffer;
    REQUIRE_THROWS_WITH(context.draw(command),
                        Contains("'lit quad'") && Contains("'normal' (location 1)") && Contains("does not supply"));

    // An attribute no mesh has at all.
    description.vertex = ShaderSource::fromText("w.vert.glsl", "in vec4 position;\nin float weight;\n"
                                                               "void main() { gl_Position = position * weight; }\n");
    description.fragment = test::solidColorDescription().fragment;
    ShaderProgram weighted = device.createShaderProgram(description);
    REQUIRE_THROWS_WITH(context.createVertexArray(mesh, weighted), Contains("'weight'"));
}

TEST_CASE("16- and 32-bit indices draw the same picture", "[renderer][vertexarray]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(32, 32);
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    const Mesh mesh = test::quad(-0.5, -0.5, 0.5, 0.5);

    Image images[2];
    const IndexType types[2] = {IndexType::UnsignedShort, IndexType::UnsignedInt};
    for (int i = 0; i < 2; ++i) {
        VertexArrayOptions options;
        options.indexType = types[i];
        const VertexArray array = context.createVertexArray(mesh, program, options);
        CHECK(array.indexType() == types[i]);
        context.clear(ClearState{}, &framebuffer);
        context.draw(test::makeCommand(array, program, framebuffer, {0.0f, 1.0f, 0.0f, 1.0f}));
        images[i] = context.readPixels(&framebuffer);
    }
    CHECK(test::pixelNear(images[0], 16, 16, {0, 255, 0, 255}));
    CHECK(test::pixelNear(images[0], 2, 2, {0, 0, 0, 255}));
    CHECK(images[0].pixels == images[1].pixels);

    // By default, the narrowest type that fits.
    CHECK(context.createVertexArray(mesh, program).indexType() == IndexType::UnsignedShort);
}

TEST_CASE("A mesh without indices draws its vertices in order", "[renderer][vertexarray]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(16, 16);
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    Mesh mesh;
    mesh.positions = {{-1.0, -1.0, 0.0}, {3.0, -1.0, 0.0}, {-1.0, 3.0, 0.0}}; // one triangle over the viewport
    const VertexArray array = context.createVertexArray(mesh, program);
    CHECK_FALSE(array.indexed());
    CHECK(array.vertexCount() == 3);
    context.clear(ClearState{}, &framebuffer);
    context.draw(test::makeCommand(array, program, framebuffer, {1.0f, 1.0f, 0.0f, 1.0f}));
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 15, 15, {255, 255, 0, 255}));
}

TEST_CASE("Bad meshes and out-of-range draws are clear errors", "[renderer][vertexarray][errors]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    Mesh mesh = test::quad(0, 0, 1, 1);
    mesh.indices.push_back(7);
    REQUIRE_THROWS_WITH(context.createVertexArray(mesh, program), Contains("index 6 is 7") && Contains("4 positions"));
    mesh.indices.pop_back();
    mesh.normals = {{0.0f, 0.0f, 1.0f}};
    REQUIRE_THROWS_WITH(context.createVertexArray(mesh), Contains("1 normals for 4 positions"));
    mesh.normals.clear();

    const VertexArray array = context.createVertexArray(mesh, program);
    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    DrawCommand command = test::makeCommand(array, program, framebuffer, glm::vec4(1.0f), "too many");
    command.first = 3;
    command.count = 6;
    REQUIRE_THROWS_WITH(context.draw(command), Contains("'too many'") && Contains("indices [3, 9)"));
    command.first = 7;
    command.count.reset();
    REQUIRE_THROWS_WITH(context.draw(command), Contains("first 7"));
}
