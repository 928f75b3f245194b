#include "Viewer.h"

#include <orbis/renderer/Window.h>
#include <orbis/scene/CameraControllers.h>
#include <orbis/world/ImageFile.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <utility>

using namespace orbis::world;
using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::examples {

Device createViewerDevice(const ViewerOptions& options)
{
    DeviceOptions deviceOptions;
    deviceOptions.backend = GlBackend::Window;
    deviceOptions.windowWidth = options.width;
    deviceOptions.windowHeight = options.height;
    deviceOptions.windowTitle = options.title;
    return Device(deviceOptions);
}

void runViewer(Device& device, Scene& scene, const ViewerOptions& options)
{
    Context& context = device.context();
    Window& window = *device.window();
    ViewerController controller(scene.ellipsoid(), scene.camera());
    using Key = InputEvent::Key;
    constexpr std::pair<char, Key> kFlyKeys[] = {{'W', Key::Forward}, {'S', Key::Backward}, {'A', Key::Left},
                                                 {'D', Key::Right},   {'E', Key::Up},       {'Q', Key::Down}};
    auto lastFrame = std::chrono::steady_clock::now();
    // H flies back to where the viewer started.
    const Geodetic3D home = scene.ellipsoid().toGeodetic3D(scene.camera().eye());
    const HeadingPitchRoll homeOrientation = scene.camera().headingPitchRoll(scene.ellipsoid());
    std::optional<CameraFlight> flight;
    double flown = 0.0;

    std::optional<Framebuffer> frame;
    std::string title;
    int shown = 0;
    while (!window.shouldClose() && (!options.frames || shown < *options.frames)) {
        window.pollEvents();
        const auto now = std::chrono::steady_clock::now();
        // Held keys move by the time since the last frame, at most a tenth of a second of it.
        const double seconds = std::min(std::chrono::duration<double>(now - lastFrame).count(), 0.1);
        lastFrame = now;
        const WindowInput input = window.takeInput();
        bool moved = input.dragPixels != glm::dvec2(0.0) || input.scrollSteps != 0.0;
        for (const char letter : input.pressedLetters) {
            if (letter == 'H') {
                flight.emplace(scene.ellipsoid(), scene.camera(), home, homeOrientation, 3.0);
                flown = 0.0;
            }
            if (letter == 'F') {
                const bool flying = controller.mode() == ViewerController::Mode::Fly;
                controller.setMode(flying ? ViewerController::Mode::Orbit : ViewerController::Mode::Fly, scene.camera());
                std::printf("%s\n", flying ? "orbiting" : "flying");
                std::fflush(stdout);
            }
        }
        controller.handle(InputEvent::drag(input.dragPixels.x, input.dragPixels.y));
        controller.handle(InputEvent::scroll(input.scrollSteps));
        if (controller.mode() == ViewerController::Mode::Fly) {
            for (const auto& [letter, key] : kFlyKeys) {
                if (window.isKeyDown(letter)) {
                    controller.handle(InputEvent::keyHeld(key, seconds));
                    moved = true;
                }
            }
        }
        if (input.doubleClickPixels) {
            // A double click flies to the ground under the pointer, a third of the way closer,
            // looking the same way.
            const int width = window.framebufferWidth();
            const int height = window.framebufferHeight();
            if (const std::optional<glm::dvec3> picked = scene.pickGround(*input.doubleClickPixels, width, height)) {
                const Camera& camera = scene.camera();
                const double distance = glm::distance(camera.eye(), *picked);
                const glm::dvec3 destination = *picked + (camera.eye() - *picked) * (1.0 / 3.0);
                flight.emplace(scene.ellipsoid(), camera, scene.ellipsoid().toGeodetic3D(destination),
                               camera.headingPitchRoll(scene.ellipsoid()), std::clamp(distance / 2.0e5, 1.0, 3.0));
                flown = 0.0;
            }
        }
        if (flight && moved) {
            // The user takes over from wherever the flight got to.
            flight.reset();
            controller.setMode(controller.mode(), scene.camera());
        }
        if (flight) {
            flown += seconds;
            flight->apply(flown, scene.camera());
            if (flown >= flight->duration()) {
                flight.reset();
                controller.setMode(controller.mode(), scene.camera());
            }
        } else if (moved) {
            controller.apply(scene.camera());
        }
        // Never under the terrain: 2 m above what was drawn there last.
        if (scene.keepCameraAboveGround(2.0)) {
            controller.setMode(controller.mode(), scene.camera());
        }
        const int width = window.framebufferWidth();
        const int height = window.framebufferHeight();
        if (width == 0 || height == 0) { // minimised
            continue;
        }
        if (!frame || frame->width() != width || frame->height() != height) {
            frame = context.createFramebuffer(width, height);
        }
        context.setFramebuffer(&*frame);
        const FrameStatistics statistics = scene.render(context);
        context.blit(*frame);
        if (statistics.tiles) {
            // The title bar says what is still streaming in.
            const TileStatistics& tiles = *statistics.tiles;
            std::string status = options.title;
            status.append(" - tiles: ").append(std::to_string(tiles.drawn)).append(" drawn, ");
            status.append(std::to_string(tiles.pending)).append(" pending");
            if (tiles.failed > 0) {
                status.append(", ").append(std::to_string(tiles.failed)).append(" failed");
            }
            if (status != title) {
                window.setTitle(status);
                title = status;
            }
        }
        if (shown == 0) {
            std::printf("window %dx%d, %s\n%s", width, height, device.info().renderer.c_str(), statistics.toText().c_str());
            std::fflush(stdout);
        }
        if (++shown == options.frames && options.output) {
            context.setFramebuffer(nullptr);
            writePng(context.readPixels(), *options.output);
            std::printf("%s: frame %d as shown\n", options.output->c_str(), shown);
        }
        window.swapBuffers();
    }
}

} // namespace orbis::examples
