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
