#include <orbis/world/GeoJson.h>

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include "GeodeticChecks.h"
#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;

namespace {

const std::filesystem::path kDataDir = std::filesystem::path(ORBIS_SOURCE_DIR) / "data";

/// A FeatureCollection around the given feature texts.
std::string collection(std::initializer_list<std::string> features)
{
    std::string text = R"({"type": "FeatureCollection", "features": [)";
    bool first = true;
    for (const std::string& feature : features) {
        text += (first ? "\n" : ",\n") + feature;
        first = false;
    }
    return text + "\n]}\n";
}

std::string feature(const std::string& name, const std::string& geometry)
{
    return R"({"type": "Feature", "properties": {"name": ")" + name + R"("}, "geometry": )" + geometry + "}";
}

const std::string kSquare = R"({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]})";

} // namespace

TEST_CASE("loadGeoJson reads the 177 Natural Earth countries with names and valid positions", "[world][geojson]")
{
    const FeatureCollection countries = loadGeoJson(kDataDir / "natural-earth/countries-110m.geojson");
    REQUIRE(countries.features.size() == 177);
    CHECK(countries.warnings.empty());
    std::size_t polygons = 0;
    std::size_t multiPolygons = 0;
    for (std::size_t i = 0; i < countries.features.size(); ++i) {
        const Feature& country = countries.features[i];
        CHECK(country.index == i);
        REQUIRE(country.geometry);
        CHECK(country.stringProperty("name"));
        polygons += std::holds_alternative<Polygon>(country.geometry->value);
        multiPolygons += std::holds_alternative<MultiPolygon>(country.geometry->value);
    }
    CHECK(polygons + multiPolygons == 177);

    const Feature& fiji = countries.features[0];
    CHECK(fiji.stringProperty("name") == "Fiji");
    CHECK(fiji.id == "242");
    const auto* multi = std::get_if<MultiPolygon>(&fiji.geometry->value);
    REQUIRE(multi);
    REQUIRE(multi->polygons.size() == 2); // Fiji's two main islands at 1:110m
    const LinearRing& ring = multi->polygons[0].rings.at(0);
    REQUIRE(ring.size() == 9);
    test::checkPosition(ring[0], 178.12438124381248, -17.505557252327606);
    CHECK(ring.front() == ring.back());
}

TEST_CASE("loadGeoJson reads the Natural Earth land polygons", "[world][geojson]")
{
    const FeatureCollection land = loadGeoJson(kDataDir / "natural-earth/land-110m.geojson");
    REQUIRE_FALSE(land.features.empty());
    for (const Feature& feature : land.features) {
        REQUIRE(feature.geometry);
        const bool polygonal = std::holds_alternative<Polygon>(feature.geometry->value) ||
                               std::holds_alternative<MultiPolygon>(feature.geometry->value);
        CHECK(polygonal);
    }
}

