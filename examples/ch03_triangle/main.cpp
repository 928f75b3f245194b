// Chapter 3's first example: one triangle, drawn headless through the renderer layer and written
// to a PNG. Usage: ch03_triangle [out.png] [--backend egl|osmesa] [--size N]
#include <orbis/renderer/Device.h>
#include <orbis/world/ImageFile.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

int main(int argc, char** argv)
{
    const auto start = std::chrono::steady_clock::now();
    std::string output = "ch03_triangle.png";
    orbis::renderer::DeviceOptions options;
    int size = 256;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--backend") == 0 && i + 1 < argc) {
            const std::string name = argv[++i];
            options.backend = name == "osmesa" ? orbis::renderer::GlBackend::OsMesa : orbis::renderer::GlBackend::Egl;
        } else if (std::strcmp(argv[i], "--size") == 0 && i + 1 < argc) {
            size = std::atoi(argv[++i]);
        } else {
            output = argv[i];
        }
    }
    try {
        orbis::renderer::Device device(options);
        orbis::renderer::Context& context = device.context();
        orbis::renderer::Framebuffer framebuffer = context.createFramebuffer(size, size);
        context.setFramebuffer(&framebuffer);

        // The triangle of the book, in the xz plane, seen from -y.
        orbis::Mesh mesh;
        mesh.positions = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
        mesh.indices = {0, 1, 2};

        orbis::renderer::ShaderProgramDescription description;
        description.name = "triangle";
        description.vertex = orbis::renderer::ShaderSource::embedded("examples/triangle/triangle.vert.glsl");
        description.fragment = orbis::renderer::ShaderSource::embedded("examples/triangle/triangle.frag.glsl");
        orbis::renderer::ShaderProgram program = device.createShaderProgram(description);
        orbis::renderer::VertexArray vertexArray = context.createVertexArray(mesh, program);

        orbis::renderer::SceneState scene;
        scene.cameraEye = {0.3, -2.0, 0.3};
        scene.viewMatrix = glm::lookAt(scene.cameraEye, glm::dvec3(0.3, 0.0, 0.3), glm::dvec3(0.0, 0.0, 1.0));
        scene.nearDistance = 0.1;
        scene.farDistance = 10.0;
        scene.projectionMatrix = glm::perspective(glm::radians(45.0), 1.0, scene.nearDistance, scene.farDistance);

        orbis::renderer::DrawCommand command;
        command.debugName = "triangle";
        command.vertexArray = &vertexArray;
        command.shaderProgram = &program;
        command.uniforms.set("u_color", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
        command.renderState.facetCulling.enabled = false; // seen from behind, as in the book

        orbis::renderer::ClearState clear;
        clear.color = {1.0f, 1.0f, 1.0f, 1.0f};
        context.clear(clear);
        context.draw(command, scene);
        orbis::world::writePng(context.readPixels(), output);

        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("%s: %d x %d, %s, %s; %.1f ms from main to PNG\n", output.c_str(), size, size,
                    device.info().backendDescription.c_str(), device.info().renderer.c_str(), seconds * 1e3);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "ch03_triangle: %s\n", error.what());
        return 1;
    }
    return 0;
}
