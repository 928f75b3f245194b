// Terrain sources on data the tests write themselves: quantized-mesh and heightmap-1.0 sets with
// layer.json (folders, MBTiles, HTTP from a server on 127.0.0.1), 16-bit PNG, Terrain-RGB and
// Terrarium pyramids, SRTM .hgt folders and GeoTIFF DEMs (geographic, 0..360, UTM), each against
// the height field it was made from.

#include "TempFiles.h"
#include "TestHttpServer.h"
#include "WorldTestSupport.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/FunctionTerrainSource.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TerrainCodec.h>
#include <orbis/world/TerrainLayer.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileMapResource.h>

#include <catch2/catch.hpp>

#include <GeographicLib/UTMUPS.hpp>
#include <glm/geometric.hpp>

#include <future>
#include <thread>

using namespace orbis;
using namespace orbis::world;
using orbis::test::MBTilesWriter;
using orbis::test::ScriptedResponse;
using orbis::test::TempDirectory;
using orbis::test::TestHttpServer;
using orbis::test::errorMessage;
using Catch::Matchers::Contains;
using Status = TerrainFetch::Status;

namespace {

/// The height field the DEMs and pyramids here are made from (degrees in, metres out): smooth, so
/// that bilinear interpolation at their resolutions stays within a few centimetres of it.
double field(double longitude, double latitude)
{
    return 1500.0 + 900.0 * std::sin(toRadians(3.0 * longitude)) * std::cos(toRadians(2.0 * latitude)) +
           20.0 * latitude;
}

TerrainSourceOptions formatOptions(const std::string& format)
{
    TerrainSourceOptions options;
    options.format = format;
    return options;
}

/// A mesh tile (n x n grid) of `f(u, v)`, as quantized-mesh bytes.
std::vector<std::uint8_t> meshTile(const TileKey& key, int n, float base, const std::string& metadata = "")
{
    TerrainTileData tile;
    tile.key = key;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            tile.vertices.emplace_back(float(i) / float(n - 1), float(j) / float(n - 1), base + 10.0f * float(i + j));
        }
    }
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const auto a = static_cast<std::uint32_t>(j * n + i);
            tile.indices.insert(tile.indices.end(), {a, a + 1, a + 1 + std::uint32_t(n), a, a + 1 + std::uint32_t(n), a + std::uint32_t(n)});
        }
    }
    QuantizedMeshEncoding encoding;
    encoding.metadataJson = metadata;
    encoding.gzipLevel = 6;
    return encodeQuantizedMesh(tile, encoding);
}

void write(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes)
{
    writeFileAtomically(path, bytes);
}

void write(const std::filesystem::path& path, const std::string& text)
{
    writeFileAtomically(path, std::string_view(text));
}

/// The largest difference between a grid tile's heights and the field at its samples.
double worstAgainstField(const TerrainTileData& tile)
{
    double worst = 0.0;
    for (int row = 0; row < tile.size; ++row) {
        for (int column = 0; column < tile.size; ++column) {
            const Geodetic2D g = terrainGridPosition(tile.key, tile.size, column, row);
            const double h = static_cast<double>(tile.heights[static_cast<std::size_t>(row * tile.size + column)]);
            worst = std::max(worst, std::abs(h - field(toDegrees(g.longitude), toDegrees(g.latitude))));
        }
    }
    return worst;
}

TerrainFetch loadOk(TerrainSource& source, const TileKey& key)
{
    TerrainFetch fetched = source.load(key);
    INFO(fetched.message);
    REQUIRE(fetched.status == Status::Ok);
    return fetched;
}

enum class Levels { Shared, Own };

/// Samples two neighbours (east-west and north-south) share are equal bit for bit, and those a
/// parent and child share too where both are sampled from the same height field (Levels::Shared;
/// a pyramid serves each level from its own source level, which are not the same heights).
void checkSharedSamples(TerrainSource& source, const TileKey& key, Levels levels = Levels::Shared)
{
    const TerrainTileData tile = loadOk(source, key).tile;
    const TerrainTileData east = loadOk(source, {key.level, key.x + 1, key.y}).tile;
    const TerrainTileData north = loadOk(source, {key.level, key.x, key.y + 1}).tile;
    const TerrainTileData child = loadOk(source, key.child(3)).tile; // north-east child
    const int n = tile.size;
    const int last = n - 1;
    auto at = [n](const TerrainTileData& t, int column, int row) { return t.heights[static_cast<std::size_t>(row * n + column)]; };
    for (int i = 0; i < n; ++i) {
        REQUIRE(at(tile, last, i) == at(east, 0, i));
        REQUIRE(at(tile, i, 0) == at(north, i, last));
    }
    // Normals, where the source gives them, see across the edge: both tiles shade it alike.
    if (!tile.normals.empty()) {
        auto normal = [n](const TerrainTileData& t, int column, int row) { return t.normals[static_cast<std::size_t>(row * n + column)]; };
        for (int i = 0; i < n; ++i) {
            REQUIRE(normal(tile, last, i) == normal(east, 0, i));
            REQUIRE(normal(tile, i, 0) == normal(north, i, last));
        }
    }
    if (levels == Levels::Own) {
        return;
    }
    // The child's samples at even indices are the parent's samples of its north-east quarter.
    for (int row = 0; row < n; row += 2) {
        for (int column = 0; column < n; column += 2) {
            REQUIRE(at(child, column, row) == at(tile, last / 2 + column / 2, row / 2));
        }
    }
}

} // namespace

