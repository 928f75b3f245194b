#pragma once

// The GL state one context has, as the renderer last set it (the shadow), and the calls that change
// it only when it differs. One ContextState per GL context; the one current on a thread is found
// through currentState(). Private.

#include "Backend.h"
#include "GlApi.h"

#include "orbis/renderer/ClearState.h"
#include "orbis/renderer/RenderState.h"
#include "orbis/renderer/RenderStatistics.h"

#include <glm/mat4x4.hpp>

#include <array>
#include <cstdint>
#include <memory>

namespace orbis::renderer {
class Device;
}

namespace orbis::renderer::detail {

/// Texture units the shadow tracks; the last usable one is kept for uploads.
inline constexpr int kMaxTrackedTextureUnits = 32;

class ContextState;
/// The state of the context current on this thread (see currentState()).
extern thread_local ContextState* tlsCurrentState;

/// A number no other GL object of the process ever gets: the shadow compares these, not GL names,
/// so a deleted name that GL hands out again is never mistaken for the old object.
std::uint64_t nextObjectSerial() noexcept;

/// The matrix products of the automatic uniforms, kept while the matrices they come from stay the
/// same (consecutive draws usually share the camera, often the model matrix too).
struct MatrixCache {
    bool valid = false;
    glm::dmat4 model{0.0};
    glm::dmat4 view{0.0};
    glm::dmat4 projection{0.0};
    bool haveModelView = false;
    bool haveModelViewProjection = false;
    glm::dmat4 modelView{0.0};
    glm::mat4 modelViewProjection{0.0f}; ///< as sent
};

class ContextState {
public:
    ContextState(Device& device, const GlApi& gl, std::unique_ptr<BackendContext> backend, int commandTextureUnits);
    ~ContextState();
    ContextState(const ContextState&) = delete;
    ContextState& operator=(const ContextState&) = delete;

    /// Makes the context current on this thread and records it as this thread's state.
    void makeCurrent();
    void releaseCurrent() noexcept;
    bool isCurrent() const noexcept { return tlsCurrentState == this; }

    /// Forgets what GL has: after GL calls made outside the renderer. The next state change
    /// first sets every item to what the shadow holds, making it true again.
    void forgetState() noexcept;

    void applyRenderState(const RenderState& state);
    /// The parts of the state a clear obeys: scissor, colour, depth and stencil write masks.
    void applyClearState(const ClearState& clear);
    void applyViewport(const PixelRectangle& viewport);
    /// glClipControl's depth mode: 0..1 when true, GL's -1..1 otherwise (needs glClipControl).
    void applyClipDepthZeroToOne(bool zeroToOne);
    bool clipDepthZeroToOne() const noexcept { return _clipDepthZeroToOne; }

    void bindProgram(std::uint64_t serial, GLuint name);
    void bindVertexArray(std::uint64_t serial, GLuint name);
    void bindFramebuffer(std::uint64_t serial, GLuint name);
    void bindTexture(int unit, std::uint64_t serial, GLuint name);
    void bindSampler(int unit, std::uint64_t serial, GLuint name);
    /// Binds a texture on the unit kept for uploads, so that draw bindings stay as they are.
    void bindTextureForUpload(std::uint64_t serial, GLuint name);

    Device& device;
    const GlApi& gl;
    std::unique_ptr<BackendContext> backend;
    const int commandTextureUnits; ///< units 0..commandTextureUnits-1 are for draw commands
    RenderStatistics statistics;
    std::uint64_t glCallsAtReset = 0;
    MatrixCache matrices;
    bool debugOutput = false; ///< ask for KHR_debug messages on first make-current
    // Clear values GL has (glClearColor, glClearDepth, glClearStencil).
    float clearColor[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    double clearDepth = 1.0;
    int clearStencil = 0;

private:
    void initialize();
    void activeTexture(int unit);
    /// When the shadow is unknown, sets GL to it with every call.
    void ensureKnown();

    bool _initialized = false;
    bool _known = true;
    // The state last asked for, when GL has it: asking for the same again skips the item-by-item
    // comparison (only a memcmp). Items it stands for, all found set: _lastWantedItems.
    bool _lastWantedValid = false;
    RenderState _lastWanted;
    std::uint64_t _lastWantedItems = 0;
    RenderState _state;     ///< what GL has
    PixelRectangle _viewport{-1, -1, -1, -1};
    bool _clipDepthZeroToOne = false;
    std::uint64_t _program = 0;
    std::uint64_t _vertexArray = 0;
    std::uint64_t _framebuffer = 0;
    int _activeUnit = 0;
    std::array<std::uint64_t, kMaxTrackedTextureUnits> _textures{};
    std::array<std::uint64_t, kMaxTrackedTextureUnits> _samplers{};
};

/// The state of the context current on this thread; null when none is.
ContextState* currentState() noexcept;
void setCurrentState(ContextState* state) noexcept;
/// The current state, which must belong to `device`; throws orbis::Error naming `what` otherwise.
ContextState& requireCurrent(const Device* device, const char* what);
/// The current state when it belongs to `device`, for destructors; null otherwise.
ContextState* currentStateOf(const Device* device) noexcept;

} // namespace orbis::renderer::detail
