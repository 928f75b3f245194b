// With GL checks on, every GL call is followed by glGetError, and KHR_debug messages go to stderr.
#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <cstdio>
#include <unistd.h>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

/// Collects what is written to stderr (file descriptor 2) while it lives.
class StderrCapture {
public:
    StderrCapture()
    {
        std::fflush(stderr);
        _saved = dup(2);
        _file = std::tmpfile();
        dup2(fileno(_file), 2);
    }
    ~StderrCapture() { restore(); }
    std::string text()
    {
        restore();
        std::string result;
        std::rewind(_file);
        char buffer[512];
        std::size_t n = 0;
        while ((n = std::fread(buffer, 1, sizeof buffer, _file)) > 0) {
            result.append(buffer, n);
        }
        return result;
    }

private:
    void restore()
    {
        if (_saved >= 0) {
            std::fflush(stderr);
            dup2(_saved, 2);
            close(_saved);
            _saved = -1;
        }
    }
    int _saved = -1;
    std::FILE* _file = nullptr;
};

/// A program whose geometry shader takes triangles: drawing points with it is a GL error that the
/// renderer does not check for itself (GL_INVALID_OPERATION from the draw call).
ShaderProgramDescription trianglesGeometryDescription()
{
    ShaderProgramDescription description = test::solidColorDescription();
    description.name = "triangles in";
    description.geometry = ShaderSource::fromText("triangles.geom.glsl", R"(
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
void main()
{
    for (int i = 0; i < 3; ++i) { gl_Position = gl_in[i].gl_Position; EmitVertex(); }
    EndPrimitive();
}
)");
    return description;
}

void drawPointsThroughTriangleShader(Device& device)
{
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(trianglesGeometryDescription());
    Mesh mesh;
    mesh.positions = {{0.0, 0.0, 0.0}};
    const VertexArray array = context.createVertexArray(mesh, program);
    Framebuffer framebuffer = context.createFramebuffer(4, 4);
    DrawCommand command = test::makeCommand(array, program, framebuffer, glm::vec4(1.0f), "points into triangles");
    command.primitiveType = PrimitiveType::Points;
    context.draw(command);
}

} // namespace

TEST_CASE("With GL checks on, a GL error throws naming the GL function, and KHR_debug reports it",
          "[renderer][glchecks]")
{
    DeviceOptions options;
    options.glChecks = true;
    Device device(options);
    CHECK(device.info().glChecks);
    INFO("KHR_debug: " << device.info().khrDebug);

    StderrCapture capture;
    REQUIRE_THROWS_WITH(drawPointsThroughTriangleShader(device),
                        Contains("GL_INVALID_OPERATION") && Contains("glDrawArrays"));
    const std::string messages = capture.text();
    INFO(messages);
    if (device.info().khrDebug) {
        CHECK_THAT(messages, Contains("orbis: GL error"));
    }
}

TEST_CASE("Without GL checks the same mistake is not looked for", "[renderer][glchecks]")
{
    DeviceOptions options;
    options.glChecks = false;
    Device device(options);
    CHECK_FALSE(device.info().glChecks);
    CHECK_NOTHROW(drawPointsThroughTriangleShader(device));
}

TEST_CASE("With GL checks on, ordinary work raises no GL error", "[renderer][glchecks]")
{
    const GlBackend backend = GENERATE(GlBackend::Egl, GlBackend::OsMesa);
    DeviceOptions options;
    options.backend = backend;
    options.glChecks = true;
    Device device(options);
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    const VertexArray array = context.createVertexArray(test::fullScreenQuad(), program);
    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    DrawCommand command = test::makeCommand(array, program, framebuffer, {1, 0, 0, 1});
    command.renderState.blending = Blending::alphaBlending();
    command.renderState.stencilTest.enabled = true;
    command.renderState.scissorTest = {true, {0, 0, 4, 4}};
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    context.resetState();
    context.draw(command);
    Texture2D texture = device.createTexture2D({4, 4, TextureFormat::RGBA32F, true});
    texture.generateMipmaps();
    CHECK(texture.copyToSystemMemory(2).size() == 16);
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 1, 6, {255, 0, 0, 255}));
}