TEST_CASE("Grid sample positions are shared bit for bit by neighbours and by parents and children", "[world][terrain][source]")
{
    const TilingScheme scheme = TilingScheme::geographic();
    for (const TileKey key : {TileKey{0, 0, 0}, TileKey{3, 5, 2}, TileKey{17, 70001, 30002}}) {
        const int n = 65;
        const GeodeticExtent extent = scheme.tileExtent(key);
        CHECK(terrainGridPosition(key, n, 0, 0).longitude == extent.west);
        CHECK(terrainGridPosition(key, n, 0, 0).latitude == extent.north);
        CHECK(terrainGridPosition(key, n, n - 1, n - 1).longitude == extent.east);
        CHECK(terrainGridPosition(key, n, n - 1, n - 1).latitude == extent.south);
        for (int i = 0; i < n; ++i) {
            CHECK(terrainGridPosition(key, n, n - 1, i) == terrainGridPosition({key.level, key.x + 1, key.y}, n, 0, i));
            CHECK(terrainGridPosition(key, n, i, 0) == terrainGridPosition({key.level, key.x, key.y + 1}, n, i, n - 1));
        }
        for (int child = 0; child < 4; ++child) {
            const TileKey c = key.child(child);
            for (int row = 0; row < n; row += 2) {
                for (int column = 0; column < n; column += 2) {
                    const int parentColumn = (child & 1) * 32 + column / 2;
                    const int parentRow = (child & 2 ? 0 : 32) + row / 2;
                    REQUIRE(terrainGridPosition(c, n, column, row) == terrainGridPosition(key, n, parentColumn, parentRow));
                }
            }
        }
    }
    CHECK(terrainLevelForResolution(1.0 / 12.0, 65) == 5);  // ETOPO5: 0.0879 degrees, within 10 %
    CHECK(terrainLevelForResolution(1.0 / 12.0, 257) == 3);
    CHECK(terrainLevelForResolution(3.0 / 3600.0, 65) == 12);
    CHECK(isTerrainGridSize(65));
    CHECK_FALSE(isTerrainGridSize(64));
    CHECK_FALSE(isTerrainGridSize(2049));
}

TEST_CASE("A quantized-mesh folder: layer.json's availability, errors and levels; a broken tile fails naming it",
          "[world][terrain][source]")
{
    const TempDirectory folder;
    TerrainLayer layer;
    layer.name = "test";
    layer.attribution = "made here";
    layer.maximumLevel = 1;
    layer.hasAvailable = true;
    layer.available = {{{0, 0, 1, 0}}, {{0, 0, 1, 1}}};
    LevelGeometricErrors errors;
    errors.width = 2;
    errors.height = 1;
    errors.errors = {12.5f, 7.0f};
    layer.geometricErrors = {errors};
    write(folder.path() / "layer.json", formatTerrainLayer(layer));
    write(folder.path() / "0/0/0.terrain", meshTile({0, 0, 0}, 5, 100.0f));
    write(folder.path() / "0/1/0.terrain", meshTile({0, 1, 0}, 3, 200.0f));
    write(folder.path() / "1/0/1.terrain", meshTile({1, 0, 1}, 3, 300.0f));
    write(folder.path() / "1/1/0.terrain", std::vector<std::uint8_t>{1, 2, 3});

    const auto source = openTerrainSource(folder.path().string());
    const TerrainSourceInfo& info = source->info();
    CHECK(info.format == "quantized-mesh");
    CHECK(info.gridSize == 0);
    CHECK(info.minimumLevel == 0);
    CHECK(info.maximumLevel == 1);
    CHECK(info.attribution == "made here");

    // The errors are known before any tile loads: the selection reads them.
    CHECK(source->geometricError({0, 1, 0}) == 7.0);
    CHECK_FALSE(source->geometricError({1, 0, 1}));

    const TerrainFetch first = loadOk(*source, {0, 0, 0});
    CHECK(first.tile.vertices.size() == 25);
    CHECK(first.tile.geometricError == 12.5);
    CHECK(first.tile.childMask == 0x0f);
    CHECK(loadOk(*source, {0, 1, 0}).tile.childMask == 0x00); // level 1 has columns 0 and 1 only
    CHECK(loadOk(*source, {1, 0, 1}).tile.vertices[0].z == 300.0f);
    CHECK_FALSE(loadOk(*source, {1, 0, 1}).tile.geometricError);

    CHECK(source->hasTile({1, 1, 1}));
    CHECK_FALSE(source->hasTile({1, 2, 0}));
    CHECK(source->load({1, 2, 0}).status == Status::Missing);
    CHECK(source->load({1, 1, 1}).status == Status::Missing); // available, but no file
    CHECK(source->load({2, 0, 0}).status == Status::Missing);
    const TerrainFetch broken = source->load({1, 1, 0});
    CHECK(broken.status == Status::Failed);
    CHECK_THAT(broken.message, Contains((folder.path() / "1/1/0.terrain").string()));

    // The same through layer.json's own path.
    CHECK(openTerrainSource((folder.path() / "layer.json").string())->load({0, 0, 0}).status == Status::Ok);
}

