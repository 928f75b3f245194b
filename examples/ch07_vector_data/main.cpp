// Book chapter 7: vector data as polylines. Natural Earth's country borders on the day globe, and
// two flight routes along geodesics, one across the antimeridian, drawn as wide outlined lines.
// Usage: ch07_vector_data [--out file.png] [--width W --height H]
#include "../common/SceneExample.h"

#include <orbis/scene/FeaturePrimitives.h>
#include <orbis/scene/Globe.h>
#include <orbis/world/GeoJson.h>

#include <glm/geometric.hpp>

int main(int argc, char** argv)
{
    using namespace orbis;
    using namespace orbis::world;
    using namespace orbis::scene;
    return examples::runSceneExample(argc, argv, "ch07_vector_data.png", [](Scene& scene, const auto&) {
        GlobeOptions globe;
        globe.lighting = true;
        globe.dayTexture = examples::xplanetDayImage();
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), globe));

        FeatureStyle style;
        style.fill = false;
        style.border = {glm::vec4(1.0f, 0.85f, 0.2f, 1.0f), 1.5f, glm::vec4(0.1f, 0.1f, 0.1f, 1.0f), 0.75f, true};
        style.granularityRadians = toRadians(0.5);
        const FeatureCollection countries = loadGeoJson(examples::dataDirectory() / "natural-earth" / "countries-110m.geojson");
        buildFeaturePrimitives(scene.ellipsoid(), countries, style).addTo(scene);

        PolylineCollectionOptions options;
        options.curve = CurveType::Geodesic;
        options.granularityRadians = toRadians(0.5);
        auto routes = std::make_shared<PolylineCollection>(scene.ellipsoid(), options);
        const PolylineStyle route{glm::vec4(0.9f, 0.1f, 0.1f, 1.0f), 3.0f, glm::vec4(1.0f), 1.0f, true};
        const Geodetic3D tokyoSanFrancisco[] = {Geodetic3D::fromDegrees(139.78, 35.55),
                                                Geodetic3D::fromDegrees(-122.38, 37.62)};
        const Geodetic3D aucklandHonolulu[] = {Geodetic3D::fromDegrees(174.79, -37.01),
                                               Geodetic3D::fromDegrees(-157.92, 21.32)};
        routes->add(tokyoSanFrancisco, route);
        routes->add(aucklandHonolulu, route);
        scene.add(routes);

        // Daylight where the camera looks.
        scene.setSunDirection(glm::normalize(scene.ellipsoid().toCartesian(Geodetic3D::fromDegrees(-170.0, 10.0))));
        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(-170.0, 30.0, 1.6e7));
    });
}
