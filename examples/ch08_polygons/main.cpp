// Book chapter 8: filled polygons on the ellipsoid. Every country of Natural Earth's countries-110m,
// ear clipped on the ellipsoid and subdivided to one degree, in translucent colours with white
// borders, seen from over Japan: Russia across the antimeridian to Chukotka, East Asia, Alaska. Usage: ch08_polygons [--out file.png] [--width W --height H]
#include "../common/SceneExample.h"

#include <orbis/scene/FeaturePrimitives.h>
#include <orbis/scene/Globe.h>
#include <orbis/world/GeoJson.h>

#include <glm/geometric.hpp>

#include <array>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::world;
    using namespace orbis::scene;
    return examples::runSceneExample(argc, argv, "ch08_polygons.png", [](Scene& scene, const auto&) {
        GlobeOptions globe;
        globe.lighting = true;
        globe.color = {0.08f, 0.16f, 0.32f, 1.0f};
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), globe));

        FeatureStyle style;
        // Colours by the feature's place in the file (alphabetical), so neighbours mostly differ.
        static constexpr std::array<glm::vec4, 7> kPalette = {
            glm::vec4(0.89f, 0.45f, 0.36f, 0.8f), glm::vec4(0.95f, 0.77f, 0.36f, 0.8f),
            glm::vec4(0.55f, 0.78f, 0.45f, 0.8f), glm::vec4(0.42f, 0.68f, 0.84f, 0.8f),
            glm::vec4(0.70f, 0.55f, 0.82f, 0.8f), glm::vec4(0.93f, 0.60f, 0.75f, 0.8f),
            glm::vec4(0.45f, 0.80f, 0.75f, 0.8f)};
        style.fillColorOf = [](const Feature& feature) { return kPalette[feature.index % kPalette.size()]; };
        style.border.color = {1.0f, 1.0f, 1.0f, 1.0f};
        style.border.widthPixels = 1.0f;
        const FeatureCollection countries = loadGeoJson(examples::dataDirectory() / "natural-earth" / "countries-110m.geojson");
        buildFeaturePrimitives(scene.ellipsoid(), countries, style).addTo(scene);

        // Daylight where the camera looks.
        scene.setSunDirection(glm::normalize(scene.ellipsoid().toCartesian(Geodetic3D::fromDegrees(140.0, 40.0))));
        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(140.0, 40.0, 1.4e7));
    });
}
