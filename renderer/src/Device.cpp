#include "orbis/renderer/Device.h"

#include "Backend.h"
#include "ContextState.h"
#include "GlApi.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Window.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <set>

namespace orbis::renderer {

struct Device::Impl {
    std::unique_ptr<detail::Backend> backend;
    std::unique_ptr<Window> window;
    std::unique_ptr<detail::GlApi> gl;
    std::unique_ptr<Context> context;
    std::unique_ptr<ShaderCache> cache;
    DeviceInfo info;
};

namespace {

bool defaultGlChecks()
{
    if (const char* env = std::getenv("ORBIS_GL_CHECKS"); env && *env) {
        return std::strcmp(env, "0") != 0;
    }
#if defined(ORBIS_GL_CHECKS_DEFAULT) || !defined(NDEBUG)
    return true;
#else
    return false;
#endif
}

GlBackend resolveBackend(GlBackend requested)
{
    if (requested != GlBackend::Auto) {
        return requested;
    }
    const char* env = std::getenv("ORBIS_GL_BACKEND");
    if (!env || !*env || std::strcmp(env, "auto") == 0) {
        return GlBackend::Auto;
    }
    if (std::strcmp(env, "egl") == 0) {
        return GlBackend::Egl;
    }
    if (std::strcmp(env, "osmesa") == 0) {
        return GlBackend::OsMesa;
    }
    if (std::strcmp(env, "window") == 0 || std::strcmp(env, "glfw") == 0) {
        return GlBackend::Window;
    }
    throw Error(std::string("ORBIS_GL_BACKEND=") + env + ": expected egl, osmesa, window or auto");
}

std::string glString(const detail::GlApi& gl, GLenum name)
{
    const GLubyte* text = gl.glGetString(name);
    return text ? reinterpret_cast<const char*>(text) : "";
}

GLint glInteger(const detail::GlApi& gl, GLenum name)
{
    GLint value = 0;
    gl.glGetIntegerv(name, &value);
    return value;
}

} // namespace

namespace detail {
namespace {
// Zero-initialised before any constructor runs, so a registration before main always sticks.
WindowBackendFactory windowBackendFactory = nullptr;
} // namespace

bool registerWindowBackend(WindowBackendFactory factory) noexcept
{
    windowBackendFactory = factory;
    return true;
}

std::unique_ptr<Backend> createWindowBackend(const BackendRequest& request)
{
    if (!windowBackendFactory) {
        throw Error("window backend: this program is not linked with the window library (link orbis::window, "
                    "find_package(orbis COMPONENTS window))");
    }
    return windowBackendFactory(request);
}
} // namespace detail

const char* glBackendName(GlBackend backend) noexcept
{
    switch (backend) {
    case GlBackend::Auto: return "auto";
    case GlBackend::Egl: return "EGL";
    case GlBackend::OsMesa: return "OSMesa";
    case GlBackend::Window: return "window";
    }
    return "auto";
}

Device::Device(const DeviceOptions& options)
    : _impl(std::make_unique<Impl>())
{
    const bool checks = options.glChecks.value_or(defaultGlChecks());
    detail::BackendRequest request;
    const bool below33 = options.glMajorVersion < 3 || (options.glMajorVersion == 3 && options.glMinorVersion < 3);
    request.majorVersion = below33 ? 3 : options.glMajorVersion;
    request.minorVersion = below33 ? 3 : options.glMinorVersion;
    request.debug = checks;
    request.windowWidth = options.windowWidth;
    request.windowHeight = options.windowHeight;
    request.windowTitle = options.windowTitle;
    const std::string version = std::to_string(request.majorVersion) + "." + std::to_string(request.minorVersion);

    auto attempt = [&](GlBackend kind) {
        std::unique_ptr<detail::Backend> backend = kind == GlBackend::Egl      ? detail::createEglBackend(request)
                                                   : kind == GlBackend::OsMesa ? detail::createOsMesaBackend(request)
                                                                               : detail::createWindowBackend(request);
        std::unique_ptr<detail::BackendContext> backendContext = backend->createContext(nullptr);
        backendContext->makeCurrent();
        auto gl = std::make_unique<detail::GlApi>(backend->getProcAddress(), backend->description(), checks);

        const GLint major = glInteger(*gl, GL_MAJOR_VERSION);
        const GLint minor = glInteger(*gl, GL_MINOR_VERSION);
        if (major * 10 + minor < request.majorVersion * 10 + request.minorVersion) {
            backendContext->releaseCurrent();
            throw Error(backend->description() + ": the context is OpenGL " + std::to_string(major) + "." +
                        std::to_string(minor) + ", " + version + " core is needed");
        }
        std::set<std::string> extensions;
        const GLint extensionCount = glInteger(*gl, GL_NUM_EXTENSIONS);
        for (GLint i = 0; i < extensionCount; ++i) {
            const GLubyte* name = gl->glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
            if (name) {
                extensions.insert(reinterpret_cast<const char*>(name));
            }
        }
        DeviceInfo info;
        info.backend = kind;
        info.backendDescription = backend->description();
        info.vendor = glString(*gl, GL_VENDOR);
        info.renderer = glString(*gl, GL_RENDERER);
        info.version = glString(*gl, GL_VERSION);
        info.shadingLanguageVersion = glString(*gl, GL_SHADING_LANGUAGE_VERSION);
        info.maxTextureSize = glInteger(*gl, GL_MAX_TEXTURE_SIZE);
        const int units = std::min<int>(glInteger(*gl, GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS),
                                        detail::kMaxTrackedTextureUnits);
        info.maxTextureUnits = units - 1; // the last one is kept for uploads
        info.maxColorAttachments = glInteger(*gl, GL_MAX_COLOR_ATTACHMENTS);
        info.maxSamples = std::max(1, glInteger(*gl, GL_MAX_SAMPLES));
        info.maxVertexAttributes = glInteger(*gl, GL_MAX_VERTEX_ATTRIBS);
        const bool anisotropy = extensions.count("GL_EXT_texture_filter_anisotropic") ||
                                extensions.count("GL_ARB_texture_filter_anisotropic") || major * 10 + minor >= 46;
        if (anisotropy) {
            GLfloat maximum = 1.0f;
            gl->glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &maximum);
            info.maxAnisotropy = std::max(1.0f, maximum);
        }
        info.khrDebug = (extensions.count("GL_KHR_debug") || major * 10 + minor >= 43) &&
                        static_cast<bool>(gl->glDebugMessageCallback);
        info.glChecks = checks;
        info.glMajorVersion = major;
        info.glMinorVersion = minor;
        info.extensions.assign(extensions.begin(), extensions.end());
        info.clipControl = (extensions.count("GL_ARB_clip_control") || major * 10 + minor >= 45) &&
                           static_cast<bool>(gl->glClipControl);
        // The shaders are GLSL 3.30, so `precise` needs the extension's directive even on GL 4.
        info.gpuShader5 = extensions.count("GL_ARB_gpu_shader5") != 0;
        info.sparseTexture = extensions.count("GL_ARB_sparse_texture") && gl->glTexStorage2D &&
                             gl->glGetInternalformativ && gl->glGetTexParameteriv && gl->glTexPageCommitmentARB;
        if (info.sparseTexture) {
            info.maxSparseTextureSize = glInteger(*gl, GL_MAX_SPARSE_TEXTURE_SIZE_ARB);
        }

        auto state = std::make_unique<detail::ContextState>(*this, *gl, std::move(backendContext), info.maxTextureUnits);
        state->debugOutput = checks && info.khrDebug;
        _impl->backend = std::move(backend);
        _impl->gl = std::move(gl);
        _impl->info = std::move(info);
        _impl->context.reset(new Context(*this, std::move(state)));
        _impl->context->makeCurrent();
        if (void* native = _impl->backend->nativeWindow()) {
            _impl->window = std::make_unique<Window>(native);
        }
    };

