#include "GdalSupport.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <mutex>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace orbis::world::detail {

void prepareGdal()
{
    static std::once_flag registered;
    std::call_once(registered, [] { GDALAllRegister(); });
    CPLSetThreadLocalConfigOption("GDAL_ERROR_ON_LIBJPEG_WARNING", "TRUE");
}

QuietGdal::QuietGdal()
{
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
}

QuietGdal::~QuietGdal()
{
    CPLPopErrorHandler();
}

std::string gdalMessage()
{
    const char* message = CPLGetLastErrorMsg();
    return message && *message ? cutForMessage(message) : std::string("GDAL gave no reason");
}

void DatasetCloser::operator()(void* dataset) const noexcept
{
    if (dataset) {
        GDALClose(dataset);
    }
}

void checkInputFile(const std::filesystem::path& path, std::string_view kind)
{
    const std::string where = cutForMessage(path.string());
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        throw Error(where + ": cannot open the " + std::string(kind) + ": " + std::strerror(errno));
    }
    struct stat status {};
    const bool regular = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode);
    ::close(fd);
    if (!regular) {
        throw Error(where + ": the " + std::string(kind) + " is not a regular file");
    }
}

Dataset openRaster(const std::filesystem::path& path, std::string_view kind)
{
    prepareGdal();
    const QuietGdal quiet;
    Dataset dataset(GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!dataset) {
        throw Error(cutForMessage(path.string()) + ": GDAL cannot read the " + std::string(kind) + ": " + gdalMessage());
    }
    return dataset;
}

OGRSpatialReference geographicReference()
{
    OGRSpatialReference reference;
    reference.SetWellKnownGeogCS("WGS84");
    reference.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    return reference;
}

RasterFootprint rasterFootprint(int width, int height, const double transform[6], const OGRSpatialReference& sourceReference,
                                const std::string& where)
{
    OGRSpatialReference reference = sourceReference;
    reference.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    const OGRSpatialReference geographic = geographicReference();
    std::unique_ptr<OGRCoordinateTransformation> toGeographic(OGRCreateCoordinateTransformation(&reference, &geographic));
    if (!toGeographic) {
        throw Error(where + ": cannot transform the coordinate reference system to longitude and latitude: " +
                    gdalMessage());
    }
    auto toLongitudeLatitude = [&](double column, double row, double& longitude, double& latitude) {
        double x = transform[0] + column * transform[1] + row * transform[2];
        double y = transform[3] + column * transform[4] + row * transform[5];
        if (!toGeographic->Transform(1, &x, &y) || !std::isfinite(x) || !std::isfinite(y)) {
            return false;
        }
        longitude = x;
        latitude = y;
        return true;
    };
    // The raster's edges and a grid inside it, taken to longitude and latitude.
    constexpr int kSamples = 64;
    std::vector<double> longitudes;
    double south = 90.0;
    double north = -90.0;
    for (int i = 0; i <= kSamples; ++i) {
        for (int j = 0; j <= kSamples; ++j) {
            double longitude = 0.0;
            double latitude = 0.0;
            if (toLongitudeLatitude(width * double(i) / kSamples, height * double(j) / kSamples, longitude, latitude)) {
                longitudes.push_back(longitude);
                south = std::min(south, latitude);
                north = std::max(north, latitude);
            }
        }
    }
    if (longitudes.empty() || !(south < north)) {
        throw Error(where + ": the raster's corners do not transform to an area of the globe");
    }
    RasterFootprint footprint;
    const double west = *std::min_element(longitudes.begin(), longitudes.end());
    const double east = *std::max_element(longitudes.begin(), longitudes.end());
    // Whole turns of longitude: a geographic raster given 0..360 (or -180..180) all the way round.
    double columnDegrees = std::abs(transform[1]);
    if (reference.IsGeographic() && transform[2] == 0.0 && transform[4] == 0.0 &&
        std::abs(columnDegrees * width - 360.0) <= 1.5 * columnDegrees) {
        footprint.extent = {-kPi, toRadians(std::max(south, -90.0)), kPi, toRadians(std::min(north, 90.0))};
        footprint.wrapsLongitude = std::abs(columnDegrees * width - 360.0) <= 1e-6 * columnDegrees;
    } else {
        // Longitudes taken into [-180, 180); where that splits them at the antimeridian (a span
        // over 180 degrees that shrinks when the western ones move east), the extent crosses it.
        std::vector<double> wrapped(longitudes);
        for (double& longitude : wrapped) {
            longitude = std::remainder(longitude, 360.0);
            if (longitude >= 180.0) {
                longitude -= 360.0;
            }
        }
        double wrappedWest = *std::min_element(wrapped.begin(), wrapped.end());
        double wrappedEast = *std::max_element(wrapped.begin(), wrapped.end());
        if (east - west >= 360.0 - 1e-9) {
            wrappedWest = -180.0;
            wrappedEast = 180.0;
        } else if (wrappedEast - wrappedWest > 180.0) {
            double shiftedWest = 360.0;
            double shiftedEast = 0.0;
            for (const double longitude : wrapped) {
                const double shifted = longitude < 0.0 ? longitude + 360.0 : longitude;
                shiftedWest = std::min(shiftedWest, shifted);
                shiftedEast = std::max(shiftedEast, shifted);
            }
            if (shiftedEast - shiftedWest < wrappedEast - wrappedWest) {
                wrappedWest = shiftedWest;
                wrappedEast = shiftedEast > 180.0 ? shiftedEast - 360.0 : shiftedEast;
            }
        }
        footprint.extent = {toRadians(wrappedWest), toRadians(std::max(south, -90.0)), toRadians(std::min(wrappedEast, 180.0)),
                            toRadians(std::min(north, 90.0))};
        if (footprint.extent.west == footprint.extent.east) {
            throw Error(where + ": the raster has no width on the globe");
        }
    }
    // The smaller side of a pixel at the centre, in degrees.
    const double centreColumn = width / 2.0;
    const double centreRow = height / 2.0;
    double longitude0 = 0.0, latitude0 = 0.0, longitude1 = 0.0, latitude1 = 0.0, longitude2 = 0.0, latitude2 = 0.0;
    if (!toLongitudeLatitude(centreColumn, centreRow, longitude0, latitude0) ||
        !toLongitudeLatitude(centreColumn + 1.0, centreRow, longitude1, latitude1) ||
        !toLongitudeLatitude(centreColumn, centreRow + 1.0, longitude2, latitude2)) {
        throw Error(where + ": the centre of the raster does not transform to longitude and latitude");
    }
    footprint.degreesPerPixel = std::min(std::hypot(longitude1 - longitude0, latitude1 - latitude0),
                                         std::hypot(longitude2 - longitude0, latitude2 - latitude0));
    if (!(footprint.degreesPerPixel > 0.0)) {
        throw Error(where + ": the raster's pixels have no size on the globe");
    }
    return footprint;
}

} // namespace orbis::world::detail
