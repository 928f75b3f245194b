// Height queries: which tiles hold a point, a tile's height at a point (the same from both tiles
// of an edge), and the most-detailed query over tile sets the terrain tiler cut from a DEM the
// test writes, checked against that DEM at every pixel and along every tile edge and corner
// within each tile's stated geometric error.

#include "TempFiles.h"
#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/world/TerrainHeight.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TerrainTiler.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

using namespace orbis;
using namespace orbis::world;
using orbis::test::TempDirectory;
using orbis::test::errorMessage;
using Catch::Matchers::Contains;

namespace {

// A geographic DEM: 1.5 x 1 degrees from 7.25 E, 45.6 N, 30 arc-second pixels (180 x 120).
constexpr double kWest = 7.25;
constexpr double kNorth = 46.6;
constexpr double kPixel = 1.0 / 120.0;
constexpr int kColumns = 180;
constexpr int kRows = 120;

/// Mountains with ridges at several scales, so that simplification has work to do.
float ground(int column, int row)
{
    const double longitude = kWest + (column + 0.5) * kPixel;
    const double latitude = kNorth - (row + 0.5) * kPixel;
    const double h = 1500.0 + 900.0 * std::sin(toRadians(longitude * 300.0)) * std::cos(toRadians(latitude * 240.0)) +
                     250.0 * std::sin(toRadians((longitude - latitude) * 1100.0)) +
                     60.0 * std::cos(toRadians(longitude * 3300.0 + latitude * 2100.0));
    return static_cast<float>(h);
}

std::filesystem::path writeDem(const TempDirectory& folder)
{
    const auto path = folder.path() / "alps.tif";
    const double transform[6] = {kWest, kPixel, 0.0, kNorth, 0.0, -kPixel};
    orbis::test::writeDem(path, kColumns, kRows, transform, 4326, ground);
    return path;
}

/// The DEM between its pixel centres (bilinear), as the tiler samples it; edge pixels stand in
/// within half a pixel of the edge.
double demAt(double longitude, double latitude)
{
    const double x = std::clamp((longitude - kWest) / kPixel - 0.5, 0.0, kColumns - 1.0);
    const double y = std::clamp((kNorth - latitude) / kPixel - 0.5, 0.0, kRows - 1.0);
    const int c = std::min(int(x), kColumns - 2);
    const int r = std::min(int(y), kRows - 2);
    const double fx = x - c, fy = y - r;
    auto h = [](int cc, int rr) { return double(ground(cc, rr)); };
    return (1 - fy) * ((1 - fx) * h(c, r) + fx * h(c + 1, r)) + fy * ((1 - fx) * h(c, r + 1) + fx * h(c + 1, r + 1));
}

bool sameBits(double a, double b)
{
    return std::memcmp(&a, &b, sizeof a) == 0;
}

std::unique_ptr<TerrainSource> tile(const TempDirectory& folder, TerrainTileFormat format, const std::string& name)
{
    TerrainTilerOptions options;
    options.input = writeDem(folder);
    options.output = folder.path() / name;
    options.format = format;
    options.levels = 10; // 0..9: level 9's samples (0.0055 degrees) about as fine as the pixels
    options.threads = 2;
    TerrainTiler(options).run();
    return openTerrainSource(options.output.string());
}

/// Every DEM pixel centre, every grid sample on the edges and corners of the deepest tiles, and
/// random points between them: within the stated error of the tile that answered, and answered
/// everywhere.
void checkAgainstDem(TerrainSource& source)
{
    TerrainHeightQuery query(source);
    std::size_t checked = 0;
    double worstRatio = 0.0;
    auto check = [&](double longitude, double latitude, double truth) {
        const auto height = query.at(Geodetic2D::fromDegrees(longitude, latitude));
        INFO(source.info().format << " at " << longitude << ", " << latitude);
        REQUIRE(height);
        REQUIRE(height->tile.level == 9);
        REQUIRE(height->geometricError);
        // The DEM stores floats; the stated error is rounded up to centimetres.
        REQUIRE(std::abs(height->height - truth) <= *height->geometricError + 1e-3);
        worstRatio = std::max(worstRatio, std::abs(height->height - truth) / std::max(*height->geometricError, 1e-3));
        ++checked;
    };
    for (int row = 0; row < kRows; ++row) {
        for (int column = 0; column < kColumns; ++column) {
            check(kWest + (column + 0.5) * kPixel, kNorth - (row + 0.5) * kPixel, double(ground(column, row)));
        }
    }
    // Edges and corners of level 9's tiles inside the DEM (those nearest its border are left out:
    // the DEM's edge pixels stand in for what lies beyond them).
    const TilingScheme scheme = TilingScheme::geographic();
    std::size_t onEdges = 0;
    for (std::uint32_t x = 0; x < scheme.tilesX(9); ++x) {
        for (std::uint32_t y = 0; y < scheme.tilesY(9); ++y) {
            const GeodeticExtent e = scheme.tileExtent({9, x, y});
            if (toDegrees(e.west) < kWest + kPixel || toDegrees(e.east) > kWest + kColumns * kPixel - kPixel ||
                toDegrees(e.south) < kNorth - kRows * kPixel + kPixel || toDegrees(e.north) > kNorth - kPixel) {
                continue;
            }
            for (int i = 0; i < 65; ++i) {
                for (const auto& [column, row] : {std::pair(i, 0), std::pair(0, i)}) { // north and west edges
                    const Geodetic2D g = terrainGridPosition({9, x, y}, 65, column, row);
                    check(toDegrees(g.longitude), toDegrees(g.latitude), demAt(toDegrees(g.longitude), toDegrees(g.latitude)));
                    ++onEdges;
                }
            }
        }
    }
    CHECK(onEdges > 500);
    // And anywhere between them: 80,000 points at random (a fixed seed), one pixel in from the
    // DEM's border, against the DEM's bilinear surface.
    std::mt19937_64 random(13);
    std::uniform_real_distribution<double> across(kWest + kPixel, kWest + (kColumns - 1) * kPixel);
    std::uniform_real_distribution<double> down(kNorth - (kRows - 1) * kPixel, kNorth - kPixel);
    constexpr std::size_t kRandomPoints = 80000;
    for (std::size_t i = 0; i < kRandomPoints; ++i) {
        const double longitude = across(random);
        const double latitude = down(random);
        check(longitude, latitude, demAt(longitude, latitude));
    }
    CHECK(checked == std::size_t(kColumns * kRows) + onEdges + kRandomPoints);
    CHECK(checked > 100000);
    // The errors are tight: some point comes near its tile's stated error.
    CHECK(worstRatio > 0.9); // measured: 0.999 on meshes, 0.987 on heightmaps
    INFO("loaded " << query.tilesLoaded());
    CHECK(query.tilesLoaded() < 200); // each tile once: the cache holds them all
}

} // namespace

