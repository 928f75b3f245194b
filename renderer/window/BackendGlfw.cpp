// A window from GLFW: the window library (orbis_window, only built with GLFW installed; see
// renderer/CMakeLists.txt). Its framebuffer 0 is the window; shared contexts are hidden windows
// sharing objects with it.

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "Backend.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Window.h"

#include <glm/geometric.hpp>

#include <cstdlib>
#include <memory>
#include <mutex>
#include <utility>

namespace orbis::renderer::detail {
namespace {

std::mutex glfwMutex;
int glfwUsers = 0;
std::string glfwLastError;

void recordError(int code, const char* description)
{
    glfwLastError = std::string(description) + " (GLFW error " + std::to_string(code) + ")";
}

GlProc glfwProc(const char* name)
{
    return glfwGetProcAddress(name);
}

/// Input gathered by the visible window's callbacks (its user pointer) until Window::takeInput.
struct GatheredInput {
    WindowInput input;
    glm::dvec2 cursor{0.0};
    bool cursorKnown = false;
    double lastPressSeconds = -1.0; ///< glfwGetTime of the last left press
    glm::dvec2 lastPressCursor{0.0};
};

GatheredInput& gatheredInput(GLFWwindow* window)
{
    return *static_cast<GatheredInput*>(glfwGetWindowUserPointer(window));
}

void onCursorMoved(GLFWwindow* window, double x, double y)
{
    GatheredInput& gathered = gatheredInput(window);
    const glm::dvec2 cursor(x, y);
    if (gathered.cursorKnown && glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
        gathered.input.dragPixels += cursor - gathered.cursor;
    }
    gathered.cursor = cursor;
    gathered.cursorKnown = true;
}

void onMouseButton(GLFWwindow* window, int button, int action, int)
{
    if (button != GLFW_MOUSE_BUTTON_LEFT || action != GLFW_PRESS) {
        return;
    }
    GatheredInput& gathered = gatheredInput(window);
    const double now = glfwGetTime();
    if (gathered.lastPressSeconds >= 0.0 && now - gathered.lastPressSeconds < 1.0 / 3.0 &&
        glm::distance(gathered.cursor, gathered.lastPressCursor) <= 4.0) {
        // The cursor is in screen coordinates; the scene is drawn in framebuffer pixels.
        int windowWidth = 0;
        int windowHeight = 0;
        int framebufferWidth = 0;
        int framebufferHeight = 0;
        glfwGetWindowSize(window, &windowWidth, &windowHeight);
        glfwGetFramebufferSize(window, &framebufferWidth, &framebufferHeight);
        const glm::dvec2 scale(windowWidth > 0 ? static_cast<double>(framebufferWidth) / windowWidth : 1.0,
                               windowHeight > 0 ? static_cast<double>(framebufferHeight) / windowHeight : 1.0);
        gathered.input.doubleClickPixels = gathered.cursor * scale;
        gathered.lastPressSeconds = -1.0; // a third press starts a new pair
        return;
    }
    gathered.lastPressSeconds = now;
    gathered.lastPressCursor = gathered.cursor;
}

void onScrolled(GLFWwindow* window, double, double steps)
{
    gatheredInput(window).input.scrollSteps += steps;
}

void onKey(GLFWwindow* window, int key, int, int action, int)
{
    if (action != GLFW_PRESS) {
        return;
    }
    if (key == GLFW_KEY_ESCAPE) {
        glfwSetWindowShouldClose(window, GLFW_TRUE);
    } else if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) { // GLFW's letter keys are their ASCII capitals
        gatheredInput(window).input.pressedLetters += static_cast<char>(key);
    }
}

class GlfwContext final : public BackendContext {
public:
    GlfwContext(GLFWwindow* window, bool visible) : _window(window), _visible(visible)
    {
        if (visible) {
            _input = std::make_unique<GatheredInput>();
            glfwSetWindowUserPointer(window, _input.get());
            glfwSetCursorPosCallback(window, &onCursorMoved);
            glfwSetScrollCallback(window, &onScrolled);
            glfwSetMouseButtonCallback(window, &onMouseButton);
            glfwSetKeyCallback(window, &onKey);
        }
    }
    ~GlfwContext() override
    {
        if (glfwGetCurrentContext() == _window) {
            glfwMakeContextCurrent(nullptr);
        }
        glfwDestroyWindow(_window);
    }
    void makeCurrent() override
    {
        glfwMakeContextCurrent(_window);
        if (_visible && !_vsync) {
            glfwSwapInterval(1); // show at the display's rate rather than spin a core
            _vsync = true;
        }
    }
    void releaseCurrent() noexcept override { glfwMakeContextCurrent(nullptr); }
    bool hasDefaultFramebuffer() const noexcept override { return _visible; }
    void defaultFramebufferSize(int& width, int& height) const noexcept override
    {
        glfwGetFramebufferSize(_window, &width, &height);
    }
    GLFWwindow* window() const noexcept { return _window; }

private:
    GLFWwindow* _window;
    bool _visible;
    std::unique_ptr<GatheredInput> _input; ///< the visible window's only
    bool _vsync = false;                   ///< swap interval set (once current)
};

class GlfwBackend final : public Backend {
public:
    explicit GlfwBackend(const BackendRequest& request) : _request(request) {}
    ~GlfwBackend() override
    {
        std::lock_guard lock(glfwMutex);
        if (--glfwUsers == 0) {
            glfwTerminate();
        }
    }

