// Loading on a worker thread (book chapter 10): a shared context creates resources there, a fence
// tells the rendering thread when they are ready.
#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <future>
#include <thread>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

struct Loaded {
    Texture2D texture;
    std::shared_ptr<ShaderProgram> program;
    Fence fence;
};

} // namespace

TEST_CASE("A texture and a program made on a worker thread are drawn by the main context", "[renderer][worker]")
{
    const GlBackend backend = GENERATE(GlBackend::Egl, GlBackend::OsMesa);
    DeviceOptions options;
    options.backend = backend;
    Device device(options);
    INFO(device.info().backendDescription);

    std::promise<Loaded> promise;
    std::future<Loaded> future = promise.get_future();
    std::thread worker([&] {
        try {
            std::unique_ptr<Context> context = device.createSharedContext();
            context->makeCurrent();
            CHECK_FALSE(device.context().isCurrent()); // the main context stays with the main thread
            Image image(2, 2, 4);
            image.pixels = {255, 0, 0, 255, 0, 255, 0, 255,    // top: red, green
                            0, 0, 255, 255, 255, 255, 0, 255}; // bottom: blue, yellow
            Loaded loaded{device.createTexture2D(image), device.shaderCache().get(test::texturedDescription()),
                          device.createFence()};
            context->flush();
            context->releaseCurrent();
            promise.set_value(std::move(loaded));
        } catch (...) {
            promise.set_exception(std::current_exception());
        }
    });
    Loaded loaded = future.get();
    worker.join();

    // The GPU of the main context waits for the worker's commands before using their results.
    loaded.fence.serverWait();
    CHECK(loaded.fence.clientWait() == Fence::Status::Signaled);
    CHECK(loaded.fence.signaled());
    CHECK(device.shaderCache().get(test::texturedDescription()) == loaded.program); // compiled once, on the worker

    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(16, 16);
    const VertexArray array = context.createVertexArray(test::fullScreenQuad(), *loaded.program);
    SamplerDescription nearest;
    nearest.minificationFilter = TextureMinificationFilter::Nearest;
    nearest.magnificationFilter = TextureMagnificationFilter::Nearest;
    const Sampler sampler = device.createSampler(nearest);
    DrawCommand command;
    command.debugName = "worker texture";
    command.vertexArray = &array;
    command.shaderProgram = loaded.program.get();
    command.framebuffer = &framebuffer;
    command.uniforms.set("u_scale", 1.0f);
    command.textures.push_back({0, &loaded.texture, &sampler});
    context.clear(ClearState{}, &framebuffer);
    context.draw(command);
    const Image image = context.readPixels(&framebuffer);
    CHECK(test::pixelNear(image, 2, 2, {255, 0, 0, 255}));
    CHECK(test::pixelNear(image, 13, 2, {0, 255, 0, 255}));
    CHECK(test::pixelNear(image, 2, 13, {0, 0, 255, 255}));
    CHECK(test::pixelNear(image, 13, 13, {255, 255, 0, 255}));
}

TEST_CASE("Objects that belong to one context are refused by another", "[renderer][worker][errors]")
{
    test::QuadFixture quad(4);
    auto& [device, main, framebuffer, program, array] = quad;

    std::unique_ptr<Context> shared = device.createSharedContext();
    CHECK_FALSE(shared->isCurrent());
    REQUIRE_THROWS_WITH(shared->draw(test::makeCommand(array, program, framebuffer, glm::vec4(1.0f))),
                        Contains("not current"));
    shared->makeCurrent();
    Framebuffer sharedTarget = shared->createFramebuffer(4, 4);
    REQUIRE_THROWS_WITH(shared->draw(test::makeCommand(array, program, sharedTarget, glm::vec4(1.0f))),
                        Contains("vertex array belongs to another context"));
    REQUIRE_THROWS_WITH(shared->clear(ClearState{}, &framebuffer), Contains("framebuffer belongs to another context"));
    // The program, a shared object, works in the shared context with an array made there.
    const VertexArray sharedArray = shared->createVertexArray(test::fullScreenQuad(), program);
    shared->clear(ClearState{}, &sharedTarget);
    shared->draw(test::makeCommand(sharedArray, program, sharedTarget, {1, 0, 1, 1}));
    CHECK(test::pixelNear(shared->readPixels(&sharedTarget), 1, 1, {255, 0, 255, 255}));
    main.makeCurrent();
}

TEST_CASE("A fence is signalled once the commands before it have run", "[renderer][fence]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(64, 64);
    context.clear(ClearState{}, &framebuffer);
    Fence fence = device.createFence();
    CHECK(fence.valid());
    CHECK(fence.clientWait(std::chrono::seconds(10)) == Fence::Status::Signaled);
    CHECK(fence.signaled());
    Fence moved = std::move(fence);
    CHECK(moved.signaled());
    CHECK_FALSE(fence.valid()); // NOLINT(bugprone-use-after-move)
    REQUIRE_THROWS_WITH(fence.signaled(), Contains("empty"));
}
