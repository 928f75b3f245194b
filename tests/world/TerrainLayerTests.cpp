// layer.json: read as CesiumJS writes it, written and read back equal, and refused with the key
// named when anything is wrong.

#include "TempFiles.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/world/TerrainLayer.h>

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace orbis;
using namespace orbis::world;
using orbis::test::errorMessage;
using Catch::Matchers::Contains;

namespace {

// As terrain servers publish it (keys they add that we do not read included).
const char* const kCesiumStyle = R"({
  "tilejson": "2.1.0",
  "name": "world",
  "description": "",
  "version": "1.2.0",
  "format": "quantized-mesh-1.0",
  "attribution": "Someone",
  "template": "terrain",
  "legend": "",
  "scheme": "tms",
  "tiles": [ "{z}/{x}/{y}.terrain?v={version}" ],
  "projection": "EPSG:4326",
  "bounds": [ -180.00, -90.00, 180.00, 90.00 ],
  "available": [
    [ { "startX": 0, "startY": 0, "endX": 1, "endY": 0 } ],
    [ { "startX": 0, "startY": 0, "endX": 3, "endY": 1 } ],
    [ { "startX": 0, "startY": 0, "endX": 3, "endY": 1 }, { "startX": 6, "startY": 2, "endX": 7, "endY": 3 } ]
  ],
  "extensions": ["octvertexnormals", "watermask", "metadata"],
  "metadataAvailability": 10,
  "bvhlevels": 6
})";

} // namespace

TEST_CASE("A layer.json as terrain servers write it is read", "[world][terrain][layer]")
{
    const TerrainLayer layer = parseTerrainLayer(kCesiumStyle, "layer.json");
    CHECK(layer.name == "world");
    CHECK(layer.version == "1.2.0");
    CHECK(layer.format == "quantized-mesh-1.0");
    CHECK(layer.attribution == "Someone");
    CHECK(layer.rowsFromSouth);
    CHECK(layer.tiles == std::vector<std::string>{"{z}/{x}/{y}.terrain?v={version}"});
    CHECK(layer.bounds == GeodeticExtent::maximum());
    REQUIRE(layer.available.size() == 3);
    CHECK(layer.available[2][1] == TileRectangle{6, 2, 7, 3});
    CHECK(layer.metadataAvailability == 10u);
    CHECK(layer.extensions.size() == 3);
    CHECK(layer.minimumLevel == 0);
    CHECK(layer.maximumLevel == 30); // no maxzoom: as deep as the metadata tiles say

    CHECK(layerHasTile(layer, {2, 7, 3}));
    CHECK_FALSE(layerHasTile(layer, {2, 5, 3}));
    CHECK(layerHasTile(layer, {1, 3, 1}));
    CHECK(layerHasTile(layer, {5, 0, 0})); // beyond "available": in metadata tiles, not known here
}

TEST_CASE("layer.json written by formatTerrainLayer reads back equal, per-tile errors included", "[world][terrain][layer]")
{
    TerrainLayer layer;
    layer.name = "ETOPO5 \"5 minute\"";
    layer.description = "a test\nwith a newline";
    layer.attribution = "NOAA";
    layer.format = "heightmap-1.0";
    layer.rowsFromSouth = false;
    layer.bounds = GeodeticExtent::fromDegrees(-84.41375, 36.44625, -84.077916666666667, 36.732916666666667);
    layer.minimumLevel = 0;
    layer.maximumLevel = 2;
    layer.hasAvailable = true;
    layer.available = {{{0, 0, 0, 0}}, {{1, 0, 2, 1}}, {{3, 1, 4, 2}, {7, 3, 7, 3}}};
    layer.extensions = {"octvertexnormals"};
    layer.metadataAvailability = 4;
    LevelGeometricErrors errors;
    errors.level = 2;
    errors.startX = 3;
    errors.startY = 1;
    errors.width = 2;
    errors.height = 2;
    errors.errors = {1.25f, std::numeric_limits<float>::quiet_NaN(), 0.07f, 1234.5f};
    layer.geometricErrors = {errors};
    const std::string text = formatTerrainLayer(layer);
    const TerrainLayer back = parseTerrainLayer(text, "written.json");
    CHECK(back.name == layer.name);
    CHECK(back.description == layer.description);
    CHECK(back.format == layer.format);
    CHECK(back.rowsFromSouth == false);
    CHECK(back.bounds == layer.bounds);
    CHECK(back.available == layer.available);
    CHECK(back.extensions == layer.extensions);
    CHECK(back.metadataAvailability == 4u);
    CHECK(back.maximumLevel == 2);
    REQUIRE(back.geometricErrors.size() == 1);
    CHECK(back.geometricError({2, 3, 1}) == 1.25);
    CHECK_FALSE(back.geometricError({2, 4, 1}));
    CHECK(back.geometricError({2, 3, 2}) == double(0.07f));
    CHECK(back.geometricError({2, 4, 2}) == 1234.5);
    CHECK_FALSE(back.geometricError({2, 5, 2}));
    CHECK_FALSE(back.geometricError({1, 1, 0}));
    CHECK(formatTerrainLayer(back) == text);
}

