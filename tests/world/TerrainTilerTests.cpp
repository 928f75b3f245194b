// The terrain tiler on DEMs the tests write with GDAL: a UTM GeoTIFF and a whole-globe DEM given
// 0..360. The tiles are read back through openTerrainSource and checked against the DEM at every
// pixel, with positions from GeographicLib (not the PROJ the tiler uses), within each tile's
// stated geometric error; sub-range jobs write the same bytes as one job.

#include "TempFiles.h"
#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/TerrainCodec.h>
#include <orbis/world/TerrainLayer.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TerrainTiler.h>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <GeographicLib/UTMUPS.hpp>

#include <map>

using namespace orbis;
using namespace orbis::world;
using orbis::test::TempDirectory;
using orbis::test::errorMessage;
using Catch::Matchers::Contains;

namespace {

/// Rough ground with a ridge and a valley: what simplification has to work for.
double ground(double longitude, double latitude)
{
    return 800.0 + 400.0 * std::sin(toRadians(longitude * 40.0)) * std::cos(toRadians(latitude * 55.0)) +
           150.0 * std::cos(toRadians((longitude + latitude) * 170.0));
}

// UTM zone 33 north, 90 m pixels, 160 x 160 (14.4 km), top left at E 500 km, N 5,000 km (45.1 N, 15 E).
constexpr double kEasting = 500000.0;
constexpr double kNorthing = 5000000.0;
constexpr double kPixel = 90.0;
constexpr int kSize = 160;

std::pair<double, double> utmPixelDegrees(int column, int row)
{
    double latitude = 0.0, longitude = 0.0;
    GeographicLib::UTMUPS::Reverse(33, true, kEasting + (column + 0.5) * kPixel, kNorthing - (row + 0.5) * kPixel, latitude,
                                   longitude);
    return {longitude, latitude};
}

std::filesystem::path writeUtmDem(const TempDirectory& folder)
{
    const auto path = folder.path() / "utm.tif";
    const double transform[6] = {kEasting, kPixel, 0.0, kNorthing, 0.0, -kPixel};
    orbis::test::writeDem(path, kSize, kSize, transform, 32633, [](int column, int row) {
        const auto [longitude, latitude] = utmPixelDegrees(column, row);
        return static_cast<float>(ground(longitude, latitude));
    });
    return path;
}

/// The height of a tile's surface at a longitude and latitude (degrees): its mesh or grid
/// interpolated linearly in the triangle holding the point (both diagonals for a grid: the
/// nearer of the two is returned, as the tile's error bounds both).
std::vector<double> surfaceHeights(const TerrainTileData& tile, double longitude, double latitude)
{
    const GeodeticExtent extent = TilingScheme::geographic().tileExtent(tile.key);
    const double u = (toRadians(longitude) - extent.west) / (extent.east - extent.west);
    const double v = (toRadians(latitude) - extent.south) / (extent.north - extent.south);
    std::vector<double> heights;
    if (!tile.isMesh()) {
        const int n = tile.size;
        const double x = u * (n - 1);
        const double y = (1.0 - v) * (n - 1);
        const int c = std::clamp(int(x), 0, n - 2);
        const int r = std::clamp(int(y), 0, n - 2);
        const double fx = x - c, fy = y - r;
        auto h = [&](int rr, int cc) { return double(tile.heights[std::size_t(rr * n + cc)]); };
        heights.push_back(fx >= fy ? h(r, c) + fx * (h(r, c + 1) - h(r, c)) + fy * (h(r + 1, c + 1) - h(r, c + 1))
                                   : h(r, c) + fy * (h(r + 1, c) - h(r, c)) + fx * (h(r + 1, c + 1) - h(r + 1, c)));
        heights.push_back(fx + fy <= 1.0 ? h(r, c) + fx * (h(r, c + 1) - h(r, c)) + fy * (h(r + 1, c) - h(r, c))
                                         : h(r + 1, c + 1) + (1 - fx) * (h(r + 1, c) - h(r + 1, c + 1)) +
                                               (1 - fy) * (h(r, c + 1) - h(r + 1, c + 1)));
        return heights;
    }
    for (std::size_t t = 0; t < tile.indices.size(); t += 3) {
        const glm::vec3& a = tile.vertices[tile.indices[t]];
        const glm::vec3& b = tile.vertices[tile.indices[t + 1]];
        const glm::vec3& c = tile.vertices[tile.indices[t + 2]];
        const double area = double(b.x - a.x) * double(c.y - a.y) - double(c.x - a.x) * double(b.y - a.y);
        const double wa = ((double(b.x) - u) * (double(c.y) - v) - (double(c.x) - u) * (double(b.y) - v)) / area;
        const double wb = ((double(c.x) - u) * (double(a.y) - v) - (double(a.x) - u) * (double(c.y) - v)) / area;
        const double wc = 1.0 - wa - wb;
        if (wa >= -1e-7 && wb >= -1e-7 && wc >= -1e-7) {
            heights.push_back(wa * double(a.z) + wb * double(b.z) + wc * double(c.z));
            return heights;
        }
    }
    return heights;
}

/// Every DEM pixel against the tiles of a level that hold it: within each tile's stated error.
/// Returns the number of pixels checked.
std::size_t checkAgainstDem(TerrainSource& source, std::uint32_t level)
{
    std::map<std::pair<std::uint32_t, std::uint32_t>, TerrainTileData> tiles;
    std::size_t checked = 0;
    for (int row = 0; row < kSize; ++row) {
        for (int column = 0; column < kSize; ++column) {
            const auto [longitude, latitude] = utmPixelDegrees(column, row);
            const TileKey key = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(longitude, latitude), level);
            auto found = tiles.find({key.x, key.y});
            if (found == tiles.end()) {
                const TerrainFetch fetched = source.load(key);
                INFO(fetched.message);
                REQUIRE(fetched.status == TerrainFetch::Status::Ok);
                REQUIRE(fetched.tile.geometricError);
                found = tiles.emplace(std::pair(key.x, key.y), fetched.tile).first;
            }
            const TerrainTileData& tile = found->second;
            const double truth = ground(longitude, latitude);
            const std::vector<double> surface = surfaceHeights(tile, longitude, latitude);
            REQUIRE(!surface.empty());
            for (const double h : surface) {
                INFO("level " << level << " pixel " << column << ", " << row << ": " << h << " against " << truth);
                // The DEM stores floats; the stated error is rounded up to centimetres.
                REQUIRE(std::abs(h - truth) <= *tile.geometricError + 1e-3);
            }
            ++checked;
        }
    }
    return checked;
}

