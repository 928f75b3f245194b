#pragma once

// What every scene example shares: arguments, a headless device, a framebuffer, one frame of a
// Scene written to a PNG, and the frame statistics printed.

#include <orbis/scene/Scene.h>

#include <functional>
#include <string>

namespace orbis::examples {

struct ExampleSettings {
    std::string output; ///< PNG path
    int width = 800;
    int height = 600;
};

/// Parses [--out file.png] [--width W] [--height H], builds the scene with `setup`, renders one
/// frame and writes the PNG. Returns the process exit code: 0, 1 for an orbis::Error, 2 for usage.
int runSceneExample(int argc, char** argv, const std::string& defaultOutput,
                    const std::function<void(Scene&, const ExampleSettings&)>& setup);

/// The Natural Earth II TMS pyramid in data/imagery.
std::string naturalEarthPyramid();

/// The day and night Earth images of Debian's xplanet-images package.
std::string xplanetDayImage();
std::string xplanetNightImage();

/// A camera looking at the Earth's centre from a geodetic position.
void lookAtEarthFrom(Scene& scene, const Geodetic3D& eye);

} // namespace orbis::examples
