#include "orbis/renderer/Context.h"

#include "AutomaticUniforms.h"
#include "ContextState.h"
#include "GlEnums.h"
#include "ShaderProgramAccess.h"
#include "SplitDouble.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Device.h"
#include "orbis/renderer/Sampler.h"
#include "orbis/renderer/ShaderProgram.h"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

namespace orbis::renderer {
namespace {

/// The texture target a texture is attached as: multisampled or not.
GLenum textureTarget(const Texture2D* texture) noexcept
{
    return texture && texture->samples() > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D;
}

} // namespace

namespace {

using detail::AutomaticUniform;
using detail::ShaderProgramAccess;

using detail::ErrorSource;

std::string commandLabel(const DrawCommand& command)
{
    return ErrorSource{"DrawCommand", command.debugName}.text();
}

std::string framebufferStatusName(GLenum status)
{
    switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED (no default framebuffer)";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT (an attachment cannot be rendered to)";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT (no attachment)";
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED (this combination of formats)";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    default: return "status " + std::to_string(status);
    }
}

template <typename T>
void putAutomatic(ShaderProgram& program, int slot, const T& value, RenderStatistics& statistics)
{
    if (!ShaderProgramAccess::assignRaw(program, slot, &value, sizeof value)) {
        ++statistics.uniformUploadsAvoided;
    }
}

glm::mat4 toFloat(const glm::dmat4& m) noexcept
{
    return glm::mat4(m);
}

/// Fills the og_ uniforms the program uses, each computed in double and sent as float.
void setAutomaticUniforms(ShaderProgram& program, const SceneState& scene, const glm::dmat4& model,
                          const PixelRectangle& viewport, const DepthRange& depthRange, detail::MatrixCache& cache,
                          RenderStatistics& statistics)
{
    const auto& slots = ShaderProgramAccess::automaticSlots(program);
    if (slots.empty()) {
        return;
    }
    if (!cache.valid || std::memcmp(&cache.model, &model, sizeof model) != 0 ||
        std::memcmp(&cache.view, &scene.viewMatrix, sizeof model) != 0 ||
        std::memcmp(&cache.projection, &scene.projectionMatrix, sizeof model) != 0) {
        cache.valid = true;
        cache.model = model;
        cache.view = scene.viewMatrix;
        cache.projection = scene.projectionMatrix;
        cache.haveModelView = false;
        cache.haveModelViewProjection = false;
    }
    auto getModelView = [&]() -> const glm::dmat4& {
        if (!cache.haveModelView) {
            cache.modelView = scene.viewMatrix * model;
            cache.haveModelView = true;
        }
        return cache.modelView;
    };
    auto relativeToEye = [&] {
        glm::dmat4 m = getModelView();
        m[3] = glm::dvec4(0.0, 0.0, 0.0, 1.0);
        return m;
    };
    for (const auto& [id, slot] : slots) {
        switch (static_cast<AutomaticUniform>(id)) {
        case AutomaticUniform::ModelMatrix: putAutomatic(program, slot, toFloat(model), statistics); break;
        case AutomaticUniform::ViewMatrix: putAutomatic(program, slot, toFloat(scene.viewMatrix), statistics); break;
        case AutomaticUniform::ProjectionMatrix:
            putAutomatic(program, slot, toFloat(scene.projectionMatrix), statistics);
            break;
        case AutomaticUniform::ModelViewMatrix: putAutomatic(program, slot, toFloat(getModelView()), statistics); break;
        case AutomaticUniform::ViewProjectionMatrix:
            putAutomatic(program, slot, toFloat(scene.projectionMatrix * scene.viewMatrix), statistics);
            break;
        case AutomaticUniform::ModelViewProjectionMatrix:
            if (!cache.haveModelViewProjection) {
                cache.modelViewProjection = toFloat(scene.projectionMatrix * getModelView());
                cache.haveModelViewProjection = true;
            }
            putAutomatic(program, slot, cache.modelViewProjection, statistics);
            break;
        case AutomaticUniform::NormalMatrix:
            putAutomatic(program, slot, glm::mat3(glm::transpose(glm::inverse(glm::dmat3(getModelView())))), statistics);
            break;
        case AutomaticUniform::ModelViewMatrixRelativeToEye:
            putAutomatic(program, slot, toFloat(relativeToEye()), statistics);
            break;
        case AutomaticUniform::ModelViewProjectionMatrixRelativeToEye:
            putAutomatic(program, slot, toFloat(scene.projectionMatrix * relativeToEye()), statistics);
            break;
        case AutomaticUniform::CameraEye: putAutomatic(program, slot, glm::vec3(scene.cameraEye), statistics); break;
        case AutomaticUniform::CameraEyeHigh:
        case AutomaticUniform::CameraEyeLow: {
            glm::vec3 high;
            glm::vec3 low;
            for (int i = 0; i < 3; ++i) {
                detail::splitDouble(scene.cameraEye[i], high[i], low[i]);
            }
            putAutomatic(program, slot, static_cast<AutomaticUniform>(id) == AutomaticUniform::CameraEyeHigh ? high : low,
                         statistics);
            break;
        }
        case AutomaticUniform::CameraEyeHigh65536:
        case AutomaticUniform::CameraEyeLow65536: {
            glm::vec3 high;
            glm::vec3 low;
            for (int i = 0; i < 3; ++i) {
                const double truncated = std::trunc(scene.cameraEye[i] / 65536.0) * 65536.0;
                high[i] = static_cast<float>(truncated);
                low[i] = static_cast<float>(scene.cameraEye[i] - truncated);
            }
            putAutomatic(program, slot,
                         static_cast<AutomaticUniform>(id) == AutomaticUniform::CameraEyeHigh65536 ? high : low,
                         statistics);
            break;
        }
        case AutomaticUniform::Viewport:
            putAutomatic(program, slot,
                         glm::vec4(float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height)),
                         statistics);
            break;
        case AutomaticUniform::InverseViewportDimensions:
            putAutomatic(program, slot, glm::vec2(1.0f / float(viewport.width), 1.0f / float(viewport.height)),
                         statistics);
            break;
        case AutomaticUniform::ViewportTransformationMatrix: {
            const double halfWidth = 0.5 * viewport.width;
            const double halfHeight = 0.5 * viewport.height;
            const double halfDepth = 0.5 * (depthRange.farValue - depthRange.nearValue);
            glm::dmat4 m(1.0);
            m[0][0] = halfWidth;
            m[1][1] = halfHeight;
            m[2][2] = halfDepth;
            m[3] = glm::dvec4(viewport.x + halfWidth, viewport.y + halfHeight, depthRange.nearValue + halfDepth, 1.0);
            putAutomatic(program, slot, toFloat(m), statistics);
            break;
        }
        case AutomaticUniform::NearDistance: putAutomatic(program, slot, float(scene.nearDistance), statistics); break;
        case AutomaticUniform::FarDistance: putAutomatic(program, slot, float(scene.farDistance), statistics); break;
        case AutomaticUniform::LogarithmicDepth: {
            const double ratio = scene.farDistance / scene.nearDistance;
            const double scale = ratio > 1.0 && std::isfinite(ratio) ? 1.0 / std::log2(ratio) : 1.0;
            putAutomatic(program, slot, glm::vec2(float(1.0 / scene.nearDistance), float(scale)), statistics);
            break;
        }
        case AutomaticUniform::OwnedDepthRange: {
            auto finite = [](double d) { return static_cast<float>(std::min(d, static_cast<double>(FLT_MAX))); };
            putAutomatic(program, slot, glm::vec2(finite(scene.ownedNearDistance), finite(scene.ownedFarDistance)),
                         statistics);
            break;
        }
        case AutomaticUniform::SunDirection: {
            const double length = glm::length(scene.sunDirection);
            const glm::dvec3 sun = length > 0.0 ? scene.sunDirection / length : glm::dvec3(0.0, 0.0, 1.0);
            putAutomatic(program, slot, glm::vec3(sun), statistics);
            break;
        }
        case AutomaticUniform::SunDirectionEye: {
            const glm::dvec3 eye = glm::dmat3(scene.viewMatrix) * scene.sunDirection;
            const double length = glm::length(eye);
            putAutomatic(program, slot, glm::vec3(length > 0.0 ? eye / length : glm::dvec3(0.0, 0.0, 1.0)),
                         statistics);
            break;
        }
        case AutomaticUniform::Time: putAutomatic(program, slot, float(scene.timeSeconds), statistics); break;
        case AutomaticUniform::OpaqueOne: putAutomatic(program, slot, 1.0f, statistics); break;
        case AutomaticUniform::Count: break;
        }
    }
}

} // namespace

