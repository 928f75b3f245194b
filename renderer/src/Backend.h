#pragma once

// Where GL contexts come from: EGL (surfaceless), OSMesa, or a GLFW window (the window library).
// Private.

#include "GlProc.h"

#include <memory>
#include <string>

namespace orbis::renderer::detail {

/// One GL context of a backend.
class BackendContext {
public:
    virtual ~BackendContext() = default;
    /// Makes the context current on the calling thread; throws orbis::Error on failure.
    virtual void makeCurrent() = 0;
    /// Leaves the calling thread without a current context.
    virtual void releaseCurrent() noexcept = 0;
    /// True for a window's context, whose framebuffer 0 is the window.
    virtual bool hasDefaultFramebuffer() const noexcept { return false; }
    /// The default framebuffer's size in pixels (a window's); 0 x 0 without one.
    virtual void defaultFramebufferSize(int& width, int& height) const noexcept
    {
        width = 0;
        height = 0;
    }
};

struct BackendRequest {
    int majorVersion = 3;
    int minorVersion = 3;
    bool debug = false; ///< ask for a debug context (KHR_debug messages)
    int windowWidth = 800;
    int windowHeight = 600;
    std::string windowTitle = "Orbis";
};

class Backend {
public:
    virtual ~Backend() = default;
    /// A new context sharing objects with `shareWith` (none when null), not current anywhere.
    /// Throws orbis::Error saying why when the backend cannot make one.
    virtual std::unique_ptr<BackendContext> createContext(BackendContext* shareWith) = 0;
    virtual GetProcAddressFunction getProcAddress() const noexcept = 0;
    /// "EGL 1.5 surfaceless (Mesa Project)" and the like.
    virtual std::string description() const = 0;
    /// The window of a window backend (a GLFWwindow); null for the headless ones.
    virtual void* nativeWindow() const noexcept { return nullptr; }
};

/// Throws orbis::Error listing what each display tried answered.
std::unique_ptr<Backend> createEglBackend(const BackendRequest& request);
std::unique_ptr<Backend> createOsMesaBackend(const BackendRequest& request);
/// How GlBackend::Window makes its backend: set before main by the window library (orbis_window,
/// renderer/window), which a program links to have windows; null without it.
using WindowBackendFactory = std::unique_ptr<Backend> (*)(const BackendRequest&);
bool registerWindowBackend(WindowBackendFactory factory) noexcept;
/// The registered factory's backend; throws orbis::Error when no window library is linked, or as the
/// factory does (no GLFW in this build, no display).
std::unique_ptr<Backend> createWindowBackend(const BackendRequest& request);

} // namespace orbis::renderer::detail
