#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>
#include <orbis/world/ImageFile.h>

#include <catch2/catch.hpp>

#include <filesystem>

#include <unistd.h>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

/// A new width x height framebuffer on the shared device, cleared to `color`.
Framebuffer clearedFramebuffer(int width, int height, const glm::vec4& color)
{
    Context& context = test::sharedDevice().context();
    Framebuffer framebuffer = context.createFramebuffer(width, height);
    ClearState clear;
    clear.color = color;
    context.clear(clear, &framebuffer);
    return framebuffer;
}

} // namespace

TEST_CASE("A framebuffer of any size clears to the colour and reads back", "[renderer][framebuffer]")
{
    const auto [width, height] = GENERATE(table<int, int>({{1, 1}, {37, 19}, {300, 7}, {64, 64}}));
    Context& context = test::sharedDevice().context();
    Framebuffer framebuffer = clearedFramebuffer(width, height, {0.2f, 0.4f, 0.6f, 0.8f});
    CHECK(framebuffer.width() == width);
    CHECK(framebuffer.height() == height);
    const Image image = context.readPixels(&framebuffer);
    REQUIRE(image.width == width);
    REQUIRE(image.height == height);
    // 0.2 * 255 = 51, 0.4 * 255 = 102, ...
    CHECK(test::pixelNear(image, 0, 0, {51, 102, 153, 204}));
    CHECK(test::pixelNear(image, width - 1, height - 1, {51, 102, 153, 204}));
}

TEST_CASE("readPixels returns the rows top to bottom", "[renderer][framebuffer]")
{
    Context& context = test::sharedDevice().context();
    Framebuffer framebuffer = clearedFramebuffer(16, 16, {0.0f, 0.0f, 1.0f, 1.0f}); // blue
    ClearState redBottom; // GL counts rows from the bottom: the scissor keeps the lower 4 rows
    redBottom.color = {1.0f, 0.0f, 0.0f, 1.0f};
    redBottom.scissorTest = {true, {0, 0, 16, 4}};
    context.clear(redBottom, &framebuffer);
    const Image image = context.readPixels(&framebuffer);
    INFO(test::describePixel(image, 0, 0) << ", " << test::describePixel(image, 0, 15));
    CHECK(test::pixelNear(image, 0, 0, {0, 0, 255, 255}));
    CHECK(test::pixelNear(image, 0, 11, {0, 0, 255, 255}));
    CHECK(test::pixelNear(image, 0, 12, {255, 0, 0, 255}));
    CHECK(test::pixelNear(image, 15, 15, {255, 0, 0, 255}));
}

TEST_CASE("A framebuffer writes a PNG that reads back the same", "[renderer][framebuffer]")
{
    Context& context = test::sharedDevice().context();
    Framebuffer framebuffer = clearedFramebuffer(8, 5, {1.0f, 0.5f, 0.0f, 1.0f});
    const Image image = context.readPixels(&framebuffer);
    const auto path = std::filesystem::temp_directory_path() /
                      ("orbis-framebuffer-test-" + std::to_string(getpid()) + ".png"); // parallel runs apart
    writePng(image, path);
    const Image back = readImage(path);
    std::filesystem::remove(path);
    CHECK(back.width == 8);
    CHECK(back.height == 5);
    CHECK(back.pixels == image.pixels);
}

TEST_CASE("An incomplete framebuffer is a clear error, never a crash", "[renderer][framebuffer][errors]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer empty = context.createFramebuffer();
    REQUIRE_THROWS_WITH(context.clear(ClearState{}, &empty),
                        Contains("incomplete") && Contains("MISSING_ATTACHMENT"));
    REQUIRE_THROWS_WITH(context.readPixels(&empty), Contains("incomplete"));

    auto depth = std::make_shared<Texture2D>(device.createTexture2D({8, 8, TextureFormat::Depth24}));
    auto color = std::make_shared<Texture2D>(device.createTexture2D({8, 8, TextureFormat::RGBA8}));
    REQUIRE_THROWS_WITH(empty.setColorAttachment(0, depth), Contains("Depth24") && Contains("colour attachment"));
    REQUIRE_THROWS_WITH(empty.setDepthAttachment(color), Contains("RGBA8") && Contains("depth attachment"));
    REQUIRE_THROWS_WITH(empty.setColorAttachment(8, color), Contains("index 8"));

    // Once attached, the same framebuffer becomes complete.
    empty.setColorAttachment(0, color);
    context.clear(ClearState{}, &empty);
    REQUIRE_THROWS_WITH(context.readPixels(&empty, 1), Contains("no colour attachment 1"));
}

TEST_CASE("Drawing or clearing with no framebuffer on a headless context is a clear error",
          "[renderer][framebuffer][errors][headless]")
{
    Context& context = test::sharedDevice().context();
    context.setFramebuffer(nullptr);
    REQUIRE_THROWS_WITH(context.clear(ClearState{}), Contains("no framebuffer"));
    REQUIRE_THROWS_WITH(context.readPixels(), Contains("no framebuffer"));
}

TEST_CASE("A colour attachment can be read as a texture after rendering into it", "[renderer][framebuffer]")
{
    const Framebuffer framebuffer = clearedFramebuffer(4, 4, {0.0f, 1.0f, 0.0f, 1.0f});
    const Image image = framebuffer.colorAttachment(0)->copyToImage();
    CHECK(test::pixelNear(image, 3, 3, {0, 255, 0, 255}));
}