Context::Context(Device& /*device*/, std::unique_ptr<detail::ContextState> state)
    : _state(std::move(state))
{
}

Context::~Context() = default;

Device& Context::device() const noexcept
{
    return _state->device;
}

void Context::makeCurrent()
{
    _state->makeCurrent();
}

void Context::releaseCurrent() noexcept
{
    _state->releaseCurrent();
}

bool Context::isCurrent() const noexcept
{
    return _state->isCurrent();
}

PixelRectangle Context::targetRectangle(const Framebuffer* framebuffer) const noexcept
{
    if (framebuffer) {
        return {0, 0, framebuffer->width(), framebuffer->height()};
    }
    PixelRectangle r;
    _state->backend->defaultFramebufferSize(r.width, r.height);
    return r;
}

Framebuffer* Context::bindTarget(Framebuffer* requested, const detail::ErrorSource& source)
{
    auto where = [&] { return source.text(); }; // put into words only on the way to an error
    detail::ContextState& state = *_state;
    if (!state.isCurrent()) {
        throw Error(where() + ": the context is not current on this thread");
    }
    Framebuffer* framebuffer = requested ? requested : _framebuffer;
    if (!framebuffer) {
        if (!state.backend->hasDefaultFramebuffer()) {
            throw Error(where() +
                        ": no framebuffer to draw into (a headless context has no default framebuffer: pass one in "
                        "the command or call Context::setFramebuffer)");
        }
        state.bindFramebuffer(0, 0);
        return nullptr;
    }
    if (!framebuffer->valid()) {
        throw Error(where() + ": the framebuffer is empty");
    }
    if (framebuffer->_owner != &state) {
        throw Error(where() + ": the framebuffer belongs to another context (framebuffers are not shared)");
    }
    state.bindFramebuffer(framebuffer->_serial, framebuffer->_name);
    if (framebuffer->_dirty) {
        const detail::GlApi& gl = state.gl;
        GLenum drawBuffers[Framebuffer::kMaxColorAttachments];
        GLenum readBuffer = GL_NONE;
        GLsizei drawBufferCount = 0;
        for (int i = 0; i < Framebuffer::kMaxColorAttachments; ++i) {
            const auto& texture = framebuffer->_colors[i];
            const GLenum attachment = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i);
            if (i < device().info().maxColorAttachments) {
                gl.glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, textureTarget(texture.get()),
                                          texture ? texture->_name : 0u, 0);
            } else if (texture) {
                throw Error(where() + ": colour attachment " + std::to_string(i) + " is beyond the device's " +
                            std::to_string(device().info().maxColorAttachments));
            }
            if (texture) {
                drawBuffers[i] = attachment;
                drawBufferCount = i + 1;
                if (readBuffer == GL_NONE) {
                    readBuffer = attachment;
                }
            } else {
                drawBuffers[i] = GL_NONE;
            }
        }
        const auto& depth = framebuffer->_depth;
        const bool depthStencil = depth && hasStencil(depth->format());
        gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D, 0u, 0);
        if (depth) {
            gl.glFramebufferTexture2D(GL_FRAMEBUFFER, depthStencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                                      textureTarget(depth.get()), depth->_name, 0);
        }
        if (drawBufferCount > 0) {
            gl.glDrawBuffers(drawBufferCount, drawBuffers);
        } else {
            const GLenum none = GL_NONE;
            gl.glDrawBuffers(1, &none);
        }
        gl.glReadBuffer(readBuffer);
        const GLenum status = gl.glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            throw Error(where() + ": the framebuffer is incomplete: " + framebufferStatusName(status));
        }
        framebuffer->_dirty = false;
    }
    return framebuffer;
}

