#include "DemRaster.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <gdal.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::world::detail {

namespace {

/// The most pixels read at once: a window for one tile's samples, a strip of rows for forEachPixel.
constexpr std::size_t kMaximumWindowPixels = std::size_t{16} << 20;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// x taken into [start, start + 360).
double wrapInto(double x, double start) noexcept
{
    const double turns = std::floor((x - start) / 360.0);
    return x - 360.0 * turns;
}

} // namespace

std::shared_ptr<const DemDescription> describeDem(const std::filesystem::path& path)
{
    auto description = std::make_shared<DemDescription>();
    description->path = path;
    description->name = cutForMessage(path.string());
    const std::string& where = description->name;
    checkInputFile(path, "DEM");
    Dataset dataset = openRaster(path, "DEM");
    const QuietGdal quiet;
    description->width = GDALGetRasterXSize(dataset.get());
    description->height = GDALGetRasterYSize(dataset.get());
    if (description->width <= 0 || description->height <= 0 || GDALGetRasterCount(dataset.get()) < 1) {
        throw Error(where + ": the DEM has no raster pixels");
    }
    GDALRasterBandH band = GDALGetRasterBand(dataset.get(), 1);
    if (GDALDataTypeIsComplex(GDALGetRasterDataType(band))) {
        throw Error(where + ": the DEM's band 1 holds complex numbers, not heights");
    }
    const bool hasTransform = GDALGetGeoTransform(dataset.get(), description->transform) == CE_None;
    const OGRSpatialReferenceH handle = GDALGetSpatialRef(dataset.get());
    if (!hasTransform || !handle) {
        throw Error(where + ": the DEM is not georeferenced (no " + (hasTransform ? "coordinate reference system" : "geotransform") +
                    "); give it one, e.g. with a VRT or gdal_edit.py -a_srs EPSG:4326 -a_ullr west north east south");
    }
    if (!GDALInvGeoTransform(description->transform, description->inverse)) {
        throw Error(where + ": the DEM's geotransform cannot be inverted");
    }
    OGRSpatialReference reference = *OGRSpatialReference::FromHandle(handle);
    reference.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    char* wkt = nullptr;
    reference.exportToWkt(&wkt);
    description->wkt = wkt ? wkt : "";
    CPLFree(wkt);
    const OGRSpatialReference wgs84 = geographicReference();
    description->geographic = reference.IsGeographic() && reference.IsSameGeogCS(&wgs84) &&
                              reference.GetAngularUnits(nullptr) == wgs84.GetAngularUnits(nullptr);
    description->footprint =
        rasterFootprint(description->width, description->height, description->transform, reference, where);
    int hasNoData = 0;
    const double noData = GDALGetRasterNoDataValue(band, &hasNoData);
    if (hasNoData && !std::isnan(noData)) {
        description->noData = noData;
    }
    int hasScale = 0;
    int hasOffset = 0;
    const double scale = GDALGetRasterScale(band, &hasScale);
    const double offset = GDALGetRasterOffset(band, &hasOffset);
    description->scale = hasScale && std::isfinite(scale) && scale != 0.0 ? scale : 1.0;
    description->offset = hasOffset && std::isfinite(offset) ? offset : 0.0;
    if (static_cast<std::size_t>(description->width) * static_cast<std::size_t>(description->height) <=
        DemDescription::kInMemoryPixels) {
        description->pixels = std::make_shared<DemPixels>();
    }
    return description;
}

DemReader::DemReader(std::shared_ptr<const DemDescription> description) : _description(std::move(description))
{
    _dataset = openRaster(_description->path, "DEM");
    _band = GDALGetRasterBand(_dataset.get(), 1);
    if (!_description->geographic) {
        OGRSpatialReference reference;
        reference.importFromWkt(_description->wkt.c_str());
        reference.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        const OGRSpatialReference geographic = geographicReference();
        _toSource.reset(OGRCreateCoordinateTransformation(&geographic, &reference));
        _toGeographic.reset(OGRCreateCoordinateTransformation(&reference, &geographic));
        if (!_toSource || !_toGeographic) {
            throw Error(_description->name + ": cannot transform between the DEM's CRS and longitude and latitude: " +
                        gdalMessage());
        }
    }
}