/// Every file under a folder, by its relative path.
std::map<std::string, std::vector<std::uint8_t>> filesUnder(const std::filesystem::path& folder)
{
    std::map<std::string, std::vector<std::uint8_t>> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file()) {
            files[std::filesystem::relative(entry.path(), folder).string()] = readFileBytes(entry.path(), "file");
        }
    }
    return files;
}

} // namespace

TEST_CASE("A UTM DEM tiled as heightmap-1.0 and quantized-mesh: every pixel within its tile's stated error",
          "[world][terrain][tiler]")
{
    const TempDirectory folder;
    const auto dem = writeUtmDem(folder);
    for (const TerrainTileFormat format : {TerrainTileFormat::Heightmap, TerrainTileFormat::QuantizedMesh}) {
        const bool mesh = format == TerrainTileFormat::QuantizedMesh;
        TerrainTilerOptions options;
        options.input = dem;
        options.output = folder.path() / (mesh ? "mesh" : "heightmap");
        options.format = format;
        options.threads = 2;
        options.maximumError = 50000.0; // halved per level: 48.8 m at level 10, 12.2 m at level 12
        std::size_t calls = 0;
        TilerProgress last;
        options.progress = [&](const TilerProgress& progress) {
            ++calls;
            last = progress;
        };
        TerrainTiler tiler(options);
        // 90 m of latitude is 0.00081 degrees: level 12 (0.00069) is the first within 10 %.
        REQUIRE(tiler.levelCount() == 13);
        CHECK_THAT(tiler.tolerance(12), Catch::Matchers::WithinRel(50000.0 / 4096.0));
        const TerrainTilerSummary summary = tiler.run();
        CHECK(summary.tilesWritten == calls);
        CHECK(last.done == last.total);
        CHECK(summary.levelCount == 13);
        CHECK(summary.bytesWritten > 0);

        const auto source = openTerrainSource(options.output.string());
        CHECK(source->info().format == (mesh ? "quantized-mesh" : "heightmap"));
        CHECK(source->info().maximumLevel == 12);
        for (const std::uint32_t level : {8u, 11u, 12u}) {
            CHECK(checkAgainstDem(*source, level) == std::size_t(kSize) * kSize);
        }
        // Inside the DEM, at the deepest level, the error is the tiling's: the tolerance for meshes,
        // the 0.2 m steps of heightmap-1.0 and the grid's interpolation for grids. (Tiles over the
        // DEM's edge drop to the nodata height beside it, and say so in their errors.)
        const auto [longitude, latitude] = utmPixelDegrees(kSize / 2, kSize / 2);
        const TileKey centre = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(longitude, latitude), 12);
        const double error = *source->load(centre).tile.geometricError;
        CHECK(error > 0.0);
        CHECK(error <= (mesh ? tiler.tolerance(12) + 1.0 : 1.0));
        CHECK(summary.maximumErrors[12] >= error);
    }
}