void Context::clear(const ClearState& clearState)
{
    clear(clearState, nullptr);
}

void Context::clear(const ClearState& clearState, Framebuffer* framebuffer)
{
    detail::ContextState& state = *_state;
    bindTarget(framebuffer, ErrorSource{"Context::clear", {}});
    state.applyClearState(clearState);
    const detail::GlApi& gl = state.gl;
    GLbitfield mask = 0;
    if (hasAny(clearState.buffers, ClearBuffers::Color)) {
        const glm::vec4& c = clearState.color;
        if (std::memcmp(state.clearColor, &c[0], sizeof state.clearColor) != 0) {
            gl.glClearColor(c.r, c.g, c.b, c.a);
            std::memcpy(state.clearColor, &c[0], sizeof state.clearColor);
        }
        mask |= GL_COLOR_BUFFER_BIT;
    }
    if (hasAny(clearState.buffers, ClearBuffers::Depth)) {
        if (state.clearDepth != clearState.depth) {
            gl.glClearDepth(clearState.depth);
            state.clearDepth = clearState.depth;
        }
        mask |= GL_DEPTH_BUFFER_BIT;
    }
    if (hasAny(clearState.buffers, ClearBuffers::Stencil)) {
        if (state.clearStencil != clearState.stencil) {
            gl.glClearStencil(clearState.stencil);
            state.clearStencil = clearState.stencil;
        }
        mask |= GL_STENCIL_BUFFER_BIT;
    }
    if (mask) {
        gl.glClear(mask);
        ++state.statistics.clears;
    }
}

