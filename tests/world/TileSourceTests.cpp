#include "TempFiles.h"
#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TileMapResource.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

#include <sqlite3.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include <sys/stat.h>

using namespace orbis;
using namespace orbis::world;
using orbis::test::MBTilesWriter;
using orbis::test::TempDirectory;
using Catch::Matchers::Contains;
using Status = TileFetch::Status;

namespace {

const std::filesystem::path kNaturalEarth = ORBIS_SOURCE_DIR "/data/imagery/NaturalEarthII";

std::vector<std::uint8_t> tileBytes(int seed)
{
    return encodePng(orbis::test::testPattern(8 + seed, 8, 3), 1);
}

/// Runs `work` where a hang shows as a failed wait instead of blocking the suite.
template <typename Work>
auto withinSeconds(int seconds, Work work)
{
    auto future = std::async(std::launch::async, work);
    REQUIRE(future.wait_for(std::chrono::seconds(seconds)) == std::future_status::ready);
    return future.get();
}

} // namespace

TEST_CASE("A TMS folder gives its tiles, and keys outside its levels are missing without a look", "[world][source]")
{
    const auto source = openTileSource(kNaturalEarth.string());
    const TileSourceInfo& info = source->info();
    REQUIRE(info.name == kNaturalEarth.string());
    REQUIRE(info.scheme == TilingScheme::geographic());
    REQUIRE(info.minimumLevel == 0);
    REQUIRE(info.maximumLevel == 2);
    REQUIRE(info.format == "jpg");
    REQUIRE(source->locate({1, 2, 1}) == (kNaturalEarth / "1/2/1.jpg").string());
    const TileFetch fetched = source->fetch({1, 2, 1});
    REQUIRE(fetched.status == Status::Ok);
    REQUIRE(fetched.bytes == readFileBytes(kNaturalEarth / "1/2/1.jpg", "tile"));
    REQUIRE(decodeImage(fetched.bytes, source->locate({1, 2, 1})).width == 256);
    REQUIRE(source->fetch({3, 0, 0}).status == Status::Missing);  // deeper than the pyramid
    REQUIRE(source->fetch({1, 4, 0}).status == Status::Missing);  // column 4 of 4
    REQUIRE(source->fetch({0, 0, 1}).status == Status::Missing);  // row 1 of 1
    // The description's own path opens the same pyramid.
    REQUIRE(openTileSource((kNaturalEarth / "tilemapresource.xml").string())->info().maximumLevel == 2);
}

TEST_CASE("A tile that is missing, a pipe or a folder is Missing or Failed, quickly", "[world][source][hostile]")
{
    const TempDirectory folder;
    TileMapResource resource;
    resource.extension = "png";
    resource.tileSets = {{"0", 0, tileMapUnitsPerPixel(TilingScheme::geographic(), 0, 256)}};
    writeFileAtomically(folder.path() / "tilemapresource.xml", formatTileMapResource(resource));
    writeFileAtomically(folder.path() / "0/0/0.png", tileBytes(0));
    std::filesystem::create_directories(folder.path() / "0/1");
    REQUIRE(::mkfifo((folder.path() / "0/1/0.png").c_str(), 0600) == 0);
    const auto source = openTileSource(folder.path().string());
    REQUIRE(source->fetch({0, 0, 0}).status == Status::Ok);
    const TileFetch pipe = withinSeconds(10, [&] { return source->fetch({0, 1, 0}); });
    REQUIRE(pipe.status == Status::Failed);
    REQUIRE_THAT(pipe.message, Contains((folder.path() / "0/1/0.png").string()) && Contains("named pipe"));
    std::filesystem::remove(folder.path() / "0/1/0.png");
    REQUIRE(source->fetch({0, 1, 0}).status == Status::Missing);
    std::filesystem::create_directories(folder.path() / "0/1/0.png");
    REQUIRE_THAT(source->fetch({0, 1, 0}).message, Contains("is a folder"));
    TileSourceOptions small;
    small.maximumTileBytes = 10;
    REQUIRE_THAT(openTileSource(folder.path().string(), small)->fetch({0, 0, 0}).message, Contains("more than the 10 allowed"));
}

