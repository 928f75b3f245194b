#include "RendererTestSupport.h"

#include <memory>
#include <sstream>

using namespace orbis::renderer;

namespace orbis::test {

GoldenTolerance exactOnLlvmpipe(const Device& device, const GoldenTolerance& elsewhere)
{
    return device.info().renderer.find("llvmpipe") != std::string::npos ? GoldenTolerance{2, 0.0} : elsewhere;
}

Device& sharedDevice()
{
    static std::unique_ptr<Device> device = std::make_unique<Device>();
    if (!device->context().isCurrent()) {
        device->context().makeCurrent();
    }
    return *device;
}

Mesh quad(double x0, double y0, double x1, double y1, double z)
{
    Mesh mesh;
    mesh.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    mesh.textureCoordinates = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

ShaderProgramDescription solidColorDescription()
{
    ShaderProgramDescription description;
    description.name = "solid colour";
    description.vertex = ShaderSource::fromText("test/solid.vert.glsl", R"(
in vec4 position;
uniform mat4 og_modelViewProjectionMatrix;
void main() { gl_Position = og_modelViewProjectionMatrix * position; }
)");
    description.fragment = ShaderSource::fromText("test/solid.frag.glsl", R"(
out vec4 fragmentColor;
uniform vec4 u_color;
void main() { fragmentColor = u_color; }
)");
    return description;
}

ShaderProgramDescription texturedDescription()
{
    ShaderProgramDescription description;
    description.name = "textured";
    description.vertex = ShaderSource::fromText("test/textured.vert.glsl", R"(
in vec4 position;
in vec2 textureCoordinate;
out vec2 v_textureCoordinate;
uniform float u_scale;
void main() { v_textureCoordinate = textureCoordinate * u_scale; gl_Position = position; }
)");
    description.fragment = ShaderSource::fromText("test/textured.frag.glsl", R"(
in vec2 v_textureCoordinate;
out vec4 fragmentColor;
uniform sampler2D og_texture0;
void main() { fragmentColor = texture(og_texture0, v_textureCoordinate); }
)");
    return description;
}

QuadFixture::QuadFixture(int size, const ShaderProgramDescription& description)
    : device(sharedDevice()),
      context(device.context()),
      framebuffer(context.createFramebuffer(size, size)),
      program(device.createShaderProgram(description)),
      array(context.createVertexArray(fullScreenQuad(), program))
{
}

glm::ivec4 pixelAt(const Image& image, int x, int y)
{
    const std::uint8_t* p = image.pixel(x, y);
    return {p[0], p[1], p[2], image.channels == 4 ? p[3] : 255};
}

bool pixelNear(const Image& image, int x, int y, const glm::ivec4& expected, int tolerance)
{
    const glm::ivec4 p = pixelAt(image, x, y);
    for (int c = 0; c < 4; ++c) {
        if (std::abs(p[c] - expected[c]) > tolerance) {
            return false;
        }
    }
    return true;
}

std::string describePixel(const Image& image, int x, int y)
{
    const glm::ivec4 p = pixelAt(image, x, y);
    std::ostringstream text;
    text << "pixel (" << x << ", " << y << ") = (" << p.r << ", " << p.g << ", " << p.b << ", " << p.a << ")";
    return text.str();
}

DrawCommand makeCommand(const VertexArray& array, ShaderProgram& program, Framebuffer& framebuffer,
                        const glm::vec4& color, const char* name)
{
    DrawCommand command;
    command.debugName = name;
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.framebuffer = &framebuffer;
    command.uniforms.set("u_color", color);
    return command;
}

} // namespace orbis::test
