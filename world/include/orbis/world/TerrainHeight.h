#pragma once

#include "orbis/world/TerrainSource.h"

#include <orbis/core/Geodetic.h>
#include <orbis/core/TileKey.h>

#include <cstddef>
#include <future>
#include <memory>
#include <optional>
#include <vector>

namespace orbis::world {

/// The height of one tile's surface at a position (radians) inside its extent or on its edge: a
/// grid bilinearly in the cell holding the point, a mesh on the triangle holding it. On a grid
/// tile's edge only the edge's two nearest samples count, with the same weights in both tiles
/// that share it, so neighbours of a source that shares edge samples (every grid source here)
/// give the same value bit for bit. Longitudes a turn away are the same. Empty outside the tile,
/// or where no triangle of a mesh covers the point.
std::optional<double> terrainTileHeight(const TerrainTileData& tile, const orbis::Geodetic2D& position);

/// The tiles of a level of the geographic scheme whose extent holds the position, edges included:
/// one inside a tile, two on an edge, four at a corner (longitude +-180 degrees is one meridian;
/// at a pole, the tile or two whose columns hold the longitude). Sorted by key.
std::vector<orbis::TileKey> terrainTilesAt(std::uint32_t level, const orbis::Geodetic2D& position);

struct TerrainHeight {
    double height = 0.0;
    /// The tile the height came from: the deepest the source has there. On an edge or a corner
    /// several tiles of that level hold the point; the height is the mean of theirs (equal for
    /// grids) and this is the first of them.
    orbis::TileKey tile;
    std::optional<double> geometricError; ///< of that tile, when the source states it
};

/// Most-detailed heights from a terrain source: each point answered by the deepest tile the
/// source has there (its availability first, then loading, one level up where a tile turns out
/// missing). The answer does not depend on which of the tiles sharing an edge or corner is
/// read first. Tiles loaded are kept, up to a budget of bytes, so that points near each other
/// load each tile once. One caller at a time.
class TerrainHeightQuery {
public:
    explicit TerrainHeightQuery(TerrainSource& source, std::size_t cacheBytes = std::size_t{256} << 20);
    ~TerrainHeightQuery();
    TerrainHeightQuery(const TerrainHeightQuery&) = delete;
    TerrainHeightQuery& operator=(const TerrainHeightQuery&) = delete;

    /// The height at a position (radians); empty where the source has no tile there. Throws
    /// orbis::Error with the source's message (naming the tile) when a tile it needs fails to load.
    std::optional<TerrainHeight> at(const orbis::Geodetic2D& position);

    /// Tiles loaded so far (each once while it stays within the budget).
    std::size_t tilesLoaded() const noexcept;

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
};

/// The most-detailed heights at many positions (radians), answered on a thread of its own by a
/// TerrainHeightQuery, which loads the tiles it needs: the way to ask without blocking a frame.
/// The future holds one answer per position in their order (empty where the source has no tile),
/// or the orbis::Error of a tile that failed to load, which names it. The source is kept alive
/// until the answers are in; other threads may load from it meanwhile.
std::future<std::vector<std::optional<TerrainHeight>>> mostDetailedHeights(std::shared_ptr<TerrainSource> source,
                                                                           std::vector<orbis::Geodetic2D> positions);

} // namespace orbis::world