TEST_CASE("Availability in metadata tiles is learned as those tiles load", "[world][terrain][source]")
{
    const TempDirectory folder;
    TerrainLayer layer;
    layer.hasAvailable = true;
    layer.available = {{{0, 0, 1, 0}}};
    layer.metadataAvailability = 1;
    layer.maximumLevel = 3;
    write(folder.path() / "layer.json", formatTerrainLayer(layer));
    write(folder.path() / "0/0/0.terrain",
          meshTile({0, 0, 0}, 3, 0.0f, R"({"available":[[{"startX":0,"startY":0,"endX":0,"endY":0}]]})"));
    write(folder.path() / "1/0/0.terrain", meshTile({1, 0, 0}, 3, 0.0f));
    const auto source = openTerrainSource(folder.path().string());
    CHECK(source->hasTile({1, 1, 1})); // not known yet: its metadata tile has not loaded
    loadOk(*source, {0, 0, 0});
    CHECK(source->hasTile({1, 0, 0}));
    CHECK_FALSE(source->hasTile({1, 1, 1}));
    CHECK(source->load({1, 1, 1}).status == Status::Missing);
    CHECK(source->hasTile({1, 2, 0})); // under tile 0/1/0, which has not loaded
    CHECK(source->load({1, 0, 0}).status == Status::Ok);
}

TEST_CASE("heightmap-1.0 tiles from a folder keep their own child mask", "[world][terrain][source]")
{
    const TempDirectory folder;
    TerrainLayer layer;
    layer.format = "heightmap-1.0";
    layer.maximumLevel = 0;
    write(folder.path() / "layer.json", formatTerrainLayer(layer));
    TerrainTileData tile;
    tile.size = 65;
    tile.heights.assign(65 * 65, 42.0f);
    tile.childMask = 0x05;
    write(folder.path() / "0/1/0.terrain", encodeHeightmapTerrain(tile, 6));
    const auto source = openTerrainSource(folder.path().string());
    CHECK(source->info().format == "heightmap");
    CHECK(source->info().gridSize == 65);
    const TerrainFetch fetched = loadOk(*source, {0, 1, 0});
    CHECK(fetched.tile.size == 65);
    CHECK(fetched.tile.heights[100] == 42.0f);
    CHECK(fetched.tile.childMask == 0x05);
    CHECK(source->load({0, 0, 0}).status == Status::Missing);
    CHECK_THAT(errorMessage([&] { openTerrainSource(folder.path().string(), formatOptions("quantized-mesh")); }),
               Contains("layer.json says heightmap-1.0, not quantized-mesh"));
}

TEST_CASE("Quantized-mesh tiles in MBTiles, with layer.json in the metadata's json row", "[world][terrain][source][mbtiles]")
{
    const TempDirectory folder;
    const auto path = folder.path() / "terrain.mbtiles";
    {
        MBTilesWriter writer(path);
        writer.metadata("name", "terrain");
        writer.metadata("format", "quantized-mesh-1.0");
        writer.metadata("minzoom", "0");
        writer.metadata("maxzoom", "1");
        writer.metadata("json", R"({"available": [[{"startX": 0, "startY": 0, "endX": 1, "endY": 0}],
                                                  [{"startX": 3, "startY": 1, "endX": 3, "endY": 1}]]})");
        writer.tile(0, 1, 0, meshTile({0, 1, 0}, 3, 50.0f));
        writer.tile(1, 3, 1, meshTile({1, 3, 1}, 3, 60.0f));
    }
    const auto source = openTerrainSource(path.string());
    CHECK(source->info().format == "quantized-mesh");
    CHECK(loadOk(*source, {1, 3, 1}).tile.vertices[0].z == 60.0f);
    CHECK(source->hasTile({1, 3, 1}));
    CHECK_FALSE(source->hasTile({1, 2, 1}));
    CHECK(loadOk(*source, {0, 1, 0}).tile.childMask == 0x08); // only the north-east child (3, 1)
}

