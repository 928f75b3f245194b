#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <cstring>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

/// The framebuffer cleared to `bottom`, its top half to `top` (GL rows from the bottom).
void clearHalves(Context& context, Framebuffer& framebuffer, const glm::vec4& bottom, const glm::vec4& top)
{
    ClearState clear;
    clear.color = bottom;
    context.clear(clear, &framebuffer);
    clear.color = top;
    clear.scissorTest = {true, {0, framebuffer.height() / 2, framebuffer.width(), framebuffer.height() / 2}};
    context.clear(clear, &framebuffer);
}

/// The RGBA bytes of pixel (x, y) of a bottom-up read of `width` pixels a row.
glm::ivec4 texelAt(const std::vector<std::byte>& bytes, int width, int x, int y)
{
    const std::size_t at = (static_cast<std::size_t>(y) * width + x) * 4;
    return {std::to_integer<int>(bytes[at]), std::to_integer<int>(bytes[at + 1]), std::to_integer<int>(bytes[at + 2]),
            std::to_integer<int>(bytes[at + 3])};
}

} // namespace

TEST_CASE("Pixels read into a pixel buffer arrive once its fence signals, rows bottom to top",
          "[renderer][pixelbuffer]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(24, 10);
    clearHalves(context, framebuffer, {1.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f, 0.6f});
    PixelBuffer buffer = device.createPixelBuffer(24 * 10 * 4);
    CHECK(buffer.sizeInBytes() == 960);
    context.readPixels(buffer, &framebuffer);
    const Fence done = device.createFence();
    // What is drawn after the read does not reach the buffer: the copy was queued before it.
    ClearState green;
    green.color = {0.0f, 1.0f, 0.0f, 1.0f};
    context.clear(green, &framebuffer);
    REQUIRE(done.clientWait() == Fence::Status::Signaled);
    const std::vector<std::byte> bytes = buffer.copyToSystemMemory();
    REQUIRE(bytes.size() == 960);
    CHECK(texelAt(bytes, 24, 0, 0) == glm::ivec4(255, 0, 0, 255));
    CHECK(texelAt(bytes, 24, 23, 4) == glm::ivec4(255, 0, 0, 255));
    CHECK(texelAt(bytes, 24, 0, 5) == glm::ivec4(0, 0, 255, 153));
    CHECK(texelAt(bytes, 24, 23, 9) == glm::ivec4(0, 0, 255, 153));
    // The same bytes as the waiting read, once flipped to its rows.
    clearHalves(context, framebuffer, {1.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f, 0.6f});
    const Image image = context.readPixels(&framebuffer);
    for (int y = 0; y < 10; ++y) {
        REQUIRE(std::memcmp(image.pixels.data() + static_cast<std::size_t>(9 - y) * 96, bytes.data() + y * 96, 96) == 0);
    }
    // A part of the buffer.
    const std::vector<std::byte> row = buffer.copyToSystemMemory(5 * 96, 96);
    CHECK(texelAt(row, 24, 3, 0) == glm::ivec4(0, 0, 255, 153));
}

TEST_CASE("Two pixel buffers hold two frames' reads apart", "[renderer][pixelbuffer]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(4, 4);
    PixelBuffer first = device.createPixelBuffer(64);
    PixelBuffer second = device.createPixelBuffer(64);
    clearHalves(context, framebuffer, {1.0f, 1.0f, 0.0f, 1.0f}, {1.0f, 1.0f, 0.0f, 1.0f});
    context.readPixels(first, &framebuffer);
    clearHalves(context, framebuffer, {0.0f, 1.0f, 1.0f, 1.0f}, {0.0f, 1.0f, 1.0f, 1.0f});
    context.readPixels(second, &framebuffer);
    const Fence done = device.createFence();
    REQUIRE(done.clientWait() == Fence::Status::Signaled);
    CHECK(texelAt(first.copyToSystemMemory(), 4, 2, 2) == glm::ivec4(255, 255, 0, 255));
    CHECK(texelAt(second.copyToSystemMemory(), 4, 2, 2) == glm::ivec4(0, 255, 255, 255));
}

TEST_CASE("A pixel buffer too small for the framebuffer is refused", "[renderer][pixelbuffer]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    PixelBuffer small = device.createPixelBuffer(100);
    CHECK_THROWS_WITH(context.readPixels(small, &framebuffer), Contains("8 x 8") && Contains("256 bytes"));
    PixelBuffer empty;
    CHECK_THROWS_WITH(context.readPixels(empty, &framebuffer), Contains("has 0"));
    CHECK_THROWS_WITH(small.copyToSystemMemory(90, 20), Contains("leave the buffer"));
    // A framebuffer without that attachment.
    PixelBuffer enough = device.createPixelBuffer(256);
    CHECK_THROWS_WITH(context.readPixels(enough, &framebuffer, 3), Contains("no colour attachment 3"));
}
