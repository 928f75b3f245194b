// A user's program of the scene: a globe rendered headless from a scene description.
#include <orbis/renderer/Device.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/Scene.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/world/SceneFile.h>

#include <cstdio>

int main()
{
    orbis::renderer::Device device;
    orbis::renderer::Context& context = device.context();
    orbis::renderer::Framebuffer framebuffer = context.createFramebuffer(64, 64);
    context.setFramebuffer(&framebuffer);

    const orbis::world::SceneDescription description = orbis::world::parseSceneText(
        R"({"version": 1, "background": "#000000", "camera": {"position": {"lon": 0, "lat": 0, "height": 2e7},
            "target": {"lon": 0, "lat": 0, "height": 0}}, "globe": {"method": "raycast"}})",
        "consumer", ".");
    orbis::scene::Scene scene;
    orbis::scene::populateScene(description, scene);
    const orbis::scene::FrameStatistics statistics = scene.render(context);
    const orbis::Image image = context.readPixels();
    const std::uint8_t* centre = image.pixel(32, 32);
    const std::uint8_t* corner = image.pixel(0, 0);
    std::printf("globe %s, corner %s, %zu commands\n", centre[0] + centre[1] + centre[2] > 0 ? "drawn" : "missing",
                corner[0] + corner[1] + corner[2] == 0 ? "background" : "drawn", statistics.commandsExecuted);
    return 0;
}
