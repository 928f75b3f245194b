// A user's program of the renderer alone: a triangle drawn headless with its own embedded shaders,
// read back; no globe, no files, no window.
#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <cstdio>
#include <cstring>

int main()
{
    namespace renderer = orbis::renderer;
    renderer::Device device;
    renderer::Context& context = device.context();
    renderer::Framebuffer framebuffer = context.createFramebuffer(32, 32);
    context.setFramebuffer(&framebuffer);

    orbis::Mesh mesh; // covers the lower-left half of clip space, corner to corner
    mesh.positions = {{-1.0, -1.0, 0.0}, {1.0, -1.0, 0.0}, {-1.0, 1.0, 0.0}};
    mesh.indices = {0, 1, 2};
    renderer::ShaderProgramDescription description;
    description.vertex = renderer::ShaderSource::embedded("shaders/triangle.vert.glsl");
    description.fragment = renderer::ShaderSource::embedded("shaders/triangle.frag.glsl");
    renderer::ShaderProgram program = device.createShaderProgram(description);
    renderer::VertexArray vertexArray = context.createVertexArray(mesh, program);

    renderer::DrawCommand command;
    command.vertexArray = &vertexArray;
    command.shaderProgram = &program;
    command.uniforms.set("u_color", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    command.renderState.facetCulling.enabled = false;
    renderer::ClearState clear;
    clear.color = {1.0f, 1.0f, 1.0f, 1.0f};
    context.clear(clear);
    context.draw(command, renderer::SceneState{});
    const orbis::Image image = context.readPixels();
    const std::uint8_t* inside = image.pixel(4, image.height - 1 - 4);  // lower left
    const std::uint8_t* outside = image.pixel(27, image.height - 1 - 27); // upper right
    std::printf("inside %d %d %d, outside %d %d %d\n", inside[0], inside[1], inside[2], outside[0], outside[1],
                outside[2]);

    // Windows are the window component's: without it, asking for one says what to link.
    try {
        renderer::DeviceOptions options;
        options.backend = renderer::GlBackend::Window;
        renderer::Device window(options);
        std::printf("a window without the window component\n");
    } catch (const orbis::Error& error) {
        std::printf("window: %s\n", error.what());
    }
    return 0;
}
