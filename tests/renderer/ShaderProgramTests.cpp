#include "RendererTestSupport.h"
#include "TempFiles.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/EmbeddedShaders.h>

#include <catch2/catch.hpp>

#include <algorithm>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

ShaderProgramDescription withFragment(std::string name, std::string text)
{
    ShaderProgramDescription description = test::solidColorDescription();
    description.fragment = ShaderSource::fromText(std::move(name), std::move(text));
    return description;
}

std::string errorOf(Device& device, const ShaderProgramDescription& description)
{
    try {
        device.createShaderProgram(description);
    } catch (const Error& error) {
        return error.what();
    }
    return "(no error)";
}

} // namespace

TEST_CASE("Every embedded shader folder is found by its paths", "[renderer][shader]")
{
    const auto paths = embeddedShaderPaths();
    CHECK(std::is_sorted(paths.begin(), paths.end()));
    CHECK(std::find(paths.begin(), paths.end(), "renderer/builtin/constants.glsl") != paths.end());
    REQUIRE(embeddedShader("examples/triangle/triangle.frag.glsl"));
    CHECK_THAT(std::string(*embeddedShader("examples/triangle/triangle.frag.glsl")), Contains("u_color"));
    CHECK_FALSE(embeddedShader("no/such/file.glsl"));
    REQUIRE_THROWS_WITH(ShaderSource::embedded("no/such/file.glsl"), Contains("shaders/no/such/file.glsl"));
}

TEST_CASE("ShaderSource::fromFile reads a shader at run time, and its errors name the file", "[renderer][shader]")
{
    const test::TempDirectory folder;
    const std::filesystem::path path = folder.write("green.frag.glsl", "#version 330 core\nout vec4 fragmentColor;\n"
                                                                       "void main() { fragmentColor = vec4(0, 1, 0, 1); }\n");
    const ShaderSource source = ShaderSource::fromFile(path);
    CHECK(source.name == path.string());
    CHECK_THAT(source.text, Contains("vec4(0, 1, 0, 1)"));
    ShaderProgramDescription description = test::solidColorDescription();
    description.fragment = source;
    CHECK_NOTHROW(test::sharedDevice().createShaderProgram(description));

    // A compile error in a file read at run time names that file and the line.
    description.fragment = ShaderSource::fromFile(folder.write("broken.frag.glsl", "out vec4 c;\nvoid main() { c = nope; }\n"));
    CHECK_THAT(errorOf(test::sharedDevice(), description), Contains((folder.path() / "broken.frag.glsl").string() + ":2:"));

    const std::string missing = test::errorMessage([&] { ShaderSource::fromFile(folder.path() / "missing.glsl"); });
    CHECK_THAT(missing, Contains((folder.path() / "missing.glsl").string() + ": cannot open the shader file"));
    CHECK_THAT(missing, Contains("No such file"));
    const std::string directory = test::errorMessage([&] { ShaderSource::fromFile(folder.path()); });
    CHECK_THAT(directory, Contains(folder.path().string() + ": cannot"));
}

TEST_CASE("A compile error names the embedded file and the line", "[renderer][shader][errors]")
{
    Device& device = test::sharedDevice();
    ShaderProgramDescription description = test::solidColorDescription();
    description.fragment = ShaderSource::embedded("tests/compile-error.frag.glsl");
    const std::string message = errorOf(device, description);
    INFO(message);
    CHECK_THAT(message, Contains("shaders/tests/compile-error.frag.glsl:6:"));
    CHECK_THAT(message, Contains("undeclaredColor"));
    CHECK_THAT(message, Contains("fragment shader"));
}

TEST_CASE("Compile errors keep their line numbers with defines and without the library", "[renderer][shader][errors]")
{
    Device& device = test::sharedDevice();
    const bool library = GENERATE(true, false);
    ShaderProgramDescription description = withFragment("my/broken.frag.glsl", "out vec4 fragmentColor;\n"
                                                                                 "void main()\n"
                                                                                 "{\n"
                                                                                 "    fragmentColor = oops;\n"
                                                                                 "}\n");
    description.builtinLibrary = library;
    description.defines = {{"FIRST", "1"}, {"SECOND", "2"}};
    const std::string message = errorOf(device, description);
    INFO(message);
    CHECK_THAT(message, Contains("my/broken.frag.glsl:4:"));
}

