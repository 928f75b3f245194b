#pragma once

#include <glm/vec2.hpp>

#include <optional>
#include <string>

namespace orbis::renderer {

/// What the user did in a window since the last Window::takeInput().
struct WindowInput {
    glm::dvec2 dragPixels{0.0}; ///< pointer movement with the left button held, x right, y down
    double scrollSteps = 0.0;   ///< wheel steps, positive away from the user
    std::string pressedLetters; ///< letter keys pressed, upper case, in order ("F", "WW", ...)
    /// Where the left button was last double-clicked (two presses within a third of a second and
    /// 4 pixels), in framebuffer pixels from the top-left corner; empty if it was not.
    std::optional<glm::dvec2> doubleClickPixels;
};

/// The window of a Device created with GlBackend::Window (only in builds with GLFW, and only where
/// a display exists). Its Context draws into it when no framebuffer is set; swapBuffers shows the
/// frame. Owned by the Device; used on the thread that created the Device.
///
/// ```
/// DeviceOptions options;
/// options.backend = GlBackend::Window;
/// Device device(options);
/// while (!device.window()->shouldClose()) {
///     device.context().clear(ClearState{});
///     device.context().draw(command, scene);
///     device.window()->swapBuffers();
///     device.window()->pollEvents();
/// }
/// ```
class Window final {
public:
    explicit Window(void* nativeWindow) noexcept : _native(nativeWindow) {}
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    /// True once the user asked to close the window.
    bool shouldClose() const;
    /// Handles pending window-system events (input, resizing, closing). Escape asks to close.
    void pollEvents();
    /// The input gathered by pollEvents since the last call, which starts afresh.
    WindowInput takeInput();
    /// Whether the key of a letter ('A' to 'Z') is held down now; false for anything else.
    bool isKeyDown(char letter) const;
    /// Shows what was drawn into the default framebuffer.
    void swapBuffers();
    /// Sets the text of the window's title bar (UTF-8).
    void setTitle(const std::string& title);
    /// The default framebuffer's size in pixels (which may differ from the window's size in
    /// screen coordinates on high-density displays).
    int framebufferWidth() const;
    int framebufferHeight() const;

private:
    void* _native = nullptr; ///< the GLFWwindow
};

} // namespace orbis::renderer