void Context::draw(const DrawCommand& command)
{
    static const SceneState identity;
    draw(command, identity);
}

namespace {

/// Asks the CPU to fetch the command that follows `command` in memory. Commands are a few hundred
/// bytes of plain data, usually kept one after another in a vector: fetching the next while the
/// driver works on this one hides most of the memory latency of reading it. A prefetch never
/// faults, so an address past the end of an allocation is harmless.
inline void prefetchFollowing(const DrawCommand& command, std::size_t distance) noexcept
{
    const std::uintptr_t next = reinterpret_cast<std::uintptr_t>(&command) + distance * sizeof(DrawCommand);
    for (std::size_t offset = 0; offset < sizeof(DrawCommand); offset += 64) {
        __builtin_prefetch(reinterpret_cast<const void*>(next + offset));
    }
}

/// Each comparison as seen with near and far swapped: Less becomes Greater, Equal stays.
CompareFunction mirrored(CompareFunction function) noexcept
{
    switch (function) {
    case CompareFunction::Less: return CompareFunction::Greater;
    case CompareFunction::LessOrEqual: return CompareFunction::GreaterOrEqual;
    case CompareFunction::Greater: return CompareFunction::Less;
    case CompareFunction::GreaterOrEqual: return CompareFunction::LessOrEqual;
    default: return function;
    }
}

} // namespace

void Context::draw(std::span<const DrawCommand> commands, const SceneState& scene)
{
    for (const DrawCommand& command : commands) {
        draw(command, scene); // each fetches the one two ahead
    }
}

std::size_t Context::checkDrawable(const DrawCommand& command, const SceneState& scene) const
{
    const detail::ContextState& state = *_state;
    if (!state.isCurrent()) {
        throw Error(commandLabel(command) + ": the context is not current on this thread");
    }
    const ShaderProgram* program = command.shaderProgram;
    const VertexArray* array = command.vertexArray;
    if (!program || !program->valid()) {
        throw Error(commandLabel(command) + ": no shader program");
    }
    if (!array || !array->valid()) {
        throw Error(commandLabel(command) + ": no vertex array");
    }
    if (ShaderProgramAccess::device(*program) != &state.device) {
        throw Error(commandLabel(command) + ": the shader program belongs to another Device");
    }
    if (array->_owner != &state) {
        throw Error(commandLabel(command) + ": the vertex array belongs to another context");
    }
    if (const std::uint32_t missing = program->attributeMask() & ~array->attributeMask(); missing != 0) {
        std::string names;
        for (const ShaderVertexAttribute& attribute : program->vertexAttributes()) {
            if (attribute.location >= 0 && (missing & (1u << attribute.location))) {
                names += (names.empty() ? "'" : ", '") + attribute.name + "' (location " +
                         std::to_string(attribute.location) + ")";
            }
        }
        throw Error(commandLabel(command) + ": shader program '" + program->name() + "' reads vertex attribute " +
                    names + " but the vertex array does not supply it");
    }
    const std::size_t available = array->indexed() ? array->indexCount() : array->vertexCount();
    if (command.first > available) {
        throw Error(commandLabel(command) + ": first " + std::to_string(command.first) + " is past the " +
                    std::to_string(available) + (array->indexed() ? " indices" : " vertices") + " of the vertex array");
    }
    const std::size_t count = command.count.value_or(available - command.first);
    if (count > available - command.first) {
        throw Error(commandLabel(command) + ": draws " + (array->indexed() ? "indices [" : "vertices [") +
                    std::to_string(command.first) + ", " + std::to_string(command.first + count) +
                    ") but the vertex array has " + std::to_string(available));
    }
    if (scene.depthConvention == DepthConvention::Complementary && !device().info().clipControl) [[unlikely]] {
        throw Error(commandLabel(command) +
                    ": complementary depth needs glClipControl (OpenGL 4.5 or GL_ARB_clip_control) for a 0..1 "
                    "clip-space depth range, and this driver (" + device().info().renderer + ", OpenGL " +
                    device().info().version + ") has neither");
    }
    return count;
}

