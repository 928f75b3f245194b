#pragma once

#include "orbis/world/TerrainSource.h"

#include <orbis/core/Ellipsoid.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::world {

// Decoders and encoders of terrain tiles. Every decoder is safe on several threads at once and
// throws orbis::Error naming `nameForMessages` (the tile's path or URL) and what was wrong: data
// cut short, counts the bytes cannot hold (checked before anything is allocated), indices out of
// range, values outside the format's range, bad gzip. Gzip-compressed input (as servers and
// tilers store .terrain files) is recognised by its signature and inflated first.

/// The most bytes a gzip member may inflate to, and the most vertices a mesh may have.
inline constexpr std::size_t kMaximumInflatedBytes = std::size_t{64} << 20;
inline constexpr std::uint32_t kMaximumMeshVertices = std::uint32_t{1} << 22;

/// True when the bytes start with the gzip signature (1f 8b).
bool isGzip(std::span<const std::uint8_t> bytes) noexcept;
/// The bytes inflated when they are gzip, else a copy. Throws for a corrupt or truncated member,
/// bytes after it, or more than maximumBytes inflated.
std::vector<std::uint8_t> gunzipIfCompressed(std::span<const std::uint8_t> bytes, std::string_view nameForMessages,
                                             std::size_t maximumBytes = kMaximumInflatedBytes);
/// A gzip member of the bytes (zlib level 9 is the smallest, 1 the fastest).
std::vector<std::uint8_t> gzipBytes(std::span<const std::uint8_t> bytes, int level = 6);

// ---- quantized-mesh-1.0 --------------------------------------------------------------------------

/// A quantized-mesh-1.0 tile: the 88-byte header, zigzag-delta vertices, high-water-mark indices
/// (16-bit, or 32-bit above 65,536 vertices), the edge lists, and the extensions: oct-encoded
/// normals (1), water mask (2), metadata (4; its "available" goes to availableBelow). Unknown
/// extensions are skipped. Edge lists are checked to lie on their edge and sorted along it.
TerrainTileData decodeQuantizedMesh(std::span<const std::uint8_t> bytes, const orbis::TileKey& key,
                                    std::string_view nameForMessages);

struct QuantizedMeshEncoding {
    bool normals = false;        ///< write tile.normals (one per vertex) as the oct-normal extension
    bool waterMask = false;      ///< write tile.waterMask (1 or 256 x 256 values)
    std::string metadataJson;    ///< non-empty: the metadata extension's JSON
    int gzipLevel = 0;           ///< 0: not compressed
};

/// The tile (a mesh, vertices u and v in 0..1) as quantized-mesh-1.0: u and v quantized to
/// 0..32767, heights to 0..32767 between the header's minimum and maximum (the vertices' own), the
/// bounding sphere, centre and horizon occlusion point computed on `ellipsoid` for the key's tile
/// in the geographic scheme. Throws orbis::Error for a tile that is not a valid mesh.
std::vector<std::uint8_t> encodeQuantizedMesh(const TerrainTileData& tile, const QuantizedMeshEncoding& encoding = {},
                                              const orbis::Ellipsoid& ellipsoid = orbis::Ellipsoid::wgs84());

// ---- heightmap-1.0 -------------------------------------------------------------------------------

/// A heightmap-1.0 tile: 65 x 65 little-endian uint16 heights (value / 5 - 1000 metres) row by row
/// from the north, the child mask byte, then a water mask of 1 or 256 x 256 bytes (or none).
TerrainTileData decodeHeightmapTerrain(std::span<const std::uint8_t> bytes, const orbis::TileKey& key,
                                       std::string_view nameForMessages);
/// A 65 x 65 grid tile as heightmap-1.0 (heights rounded to 0.2 m and clamped to -1000..12107 m),
/// with its child mask and water mask (a single 0 byte when it has none).
std::vector<std::uint8_t> encodeHeightmapTerrain(const TerrainTileData& tile, int gzipLevel = 0);
/// The heightmap-1.0 value of a height: rounded to 0.2 m and clamped to the format's range.
float heightmapTerrainQuantize(double height) noexcept;

// ---- height images -------------------------------------------------------------------------------

/// How heights are packed into image pixels.
enum class HeightEncoding {
    Png16,     ///< 16-bit grey, height = value - 32768 (the shared ETOPO5 tiles)
    TerrainRgb, ///< Mapbox Terrain-RGB: height = -10000 + (R 65536 + G 256 + B) / 10
    Terrarium, ///< Terrarium: height = R 256 + G + B / 256 - 32768
};

/// A grid of heights, row by row from the north; NaN where there is no data.
struct HeightGrid {
    int width = 0;
    int height = 0;
    std::vector<float> heights;

    float at(int x, int y) const { return heights[static_cast<std::size_t>(y) * width + x]; }
};

/// Heights of a PNG (or WebP, for the RGB encodings). Throws for an image of another kind (a
/// Terrain-RGB tile asked for as 16-bit heights says so).
HeightGrid decodeHeightImage(std::span<const std::uint8_t> bytes, HeightEncoding encoding, std::string_view nameForMessages);
/// The heights as a 16-bit PNG (rounded to metres, clamped to -32768..32767).
std::vector<std::uint8_t> encodeHeightPng16(const HeightGrid& grid, int compressionLevel = 6);

// ---- SRTM .hgt -----------------------------------------------------------------------------------

/// An SRTM .hgt file: 1201 x 1201 (3 arc-seconds) or 3601 x 3601 (1 arc-second) big-endian int16,
/// row 0 the north edge, voids (-32768) NaN. The size comes from the byte count; any other count
/// is an error.
HeightGrid decodeHgt(std::span<const std::uint8_t> bytes, std::string_view nameForMessages);

/// The south-west corner of a .hgt file from its name ("N37W123.hgt", any case, any folder):
/// longitude, latitude in whole degrees; empty for another name.
std::optional<std::pair<int, int>> hgtCorner(std::string_view fileName) noexcept;

// ---- geometry ------------------------------------------------------------------------------------

/// The horizon occlusion point of points on or above the ellipsoid (Earth-fixed metres), in the
/// ellipsoid-scaled space of quantized-mesh: a point P along `direction` (scaled, from the
/// ellipsoid's centre towards the tile) such that whenever P is below the horizon of a viewer
/// outside the ellipsoid, so is every point. Empty when no such point exists (points spread over
/// a hemisphere or more).
std::optional<glm::dvec3> horizonOcclusionPoint(const orbis::Ellipsoid& ellipsoid, std::span<const glm::dvec3> points,
                                                const glm::dvec3& direction) noexcept;

/// Oct encoding of a unit vector into two bytes (quantized-mesh's normals), and back.
std::array<std::uint8_t, 2> octEncodeNormal(const glm::vec3& normal) noexcept;
glm::vec3 octDecodeNormal(std::uint8_t x, std::uint8_t y) noexcept;

} // namespace orbis::world
