// Book section 4.2.3: day and night textures blended across the terminator, lit by the Sun of a
// fixed date. Usage: ch04_night_lights [--out file.png]
#include "../common/SceneExample.h"

#include <orbis/core/SunPosition.h>
#include <orbis/scene/Globe.h>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::scene;
    return examples::runSceneExample(argc, argv, "ch04_night_lights.png", [](Scene& scene, const auto&) {
        GlobeOptions options;
        options.lighting = true; // night lights show where the Sun does not
        options.dayTexture = examples::xplanetDayImage();
        options.nightTexture = examples::xplanetNightImage();
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
        // Evening over Europe at the June solstice: the terminator runs through the view.
        scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-06-21T19:30:00Z")));
        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(15.0, 35.0, 1.5e7));
    });
}