PixelRectangle Context::applyDrawState(const DrawCommand& command, const SceneState& scene,
                                       const detail::ErrorSource& source)
{
    detail::ContextState& state = *_state;
    Framebuffer* target = bindTarget(command.framebuffer, source);
    const PixelRectangle viewport = scene.viewport.width > 0 && scene.viewport.height > 0 ? scene.viewport
                                                                                          : targetRectangle(target);
    state.applyViewport(viewport);
    const bool complementary = scene.depthConvention == DepthConvention::Complementary;
    if (complementary) [[unlikely]] {
        RenderState renderState = command.renderState;
        renderState.depthTest.function = mirrored(renderState.depthTest.function);
        renderState.polygonOffset.factor = -renderState.polygonOffset.factor;
        renderState.polygonOffset.units = -renderState.polygonOffset.units;
        state.applyRenderState(renderState);
    } else {
        state.applyRenderState(command.renderState);
    }
    if (complementary || state.clipDepthZeroToOne()) [[unlikely]] {
        state.applyClipDepthZeroToOne(complementary);
    }
    state.bindProgram(ShaderProgramAccess::serial(*command.shaderProgram),
                      ShaderProgramAccess::handle(*command.shaderProgram));
    state.bindVertexArray(command.vertexArray->_serial, command.vertexArray->_name);
    return viewport;
}

std::uint32_t Context::bindTextures(const DrawCommand& command)
{
    detail::ContextState& state = *_state;
    std::uint32_t boundUnits = 0;
    for (const TextureBinding& binding : command.textures) {
        if (binding.unit < 0 || binding.unit >= state.commandTextureUnits) {
            throw Error(commandLabel(command) + ": texture unit " + std::to_string(binding.unit) + " is outside 0.." +
                        std::to_string(state.commandTextureUnits - 1));
        }
        if (!binding.texture || !binding.texture->valid()) {
            throw Error(commandLabel(command) + ": no texture on unit " + std::to_string(binding.unit));
        }
        if (binding.texture->samples() > 1) {
            throw Error(commandLabel(command) + ": the texture on unit " + std::to_string(binding.unit) + " is multisampled (" +
                        std::to_string(binding.texture->samples()) + " samples): resolve it with Context::blit first");
        }
        if (binding.texture->_device != &state.device ||
            (binding.sampler && binding.sampler->_device != &state.device)) {
            throw Error(commandLabel(command) + ": the texture or sampler on unit " + std::to_string(binding.unit) +
                        " belongs to another Device");
        }
        state.bindTexture(binding.unit, binding.texture->_serial, binding.texture->_name);
        state.bindSampler(binding.unit, binding.sampler ? binding.sampler->_serial : 0u,
                          binding.sampler ? binding.sampler->_name : 0u);
        boundUnits |= 1u << binding.unit;
    }
    return boundUnits;
}

