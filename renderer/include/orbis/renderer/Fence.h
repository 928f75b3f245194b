#pragma once

#include <chrono>

namespace orbis::renderer {

class Device;

/// A point in a context's command stream: signalled when the GPU has executed everything before
/// it. Used to hand resources made on a worker thread (with a shared context) to the rendering
/// thread: the worker creates the fence after its uploads, the renderer waits on it before
/// drawing. Move-only; created by Device::createFence in the context current on the thread.
class Fence final {
public:
    enum class Status { Signaled, TimeoutExpired };

    Fence() noexcept = default;
    ~Fence();
    Fence(Fence&& other) noexcept;
    Fence& operator=(Fence&& other) noexcept;
    Fence(const Fence&) = delete;
    Fence& operator=(const Fence&) = delete;

    /// True once the commands before the fence have completed (does not wait).
    bool signaled() const;
    /// Blocks the calling thread until signalled or until the timeout, flushing first so that the
    /// fence is sure to be reached. Throws orbis::Error when the driver reports a failure.
    Status clientWait(std::chrono::nanoseconds timeout = std::chrono::seconds(10)) const;
    /// Makes the GPU wait, in the context current on this thread, until the fence is signalled;
    /// returns at once on the CPU.
    void serverWait() const;
    bool valid() const noexcept { return _sync != nullptr; }

private:
    friend class Device;
    Fence(Device& device, void* sync) noexcept;

    Device* _device = nullptr;
    void* _sync = nullptr;
};

} // namespace orbis::renderer