TEST_CASE("A mercator TMS folder counts its rows from the south on disk", "[world][source]")
{
    const TempDirectory folder;
    TileMapResource resource;
    resource.scheme = TilingScheme::webMercator();
    resource.extension = "png";
    for (std::uint32_t level = 0; level <= 2; ++level) {
        resource.tileSets.push_back({std::to_string(level), level, tileMapUnitsPerPixel(resource.scheme, level, 256)});
    }
    writeFileAtomically(folder.path() / "tilemapresource.xml", formatTileMapResource(resource));
    // XYZ row 0 (the north) of level 2 is TMS row 3.
    writeFileAtomically(folder.path() / "2/1/3.png", tileBytes(1));
    const auto source = openTileSource(folder.path().string());
    REQUIRE(source->info().scheme == TilingScheme::webMercator());
    REQUIRE(source->locate({2, 1, 0}) == (folder.path() / "2/1/3.png").string());
    REQUIRE(source->fetch({2, 1, 0}).bytes == tileBytes(1));
    REQUIRE(source->fetch({2, 1, 3}).status == Status::Missing);
}

TEST_CASE("Templates count {y} from the north and {reverseY} from the south in either scheme", "[world][source]")
{
    const TempDirectory folder;
    const std::string base = folder.path().string();
    const auto xyz = openTileSource(base + "/{z}/{x}/{y}.png");
    REQUIRE(xyz->info().scheme == TilingScheme::webMercator());
    REQUIRE(xyz->info().format == "png");
    REQUIRE(xyz->locate({2, 1, 0}) == base + "/2/1/0.png");
    REQUIRE(openTileSource(base + "/{z}/{x}/{reverseY}.png")->locate({2, 1, 0}) == base + "/2/1/3.png");
    REQUIRE(openTileSource(base + "/{z}/{x}/{-y}.png")->locate({2, 1, 0}) == base + "/2/1/3.png");
    TileSourceOptions geographic;
    geographic.scheme = TilingScheme::geographic();
    // Geographic keys count from the south: row 0 of level 1 (of 2 rows) is row 1 from the north.
    REQUIRE(openTileSource(base + "/{z}/{x}/{y}.jpg", geographic)->locate({1, 3, 0}) == base + "/1/3/1.jpg");
    REQUIRE(openTileSource(base + "/{z}/{x}/{reverseY}.jpg", geographic)->locate({1, 3, 0}) == base + "/1/3/0.jpg");
    const auto servers = openTileSource("https://{s}.tiles.example/{z}/{x}/{y}.webp?key=1");
    REQUIRE(servers->locate({1, 0, 0}) == "https://b.tiles.example/1/0/0.webp?key=1");
    REQUIRE(servers->locate({1, 1, 0}) == "https://c.tiles.example/1/1/0.webp?key=1");
    REQUIRE(servers->info().format == "webp");
    TileSourceOptions named;
    named.subdomains = "alpha,beta";
    REQUIRE(openTileSource("https://{s}.example/{z}/{x}/{y}", named)->locate({0, 0, 0}) == "https://alpha.example/0/0/0");

    writeFileAtomically(folder.path() / "2/1/0.png", tileBytes(2));
    REQUIRE(xyz->fetch({2, 1, 0}).bytes == tileBytes(2));
    REQUIRE(xyz->fetch({2, 1, 1}).status == Status::Missing);
    REQUIRE(xyz->fetch({19, 0, 0}).status == Status::Missing); // beyond the default maximum level 18
}