TEST_CASE("HTTP: layer.json and tiles from a server, with the Accept header quantized-mesh servers expect",
          "[world][terrain][source][http]")
{
    const TempDirectory cache;
    auto server = std::make_unique<TestHttpServer>();
    TerrainLayer layer;
    layer.version = "2.0";
    layer.maximumLevel = 1;
    const std::string text = formatTerrainLayer(layer);
    server->set("/world/layer.json", ScriptedResponse::ok({text.begin(), text.end()}));
    server->set("/world/0/0/0.terrain?v=2.0", ScriptedResponse::ok(meshTile({0, 0, 0}, 3, 10.0f)));
    ScriptedResponse flaky = ScriptedResponse::ok(meshTile({1, 2, 1}, 3, 20.0f));
    flaky.failuresFirst = 2;
    server->set("/world/1/2/1.terrain?v=2.0", flaky);
    TerrainSourceOptions options;
    options.tiles.http.backoff = std::chrono::milliseconds(5);
    options.tiles.http.totalTimeout = std::chrono::milliseconds(3000);
    options.tiles.cacheFolder = cache.path();
    {
        const auto source = openTerrainSource(server->url("/world"), options);
        CHECK(loadOk(*source, {0, 0, 0}).tile.vertices[0].z == 10.0f);
        CHECK_THAT(server->lastRequestHeaders("/world/0/0/0.terrain?v=2.0"),
                   Contains("Accept: application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata"));
        CHECK(loadOk(*source, {1, 2, 1}).tile.vertices[0].z == 20.0f);
        CHECK(server->requests("/world/1/2/1.terrain?v=2.0") == 3);
        CHECK(source->load({1, 0, 0}).status == Status::Missing); // 404
    }
    TerrainSourceOptions uncached = options;
    uncached.tiles.cacheFolder.clear();
    CHECK_THAT(errorMessage([&] { openTerrainSource(server->url("/none"), uncached); }),
               Contains(server->url("/none/layer.json") + ": no such file (HTTP 404)"));
    const std::string url = server->url("/world");
    server.reset();
    // Later, without the server: layer.json and the tile from the cache folder.
    const auto offline = openTerrainSource(url, options);
    CHECK(loadOk(*offline, {0, 0, 0}).tile.vertices[0].z == 10.0f);
}

TEST_CASE("A 16-bit PNG height pyramid of 2^k + 1 point samples is read tile for tile", "[world][terrain][source]")
{
    // units-per-pixel as the shared ETOPO5 tiles give it (the spacing of the samples, 180 / 16
    // degrees at level 0) or as imagery has it (180 / 17).
    const double spacing = GENERATE(180.0 / 16.0, tileMapUnitsPerPixel(TilingScheme::geographic(), 0, 17));
    const TempDirectory folder;
    TileMapResource resource;
    resource.extension = "png";
    resource.mimeType = "image/png";
    resource.tileWidth = 17;
    resource.tileHeight = 17;
    resource.tileSets = {{"0", 0, spacing}};
    write(folder.path() / "tilemapresource.xml", formatTileMapResource(resource));
    HeightGrid grid;
    grid.width = grid.height = 17;
    for (int i = 0; i < 17 * 17; ++i) {
        grid.heights.push_back(float(i * 3 - 400));
    }
    write(folder.path() / "0/1/0.png", encodeHeightPng16(grid));
    const auto source = openTerrainSource(folder.path().string());
    CHECK(source->info().format == "png16");
    CHECK(source->info().gridSize == 17);
    const TerrainFetch fetched = loadOk(*source, {0, 1, 0});
    CHECK(fetched.tile.size == 17);
    CHECK(fetched.tile.heights == grid.heights);
    CHECK(fetched.tile.minimumHeight == -400.0);
    CHECK(source->load({0, 0, 0}).status == Status::Missing);
}