void Context::setUniforms(const DrawCommand& command, const SceneState& scene, const PixelRectangle& viewport,
                          std::uint32_t boundUnits, const detail::ErrorSource& source)
{
    detail::ContextState& state = *_state;
    ShaderProgram& program = *command.shaderProgram;
    const std::uint64_t programSerial = ShaderProgramAccess::serial(program);
    const UniformValues& uniforms = command.uniforms;
    for (std::size_t i = 0; i < uniforms._count; ++i) {
        const UniformValues::Entry& entry = uniforms.entry(i);
        if (entry.cachedProgramSerial != programSerial) [[unlikely]] {
            entry.cachedSlot = ShaderProgramAccess::findSlot(program, uniforms._names[i]);
            entry.cachedProgramSerial = programSerial;
        }
        if (entry.cachedSlot < 0) [[unlikely]] {
            entry.cachedProgramSerial = 0;
            program.uniformIndex(uniforms._names[i]); // throws, naming the active uniforms
        }
        if (!ShaderProgramAccess::assignBytes(program, entry.cachedSlot, entry.type, uniforms.bytes(entry), entry.size,
                                              source)) {
            ++state.statistics.uniformUploadsAvoided;
        }
    }
    setAutomaticUniforms(program, scene, command.modelMatrix, viewport, command.renderState.depthRange, state.matrices,
                         state.statistics);
    if (ShaderProgramAccess::unsetCount(program) != 0) {
        ShaderProgramAccess::checkAllSet(program, commandLabel(command));
    }
    for (const int slot : ShaderProgramAccess::samplerSlots(program)) {
        const int unit = ShaderProgramAccess::samplerUnitOfSlot(program, slot);
        if (unit < 0 || unit >= 32 || !(boundUnits & (1u << unit))) {
            throw Error(commandLabel(command) + ": shader program '" + program.name() + "' samples " +
                        ShaderProgramAccess::uniformName(program, slot) + " from texture unit " + std::to_string(unit) +
                        " but the command binds no texture there");
        }
    }
    state.statistics.uniformUploads += ShaderProgramAccess::flush(program, state.gl);
}

void Context::draw(const DrawCommand& command, const SceneState& scene)
{
    prefetchFollowing(command, 2);
    // Check, set the state, bind, set the uniforms, then draw: nothing reaches GL for a command
    // that fails its checks.
    const std::size_t count = checkDrawable(command, scene);
    const ErrorSource source{"DrawCommand", command.debugName};
    const PixelRectangle viewport = applyDrawState(command, scene, source);
    const std::uint32_t boundUnits = bindTextures(command);
    setUniforms(command, scene, viewport, boundUnits, source);
    if (count == 0) {
        return;
    }
    detail::ContextState& state = *_state;
    const VertexArray& array = *command.vertexArray;
    const GLenum mode = detail::toGl(command.primitiveType);
    if (array.indexed()) {
        const std::size_t offset = command.first * indexSize(array.indexType());
        state.gl.glDrawElements(mode, static_cast<GLsizei>(count), detail::toGl(array.indexType()),
                                reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset)));
    } else {
        state.gl.glDrawArrays(mode, static_cast<GLint>(command.first), static_cast<GLsizei>(count));
    }
    ++state.statistics.drawCalls;
    state.statistics.primitives += detail::primitiveCount(command.primitiveType, count);
    state.statistics.vertices += count;
}