TEST_CASE("terrainTilesAt: one tile inside, two on an edge, four at a corner, both sides of 180 degrees",
          "[world][terrain][height]")
{
    CHECK(terrainTilesAt(3, Geodetic2D::fromDegrees(10.0, 10.0)) == std::vector<TileKey>{{3, 8, 4}});
    // 22.5 E is the edge between columns 8 and 9 of level 3.
    CHECK(terrainTilesAt(3, Geodetic2D::fromDegrees(22.5, 10.0)) == std::vector<TileKey>{{3, 8, 4}, {3, 9, 4}});
    CHECK(terrainTilesAt(3, Geodetic2D::fromDegrees(22.5, 22.5)) ==
          std::vector<TileKey>{{3, 8, 4}, {3, 9, 4}, {3, 8, 5}, {3, 9, 5}});
    CHECK(terrainTilesAt(3, Geodetic2D::fromDegrees(180.0, 10.0)) == std::vector<TileKey>{{3, 0, 4}, {3, 15, 4}});
    CHECK(terrainTilesAt(3, Geodetic2D::fromDegrees(-180.0, 10.0)) == std::vector<TileKey>{{3, 0, 4}, {3, 15, 4}});
    CHECK(terrainTilesAt(3, Geodetic2D::fromDegrees(190.0, 10.0)) == std::vector<TileKey>{{3, 0, 4}});
    CHECK(terrainTilesAt(0, Geodetic2D::fromDegrees(0.0, 0.0)) == std::vector<TileKey>{{0, 0, 0}, {0, 1, 0}});
    CHECK(terrainTilesAt(2, Geodetic2D::fromDegrees(10.0, 90.0)) == std::vector<TileKey>{{2, 4, 3}});
    CHECK(terrainTilesAt(2, Geodetic2D::fromDegrees(10.0, 91.0)).empty());
    CHECK(terrainTilesAt(2, Geodetic2D{std::nan(""), 0.0}).empty());
}

