#pragma once

// What the GDAL readers (the imagery and terrain tilers, the DEM terrain source) share: driver
// registration, quiet error handling, datasets closed on scope exit, inputs checked before GDAL
// opens them, and where a raster lies on the globe. Private to orbis::world.

#include <orbis/core/GeodeticExtent.h>

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

class OGRSpatialReference;

namespace orbis::world::detail {

/// Registers GDAL's drivers once, and on the calling thread makes a libjpeg warning (a truncated
/// or damaged JPEG, which GDAL would otherwise fill with grey) an error.
void prepareGdal();

/// GDAL's messages go to the error we throw, not to stderr, on this thread while this lives.
class QuietGdal {
public:
    QuietGdal();
    ~QuietGdal();
    QuietGdal(const QuietGdal&) = delete;
    QuietGdal& operator=(const QuietGdal&) = delete;
};

/// GDAL's last message on this thread, cut for a message.
std::string gdalMessage();

struct DatasetCloser {
    void operator()(void* dataset) const noexcept;
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

/// Refuses anything but a regular file before GDAL opens it (GDAL would block on a named pipe).
/// `kind` names the file in messages ("input image", "DEM").
void checkInputFile(const std::filesystem::path& path, std::string_view kind);

/// Opens a raster read-only; throws naming the path and `kind` when GDAL cannot.
Dataset openRaster(const std::filesystem::path& path, std::string_view kind);

/// The WGS84 longitude-latitude CRS, longitude first as geotransforms have it.
OGRSpatialReference geographicReference();

/// Where a raster lies: its longitude-latitude rectangle (crossing the antimeridian when its
/// longitudes do, the whole globe when they go all the way round) and the smaller side of a pixel
/// at its centre, in degrees.
struct RasterFootprint {
    orbis::GeodeticExtent extent;
    double degreesPerPixel = 0.0;
    /// A geographic raster whose columns go once round the globe: column `width` is column 0.
    bool wrapsLongitude = false;
};

/// The footprint of a width x height raster with the geotransform, in `reference` (a CRS PROJ
/// can take to WGS84 longitude and latitude). Throws naming `where` when it does not transform.
RasterFootprint rasterFootprint(int width, int height, const double transform[6], const OGRSpatialReference& reference,
                                const std::string& where);

} // namespace orbis::world::detail
