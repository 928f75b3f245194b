#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace orbis::renderer {

class Device;

/// How a buffer's contents will be used, a hint to the driver.
enum class BufferUsage : std::uint8_t {
    StreamDraw, StreamRead, StreamCopy, StaticDraw, StaticRead, StaticCopy, DynamicDraw, DynamicRead, DynamicCopy
};

/// Vertex data in GPU memory: one GL buffer object, move-only, deleted with the object. Created by
/// Device::createVertexBuffer; shared between the device's contexts.
///
/// ```
/// const float positions[] = {0, 0, 1, 0, 0, 1};
/// VertexBuffer buffer = device.createVertexBuffer(std::as_bytes(std::span(positions)));
/// buffer.copyFromSystemMemory(std::as_bytes(std::span(positions).subspan(2, 2)), 8);
/// ```
class VertexBuffer final {
public:
    /// An empty handle (owns nothing).
    VertexBuffer() noexcept = default;
    ~VertexBuffer();
    VertexBuffer(VertexBuffer&& other) noexcept;
    VertexBuffer& operator=(VertexBuffer&& other) noexcept;
    VertexBuffer(const VertexBuffer&) = delete;
    VertexBuffer& operator=(const VertexBuffer&) = delete;

    std::size_t sizeInBytes() const noexcept { return _size; }
    BufferUsage usage() const noexcept { return _usage; }
    bool valid() const noexcept { return _name != 0; }

    /// Replaces bytes [offsetInBytes, offsetInBytes + data.size()). Throws orbis::Error when the
    /// range leaves the buffer.
    void copyFromSystemMemory(std::span<const std::byte> data, std::size_t offsetInBytes = 0);
    /// The bytes [offsetInBytes, offsetInBytes + sizeInBytes); to the end when sizeInBytes is empty.
    std::vector<std::byte> copyToSystemMemory(std::size_t offsetInBytes = 0,
                                              std::optional<std::size_t> sizeInBytes = {}) const;

private:
    friend class Device;
    friend class VertexArray;
    VertexBuffer(Device& device, unsigned name, std::size_t size, BufferUsage usage) noexcept;

    Device* _device = nullptr;
    unsigned _name = 0;
    std::size_t _size = 0;
    BufferUsage _usage = BufferUsage::StaticDraw;
};

} // namespace orbis::renderer
