#pragma once

#include <orbis/core/Image.h>

#include <filesystem>
#include <optional>

namespace orbis::world {

/// A TMS tile pyramid on disk (tilemapresource.xml beside level folders z/x/y.ext), geodetic
/// profile (EPSG:4326, two root tiles, origin at the lower left), as ../data/imagery holds.
struct TileMapDescription {
    int tileWidth = 256;
    int tileHeight = 256;
    std::string extension = "jpg";
    int levelCount = 0;
};

/// Reads tilemapresource.xml. Throws orbis::Error naming the file for anything but a geodetic
/// EPSG:4326 pyramid with a lower-left origin.
TileMapDescription readTileMapDescription(const std::filesystem::path& folder);

/// The tiles of one level (the finest when level is empty) joined into one equirectangular image,
/// north up, longitude -180 at the left. Throws orbis::Error naming a missing or unreadable tile.
Image readTileMapMosaic(const std::filesystem::path& folder, std::optional<int> level = std::nullopt);

/// An image file as is, or a TMS folder's finest mosaic.
Image readGlobeImage(const std::filesystem::path& path);

} // namespace orbis::world
