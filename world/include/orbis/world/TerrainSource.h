#pragma once

#include "orbis/world/TerrainLayer.h"
#include "orbis/world/TileSource.h"

#include <orbis/core/Geodetic.h>
#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/TileKey.h>
#include <orbis/core/TilingScheme.h>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::world {

/// One terrain tile's heights (metres above the datum the source uses; the WGS84 ellipsoid is the
/// surface they are added to).
struct TerrainTileData {
    orbis::TileKey key;               ///< of the geographic scheme (TMS rows from the south)
    /// A regular grid: size x size samples over the tile's extent, row 0 the north edge, column 0
    /// the west edge, the first and last rows and columns exactly on the tile's edges (point
    /// registration: neighbours share them).
    int size = 0;                     ///< 0 when the tile is a mesh; otherwise 2^k + 1
    std::vector<float> heights;       ///< size * size, row by row from the north
    /// Or a triangle mesh (quantized-mesh): per vertex u, v (0..1 west to east, south to north)
    /// and height; counter-clockwise triangles (seen from above); the vertices on each edge,
    /// north and south sorted west to east, east and west sorted south to north.
    std::vector<glm::vec3> vertices;
    std::vector<std::uint32_t> indices;
    std::array<std::vector<std::uint32_t>, 4> edgeVertices; ///< north, east, south, west
    double minimumHeight = 0.0, maximumHeight = 0.0;  ///< of the heights or vertices
    std::optional<glm::dvec3> horizonOcclusionPoint;  ///< ellipsoid-scaled, when the format gives one
    /// Per vertex (or per sample), unit, Earth-fixed, when the format gives them (oct-encoded normals).
    std::vector<glm::vec3> normals;
    /// 0: none; 1: one value for the whole tile (0 land, 255 water); else waterMaskSize^2 values,
    /// row by row from the north.
    std::vector<std::uint8_t> waterMask;
    int waterMaskSize = 0;
    std::optional<double> geometricError; ///< metres, when the source states it (our tiler's layer.json)
    std::uint8_t childMask = 0x0f;    ///< which children exist (bits: SW 1, SE 2, NW 4, NE 8), when known
    /// The quantized-mesh metadata extension's availability: element i covers level key.level + 1 + i.
    std::vector<LevelAvailability> availableBelow;

    bool isMesh() const noexcept { return size == 0; }
    /// The bytes the tile's vectors hold (their capacity), for cache accounting.
    std::size_t memoryBytes() const noexcept;
};

struct TerrainSourceInfo {
    std::string name;                 ///< the path or URL, for messages
    /// "quantized-mesh", "heightmap", "png16", "terrain-rgb", "terrarium", "hgt", "gdal"
    std::string format;
    orbis::TilingScheme scheme = orbis::TilingScheme::geographic(); ///< of the keys load() takes: always geographic
    std::uint32_t minimumLevel = 0, maximumLevel = 0;
    orbis::GeodeticExtent extent = orbis::GeodeticExtent::maximum();
    std::string attribution;
    /// Samples per tile side of the grids load() returns; 0 for meshes (quantized-mesh).
    int gridSize = 0;
};

struct TerrainFetch {
    enum class Status { Ok, Missing, Failed };
    Status status = Status::Failed;
    TerrainTileData tile;             ///< Ok only
    std::string message;              ///< Failed: names the tile (its path or URL) and what was wrong
};

/// A source of terrain tiles in the geographic scheme. load() may be called from several threads
/// at once; the source must outlive those calls.
class TerrainSource {
public:
    virtual ~TerrainSource() = default;
    virtual const TerrainSourceInfo& info() const noexcept = 0;
    /// Blocking, never throws for one tile's trouble; Missing where the source has no such tile
    /// (availability, 404, a key outside its levels or extent).
    virtual TerrainFetch load(const orbis::TileKey& key) = 0;
    /// Whether the source has the tile, from its availability (layer.json, and the metadata of
    /// tiles loaded so far) or its levels and extent; cheap, no I/O. Where availability is given
    /// by tiles not loaded yet (the metadata extension), true for children of available tiles.
    virtual bool hasTile(const orbis::TileKey& key) const = 0;
    /// The tile's geometric error (metres: how far its surface is from the data it stands for)
    /// where the source states it before loading it (our tiler's layer.json); cheap, no I/O.
    virtual std::optional<double> geometricError(const orbis::TileKey&) const { return std::nullopt; }
};

