// A user's program of the world-data layer alone: reads Natural Earth's countries (the GeoJSON
// installed with the package) without linking any GL.
#include <orbis/core/Math.h>
#include <orbis/world/GeoJson.h>
#include <orbis/world/SceneFile.h>

#include <cstdio>

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer countries.geojson\n");
        return 2;
    }
    const orbis::world::FeatureCollection countries = orbis::world::loadGeoJson(argv[1]);
    std::size_t named = 0;
    for (const orbis::world::Feature& feature : countries.features) {
        named += feature.stringProperty("name") ? 1 : 0;
    }
    std::printf("countries %zu, named %zu\n", countries.features.size(), named);
    // Scene files are world data too.
    const orbis::world::SceneDescription scene = orbis::world::parseSceneText(R"({"version": 1, "width": 320})", "consumer", ".");
    std::printf("scene width %d\n", scene.width);
    return 0;
}