DemReader::~DemReader() = default;

bool DemReader::hasData(float raw) const noexcept
{
    return std::isfinite(raw) && !(_description->noData && raw == static_cast<float>(*_description->noData));
}

void DemReader::toPixels(std::span<const Geodetic2D> points, std::vector<double>& columns, std::vector<double>& rows)
{
    const DemDescription& d = *_description;
    const std::size_t count = points.size();
    columns.resize(count);
    rows.resize(count);
    std::vector<double> xs(count), ys(count);
    for (std::size_t i = 0; i < count; ++i) {
        xs[i] = toDegrees(points[i].longitude);
        ys[i] = toDegrees(points[i].latitude);
    }
    if (d.geographic) {
        // The longitude a turn away that lies in the raster's own range (0..360 rasters), or
        // nearest to it: points off the raster stay off it, on the side they are.
        const double west = std::min(d.transform[0], d.transform[0] + d.width * d.transform[1]);
        const double east = std::max(d.transform[0], d.transform[0] + d.width * d.transform[1]);
        for (double& x : xs) {
            const double wrapped = wrapInto(x, west);
            if (d.footprint.wrapsLongitude || wrapped <= east) {
                x = wrapped;
            } else if (wrapped - east > west + 360.0 - wrapped) {
                x = wrapped - 360.0; // nearer the west edge, west of it
            } else {
                x = wrapped; // nearer the east edge, east of it
            }
        }
    } else {
        // Points outside the CRS's domain fail one by one (NaN below), without PROJ's messages.
        const QuietGdal quiet;
        std::vector<int> success(count, 0);
        if (count > 0 && !_toSource->Transform(static_cast<int>(count), xs.data(), ys.data(), nullptr, success.data())) {
            std::fill(success.begin(), success.end(), 0);
        }
        for (std::size_t i = 0; i < count; ++i) {
            if (!success[i]) {
                xs[i] = std::numeric_limits<double>::quiet_NaN();
            }
        }
    }
    for (std::size_t i = 0; i < count; ++i) {
        const double* g = d.inverse;
        columns[i] = g[0] + xs[i] * g[1] + ys[i] * g[2] - 0.5;
        rows[i] = g[3] + xs[i] * g[4] + ys[i] * g[5] - 0.5;
    }
}

void DemReader::read(int x0, int y0, int w, int h, std::vector<float>& values)
{
    const DemDescription& d = *_description;
    values.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    const QuietGdal quiet;
    auto readBand = [&](int x, int y, int width, int height, float* out, std::size_t rowStride) {
        if (GDALRasterIOEx(_band, GF_Read, x, y, width, height, out, width, height, GDT_Float32, sizeof(float),
                           static_cast<GSpacing>(sizeof(float) * rowStride), nullptr) != CE_None) {
            throw Error(d.name + ": cannot read the DEM's pixels: " + gdalMessage());
        }
    };
    if (d.pixels) {
        std::call_once(d.pixels->read, [&] {
            d.pixels->values.resize(static_cast<std::size_t>(d.width) * static_cast<std::size_t>(d.height));
            readBand(0, 0, d.width, d.height, d.pixels->values.data(), static_cast<std::size_t>(d.width));
        });
    }
    // Columns beyond the raster's east edge wrap to its west edge (rasters round the globe).
    int column = x0;
    int done = 0;
    while (done < w) {
        const int start = ((column % d.width) + d.width) % d.width;
        const int run = std::min(w - done, d.width - start);
        if (d.pixels) {
            for (int row = 0; row < h; ++row) {
                const float* from = &d.pixels->values[static_cast<std::size_t>(y0 + row) * static_cast<std::size_t>(d.width) +
                                                      static_cast<std::size_t>(start)];
                std::copy_n(from, run, &values[static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(done)]);
            }
        } else {
            readBand(start, y0, run, h, values.data() + done, static_cast<std::size_t>(w));
        }
        done += run;
        column += run;
    }
}

