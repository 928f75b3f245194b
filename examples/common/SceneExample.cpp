#include "SceneExample.h"

#include <orbis/core/Error.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Device.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>

namespace orbis::examples {

int runSceneExample(int argc, char** argv, const std::string& defaultOutput,
                    const std::function<void(Scene&, const ExampleSettings&)>& setup)
{
    ExampleSettings settings;
    settings.output = defaultOutput;
    for (int i = 1; i < argc; ++i) {
        const bool hasValue = i + 1 < argc;
        if (std::strcmp(argv[i], "--out") == 0 && hasValue) {
            settings.output = argv[++i];
        } else if (std::strcmp(argv[i], "--width") == 0 && hasValue) {
            settings.width = std::atoi(argv[++i]);
        } else if (std::strcmp(argv[i], "--height") == 0 && hasValue) {
            settings.height = std::atoi(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: %s [--out file.png] [--width W] [--height H]\n", argv[0]);
            return 2;
        }
    }
    try {
        Device device;
        Context& context = device.context();
        Framebuffer framebuffer = context.createFramebuffer(settings.width, settings.height);
        context.setFramebuffer(&framebuffer);
        Scene scene;
        scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T12:00:00Z")));
        setup(scene, settings);
        const FrameStatistics statistics = scene.render(context);
        writePng(context.readPixels(), settings.output);
        std::printf("%s: %dx%d\n%s", settings.output.c_str(), settings.width, settings.height,
                    statistics.toText().c_str());
        return 0;
    } catch (const Error& error) {
        std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
        return 1;
    }
}

std::string naturalEarthPyramid()
{
    return std::string(ORBIS_DATA_DIR) + "/imagery/NaturalEarthII";
}

std::string xplanetDayImage()
{
    return "/usr/share/xplanet/images/earth.jpg";
}

std::string xplanetNightImage()
{
    return "/usr/share/xplanet/images/night.jpg";
}

void lookAtEarthFrom(Scene& scene, const Geodetic3D& eye)
{
    scene.camera().lookAt(scene.ellipsoid().toCartesian(eye), glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0));
}

} // namespace orbis::examples
