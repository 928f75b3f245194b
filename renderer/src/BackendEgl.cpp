// EGL without a window: EGL_EXT_platform_device (a GPU's vendor driver first), then
// EGL_MESA_platform_surfaceless (Mesa llvmpipe), then the default display. Contexts are made
// current with no surface (EGL_KHR_surfaceless_context); all drawing goes to framebuffer objects.

#define EGL_NO_X11 1
#define MESA_EGL_NO_X11_HEADERS 1
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "Backend.h"

#include "orbis/core/Error.h"

#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <vector>

namespace orbis::renderer::detail {
namespace {

std::string eglErrorName(EGLint error)
{
    switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: {
        char text[32];
        std::snprintf(text, sizeof text, "EGL error 0x%04X", static_cast<unsigned>(error));
        return text;
    }
    }
}

bool hasExtension(const char* extensions, const char* name)
{
    if (!extensions) {
        return false;
    }
    const std::size_t length = std::strlen(name);
    for (const char* p = extensions; (p = std::strstr(p, name)) != nullptr; p += length) {
        const bool startOk = p == extensions || p[-1] == ' ';
        const bool endOk = p[length] == '\0' || p[length] == ' ';
        if (startOk && endOk) {
            return true;
        }
    }
    return false;
}

// EGL hands out one EGLDisplay per platform and native display, shared by everything in the
// process, and eglTerminate ends it for all of them. Devices count their uses so that the last
// one out terminates it.
std::mutex displayMutex;
std::map<EGLDisplay, int> displayUsers;

bool initializeDisplay(EGLDisplay display, EGLint& major, EGLint& minor)
{
    std::lock_guard lock(displayMutex);
    if (!eglInitialize(display, &major, &minor)) {
        return false;
    }
    ++displayUsers[display];
    return true;
}

void releaseDisplay(EGLDisplay display)
{
    std::lock_guard lock(displayMutex);
    auto found = displayUsers.find(display);
    if (found != displayUsers.end() && --found->second == 0) {
        displayUsers.erase(found);
        eglTerminate(display);
    }
}

GlProc eglProc(const char* name)
{
    return eglGetProcAddress(name);
}

struct Candidate {
    std::string label;
    EGLenum platform = 0; ///< 0: eglGetDisplay(EGL_DEFAULT_DISPLAY)
    void* nativeDisplay = nullptr;
};

class EglContext final : public BackendContext {
public:
    EglContext(EGLDisplay display, EGLContext context) noexcept : _display(display), _context(context) {}
    ~EglContext() override
    {
        if (eglGetCurrentContext() == _context) {
            eglMakeCurrent(_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(_display, _context);
    }
    void makeCurrent() override
    {
        eglBindAPI(EGL_OPENGL_API); // per thread
        if (!eglMakeCurrent(_display, EGL_NO_SURFACE, EGL_NO_SURFACE, _context)) {
            throw Error("EGL: eglMakeCurrent failed: " + eglErrorName(eglGetError()));
        }
    }
    void releaseCurrent() noexcept override
    {
        eglMakeCurrent(_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    EGLContext handle() const noexcept { return _context; }

private:
    EGLDisplay _display;
    EGLContext _context;
};

class EglBackend final : public Backend {
public:
    EglBackend(EGLDisplay display, EGLConfig config, const BackendRequest& request, std::string description)
        : _display(display), _config(config), _request(request), _description(std::move(description))
    {
    }
    ~EglBackend() override { releaseDisplay(_display); }

    std::unique_ptr<BackendContext> createContext(BackendContext* shareWith) override
    {
        const EGLContext share = shareWith ? static_cast<EglContext*>(shareWith)->handle() : EGL_NO_CONTEXT;
        EGLContext context = createRaw(_display, _config, _request, share);
        if (context == EGL_NO_CONTEXT) {
            throw Error("EGL (" + _description + "): cannot create an OpenGL " + std::to_string(_request.majorVersion) +
                        "." + std::to_string(_request.minorVersion) +
                        " core context: " + eglErrorName(eglGetError()));
        }
        return std::make_unique<EglContext>(_display, context);
    }
    GetProcAddressFunction getProcAddress() const noexcept override { return &eglProc; }
    std::string description() const override { return _description; }

    static EGLContext createRaw(EGLDisplay display, EGLConfig config, const BackendRequest& request, EGLContext share)
    {
        eglBindAPI(EGL_OPENGL_API);
        const EGLint attributes[] = {
            EGL_CONTEXT_MAJOR_VERSION_KHR, request.majorVersion,
            EGL_CONTEXT_MINOR_VERSION_KHR, request.minorVersion,
            EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
            EGL_CONTEXT_FLAGS_KHR, request.debug ? EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR : 0,
            EGL_NONE,
        };
        return eglCreateContext(display, config, share, attributes);
    }

private:
    EGLDisplay _display;
    EGLConfig _config;
    BackendRequest _request;
    std::string _description;
};

std::vector<Candidate> candidates(const char* clientExtensions)
{
    std::vector<Candidate> hardware;
    std::vector<Candidate> software;
    if (hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
        hasExtension(clientExtensions, "EGL_EXT_device_enumeration")) {
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        auto queryDeviceString =
            reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (queryDevices && queryDevices(16, devices, &count)) {
            for (EGLint i = 0; i < count; ++i) {
                const char* deviceExtensions = queryDeviceString ? queryDeviceString(devices[i], EGL_EXTENSIONS) : nullptr;
                const bool isSoftware = hasExtension(deviceExtensions, "EGL_MESA_device_software");
                Candidate candidate{std::string("device ") + std::to_string(i) + (isSoftware ? " (software)" : ""),
                                    EGL_PLATFORM_DEVICE_EXT, devices[i]};
                (isSoftware ? software : hardware).push_back(candidate);
            }
        }
    }
    std::vector<Candidate> all = hardware;
    if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        all.push_back({"surfaceless", EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY});
    }
    all.insert(all.end(), software.begin(), software.end());
    all.push_back({"default display", 0, nullptr});
    return all;
}

} // namespace

std::unique_ptr<Backend> createEglBackend(const BackendRequest& request)
{
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    std::string reasons;
    for (const Candidate& candidate : candidates(clientExtensions)) {
        EGLDisplay display = EGL_NO_DISPLAY;
        if (candidate.platform != 0) {
            if (!getPlatformDisplay) {
                continue;
            }
            display = getPlatformDisplay(candidate.platform, candidate.nativeDisplay, nullptr);
        } else {
            display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        }
        auto fail = [&](const std::string& why) { reasons += "\n  " + candidate.label + ": " + why; };
        if (display == EGL_NO_DISPLAY) {
            fail("no display (" + eglErrorName(eglGetError()) + ")");
            continue;
        }
        EGLint major = 0;
        EGLint minor = 0;
        if (!initializeDisplay(display, major, minor)) {
            fail("eglInitialize failed (" + eglErrorName(eglGetError()) + ")");
            continue;
        }
        const char* displayExtensions = eglQueryString(display, EGL_EXTENSIONS);
        if (!hasExtension(displayExtensions, "EGL_KHR_surfaceless_context")) {
            fail("no EGL_KHR_surfaceless_context");
            releaseDisplay(display);
            continue;
        }
        if (!eglBindAPI(EGL_OPENGL_API)) {
            fail("no desktop OpenGL (eglBindAPI: " + eglErrorName(eglGetError()) + ")");
            releaseDisplay(display);
            continue;
        }
        EGLConfig config = EGL_NO_CONFIG_KHR;
        if (!hasExtension(displayExtensions, "EGL_KHR_no_config_context")) {
            const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                               EGL_NONE};
            EGLint count = 0;
            if (!eglChooseConfig(display, configAttributes, &config, 1, &count) || count == 0) {
                fail("no config for desktop OpenGL");
                releaseDisplay(display);
                continue;
            }
        }
        // Check that a 3.3 core context can be had here before settling on this display.
        EGLContext probe = EglBackend::createRaw(display, config, request, EGL_NO_CONTEXT);
        if (probe == EGL_NO_CONTEXT) {
            fail("no OpenGL " + std::to_string(request.majorVersion) + "." + std::to_string(request.minorVersion) +
                 " core context (" + eglErrorName(eglGetError()) + ")");
            releaseDisplay(display);
            continue;
        }
        eglDestroyContext(display, probe);
        const char* vendor = eglQueryString(display, EGL_VENDOR);
        std::string description = "EGL " + std::to_string(major) + "." + std::to_string(minor) + " " +
                                  candidate.label + " (" + (vendor ? vendor : "unknown vendor") + ")";
        return std::make_unique<EglBackend>(display, config, request, std::move(description));
    }
    throw Error("EGL: no display gives an OpenGL " + std::to_string(request.majorVersion) + "." +
                std::to_string(request.minorVersion) + " core context:" + reasons);
}

} // namespace orbis::renderer::detail
