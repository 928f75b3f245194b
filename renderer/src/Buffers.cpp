// VertexBuffer, IndexBuffer and PixelBuffer: GL buffer objects. Uploads and reads go through the
// copy-write and copy-read binding points, which no vertex array records, so they never disturb a
// draw's state.

#include "orbis/renderer/IndexBuffer.h"
#include "orbis/renderer/PixelBuffer.h"
#include "orbis/renderer/VertexBuffer.h"

#include "ContextState.h"
#include "GlEnums.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Device.h"

#include <cstring>
#include <utility>

namespace orbis::renderer {
namespace {

GLuint createBuffer(const detail::GlApi& gl, std::size_t size, const void* data, BufferUsage usage)
{
    GLuint name = 0;
    gl.glGenBuffers(1, &name);
    gl.glBindBuffer(GL_COPY_WRITE_BUFFER, name);
    gl.glBufferData(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(size), data, detail::toGl(usage));
    return name;
}

void writeBuffer(const detail::GlApi& gl, GLuint name, std::size_t offset, std::span<const std::byte> data)
{
    if (data.empty()) {
        return;
    }
    gl.glBindBuffer(GL_COPY_WRITE_BUFFER, name);
    gl.glBufferSubData(GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(data.size()),
                       data.data());
}

std::vector<std::byte> readBuffer(const detail::GlApi& gl, GLuint name, std::size_t offset, std::size_t size)
{
    std::vector<std::byte> bytes(size);
    if (size > 0) {
        gl.glBindBuffer(GL_COPY_READ_BUFFER, name);
        gl.glGetBufferSubData(GL_COPY_READ_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(size),
                              bytes.data());
    }
    return bytes;
}

void deleteBuffer(Device* device, unsigned name) noexcept
{
    if (name) {
        if (detail::ContextState* state = detail::currentStateOf(device)) {
            state->gl.glDeleteBuffers.unchecked(1, &name);
        }
    }
}

void checkRange(const char* what, std::size_t offset, std::size_t size, std::size_t capacity, const char* unit)
{
    if (offset > capacity || size > capacity - offset) {
        throw Error(std::string(what) + ": " + unit + " [" + std::to_string(offset) + ", " +
                    std::to_string(offset + size) + ") leave the buffer of " + std::to_string(capacity) + " " + unit);
    }
}

} // namespace

// VertexBuffer

VertexBuffer::VertexBuffer(Device& device, unsigned name, std::size_t size, BufferUsage usage) noexcept
    : _device(&device), _name(name), _size(size), _usage(usage)
{
}

VertexBuffer::~VertexBuffer()
{
    deleteBuffer(_device, _name);
}

VertexBuffer::VertexBuffer(VertexBuffer&& other) noexcept
    : _device(other._device)
    , _name(std::exchange(other._name, 0u))
    , _size(std::exchange(other._size, 0u))
    , _usage(other._usage)
{
}

VertexBuffer& VertexBuffer::operator=(VertexBuffer&& other) noexcept
{
    if (this != &other) {
        deleteBuffer(_device, _name);
        _device = other._device;
        _name = std::exchange(other._name, 0u);
        _size = std::exchange(other._size, 0u);
        _usage = other._usage;
    }
    return *this;
}

void VertexBuffer::copyFromSystemMemory(std::span<const std::byte> data, std::size_t offsetInBytes)
{
    detail::ContextState& state = detail::requireCurrent(_device, "VertexBuffer::copyFromSystemMemory");
    checkRange("VertexBuffer::copyFromSystemMemory", offsetInBytes, data.size(), _size, "bytes");
    writeBuffer(state.gl, _name, offsetInBytes, data);
}

std::vector<std::byte> VertexBuffer::copyToSystemMemory(std::size_t offsetInBytes,
                                                        std::optional<std::size_t> sizeInBytes) const
{
    detail::ContextState& state = detail::requireCurrent(_device, "VertexBuffer::copyToSystemMemory");
    const std::size_t size = sizeInBytes.value_or(offsetInBytes <= _size ? _size - offsetInBytes : 0);
    checkRange("VertexBuffer::copyToSystemMemory", offsetInBytes, size, _size, "bytes");
    return readBuffer(state.gl, _name, offsetInBytes, size);
}

VertexBuffer Device::createVertexBuffer(std::size_t sizeInBytes, BufferUsage usage)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createVertexBuffer");
    return VertexBuffer(*this, createBuffer(state.gl, sizeInBytes, nullptr, usage), sizeInBytes, usage);
}

VertexBuffer Device::createVertexBuffer(std::span<const std::byte> data, BufferUsage usage)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createVertexBuffer");
    return VertexBuffer(*this, createBuffer(state.gl, data.size(), data.data(), usage), data.size(), usage);
}

// IndexBuffer

IndexBuffer::IndexBuffer(Device& device, unsigned name, IndexType type, std::size_t count, BufferUsage usage) noexcept
    : _device(&device), _name(name), _type(type), _count(count), _usage(usage)
{
}

IndexBuffer::~IndexBuffer()
{
    deleteBuffer(_device, _name);
}

