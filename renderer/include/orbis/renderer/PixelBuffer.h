#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace orbis::renderer {

class Device;

/// GPU memory that pixels are read into without waiting for them (a pixel buffer object, GL's
/// pixel-pack buffer): Context::readPixels(PixelBuffer&, ...) queues the copy and returns at once,
/// and the bytes are read later, a frame or more later, once a Fence created after the read has
/// signalled, so the read stalls neither the CPU nor the GPU (Mayer's feedback read-back).
/// Move-only, one GL buffer object, shared between the device's contexts.
///
/// ```
/// PixelBuffer buffer = device.createPixelBuffer(width * height * 4);
/// context.readPixels(buffer, &framebuffer); // queued
/// Fence done = device.createFence();
/// ... next frame ...
/// if (done.signaled()) { std::vector<std::byte> pixels = buffer.copyToSystemMemory(); }
/// ```
class PixelBuffer final {
public:
    PixelBuffer() noexcept = default;
    ~PixelBuffer();
    PixelBuffer(PixelBuffer&& other) noexcept;
    PixelBuffer& operator=(PixelBuffer&& other) noexcept;
    PixelBuffer(const PixelBuffer&) = delete;
    PixelBuffer& operator=(const PixelBuffer&) = delete;

    std::size_t sizeInBytes() const noexcept { return _size; }
    bool valid() const noexcept { return _name != 0; }

    /// The bytes [offsetInBytes, offsetInBytes + sizeInBytes); to the end when sizeInBytes is
    /// empty. Waits for reads still running on the GPU (none once their fence signalled). Throws
    /// orbis::Error when the range leaves the buffer.
    std::vector<std::byte> copyToSystemMemory(std::size_t offsetInBytes = 0,
                                              std::optional<std::size_t> sizeInBytes = {}) const;

private:
    friend class Device;
    friend class Context;
    PixelBuffer(Device& device, unsigned name, std::size_t size) noexcept;

    Device* _device = nullptr;
    unsigned _name = 0;
    std::size_t _size = 0;
};

} // namespace orbis::renderer
