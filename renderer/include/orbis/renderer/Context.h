#pragma once

#include "orbis/core/Mesh.h"
#include "orbis/renderer/ClearState.h"
#include "orbis/renderer/DrawCommand.h"
#include "orbis/renderer/Framebuffer.h"
#include "orbis/core/Image.h"
#include "orbis/renderer/RenderStatistics.h"
#include "orbis/renderer/SceneState.h"
#include "orbis/renderer/VertexArray.h"

#include <memory>
#include <span>
#include <vector>

namespace orbis::renderer {

class Device;
class PixelBuffer;
class ShaderProgram;
namespace detail {
class ContextState;
class BackendContext;
struct RawGlBaselineAccess;
struct ErrorSource;
} // namespace detail

/// Colour and depth formats of Context::createFramebuffer(width, height, ...).
struct FramebufferOptions {
    TextureFormat colorFormat = TextureFormat::RGBA8;
    /// Depth24Stencil8 by default; set hasDepth to false for colour only.
    TextureFormat depthFormat = TextureFormat::Depth24Stencil8;
    bool hasDepth = true;
};

/// A GL context: it draws. It executes DrawCommands against the current framebuffer, shadows the
/// GL state so that only what differs is changed, sets the automatic og_ uniforms and counts what
/// it did. It also creates the objects GL does not share between contexts (vertex arrays and
/// framebuffers). A context is used on one thread at a time, the one it is current on; the
/// Device's main context is current on the thread that created the Device.
///
/// ```
/// Device device;                       // EGL surfaceless, or OSMesa
/// Context& context = device.context();
/// Framebuffer target = context.createFramebuffer(640, 480);
/// context.setFramebuffer(&target);
/// context.clear(ClearState{});
/// context.draw(command, sceneState);
/// world::writePng(context.readPixels(), "frame.png"); // orbis/world/ImageFile.h
/// ```
class Context final {
public:
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    Device& device() const noexcept;

    /// Makes this context current on the calling thread (for a shared context on a worker).
    void makeCurrent();
    /// Leaves the calling thread with no current context.
    void releaseCurrent() noexcept;
    bool isCurrent() const noexcept;

    /// An empty vertex array, to fill with VertexArray::setAttribute.
    VertexArray createVertexArray();
    /// Uploads every attribute the mesh has, at the standard locations ("position" as
    /// float(position - options.center), "positionHigh"/"positionLow", "normal",
    /// "textureCoordinate") and its indices.
    VertexArray createVertexArray(const Mesh& mesh, const VertexArrayOptions& options = {});
    /// Uploads the attributes the program reads, matched by name. Throws orbis::Error naming the
    /// attribute when the program reads one the mesh does not have.
    VertexArray createVertexArray(const Mesh& mesh, const ShaderProgram& program,
                                  const VertexArrayOptions& options = {});

    /// A framebuffer without attachments.
    Framebuffer createFramebuffer();
    /// A framebuffer with a new colour texture and (by default) a depth-stencil texture. Throws
    /// orbis::Error for a size outside 1..maximum texture size.
    Framebuffer createFramebuffer(int width, int height, const FramebufferOptions& options = {});

    /// Where draws and clears go when their command names no framebuffer; null for the default
    /// framebuffer, which only a window has.
    void setFramebuffer(Framebuffer* framebuffer) noexcept { _framebuffer = framebuffer; }
    Framebuffer* framebuffer() const noexcept { return _framebuffer; }

    /// Clears the current framebuffer.
    void clear(const ClearState& clearState);
    /// Clears the given framebuffer.
    void clear(const ClearState& clearState, Framebuffer* framebuffer);
    /// Executes a command. Throws orbis::Error naming the command for bad input: no program or
    /// vertex array, an attribute the array lacks, a uniform never set or of the wrong type, an
    /// incomplete framebuffer, no framebuffer where there is no default one.
    void draw(const DrawCommand& command, const SceneState& sceneState);
    /// The same with a default SceneState (identity matrices).
    void draw(const DrawCommand& command);
    /// Executes commands in order (a command list, as the scene layer produces them per frustum and
    /// pass). Stops at the first that throws. Commands kept one after another in memory, as here or
    /// in a vector, draw fastest: each draw fetches the memory of the command two places on.
    void draw(std::span<const DrawCommand> commands, const SceneState& sceneState);
    /// Runs the command's vertex (and geometry) stage with rasterisation off and returns the
    /// outputs its program captures (ShaderProgramDescription::transformFeedbackVaryings), as
    /// floats interleaved in that order, program->capturedComponents() per vertex, one record per
    /// vertex of each primitive drawn: points one, lines two, triangles three (strips as separate
    /// primitives). Reads back what the GPU computed, e.g. gl_Position for precision
    /// measurements. Throws orbis::Error as draw does, and for a program that captures nothing.
    std::vector<float> captureVertexOutputs(const DrawCommand& command, const SceneState& sceneState);

