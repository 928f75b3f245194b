#pragma once

// The tile sources behind openTileSource. Private to orbis::world.

#include "orbis/world/TileSource.h"

#include <memory>
#include <string>

namespace orbis::world::detail {

/// True when `key` is inside the source's levels, a valid tile of its scheme, and touches its extent.
bool sourceHasTile(const TileSourceInfo& info, const orbis::TileKey& key) noexcept;

/// An MBTiles database (SQLite), read only. Throws orbis::Error when it cannot be opened.
std::unique_ptr<TileSource> openMBTiles(const std::string& path, const TileSourceOptions& options);

} // namespace orbis::world::detail
