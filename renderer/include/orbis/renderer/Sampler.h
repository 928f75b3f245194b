#pragma once

#include <orbis/core/SamplerDescription.h>

#include <cstdint>

namespace orbis::renderer {

class Device;

/// How a texture is read (filters, wrapping, anisotropy): one GL sampler object, move-only,
/// shared between the device's contexts; bound per texture unit by a DrawCommand.
class Sampler final {
public:
    Sampler() noexcept = default;
    ~Sampler();
    Sampler(Sampler&& other) noexcept;
    Sampler& operator=(Sampler&& other) noexcept;
    Sampler(const Sampler&) = delete;
    Sampler& operator=(const Sampler&) = delete;

    const SamplerDescription& description() const noexcept { return _description; }
    /// The anisotropy set in GL: 1 where the device has no anisotropic filtering.
    float appliedAnisotropy() const noexcept { return _appliedAnisotropy; }
    bool valid() const noexcept { return _name != 0; }

private:
    friend class Device;
    friend class Context;
    Sampler(Device& device, unsigned name, const SamplerDescription& description, float anisotropy) noexcept;

    Device* _device = nullptr;
    unsigned _name = 0;
    std::uint64_t _serial = 0;
    SamplerDescription _description;
    float _appliedAnisotropy = 1.0f;
};

} // namespace orbis::renderer
