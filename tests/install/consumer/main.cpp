// A user's program built against the installed orbis package.
#include <orbis/core/Ellipsoid.h>
#include <orbis/renderer/EmbeddedShaders.h>
#include <orbis/world/SceneFile.h>

#include <cstdio>

int main()
{
    const orbis::Ellipsoid earth = orbis::Ellipsoid::wgs84();
    const orbis::Geodetic3D centre = earth.toGeodetic3D({0.0, 0.0, 0.0});
    std::printf("centre height %.0f\n", centre.height);
    // The renderer links too (its shaders are embedded; no GL context is needed for this).
    std::printf("built-in GLSL library %s\n", orbis::renderer::embeddedShader("renderer/builtin/constants.glsl") ? "embedded" : "missing");
    // orbis::scene, with its privately linked dependencies found by the package.
    const orbis::world::SceneDescription scene = orbis::world::parseSceneText(R"({"version": 1, "width": 320})", "consumer", ".");
    std::printf("scene width %d\n", scene.width);
    return 0;
}
