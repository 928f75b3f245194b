#pragma once

#include "orbis/renderer/Context.h"
#include "orbis/renderer/Fence.h"
#include "orbis/renderer/IndexBuffer.h"
#include "orbis/renderer/PixelBuffer.h"
#include "orbis/renderer/Sampler.h"
#include "orbis/renderer/ShaderCache.h"
#include "orbis/renderer/ShaderProgram.h"
#include "orbis/renderer/Texture2D.h"
#include "orbis/renderer/VertexBuffer.h"
#include "orbis/renderer/Window.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::renderer {

/// Where the GL context comes from.
enum class GlBackend : std::uint8_t {
    Auto,   ///< ORBIS_GL_BACKEND (egl, osmesa, window) when set; otherwise EGL, then OSMesa
    Egl,    ///< EGL without a surface: a GPU's vendor driver, or Mesa (llvmpipe) without one
    OsMesa, ///< Mesa's off-screen library, in software
    Window, ///< a GLFW window (only in builds with GLFW, and only with a display)
};

/// "EGL", "OSMesa", "window" or "auto".
const char* glBackendName(GlBackend backend) noexcept;

struct DeviceOptions {
    GlBackend backend = GlBackend::Auto;
    /// Check glGetError after every GL call (and print KHR_debug messages). Default: on in Debug
    /// builds, in builds configured with ORBIS_GL_CHECKS, or with ORBIS_GL_CHECKS=1 set.
    std::optional<bool> glChecks;
    /// The OpenGL version asked for (core profile); lower than 3.3 is raised to 3.3.
    int glMajorVersion = 3;
    int glMinorVersion = 3;
    /// Window backend only.
    int windowWidth = 800;
    int windowHeight = 600;
    std::string windowTitle = "Orbis";
};

/// What the device's driver is and can do.
struct DeviceInfo {
    GlBackend backend = GlBackend::Auto;
    std::string backendDescription; ///< e.g. "EGL 1.5 surfaceless (Mesa)"
    std::string vendor;
    std::string renderer;
    std::string version;
    std::string shadingLanguageVersion;
    int maxTextureSize = 0;
    int maxTextureUnits = 0;        ///< usable by draw commands (one more is kept for uploads)
    int maxColorAttachments = 0;
    int maxVertexAttributes = 0;
    float maxAnisotropy = 1.0f;     ///< 1 when anisotropic filtering is missing
    int maxSamples = 1;             ///< the most samples a multisampled texture may have (GL_MAX_SAMPLES)
    bool khrDebug = false;          ///< KHR_debug present
    bool glChecks = false;          ///< glGetError after every call
    int glMajorVersion = 3;         ///< of the context created (often above the 3.3 asked for)
    int glMinorVersion = 3;
    /// glClipControl (GL 4.5 or ARB_clip_control): a 0..1 clip-space depth range, which
    /// complementary depth in a float buffer needs (SceneState::depthConvention).
    bool clipControl = false;
    /// The GLSL `precise` qualifier (GLSL 4.00 or ARB_gpu_shader5), which keeps the compiler from
    /// reassociating or fusing float arithmetic (ShaderProgramDescription::extensions).
    bool gpuShader5 = false;
    /// ARB_sparse_texture with immutable storage: textures whose memory is committed a page at a
    /// time (TextureDescription::sparse, Texture2D::commit); the largest such texture's side.
    bool sparseTexture = false;
    int maxSparseTextureSize = 0;
    std::vector<std::string> extensions; ///< GL_EXTENSIONS, sorted

    /// Whether the driver lists the extension ("GL_ARB_clip_control").
    bool hasExtension(std::string_view name) const noexcept;
};

/// The GPU: it creates the resources (buffers, programs, textures, samplers, fences) that every
/// context of the device shares, and owns the main Context, which it makes current on the thread
/// that constructs it. Resources must be destroyed before the Device.
///
/// Headless by default: an EGL surfaceless context (the vendor's driver on a GPU, Mesa llvmpipe
/// without one), OSMesa when EGL cannot give a 3.3 core context.
///
/// ```
/// Device device;  // EGL, or OSMesa when EGL fails; DeviceOptions chooses otherwise
/// VertexBuffer buffer = device.createVertexBuffer(bytes);
/// Texture2D texture = device.createTexture2D({64, 64, TextureFormat::RGBA8});
/// auto worker = device.createSharedContext(); // for a loading thread: worker->makeCurrent() there
/// ```
class Device final {
public:
    /// Throws orbis::Error saying what each backend tried answered when no OpenGL 3.3 core
    /// context can be had.
    explicit Device(const DeviceOptions& options = {});
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const DeviceInfo& info() const noexcept;
    /// The main context, current on the thread that created the device.
    Context& context() noexcept;
    /// A new context sharing this device's resources, current nowhere: make it current on a
    /// worker thread to create resources there (book chapter 10). Destroy it on that thread.
    std::unique_ptr<Context> createSharedContext();
    /// The window of a Window device; null otherwise.
    Window* window() noexcept;

    VertexBuffer createVertexBuffer(std::size_t sizeInBytes, BufferUsage usage = BufferUsage::StaticDraw);
    VertexBuffer createVertexBuffer(std::span<const std::byte> data, BufferUsage usage = BufferUsage::StaticDraw);
    IndexBuffer createIndexBuffer(IndexType type, std::size_t count, BufferUsage usage = BufferUsage::StaticDraw);
    IndexBuffer createIndexBuffer(std::span<const std::uint16_t> indices, BufferUsage usage = BufferUsage::StaticDraw);
    IndexBuffer createIndexBuffer(std::span<const std::uint32_t> indices, BufferUsage usage = BufferUsage::StaticDraw);

    /// GPU memory for Context::readPixels to copy pixels into without waiting (a pixel-pack buffer).
    PixelBuffer createPixelBuffer(std::size_t sizeInBytes);

    /// Compiles and links. Throws orbis::Error with the driver's messages mapped to file and line.
    ShaderProgram createShaderProgram(const ShaderProgramDescription& description);
    /// The device's program cache: each variant compiled once, on first use.
    ShaderCache& shaderCache() noexcept;

    /// Throws orbis::Error for a size outside 1..maxTextureSize.
    Texture2D createTexture2D(const TextureDescription& description);
    /// An RGBA8 (4-channel image) or RGB8 (3-channel) texture holding the image, upright; with
    /// mipmaps, the driver makes them (glGenerateMipmap).
    Texture2D createTexture2D(const Image& image, bool mipmaps = false);
    /// The same with mipmap levels made already (levels 1, 2, ... down to 1 x 1, as
    /// orbis::mipmapChain makes them, e.g. on a loader's worker thread): a software rasteriser
    /// takes ten times a JPEG's decoding to make them itself. Throws for a chain of the wrong sizes.
    Texture2D createTexture2D(const Image& image, std::span<const Image> mipmapLevels);
    /// The texels a page of a sparse texture of the format spans, across and up (the driver's
    /// first virtual page size): what Texture2D::commit commits at least. {0, 0} without
    /// DeviceInfo::sparseTexture.
    SparsePageSize sparsePageSize(TextureFormat format);
    Sampler createSampler(const SamplerDescription& description = {});
    /// A fence after the commands issued so far in the context current on this thread.
    Fence createFence();

private:
    friend class Context;
    struct Impl;
    std::unique_ptr<Impl> _impl;
};

} // namespace orbis::renderer