void DemReader::sample(std::span<const Geodetic2D> points, std::span<float> heights)
{
    const DemDescription& d = *_description;
    std::vector<double> columns;
    std::vector<double> rows;
    toPixels(points, columns, rows);
    const bool wraps = d.footprint.wrapsLongitude;
    // The pixel column of a neighbour (unwrapped where the raster wraps), or false where the
    // point is off the raster: within half a pixel of its edge the edge pixels stand in.
    auto pixelOf = [&](double neighbour, double position, int size, bool wrap, int& index) {
        if (wrap) {
            index = static_cast<int>(neighbour);
            return true;
        }
        if (!(position >= -0.5 && position <= size - 0.5)) {
            return false;
        }
        index = std::clamp(static_cast<int>(neighbour), 0, size - 1);
        return true;
    };
    auto rowOf = [&](double neighbour, double position, int size, int& index) {
        return pixelOf(neighbour, position, size, false, index);
    };
    // The window that holds every neighbour, in unwrapped columns.
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    double top = low;
    double bottom = -low;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (std::isfinite(columns[i]) && std::isfinite(rows[i])) {
            low = std::min(low, columns[i]);
            high = std::max(high, columns[i]);
            top = std::min(top, rows[i]);
            bottom = std::max(bottom, rows[i]);
        }
    }
    std::fill(heights.begin(), heights.end(), kNaN);
    if (!(low <= high)) {
        return;
    }
    // Columns are unwrapped here: -1 and width are the raster's last and first columns again
    // when it goes round the globe (read() wraps them).
    int x0 = static_cast<int>(std::floor(low));
    int x1 = static_cast<int>(std::floor(high)) + 1;
    if (!wraps) {
        x0 = std::clamp(x0, 0, d.width - 1);
        x1 = std::clamp(x1, 0, d.width - 1);
    }
    const int y0 = std::clamp(static_cast<int>(std::floor(top)), 0, d.height - 1);
    const int y1 = std::clamp(static_cast<int>(std::floor(bottom)) + 1, 0, d.height - 1);
    const int windowWidth = x1 - x0 + 1;
    const bool windowed =
        static_cast<std::size_t>(windowWidth) * static_cast<std::size_t>(y1 - y0 + 1) <= kMaximumWindowPixels;
    if (windowed) {
        read(x0, y0, windowWidth, y1 - y0 + 1, _window);
    }
    std::vector<float> single;
    auto value = [&](int column, int row) -> float {
        if (!windowed) {
            read(column, row, 1, 1, single); // a window too large to hold: pixel by pixel
            return single[0];
        }
        return _window[static_cast<std::size_t>(row - y0) * static_cast<std::size_t>(windowWidth) +
                       static_cast<std::size_t>(column - x0)];
    };
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double column = columns[i];
        const double row = rows[i];
        if (!std::isfinite(column) || !std::isfinite(row)) {
            continue;
        }
        const double c0 = std::floor(column);
        const double r0 = std::floor(row);
        const double fx = column - c0;
        const double fy = row - r0;
        double sum = 0.0;
        double weights = 0.0;
        for (int corner = 0; corner < 4; ++corner) {
            const int dx = corner & 1;
            const int dy = corner >> 1;
            const double weight = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
            int pixelColumn = 0;
            int pixelRow = 0;
            if (weight <= 0.0 || !pixelOf(c0 + dx, column, d.width, wraps, pixelColumn) ||
                !rowOf(r0 + dy, row, d.height, pixelRow)) {
                continue;
            }
            const float raw = value(pixelColumn, pixelRow);
            if (hasData(raw)) {
                sum += weight * static_cast<double>(raw);
                weights += weight;
            }
        }
        if (weights > 0.0) {
            heights[i] = static_cast<float>((sum / weights) * d.scale + d.offset);
        }
    }
}

