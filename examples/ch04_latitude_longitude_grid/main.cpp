// Book section 4.2.4: a latitude-longitude grid drawn in the fragment shader with lines of
// constant pixel width, spaced by the viewer's distance. Usage: ch04_latitude_longitude_grid [--out file.png]
#include "../common/SceneExample.h"

#include <orbis/scene/Globe.h>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::scene;
    return examples::runSceneExample(argc, argv, "ch04_latitude_longitude_grid.png", [](Scene& scene, const auto&) {
        GlobeOptions options;
        options.lighting = true;
        options.dayTexture = examples::xplanetDayImage();
        options.grid = true;
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(20.0, 50.0, 1.2e7));
    });
}
