// Frame timings the scene sections share (GlMeasurements.h).

#include "GlMeasurements.h"

#include <orbis/core/Mesh.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/ShaderProgram.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/scene/Scene.h>
#include <orbis/world/ImageFile.h>

#include <chrono>

using namespace orbis::renderer;
using namespace orbis::scene;
using orbis::world::readImage;

namespace orbis::bench {

/// Average milliseconds per frame over `frames` frames after one warm-up frame.
double millisecondsPerFrame(Scene& scene, Context& context, int frames)
{
    scene.render(context);
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
        scene.render(context);
    }
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / frames;
}

/// A full-screen quad with the day texture, drawn `frames` times: the fill floor.
double fillFloorMilliseconds(Device& device, Context& context, int frames)
{
    ShaderProgramDescription description;
    description.name = "fill floor";
    description.vertex = ShaderSource::embedded("bench/textured_quad.vert.glsl");
    description.fragment = ShaderSource::embedded("bench/textured_quad.frag.glsl");
    ShaderProgram program = device.createShaderProgram(description);
    Mesh quad;
    quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.indices = {0, 1, 2, 0, 2, 3};
    VertexArray vertexArray = context.createVertexArray(quad, program);
    Texture2D texture = device.createTexture2D(readImage("/usr/share/xplanet/images/earth.jpg", 3), true);
    SamplerDescription samplerDescription;
    samplerDescription.minificationFilter = TextureMinificationFilter::LinearMipmapLinear;
    Sampler sampler = device.createSampler(samplerDescription);
    DrawCommand command;
    command.vertexArray = &vertexArray;
    command.shaderProgram = &program;
    command.textures.push_back({0, &texture, &sampler});
    command.renderState.depthTest.enabled = false;
    auto frame = [&] {
        context.clear(ClearState{});
        context.draw(command);
        context.finish();
    };
    frame();
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
        frame();
    }
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / frames;
}

} // namespace orbis::bench