std::vector<float> Context::captureVertexOutputs(const DrawCommand& command, const SceneState& scene)
{
    ShaderProgram* program = command.shaderProgram;
    const VertexArray* array = command.vertexArray;
    if (!program || !program->valid() || !array || !array->valid()) {
        draw(command, scene); // throws, saying what is missing
    }
    if (program->capturedComponents() == 0) {
        throw Error(commandLabel(command) + ": shader program '" + program->name() +
                    "' captures nothing (build it with ShaderProgramDescription::transformFeedbackVaryings)");
    }
    GLenum captureMode = GL_POINTS;
    std::size_t verticesPerPrimitive = 1;
    switch (command.primitiveType) {
    case PrimitiveType::Points: break;
    case PrimitiveType::Lines:
    case PrimitiveType::LineStrip:
    case PrimitiveType::LinesAdjacency:
    case PrimitiveType::LineStripAdjacency:
        captureMode = GL_LINES;
        verticesPerPrimitive = 2;
        break;
    case PrimitiveType::Triangles:
    case PrimitiveType::TriangleStrip:
        captureMode = GL_TRIANGLES;
        verticesPerPrimitive = 3;
        break;
    }
    // The count draw() will take (it checks it too).
    const std::size_t available = array->indexed() ? array->indexCount() : array->vertexCount();
    const std::size_t count = std::min(command.count.value_or(available - std::min(command.first, available)),
                                       available - std::min(command.first, available));
    const std::size_t records = detail::primitiveCount(command.primitiveType, count) * verticesPerPrimitive;
    std::vector<float> captured(records * static_cast<std::size_t>(program->capturedComponents()));
    if (captured.empty()) {
        return captured;
    }

    detail::ContextState& state = *_state;
    const detail::GlApi& gl = state.gl;
    GLuint buffer = 0;
    gl.glGenBuffers(1, &buffer);
    struct Guard {
        const detail::GlApi& gl;
        GLuint name;
        bool active = false;
        ~Guard()
        {
            if (active) {
                gl.glEndTransformFeedback.unchecked();
            }
            gl.glBindBufferBase.unchecked(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
            gl.glDeleteBuffers.unchecked(1, &name);
            gl.glDisable.unchecked(GL_RASTERIZER_DISCARD);
        }
    } guard{gl, buffer};
    gl.glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, buffer);
    gl.glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, static_cast<GLsizeiptr>(captured.size() * sizeof(float)), nullptr,
                    GL_STREAM_READ);
    gl.glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, buffer);
    gl.glEnable(GL_RASTERIZER_DISCARD);
    // Transform feedback begins with the capturing program bound; draw() then finds it bound.
    state.bindProgram(ShaderProgramAccess::serial(*program), ShaderProgramAccess::handle(*program));
    gl.glBeginTransformFeedback(captureMode);
    guard.active = true;
    draw(command, scene);
    gl.glEndTransformFeedback();
    guard.active = false;
    gl.glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, static_cast<GLsizeiptr>(captured.size() * sizeof(float)),
                          captured.data());
    return captured;
}

PixelRectangle Context::bindReadSource(const Framebuffer* framebuffer, int colorAttachment)
{
    detail::ContextState& state = *_state;
    Framebuffer* target = bindTarget(const_cast<Framebuffer*>(framebuffer), ErrorSource{"Context::readPixels", {}});
    if (target) {
        if (colorAttachment < 0 || colorAttachment >= Framebuffer::kMaxColorAttachments ||
            !target->_colors[colorAttachment]) {
            throw Error("Context::readPixels: the framebuffer has no colour attachment " +
                        std::to_string(colorAttachment));
        }
        state.gl.glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(colorAttachment));
    } else {
        state.gl.glReadBuffer(GL_BACK);
    }
    return targetRectangle(target);
}