TEST_CASE("A grid tile's height at a point is bilinear in its cell and the same bit for bit from both tiles of an edge",
          "[world][terrain][height]")
{
    // Two neighbours of level 4 sampling one field at terrainGridPosition, as every grid source does.
    auto field = [](const Geodetic2D& g) {
        return static_cast<float>(1000.0 + 700.0 * std::sin(9.0 * g.longitude) * std::cos(7.0 * g.latitude) +
                                  std::fmod(g.longitude * 1e5, 13.0));
    };
    auto grid = [&](const TileKey& key) {
        TerrainTileData t;
        t.key = key;
        t.size = 17;
        for (int row = 0; row < 17; ++row) {
            for (int column = 0; column < 17; ++column) {
                t.heights.push_back(field(terrainGridPosition(key, 17, column, row)));
            }
        }
        return t;
    };
    const TerrainTileData west = grid({4, 20, 10});
    const TerrainTileData east = grid({4, 21, 10});
    const TerrainTileData north = grid({4, 20, 11});
    // At the samples the samples themselves.
    CHECK(*terrainTileHeight(west, terrainGridPosition(west.key, 17, 3, 5)) == double(west.heights[5 * 17 + 3]));
    // Between two samples of a row, half way: their mean.
    const Geodetic2D a = terrainGridPosition(west.key, 17, 3, 5);
    const Geodetic2D b = terrainGridPosition(west.key, 17, 4, 5);
    CHECK_THAT(*terrainTileHeight(west, {0.5 * (a.longitude + b.longitude), a.latitude}),
               Catch::Matchers::WithinAbs(0.5 * (double(west.heights[5 * 17 + 3]) + double(west.heights[5 * 17 + 4])), 1e-3));
    const GeodeticExtent e = TilingScheme::geographic().tileExtent(west.key);
    for (int i = 0; i <= 1000; ++i) {
        const double t = i / 1000.0;
        const Geodetic2D onEastEdge{e.east, e.south + t * (e.north - e.south)};
        REQUIRE(sameBits(*terrainTileHeight(west, onEastEdge), *terrainTileHeight(east, onEastEdge)));
        const Geodetic2D onNorthEdge{e.west + t * (e.east - e.west), e.north};
        REQUIRE(sameBits(*terrainTileHeight(west, onNorthEdge), *terrainTileHeight(north, onNorthEdge)));
    }
    CHECK_FALSE(terrainTileHeight(west, {e.east + 1e-9, e.south}));
    CHECK_FALSE(terrainTileHeight(west, {e.west, e.north + 1e-9}));
    // A longitude a turn away is the same place.
    CHECK(*terrainTileHeight(west, {e.west + kTwoPi, e.south}) == double(west.heights[16 * 17]));
}

