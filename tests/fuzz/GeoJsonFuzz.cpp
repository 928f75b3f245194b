// libFuzzer target for the vector readers and what render does with their polygons: any input
// either parses (GeoJSON, or TopoJSON, which parseGeoJson recognises) into finite positions whose
// polygons triangulate or are refused with orbis::Error naming the polygon, or is refused with an
// orbis::Error naming the file. Any other exception, a crash, a hang or a sanitizer report is a bug.
// Built and run by scripts/fuzz.sh (clang, -fsanitize=fuzzer,address,undefined).
#include <orbis/core/Ellipsoid.h>
#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/core/Error.h>
#include <orbis/world/GeoJson.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

namespace {

constexpr std::string_view kOrigin = "fuzz.geojson";

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

bool isFinite(const orbis::Geodetic3D& position)
{
    return std::isfinite(position.longitude) && std::isfinite(position.latitude) && std::isfinite(position.height);
}

/// Triangulates a polygon as PolygonCollection does (a coarse granularity keeps each run short).
void triangulate(const orbis::world::Polygon& polygon, std::size_t& verticesLeft)
{
    const orbis::Ellipsoid& earth = orbis::Ellipsoid::wgs84();
    std::vector<std::vector<glm::dvec3>> rings;
    for (const orbis::world::LinearRing& ring : polygon.rings) {
        if (ring.size() > verticesLeft) {
            return;
        }
        verticesLeft -= ring.size();
        std::vector<glm::dvec3>& cartesian = rings.emplace_back();
        for (const orbis::Geodetic3D& position : ring) {
            require(isFinite(position));
            cartesian.push_back(earth.toCartesian(position));
        }
    }
    try {
        orbis::triangulatePolygon(earth, rings, orbis::toRadians(10.0), "fuzzed");
    } catch (const orbis::Error& error) {
        // Named, and a piece of it named after the name ("polygon 'fuzzed (its piece in ...)'").
        require(std::string_view(error.what()).starts_with("polygon 'fuzzed"));
    }
}

struct PolygonVisitor {
    std::size_t verticesLeft = 20000; // triangulation is n log n, but the grid and queue are not free
    void operator()(const orbis::world::Polygon& polygon) { triangulate(polygon, verticesLeft); }
    void operator()(const orbis::world::MultiPolygon& multi)
    {
        for (const orbis::world::Polygon& polygon : multi.polygons) {
            triangulate(polygon, verticesLeft);
        }
    }
    void operator()(const orbis::world::GeometryCollection& collection)
    {
        for (const orbis::world::Geometry& geometry : collection.geometries) {
            std::visit(*this, geometry.value);
        }
    }
    template <typename Other>
    void operator()(const Other&)
    {
    }
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    orbis::world::FeatureCollection features;
    try {
        features = orbis::world::parseGeoJson(text, kOrigin);
    } catch (const orbis::Error& error) {
        require(std::string_view(error.what()).starts_with(kOrigin));
        return 0;
    }
    PolygonVisitor visitor;
    for (const orbis::world::Feature& feature : features.features) {
        if (feature.geometry) {
            std::visit(visitor, feature.geometry->value);
        }
    }
    return 0;
}
