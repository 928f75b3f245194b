#pragma once

#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/TileKey.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world {

/// Tiles startX..endX by startY..endY (inclusive) of one level, rows counted from the south (TMS),
/// as layer.json's "available" gives them.
struct TileRectangle {
    std::uint32_t startX = 0, startY = 0, endX = 0, endY = 0;

    bool contains(std::uint32_t x, std::uint32_t y) const noexcept
    {
        return x >= startX && x <= endX && y >= startY && y <= endY;
    }
    friend bool operator==(const TileRectangle&, const TileRectangle&) = default;
};

/// The rectangles of one level.
using LevelAvailability = std::vector<TileRectangle>;

/// The measured geometric error of every tile of one level within a rectangle (our tiler's).
struct LevelGeometricErrors {
    std::uint32_t level = 0;
    std::uint32_t startX = 0, startY = 0; ///< rows from the south
    std::uint32_t width = 0, height = 0;
    /// width * height, row by row from startY, column by column from startX; NaN where no tile.
    std::vector<float> errors;

    /// The error of tile x, y (rows from the south); empty outside or where none.
    std::optional<double> at(std::uint32_t x, std::uint32_t y) const noexcept;
    friend bool operator==(const LevelGeometricErrors&, const LevelGeometricErrors&) = default;
};

/// A layer.json, the description of a quantized-mesh-1.0 or heightmap-1.0 tile set (the layer
/// format CesiumJS reads), with our tiler's per-tile geometric errors under "orbis:geometricError".
struct TerrainLayer {
    std::string name;
    std::string description;
    std::string attribution;
    std::string version = "1.0.0";
    std::string format = "quantized-mesh-1.0";      ///< or "heightmap-1.0"
    /// URL templates relative to the layer.json: {z}, {x}, {y}, {version}.
    std::vector<std::string> tiles = {"{z}/{x}/{y}.terrain?v={version}"};
    bool rowsFromSouth = true;                      ///< "scheme": "tms" (true) or "slippyMap"
    std::string projection = "EPSG:4326";
    orbis::GeodeticExtent bounds = orbis::GeodeticExtent::maximum(); ///< radians
    std::uint32_t minimumLevel = 0, maximumLevel = 0;
    /// Per level from 0; levels beyond its end are available only where metadata tiles say so
    /// (metadataAvailability) or, without "available" at all, everywhere within the bounds.
    std::vector<LevelAvailability> available;
    bool hasAvailable = false;                      ///< the file has "available"
    std::optional<std::uint32_t> metadataAvailability; ///< levels between metadata tiles
    std::vector<std::string> extensions;            ///< "octvertexnormals", "watermask", "metadata"
    std::vector<LevelGeometricErrors> geometricErrors;

    /// The tile's error from geometricErrors; empty where the file gives none.
    std::optional<double> geometricError(const orbis::TileKey& key) const noexcept;
};

/// Whether the layer has the tile (key rows from the south): within its levels and, where it
/// lists availability for the key's level, inside one of that level's rectangles. Levels beyond
/// the listed ones count as available when the layer has metadataAvailability (their
/// availability is in metadata tiles) or no "available" at all.
bool layerHasTile(const TerrainLayer& layer, const orbis::TileKey& key) noexcept;

/// The largest layer.json read: 32 MiB.
inline constexpr std::size_t kMaximumTerrainLayerBytes = std::size_t{32} << 20;

/// Reads a layer.json. Every value is checked (the format and projection it names, levels 0 to
/// 30, bounds on the globe, rectangles within their level, error grids of the size they claim).
/// Throws orbis::Error naming `nameForMessages` and the key (a JSON pointer) for malformed JSON
/// or any bad value.
TerrainLayer parseTerrainLayer(std::string_view text, std::string_view nameForMessages);

/// The layer as layer.json text (keys in a fixed order), which parseTerrainLayer reads back equal.
std::string formatTerrainLayer(const TerrainLayer& layer);

/// Rectangles covering exactly the given tiles of one level (x, y pairs, rows from the south):
/// runs of columns in each row, merged with the rows above where they are the same run.
LevelAvailability rectanglesOf(std::vector<std::pair<std::uint32_t, std::uint32_t>> tiles);

} // namespace orbis::world
