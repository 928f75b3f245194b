#pragma once

#include "orbis/renderer/ShaderProgram.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace orbis::renderer {

/// Programs keyed by their sources, defines and options: each variant is compiled once, the first
/// time it is asked for, and shared after that. Owned by the Device; thread-safe (a worker thread
/// with a shared context current may ask too).
///
/// ```
/// auto program = device.shaderCache().get(description); // compiles
/// auto same = device.shaderCache().get(description);    // returns the same program
/// ```
class ShaderCache final {
public:
    explicit ShaderCache(Device& device) noexcept : _device(device) {}
    ShaderCache(const ShaderCache&) = delete;
    ShaderCache& operator=(const ShaderCache&) = delete;

    /// The program for the description, compiled on first use. Throws orbis::Error (and caches
    /// nothing) when it does not compile or link.
    std::shared_ptr<ShaderProgram> get(const ShaderProgramDescription& description);

    /// Programs held.
    std::size_t size() const;
    /// Programs compiled since creation (or clear()).
    std::uint64_t compiles() const;
    /// Requests answered from the cache.
    std::uint64_t hits() const;
    /// Drops the cache's references (programs still used elsewhere stay alive).
    void clear();

private:
    Device& _device;
    mutable std::mutex _mutex;
    std::unordered_map<std::string, std::shared_ptr<ShaderProgram>> _programs;
    std::uint64_t _compiles = 0;
    std::uint64_t _hits = 0;
};

} // namespace orbis::renderer