void DemReader::forEachPixel(const GeodeticExtent& extent, const std::function<void(double, double, float)>& visit)
{
    const DemDescription& d = *_description;
    // The pixel window: the extent's outline and a grid inside it taken to pixel coordinates.
    constexpr int kOutline = 32;
    std::vector<Geodetic2D> outline;
    for (int i = 0; i <= kOutline; ++i) {
        for (int j = 0; j <= kOutline; ++j) {
            outline.push_back({extent.west + (extent.east - extent.west) * i / kOutline,
                               extent.south + (extent.north - extent.south) * j / kOutline});
        }
    }
    std::vector<double> columns;
    std::vector<double> rows;
    toPixels(outline, columns, rows);
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    double top = low;
    double bottom = -low;
    for (std::size_t i = 0; i < outline.size(); ++i) {
        if (std::isfinite(columns[i]) && std::isfinite(rows[i])) {
            low = std::min(low, columns[i]);
            high = std::max(high, columns[i]);
            top = std::min(top, rows[i]);
            bottom = std::max(bottom, rows[i]);
        }
    }
    if (!(low <= high)) {
        return;
    }
    const bool wraps = d.footprint.wrapsLongitude;
    // A margin of two pixels: the outline's grid may miss a bulge of a projected extent.
    const int margin = d.geographic ? 1 : 2;
    int x0 = static_cast<int>(std::floor(low)) - margin;
    int x1 = static_cast<int>(std::ceil(high)) + margin;
    if (wraps) {
        if (x1 - x0 + 1 > d.width) {
            x0 = 0;
            x1 = d.width - 1;
        }
    } else {
        x0 = std::max(x0, 0);
        x1 = std::min(x1, d.width - 1);
    }
    const int y0 = std::max(static_cast<int>(std::floor(top)) - margin, 0);
    const int y1 = std::min(static_cast<int>(std::ceil(bottom)) + margin, d.height - 1);
    if (x0 > x1 || y0 > y1) {
        return;
    }
    const int width = x1 - x0 + 1;
    const int stripRows = std::max(1, static_cast<int>(kMaximumWindowPixels / static_cast<std::size_t>(width)));
    std::vector<float> strip;
    std::vector<double> xs(static_cast<std::size_t>(width));
    std::vector<double> ys(static_cast<std::size_t>(width));
    std::vector<int> success(static_cast<std::size_t>(width));
    auto inside = [&](double& longitude, double latitude) {
        if (latitude < extent.south || latitude > extent.north) {
            return false;
        }
        for (const double shift : {0.0, -kTwoPi, kTwoPi}) {
            if (longitude + shift >= extent.west && longitude + shift <= extent.east) {
                longitude += shift;
                return true;
            }
        }
        return false;
    };
    const QuietGdal quiet; // pixels outside the geographic domain are skipped, not reported
    for (int rowStart = y0; rowStart <= y1; rowStart += stripRows) {
        const int rowCount = std::min(stripRows, y1 - rowStart + 1);
        read(x0, rowStart, width, rowCount, strip);
        for (int r = 0; r < rowCount; ++r) {
            const double row = rowStart + r + 0.5;
            for (int c = 0; c < width; ++c) {
                const double column = x0 + c + 0.5;
                xs[static_cast<std::size_t>(c)] = d.transform[0] + column * d.transform[1] + row * d.transform[2];
                ys[static_cast<std::size_t>(c)] = d.transform[3] + column * d.transform[4] + row * d.transform[5];
                success[static_cast<std::size_t>(c)] = 1;
            }
            if (!d.geographic &&
                !_toGeographic->Transform(width, xs.data(), ys.data(), nullptr, success.data())) {
                std::fill(success.begin(), success.end(), 0);
            }
            const float* values = strip.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(width);
            for (int c = 0; c < width; ++c) {
                const auto index = static_cast<std::size_t>(c);
                if (!success[index] || !hasData(values[c])) {
                    continue;
                }
                double longitude = toRadians(xs[index]);
                const double latitude = toRadians(ys[index]);
                if (std::isfinite(longitude) && std::isfinite(latitude) && inside(longitude, latitude)) {
                    visit(longitude, latitude, static_cast<float>(static_cast<double>(values[c]) * d.scale + d.offset));
                }
            }
        }
    }
}

} // namespace orbis::world::detail