TEST_CASE("Bad templates and missing sources are refused when opened, naming them", "[world][source][hostile]")
{
    REQUIRE_THROWS_WITH(openTileSource("tiles/{z}/{x}/{q}.png"),
                        Contains("tiles/{z}/{x}/{q}.png: unknown placeholder {q} (known: {z} {x} {y} {reverseY} {-y} {s})"));
    REQUIRE_THROWS_WITH(openTileSource("tiles/{z}/{y}.png"), Contains("a template needs {z}, {x} and {y} or {reverseY}"));
    REQUIRE_THROWS_WITH(openTileSource("tiles/{z}/{x}/{y.png"), Contains("a '{' without '}'"));
    TileSourceOptions noServers;
    noServers.subdomains = "";
    REQUIRE_THROWS_WITH(openTileSource("http://{s}.a/{z}/{x}/{y}", noServers), Contains("uses {s} but no subdomains"));
    TileSourceOptions deep;
    deep.maximumLevel = 31;
    REQUIRE_THROWS_WITH(openTileSource("t/{z}/{x}/{y}", deep), Contains("levels 0 to 31 are not within 0 to 30"));
    REQUIRE_THROWS_WITH(openTileSource("/nowhere/at/all"), Contains("/nowhere/at/all: no such file or folder"));
    REQUIRE_THROWS_WITH(openTileSource(""), Contains("an empty tile source path"));
    REQUIRE_THROWS_WITH(openTileSource("http://127.0.0.1:1/world.mbtiles"), Contains("MBTiles files are read from disk"));
    const TempDirectory folder;
    writeFileAtomically(folder.path() / "notes.txt", std::string_view("just text"));
    REQUIRE_THROWS_WITH(openTileSource((folder.path() / "notes.txt").string()), Contains("notes.txt: not an MBTiles file"));
    REQUIRE_THROWS_WITH(openTileSource(folder.path().string()), Contains("tilemapresource.xml: no such file"));
}

TEST_CASE("Keys outside the source's extent are missing without a look", "[world][source]")
{
    const TempDirectory folder;
    TileSourceOptions options;
    options.scheme = TilingScheme::geographic();
    options.extent = GeodeticExtent::fromDegrees(0.0, 0.0, 90.0, 45.0); // the level-1 tile (2, 1) and no other
    writeFileAtomically(folder.path() / "1/2/1.png", tileBytes(3));
    writeFileAtomically(folder.path() / "1/1/1.png", tileBytes(3));
    const auto source = openTileSource(folder.path().string() + "/{z}/{x}/{reverseY}.png", options);
    REQUIRE(source->fetch({1, 2, 1}).status == Status::Ok);
    // Sharing only the west edge (0 degrees) with the extent: none of it inside.
    REQUIRE(source->fetch({1, 1, 1}).status == Status::Missing);
    // Across the antimeridian: an extent from 170 E to 170 W holds the first and last columns.
    options.extent = GeodeticExtent::fromDegrees(170.0, -10.0, -170.0, 10.0);
    const auto wrapped = openTileSource(folder.path().string() + "/{z}/{x}/{reverseY}.png", options);
    writeFileAtomically(folder.path() / "2/0/1.png", tileBytes(4));
    writeFileAtomically(folder.path() / "2/7/1.png", tileBytes(4));
    writeFileAtomically(folder.path() / "2/3/1.png", tileBytes(4));
    REQUIRE(wrapped->fetch({2, 0, 1}).status == Status::Ok);
    REQUIRE(wrapped->fetch({2, 7, 1}).status == Status::Ok);
    REQUIRE(wrapped->fetch({2, 3, 1}).status == Status::Missing);
}

