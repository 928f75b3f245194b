#pragma once

#include "orbis/world/ImageCodec.h"

#include <orbis/core/GeodeticExtent.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace orbis::world {

/// Where a tiling run stands, given to ImageryTilerOptions::progress after each tile.
struct TilerProgress {
    std::uint32_t level = 0;     ///< the level being cut
    std::size_t levelDone = 0;   ///< tiles of that level done (written or found empty)
    std::size_t levelTotal = 0;
    std::size_t done = 0;        ///< tiles done in the whole run
    std::size_t total = 0;
    double seconds = 0.0;        ///< since the run started
};

struct ImageryTilerOptions {
    /// Anything GDAL reads (GeoTIFF, JPEG, PNG, ...), georeferenced in any CRS GDAL knows; an image
    /// without georeferencing is taken as the whole globe, plate carree, north up.
    std::filesystem::path input;
    /// The TMS folder written: LEVEL/X/Y.EXT and tilemapresource.xml.
    std::filesystem::path output;
    /// Levels 0 to levels - 1; empty: down to the first level whose pixels are no coarser than the
    /// input's (the smaller side of an input pixel, in degrees, at the centre of its footprint).
    std::optional<std::uint32_t> levels;
    ImageFormat format = ImageFormat::Jpeg;
    /// JPEG and WebP quality (1..100) or PNG's zlib level (0..9); empty: 90, 90, 6.
    std::optional<int> quality;
    /// Cut only this level: the deepest from the input, a shallower one from the level below it,
    /// which must be on disk already (cut earlier, by this machine or another).
    std::optional<std::uint32_t> onlyLevel;
    /// With onlyLevel: only columns first..last (inclusive) of that level, for splitting a level
    /// across machines. Jobs that split a level the same way write the same files.
    std::optional<std::pair<std::uint32_t, std::uint32_t>> columns;
    /// Worker threads; 0: one per hardware thread.
    int threads = 0;
    int tileSize = 256;
    std::string title;       ///< for tilemapresource.xml; empty: the input's file name
    std::string attribution; ///< written into tilemapresource.xml
    std::function<void(const TilerProgress&)> progress;
};

struct TilerSummary {
    std::size_t tilesWritten = 0;
    std::size_t tilesEmpty = 0;  ///< inside the footprint's rectangle but without a pixel of the input
    std::uint32_t levelCount = 0;
    double seconds = 0.0;
};

/// Cuts a large image into a TMS pyramid in the geographic scheme (EPSG:4326, two root tiles,
/// rows from the south), as data/imagery holds and openTileSource reads. The deepest level is
/// warped from the input (GDAL, reprojected from its CRS, bilinear, or averaged where the input is
/// finer than the tile); each level above is made from the four tiles below it (averaged, weighted
/// by alpha). Tiles outside the input are not written; tiles at its edge are transparent (PNG,
/// WebP) or black (JPEG) beyond it. Each tile file appears whole or not at all.
///
/// ```
/// ImageryTilerOptions options;
/// options.input = "bluemarble.jpg";
/// options.output = "data/imagery/BlueMarble";
/// options.levels = 5;
/// ImageryTiler(options).run();
/// ```
class ImageryTiler {
public:
    /// Opens the input and checks the options. Throws orbis::Error naming the input for a file GDAL
    /// cannot read, a CRS it cannot transform to longitude and latitude, bands it cannot make
    /// colours of, or options that do not fit (a level beyond the pyramid, columns outside it).
    explicit ImageryTiler(ImageryTilerOptions options);
    ~ImageryTiler();
    ImageryTiler(const ImageryTiler&) = delete;
    ImageryTiler& operator=(const ImageryTiler&) = delete;

    /// Where the input lies, longitude and latitude in radians.
    const orbis::GeodeticExtent& footprint() const noexcept;
    /// Levels of the pyramid (0 to levelCount() - 1).
    std::uint32_t levelCount() const noexcept;

    /// Cuts the tiles the options ask for, on the worker threads, then writes tilemapresource.xml.
    /// Throws orbis::Error naming the tile or file for the first failure (the other workers stop;
    /// tiles already written stay, each whole).
    TilerSummary run();

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
};

/// The smallest level of the geographic scheme whose tiles of `tileSize` pixels have pixels no
/// larger than `degreesPerPixel` (at most kMaximumTileLevel).
std::uint32_t geographicLevelForResolution(double degreesPerPixel, int tileSize) noexcept;

} // namespace orbis::world