TEST_CASE("Most-detailed heights from heightmap-1.0 tiles cut from a DEM: every pixel, edge and corner within the stated error",
          "[world][terrain][height]")
{
    const TempDirectory folder;
    const auto source = tile(folder, TerrainTileFormat::Heightmap, "heightmap");
    checkAgainstDem(*source);
    // On an edge of two level-9 tiles the query's answer is either tile's, bit for bit.
    TerrainHeightQuery query(*source);
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey left = *scheme.tileAt(Geodetic2D::fromDegrees(7.9, 46.1), 9);
    const TileKey right{9, left.x + 1, left.y};
    const TerrainTileData a = source->load(left).tile;
    const TerrainTileData b = source->load(right).tile;
    const GeodeticExtent e = scheme.tileExtent(left);
    for (int i = 0; i <= 200; ++i) {
        const Geodetic2D p{e.east, e.south + i / 200.0 * (e.north - e.south)};
        const double answer = query.at(p)->height;
        REQUIRE(sameBits(answer, *terrainTileHeight(a, p)));
        REQUIRE(sameBits(answer, *terrainTileHeight(b, p)));
    }
    // Outside the DEM the set has level 0 to 2 tiles only where the DEM's footprint is.
    CHECK_FALSE(query.at(Geodetic2D::fromDegrees(-100.0, -40.0)));
}

TEST_CASE("Most-detailed heights from quantized-mesh tiles cut from a DEM: every pixel, edge and corner within the stated error",
          "[world][terrain][height]")
{
    const TempDirectory folder;
    const auto source = tile(folder, TerrainTileFormat::QuantizedMesh, "mesh");
    checkAgainstDem(*source);
}

TEST_CASE("Most-detailed heights asked for without blocking: the synchronous query's answers, in order", "[world][terrain][height]")
{
    const TempDirectory folder;
    const std::shared_ptr<TerrainSource> source = tile(folder, TerrainTileFormat::QuantizedMesh, "mesh");
    std::mt19937 random(7);
    std::uniform_real_distribution<double> longitude(7.8, 8.2);
    std::uniform_real_distribution<double> latitude(45.8, 46.2);
    std::vector<Geodetic2D> positions;
    for (int i = 0; i < 500; ++i) {
        positions.push_back(Geodetic2D::fromDegrees(longitude(random), latitude(random)));
    }
    positions.push_back(Geodetic2D::fromDegrees(-120.0, 10.0)); // outside the DEM: no tile there
    std::future<std::vector<std::optional<TerrainHeight>>> pending = mostDetailedHeights(source, positions);
    TerrainHeightQuery query(*source);
    const std::vector<std::optional<TerrainHeight>> heights = pending.get();
    REQUIRE(heights.size() == positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const std::optional<TerrainHeight> expected = query.at(positions[i]);
        REQUIRE(heights[i].has_value() == expected.has_value());
        if (expected) {
            CHECK(heights[i]->height == expected->height);
            CHECK(heights[i]->tile == expected->tile);
        }
    }
    CHECK(heights[0]);
}

TEST_CASE("A height query names the tile that fails to load", "[world][terrain][height]")
{
    const TempDirectory folder;
    const std::shared_ptr<TerrainSource> source = tile(folder, TerrainTileFormat::QuantizedMesh, "mesh");
    const TileKey key = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(7.9, 46.1), 9);
    const auto path = folder.path() / "mesh" / "9" / std::to_string(key.x) / (std::to_string(key.y) + ".terrain");
    orbis::test::writeBytes(path, {0x1f, 0x8b, 8, 0, 0, 0});
    TerrainHeightQuery query(*source);
    CHECK_THAT(errorMessage([&] { query.at(Geodetic2D::fromDegrees(7.9, 46.1)); }), Contains(path.filename().string()));
    // Asked for without blocking, the error comes with the answers.
    auto pending = mostDetailedHeights(source, {Geodetic2D::fromDegrees(7.9, 46.1)});
    CHECK_THAT(errorMessage([&] { pending.get(); }), Contains(path.filename().string()));
}