    std::unique_ptr<BackendContext> createContext(BackendContext* shareWith) override
    {
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
        // EGL, not GLX: libglvnd lets a thread have a current context of one window-system API
        // only, so a GLX window would make every EGL device on its thread fail (EGL_BAD_ACCESS).
        glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_EGL_CONTEXT_API);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, _request.majorVersion);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, _request.minorVersion);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, _request.debug ? GLFW_TRUE : GLFW_FALSE);
        const bool visible = shareWith == nullptr;
        glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
        GLFWwindow* share = shareWith ? static_cast<GlfwContext*>(shareWith)->window() : nullptr;
        GLFWwindow* window = glfwCreateWindow(visible ? _request.windowWidth : 1, visible ? _request.windowHeight : 1,
                                              _request.windowTitle.c_str(), nullptr, share);
        if (!window) {
            throw Error("window backend: cannot create a window with an OpenGL " +
                        std::to_string(_request.majorVersion) + "." + std::to_string(_request.minorVersion) +
                        " core context: " + glfwLastError);
        }
        if (visible) {
            _mainWindow = window;
        }
        return std::make_unique<GlfwContext>(window, visible);
    }
    GetProcAddressFunction getProcAddress() const noexcept override { return &glfwProc; }
    std::string description() const override { return std::string("GLFW ") + glfwGetVersionString() + " window"; }
    void* nativeWindow() const noexcept override { return _mainWindow; }

private:
    BackendRequest _request;
    GLFWwindow* _mainWindow = nullptr;
};

} // namespace

std::unique_ptr<Backend> createGlfwBackend(const BackendRequest& request)
{
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland)) {
        throw Error("window backend: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); use the EGL or "
                    "OSMesa backend to render headless");
    }
    std::lock_guard lock(glfwMutex);
    glfwSetErrorCallback(&recordError);
    if (glfwUsers == 0 && !glfwInit()) {
        throw Error("window backend: glfwInit failed: " + glfwLastError);
    }
    ++glfwUsers;
    return std::make_unique<GlfwBackend>(request);
}

} // namespace orbis::renderer::detail

// The window backend, registered before main; named for the linker's -u (renderer/CMakeLists.txt),
// which keeps this file in the links of programs that link the static library.
extern "C" const bool orbis_window_backend;
extern "C" const bool orbis_window_backend = orbis::renderer::detail::registerWindowBackend(
    &orbis::renderer::detail::createGlfwBackend);

namespace orbis::renderer {

bool Window::shouldClose() const
{
    return glfwWindowShouldClose(static_cast<GLFWwindow*>(_native)) != 0;
}

void Window::pollEvents()
{
    glfwPollEvents();
}

WindowInput Window::takeInput()
{
    return std::exchange(detail::gatheredInput(static_cast<GLFWwindow*>(_native)).input, WindowInput{});
}

bool Window::isKeyDown(char letter) const
{
    return letter >= 'A' && letter <= 'Z' && glfwGetKey(static_cast<GLFWwindow*>(_native), letter) == GLFW_PRESS;
}

void Window::swapBuffers()
{
    glfwSwapBuffers(static_cast<GLFWwindow*>(_native));
}

void Window::setTitle(const std::string& title)
{
    glfwSetWindowTitle(static_cast<GLFWwindow*>(_native), title.c_str());
}

int Window::framebufferWidth() const
{
    int width = 0;
    int height = 0;
    glfwGetFramebufferSize(static_cast<GLFWwindow*>(_native), &width, &height);
    return width;
}

int Window::framebufferHeight() const
{
    int width = 0;
    int height = 0;
    glfwGetFramebufferSize(static_cast<GLFWwindow*>(_native), &width, &height);
    return height;
}

} // namespace orbis::renderer