TEST_CASE("A vertex shader error names the vertex file", "[renderer][shader][errors]")
{
    Device& device = test::sharedDevice();
    ShaderProgramDescription description = test::solidColorDescription();
    description.vertex = ShaderSource::fromText("my/broken.vert.glsl", "in vec4 position;\nvoid main() { gl_Position = position * missing; }\n");
    const std::string message = errorOf(device, description);
    INFO(message);
    CHECK_THAT(message, Contains("vertex shader my/broken.vert.glsl"));
    CHECK_THAT(message, Contains("my/broken.vert.glsl:2:"));
}

TEST_CASE("A link error names the program and its files", "[renderer][shader][errors]")
{
    Device& device = test::sharedDevice();
    ShaderProgramDescription description;
    description.name = "mismatch";
    description.vertex = ShaderSource::fromText("a.vert.glsl", "in vec4 position;\nout vec3 v_value;\n"
                                                               "void main() { v_value = position.xyz; gl_Position = position; }\n");
    description.fragment = ShaderSource::fromText("a.frag.glsl", "in vec4 v_value;\nout vec4 fragmentColor;\n"
                                                                 "void main() { fragmentColor = v_value; }\n");
    const std::string message = errorOf(device, description);
    INFO(message);
    CHECK_THAT(message, Contains("'mismatch'") && Contains("a.vert.glsl") && Contains("a.frag.glsl") &&
                            Contains("does not link"));
}

TEST_CASE("Reflection lists the active attributes and uniforms with their types", "[renderer][shader]")
{
    Device& device = test::sharedDevice();
    ShaderProgramDescription description;
    description.name = "reflection";
    description.vertex = ShaderSource::fromText("r.vert.glsl", R"(
in vec4 position;
in vec2 textureCoordinate;
in float custom;
out vec2 v_uv;
uniform mat4 og_modelViewProjectionMatrix;
uniform float u_scale;
void main() { v_uv = textureCoordinate * custom; gl_Position = og_modelViewProjectionMatrix * position * u_scale; }
)");
    description.fragment = ShaderSource::fromText("r.frag.glsl", R"(
in vec2 v_uv;
out vec4 fragmentColor;
uniform vec4 u_color;
uniform sampler2D og_texture1;
uniform bool u_flag;
uniform int u_unused; // declared, never read: the compiler drops it
void main() { fragmentColor = u_flag ? u_color * texture(og_texture1, v_uv) : vec4(og_pi); }
)");
    const ShaderProgram program = device.createShaderProgram(description);

    const ShaderVertexAttribute* position = program.findVertexAttribute("position");
    REQUIRE(position);
    CHECK(position->location == renderer::VertexAttributeLocation::Position);
    CHECK(position->type == UniformType::FloatVec4);
    REQUIRE(program.findVertexAttribute("textureCoordinate"));
    CHECK(program.findVertexAttribute("textureCoordinate")->location == renderer::VertexAttributeLocation::TextureCoordinate);
    REQUIRE(program.findVertexAttribute("custom"));
    CHECK(program.findVertexAttribute("custom")->type == UniformType::Float);
    CHECK(program.vertexAttributes().size() == 3);

    auto find = [&](const char* name) -> const ShaderUniform* {
        for (const ShaderUniform& u : program.uniforms()) {
            if (u.name == name) {
                return &u;
            }
        }
        return nullptr;
    };
    REQUIRE(find("og_modelViewProjectionMatrix"));
    CHECK(find("og_modelViewProjectionMatrix")->automatic);
    CHECK(find("og_modelViewProjectionMatrix")->type == UniformType::FloatMat4);
    REQUIRE(find("u_color"));
    CHECK_FALSE(find("u_color")->automatic);
    CHECK(find("u_color")->type == UniformType::FloatVec4);
    REQUIRE(find("og_texture1"));
    CHECK(find("og_texture1")->type == UniformType::Sampler2D);
    CHECK(find("u_flag")->type == UniformType::Bool);
    CHECK(find("u_scale")->type == UniformType::Float);
    CHECK_FALSE(program.hasUniform("u_unused"));
}