void Context::readPixels(PixelBuffer& destination, const Framebuffer* framebuffer, int colorAttachment)
{
    detail::ContextState& state = *_state;
    const PixelRectangle size = bindReadSource(framebuffer, colorAttachment);
    const std::size_t bytes = static_cast<std::size_t>(size.width) * static_cast<std::size_t>(size.height) * 4;
    if (!destination.valid() || destination.sizeInBytes() < bytes) {
        throw Error("Context::readPixels: " + std::to_string(size.width) + " x " + std::to_string(size.height) +
                    " pixels need a pixel buffer of " + std::to_string(bytes) + " bytes, and this one has " +
                    std::to_string(destination.sizeInBytes()));
    }
    if (bytes == 0) {
        return;
    }
    // Bound only for the copy: every other read (readPixels into memory, texture reads) wants none.
    state.gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, destination._name);
    state.gl.glReadPixels(0, 0, size.width, size.height, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    state.gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

Image Context::readPixels(const Framebuffer* framebuffer, int colorAttachment)
{
    detail::ContextState& state = *_state;
    const PixelRectangle size = bindReadSource(framebuffer, colorAttachment);
    Image image(size.width, size.height, 4);
    if (size.width > 0 && size.height > 0) {
        state.gl.glReadPixels(0, 0, size.width, size.height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
        // GL's rows go bottom to top; an Image's top to bottom.
        const std::size_t rowBytes = static_cast<std::size_t>(size.width) * 4;
        std::vector<std::uint8_t> row(rowBytes);
        for (int y = 0; y < size.height / 2; ++y) {
            std::uint8_t* a = image.pixels.data() + static_cast<std::size_t>(y) * rowBytes;
            std::uint8_t* b = image.pixels.data() + static_cast<std::size_t>(size.height - 1 - y) * rowBytes;
            std::memcpy(row.data(), a, rowBytes);
            std::memcpy(a, b, rowBytes);
            std::memcpy(b, row.data(), rowBytes);
        }
    }
    return image;
}

void Context::blit(const Framebuffer& source, Framebuffer* destination)
{
    detail::ContextState& state = *_state;
    const ErrorSource where{"Context::blit", {}};
    if (&source == destination) {
        throw Error("Context::blit: the source is the destination");
    }
    if (!destination && !state.backend->hasDefaultFramebuffer()) {
        throw Error("Context::blit: no window to copy to (a headless context has no default framebuffer)");
    }
    // Binding checks each framebuffer and attaches its textures; the source is bound last, so it
    // stays the framebuffer the context's shadow state knows as bound.
    GLuint destinationName = 0;
    if (destination) {
        bindTarget(destination, where);
        destinationName = destination->_name;
    }
    Framebuffer* read = bindTarget(const_cast<Framebuffer*>(&source), where);
    if (!read->_colors[0]) {
        throw Error("Context::blit: the source framebuffer has no colour attachment 0");
    }
    state.applyClearState(ClearState{}); // the scissor test would clip the copy
    const detail::GlApi& gl = state.gl;
    const PixelRectangle from = targetRectangle(read);
    const PixelRectangle to = targetRectangle(destination);
    gl.glReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, destinationName);
    const bool sameSize = from.width == to.width && from.height == to.height;
    if (!sameSize && read->_colors[0]->samples() > 1) {
        throw Error("Context::blit: a multisampled framebuffer resolves only into one of its size (" +
                    std::to_string(from.width) + " x " + std::to_string(from.height) + ", not " +
                    std::to_string(to.width) + " x " + std::to_string(to.height) + ")");
    }
    gl.glBlitFramebuffer(0, 0, from.width, from.height, 0, 0, to.width, to.height, GL_COLOR_BUFFER_BIT,
                         sameSize ? GL_NEAREST : GL_LINEAR);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, read->_name);
}

void Context::copyDepth(const Framebuffer& source, Framebuffer& destination)
{
    detail::ContextState& state = *_state;
    const ErrorSource where{"Context::copyDepth", {}};
    if (&source == &destination) {
        throw Error("Context::copyDepth: the source is the destination");
    }
    const std::shared_ptr<Texture2D>& from = source.depthAttachment();
    const std::shared_ptr<Texture2D>& to = destination.depthAttachment();
    if (!from || !to) {
        throw Error(std::string("Context::copyDepth: the ") + (from ? "destination" : "source") +
                    " framebuffer has no depth attachment");
    }
    if (from->format() != to->format() || from->width() != to->width() || from->height() != to->height()) {
        throw Error(std::string("Context::copyDepth: ") + textureFormatName(from->format()) + " " +
                    std::to_string(from->width()) + "x" + std::to_string(from->height()) + " cannot be copied into " +
                    textureFormatName(to->format()) + " " + std::to_string(to->width()) + "x" +
                    std::to_string(to->height()) + " (the same format and size are needed)");
    }
    // As blit: each checked and attached, the source bound last.
    bindTarget(&destination, where);
    Framebuffer* read = bindTarget(const_cast<Framebuffer*>(&source), where);
    state.applyClearState(ClearState{}); // the scissor test would clip the copy
    const detail::GlApi& gl = state.gl;
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, destination._name);
    gl.glBlitFramebuffer(0, 0, from->width(), from->height(), 0, 0, to->width(), to->height(), GL_DEPTH_BUFFER_BIT,
                         GL_NEAREST);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, read->_name);
}

void Context::resetState() noexcept
{
    _state->forgetState();
}

void Context::flush()
{
    _state->gl.glFlush();
}

void Context::finish()
{
    _state->gl.glFinish();
}

RenderStatistics Context::statistics() const noexcept
{
    RenderStatistics statistics = _state->statistics;
    statistics.glCalls = detail::tlsGlCallCount - _state->glCallsAtReset;
    return statistics;
}

void Context::resetStatistics() noexcept
{
    _state->statistics = {};
    _state->glCallsAtReset = detail::tlsGlCallCount;
}

} // namespace orbis::renderer