    const GlBackend chosen = resolveBackend(options.backend);
    if (chosen != GlBackend::Auto) {
        attempt(chosen);
    } else {
        try {
            attempt(GlBackend::Egl);
        } catch (const Error& eglError) {
            _impl = std::make_unique<Impl>();
            try {
                attempt(GlBackend::OsMesa);
            } catch (const Error& osMesaError) {
                throw Error("no OpenGL " + version + " core context can be had.\n  EGL: " + eglError.what() +
                            "\n  OSMesa (tried because EGL failed): " + osMesaError.what());
            }
        }
    }
    _impl->cache = std::make_unique<ShaderCache>(*this);
}

Device::~Device()
{
    if (!_impl || !_impl->context) {
        return;
    }
    if (!_impl->context->isCurrent()) {
        try {
            _impl->context->makeCurrent();
        } catch (const Error&) {
            // Current on another thread: the cached programs are left to the driver's teardown.
        }
    }
    _impl->cache.reset();
    _impl->window.reset();
    _impl->context.reset();
    _impl->gl.reset();
    _impl->backend.reset();
}

bool DeviceInfo::hasExtension(std::string_view name) const noexcept
{
    return std::binary_search(extensions.begin(), extensions.end(), name);
}

const DeviceInfo& Device::info() const noexcept
{
    return _impl->info;
}

Context& Device::context() noexcept
{
    return *_impl->context;
}

ShaderCache& Device::shaderCache() noexcept
{
    return *_impl->cache;
}

Window* Device::window() noexcept
{
    return _impl->window.get();
}

std::unique_ptr<Context> Device::createSharedContext()
{
    detail::ContextState& main = *_impl->context->_state;
    auto backendContext = _impl->backend->createContext(main.backend.get());
    auto state = std::make_unique<detail::ContextState>(*this, *_impl->gl, std::move(backendContext),
                                                        _impl->info.maxTextureUnits);
    state->debugOutput = main.debugOutput;
    return std::unique_ptr<Context>(new Context(*this, std::move(state)));
}

Fence Device::createFence()
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createFence");
    GLsync sync = state.gl.glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    if (!sync) {
        throw Error("Device::createFence: glFenceSync failed");
    }
    return Fence(*this, sync);
}

} // namespace orbis::renderer