TEST_CASE("parseGeoJson reads every geometry type, heights, holes and properties", "[world][geojson]")
{
    const std::string text = collection({
        R"({"type": "Feature", "id": 7, "properties": {"name": "here", "population": 1500, "capital": true,
            "note": null, "tags": ["a", "b"], "nested": {"k": 1}},
            "geometry": {"type": "Point", "coordinates": [-180, 90, 12.5]}})",
        feature("mp", R"({"type": "MultiPoint", "coordinates": [[1, 2], [3, 4]]})"),
        feature("ls", R"({"type": "LineString", "coordinates": [[1, 2], [3, 4], [5, 6]]})"),
        feature("mls", R"({"type": "MultiLineString", "coordinates": [[[1, 2], [3, 4]], [[5, 6], [7, 8]]]})"),
        feature("hole", R"({"type": "Polygon", "coordinates": [
            [[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]],
            [[2, 2], [2, 4], [4, 4], [4, 2], [2, 2]]]})"),
        feature("mpoly", R"({"type": "MultiPolygon", "coordinates": [[[[0, 0], [1, 0], [1, 1], [0, 0]]],
            [[[5, 5], [6, 5], [6, 6], [5, 5]]]]})"),
        feature("gc", R"({"type": "GeometryCollection", "geometries": [{"type": "Point", "coordinates": [1, 1]},
            {"type": "GeometryCollection", "geometries": [)" + kSquare + "]}]}"),
        R"({"type": "Feature", "properties": null, "geometry": null, "bbox": [0, 0, 1, 1], "foreign": 3})",
    });
    const FeatureCollection result = parseGeoJson(text, "inline.geojson");
    REQUIRE(result.features.size() == 8);
    CHECK(result.warnings.empty());

    const Feature& point = result.features[0];
    CHECK(point.id == "7");
    test::checkPosition(std::get<Point>(point.geometry->value).position, -180, 90, 12.5);
    CHECK(point.stringProperty("name") == "here");
    CHECK(point.numberProperty("population") == 1500.0);
    CHECK(std::get<bool>(*point.property("capital")) == true);
    CHECK(std::holds_alternative<std::monostate>(*point.property("note")));
    CHECK(std::get<std::string>(*point.property("tags")) == R"(["a","b"])");
    CHECK(std::get<std::string>(*point.property("nested")) == R"({"k":1})");
    CHECK(point.property("absent") == nullptr);
    CHECK_FALSE(point.stringProperty("population"));

    const auto& multiPoint = std::get<MultiPoint>(result.features[1].geometry->value);
    REQUIRE(multiPoint.positions.size() == 2);
    test::checkPosition(multiPoint.positions[1], 3, 4);
    CHECK(std::get<LineString>(result.features[2].geometry->value).positions.size() == 3);
    const auto& lines = std::get<MultiLineString>(result.features[3].geometry->value);
    REQUIRE(lines.lines.size() == 2);
    test::checkPosition(lines.lines[1].positions[1], 7, 8);

    const auto& withHole = std::get<Polygon>(result.features[4].geometry->value);
    REQUIRE(withHole.rings.size() == 2);
    CHECK(withHole.rings[0].size() == 5);
    test::checkPosition(withHole.rings[1][1], 2, 4);

    CHECK(std::get<MultiPolygon>(result.features[5].geometry->value).polygons.size() == 2);
    const auto& geometries = std::get<GeometryCollection>(result.features[6].geometry->value).geometries;
    REQUIRE(geometries.size() == 2);
    CHECK(std::holds_alternative<Point>(geometries[0].value));
    const auto& inner = std::get<GeometryCollection>(geometries[1].value).geometries;
    REQUIRE(inner.size() == 1);
    CHECK(std::get<Polygon>(inner[0].value).rings[0].size() == 5);

    CHECK_FALSE(result.features[7].geometry);
    CHECK(result.features[7].properties.empty());
    CHECK(result.features[7].index == 7);
}

TEST_CASE("parseGeoJson accepts a single Feature or a bare geometry at top level", "[world][geojson]")
{
    const FeatureCollection single = parseGeoJson(feature("one", kSquare), "feature.geojson");
    REQUIRE(single.features.size() == 1);
    CHECK(single.features[0].stringProperty("name") == "one");

    const FeatureCollection bare = parseGeoJson(R"({"type": "LineString", "coordinates": [[0, 0], [1, 1]]})", "g");
    REQUIRE(bare.features.size() == 1);
    CHECK(std::holds_alternative<LineString>(bare.features[0].geometry->value));
    CHECK(bare.features[0].properties.empty());
}

TEST_CASE("GeoJSON errors name the file, line and column, the feature, its name, the JSON path and the problem",
          "[world][geojson]")
{
    const test::TempDirectory directory;
    const std::string bad = R"({"type": "Polygon", "coordinates": [[[177, -17], [178, -17], [178, -16], [177, 95], [177, -17]]]})";
    const auto path = directory.write("countries.geojson", collection({feature("Tonga", kSquare), feature("Fiji", bad)}));
    CHECK_THAT(test::errorMessage([&] { loadGeoJson(path); }),
               Equals(path.string() + ":3:138: feature 1 (name \"Fiji\"): geometry.coordinates[0][3]: latitude 95 out "
                                      "of range [-90, 90]")); // the third line holds Fiji; [177, 95] starts at 138
}