TEST_CASE("An MBTiles file gives its rows counted from the south, and a missing row is Missing", "[world][source][mbtiles]")
{
    const TempDirectory folder;
    const std::filesystem::path path = folder.path() / "world.mbtiles";
    {
        MBTilesWriter writer(path);
        writer.metadata("name", "test");
        writer.metadata("format", "png");
        writer.metadata("bounds", "-180,-85.0511,180,85.0511");
        writer.metadata("minzoom", "0");
        writer.metadata("maxzoom", "2");
        writer.metadata("attribution", "made for the test");
        writer.tile(0, 0, 0, tileBytes(0));
        writer.tile(2, 1, 3, tileBytes(5)); // XYZ row 0 of level 2
        writer.tile(2, 2, 2, {});           // an empty row
    }
    const auto source = openTileSource(path.string());
    const TileSourceInfo& info = source->info();
    REQUIRE(info.scheme == TilingScheme::webMercator());
    REQUIRE(info.maximumLevel == 2);
    REQUIRE(info.format == "png");
    REQUIRE(info.attribution == "made for the test");
    REQUIRE(info.extent.north == Approx(toRadians(85.0511)));
    REQUIRE(source->fetch({0, 0, 0}).bytes == tileBytes(0));
    REQUIRE(source->fetch({2, 1, 0}).bytes == tileBytes(5));
    REQUIRE(source->fetch({2, 1, 3}).status == Status::Missing);
    REQUIRE(source->fetch({2, 2, 1}).status == Status::Missing);
    REQUIRE(source->fetch({3, 0, 0}).status == Status::Missing);
    REQUIRE_THAT(source->locate({2, 1, 0}), Contains("world.mbtiles: tile 2/1/0 (tile_row 3)"));

    std::atomic<int> wrong{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 12; ++t) {
        threads.emplace_back([&] {
            for (int i = 0; i < 50; ++i) {
                if (source->fetch({2, 1, 0}).bytes != tileBytes(5) || source->fetch({1, 0, 0}).status != Status::Missing) {
                    ++wrong;
                }
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    REQUIRE(wrong == 0);
}

TEST_CASE("MBTiles levels come from the tiles table when the metadata lacks them", "[world][source][mbtiles]")
{
    const TempDirectory folder;
    const std::filesystem::path path = folder.path() / "levels.mbtiles";
    {
        MBTilesWriter writer(path);
        writer.tile(3, 0, 0, tileBytes(0));
        writer.tile(5, 0, 0, tileBytes(0));
    }
    const auto source = openTileSource(path.string());
    REQUIRE(source->info().minimumLevel == 3);
    REQUIRE(source->info().maximumLevel == 5);
    REQUIRE(source->info().format.empty());
}

TEST_CASE("Bad MBTiles files are refused when opened, or fail per tile, without a crash", "[world][source][mbtiles][hostile]")
{
    const TempDirectory folder;
    {
        MBTilesWriter writer(folder.path() / "badzoom.mbtiles");
        writer.metadata("maxzoom", "12abc");
    }
    REQUIRE_THROWS_WITH(openTileSource((folder.path() / "badzoom.mbtiles").string()),
                        Contains("badzoom.mbtiles: metadata maxzoom \"12abc\" is not a level from 0 to 30"));
    {
        MBTilesWriter writer(folder.path() / "badbounds.mbtiles");
        writer.metadata("bounds", "-180,-90,180");
    }
    REQUIRE_THROWS_WITH(openTileSource((folder.path() / "badbounds.mbtiles").string()),
                        Contains("metadata bounds \"-180,-90,180\" is not west,south,east,north in degrees"));
    {
        sqlite3* database = nullptr;
        REQUIRE(sqlite3_open((folder.path() / "notiles.mbtiles").c_str(), &database) == SQLITE_OK);
        REQUIRE(sqlite3_exec(database, "CREATE TABLE metadata (name TEXT, value TEXT)", nullptr, nullptr, nullptr) == SQLITE_OK);
        sqlite3_close(database);
    }
    REQUIRE_THROWS_WITH(openTileSource((folder.path() / "notiles.mbtiles").string()), Contains("not an MBTiles database (no tiles table)"));
    REQUIRE(::mkfifo((folder.path() / "pipe.mbtiles").c_str(), 0600) == 0);
    const std::string pipeError = withinSeconds(10, [&] {
        try {
            openTileSource((folder.path() / "pipe.mbtiles").string());
        } catch (const Error& error) {
            return std::string(error.what());
        }
        return std::string("opened");
    });
    REQUIRE_THAT(pipeError, Contains("pipe.mbtiles: the MBTiles path is not a regular file"));

    // A database cut after its first pages: an error at open or per tile, never a crash.
    {
        MBTilesWriter writer(folder.path() / "whole.mbtiles");
        writer.metadata("format", "png");
        for (int x = 0; x < 64; ++x) {
            writer.tile(6, x, 0, encodePng(orbis::test::testPattern(64, 64, 3), 0));
        }
    }
    std::vector<std::uint8_t> bytes = readFileBytes(folder.path() / "whole.mbtiles", "database");
    for (const std::size_t keep : {std::size_t{4096}, bytes.size() / 2}) {
        orbis::test::writeBytes(folder.path() / "cut.mbtiles", {bytes.begin(), bytes.begin() + std::ptrdiff_t(keep)});
        try {
            const auto source = openTileSource((folder.path() / "cut.mbtiles").string());
            for (std::uint32_t x = 0; x < 64; ++x) {
                const TileFetch fetched = source->fetch({6, x, 63});
                if (fetched.status == Status::Failed) {
                    REQUIRE_THAT(fetched.message, Contains("cut.mbtiles: tile 6/"));
                }
            }
        } catch (const Error& error) {
            REQUIRE_THAT(error.what(), Contains("cut.mbtiles"));
        }
    }
}

TEST_CASE("The shipped Blue Marble pyramid holds every tile of levels 0-4, each level the average of the next", "[world][source][data]")
{
    const auto source = openTileSource(ORBIS_SOURCE_DIR "/data/imagery/BlueMarble");
    const TileSourceInfo& info = source->info();
    REQUIRE(info.maximumLevel == 4);
    REQUIRE(info.attribution == "NASA Visible Earth; FlightGear Earthview");
    const TilingScheme& scheme = info.scheme;
    int tiles = 0;
    for (std::uint32_t level = 0; level <= 4; ++level) {
        for (std::uint32_t y = 0; y < scheme.tilesY(level); ++y) {
            for (std::uint32_t x = 0; x < scheme.tilesX(level); ++x) {
                const TileFetch fetched = source->fetch({level, x, y});
                REQUIRE(fetched.status == Status::Ok);
                REQUIRE(decodeImage(fetched.bytes, source->locate({level, x, y}), 3).width == 256);
                ++tiles;
            }
        }
    }
    REQUIRE(tiles == 682);
    // Level 3 over Europe against the box average of its four level-4 tiles: JPEG's losses only
    // (quality 88, twice: about two levels on average; a quadrant out of place gives tens).
    const TileKey parent = *scheme.tileAt(Geodetic2D::fromDegrees(10.0, 45.0), 3);
    const Image made = decodeImage(source->fetch(parent).bytes, "parent", 3);
    double difference = 0.0;
    for (int c = 0; c < 4; ++c) {
        const Image child = decodeImage(source->fetch(parent.child(c)).bytes, "child", 3);
        const int offsetX = (c & 1) * 128;
        const int offsetY = (c & 2) ? 0 : 128;
        for (int y = 0; y < 128; ++y) {
            for (int x = 0; x < 128; ++x) {
                for (int k = 0; k < 3; ++k) {
                    const int sum = child.pixel(2 * x, 2 * y)[k] + child.pixel(2 * x + 1, 2 * y)[k] +
                                    child.pixel(2 * x, 2 * y + 1)[k] + child.pixel(2 * x + 1, 2 * y + 1)[k];
                    difference += std::abs(made.pixel(offsetX + x, offsetY + y)[k] - (sum + 2) / 4);
                }
            }
        }
    }
    REQUIRE(difference / (256.0 * 256.0 * 3.0) < 3.0);
}
