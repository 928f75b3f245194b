#pragma once

// The tile sources behind openTileSource. Private to orbis::world.

#include "orbis/world/TerrainLayer.h"
#include "orbis/world/TileSource.h"

#include <memory>
#include <string>

namespace orbis::world::detail {

/// True when `key` is inside the source's levels, a valid tile of its scheme, and touches its extent.
bool sourceHasTile(const TileSourceInfo& info, const orbis::TileKey& key) noexcept;

/// An MBTiles database (SQLite), read only. Throws orbis::Error when it cannot be opened.
std::unique_ptr<TileSource> openMBTiles(const std::string& path, const TileSourceOptions& options);

/// The tiles of a terrain set described by a layer.json, and the description.
struct LayerTiles {
    std::unique_ptr<TileSource> tiles;
    TerrainLayer layer;
};

/// A terrain set from its folder or URL (or the layer.json's own path or URL): layer.json is read
/// (over HTTP through the cache folder, as tiles are), and its first tile template, resolved
/// against the layer's location, {version} filled in and its rows counted as its scheme says,
/// locates the tiles (geographic scheme, the layer's levels and bounds; the query of a template
/// is dropped for files on disk). Throws orbis::Error when layer.json cannot be had or read.
LayerTiles openLayerTiles(const std::string& location, const TileSourceOptions& options);

/// True when `location` is a folder holding layer.json, or names a layer.json (path or URL).
bool looksLikeLayer(const std::string& location);

} // namespace orbis::world::detail