TEST_CASE("Terrain-RGB and Terrarium Web Mercator pyramids are resampled into geographic grids", "[world][terrain][source]")
{
    for (const HeightEncoding encoding : {HeightEncoding::TerrainRgb, HeightEncoding::Terrarium}) {
        const TempDirectory folder;
        const int size = 64;
        const TilingScheme mercator = TilingScheme::webMercator();
        for (std::uint32_t level = 0; level <= 2; ++level) {
            for (std::uint32_t x = 0; x < mercator.tilesX(level); ++x) {
                for (std::uint32_t y = 0; y < mercator.tilesY(level); ++y) {
                    Image image(size, size, 3);
                    for (int row = 0; row < size; ++row) {
                        for (int column = 0; column < size; ++column) {
                            const double u = (x * size + column + 0.5) / (double(mercator.tilesX(level)) * size);
                            const double v = (y * size + row + 0.5) / (double(mercator.tilesY(level)) * size);
                            const double longitude = -180.0 + 360.0 * u;
                            const double latitude = toDegrees(TilingScheme::mercatorLatitude(kPi * (1.0 - 2.0 * v)));
                            const double h = field(longitude, latitude);
                            std::uint8_t* p = image.pixel(column, row);
                            if (encoding == HeightEncoding::TerrainRgb) {
                                const auto value = static_cast<std::uint32_t>(std::lround((h + 10000.0) * 10.0));
                                p[0] = std::uint8_t(value >> 16);
                                p[1] = std::uint8_t(value >> 8);
                                p[2] = std::uint8_t(value);
                            } else {
                                const double value = h + 32768.0;
                                p[0] = std::uint8_t(int(value) >> 8);
                                p[1] = std::uint8_t(int(value) & 255);
                                p[2] = std::uint8_t(std::lround((value - std::floor(value)) * 256.0) & 255);
                            }
                        }
                    }
                    write(folder.path() / std::to_string(level) / std::to_string(x) / (std::to_string(y) + ".png"),
                          encodePng(image, 1));
                }
            }
        }
        TerrainSourceOptions options;
        options.format = encoding == HeightEncoding::TerrainRgb ? "terrain-rgb" : "terrarium";
        options.tiles.tileWidth = options.tiles.tileHeight = size;
        options.tiles.maximumLevel = 2;
        options.gridSize = 17;
        const auto source = openTerrainSource((folder.path() / "{z}/{x}/{y}.png").string(), options);
        CHECK(source->info().format == options.format);
        CHECK(source->info().scheme == TilingScheme::geographic());
        CHECK(source->info().extent.north == kHalfPi);
        // Level 0's grid spacing is 11.25 degrees: the source's level 0 (5.6 degree pixels) serves it.
        for (const TileKey key : {TileKey{0, 0, 0}, TileKey{1, 2, 1}, TileKey{2, 5, 2}}) {
            const TerrainTileData tile = loadOk(*source, key).tile;
            REQUIRE(tile.size == 17);
            double worst = 0.0;
            for (int row = 0; row < 17; ++row) {
                for (int column = 0; column < 17; ++column) {
                    const Geodetic2D g = terrainGridPosition(key, 17, column, row);
                    if (std::abs(toDegrees(g.latitude)) > 80.0) {
                        continue; // beyond the Mercator rows' reach, the last row stands in
                    }
                    worst = std::max(worst, std::abs(double(tile.heights[std::size_t(row * 17 + column)]) -
                                                     field(toDegrees(g.longitude), toDegrees(g.latitude))));
                }
            }
            INFO(options.format << " tile " << key.level << "/" << key.x << "/" << key.y);
            // Bilinear between pixels at most p degrees a side errs by at most
            // p^2 / 8 (max |f_xx| + 2 max |f_xy| + max |f_yy|): for this field (900 sin 3x cos 2y)
            // that sum is 900 (9 + 12 + 4) (pi / 180)^2 = 6.85 m per square degree. Levels 0 and 1
            // are served by the source's level 0 (5.625 degree pixels), level 2 by its level 1.
            const double pixel = 360.0 / size / double(1u << (key.level == 0 ? 0 : key.level - 1));
            const double bound = pixel * pixel / 8.0 * 900.0 * 25.0 * (kPi / 180.0) * (kPi / 180.0);
            CHECK(worst < bound + 0.2); // + the encodings' steps (0.1 m, 1/256 m)
        }
        checkSharedSamples(*source, {1, 1, 0}, Levels::Own);
    }
}

TEST_CASE("A folder of SRTM .hgt files: heights between samples, voids, cells it lacks", "[world][terrain][source][hgt]")
{
    const TempDirectory folder;
    for (const int west : {0, 1}) {
        std::vector<std::uint8_t> bytes(2 * 1201 * 1201);
        for (int row = 0; row < 1201; ++row) {
            for (int column = 0; column < 1201; ++column) {
                const double longitude = west + column / 1200.0;
                const double latitude = 1.0 - row / 1200.0;
                auto value = static_cast<std::int16_t>(std::lround(field(longitude, latitude)));
                if (west == 1 && std::abs(row - 600) <= 1 && std::abs(column - 600) <= 1) {
                    value = -32768; // voids around 1.5 E, 0.5 N
                }
                const std::size_t i = 2 * (std::size_t(row) * 1201 + std::size_t(column));
                bytes[i] = std::uint8_t(std::uint16_t(value) >> 8);
                bytes[i + 1] = std::uint8_t(value);
            }
        }
        write(folder.path() / ("N00E00" + std::to_string(west) + ".hgt"), bytes);
    }
    write(folder.path() / "notes.txt", std::string("not a cell"));
    TerrainSourceOptions options;
    options.noDataHeight = -7.0;
    const auto source = openTerrainSource(folder.path().string(), options);
    CHECK(source->info().format == "hgt");
    CHECK(source->info().maximumLevel == 12);
    CHECK(source->info().extent == GeodeticExtent::fromDegrees(0.0, 0.0, 2.0, 1.0));
    // Level 9 tiles are 0.35 degrees: tile 512 starts at 0 E, row 256 at 0 N.
    const TileKey inside{9, 513, 256};
    CHECK(worstAgainstField(loadOk(*source, inside).tile) < 0.6); // integer metres, bilinear
    checkSharedSamples(*source, {9, 514, 256}); // across the cells' shared edge at 1 E
    CHECK_FALSE(source->hasTile({9, 600, 256}));
    CHECK(source->load({9, 600, 256}).status == Status::Missing);
    CHECK_FALSE(source->hasTile({13, 0, 0}));
    // Around the voids: samples with a void neighbour are made of the others; those between
    // voids alone have no data.
    const TerrainTileData voids = loadOk(*source, {12, 4130, 2059}).tile; // holds 1.5 E, 0.5 N
    std::size_t noData = 0;
    double worst = 0.0;
    for (int row = 0; row < 65; ++row) {
        for (int column = 0; column < 65; ++column) {
            const float h = voids.heights[std::size_t(row * 65 + column)];
            const Geodetic2D g = terrainGridPosition(voids.key, 65, column, row);
            if (h == -7.0f) {
                ++noData;
                CHECK(std::abs(toDegrees(g.longitude) - 1.5) < 1.0 / 1200.0);
                CHECK(std::abs(toDegrees(g.latitude) - 0.5) < 1.0 / 1200.0);
            } else {
                worst = std::max(worst, std::abs(double(h) - field(toDegrees(g.longitude), toDegrees(g.latitude))));
            }
        }
    }
    CHECK(noData >= 1);
    CHECK(worst < 0.6);
    const auto single = openTerrainSource((folder.path() / "N00E001.hgt").string(), options);
    CHECK(single->info().extent == GeodeticExtent::fromDegrees(1.0, 0.0, 2.0, 1.0));
}

