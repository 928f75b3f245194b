#include "orbis/world/FunctionTerrainSource.h"

#include <algorithm>

namespace orbis::world {

FunctionTerrainSource::FunctionTerrainSource(std::function<double(const Geodetic2D&)> height, std::uint32_t maximumLevel,
                                             double levelOffset)
    : _height(std::move(height)), _levelOffset(levelOffset)
{
    _info.name = "terrain from a function";
    _info.format = "heightmap";
    _info.maximumLevel = std::min(maximumLevel, kMaximumTileLevel);
    _info.gridSize = 65;
}

bool FunctionTerrainSource::hasTile(const TileKey& key) const
{
    return key.level <= _info.maximumLevel && TilingScheme::geographic().isValid(key);
}

TerrainFetch FunctionTerrainSource::load(const TileKey& key)
{
    TerrainFetch fetched;
    if (!hasTile(key)) {
        fetched.status = TerrainFetch::Status::Missing;
        return fetched;
    }
    fetched.status = TerrainFetch::Status::Ok;
    TerrainTileData& tile = fetched.tile;
    tile.key = key;
    tile.size = _info.gridSize;
    tile.heights.resize(static_cast<std::size_t>(tile.size) * static_cast<std::size_t>(tile.size));
    for (int row = 0; row < tile.size; ++row) {
        for (int column = 0; column < tile.size; ++column) {
            tile.heights[static_cast<std::size_t>(row * tile.size + column)] = static_cast<float>(
                _height(terrainGridPosition(key, tile.size, column, row)) + _levelOffset * key.level);
        }
    }
    const auto [low, high] = std::minmax_element(tile.heights.begin(), tile.heights.end());
    tile.minimumHeight = *low;
    tile.maximumHeight = *high;
    return fetched;
}

} // namespace orbis::world
