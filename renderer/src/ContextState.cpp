#include "ContextState.h"

#include "GlEnums.h"

#include "orbis/core/Error.h"

#include <atomic>
#include <cstring>
#include <cstdio>
#include <string>

namespace orbis::renderer::detail {
thread_local ContextState* tlsCurrentState = nullptr;

namespace {

void APIENTRY printDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                const GLchar* message, const void* userParam)
{
    (void)source;
    (void)userParam;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION || (severity == GL_DEBUG_SEVERITY_LOW && type != GL_DEBUG_TYPE_ERROR)) {
        return;
    }
    const char* kind = type == GL_DEBUG_TYPE_ERROR                 ? "error"
                       : type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR ? "deprecated"
                       : type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR  ? "undefined behaviour"
                       : type == GL_DEBUG_TYPE_PERFORMANCE         ? "performance"
                       : type == GL_DEBUG_TYPE_PORTABILITY         ? "portability"
                                                                   : "message";
    std::fprintf(stderr, "orbis: GL %s %u: %.*s\n", kind, id, static_cast<int>(length), message);
}

/// The GL state of a new context, which the shadow starts from.
RenderState glInitialState()
{
    RenderState s;
    s.primitiveRestart = {false, 0};
    s.facetCulling = {false, CullFace::Back, WindingOrder::Counterclockwise};
    s.rasterizationMode = RasterizationMode::Fill;
    // The initial scissor box is the first surface's size: unknown here, so never equal.
    s.scissorTest = {false, {-1, -1, -1, -1}};
    s.stencilTest.enabled = false;
    s.depthTest = {false, CompareFunction::Less};
    s.depthRange = {0.0, 1.0};
    s.depthClamp = false;
    s.blending = Blending{};
    s.colorMask = {};
    s.depthMask = true;
    s.polygonOffset = {false, 0.0f, 0.0f};
    s.programPointSize = false;
    return s;
}

} // namespace