TEST_CASE("A GeoTIFF DEM is point-sampled into every tile: the same sample has the same height everywhere",
          "[world][terrain][source][gdal]")
{
    const TempDirectory folder;
    // 10 .. 12 E, 40 .. 41 N at 0.01 degrees, with a block of nodata.
    const double transform[6] = {10.0, 0.01, 0.0, 41.0, 0.0, -0.01};
    orbis::test::writeDem(folder.path() / "dem.tif", 200, 100, transform, 4326, [](int column, int row) {
        if (column >= 150 && row >= 50) {
            return -9999.0f;
        }
        return static_cast<float>(field(10.0 + (column + 0.5) * 0.01, 41.0 - (row + 0.5) * 0.01));
    }, -9999.0);
    CHECK(openTerrainSource((folder.path() / "dem.tif").string())->info().maximumLevel == 8); // 0.0107: within 10 %
    TerrainSourceOptions options;
    options.noDataHeight = -5.0;
    options.maximumLevel = 10;
    const auto source = openTerrainSource((folder.path() / "dem.tif").string(), options);
    CHECK(source->info().format == "gdal");
    CHECK(source->info().gridSize == 65);
    CHECK(source->info().maximumLevel == 10);
    // Level 7 tiles are 1.4 degrees: column 135 is 9.84 .. 11.25 E, row 92 39.4 .. 40.8 N.
    CHECK(source->hasTile({7, 136, 92}));
    CHECK_FALSE(source->hasTile({7, 140, 92}));
    CHECK_FALSE(source->hasTile({7, 135, 80}));
    // A tile wholly on the DEM: 10.547 .. 11.25 E, 40.078 .. 40.781 N (level 8, 0.703 degrees).
    const TileKey whole{8, 271, 185};
    const GeodeticExtent extent = TilingScheme::geographic().tileExtent(whole);
    REQUIRE(toDegrees(extent.west) > 10.0);
    REQUIRE(toDegrees(extent.north) < 41.0);
    REQUIRE(toDegrees(extent.south) > 40.0);
    const TerrainTileData tile = loadOk(*source, whole).tile;
    CHECK(worstAgainstField(tile) < 0.2);
    checkSharedSamples(*source, {7, 135, 92});
    // Each sample's normal is the field's: its slope east and north, in metres a metre.
    REQUIRE(tile.normals.size() == tile.heights.size());
    const Ellipsoid earth = Ellipsoid::wgs84();
    double worstAngle = 0.0;
    for (int row = 0; row < tile.size; row += 8) {
        for (int column = 0; column < tile.size; column += 8) {
            const Geodetic2D g = terrainGridPosition(whole, tile.size, column, row);
            const double longitude = toDegrees(g.longitude);
            const double latitude = toDegrees(g.latitude);
            const double step = 0.001;
            const glm::dvec3 here = earth.toCartesian(Geodetic3D(g.longitude, g.latitude, 0.0));
            const double metresEast = glm::length(earth.toCartesian(Geodetic3D::fromDegrees(longitude + step, latitude, 0.0)) - here);
            const double metresNorth = glm::length(earth.toCartesian(Geodetic3D::fromDegrees(longitude, latitude + step, 0.0)) - here);
            const double dEast = (field(longitude + step, latitude) - field(longitude - step, latitude)) / (2.0 * metresEast);
            const double dNorth = (field(longitude, latitude + step) - field(longitude, latitude - step)) / (2.0 * metresNorth);
            const glm::dvec3 up = earth.geodeticSurfaceNormal(Geodetic3D(g.longitude, g.latitude, 0.0));
            const glm::dvec3 east = glm::normalize(glm::dvec3(-up.y, up.x, 0.0));
            const glm::dvec3 north = glm::cross(up, east);
            const glm::dvec3 expected = glm::normalize(-dEast * east - dNorth * north + up);
            const glm::dvec3 normal(tile.normals[static_cast<std::size_t>(row * tile.size + column)]);
            worstAngle = std::max(worstAngle, std::acos(std::min(1.0, glm::dot(normal, expected))));
        }
    }
    CHECK(toDegrees(worstAngle) < 0.05);
    // The nodata corner (11.5 .. 12 E, 40 .. 40.5 N) takes noDataHeight: a level 9 tile inside it.
    const TerrainTileData corner = loadOk(*source, {9, 545, 370}).tile; // 11.6 .. 11.95 E, 40.08 .. 40.43 N
    CHECK(std::all_of(corner.heights.begin(), corner.heights.end(), [](float h) { return h == -5.0f; }));
    CHECK(corner.minimumHeight == -5.0);

    // Loaded from four threads at once: the same heights.
    std::vector<TileKey> keys;
    for (std::uint32_t x = 271; x < 274; ++x) {
        for (std::uint32_t y = 185; y < 187; ++y) {
            keys.push_back({8, x, y});
        }
    }
    std::vector<std::vector<float>> alone;
    for (const TileKey& k : keys) {
        alone.push_back(loadOk(*source, k).tile.heights);
    }
    std::vector<std::future<bool>> threads;
    for (int t = 0; t < 4; ++t) {
        threads.push_back(std::async(std::launch::async, [&, t] {
            for (std::size_t i = 0; i < keys.size(); ++i) {
                const std::size_t j = (i + std::size_t(t) * 5) % keys.size();
                if (source->load(keys[j]).tile.heights != alone[j]) {
                    return false;
                }
            }
            return true;
        }));
    }
    for (auto& thread : threads) {
        CHECK(thread.get());
    }
}