TEST_CASE("layer.json lists exactly the tiles written, each with its error", "[world][terrain][tiler]")
{
    const TempDirectory folder;
    TerrainTilerOptions options;
    options.input = writeUtmDem(folder);
    options.output = folder.path() / "out";
    options.levels = 10;
    options.format = TerrainTileFormat::Heightmap;
    TerrainTiler(options).run();
    const std::vector<std::uint8_t> bytes = readFileBytes(options.output / "layer.json", "layer.json");
    const TerrainLayer layer = parseTerrainLayer({reinterpret_cast<const char*>(bytes.data()), bytes.size()}, "layer.json");
    CHECK(layer.format == "heightmap-1.0");
    CHECK(layer.maximumLevel == 9);
    CHECK(layer.name == "utm.tif");
    REQUIRE(layer.available.size() == 10);
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(options.output)) {
        if (entry.path().extension() != ".terrain") {
            continue;
        }
        ++files;
        const auto relative = std::filesystem::relative(entry.path(), options.output);
        const auto level = std::uint32_t(std::stoul(relative.begin()->string()));
        const auto x = std::uint32_t(std::stoul(std::next(relative.begin())->string()));
        const auto y = std::uint32_t(std::stoul(entry.path().stem().string()));
        CHECK(layerHasTile(layer, {level, x, y}));
        CHECK(layer.geometricError({level, x, y}));
    }
    std::size_t available = 0;
    for (const LevelAvailability& level : layer.available) {
        for (const TileRectangle& r : level) {
            available += std::size_t(r.endX - r.startX + 1) * (r.endY - r.startY + 1);
        }
    }
    CHECK(available == files);
    // Heightmap tiles' child masks agree with the availability of the level below.
    const auto source = openTerrainSource(options.output.string());
    for (std::uint32_t level = 0; level + 1 < 10; ++level) {
        for (const TileRectangle& r : layer.available[level]) {
            for (std::uint32_t y = r.startY; y <= r.endY; ++y) {
                for (std::uint32_t x = r.startX; x <= r.endX; ++x) {
                    const TerrainFetch fetched = source->load({level, x, y});
                    REQUIRE(fetched.status == TerrainFetch::Status::Ok);
                    for (int child = 0; child < 4; ++child) {
                        CHECK(bool(fetched.tile.childMask & (1 << child)) ==
                              layerHasTile(layer, TileKey{level, x, y}.child(child)));
                    }
                }
            }
        }
    }
}