TEST_CASE("Context::blit copies colour attachment 0, scaling to the destination, whatever the scissor", "[renderer][framebuffer]")
{
    Context& context = test::sharedDevice().context();
    // Left half red, right half green; the scissor left enabled by the second clear must not clip
    // the copy.
    Framebuffer source = clearedFramebuffer(8, 8, {1.0f, 0.0f, 0.0f, 1.0f});
    ClearState rightHalf;
    rightHalf.color = {0.0f, 1.0f, 0.0f, 1.0f};
    rightHalf.scissorTest.enabled = true;
    rightHalf.scissorTest.rectangle = {4, 0, 4, 8};
    context.clear(rightHalf, &source);

    Framebuffer same = clearedFramebuffer(8, 8, {0.0f, 0.0f, 1.0f, 1.0f});
    context.blit(source, &same);
    const Image copied = context.readPixels(&same);
    const Image original = context.readPixels(&source);
    CHECK(copied.pixels == original.pixels);

    Framebuffer larger = clearedFramebuffer(16, 12, {0.0f, 0.0f, 1.0f, 1.0f});
    context.blit(source, &larger);
    const Image scaled = context.readPixels(&larger);
    for (int y : {0, 6, 11}) {
        CHECK(test::pixelNear(scaled, 0, y, {255, 0, 0, 255}));
        CHECK(test::pixelNear(scaled, 5, y, {255, 0, 0, 255}));
        CHECK(test::pixelNear(scaled, 10, y, {0, 255, 0, 255}));
        CHECK(test::pixelNear(scaled, 15, y, {0, 255, 0, 255}));
    }

    // The context still draws where it did: the source is the bound framebuffer afterwards.
    ClearState white;
    white.color = {1.0f, 1.0f, 1.0f, 1.0f};
    context.clear(white, &larger);
    CHECK(test::pixelNear(context.readPixels(&larger), 8, 6, {255, 255, 255, 255}));
    CHECK(test::pixelNear(context.readPixels(&source), 0, 0, {255, 0, 0, 255}));

    REQUIRE_THROWS_WITH(context.blit(source, &source), Contains("the source is the destination"));
    Framebuffer empty;
    REQUIRE_THROWS_WITH(context.blit(empty, &larger), Contains("Context::blit") && Contains("empty"));
}

TEST_CASE("Context::blit to the window of a headless context is a clear error", "[renderer][framebuffer][errors][headless]")
{
    Context& context = test::sharedDevice().context();
    Framebuffer source = clearedFramebuffer(4, 4, {1.0f, 0.0f, 0.0f, 1.0f});
    REQUIRE_THROWS_WITH(context.blit(source), Contains("Context::blit: no window"));
}

TEST_CASE("A multisampled framebuffer resolved by blit has pixels between the colours along an edge; a single-sampled one has none", "[renderer][framebuffer][msaa]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    INFO("device maximum " << device.info().maxSamples << " samples");
    REQUIRE(device.info().maxSamples >= 4); // llvmpipe and every GPU of the last decade
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    // A triangle with a slanted edge across a 16 x 16 target.
    Mesh triangle;
    triangle.positions = {{-1.0, -1.0, 0.0}, {1.0, -1.0, 0.0}, {-0.7, 1.0, 0.0}};
    triangle.indices = {0, 1, 2};
    const VertexArray array = context.createVertexArray(triangle, program);
    auto edgePixels = [&](int samples) {
        Framebuffer drawn = context.createFramebuffer();
        drawn.setColorAttachment(0, std::make_shared<Texture2D>(device.createTexture2D({16, 16, TextureFormat::RGBA8, false, samples})));
        drawn.setDepthAttachment(
            std::make_shared<Texture2D>(device.createTexture2D({16, 16, TextureFormat::Depth24Stencil8, false, samples})));
        context.clear(ClearState{}, &drawn);
        context.draw(test::makeCommand(array, program, drawn, {1.0f, 1.0f, 1.0f, 1.0f}, "slanted triangle"));
        Framebuffer resolved = clearedFramebuffer(16, 16, {0.0f, 0.0f, 1.0f, 1.0f});
        context.blit(drawn, &resolved);
        const Image image = context.readPixels(&resolved);
        int between = 0;
        int white = 0;
        for (int y = 0; y < 16; ++y) {
            for (int x = 0; x < 16; ++x) {
                const int red = test::pixelAt(image, x, y).r;
                between += red > 0 && red < 255 ? 1 : 0;
                white += red == 255 ? 1 : 0;
            }
        }
        CHECK(white > 60); // the triangle covers over a third of the target either way
        return between;
    };
    CHECK(edgePixels(1) == 0);
    const int multisampled = edgePixels(4);
    CHECK(multisampled >= 16); // about one a row along the slanted edge
    // A multisampled texture is drawn into and resolved, never copied or sampled.
    Texture2D samples4 = device.createTexture2D({4, 4, TextureFormat::RGBA8, false, 4});
    REQUIRE(samples4.samples() == 4);
    REQUIRE_THROWS_WITH(samples4.copyToSystemMemory(), Contains("multisampled"));
    REQUIRE_THROWS_WITH(device.createTexture2D({4, 4, TextureFormat::RGBA8, true, 4}), Contains("no mipmaps"));
    REQUIRE_THROWS_WITH(device.createTexture2D({4, 4, TextureFormat::RGBA8, false, device.info().maxSamples + 1}),
                        Contains("samples"));
}