TEST_CASE("A DEM with longitudes 0..360 gives the heights of the same DEM given -180..180", "[world][terrain][source][gdal]")
{
    const TempDirectory folder;
    // 190 .. 200 E is 170 .. 160 W; and a whole-globe DEM 0 .. 360 at 1 degree.
    const double east[6] = {190.0, 0.05, 0.0, 30.0, 0.0, -0.05};
    const double west[6] = {-170.0, 0.05, 0.0, 30.0, 0.0, -0.05};
    const auto height = [](double longitude0) {
        return [longitude0](int column, int row) {
            return static_cast<float>(field(longitude0 + (column + 0.5) * 0.05, 30.0 - (row + 0.5) * 0.05));
        };
    };
    orbis::test::writeDem(folder.path() / "east.tif", 200, 100, east, 4326, height(190.0));
    orbis::test::writeDem(folder.path() / "west.tif", 200, 100, west, 4326, height(-170.0));
    const double globe[6] = {-0.5, 1.0, 0.0, 90.5, 0.0, -1.0}; // 360 columns from 0 E, point samples at whole degrees
    orbis::test::writeDem(folder.path() / "globe.tif", 360, 181, globe, 4326,
                          [](int column, int row) { return static_cast<float>(field(column, 90.0 - row)); });
    TerrainSourceOptions deep;
    deep.maximumLevel = 8;
    const auto sourceEast = openTerrainSource((folder.path() / "east.tif").string(), deep);
    const auto sourceWest = openTerrainSource((folder.path() / "west.tif").string(), deep);
    CHECK(sourceEast->info().extent.west == sourceWest->info().extent.west);
    CHECK(sourceEast->info().extent.east == sourceWest->info().extent.east);
    // 168.75 .. 165.94 W, 25.3 .. 28.1 N; and 168.75 .. 167.3 W, 25.3 .. 26.7 N.
    for (const TileKey k : {TileKey{6, 4, 41}, TileKey{7, 8, 82}}) {
        const TerrainTileData a = loadOk(*sourceEast, k).tile;
        const TerrainTileData b = loadOk(*sourceWest, k).tile;
        REQUIRE(a.heights.size() == b.heights.size());
        for (std::size_t i = 0; i < a.heights.size(); ++i) {
            REQUIRE(std::abs(a.heights[i] - b.heights[i]) < 1e-3f);
        }
        CHECK(worstAgainstField(a) < 0.1);
    }
    const auto world = openTerrainSource((folder.path() / "globe.tif").string(), deep);
    CHECK(world->info().extent == GeodeticExtent::maximum());
    // Across the antimeridian (the DEM's columns 179 and 180) and the prime meridian (its seam).
    for (const TileKey k : {TileKey{3, 15, 4}, TileKey{3, 0, 4}, TileKey{3, 8, 4}, TileKey{3, 7, 4}}) {
        const TerrainTileData tile = loadOk(*world, k).tile;
        CHECK(worstAgainstField(tile) < 2.0); // bilinear between 1-degree samples
    }
    checkSharedSamples(*world, {3, 7, 4}); // across 0 E, where the DEM's columns wrap
    const TerrainTileData last = loadOk(*world, {3, 15, 4}).tile;
    const TerrainTileData first = loadOk(*world, {3, 0, 4}).tile;
    for (int row = 0; row < 65; ++row) {
        CHECK(last.heights[std::size_t(row * 65 + 64)] == first.heights[std::size_t(row * 65)]); // across 180 degrees
    }
}

