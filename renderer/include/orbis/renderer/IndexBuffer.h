#pragma once

#include "orbis/renderer/VertexBuffer.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace orbis::renderer {

/// The width of one index.
enum class IndexType : std::uint8_t { UnsignedShort, UnsignedInt };

/// Bytes per index: 2 or 4.
constexpr std::size_t indexSize(IndexType type) noexcept { return type == IndexType::UnsignedShort ? 2 : 4; }

/// Indices in GPU memory, 16 or 32 bits each: one GL buffer object, move-only. Created by
/// Device::createIndexBuffer.
class IndexBuffer final {
public:
    IndexBuffer() noexcept = default;
    ~IndexBuffer();
    IndexBuffer(IndexBuffer&& other) noexcept;
    IndexBuffer& operator=(IndexBuffer&& other) noexcept;
    IndexBuffer(const IndexBuffer&) = delete;
    IndexBuffer& operator=(const IndexBuffer&) = delete;

    IndexType type() const noexcept { return _type; }
    std::size_t count() const noexcept { return _count; }
    BufferUsage usage() const noexcept { return _usage; }
    bool valid() const noexcept { return _name != 0; }

    /// Replaces indices [first, first + indices.size()). Throws orbis::Error when the type differs
    /// from the buffer's or the range leaves the buffer.
    void copyFromSystemMemory(std::span<const std::uint16_t> indices, std::size_t first = 0);
    void copyFromSystemMemory(std::span<const std::uint32_t> indices, std::size_t first = 0);
    /// Every index, widened to 32 bits.
    std::vector<std::uint32_t> copyToSystemMemory() const;

private:
    friend class Device;
    friend class VertexArray;
    IndexBuffer(Device& device, unsigned name, IndexType type, std::size_t count, BufferUsage usage) noexcept;
    void copyBytes(std::span<const std::byte> bytes, IndexType type, std::size_t first);

    Device* _device = nullptr;
    unsigned _name = 0;
    IndexType _type = IndexType::UnsignedInt;
    std::size_t _count = 0;
    BufferUsage _usage = BufferUsage::StaticDraw;
};

} // namespace orbis::renderer
