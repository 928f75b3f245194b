// Book section 4.3: the globe ray cast in a fragment shader over its bounding box, with the
// correct depth written. Usage: ch04_globe_ray_casting [--out file.png] [--width W] [--height H]
#include "../common/SceneExample.h"

#include <orbis/scene/Globe.h>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::scene;
    return examples::runSceneExample(argc, argv, "ch04_globe_ray_casting.png", [](Scene& scene, const auto&) {
        GlobeOptions options;
        options.lighting = true;
        options.method = GlobeMethod::RayCast;
        options.dayTexture = examples::xplanetDayImage();
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(10.0, 20.0, 2.0e7));
    });
}