TEST_CASE("A malformed layer.json names the file and the key", "[world][terrain][layer]")
{
    auto message = [](const std::string& text) { return errorMessage([&] { parseTerrainLayer(text, "bad/layer.json"); }); };
    CHECK_THAT(message("{\"format\": \"quantized-mesh-1.0\",\n \"tiles\": [\"a\" \"b\"]}"),
               Contains("bad/layer.json:2:") && Contains("invalid JSON"));
    CHECK_THAT(message(std::string(100, '[') + std::string(100, ']')), Contains("JSON nested deeper than 32 levels"));
    CHECK_THAT(message("[]"), Contains("bad/layer.json: /: a layer.json is a JSON object"));
    CHECK_THAT(message(R"({"format": "pbf"})"),
               Contains("/format: \"pbf\" is not a tile format this reader knows"));
    CHECK_THAT(message(R"({"tiles": []})"), Contains("/tiles: no tile URL template"));
    CHECK_THAT(message(R"({"tiles": [7]})"), Contains("/tiles/0: expected a string"));
    CHECK_THAT(message(R"({"scheme": "zxy"})"), Contains("/scheme: \"zxy\" is neither"));
    CHECK_THAT(message(R"({"projection": "EPSG:2056"})"), Contains("/projection: \"EPSG:2056\""));
    CHECK_THAT(message(R"({"bounds": [10, 0, -10, 5]})"), Contains("/bounds: not a rectangle"));
    CHECK_THAT(message(R"({"bounds": [0, 0, 1]})"), Contains("/bounds: expected [west, south, east, north]"));
    CHECK_THAT(message(R"({"available": [[{"startX": 0, "startY": 0, "endX": 2, "endY": 0}]]})"),
               Contains("/available/0/0/endX: expected a whole number from 0 to 1"));
    CHECK_THAT(message(R"({"available": [[], [{"startX": 1, "startY": 0, "endX": 0, "endY": 0}]]})"),
               Contains("/available/1/0: start beyond end"));
    CHECK_THAT(message(R"({"available": [[{"startX": -1, "startY": 0, "endX": 0, "endY": 0}]]})"),
               Contains("/available/0/0/startX: expected a whole number"));
    CHECK_THAT(message(R"({"available": [[{"startX": 0, "startY": 0, "endX": 0}]]})"), Contains("/available/0/0: no endY"));
    CHECK_THAT(message(R"({"minzoom": 5, "maxzoom": 2})"), Contains("/minzoom: minzoom 5 is above maxzoom 2"));
    CHECK_THAT(message(R"({"maxzoom": 31})"), Contains("/maxzoom: expected a whole number from 0 to 30"));
    CHECK_THAT(message(R"({"metadataAvailability": 0})"), Contains("0 levels between metadata tiles"));
    CHECK_THAT(message(R"({"orbis:geometricError": [{"level": 0, "startX": 0, "startY": 0, "width": 2, "height": 1, "errors": [1]}]})"),
               Contains("/orbis:geometricError/0/errors: 1 errors for 2 x 1 tiles"));
    CHECK_THAT(message(R"({"orbis:geometricError": [{"level": 0, "startX": 0, "startY": 0, "width": 3, "height": 1, "errors": [1, 2, 3]}]})"),
               Contains("/orbis:geometricError/0/width: expected a whole number from 0 to 2"));
    CHECK_THAT(message(R"({"orbis:geometricError": [{"level": 0, "startX": 0, "startY": 0, "width": 1, "height": 1, "errors": [-1]}]})"),
               Contains("a negative error"));
    CHECK_THAT(message(std::string("{\"name\": \"a\"}\0", 14)), Contains("a NUL byte"));
    CHECK_THAT(message(std::string(kMaximumTerrainLayerBytes + 1, ' ')), Contains("more than the 33554432 a layer.json may have"));
}

TEST_CASE("rectanglesOf covers exactly the tiles given", "[world][terrain][layer]")
{
    std::mt19937 random(5);
    for (int trial = 0; trial < 50; ++trial) {
        std::set<std::pair<std::uint32_t, std::uint32_t>> tiles;
        for (int i = 0; i < 60; ++i) {
            tiles.insert({random() % 12, random() % 9});
        }
        const LevelAvailability rectangles = rectanglesOf({tiles.begin(), tiles.end()});
        std::size_t covered = 0;
        for (std::uint32_t y = 0; y < 9; ++y) {
            for (std::uint32_t x = 0; x < 12; ++x) {
                const auto count = std::count_if(rectangles.begin(), rectangles.end(),
                                                 [&](const TileRectangle& r) { return r.contains(x, y); });
                REQUIRE(count == (tiles.count({x, y}) ? 1 : 0));
                covered += static_cast<std::size_t>(count);
            }
        }
        CHECK(covered == tiles.size());
        CHECK(rectangles.size() <= tiles.size());
    }
    // A full block is one rectangle.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> block;
    for (std::uint32_t y = 3; y < 7; ++y) {
        for (std::uint32_t x = 2; x < 5; ++x) {
            block.emplace_back(x, y);
        }
    }
    CHECK(rectanglesOf(block) == LevelAvailability{{2, 3, 4, 6}});
}
