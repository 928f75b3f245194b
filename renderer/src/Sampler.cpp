#include "orbis/renderer/Sampler.h"

#include "ContextState.h"
#include "GlEnums.h"

#include "orbis/renderer/Device.h"

#include <algorithm>
#include <utility>

namespace orbis::renderer {

Sampler::Sampler(Device& device, unsigned name, const SamplerDescription& description, float anisotropy) noexcept
    : _device(&device)
    , _name(name)
    , _serial(detail::nextObjectSerial())
    , _description(description)
    , _appliedAnisotropy(anisotropy)
{
}

Sampler::~Sampler()
{
    if (_name) {
        if (detail::ContextState* state = detail::currentStateOf(_device)) {
            state->gl.glDeleteSamplers.unchecked(1, &_name);
        }
    }
}

Sampler::Sampler(Sampler&& other) noexcept
    : _device(other._device)
    , _name(std::exchange(other._name, 0u))
    , _serial(std::exchange(other._serial, 0u))
    , _description(other._description)
    , _appliedAnisotropy(other._appliedAnisotropy)
{
}

Sampler& Sampler::operator=(Sampler&& other) noexcept
{
    if (this != &other) {
        Sampler moved(std::move(other));
        std::swap(_device, moved._device);
        std::swap(_name, moved._name);
        std::swap(_serial, moved._serial);
        std::swap(_description, moved._description);
        std::swap(_appliedAnisotropy, moved._appliedAnisotropy);
    }
    return *this;
}

Sampler Device::createSampler(const SamplerDescription& description)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createSampler");
    const detail::GlApi& gl = state.gl;
    GLuint name = 0;
    gl.glGenSamplers(1, &name);
    gl.glSamplerParameteri(name, GL_TEXTURE_MIN_FILTER, detail::toGl(description.minificationFilter));
    gl.glSamplerParameteri(name, GL_TEXTURE_MAG_FILTER, detail::toGl(description.magnificationFilter));
    gl.glSamplerParameteri(name, GL_TEXTURE_WRAP_S, detail::toGl(description.wrapS));
    gl.glSamplerParameteri(name, GL_TEXTURE_WRAP_T, detail::toGl(description.wrapT));
    float anisotropy = 1.0f;
    if (info().maxAnisotropy > 1.0f) {
        anisotropy = std::clamp(description.maximumAnisotropy, 1.0f, info().maxAnisotropy);
        gl.glSamplerParameterf(name, GL_TEXTURE_MAX_ANISOTROPY, anisotropy);
    }
    return Sampler(*this, name, description, anisotropy);
}

} // namespace orbis::renderer