IndexBuffer::IndexBuffer(IndexBuffer&& other) noexcept
    : _device(other._device)
    , _name(std::exchange(other._name, 0u))
    , _type(other._type)
    , _count(std::exchange(other._count, 0u))
    , _usage(other._usage)
{
}

IndexBuffer& IndexBuffer::operator=(IndexBuffer&& other) noexcept
{
    if (this != &other) {
        deleteBuffer(_device, _name);
        _device = other._device;
        _name = std::exchange(other._name, 0u);
        _type = other._type;
        _count = std::exchange(other._count, 0u);
        _usage = other._usage;
    }
    return *this;
}

void IndexBuffer::copyBytes(std::span<const std::byte> bytes, IndexType type, std::size_t first)
{
    detail::ContextState& state = detail::requireCurrent(_device, "IndexBuffer::copyFromSystemMemory");
    if (type != _type) {
        throw Error(std::string("IndexBuffer::copyFromSystemMemory: the buffer holds ") +
                    (_type == IndexType::UnsignedShort ? "16" : "32") + "-bit indices, the data " +
                    (type == IndexType::UnsignedShort ? "16" : "32") + "-bit ones");
    }
    const std::size_t count = bytes.size() / indexSize(type);
    checkRange("IndexBuffer::copyFromSystemMemory", first, count, _count, "indices");
    writeBuffer(state.gl, _name, first * indexSize(type), bytes);
}

void IndexBuffer::copyFromSystemMemory(std::span<const std::uint16_t> indices, std::size_t first)
{
    copyBytes(std::as_bytes(indices), IndexType::UnsignedShort, first);
}

void IndexBuffer::copyFromSystemMemory(std::span<const std::uint32_t> indices, std::size_t first)
{
    copyBytes(std::as_bytes(indices), IndexType::UnsignedInt, first);
}

std::vector<std::uint32_t> IndexBuffer::copyToSystemMemory() const
{
    detail::ContextState& state = detail::requireCurrent(_device, "IndexBuffer::copyToSystemMemory");
    const std::vector<std::byte> bytes = readBuffer(state.gl, _name, 0, _count * indexSize(_type));
    std::vector<std::uint32_t> indices(_count);
    for (std::size_t i = 0; i < _count; ++i) {
        if (_type == IndexType::UnsignedShort) {
            std::uint16_t index = 0;
            std::memcpy(&index, bytes.data() + 2 * i, 2);
            indices[i] = index;
        } else {
            std::memcpy(&indices[i], bytes.data() + 4 * i, 4);
        }
    }
    return indices;
}

IndexBuffer Device::createIndexBuffer(IndexType type, std::size_t count, BufferUsage usage)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createIndexBuffer");
    return IndexBuffer(*this, createBuffer(state.gl, count * indexSize(type), nullptr, usage), type, count, usage);
}

IndexBuffer Device::createIndexBuffer(std::span<const std::uint16_t> indices, BufferUsage usage)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createIndexBuffer");
    return IndexBuffer(*this, createBuffer(state.gl, indices.size_bytes(), indices.data(), usage),
                       IndexType::UnsignedShort, indices.size(), usage);
}

IndexBuffer Device::createIndexBuffer(std::span<const std::uint32_t> indices, BufferUsage usage)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createIndexBuffer");
    return IndexBuffer(*this, createBuffer(state.gl, indices.size_bytes(), indices.data(), usage),
                       IndexType::UnsignedInt, indices.size(), usage);
}

// PixelBuffer

PixelBuffer::PixelBuffer(Device& device, unsigned name, std::size_t size) noexcept
    : _device(&device), _name(name), _size(size)
{
}

PixelBuffer::~PixelBuffer()
{
    deleteBuffer(_device, _name);
}

PixelBuffer::PixelBuffer(PixelBuffer&& other) noexcept
    : _device(other._device)
    , _name(std::exchange(other._name, 0u))
    , _size(std::exchange(other._size, 0u))
{
}

PixelBuffer& PixelBuffer::operator=(PixelBuffer&& other) noexcept
{
    if (this != &other) {
        deleteBuffer(_device, _name);
        _device = other._device;
        _name = std::exchange(other._name, 0u);
        _size = std::exchange(other._size, 0u);
    }
    return *this;
}

std::vector<std::byte> PixelBuffer::copyToSystemMemory(std::size_t offsetInBytes,
                                                       std::optional<std::size_t> sizeInBytes) const
{
    detail::ContextState& state = detail::requireCurrent(_device, "PixelBuffer::copyToSystemMemory");
    const std::size_t size = sizeInBytes.value_or(offsetInBytes <= _size ? _size - offsetInBytes : 0);
    checkRange("PixelBuffer::copyToSystemMemory", offsetInBytes, size, _size, "bytes");
    return readBuffer(state.gl, _name, offsetInBytes, size);
}

PixelBuffer Device::createPixelBuffer(std::size_t sizeInBytes)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createPixelBuffer");
    return PixelBuffer(*this, createBuffer(state.gl, sizeInBytes, nullptr, BufferUsage::StreamRead), sizeInBytes);
}

} // namespace orbis::renderer