TEST_CASE("GeoJSON syntax errors name the file, line and column, as scene files' do", "[world][geojson]")
{
    const test::TempDirectory directory;
    const std::string whole = collection({feature("a", kSquare), feature("b", kSquare)});
    const std::string half = whole.substr(0, whole.size() / 2);
    const auto truncated = directory.write("truncated.geojson", half);
    const std::string message = test::errorMessage([&] { loadGeoJson(truncated); });
    // The error is at the end of the text: its last line, one past its last byte.
    const auto lines = std::count(half.begin(), half.end(), '\n') + 1;
    const auto lastLineLength = half.size() - half.rfind('\n') - 1;
    CHECK_THAT(message, Contains(truncated.string() + ":" + std::to_string(lines) + ":" +
                                 std::to_string(lastLineLength + 1) + ": invalid JSON: "));
    CHECK_THAT(message, Contains("unexpected end of input"));

    const auto comma = directory.write("comma.geojson", "{\"type\": \"Point\",\n \"coordinates\": [1, 2],, }");
    CHECK_THAT(test::errorMessage([&] { loadGeoJson(comma); }),
               Contains(comma.string() + ":2:24: invalid JSON: "));

    // A number too large for a double is caught by the JSON reader, before any feature is read.
    CHECK_THAT(test::errorMessage([&] { parseGeoJson("{\"type\": \"Point\",\n\"coordinates\": [1, 1e999]}", "big.json"); }),
               Equals("big.json:2:20: invalid JSON: 1e999 is too large for a double"));

    // Nesting deep enough to exhaust the stack is refused before parsing; brackets in strings do not count.
    const std::string deep = R"({"type": "Feature", "geometry": null, "properties": {"s": "[[[[", "a": )" +
                             std::string(100000, '[') + std::string(100000, ']') + "}}";
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(deep, "deep.json"); }),
               Equals("deep.json:1:326: invalid JSON: nested deeper than 256 levels"));

    CHECK_THAT(test::errorMessage([&] { parseGeoJson("", "empty.json"); }),
               Equals("empty.json: the file is empty; expected a JSON object"));

    // The parser stops at a NUL byte: what follows would be ignored without a word.
    const std::string nul("{\"type\": \"FeatureCollection\", \"features\": []}\n\0{{{", 50);
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(nul, "nul.json"); }),
               Equals("nul.json:2:1: invalid JSON: a NUL byte (JSON text has none; is this a binary file?)"));
}

TEST_CASE("GeoJSON with wrong types, missing members and non-numbers is rejected with a path", "[world][geojson]")
{
    struct Case {
        std::string geometry;
        std::string expected;
    };
    const Case cases[] = {
        {R"({"type": "Point", "coordinates": ["NaN", 1]})",
         R"(geometry.coordinates[0]: expected a number (longitude), got "NaN")"},
        {R"({"type": "Point", "coordinates": [1, "Infinity"]})",
         R"(geometry.coordinates[1]: expected a number (latitude), got "Infinity")"},
        {R"({"type": "Point", "coordinates": [1]})",
         "geometry.coordinates: a position needs longitude and latitude, got an array of 1 element"},
        {R"({"type": "Point"})", "geometry: missing \"coordinates\" for a Point"},
        {R"({"type": "Polygon", "coordinates": "none"})",
         "geometry.coordinates: expected an array of rings, got \"none\""},
        {R"({"type": "MultiPolygon", "coordinates": [[[[0, 0], [1, 0], [1, 1], [0, 0]]], 5]})",
         "geometry.coordinates[1]: expected an array of rings, got 5"},
        {R"({"type": "LineString", "coordinates": [[0, 0]]})",
         "geometry.coordinates: a LineString needs at least 2 positions, got 1"},
        {R"({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [0, 0]]]})",
         "geometry.coordinates[0]: a ring needs at least 4 positions (3 corners and the first repeated), got 3"},
        {R"({"type": "MultiLineString", "coordinates": [[[0, 0], [200, 0]]]})",
         "geometry.coordinates[0][1]: longitude 200 out of range [-180, 180]"},
        {R"({"type": "Circle", "coordinates": [0, 0]})", "geometry.type: unknown geometry type \"Circle\""},
        {R"({"coordinates": [0, 0]})", "geometry: missing \"type\""},
        {R"([0, 0])", "geometry: expected a geometry object, got an array of 2 elements"},
        {R"({"type": "GeometryCollection", "geometries": [{"type": "Point", "coordinates": [0, true]}]})",
         "geometry.geometries[0].coordinates[1]: expected a number (latitude), got true"},
    };
    for (const Case& c : cases) {
        INFO(c.geometry);
        CHECK_THAT(test::errorMessage([&] { parseGeoJson(collection({feature("x", c.geometry)}), "f.json"); }),
                   Contains(": feature 0 (name \"x\"): " + c.expected));
        // On the feature's line, at the value at fault.
        CHECK_THAT(test::errorMessage([&] { parseGeoJson(collection({feature("x", c.geometry)}), "f.json"); }),
                   StartsWith("f.json:2:"));
    }

    CHECK_THAT(test::errorMessage([&] { parseGeoJson(collection({R"({"type": "Feature", "properties": {}})"}), "f"); }),
               Equals("f:2:1: feature 0: missing \"geometry\" (use null for a feature without one)"));
    CHECK_THAT(test::errorMessage([&] {
                   parseGeoJson(collection({R"({"type": "Feature", "properties": 3, "geometry": null})"}), "f");
               }),
               Equals("f:2:35: feature 0: properties: expected an object or null, got 3"));
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(collection({"42"}), "f"); }),
               Equals("f:2:1: feature 0: expected a Feature object, got 42"));
    CHECK_THAT(test::errorMessage([&] {
                   parseGeoJson(collection({R"({"type": "Feature", "id": "a1", "geometry": {"type": "Point"}})"}), "f");
               }),
               Equals("f:2:45: feature 0 (id \"a1\"): geometry: missing \"coordinates\" for a Point"));
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(R"({"type": "FeatureCollection"})", "f"); }),
               Equals("f: features: expected an array of features, got nothing"));
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(R"({"type": "Topology"})", "f"); }),
               Contains("f: arcs: expected an array of arcs"));
    // A named object whose "type" is not a string (the geojson fuzzer's crash): an error, not an
    // escaped JSON exception.
    CHECK_THROWS_AS(parseGeoJson(R"({"type": "Topology", "arcs": [], "objects": {"a": {"type": 7}}})", "f"), Error);
    CHECK_THAT(test::errorMessage([&] { parseGeoJson("[1, 2]", "f"); }),
               Equals("f:1:1: expected a GeoJSON object at top level, got an array of 2 elements"));
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(R"({"type": "Point", "coordinates": [0, -91]})", "f"); }),
               Equals("f:1:34: coordinates: latitude -91 out of range [-90, 90]"));
}

