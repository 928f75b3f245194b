// The window library of a build without GLFW: GlBackend::Window says so, and no Window is ever made,
// so its functions are never reached (they exist for programs such as the viewer to link).

#include "Backend.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Window.h"

namespace orbis::renderer {

namespace {

std::unique_ptr<detail::Backend> noWindowBackend(const detail::BackendRequest&)
{
    throw Error("window backend: this build of Orbis has no GLFW (install GLFW 3.3 and reconfigure)");
}

} // namespace

bool Window::shouldClose() const
{
    return true;
}
void Window::pollEvents() {}
WindowInput Window::takeInput()
{
    return {};
}
bool Window::isKeyDown(char) const
{
    return false;
}
void Window::swapBuffers() {}
void Window::setTitle(const std::string&) {}
int Window::framebufferWidth() const
{
    return 0;
}
int Window::framebufferHeight() const
{
    return 0;
}

} // namespace orbis::renderer

// Registered before main like BackendGlfw.cpp's backend.
extern "C" const bool orbis_window_backend;
extern "C" const bool orbis_window_backend =
    orbis::renderer::detail::registerWindowBackend(&orbis::renderer::noWindowBackend);