TEST_CASE("Uniform setters check names and types and skip unchanged values", "[renderer][shader]")
{
    Device& device = test::sharedDevice();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    CHECK(program.setUniform("u_color", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)));
    CHECK_FALSE(program.setUniform("u_color", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)));
    CHECK(program.setUniform(program.uniformIndex("u_color"), glm::vec4(0.0f, 1.0f, 0.0f, 1.0f)));
    REQUIRE_THROWS_WITH(program.setUniform("u_colour", glm::vec4(1.0f)),
                        Contains("no active uniform u_colour") && Contains("u_color"));
    REQUIRE_THROWS_WITH(program.setUniform("u_color", glm::vec3(1.0f)),
                        Contains("u_color is vec4") && Contains("vec3"));
    REQUIRE_THROWS_WITH(program.setUniform("og_modelViewProjectionMatrix", glm::mat4(1.0f)),
                        Contains("automatic"));
}

TEST_CASE("The built-in GLSL library is prepended on request", "[renderer][shader]")
{
    Device& device = test::sharedDevice();
    ShaderProgramDescription description =
        withFragment("pi.frag.glsl", "out vec4 fragmentColor;\nvoid main() { fragmentColor = vec4(og_oneOverPi * og_pi); }\n");
    CHECK(device.createShaderProgram(description).valid());
    description.builtinLibrary = false;
    const std::string message = errorOf(device, description);
    INFO(message);
    CHECK_THAT(message, Contains("pi.frag.glsl:2:") && Contains("og_"));
}

TEST_CASE("A uniform with the og_ prefix that is not automatic is a clear error", "[renderer][shader][errors]")
{
    Device& device = test::sharedDevice();
    const std::string message = errorOf(
        device, withFragment("og.frag.glsl", "out vec4 fragmentColor;\nuniform vec4 og_colour;\n"
                                             "void main() { fragmentColor = og_colour; }\n"));
    INFO(message);
    CHECK_THAT(message, Contains("og_colour") && Contains("og_modelViewProjectionMatrix"));

    const std::string typeMessage = errorOf(
        device, withFragment("og.frag.glsl", "out vec4 fragmentColor;\nuniform vec4 og_time;\n"
                                             "void main() { fragmentColor = og_time; }\n"));
    INFO(typeMessage);
    CHECK_THAT(typeMessage, Contains("og_time must be float"));
}

TEST_CASE("A version line in a source is replaced, keeping line numbers", "[renderer][shader]")
{
    Device& device = test::sharedDevice();
    const std::string message = errorOf(
        device, withFragment("v.frag.glsl", "#version 150\nout vec4 fragmentColor;\nvoid main() { fragmentColor = bad; }\n"));
    INFO(message);
    CHECK_THAT(message, Contains("v.frag.glsl:3:"));
}

TEST_CASE("A geometry shader stage turns points into quads", "[renderer][shader]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgramDescription description = test::solidColorDescription();
    description.name = "point sprites";
    description.geometry = ShaderSource::fromText("sprite.geom.glsl", R"(
layout(points) in;
layout(triangle_strip, max_vertices = 4) out;
uniform float u_halfSize;
void main()
{
    vec4 c = gl_in[0].gl_Position;
    gl_Position = c + vec4(-u_halfSize, -u_halfSize, 0.0, 0.0); EmitVertex();
    gl_Position = c + vec4( u_halfSize, -u_halfSize, 0.0, 0.0); EmitVertex();
    gl_Position = c + vec4(-u_halfSize,  u_halfSize, 0.0, 0.0); EmitVertex();
    gl_Position = c + vec4( u_halfSize,  u_halfSize, 0.0, 0.0); EmitVertex();
    EndPrimitive();
}
)");
    ShaderProgram program = device.createShaderProgram(description);
    CHECK(program.hasUniform("u_halfSize"));
    Mesh mesh;
    mesh.primitiveType = PrimitiveType::Points;
    mesh.positions = {{-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0}};
    const VertexArray array = context.createVertexArray(mesh, program);
    Framebuffer framebuffer = context.createFramebuffer(16, 16);
    DrawCommand command = test::makeCommand(array, program, framebuffer, {0, 1, 1, 1});
    command.primitiveType = PrimitiveType::Points;
    command.uniforms.set("u_halfSize", 0.25f);
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    const Image image = context.readPixels(&framebuffer);
    CHECK(test::pixelNear(image, 4, 11, {0, 255, 255, 255})); // around (-0.5, -0.5)
    CHECK(test::pixelNear(image, 11, 4, {0, 255, 255, 255})); // around (0.5, 0.5)
    CHECK(test::pixelNear(image, 11, 11, {0, 0, 0, 255}));

    description.geometry->text = "layout(points) in;\nlayout(points, max_vertices = 1) out;\nvoid main() { bad }\n";
    description.geometry->name = "broken.geom.glsl";
    REQUIRE_THROWS_WITH(device.createShaderProgram(description),
                        Contains("geometry shader broken.geom.glsl") && Contains("broken.geom.glsl:3:"));
}

