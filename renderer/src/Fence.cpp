#include "orbis/renderer/Fence.h"

#include "ContextState.h"

#include "orbis/core/Error.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace orbis::renderer {

Fence::Fence(Device& device, void* sync) noexcept
    : _device(&device), _sync(sync)
{
}

Fence::~Fence()
{
    if (_sync) {
        if (detail::ContextState* state = detail::currentStateOf(_device)) {
            state->gl.glDeleteSync.unchecked(static_cast<GLsync>(_sync));
        }
    }
}

Fence::Fence(Fence&& other) noexcept
    : _device(other._device), _sync(std::exchange(other._sync, nullptr))
{
}

Fence& Fence::operator=(Fence&& other) noexcept
{
    if (this != &other) {
        Fence moved(std::move(other));
        std::swap(_device, moved._device);
        std::swap(_sync, moved._sync);
    }
    return *this;
}

bool Fence::signaled() const
{
    detail::ContextState& state = detail::requireCurrent(_device, "Fence::signaled");
    if (!_sync) {
        throw Error("Fence::signaled: empty fence");
    }
    GLint status = GL_UNSIGNALED;
    state.gl.glGetSynciv(static_cast<GLsync>(_sync), GL_SYNC_STATUS, 1, nullptr, &status);
    return status == GL_SIGNALED;
}

Fence::Status Fence::clientWait(std::chrono::nanoseconds timeout) const
{
    detail::ContextState& state = detail::requireCurrent(_device, "Fence::clientWait");
    if (!_sync) {
        throw Error("Fence::clientWait: empty fence");
    }
    const GLenum result = state.gl.glClientWaitSync(static_cast<GLsync>(_sync), GL_SYNC_FLUSH_COMMANDS_BIT,
                                                    static_cast<GLuint64>(std::max<std::int64_t>(timeout.count(), 0)));
    switch (result) {
    case GL_ALREADY_SIGNALED:
    case GL_CONDITION_SATISFIED: return Status::Signaled;
    case GL_TIMEOUT_EXPIRED: return Status::TimeoutExpired;
    default: throw Error("Fence::clientWait: glClientWaitSync failed");
    }
}

void Fence::serverWait() const
{
    detail::ContextState& state = detail::requireCurrent(_device, "Fence::serverWait");
    if (!_sync) {
        throw Error("Fence::serverWait: empty fence");
    }
    state.gl.glWaitSync(static_cast<GLsync>(_sync), 0, GL_TIMEOUT_IGNORED);
}

} // namespace orbis::renderer
