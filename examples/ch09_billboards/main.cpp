// Book chapter 9: billboards and labels. All 171,075 GeoNames cities as billboards in one
// collection (one draw call), and the name of every Natural Earth country as a label with a halo,
// over the textured globe. Cities and names behind the Earth are hidden by the horizon test, and
// names that would overlap a larger country's are left out (LabelCollectionOptions::declutter).
// Usage: ch09_billboards [--out file.png] [--width W] [--height H]
// Data: examples::dataDirectory() (the folder ORBIS_DATA_DIR names, or data/).
#include "../common/SceneExample.h"

#include <orbis/scene/BillboardCollection.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/LabelCollection.h>
#include <orbis/world/CsvPoints.h>
#include <orbis/world/GeoJson.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace {

using namespace orbis;
using namespace orbis::world;
using namespace orbis::scene;

/// A soft round dot, 3 x 3 pixels, white: the colour comes from each billboard.
Image cityDot()
{
    static const std::uint8_t alpha[3][3] = {{40, 150, 40}, {150, 255, 150}, {40, 150, 40}};
    Image image(3, 3, 4);
    for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 3; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            p[0] = p[1] = p[2] = 255;
            p[3] = alpha[y][x];
        }
    }
    return image;
}

glm::dvec3 unitVector(const Geodetic3D& p)
{
    return {std::cos(p.latitude) * std::cos(p.longitude), std::cos(p.latitude) * std::sin(p.longitude),
            std::sin(p.latitude)};
}

/// Twice the vector area of a ring on the unit sphere (its magnitude grows with the area, its
/// direction points to the middle for rings smaller than a hemisphere), turned outwards.
glm::dvec3 vectorArea(const LinearRing& ring)
{
    glm::dvec3 sum(0.0);
    glm::dvec3 mean(0.0);
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
        const glm::dvec3 a = unitVector(ring[i]);
        sum += glm::cross(a, unitVector(ring[i + 1]));
        mean += a;
    }
    return glm::dot(sum, mean) < 0.0 ? -sum : sum;
}

/// Where a country's name goes: the direction of the middle of its largest polygon's outer ring,
/// with that polygon's size (twice its area on the unit sphere, roughly) as the length.
std::optional<glm::dvec3> largestPolygonArea(const Feature& feature)
{
    if (!feature.geometry) {
        return std::nullopt;
    }
    std::vector<const Polygon*> polygons;
    if (const auto* polygon = std::get_if<Polygon>(&feature.geometry->value)) {
        polygons.push_back(polygon);
    } else if (const auto* multi = std::get_if<MultiPolygon>(&feature.geometry->value)) {
        for (const Polygon& p : multi->polygons) {
            polygons.push_back(&p);
        }
    }
    glm::dvec3 best(0.0);
    for (const Polygon* polygon : polygons) {
        if (!polygon->rings.empty()) {
            const glm::dvec3 area = vectorArea(polygon->rings.front());
            if (glm::length(area) > glm::length(best)) {
                best = area;
            }
        }
    }
    return glm::length(best) > 0.0 ? std::optional(best) : std::nullopt;
}

} // namespace

int main(int argc, char** argv)
{
    return examples::runSceneExample(argc, argv, "ch09_billboards.png", [](Scene& scene, const auto&) {
        const Ellipsoid& ellipsoid = scene.ellipsoid();
        GlobeOptions globe;
        globe.lighting = true;
        globe.dayTexture = examples::xplanetDayImage();
        scene.add(std::make_shared<Globe>(ellipsoid, globe));

        const CsvPoints cities = loadCsvPoints(examples::dataDirectory() / "geonames" / "cities.csv");
        const auto billboards = examples::cityBillboards(ellipsoid, cities, cityDot());
        scene.add(billboards);

        const FeatureCollection countries = loadGeoJson(examples::dataDirectory() / "natural-earth" / "countries-110m.geojson");
        // Larger countries first: where names overlap, decluttering keeps the earlier one.
        std::vector<std::pair<double, Label>> named;
        for (const Feature& country : countries.features) {
            const std::optional<std::string> name = country.stringProperty("name");
            const std::optional<glm::dvec3> area = largestPolygonArea(country);
            if (!name || !area) {
                continue;
            }
            Label label;
            label.position = ellipsoid.scaleToGeocentricSurface(glm::normalize(*area) * ellipsoid.maximumRadius());
            label.text = *name;
            label.fontSizePixels = 13.0f;
            label.verticalOrigin = VerticalOrigin::Center;
            named.emplace_back(glm::length(*area), label);
        }
        std::stable_sort(named.begin(), named.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        LabelCollectionOptions labelOptions;
        labelOptions.declutter = true;
        auto labels = std::make_shared<LabelCollection>(labelOptions);
        for (const auto& [size, label] : named) {
            labels->add(label);
        }
        scene.add(labels);
        std::printf("%zu cities as billboards (%zu bytes each), %zu country labels (decluttered)\n",
                    billboards->size(), BillboardCollection::vertexSizeInBytes(), labels->size());

        examples::lookAtEarthFrom(scene, Geodetic3D::fromDegrees(20.0, 35.0, 1.1e7));
    });
}