std::uint64_t nextObjectSerial() noexcept
{
    static std::atomic<std::uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

ContextState* currentState() noexcept
{
    return tlsCurrentState;
}

void setCurrentState(ContextState* state) noexcept
{
    tlsCurrentState = state;
}

ContextState& requireCurrent(const Device* device, const char* what)
{
    if (!device) {
        throw Error(std::string(what) + ": the object is empty (default-constructed or moved from)");
    }
    ContextState* state = tlsCurrentState;
    if (!state) {
        throw Error(std::string(what) + ": no Orbis context is current on this thread (call Context::makeCurrent)");
    }
    if (&state->device != device) {
        throw Error(std::string(what) + ": the context current on this thread belongs to another Device");
    }
    return *state;
}

ContextState* currentStateOf(const Device* device) noexcept
{
    ContextState* state = tlsCurrentState;
    return state && &state->device == device ? state : nullptr;
}

ContextState::ContextState(Device& device_, const GlApi& gl_, std::unique_ptr<BackendContext> backend_,
                           int commandTextureUnits_)
    : device(device_)
    , gl(gl_)
    , backend(std::move(backend_))
    , commandTextureUnits(commandTextureUnits_)
    , _state(glInitialState())
{
}

ContextState::~ContextState()
{
    if (tlsCurrentState == this) {
        backend->releaseCurrent();
        tlsCurrentState = nullptr;
    }
}

void ContextState::makeCurrent()
{
    backend->makeCurrent();
    tlsCurrentState = this;
    if (!_initialized) {
        initialize();
    }
}

void ContextState::releaseCurrent() noexcept
{
    backend->releaseCurrent();
    if (tlsCurrentState == this) {
        tlsCurrentState = nullptr;
    }
}

void ContextState::initialize()
{
    _initialized = true;
    // Rows in system memory are tightly packed (RGB8 rows need not be multiples of 4 bytes).
    gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (debugOutput && gl.glDebugMessageCallback) {
        gl.glEnable(GL_DEBUG_OUTPUT);
        gl.glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        gl.glDebugMessageCallback(&printDebugMessage, nullptr);
    }
}

void ContextState::forgetState() noexcept
{
    constexpr std::uint64_t unknown = ~std::uint64_t{0}; // a serial no object has
    _known = false;
    _lastWantedValid = false;
    _viewport = {-1, -1, -1, -1};
    _program = unknown;
    _vertexArray = unknown;
    _framebuffer = unknown;
    _activeUnit = -1;
    _textures.fill(unknown);
    _samplers.fill(unknown);
    clearColor[0] = -1.0f; // outside 0..1: a clear always sets it
    clearDepth = -1.0;
    clearStencil = -1;
}

void ContextState::ensureKnown()
{
    if (_known) {
        return;
    }
    _known = true;
    const RenderState& s = _state;
    auto enable = [&](bool on, GLenum capability) {
        if (on) {
            gl.glEnable(capability);
        } else {
            gl.glDisable(capability);
        }
    };
    enable(s.primitiveRestart.enabled, GL_PRIMITIVE_RESTART);
    gl.glPrimitiveRestartIndex(s.primitiveRestart.index);
    enable(s.facetCulling.enabled, GL_CULL_FACE);
    gl.glCullFace(toGl(s.facetCulling.face));
    gl.glFrontFace(toGl(s.facetCulling.frontFaceWindingOrder));
    gl.glPolygonMode(GL_FRONT_AND_BACK, toGl(s.rasterizationMode));
    enable(s.scissorTest.enabled, GL_SCISSOR_TEST);
    if (s.scissorTest.rectangle.width >= 0 && s.scissorTest.rectangle.height >= 0) {
        const PixelRectangle& r = s.scissorTest.rectangle;
        gl.glScissor(r.x, r.y, r.width, r.height);
    }
    enable(s.stencilTest.enabled, GL_STENCIL_TEST);
    const std::pair<const StencilTestFace*, GLenum> faces[] = {{&s.stencilTest.frontFace, GL_FRONT},
                                                                 {&s.stencilTest.backFace, GL_BACK}};
    for (const auto& [face, glFace] : faces) {
        gl.glStencilFuncSeparate(glFace, toGl(face->function), face->referenceValue, face->mask);
        gl.glStencilOpSeparate(glFace, toGl(face->stencilFailOperation), toGl(face->depthFailStencilPassOperation),
                               toGl(face->depthPassStencilPassOperation));
        gl.glStencilMaskSeparate(glFace, face->writeMask);
    }
    enable(s.depthTest.enabled, GL_DEPTH_TEST);
    gl.glDepthFunc(toGl(s.depthTest.function));
    gl.glDepthRange(s.depthRange.nearValue, s.depthRange.farValue);
    enable(s.depthClamp, GL_DEPTH_CLAMP);
    const Blending& b = s.blending;
    enable(b.enabled, GL_BLEND);
    gl.glBlendFuncSeparate(toGl(b.sourceRgbFactor), toGl(b.destinationRgbFactor), toGl(b.sourceAlphaFactor),
                           toGl(b.destinationAlphaFactor));
    gl.glBlendEquationSeparate(toGl(b.rgbEquation), toGl(b.alphaEquation));
    gl.glBlendColor(b.color.r, b.color.g, b.color.b, b.color.a);
    gl.glColorMask(s.colorMask.red, s.colorMask.green, s.colorMask.blue, s.colorMask.alpha);
    gl.glDepthMask(s.depthMask);
    enable(s.polygonOffset.enabled, GL_POLYGON_OFFSET_FILL);
    gl.glPolygonOffset(s.polygonOffset.factor, s.polygonOffset.units);
    enable(s.programPointSize, GL_PROGRAM_POINT_SIZE);
    statistics.stateChangesMade += 30;
}

namespace {

/// Brings one item of GL's state to what a draw wants, counting the calls made and avoided.
class StateDiff {
public:
    explicit StateDiff(const GlApi& gl) noexcept : _gl(gl) {}

    /// Enables or disables a capability when `current` differs from `want`.
    void enable(bool& current, bool want, GLenum capability)
    {
        change(current == want, [&] {
            if (want) {
                _gl.glEnable(capability);
            } else {
                _gl.glDisable(capability);
            }
            current = want;
        });
    }

    /// Sets `current` to `want` with `apply` when they differ.
    template <class T, class Apply>
    void update(T& current, const T& want, Apply&& apply)
    {
        change(current == want, [&] {
            apply();
            current = want;
        });
    }

    /// Runs `apply` (which makes one GL call and records it in the shadow state) unless `same`.
    template <class Apply>
    void change(bool same, Apply&& apply)
    {
        if (same) {
            ++avoided;
            return;
        }
        apply();
        ++made;
    }

    const GlApi& gl() const noexcept { return _gl; }

    std::uint64_t made = 0;
    std::uint64_t avoided = 0;

private:
    const GlApi& _gl;
};

void applyStencilFace(StateDiff& diff, StencilTestFace& current, const StencilTestFace& want, GLenum glFace)
{
    const GlApi& gl = diff.gl();
    diff.change(current.function == want.function && current.referenceValue == want.referenceValue &&
                    current.mask == want.mask,
                [&] {
                    gl.glStencilFuncSeparate(glFace, toGl(want.function), want.referenceValue, want.mask);
                    current.function = want.function;
                    current.referenceValue = want.referenceValue;
                    current.mask = want.mask;
                });
    diff.change(current.stencilFailOperation == want.stencilFailOperation &&
                    current.depthFailStencilPassOperation == want.depthFailStencilPassOperation &&
                    current.depthPassStencilPassOperation == want.depthPassStencilPassOperation,
                [&] {
                    gl.glStencilOpSeparate(glFace, toGl(want.stencilFailOperation),
                                           toGl(want.depthFailStencilPassOperation),
                                           toGl(want.depthPassStencilPassOperation));
                    current.stencilFailOperation = want.stencilFailOperation;
                    current.depthFailStencilPassOperation = want.depthFailStencilPassOperation;
                    current.depthPassStencilPassOperation = want.depthPassStencilPassOperation;
                });
    diff.update(current.writeMask, want.writeMask, [&] { gl.glStencilMaskSeparate(glFace, want.writeMask); });
}

void applyBlending(StateDiff& diff, Blending& current, const Blending& want)
{
    const GlApi& gl = diff.gl();
    diff.enable(current.enabled, want.enabled, GL_BLEND);
    if (!want.enabled) {
        return; // the function is left alone while blending is off
    }
    diff.change(current.sourceRgbFactor == want.sourceRgbFactor && current.sourceAlphaFactor == want.sourceAlphaFactor &&
                    current.destinationRgbFactor == want.destinationRgbFactor &&
                    current.destinationAlphaFactor == want.destinationAlphaFactor,
                [&] {
                    gl.glBlendFuncSeparate(toGl(want.sourceRgbFactor), toGl(want.destinationRgbFactor),
                                           toGl(want.sourceAlphaFactor), toGl(want.destinationAlphaFactor));
                    current.sourceRgbFactor = want.sourceRgbFactor;
                    current.sourceAlphaFactor = want.sourceAlphaFactor;
                    current.destinationRgbFactor = want.destinationRgbFactor;
                    current.destinationAlphaFactor = want.destinationAlphaFactor;
                });
    diff.change(current.rgbEquation == want.rgbEquation && current.alphaEquation == want.alphaEquation, [&] {
        gl.glBlendEquationSeparate(toGl(want.rgbEquation), toGl(want.alphaEquation));
        current.rgbEquation = want.rgbEquation;
        current.alphaEquation = want.alphaEquation;
    });
    diff.update(current.color, want.color,
                [&] { gl.glBlendColor(want.color.r, want.color.g, want.color.b, want.color.a); });
}

} // namespace

void ContextState::applyRenderState(const RenderState& wanted)
{
    if (_lastWantedValid && std::memcmp(&_lastWanted, &wanted, sizeof wanted) == 0) {
        statistics.stateChangesAvoided += _lastWantedItems;
        return;
    }
    ensureKnown();
    RenderState& s = _state;
    StateDiff diff(gl);
    // Items of a disabled group (the cull face while culling is off) are left alone.
    const PrimitiveRestart& restart = wanted.primitiveRestart;
    diff.enable(s.primitiveRestart.enabled, restart.enabled, GL_PRIMITIVE_RESTART);
    if (restart.enabled) {
        diff.update(s.primitiveRestart.index, restart.index, [&] { gl.glPrimitiveRestartIndex(restart.index); });
    }
    const FacetCulling& culling = wanted.facetCulling;
    diff.enable(s.facetCulling.enabled, culling.enabled, GL_CULL_FACE);
    if (culling.enabled) {
        diff.update(s.facetCulling.face, culling.face, [&] { gl.glCullFace(toGl(culling.face)); });
    }
    // The winding also decides gl_FrontFacing and which stencil face applies: set it always.
    diff.update(s.facetCulling.frontFaceWindingOrder, culling.frontFaceWindingOrder,
                [&] { gl.glFrontFace(toGl(culling.frontFaceWindingOrder)); });
    diff.update(s.rasterizationMode, wanted.rasterizationMode,
                [&] { gl.glPolygonMode(GL_FRONT_AND_BACK, toGl(wanted.rasterizationMode)); });
    const ScissorTest& scissor = wanted.scissorTest;
    diff.enable(s.scissorTest.enabled, scissor.enabled, GL_SCISSOR_TEST);
    if (scissor.enabled) {
        diff.update(s.scissorTest.rectangle, scissor.rectangle, [&] {
            const PixelRectangle& r = scissor.rectangle;
            gl.glScissor(r.x, r.y, r.width, r.height);
        });
    }
    const StencilTest& stencil = wanted.stencilTest;
    diff.enable(s.stencilTest.enabled, stencil.enabled, GL_STENCIL_TEST);
    if (stencil.enabled) {
        applyStencilFace(diff, s.stencilTest.frontFace, stencil.frontFace, GL_FRONT);
        applyStencilFace(diff, s.stencilTest.backFace, stencil.backFace, GL_BACK);
    }
    const DepthTest& depth = wanted.depthTest;
    diff.enable(s.depthTest.enabled, depth.enabled, GL_DEPTH_TEST);
    if (depth.enabled) {
        diff.update(s.depthTest.function, depth.function, [&] { gl.glDepthFunc(toGl(depth.function)); });
    }
    diff.update(s.depthRange, wanted.depthRange,
                [&] { gl.glDepthRange(wanted.depthRange.nearValue, wanted.depthRange.farValue); });
    // Counted only once a draw has asked for it, so that frames without shadow volumes count
    // their state changes as they always have.
    if (wanted.depthClamp || s.depthClamp) {
        diff.enable(s.depthClamp, wanted.depthClamp, GL_DEPTH_CLAMP);
    }
    applyBlending(diff, s.blending, wanted.blending);
    diff.update(s.colorMask, wanted.colorMask, [&] {
        const ColorMask& m = wanted.colorMask;
        gl.glColorMask(m.red, m.green, m.blue, m.alpha);
    });
    diff.update(s.depthMask, wanted.depthMask, [&] { gl.glDepthMask(wanted.depthMask); });
    const PolygonOffset& offset = wanted.polygonOffset;
    diff.enable(s.polygonOffset.enabled, offset.enabled, GL_POLYGON_OFFSET_FILL);
    if (offset.enabled) {
        diff.change(s.polygonOffset.factor == offset.factor && s.polygonOffset.units == offset.units, [&] {
            gl.glPolygonOffset(offset.factor, offset.units);
            s.polygonOffset.factor = offset.factor;
            s.polygonOffset.units = offset.units;
        });
    }
    diff.enable(s.programPointSize, wanted.programPointSize, GL_PROGRAM_POINT_SIZE);

    statistics.stateChangesMade += diff.made;
    statistics.stateChangesAvoided += diff.avoided;
    // Copied whole, padding included, so that the next memcmp of an equal copy can match.
    std::memcpy(static_cast<void*>(&_lastWanted), &wanted, sizeof wanted);
    _lastWantedItems = diff.made + diff.avoided;
    _lastWantedValid = true;
}

void ContextState::applyClearState(const ClearState& clear)
{
    _lastWantedValid = false; // a clear sets the scissor and the masks its own way
    ensureKnown();
    std::uint64_t made = 0;
    std::uint64_t avoided = 0;
    RenderState& s = _state;
    auto count = [&](bool changed) { ++(changed ? made : avoided); };

    if (s.scissorTest.enabled != clear.scissorTest.enabled) {
        if (clear.scissorTest.enabled) {
            gl.glEnable(GL_SCISSOR_TEST);
        } else {
            gl.glDisable(GL_SCISSOR_TEST);
        }
        s.scissorTest.enabled = clear.scissorTest.enabled;
        count(true);
    } else {
        count(false);
    }
    if (clear.scissorTest.enabled) {
        const PixelRectangle& r = clear.scissorTest.rectangle;
        const bool changed = !(s.scissorTest.rectangle == r);
        if (changed) {
            gl.glScissor(r.x, r.y, r.width, r.height);
            s.scissorTest.rectangle = r;
        }
        count(changed);
    }
    if (hasAny(clear.buffers, ClearBuffers::Color)) {
        const bool changed = !(s.colorMask == clear.colorMask);
        if (changed) {
            const ColorMask& m = clear.colorMask;
            gl.glColorMask(m.red, m.green, m.blue, m.alpha);
            s.colorMask = m;
        }
        count(changed);
    }
    if (hasAny(clear.buffers, ClearBuffers::Depth)) {
        const bool changed = s.depthMask != clear.depthMask;
        if (changed) {
            gl.glDepthMask(clear.depthMask);
            s.depthMask = clear.depthMask;
        }
        count(changed);
    }
    if (hasAny(clear.buffers, ClearBuffers::Stencil)) {
        auto mask = [&](std::uint32_t& current, std::uint32_t want, GLenum face) {
            const bool changed = current != want;
            if (changed) {
                gl.glStencilMaskSeparate(face, want);
                current = want;
            }
            count(changed);
        };
        mask(s.stencilTest.frontFace.writeMask, clear.frontStencilMask, GL_FRONT);
        mask(s.stencilTest.backFace.writeMask, clear.backStencilMask, GL_BACK);
    }
    statistics.stateChangesMade += made;
    statistics.stateChangesAvoided += avoided;
}

void ContextState::applyViewport(const PixelRectangle& viewport)
{
    if (_viewport == viewport) {
        ++statistics.stateChangesAvoided;
        return;
    }
    gl.glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
    _viewport = viewport;
    ++statistics.stateChangesMade;
}

void ContextState::applyClipDepthZeroToOne(bool zeroToOne)
{
    if (_clipDepthZeroToOne == zeroToOne) {
        return; // not counted as avoided: it is not part of a command's RenderState
    }
    gl.glClipControl(GL_LOWER_LEFT, zeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    _clipDepthZeroToOne = zeroToOne;
    ++statistics.stateChangesMade;
}

void ContextState::bindProgram(std::uint64_t serial, GLuint name)
{
    if (_program == serial) {
        ++statistics.bindsAvoided;
        return;
    }
    gl.glUseProgram(name);
    _program = serial;
    ++statistics.programBinds;
}

void ContextState::bindVertexArray(std::uint64_t serial, GLuint name)
{
    if (_vertexArray == serial) {
        ++statistics.bindsAvoided;
        return;
    }
    gl.glBindVertexArray(name);
    _vertexArray = serial;
    ++statistics.vertexArrayBinds;
}

void ContextState::bindFramebuffer(std::uint64_t serial, GLuint name)
{
    if (_framebuffer == serial) {
        ++statistics.bindsAvoided;
        return;
    }
    gl.glBindFramebuffer(GL_FRAMEBUFFER, name);
    _framebuffer = serial;
    ++statistics.framebufferBinds;
}

void ContextState::activeTexture(int unit)
{
    if (_activeUnit != unit) { // -1 after forgetState: never equal
        gl.glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
        _activeUnit = unit;
    }
}

void ContextState::bindTexture(int unit, std::uint64_t serial, GLuint name)
{
    if (_textures[unit] == serial) {
        ++statistics.bindsAvoided;
        return;
    }
    activeTexture(unit);
    gl.glBindTexture(GL_TEXTURE_2D, name);
    _textures[unit] = serial;
    ++statistics.textureBinds;
}

void ContextState::bindSampler(int unit, std::uint64_t serial, GLuint name)
{
    if (_samplers[unit] == serial) {
        ++statistics.bindsAvoided;
        return;
    }
    gl.glBindSampler(static_cast<GLuint>(unit), name);
    _samplers[unit] = serial;
    ++statistics.textureBinds;
}

void ContextState::bindTextureForUpload(std::uint64_t serial, GLuint name)
{
    const int unit = commandTextureUnits; // one past the units commands may use
    if (_textures[unit] == serial && _activeUnit == unit) {
        return;
    }
    activeTexture(unit);
    if (_textures[unit] != serial) {
        gl.glBindTexture(GL_TEXTURE_2D, name);
        _textures[unit] = serial;
    }
}

} // namespace orbis::renderer::detail
