#include <orbis/core/TilingScheme.h>
#include <orbis/world/TerrainSampler.h>
#include <orbis/world/TerrainSource.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <memory>

using namespace orbis;
using namespace orbis::world;

namespace {

std::string dataPath(const std::string& relative)
{
    return std::string(ORBIS_SOURCE_DIR) + "/data/" + relative;
}

TerrainSampler samplerOf(world::TerrainSource& source, const TileKey& key)
{
    world::TerrainFetch fetched = source.load(key);
    REQUIRE(fetched.status == world::TerrainFetch::Status::Ok);
    return TerrainSampler(std::make_shared<const world::TerrainTileData>(std::move(fetched.tile)));
}

/// The lattice heights and normals of two tiles side by side (west, east) along their shared
/// edge: the largest differences.
std::pair<double, double> edgeMismatch(const TerrainSampler& westData, const TileKey& west, const TerrainSampler& eastData,
                                       const TileKey& east, int samplesLog2)
{
    const int size = (1 << samplesLog2) + 1;
    const std::vector<float> westHeights = westData.latticeHeights(west, samplesLog2);
    const std::vector<float> eastHeights = eastData.latticeHeights(east, samplesLog2);
    const std::vector<float> westNormals = westData.latticeNormals(west, samplesLog2);
    const std::vector<float> eastNormals = eastData.latticeNormals(east, samplesLog2);
    REQUIRE(westNormals.size() == westHeights.size() * 3);
    REQUIRE(eastNormals.size() == eastHeights.size() * 3);
    double heights = 0.0;
    double normals = 0.0;
    for (int row = 0; row < size; ++row) {
        const std::size_t w = static_cast<std::size_t>(row * size + size - 1);
        const std::size_t e = static_cast<std::size_t>(row * size);
        heights = std::max(heights, static_cast<double>(std::abs(westHeights[w] - eastHeights[e])));
        const glm::dvec3 a(westNormals[3 * w], westNormals[3 * w + 1], westNormals[3 * w + 2]);
        const glm::dvec3 b(eastNormals[3 * e], eastNormals[3 * e + 1], eastNormals[3 * e + 2]);
        CHECK(std::abs(glm::length(a) - 1.0) < 1e-6);
        normals = std::max(normals, glm::length(a - b));
    }
    return {heights, normals};
}

} // namespace

TEST_CASE("Tiles cut from terrain data meet in heights and normals: within one data tile and across two",
          "[world][terrain][sampler]")
{
    // ETOPO5's level 5 quantized-mesh tiles (oct-encoded normals) over the Alps, cut into level 7
    // lattices: tiles 132 | 133 lie in data tile 33, tiles 135 | 136 in data tiles 33 | 34.
    const auto etopo5 = world::openTerrainSource(dataPath("terrain/etopo5"));
    const TerrainSampler data33 = samplerOf(*etopo5, {5, 33, 24});
    const TerrainSampler data34 = samplerOf(*etopo5, {5, 34, 24});
    const auto [inHeights, inNormals] = edgeMismatch(data33, {7, 132, 97}, data33, {7, 133, 97}, 6);
    CHECK(inHeights == 0.0);
    CHECK(inNormals == 0.0);
    const auto [acrossHeights, acrossNormals] = edgeMismatch(data33, {7, 135, 97}, data34, {7, 136, 97}, 6);
    // Each quantized-mesh tile stores heights in 32,767 steps of its own range.
    const auto step = [](const TerrainSampler& sampler) {
        return (sampler.data().maximumHeight - sampler.data().minimumHeight) / 32767.0;
    };
    CHECK(acrossHeights <= std::max(step(data33), step(data34)));
    CHECK(acrossNormals < 1e-3); // the oct encoding's step, about 0.1 degree

    // A DEM read by GDAL (the Cumberland Mountains): grids with normals that see across the edge.
    const auto dem = world::openTerrainSource(dataPath("terrain/cumberland/jacksboro_fault.vrt"));
    const std::uint32_t level = dem->info().maximumLevel;
    const TileKey west = *TilingScheme::geographic().tileAt(Geodetic2D::fromDegrees(-84.25, 36.6), level);
    const TileKey east{level, west.x + 1, west.y};
    const auto [demHeights, demNormals] = edgeMismatch(samplerOf(*dem, west), west, samplerOf(*dem, east), east, 6);
    CHECK(demHeights == 0.0);
    CHECK(demNormals == 0.0);

    // A source without normals gives none: the mesh's own are used then.
    world::TerrainTileData flat;
    flat.key = {0, 0, 0};
    flat.size = 3;
    flat.heights.assign(9, 100.0f);
    const TerrainSampler plain(std::make_shared<const world::TerrainTileData>(flat));
    CHECK(plain.latticeNormals({2, 1, 1}, 4).empty());
    CHECK(plain.latticeHeights({2, 1, 1}, 4) == std::vector<float>(17 * 17, 100.0f));
}

TEST_CASE("A mesh's height with hints equals its height without, whatever the hints name", "[world][terrain][sampler]")
{
    // ETOPO5's quantized-mesh tile over the Alps, asked for as a clipmap finer than the data asks:
    // rows in order, the last post's and the post a row before's triangles as hints (mostly the
    // point's, else the buckets' search), and every seventh post a hint far away instead.
    const auto etopo5 = world::openTerrainSource(dataPath("terrain/etopo5"));
    const TerrainSampler mesh = samplerOf(*etopo5, {5, 33, 24});
    REQUIRE(mesh.data().isMesh());
    const auto triangles = static_cast<std::uint32_t>(mesh.data().indices.size() / 3);
    REQUIRE(triangles > 500);
    constexpr int kPosts = 301;
    std::vector<std::uint32_t> below(kPosts, ~0u);
    std::uint32_t random = 12345u;
    double largest = 0.0;
    int found = 0;
    for (int j = 0; j < kPosts; ++j) {
        std::uint32_t left = ~0u;
        for (int i = 0; i < kPosts; ++i) {
            const double u = i / (kPosts - 1.0), v = j / (kPosts - 1.0);
            random = random * 1664525u + 1013904223u;
            std::array<std::uint32_t, 2> hints{i % 7 == 3 ? random % triangles : left, below[static_cast<std::size_t>(i)]};
            const double hinted = mesh.height(u, v, hints);
            largest = std::max(largest, std::abs(hinted - mesh.height(u, v)));
            found += hints[0] < triangles ? 1 : 0;
            left = below[static_cast<std::size_t>(i)] = hints[0];
        }
    }
    // Only a point on an edge shared by two triangles may differ, by their planes' roundings.
    CHECK(largest <= 1e-6);
    CHECK(found == kPosts * kPosts); // the mesh covers its tile: every point's triangle is left as a hint
}
