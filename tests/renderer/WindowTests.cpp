// The optional window backend (GLFW). Headless machines, and builds without GLFW, must say so
// clearly; with GLFW and a display, a window device draws into its window.
#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <cstdlib>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

TEST_CASE("A window device draws into its window, or says clearly why there is none", "[renderer][window]")
{
    DeviceOptions options;
    options.backend = GlBackend::Window;
    options.windowWidth = 32;
    options.windowHeight = 32;
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    const bool hasDisplay = (display && *display) || (wayland && *wayland);
#ifdef ORBIS_TEST_HAVE_GLFW
    if (!hasDisplay) {
        REQUIRE_THROWS_WITH(Device(options), Contains("window backend: no display"));
        return;
    }
    Device device(options);
    REQUIRE(device.window());
    Context& context = device.context();
    context.setFramebuffer(nullptr); // the window
    ClearState clear;
    clear.color = {0.0f, 1.0f, 0.0f, 1.0f};
    context.clear(clear);
    const Image image = context.readPixels();
    CHECK(image.width == device.window()->framebufferWidth());
    CHECK(test::pixelNear(image, 0, 0, {0, 255, 0, 255}));

    // A frame rendered offscreen, shown through blit.
    Framebuffer offscreen = context.createFramebuffer(image.width, image.height);
    ClearState magenta;
    magenta.color = {1.0f, 0.0f, 1.0f, 1.0f};
    context.clear(magenta, &offscreen);
    context.blit(offscreen);
    const Image shown = context.readPixels();
    CHECK(test::pixelNear(shown, 0, 0, {255, 0, 255, 255}));
    CHECK(test::pixelNear(shown, shown.width - 1, shown.height - 1, {255, 0, 255, 255}));

    device.window()->swapBuffers();
    device.window()->pollEvents();
    const WindowInput input = device.window()->takeInput(); // nobody touched the virtual display
    CHECK(input.dragPixels == glm::dvec2(0.0));
    CHECK(input.scrollSteps == 0.0);
    CHECK(input.pressedLetters.empty());
    CHECK_FALSE(input.doubleClickPixels);
    CHECK_FALSE(device.window()->isKeyDown('W'));
    CHECK_FALSE(device.window()->isKeyDown('?'));
#else
    (void)hasDisplay;
    REQUIRE_THROWS_WITH(Device(options), Contains("window backend") && Contains("no GLFW"));
#endif
}

TEST_CASE("Headless devices have no window", "[renderer][window][headless]")
{
    CHECK(test::sharedDevice().window() == nullptr);
}
