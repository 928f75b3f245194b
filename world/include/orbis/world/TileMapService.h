#pragma once

#include <orbis/core/Image.h>

#include <filesystem>
#include <optional>

namespace orbis::world {

/// The most pixels a side of a whole-globe mosaic may have: 16384, what GPUs take as one texture.
inline constexpr int kMaximumMosaicSide = 16384;

/// The tiles of one level (the finest when level is empty) of a geodetic TMS folder (as
/// ../data/imagery holds; read as openTileSource reads it) joined into one equirectangular RGB
/// image, north up, longitude -180 at the left. Throws orbis::Error naming the folder for a
/// description that is not geodetic, a level not in the pyramid, or a mosaic wider than
/// kMaximumMosaicSide (checked before anything is allocated), and naming the tile for a missing,
/// unreadable or wrongly sized one.
Image readTileMapMosaic(const std::filesystem::path& folder, std::optional<int> level = std::nullopt);

/// An image file as is, or a TMS folder's finest mosaic.
Image readGlobeImage(const std::filesystem::path& path);

} // namespace orbis::world