TEST_CASE("Heightmap tiles share their samples bit for bit across edges and levels", "[world][terrain][tiler]")
{
    const TempDirectory folder;
    TerrainTilerOptions options;
    options.input = writeUtmDem(folder);
    options.output = folder.path() / "out";
    options.format = TerrainTileFormat::Heightmap;
    TerrainTiler(options).run();
    const auto source = openTerrainSource(options.output.string());
    // Two level-12 neighbours inside the DEM and their parent.
    const auto [longitude, latitude] = utmPixelDegrees(kSize / 2, kSize / 2);
    const TileKey key = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(longitude, latitude), 12);
    const TerrainTileData tile = source->load(key).tile;
    const TerrainTileData east = source->load({12, key.x + 1, key.y}).tile;
    const TerrainTileData parent = source->load(key.parent()).tile;
    REQUIRE(tile.size == 65);
    REQUIRE(east.size == 65);
    REQUIRE(parent.size == 65);
    for (int row = 0; row < 65; ++row) {
        CHECK(tile.heights[std::size_t(row * 65 + 64)] == east.heights[std::size_t(row * 65)]);
    }
    const int offsetColumn = (key.x & 1) * 32;
    const int offsetRow = (key.y & 1) ? 0 : 32;
    for (int row = 0; row < 65; row += 2) {
        for (int column = 0; column < 65; column += 2) {
            REQUIRE(tile.heights[std::size_t(row * 65 + column)] ==
                    parent.heights[std::size_t((offsetRow + row / 2) * 65 + offsetColumn + column / 2)]);
        }
    }
}

TEST_CASE("Quantized-mesh neighbours share their edge vertices", "[world][terrain][tiler]")
{
    const TempDirectory folder;
    TerrainTilerOptions options;
    options.input = writeUtmDem(folder);
    options.output = folder.path() / "out";
    options.levels = 12;
    options.onlyLevel = 11;
    options.maximumError = 200000.0; // 97 m at level 11: edges simplified hard
    TerrainTiler(options).run();
    const auto source = openTerrainSource(options.output.string());
    const auto [longitude, latitude] = utmPixelDegrees(kSize / 2, kSize / 2);
    const TileKey key = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(longitude, latitude), 11);
    const TerrainTileData west = source->load(key).tile;
    const TerrainTileData east = source->load({11, key.x + 1, key.y}).tile;
    const std::vector<std::uint32_t>& westEdge = west.edgeVertices[1]; // its east edge
    const std::vector<std::uint32_t>& eastEdge = east.edgeVertices[3]; // its neighbour's west edge
    REQUIRE(westEdge.size() == eastEdge.size());
    CHECK(westEdge.size() < 65); // simplified
    const double stepWest = (west.maximumHeight - west.minimumHeight) / 32767.0;
    const double stepEast = (east.maximumHeight - east.minimumHeight) / 32767.0;
    for (std::size_t i = 0; i < westEdge.size(); ++i) {
        const glm::vec3& a = west.vertices[westEdge[i]];
        const glm::vec3& b = east.vertices[eastEdge[i]];
        CHECK(a.x == 1.0f);
        CHECK(b.x == 0.0f);
        CHECK(a.y == b.y);
        CHECK(std::abs(double(a.z) - double(b.z)) <= 0.5 * (stepWest + stepEast) + 1e-3);
    }
    REQUIRE(west.normals.size() == west.vertices.size());
    for (std::size_t i = 0; i < westEdge.size(); ++i) {
        CHECK(glm::length(west.normals[westEdge[i]] - east.normals[eastEdge[i]]) < 1e-6f);
    }
}

TEST_CASE("A whole-globe DEM given 0..360 is tiled where it lies, across the antimeridian", "[world][terrain][tiler]")
{
    const TempDirectory folder;
    // 1-degree point samples from 0 E eastwards, 360 columns, poles included.
    const double transform[6] = {-0.5, 1.0, 0.0, 90.5, 0.0, -1.0};
    const auto dem = folder.path() / "globe.tif";
    orbis::test::writeDem(dem, 360, 181, transform, 4326,
                          [](int column, int row) { return static_cast<float>(ground(column * 0.1, (90 - row) * 0.1)); });
    TerrainTilerOptions options;
    options.input = dem;
    options.output = folder.path() / "out";
    options.levels = 3;
    options.gridSize = 17;
    TerrainTiler tiler(options);
    CHECK(tiler.footprint() == GeodeticExtent::maximum());
    const TerrainTilerSummary summary = tiler.run();
    CHECK(summary.tilesWritten == 2 + 8 + 32);
    const auto source = openTerrainSource(options.output.string());
    // The DEM's own samples at whole degrees, west and east of the antimeridian, against the
    // tiles: within their stated errors.
    for (const double longitude : {-179.0, -1.0, 0.0, 1.0, 90.0, 179.0, 180.0}) {
        for (const double latitude : {-89.0, -45.0, 0.0, 30.0, 89.0}) {
            const double dataColumn = longitude < 0.0 ? longitude + 360.0 : longitude;
            const double truth = ground(std::fmod(dataColumn, 360.0) * 0.1, latitude * 0.1);
            const TileKey key = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(longitude, latitude), 2);
            const TerrainFetch fetched = source->load(key);
            REQUIRE(fetched.status == TerrainFetch::Status::Ok);
            const std::vector<double> surface =
                surfaceHeights(fetched.tile, longitude >= 180.0 ? longitude - 360.0 : longitude, latitude);
            REQUIRE(surface.size() == 1);
            INFO(longitude << ", " << latitude);
            CHECK(std::abs(surface[0] - truth) <= *fetched.tile.geometricError + 1e-3);
        }
    }
}

