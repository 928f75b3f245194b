#pragma once

#include "orbis/world/ImageryTiler.h"

#include <orbis/core/GeodeticExtent.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace orbis::world {

enum class TerrainTileFormat { QuantizedMesh, Heightmap };

struct TerrainTilerOptions {
    /// One DEM that GDAL reads (GeoTIFF, a VRT, ...), in any CRS PROJ knows; band 1 holds the
    /// heights (its scale, offset and nodata honoured), longitudes may run 0..360.
    std::filesystem::path input;
    /// The folder written: LEVEL/X/Y.terrain (rows from the south), layer.json, and
    /// geometric-error/LEVEL/X.txt (each column's measured errors, from which layer.json is made).
    std::filesystem::path output;
    TerrainTileFormat format = TerrainTileFormat::QuantizedMesh;
    /// Levels 0 to levels - 1; empty: down to terrainLevelForResolution of the DEM's pixels.
    std::optional<std::uint32_t> levels;
    /// Cut only this level (any order: every level is sampled from the DEM itself).
    std::optional<std::uint32_t> onlyLevel;
    /// With onlyLevel: only columns first..last (inclusive) of that level. Jobs that split the
    /// pyramid write the same files as one job.
    std::optional<std::pair<std::uint32_t, std::uint32_t>> columns;
    /// Worker threads; 0: one per hardware thread.
    int threads = 0;
    /// Samples a side of each tile's grid: 65 for heightmap-1.0 (the format's); for quantized-mesh
    /// the grid that is simplified, 2^k + 1 from 5 to 1025.
    int gridSize = 65;
    /// Quantized-mesh: the simplification tolerance at level 0 in metres, halved at each level
    /// below; empty: a sixteenth of TilingScheme::geometricError at level 0 (4.8 km: 150 m at
    /// level 5, 1.2 m at level 12). 0 keeps every grid sample.
    std::optional<double> maximumError;
    /// Quantized-mesh: write Earth-fixed vertex normals (the oct-encoded normals extension).
    bool normals = true;
    /// zlib level of each tile file's gzip compression (0: none), as terrain servers store them.
    int gzipLevel = 6;
    /// The height of samples where the DEM has no data.
    double noDataHeight = 0.0;
    std::string title;       ///< layer.json's name; empty: the input's file name
    std::string attribution; ///< layer.json's attribution
    std::function<void(const TilerProgress&)> progress;
};

struct TerrainTilerSummary {
    std::size_t tilesWritten = 0;
    std::uint32_t levelCount = 0;
    std::uint64_t bytesWritten = 0; ///< of the tile files
    double seconds = 0.0;
    /// The largest measured geometric error of the tiles cut, per level (0 for levels not cut).
    std::vector<double> maximumErrors;
};

/// Cuts a DEM into a terrain tile set of the geographic scheme that openTerrainSource reads (and
/// CesiumJS, for quantized-mesh and heightmap-1.0 alike). Every level is point-sampled from the
/// DEM at the grid samples of terrainGridPosition (bilinear between the DEM's pixel centres), so a
/// sample that a parent and child or two neighbours share has the same height in each. Each
/// tile's geometric error is measured: the largest vertical distance between the tile as written
/// (decoded back) and the DEM at every DEM pixel centre inside the tile, every grid sample and
/// every grid cell's centre (for grids: the larger of the two triangulations of each cell), and
/// along a mesh's triangle edges (four points a DEM pixel), where the largest differences lie, in
/// layer.json as "orbis:geometricError" beside the availability. Tiles are cut where the DEM's
/// footprint is; files appear whole or not at all.
///
/// Quantized-mesh tiles: the grid simplified (see maximumError) with each edge reduced from its own
/// samples alone, so neighbours of one level share their edge vertices exactly (positions and the
/// heights before quantization; quantized heights differ by at most half a step of either tile's
/// range / 32767).
class TerrainTiler {
public:
    /// Opens the DEM and checks the options. Throws orbis::Error naming the input or option.
    explicit TerrainTiler(TerrainTilerOptions options);
    ~TerrainTiler();
    TerrainTiler(const TerrainTiler&) = delete;
    TerrainTiler& operator=(const TerrainTiler&) = delete;

    const orbis::GeodeticExtent& footprint() const noexcept;
    std::uint32_t levelCount() const noexcept;
    /// The simplification tolerance of a level (quantized-mesh), metres.
    double tolerance(std::uint32_t level) const noexcept;

    /// Cuts the tiles, then writes layer.json from every column's errors on disk. Throws
    /// orbis::Error naming the tile or file for the first failure (the others stop).
    TerrainTilerSummary run();

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
};

} // namespace orbis::world