struct TerrainSourceOptions {
    /// How tiles are fetched (HTTP retries, cache folder, levels and scheme of templates).
    TileSourceOptions tiles;
    /// "quantized-mesh", "heightmap", "png16", "terrain-rgb", "terrarium", "hgt", "gdal"; empty:
    /// from layer.json, the MBTiles metadata, .hgt names, a template's extension (".terrain" is
    /// quantized-mesh, ".png" 16-bit heights), else GDAL. Terrain-RGB and Terrarium must be named.
    std::string format;
    /// Samples per side of the tiles that resampled sources (Terrain-RGB, Terrarium, PNG heights
    /// whose tiles are not 2^k + 1 geographic ones, .hgt, GDAL) return: 2^k + 1, 3 to 1025.
    int gridSize = 65;
    /// The height of samples where the source has no data (voids, outside a DEM).
    double noDataHeight = 0.0;
    /// Deepest level of resampled sources (.hgt, GDAL); empty: the first level whose sample
    /// spacing is no coarser than the source's.
    std::optional<std::uint32_t> maximumLevel;
    /// Quantized-mesh over HTTP: ask for the oct-normal, water-mask and metadata extensions (the
    /// Accept header servers expect).
    bool requestExtensions = true;
};

/// Opens a terrain source by its path or URL:
///  - a folder or URL with layer.json, or layer.json itself: quantized-mesh-1.0 or heightmap-1.0
///    tiles as layer.json says (its tile template, scheme, levels, bounds and availability);
///  - a `.mbtiles` file of those tiles (or of PNG heights): its metadata's `format`, and its
///    `json` row read as layer.json for availability;
///  - a TMS folder (tilemapresource.xml) or a `{z}/{x}/{y}` template of 16-bit PNG, Terrain-RGB or
///    Terrarium tiles, or of `.terrain` tiles;
///  - a folder of SRTM `.hgt` files (N37W123.hgt: 1201 or 3601 samples a side), or one such file;
///  - any other file: one DEM that GDAL reads, in any CRS, warped into each tile on demand.
/// Throws orbis::Error naming the source when it cannot be opened (no such file, a malformed
/// layer.json, a format it cannot tell, a projection it does not support).
std::unique_ptr<TerrainSource> openTerrainSource(const std::string& pathOrUrl, const TerrainSourceOptions& options = {});

/// The longitude and latitude of sample (column, row) of a size x size grid tile (row 0 the
/// north edge; size 2^k + 1). Computed from the sample's index on the whole level's lattice, so
/// that a sample shared by neighbours, or by a parent and its child, is the same pair of doubles
/// in each, and edge samples are exactly TilingScheme::tileExtent's edges. Columns and rows beyond
/// 0..size - 1 continue the lattice into the neighbours (latitudes then may pass the poles).
orbis::Geodetic2D terrainGridPosition(const orbis::TileKey& key, int size, int column, int row) noexcept;

/// The level of the geographic scheme at which a grid of gridSize samples a side is about as fine
/// as a source with degreesPerSample: the first whose spacing is at most 1.1 times it (a grid of
/// 2^k + 1 samples cannot match every spacing; one level finer quadruples the tiles for 5 %).
std::uint32_t terrainLevelForResolution(double degreesPerSample, int gridSize) noexcept;

/// True for 2^k + 1 from 3 to 1025.
bool isTerrainGridSize(int size) noexcept;

/// The format names openTerrainSource takes, for messages and usage lines.
inline constexpr const char* kTerrainFormats = "quantized-mesh, heightmap, png16, terrain-rgb, terrarium, hgt, gdal";

} // namespace orbis::world