TEST_CASE("An open ring is an error unless closeOpenRings, which closes it and warns", "[world][geojson]")
{
    const std::string open = collection(
        {feature("open", R"({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1]]]})")});
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(open, "open.geojson"); }),
               Equals("open.geojson:2:101: feature 0 (name \"open\"): geometry.coordinates[0]: ring is not closed: "
                      "first position (0, 0) differs from the last (0, 1)"));

    GeoJsonOptions options;
    options.closeOpenRings = true;
    const FeatureCollection closed = parseGeoJson(open, "open.geojson", options);
    REQUIRE(closed.features.size() == 1);
    const LinearRing& ring = std::get<Polygon>(closed.features[0].geometry->value).rings[0];
    REQUIRE(ring.size() == 5);
    CHECK(ring.front() == ring.back());
    REQUIRE(closed.warnings.size() == 1);
    CHECK_THAT(closed.warnings[0], Contains("open.geojson:2:101: feature 0 (name \"open\"): geometry.coordinates[0]: "
                                            "closed an open ring"));

    // Closing cannot rescue a ring with too few corners.
    const std::string twoCorners =
        collection({feature("two", R"({"type": "Polygon", "coordinates": [[[0, 0], [1, 0]]]})")});
    CHECK_THAT(test::errorMessage([&] { parseGeoJson(twoCorners, "f", options); }), Contains("got 3"));
}

TEST_CASE("skipInvalidFeatures keeps the valid features and reports each bad one", "[world][geojson]")
{
    const test::TempDirectory directory;
    const auto path = directory.write(
        "mixed.geojson",
        collection({feature("good", kSquare), feature("bad", R"({"type": "Point", "coordinates": [0, "x"]})"),
                    feature("open", R"({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1]]]})"),
                    feature("also good", R"({"type": "Point", "coordinates": [3, 4]})")}));
    CHECK_THROWS_AS(loadGeoJson(path), Error);

    GeoJsonOptions options;
    options.skipInvalidFeatures = true;
    const FeatureCollection result = loadGeoJson(path, options);
    REQUIRE(result.features.size() == 2);
    CHECK(result.features[0].index == 0);
    CHECK(result.features[1].index == 3);
    CHECK(result.features[1].stringProperty("name") == "also good");
    REQUIRE(result.warnings.size() == 2);
    CHECK_THAT(result.warnings[0], Contains(path.string() + ":3:") && Contains(": feature 1 (name \"bad\"): geometry.coordinates[1]"));
    CHECK_THAT(result.warnings[1], Contains(path.string() + ":4:") && Contains(": feature 2 (name \"open\")"));

    // Errors outside any feature still throw.
    CHECK_THROWS_AS(parseGeoJson("{\"type\": ", "f", options), Error);
}

TEST_CASE("loadGeoJson names the path of a missing file", "[world][geojson]")
{
    CHECK_THAT(test::errorMessage([] { loadGeoJson("/nonexistent/countries.geojson"); }),
               Contains("/nonexistent/countries.geojson: GeoJSON file: no such file"));
}