TEST_CASE("Uniform arrays are set on the program, each element reaching the shader, unchanged ones not sent", "[renderer][shader][uniforms]")
{
    ShaderProgramDescription description = test::solidColorDescription();
    description.name = "palette";
    description.fragment = ShaderSource::fromText("test/palette.frag.glsl", R"(
out vec4 fragmentColor;
uniform vec4 u_palette[3];
uniform float u_weights[3];
void main()
{
    int i = min(int(gl_FragCoord.x), 2); // pixel column 0, 1, 2
    fragmentColor = u_palette[i] * u_weights[i];
}
)");
    test::QuadFixture quad(3, description);
    auto& [device, context, framebuffer, program, array] = quad;
    DrawCommand command;
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.framebuffer = &framebuffer;

    REQUIRE(program.uniforms().size() >= 2);
    REQUIRE_THROWS_WITH(context.draw(command), Contains("never given a value") && Contains("u_palette (vec4)"));

    const glm::vec4 palette[] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
    const float weights[] = {1.0f, 0.5f, 1.0f};
    REQUIRE(program.setUniformArray<glm::vec4>("u_palette", palette));
    REQUIRE(program.setUniformArray<float>("u_weights", weights));
    context.clear(ClearState{}, &framebuffer);
    context.resetStatistics();
    context.draw(command);
    CHECK(context.statistics().uniformUploads >= 2); // the two arrays (and the matrix)
    Image image = context.readPixels(&framebuffer);
    CHECK(test::pixelNear(image, 0, 1, {255, 0, 0, 255}));
    CHECK(test::pixelNear(image, 1, 1, {0, 128, 0, 128}));
    CHECK(test::pixelNear(image, 2, 1, {0, 0, 255, 255}));

    // The same values: nothing to send.
    REQUIRE_FALSE(program.setUniformArray<glm::vec4>("u_palette", palette));
    context.resetStatistics();
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    CHECK(context.statistics().uniformUploads == 0);

    // A shorter span sets the leading elements and keeps the rest; a longer one is cut to the size.
    const glm::vec4 white[] = {{1, 1, 1, 1}};
    REQUIRE(program.setUniformArray<glm::vec4>("u_palette", white));
    const float more[] = {1.0f, 1.0f, 0.0f, 7.0f, 7.0f};
    REQUIRE(program.setUniformArray<float>("u_weights", more));
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    image = context.readPixels(&framebuffer);
    CHECK(test::pixelNear(image, 0, 1, {255, 255, 255, 255}));
    CHECK(test::pixelNear(image, 1, 1, {0, 255, 0, 255}));
    CHECK(test::pixelNear(image, 2, 1, {0, 0, 0, 0}));

    // Errors name the uniform and what was wrong.
    command.uniforms.set("u_weights", 1.0f);
    REQUIRE_THROWS_WITH(context.draw(command),
                        Contains("u_weights is an array of 3 float; set it with ShaderProgram::setUniformArray"));
    command.uniforms.clear();
    REQUIRE_THROWS_WITH(program.setUniformArray<float>("u_palette", weights),
                        Contains("u_palette is an array of vec4, not of float"));
    REQUIRE_THROWS_WITH(program.setUniformArray<glm::vec4>("u_palette", std::span<const glm::vec4>()),
                        Contains("u_palette: no values given"));
    REQUIRE_THROWS_WITH(program.setUniformArray<float>("u_missing", weights), Contains("u_missing is not an active uniform"));
    const glm::mat4 identity[] = {glm::mat4(1.0f)};
    REQUIRE_THROWS_WITH(program.setUniformArray<glm::mat4>("og_modelViewProjectionMatrix", identity),
                        Contains("og_modelViewProjectionMatrix is not an array"));
}
