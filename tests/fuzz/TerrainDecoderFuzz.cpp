// libFuzzer target for the terrain decoders: quantized-mesh-1.0 (and its gzip), heightmap-1.0,
// 16-bit PNG / Terrain-RGB / Terrarium heights, SRTM .hgt and layer.json. Any input either
// decodes into a tile whose counts and indices hold together, or throws orbis::Error naming the
// tile. Any other exception, a crash, a sanitizer report or a broken invariant is a bug. Built and
// run by scripts/fuzz.sh --target terrain.
#include <orbis/core/Error.h>
#include <orbis/world/TerrainCodec.h>
#include <orbis/world/TerrainLayer.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string_view>

namespace {

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

void requireNamed(const orbis::Error& error)
{
    require(std::string_view(error.what()).find("fuzz tile") != std::string_view::npos);
}

void checkMesh(const orbis::world::TerrainTileData& tile)
{
    require(tile.isMesh());
    require(tile.indices.size() % 3 == 0);
    for (const std::uint32_t index : tile.indices) {
        require(index < tile.vertices.size());
    }
    for (const auto& edge : tile.edgeVertices) {
        for (const std::uint32_t index : edge) {
            require(index < tile.vertices.size());
        }
    }
    for (const auto& vertex : tile.vertices) {
        require(vertex.x >= 0.0f && vertex.x <= 1.0f && vertex.y >= 0.0f && vertex.y <= 1.0f && std::isfinite(vertex.z));
    }
    require(tile.normals.empty() || tile.normals.size() == tile.vertices.size());
    require(tile.waterMask.size() <= 1 || tile.waterMask.size() == std::size_t(tile.waterMaskSize) * std::size_t(tile.waterMaskSize));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace orbis::world;
    const std::span<const std::uint8_t> bytes(data, size);
    const orbis::TileKey key{5, 17, 9};
    try {
        checkMesh(decodeQuantizedMesh(bytes, key, "fuzz tile"));
    } catch (const orbis::Error& error) {
        requireNamed(error);
    }
    try {
        const TerrainTileData tile = decodeHeightmapTerrain(bytes, key, "fuzz tile");
        require(tile.size == 65 && tile.heights.size() == 65u * 65u);
    } catch (const orbis::Error& error) {
        requireNamed(error);
    }
    for (const HeightEncoding encoding : {HeightEncoding::Png16, HeightEncoding::TerrainRgb, HeightEncoding::Terrarium}) {
        try {
            const HeightGrid grid = decodeHeightImage(bytes, encoding, "fuzz tile");
            require(grid.width > 0 && grid.height > 0);
            require(grid.heights.size() == std::size_t(grid.width) * std::size_t(grid.height));
        } catch (const orbis::Error& error) {
            requireNamed(error);
        }
    }
    try {
        const HeightGrid grid = decodeHgt(bytes, "fuzz tile");
        require(grid.heights.size() == std::size_t(grid.width) * std::size_t(grid.height));
    } catch (const orbis::Error& error) {
        requireNamed(error);
    }
    try {
        const TerrainLayer layer =
            parseTerrainLayer(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz tile layer.json");
        require(layer.minimumLevel <= layer.maximumLevel && !layer.tiles.empty());
        // What it writes reads back.
        require(parseTerrainLayer(formatTerrainLayer(layer), "fuzz tile again").available == layer.available);
    } catch (const orbis::Error& error) {
        requireNamed(error);
    }
    return 0;
}
