#pragma once

// One DEM that GDAL reads, sampled at longitudes and latitudes: the GDAL terrain source and the
// terrain tiler. Private to orbis::world.

#include "GdalSupport.h"

#include <orbis/core/Geodetic.h>
#include <orbis/core/GeodeticExtent.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

class OGRCoordinateTransformation;

namespace orbis::world::detail {

/// A DEM's band 1 in memory (raw values, row by row from the top), read once by the first reader
/// that needs it and then shared by all: GDAL's block cache locks on every read, and threads
/// reading one DEM through it spent a third more CPU per tile than one thread did.
struct DemPixels {
    std::once_flag read;
    std::vector<float> values;
};

/// What is known about a DEM once opened; shared by the readers of every thread.
struct DemDescription {
    /// DEMs of at most this many pixels (256 MiB as floats) are read into memory whole.
    static constexpr std::size_t kInMemoryPixels = std::size_t{64} << 20;

    std::filesystem::path path;
    std::string name;              ///< the path, cut for messages
    int width = 0;
    int height = 0;
    double transform[6] = {};      ///< pixel corner (column, row) to the CRS
    double inverse[6] = {};        ///< the CRS to pixel corner coordinates
    std::string wkt;
    /// The CRS is WGS84 longitude and latitude (degrees): pixels map to them without PROJ.
    bool geographic = false;
    RasterFootprint footprint;
    std::optional<double> noData;
    double scale = 1.0;
    double offset = 0.0;
    /// For DEMs of at most kInMemoryPixels; null for larger ones, read window by window.
    std::shared_ptr<DemPixels> pixels;
};

/// Opens the DEM once to describe it (band 1). Throws orbis::Error naming it for a file GDAL cannot
/// read, one without georeferencing, or a CRS that does not transform to longitude and latitude.
std::shared_ptr<const DemDescription> describeDem(const std::filesystem::path& path);

/// One thread's reader of a DEM (GDAL datasets are not shared between threads).
class DemReader {
public:
    explicit DemReader(std::shared_ptr<const DemDescription> description);
    ~DemReader();
    DemReader(const DemReader&) = delete;
    DemReader& operator=(const DemReader&) = delete;

    const DemDescription& description() const noexcept { return *_description; }

    /// Heights (scaled, offset) at the points: bilinear between the four pixel centres around
    /// each, over those with data (weights renormalised); NaN where none has. Points within half a
    /// pixel outside the raster take its edge pixels; farther out they have no data. A function of
    /// the point alone: the same point gives the same height whatever else is asked with it.
    /// Throws orbis::Error naming the DEM when GDAL fails to read it.
    void sample(std::span<const orbis::Geodetic2D> points, std::span<float> heights);

    /// Calls visit(longitude, latitude, height) (radians, metres) for every pixel with data whose
    /// centre lies in the extent (its boundary included), row by row.
    void forEachPixel(const orbis::GeodeticExtent& extent, const std::function<void(double, double, float)>& visit);

private:
    /// Pixel-centre coordinates (column, row) of points; NaN where the CRS cannot take them.
    void toPixels(std::span<const orbis::Geodetic2D> points, std::vector<double>& columns, std::vector<double>& rows);
    /// Reads columns x0..x0+w-1 (wrapped for a raster that goes round the globe) and rows y0..y0+h-1.
    void read(int x0, int y0, int w, int h, std::vector<float>& values);
    bool hasData(float raw) const noexcept;

    std::shared_ptr<const DemDescription> _description;
    Dataset _dataset;
    void* _band = nullptr;
    std::unique_ptr<OGRCoordinateTransformation> _toSource;
    std::unique_ptr<OGRCoordinateTransformation> _toGeographic;
    std::vector<float> _window;
};

} // namespace orbis::world::detail