TEST_CASE("A UTM DEM is warped into geographic tiles at the places GeographicLib puts its pixels", "[world][terrain][source][gdal]")
{
    const TempDirectory folder;
    // UTM zone 33 N, 100 m pixels, 300 x 300, top left at E 400 km, N 5,100 km (about 46 N, 13.7 E).
    const double transform[6] = {400000.0, 100.0, 0.0, 5100000.0, 0.0, -100.0};
    orbis::test::writeDem(folder.path() / "utm.tif", 300, 300, transform, 32633, [](int column, int row) {
        double latitude = 0.0, longitude = 0.0;
        GeographicLib::UTMUPS::Reverse(33, true, 400000.0 + (column + 0.5) * 100.0, 5100000.0 - (row + 0.5) * 100.0,
                                       latitude, longitude);
        return static_cast<float>(field(longitude, latitude));
    });
    const auto source = openTerrainSource((folder.path() / "utm.tif").string());
    // 100 m of latitude is 0.0009 degrees: level 11's 0.00137 is too coarse, level 12's 0.00069 fine enough.
    CHECK(source->info().maximumLevel == 12);
    const GeodeticExtent extent = source->info().extent;
    const TileKey key = *TilingScheme::geographic().tileAt(extent.centre(), 11);
    const TerrainTileData tile = loadOk(*source, key).tile;
    CHECK(worstAgainstField(tile) < 0.5);
}

TEST_CASE("Opening a terrain source that cannot be read says why", "[world][terrain][source]")
{
    const TempDirectory folder;
    CHECK_THAT(errorMessage([&] { openTerrainSource((folder.path() / "none").string()); }), Contains("none: no such file or folder"));
    CHECK_THAT(errorMessage([&] { openTerrainSource(folder.path().string()); }),
               Contains("no SRTM .hgt files (named like N37W123.hgt)"));
    CHECK_THAT(errorMessage([&] { openTerrainSource(folder.path().string(), formatOptions("lerc")); }),
               Contains("unknown terrain format \"lerc\""));
    TerrainSourceOptions odd;
    odd.gridSize = 64;
    CHECK_THAT(errorMessage([&] { openTerrainSource(folder.path().string(), odd); }),
               Contains("a terrain grid of 64 samples a side (2^k + 1, 3 to 1025)"));
    write(folder.path() / "plain.png", encodePng(Image(8, 8, 1), 1));
    CHECK_THAT(errorMessage([&] { openTerrainSource((folder.path() / "plain.png").string()); }),
               Contains("plain.png: the DEM is not georeferenced"));
    write(folder.path() / "bad/layer.json", std::string("{\"format\": 7}"));
    CHECK_THAT(errorMessage([&] { openTerrainSource((folder.path() / "bad").string()); }),
               Contains("bad/layer.json: /format: expected a string"));
    TerrainLayer mercator;
    mercator.projection = "EPSG:3857";
    write(folder.path() / "mercator/layer.json", formatTerrainLayer(mercator));
    CHECK_THAT(errorMessage([&] { openTerrainSource((folder.path() / "mercator").string()); }),
               Contains("terrain in EPSG:3857 is not supported"));
    CHECK_THAT(errorMessage([&] { openTerrainSource((folder.path() / "{z}/{x}/{y}.jpg").string()); }),
               Contains("name the terrain format"));
}

TEST_CASE("Terrain from a function: its heights at the grid samples, shared by neighbours and levels",
          "[world][terrain][source]")
{
    const auto height = [](const Geodetic2D& g) { return 1000.0 + 500.0 * std::sin(3.0 * g.longitude) * std::cos(2.0 * g.latitude); };
    FunctionTerrainSource source(height, 8);
    CHECK(source.info().gridSize == 65);
    CHECK(source.info().maximumLevel == 8);
    checkSharedSamples(source, {5, 20, 10});
    const TerrainTileData tile = loadOk(source, {3, 5, 2}).tile;
    for (int row = 0; row < tile.size; row += 16) {
        for (int column = 0; column < tile.size; column += 16) {
            CHECK(tile.heights[static_cast<std::size_t>(row * tile.size + column)] ==
                  static_cast<float>(height(terrainGridPosition({3, 5, 2}, 65, column, row))));
        }
    }
    CHECK_FALSE(source.hasTile({9, 0, 0}));
    CHECK(source.load({9, 0, 0}).status == TerrainFetch::Status::Missing);
    // Levels raised by the offset disagree, as a filtered pyramid's levels do.
    FunctionTerrainSource raised(height, 8, 10.0);
    const TerrainTileData level4 = loadOk(raised, {4, 3, 3}).tile;
    CHECK(level4.heights[0] == static_cast<float>(height(terrainGridPosition({4, 3, 3}, 65, 0, 0)) + 40.0));
}
