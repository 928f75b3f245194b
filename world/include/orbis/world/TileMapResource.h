#pragma once

#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/TilingScheme.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world {

/// A TMS tile map description (tilemapresource.xml, OSGeo TMS 1.0): the global-geodetic profile
/// (EPSG:4326, two root tiles, as data/imagery holds) or the global-mercator one (EPSG:3857, one
/// root tile). Rows are counted from the south in both, as TMS does; TileKey rows follow the
/// TilingScheme (from the north for Web Mercator), and the tile sources convert.
struct TileMapResource {
    struct TileSet {
        std::string href;          ///< the level's folder or URL, relative to the description's folder
        std::uint32_t level = 0;   ///< `order`
        double unitsPerPixel = 0.0; ///< degrees (geodetic) or metres (mercator) per pixel
    };

    std::string title;
    std::string abstract;
    std::string attribution;       ///< `<Attribution><Title>`, where the file has one
    orbis::TilingScheme scheme = orbis::TilingScheme::geographic();
    orbis::GeodeticExtent extent = orbis::GeodeticExtent::maximum(); ///< the BoundingBox, radians
    int tileWidth = 256;
    int tileHeight = 256;
    std::string mimeType = "image/jpeg";
    std::string extension = "jpg";
    std::vector<TileSet> tileSets; ///< one per level, levels ascending and contiguous

    std::uint32_t minimumLevel() const noexcept { return tileSets.empty() ? 0 : tileSets.front().level; }
    std::uint32_t maximumLevel() const noexcept { return tileSets.empty() ? 0 : tileSets.back().level; }
};

/// The largest tile side a description may give: 4096 pixels.
inline constexpr int kMaximumTileSide = 4096;

/// Reads a description. Every value is checked before anything is built from it: the SRS and
/// profile, the origin (the scheme's lower left), the bounding box (finite, ordered, on the globe),
/// the tile size (1..kMaximumTileSide), the extension, and the tile sets (1 to 31, orders 0..30
/// unique and contiguous, units-per-pixel matching each level). Throws orbis::Error naming
/// `nameForMessages`, the line and the element or attribute for malformed XML or any bad value.
TileMapResource parseTileMapResource(std::string_view xml, std::string_view nameForMessages);

/// parseTileMapResource of `folder`/tilemapresource.xml (or of the file itself, when `path` names one).
TileMapResource readTileMapResource(const std::filesystem::path& path);

/// The description as tilemapresource.xml text, which parseTileMapResource reads back equal.
std::string formatTileMapResource(const TileMapResource& resource);

/// The units per pixel of `level` in `scheme` for tiles `tileWidth` pixels wide, as TMS gives them.
double tileMapUnitsPerPixel(const orbis::TilingScheme& scheme, std::uint32_t level, int tileWidth) noexcept;

} // namespace orbis::world
