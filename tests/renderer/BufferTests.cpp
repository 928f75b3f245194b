#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <cstring>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

TEST_CASE("A vertex buffer round-trips and takes partial updates", "[renderer][buffer]")
{
    Device& device = test::sharedDevice();
    const float values[] = {1, 2, 3, 4, 5, 6};
    VertexBuffer buffer = device.createVertexBuffer(std::as_bytes(std::span(values)), BufferUsage::DynamicDraw);
    CHECK(buffer.sizeInBytes() == sizeof values);
    CHECK(buffer.usage() == BufferUsage::DynamicDraw);
    std::vector<std::byte> bytes = buffer.copyToSystemMemory();
    REQUIRE(bytes.size() == sizeof values);
    CHECK(std::memcmp(bytes.data(), values, sizeof values) == 0);

    const float update[] = {-7, -8};
    buffer.copyFromSystemMemory(std::as_bytes(std::span(update)), 2 * sizeof(float));
    float back[6];
    bytes = buffer.copyToSystemMemory();
    std::memcpy(back, bytes.data(), sizeof back);
    CHECK(std::vector<float>(back, back + 6) == std::vector<float>{1, 2, -7, -8, 5, 6});
    bytes = buffer.copyToSystemMemory(4 * sizeof(float), 2 * sizeof(float));
    std::memcpy(back, bytes.data(), 2 * sizeof(float));
    CHECK(back[0] == 5.0f);
    CHECK(back[1] == 6.0f);

    REQUIRE_THROWS_WITH(buffer.copyFromSystemMemory(std::as_bytes(std::span(update)), 5 * sizeof(float)),
                        Contains("bytes [20, 28) leave the buffer of 24 bytes"));
    REQUIRE_THROWS_WITH(buffer.copyToSystemMemory(30), Contains("leave the buffer"));

    VertexBuffer empty = device.createVertexBuffer(std::size_t{0});
    CHECK(empty.copyToSystemMemory().empty());
    VertexBuffer moved = std::move(buffer);
    CHECK(moved.valid());
    CHECK_FALSE(buffer.valid()); // NOLINT(bugprone-use-after-move): moved-from is empty
}

TEST_CASE("Index buffers of 16 and 32 bits round-trip and take partial updates", "[renderer][buffer]")
{
    Device& device = test::sharedDevice();
    const std::uint16_t narrow[] = {0, 1, 2, 65535};
    IndexBuffer shortBuffer = device.createIndexBuffer(std::span<const std::uint16_t>(narrow));
    CHECK(shortBuffer.type() == IndexType::UnsignedShort);
    CHECK(shortBuffer.count() == 4);
    CHECK(shortBuffer.copyToSystemMemory() == std::vector<std::uint32_t>{0, 1, 2, 65535});

    const std::uint32_t wide[] = {7, 100000, 4000000000u};
    IndexBuffer intBuffer = device.createIndexBuffer(std::span<const std::uint32_t>(wide));
    CHECK(intBuffer.type() == IndexType::UnsignedInt);
    CHECK(intBuffer.copyToSystemMemory() == std::vector<std::uint32_t>{7, 100000, 4000000000u});
    const std::uint32_t update[] = {9};
    intBuffer.copyFromSystemMemory(std::span<const std::uint32_t>(update), 1);
    CHECK(intBuffer.copyToSystemMemory() == std::vector<std::uint32_t>{7, 9, 4000000000u});

    REQUIRE_THROWS_WITH(shortBuffer.copyFromSystemMemory(std::span<const std::uint32_t>(update)),
                        Contains("16-bit indices, the data 32-bit"));
    REQUIRE_THROWS_WITH(intBuffer.copyFromSystemMemory(std::span<const std::uint32_t>(wide), 1),
                        Contains("indices [1, 4) leave the buffer of 3 indices"));

    IndexBuffer sized = device.createIndexBuffer(IndexType::UnsignedShort, 10);
    CHECK(sized.count() == 10);
    CHECK(sized.copyToSystemMemory().size() == 10);
}

TEST_CASE("A vertex array built by hand reads interleaved buffers", "[renderer][buffer][vertexarray]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());
    // x, y, z, padding per vertex: a 16-byte stride.
    const float interleaved[] = {-1, -1, 0, 9, 1, -1, 0, 9, 1, 1, 0, 9, -1, 1, 0, 9};
    const VertexBuffer vertices = device.createVertexBuffer(std::as_bytes(std::span(interleaved)));
    const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};
    const IndexBuffer indexBuffer = device.createIndexBuffer(std::span<const std::uint32_t>(indices));
    VertexArray array = context.createVertexArray();
    VertexAttributeFormat format;
    format.components = 3;
    format.strideInBytes = 16;
    array.setAttribute("position", vertices, format);
    array.setIndexBuffer(&indexBuffer);
    CHECK(array.vertexCount() == 4);
    CHECK(array.indexCount() == 6);
    CHECK(array.indexType() == IndexType::UnsignedInt);

    Framebuffer framebuffer = context.createFramebuffer(8, 8);
    context.clear(ClearState{}, &framebuffer);
    context.draw(test::makeCommand(array, program, framebuffer, {0, 0, 1, 1}));
    CHECK(test::pixelNear(context.readPixels(&framebuffer), 3, 3, {0, 0, 255, 255}));

    REQUIRE_THROWS_WITH(array.setAttribute("positon", vertices, format), Contains("'positon' is not a standard"));
    REQUIRE_THROWS_WITH(array.setAttribute(16, vertices, format), Contains("location 16"));
    format.components = 5;
    REQUIRE_THROWS_WITH(array.setAttribute(7, vertices, format), Contains("5 components"));
}