TEST_CASE("Sub-range jobs write the same files, byte for byte, as one job", "[world][terrain][tiler]")
{
    const TempDirectory folder;
    const auto dem = writeUtmDem(folder);
    TerrainTilerOptions options;
    options.input = dem;
    options.levels = 12;
    options.threads = 2;
    options.output = folder.path() / "whole";
    TerrainTiler(options).run();
    const auto whole = filesUnder(options.output);

    options.output = folder.path() / "split";
    options.threads = 1;
    // Level 11 in two column ranges, the deepest first, then the rest level by level out of order.
    const auto [longitude, latitude] = utmPixelDegrees(kSize / 2, kSize / 2);
    const std::uint32_t middle = TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(longitude, latitude), 11)->x;
    for (const auto& range : {std::pair(0u, middle), std::pair(middle + 1, 4095u)}) {
        options.onlyLevel = 11;
        options.columns = range;
        TerrainTiler(options).run();
    }
    options.columns.reset();
    for (std::uint32_t level = 0; level < 11; ++level) {
        options.onlyLevel = (level * 7) % 11;
        TerrainTiler(options).run();
    }
    const auto split = filesUnder(options.output);
    REQUIRE(split.size() == whole.size());
    for (const auto& [name, bytes] : whole) {
        INFO(name);
        REQUIRE(split.count(name));
        CHECK(split.at(name) == bytes);
    }
}

TEST_CASE("The terrain tiler refuses what it cannot do, before writing anything", "[world][terrain][tiler]")
{
    const TempDirectory folder;
    const auto dem = writeUtmDem(folder);
    auto attempt = [&](const std::function<void(TerrainTilerOptions&)>& change) {
        TerrainTilerOptions options;
        options.input = dem;
        options.output = folder.path() / "never";
        change(options);
        return errorMessage([&] { TerrainTiler(options).run(); });
    };
    CHECK_THAT(attempt([](auto& o) { o.format = TerrainTileFormat::Heightmap, o.gridSize = 129; }),
               Contains("heightmap-1.0 tiles are 65 x 65 samples, not 129"));
    CHECK_THAT(attempt([](auto& o) { o.gridSize = 100; }), Contains("a grid of 100 samples a side"));
    CHECK_THAT(attempt([](auto& o) { o.maximumError = -1.0; }), Contains("the maximum error must be"));
    CHECK_THAT(attempt([](auto& o) { o.columns = std::pair(0u, 1u); }), Contains("a range of columns needs the level"));
    CHECK_THAT(attempt([](auto& o) { o.onlyLevel = 13; }), Contains("level 13 is not in the pyramid (0 to 12)"));
    CHECK_THAT(attempt([](auto& o) { o.onlyLevel = 2, o.columns = std::pair(3u, 8u); }),
               Contains("columns 3:8 are not within 0:7 of level 2"));
    CHECK_THAT(attempt([](auto& o) { o.levels = 31, o.gridSize = 1025; }), Contains("tiles at the deepest level alone"));
    CHECK_THAT(attempt([&](auto& o) { o.input = folder.path() / "none.tif"; }), Contains("none.tif: cannot open the DEM"));
    CHECK_THAT(attempt([&](auto& o) { o.input = folder.path(); }), Contains("the DEM is not a regular file"));
    orbis::test::writeBytes(folder.path() / "file", {1});
    CHECK_THAT(attempt([&](auto& o) { o.output = folder.path() / "file"; }), Contains("the output exists and is not a folder"));
    CHECK_FALSE(std::filesystem::exists(folder.path() / "never"));
}