    /// A colour attachment of a framebuffer (the current one when null) as an RGBA image, top row
    /// first. Float formats are clamped to 0..1.
    Image readPixels(const Framebuffer* framebuffer = nullptr, int colorAttachment = 0);

    /// Queues a copy of a colour attachment of a framebuffer (the current one when null) into the
    /// buffer and returns at once: RGBA8, 4 bytes a pixel, rows bottom to top, tightly packed. The
    /// copy has happened once a Fence created after this call signals; read it then with
    /// PixelBuffer::copyToSystemMemory. Throws orbis::Error when the buffer holds fewer than
    /// width x height x 4 bytes or the attachment does not exist.
    void readPixels(PixelBuffer& destination, const Framebuffer* framebuffer = nullptr, int colorAttachment = 0);

    /// Copies colour attachment 0 of `source` over the whole of `destination`, or of the window's
    /// framebuffer when null (whatever framebuffer is current), filtering linearly when the sizes
    /// differ: how a frame rendered offscreen, with a depth buffer the window cannot have, is shown.
    /// Throws orbis::Error for a headless context with a null destination, as clear does.
    void blit(const Framebuffer& source, Framebuffer* destination = nullptr);

    /// Copies the depth attachment of `source` into that of `destination`, texel for texel: how a
    /// pass reads the depth the passes before it wrote (a texture cannot be sampled while it is
    /// drawn into). Throws orbis::Error unless both have depth attachments of one format and size.
    /// `source` stays the bound framebuffer.
    void copyDepth(const Framebuffer& source, Framebuffer& destination);

    /// Sends the queued commands to the GPU.
    void flush();
    /// Waits until the GPU has executed every queued command.
    void finish();

    /// Forgets what the context knows of the GL state. Call it after code outside Orbis made GL
    /// calls on this context (another library, a raw-GL baseline): the next clear or draw sets every
    /// render-state item and binding again. Uniform values kept in ShaderPrograms are not covered.
    void resetState() noexcept;

    /// What the context did since the last reset.
    RenderStatistics statistics() const noexcept;
    void resetStatistics() noexcept;

private:
    friend class Device;
    friend struct detail::RawGlBaselineAccess; // the benchmark's raw-GL baseline, bench/RawGlBaseline.cpp
    Context(Device& device, std::unique_ptr<detail::ContextState> state);
    /// The framebuffer a draw or clear goes to, bound, its attachments updated and checked.
    Framebuffer* bindTarget(Framebuffer* requested, const detail::ErrorSource& source);
    PixelRectangle targetRectangle(const Framebuffer* framebuffer) const noexcept;
    /// Binds the framebuffer for reading and selects the attachment; returns its size.
    PixelRectangle bindReadSource(const Framebuffer* framebuffer, int colorAttachment);
    // The steps of draw(), in order (Context.cpp).
    /// Throws orbis::Error for a command that cannot be drawn; the count of indices or vertices.
    std::size_t checkDrawable(const DrawCommand& command, const SceneState& scene) const;
    /// Binds the target, program and vertex array, applies the render state; the viewport.
    PixelRectangle applyDrawState(const DrawCommand& command, const SceneState& scene,
                                  const detail::ErrorSource& source);
    /// Binds the command's textures and samplers; the units bound, one bit each.
    std::uint32_t bindTextures(const DrawCommand& command);
    /// The command's and the automatic uniforms, checked and sent.
    void setUniforms(const DrawCommand& command, const SceneState& scene, const PixelRectangle& viewport,
                     std::uint32_t boundUnits, const detail::ErrorSource& source);

    std::unique_ptr<detail::ContextState> _state;
    Framebuffer* _framebuffer = nullptr;
};

} // namespace orbis::renderer
