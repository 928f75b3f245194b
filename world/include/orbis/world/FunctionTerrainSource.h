#pragma once

#include <orbis/world/TerrainSource.h>

#include <functional>

namespace orbis::world {

/// Terrain from a function: metres at a longitude and latitude (radians), sampled into 65 x 65
/// grids (terrainGridPosition) for levels 0 to maximumLevel, each level's heights raised by
/// levelOffset x level, so that the levels can disagree as a box-filtered pyramid's do. For
/// synthetic terrain in tests, benchmarks and procedural scenes; the function is called from the
/// loader's threads at once, so it must be safe to call concurrently.
class FunctionTerrainSource final : public TerrainSource {
public:
    FunctionTerrainSource(std::function<double(const orbis::Geodetic2D&)> height, std::uint32_t maximumLevel,
                          double levelOffset = 0.0);

    const TerrainSourceInfo& info() const noexcept override { return _info; }
    bool hasTile(const orbis::TileKey& key) const override;
    TerrainFetch load(const orbis::TileKey& key) override;

private:
    std::function<double(const orbis::Geodetic2D&)> _height;
    double _levelOffset;
    TerrainSourceInfo _info;
};

} // namespace orbis::world
