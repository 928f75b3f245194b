// Book section 4.1: the globe as a tessellated mesh, here an octahedron subdivided six times and
// projected onto WGS84, drawn relative to the eye, textured with the Natural Earth II tile
// pyramid. Usage: ch04_subdivision_sphere [--out file.png]
#include "../common/SceneExample.h"

#include <orbis/scene/Globe.h>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::scene;
    return examples::runSceneExample(argc, argv, "ch04_subdivision_sphere.png", [](Scene& scene, const auto&) {
        GlobeOptions options;
        options.lighting = true;
        options.method = GlobeMethod::Tessellated;
        options.tessellation = GlobeTessellation::SubdivisionEllipsoid;
        options.tessellationLevel = 6;
        options.dayTexture = examples::naturalEarthPyramid(); // the TMS tiles, joined

        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(-60.0, 10.0, 1.8e7));
    });
}
