#include "orbis/world/ImageryTiler.h"

#include "GdalSupport.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/TileMapResource.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdal_utils.h>
#include <gdalwarper.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace orbis::world {

namespace {

using Clock = std::chrono::steady_clock;

using detail::checkInputFile;
using detail::Dataset;
using detail::gdalMessage;
using detail::geographicReference;
using detail::prepareGdal;
using detail::QuietGdal;

/// An argument list for GDAL's utilities (a NULL-terminated char** owned here).
class ArgumentList {
public:
    explicit ArgumentList(const std::vector<std::string>& arguments)
    {
        for (const std::string& argument : arguments) {
            _list = CSLAddString(_list, argument.c_str());
        }
    }
    ~ArgumentList() { CSLDestroy(_list); }
    ArgumentList(const ArgumentList&) = delete;
    ArgumentList& operator=(const ArgumentList&) = delete;
    char** get() const noexcept { return _list; }

private:
    char** _list = nullptr;
};

/// How the input is turned into 8-bit colours (GDALTranslate to an in-memory VRT) and which of
/// its bands the warper reads. Found once, applied by each worker to its own datasets.
struct InputPlan {
    std::vector<std::string> translate = {"-of", "VRT"};
    std::vector<int> colourBands;   ///< three band numbers (grey repeats band 1)
    int alphaBand = 0;              ///< 0: none
    std::vector<double> noData;     ///< per colour band; NaN where none
    int width = 0;
    int height = 0;
    bool georeferenced = true;
    GeodeticExtent footprint;
    double degreesPerPixel = 0.0;
    /// The colours (and alpha) decoded once, pixel-interleaved, when they fit in
    /// kMaximumInMemoryBytes: every worker then warps from this memory, so the input is decoded
    /// once, and no tile can depend on the order tiles were cut in (as a JPEG re-read from its
    /// middle can). Empty: each worker reads the file itself (large tiled GeoTIFFs, made for that).
    std::shared_ptr<const std::vector<std::uint8_t>> pixels;
    int pixelBands = 0;
    double transform[6] = {};
    std::string wkt;
};

/// The most input pixels (bytes of 8-bit bands) kept in memory: 2 GiB, a 32768 x 21845 RGB image.
constexpr std::size_t kMaximumInMemoryBytes = std::size_t{2} << 30;

Dataset openSource(const std::filesystem::path& path)
{
    return detail::openRaster(path, "input image");
}

Dataset prepare(void* source, const InputPlan& plan, const std::filesystem::path& path)
{
    const QuietGdal quiet;
    ArgumentList arguments(plan.translate);
    GDALTranslateOptions* options = GDALTranslateOptionsNew(arguments.get(), nullptr);
    if (!options) {
        throw Error(cutForMessage(path.string()) + ": cannot set up the conversion to 8-bit colours: " + gdalMessage());
    }
    int usageError = 0;
    Dataset prepared(GDALTranslate("", source, options, &usageError));
    GDALTranslateOptionsFree(options);
    if (!prepared) {
        throw Error(cutForMessage(path.string()) + ": cannot convert the input to 8-bit colours: " + gdalMessage());
    }
    return prepared;
}

/// The input's band layout, scaling and footprint, or an error saying what cannot be tiled.
InputPlan planInput(const std::filesystem::path& path)
{
    const std::string where = cutForMessage(path.string());
    InputPlan plan;
    Dataset source = openSource(path);
    const QuietGdal quiet;
    plan.width = GDALGetRasterXSize(source.get());
    plan.height = GDALGetRasterYSize(source.get());
    const int bands = GDALGetRasterCount(source.get());
    if (plan.width <= 0 || plan.height <= 0 || bands <= 0) {
        throw Error(where + ": the input has no raster pixels");
    }
    double transform[6] = {};
    const bool hasTransform = GDALGetGeoTransform(source.get(), transform) == CE_None;
    OGRSpatialReference reference;
    if (const OGRSpatialReferenceH sourceReference = GDALGetSpatialRef(source.get())) {
        reference = *OGRSpatialReference::FromHandle(sourceReference);
    }
    plan.georeferenced = hasTransform && !reference.IsEmpty();
    if (!plan.georeferenced) {
        if (hasTransform) {
            throw Error(where + ": the input has a geotransform but no coordinate reference system (add one, e.g. "
                                "gdal_edit.py -a_srs EPSG:4326)");
        }
        // A plain image: the whole globe, plate carree, north up.
        plan.translate.insert(plan.translate.end(), {"-a_srs", "EPSG:4326", "-a_ullr", "-180", "90", "180", "-90"});
        transform[0] = -180.0;
        transform[1] = 360.0 / plan.width;
        transform[2] = 0.0;
        transform[3] = 90.0;
        transform[4] = 0.0;
        transform[5] = -180.0 / plan.height;
        reference = geographicReference();
    }

    GDALRasterBandH first = GDALGetRasterBand(source.get(), 1);
    if (GDALGetRasterColorInterpretation(first) == GCI_PaletteIndex) {
        plan.translate.insert(plan.translate.end(), {"-expand", "rgba"});
    } else {
        bool eightBit = true;
        for (int band = 1; band <= std::min(bands, 3); ++band) {
            eightBit = eightBit && GDALGetRasterDataType(GDALGetRasterBand(source.get(), band)) == GDT_Byte;
        }
        if (!eightBit) {
            // Scaled linearly from the colour bands' range (approximate: GDAL may sample it).
            double minimum = std::numeric_limits<double>::infinity();
            double maximum = -minimum;
            for (int band = 1; band <= std::min(bands, 3); ++band) {
                double range[2] = {};
                if (GDALComputeRasterMinMax(GDALGetRasterBand(source.get(), band), TRUE, range) == CE_None) {
                    minimum = std::min(minimum, range[0]);
                    maximum = std::max(maximum, range[1]);
                }
            }
            if (!std::isfinite(minimum) || !std::isfinite(maximum)) {
                throw Error(where + ": cannot find the range of the input's values to scale them to 8 bits: " + gdalMessage());
            }
            maximum = std::max(maximum, minimum + 1.0);
            plan.translate.insert(plan.translate.end(),
                                  {"-ot", "Byte", "-scale", std::to_string(minimum), std::to_string(maximum), "0", "255"});
        }
    }

    Dataset prepared = prepare(source.get(), plan, path);
    const int preparedBands = GDALGetRasterCount(prepared.get());
    auto isAlpha = [&](int band) {
        return GDALGetRasterColorInterpretation(GDALGetRasterBand(prepared.get(), band)) == GCI_AlphaBand;
    };
    if (preparedBands >= 3) {
        plan.colourBands = {1, 2, 3};
        for (int band = 4; band <= preparedBands && plan.alphaBand == 0; ++band) {
            plan.alphaBand = isAlpha(band) ? band : 0;
        }
    } else {
        plan.colourBands = {1, 1, 1};
        plan.alphaBand = preparedBands == 2 && isAlpha(2) ? 2 : 0;
    }
    for (const int band : plan.colourBands) {
        int hasNoData = 0;
        const double value = GDALGetRasterNoDataValue(GDALGetRasterBand(prepared.get(), band), &hasNoData);
        plan.noData.push_back(hasNoData ? value : std::nan(""));
    }
    const detail::RasterFootprint footprint = detail::rasterFootprint(plan.width, plan.height, transform, reference, where);
    plan.footprint = footprint.extent;
    if (plan.footprint.east < plan.footprint.west) {
        // Across the antimeridian: every column of those rows (those without pixels stay empty).
        plan.footprint.west = -kPi;
        plan.footprint.east = kPi;
    }
    plan.degreesPerPixel = footprint.degreesPerPixel;
    return plan;
}

/// Decodes the input's colours (and alpha) into plan.pixels when they fit kMaximumInMemoryBytes;
/// done only by a run that cuts the deepest level, the one level made from the input.
void loadPixels(const std::filesystem::path& path, InputPlan& plan)
{
    const std::string where = cutForMessage(path.string());
    Dataset source = openSource(path);
    Dataset prepared = prepare(source.get(), plan, path);
    const QuietGdal quiet;
    std::vector<int> loaded = {plan.colourBands[0]};
    if (plan.colourBands[1] != plan.colourBands[0]) {
        loaded.insert(loaded.end(), {plan.colourBands[1], plan.colourBands[2]});
    }
    if (plan.alphaBand) {
        loaded.push_back(plan.alphaBand);
    }
    const std::size_t bytes = static_cast<std::size_t>(plan.width) * static_cast<std::size_t>(plan.height) * loaded.size();
    if (bytes > kMaximumInMemoryBytes) {
        return;
    }
    auto pixels = std::make_shared<std::vector<std::uint8_t>>(bytes);
    const int count = static_cast<int>(loaded.size());
    // The Ex form: its line spacing is 64-bit, which the plain form's int would not hold for wide inputs.
    if (GDALDatasetRasterIOEx(prepared.get(), GF_Read, 0, 0, plan.width, plan.height, pixels->data(), plan.width,
                              plan.height, GDT_Byte, count, loaded.data(), count, GSpacing{plan.width} * count, 1,
                              nullptr) != CE_None) {
        throw Error(where + ": cannot read the input's pixels: " + gdalMessage());
    }
    GDALGetGeoTransform(prepared.get(), plan.transform);
    plan.wkt = GDALGetProjectionRef(prepared.get());
    plan.pixels = std::move(pixels);
    plan.pixelBands = count;
    plan.colourBands = count >= 3 ? std::vector<int>{1, 2, 3} : std::vector<int>{1, 1, 1};
    plan.alphaBand = plan.alphaBand ? count : 0;
}

/// One worker's GDAL state: its own datasets (GDAL datasets are not shared between threads), a
/// 4-band RGBA destination in memory whose geotransform moves from tile to tile, and the warp.
class TileWarper {
public:
    TileWarper(const std::filesystem::path& path, const InputPlan& plan, int tileSize, GDALResampleAlg resampling)
        : _path(path), _tileSize(tileSize)
    {
        prepareGdal();
        if (plan.pixels) {
            _prepared = inMemory(plan);
        } else {
            _source = openSource(path);
            _prepared = prepare(_source.get(), plan, path);
        }
        const QuietGdal quiet;
        GDALDriverH memory = GDALGetDriverByName("MEM");
        const char* createOptions[] = {"INTERLEAVE=PIXEL", nullptr};
        _destination.reset(GDALCreate(memory, "", tileSize, tileSize, 4, GDT_Byte, const_cast<char**>(createOptions)));
        if (!_destination) {
            throw Error("cannot create a tile in memory: " + gdalMessage());
        }
        OGRSpatialReference geographic = geographicReference();
        GDALSetSpatialRef(_destination.get(), OGRSpatialReference::ToHandle(&geographic));
        double transform[6] = {-180.0, 1.0, 0.0, 90.0, 0.0, -1.0};
        GDALSetGeoTransform(_destination.get(), transform);
        _transformer = GDALCreateGenImgProjTransformer2(_prepared.get(), _destination.get(), nullptr);
        if (!_transformer) {
            throw Error(cutForMessage(path.string()) + ": cannot transform the input to longitude and latitude: " +
                        gdalMessage());
        }
        _options = GDALCreateWarpOptions();
        _options->hSrcDS = _prepared.get();
        _options->hDstDS = _destination.get();
        _options->nBandCount = 3;
        _options->panSrcBands = static_cast<int*>(CPLMalloc(sizeof(int) * 3));
        _options->panDstBands = static_cast<int*>(CPLMalloc(sizeof(int) * 3));
        for (int i = 0; i < 3; ++i) {
            _options->panSrcBands[i] = plan.colourBands[static_cast<std::size_t>(i)];
            _options->panDstBands[i] = i + 1;
        }
        if (std::any_of(plan.noData.begin(), plan.noData.end(), [](double v) { return !std::isnan(v); })) {
            _options->padfSrcNoDataReal = static_cast<double*>(CPLMalloc(sizeof(double) * 3));
            for (int i = 0; i < 3; ++i) {
                const double value = plan.noData[static_cast<std::size_t>(i)];
                // A band without nodata next to ones with: a value 8-bit data cannot hold.
                _options->padfSrcNoDataReal[i] = std::isnan(value) ? -1e10 : value;
            }
        }
        _options->nSrcAlphaBand = plan.alphaBand;
        _options->nDstAlphaBand = 4;
        _options->eResampleAlg = resampling;
        _options->pfnTransformer = GDALGenImgProjTransform;
        _options->pTransformerArg = _transformer;
        // Each tile starts transparent black; nothing is read back from the destination.
        _options->papszWarpOptions = CSLSetNameValue(_options->papszWarpOptions, "INIT_DEST", "0");
        _pixels.resize(static_cast<std::size_t>(tileSize) * tileSize * 4);
    }

    ~TileWarper()
    {
        if (_options) {
            _options->pTransformerArg = nullptr;
            GDALDestroyWarpOptions(_options);
        }
        if (_transformer) {
            GDALDestroyGenImgProjTransformer(_transformer);
        }
    }
    TileWarper(const TileWarper&) = delete;
    TileWarper& operator=(const TileWarper&) = delete;

    /// The tile's RGBA pixels, rows from the north; false when no pixel of the input falls in it.
    bool warp(const GeodeticExtent& extent, Image& tile, const std::string& tileName)
    {
        const QuietGdal quiet;
        const double pixelWidth = toDegrees(extent.east - extent.west) / _tileSize;
        const double pixelHeight = toDegrees(extent.north - extent.south) / _tileSize;
        double transform[6] = {toDegrees(extent.west), pixelWidth, 0.0, toDegrees(extent.north), 0.0, -pixelHeight};
        GDALSetGeoTransform(_destination.get(), transform);
        GDALSetGenImgProjTransformerDstGeoTransform(_transformer, transform);
        // A warp operation per tile: GDAL caches an operation's source window by the destination
        // window alone, which is the same for every tile here.
        GDALWarpOperation operation;
        if (operation.Initialize(_options) != CE_None ||
            operation.ChunkAndWarpImage(0, 0, _tileSize, _tileSize) != CE_None || readPixels() != CE_None) {
            throw Error(tileName + ": warping " + cutForMessage(_path.string()) + " failed: " + gdalMessage());
        }
        tile = Image(_tileSize, _tileSize, 4);
        tile.pixels = _pixels;
        for (std::size_t i = 3; i < _pixels.size(); i += 4) {
            if (_pixels[i] != 0) {
                return true;
            }
        }
        return false;
    }

private:
    /// A dataset over the plan's decoded pixels, without copying them.
    static Dataset inMemory(const InputPlan& plan)
    {
        const QuietGdal quiet;
        Dataset dataset(GDALCreate(GDALGetDriverByName("MEM"), "", plan.width, plan.height, 0, GDT_Byte, nullptr));
        if (!dataset) {
            throw Error("cannot wrap the input's pixels: " + gdalMessage());
        }
        // Read only: GDAL never writes through these bands here.
        auto* data = const_cast<std::uint8_t*>(plan.pixels->data());
        for (int band = 0; band < plan.pixelBands; ++band) {
            char pointer[64] = {};
            CPLPrintPointer(pointer, data + band, sizeof pointer - 1);
            const std::string options[] = {std::string("DATAPOINTER=") + pointer, "PIXELOFFSET=" + std::to_string(plan.pixelBands),
                                           "LINEOFFSET=" + std::to_string(std::int64_t{plan.width} * plan.pixelBands)};
            const char* list[] = {options[0].c_str(), options[1].c_str(), options[2].c_str(), nullptr};
            if (GDALAddBand(dataset.get(), GDT_Byte, const_cast<char**>(list)) != CE_None) {
                throw Error("cannot wrap the input's pixels: " + gdalMessage());
            }
        }
        for (int band = 1; band <= (plan.pixelBands >= 3 ? 3 : 1); ++band) {
            const double noData = plan.noData[static_cast<std::size_t>(band - 1)];
            if (!std::isnan(noData)) {
                GDALSetRasterNoDataValue(GDALGetRasterBand(dataset.get(), band), noData);
            }
        }
        if (plan.alphaBand) {
            GDALSetRasterColorInterpretation(GDALGetRasterBand(dataset.get(), plan.alphaBand), GCI_AlphaBand);
        }
        double transform[6];
        std::copy_n(plan.transform, 6, transform);
        GDALSetGeoTransform(dataset.get(), transform);
        GDALSetProjection(dataset.get(), plan.wkt.c_str());
        return dataset;
    }

    CPLErr readPixels()
    {
        return GDALDatasetRasterIO(_destination.get(), GF_Read, 0, 0, _tileSize, _tileSize, _pixels.data(), _tileSize,
                                   _tileSize, GDT_Byte, 4, nullptr, 4, _tileSize * 4, 1);
    }

    std::filesystem::path _path;
    int _tileSize;
    Dataset _source;
    Dataset _prepared;
    Dataset _destination;
    void* _transformer = nullptr;
    GDALWarpOptions* _options = nullptr;
    std::vector<std::uint8_t> _pixels;
};

struct TileRange {
    std::uint32_t firstX = 0, lastX = 0, firstY = 0, lastY = 0; ///< inclusive; rows from the south
    bool empty = true;

    std::size_t count() const
    {
        return empty ? 0 : std::size_t{lastX - firstX + 1} * std::size_t{lastY - firstY + 1};
    }
};

/// The tiles of `level` that the footprint touches.
TileRange tilesCovering(const GeodeticExtent& footprint, std::uint32_t level)
{
    const TilingScheme scheme = TilingScheme::geographic();
    const double span = kPi / static_cast<double>(std::uint64_t{1} << level);
    auto index = [&](double offset, std::uint32_t count, bool end) {
        const double position = offset / span;
        const double edge = end ? std::ceil(position) - 1.0 : std::floor(position);
        return static_cast<std::uint32_t>(std::clamp(edge, 0.0, static_cast<double>(count - 1)));
    };
    TileRange range;
    range.firstX = index(footprint.west + kPi, scheme.tilesX(level), false);
    range.lastX = index(footprint.east + kPi, scheme.tilesX(level), true);
    range.firstY = index(footprint.south + kHalfPi, scheme.tilesY(level), false);
    range.lastY = index(footprint.north + kHalfPi, scheme.tilesY(level), true);
    range.empty = range.firstX > range.lastX || range.firstY > range.lastY;
    return range;
}

/// A parent tile from its four children: each 2 x 2 block averaged, colours weighted by alpha.
Image downsample(const Image children[4], int tileSize)
{
    // children: 0 south-west, 1 south-east, 2 north-west, 3 north-east (TileKey::child order).
    Image parent(tileSize, tileSize, 4);
    const int half = tileSize / 2;
    for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const Image& child = children[quadrant];
        if (child.pixels.empty()) {
            continue;
        }
        const int offsetX = (quadrant & 1) * half;
        const int offsetY = (quadrant & 2) ? 0 : half; // the north children fill the top half
        for (int y = 0; y < half; ++y) {
            for (int x = 0; x < half; ++x) {
                unsigned alpha = 0;
                unsigned colour[3] = {0, 0, 0};
                for (int dy = 0; dy < 2; ++dy) {
                    for (int dx = 0; dx < 2; ++dx) {
                        const std::uint8_t* p = child.pixel(2 * x + dx, 2 * y + dy);
                        alpha += p[3];
                        for (int c = 0; c < 3; ++c) {
                            colour[c] += unsigned{p[c]} * p[3];
                        }
                    }
                }
                std::uint8_t* out = parent.pixel(offsetX + x, offsetY + y);
                for (int c = 0; c < 3; ++c) {
                    out[c] = static_cast<std::uint8_t>(alpha == 0 ? 0 : (colour[c] + alpha / 2) / alpha);
                }
                out[3] = static_cast<std::uint8_t>((alpha + 2) / 4);
            }
        }
    }
    return parent;
}

bool anyOpaque(const Image& image)
{
    for (std::size_t i = 3; i < image.pixels.size(); i += 4) {
        if (image.pixels[i] != 0) {
            return true;
        }
    }
    return false;
}

/// The tile as it is written: RGB for JPEG, and for PNG and WebP when every pixel is opaque.
Image forOutput(const Image& rgba, ImageFormat format)
{
    bool opaque = format == ImageFormat::Jpeg;
    if (!opaque) {
        opaque = true;
        for (std::size_t i = 3; i < rgba.pixels.size() && opaque; i += 4) {
            opaque = rgba.pixels[i] == 255;
        }
    }
    if (!opaque) {
        return rgba;
    }
    Image rgb(rgba.width, rgba.height, 3);
    for (std::size_t i = 0, j = 0; i < rgba.pixels.size(); i += 4, j += 3) {
        rgb.pixels[j] = rgba.pixels[i];
        rgb.pixels[j + 1] = rgba.pixels[i + 1];
        rgb.pixels[j + 2] = rgba.pixels[i + 2];
    }
    return rgb;
}

} // namespace

std::uint32_t geographicLevelForResolution(double degreesPerPixel, int tileSize) noexcept
{
    for (std::uint32_t level = 0; level < kMaximumTileLevel; ++level) {
        const double tileDegreesPerPixel = 180.0 / static_cast<double>(std::uint64_t{1} << level) / tileSize;
        if (tileDegreesPerPixel <= degreesPerPixel * (1.0 + 1e-9)) {
            return level;
        }
    }
    return kMaximumTileLevel;
}

struct ImageryTiler::Impl {
    ImageryTilerOptions options;
    InputPlan plan;
    std::uint32_t levelCount = 0;
    int quality = 90;
    std::string extension;

    std::filesystem::path tilePath(std::uint32_t level, std::uint32_t x, std::uint32_t y) const
    {
        return options.output / std::to_string(level) / std::to_string(x) / (std::to_string(y) + "." + extension);
    }
};

ImageryTiler::ImageryTiler(ImageryTilerOptions options) : _impl(std::make_unique<Impl>())
{
    Impl& impl = *_impl;
    impl.options = std::move(options);
    const ImageryTilerOptions& o = impl.options;
    const std::string where = cutForMessage(o.input.string());
    if (o.format == ImageFormat::Unknown) {
        throw Error("orbis tile: choose a tile format (jpg, png or webp)");
    }
    if (o.tileSize < 16 || o.tileSize > kMaximumTileSide || o.tileSize % 2 != 0) {
        throw Error("orbis tile: tiles of " + std::to_string(o.tileSize) + " pixels (an even number from 16 to " +
                    std::to_string(kMaximumTileSide) + ")");
    }
    if (o.columns && !o.onlyLevel) {
        throw Error("orbis tile: a range of columns needs the level it belongs to");
    }
    impl.extension = std::string(imageFormatExtension(o.format));
    impl.quality = o.quality.value_or(o.format == ImageFormat::Png ? 6 : 90);
    checkInputFile(o.input, "input image");
    prepareGdal();
    impl.plan = planInput(o.input);

    const std::uint32_t natural = geographicLevelForResolution(impl.plan.degreesPerPixel, o.tileSize);
    impl.levelCount = o.levels.value_or(natural + 1);
    if (impl.levelCount < 1 || impl.levelCount > kMaximumTileLevel + 1) {
        throw Error("orbis tile: " + std::to_string(impl.levelCount) + " levels (1 to " +
                    std::to_string(kMaximumTileLevel + 1) + ")");
    }
    const std::size_t deepestTiles = tilesCovering(impl.plan.footprint, impl.levelCount - 1).count();
    constexpr std::size_t kMaximumTiles = std::size_t{1} << 30;
    if (deepestTiles > kMaximumTiles) {
        throw Error(where + ": " + std::to_string(impl.levelCount) + " levels would cut " + std::to_string(deepestTiles) +
                    " tiles at the deepest level alone; ask for fewer levels");
    }
    if (o.onlyLevel && *o.onlyLevel >= impl.levelCount) {
        throw Error("orbis tile: level " + std::to_string(*o.onlyLevel) + " is not in the pyramid (0 to " +
                    std::to_string(impl.levelCount - 1) + ")");
    }
    if (o.columns) {
        const std::uint32_t columns = TilingScheme::geographic().tilesX(*o.onlyLevel);
        if (o.columns->first > o.columns->second || o.columns->second >= columns) {
            throw Error("orbis tile: columns " + std::to_string(o.columns->first) + ":" + std::to_string(o.columns->second) +
                        " are not within 0:" + std::to_string(columns - 1) + " of level " + std::to_string(*o.onlyLevel));
        }
    }
    std::error_code error;
    if (std::filesystem::exists(o.output, error) && !std::filesystem::is_directory(o.output, error)) {
        throw Error(cutForMessage(o.output.string()) + ": the output exists and is not a folder");
    }
}

ImageryTiler::~ImageryTiler() = default;

const GeodeticExtent& ImageryTiler::footprint() const noexcept
{
    return _impl->plan.footprint;
}

std::uint32_t ImageryTiler::levelCount() const noexcept
{
    return _impl->levelCount;
}

TilerSummary ImageryTiler::run()
{
    const Impl& impl = *_impl;
    const ImageryTilerOptions& options = impl.options;
    const auto start = Clock::now();
    const std::uint32_t deepest = impl.levelCount - 1;
    const int tileSize = options.tileSize;
    const TilingScheme scheme = TilingScheme::geographic();

    std::vector<std::uint32_t> levels;
    if (options.onlyLevel) {
        levels.push_back(*options.onlyLevel);
    } else {
        for (std::uint32_t level = deepest + 1; level-- > 0;) {
            levels.push_back(level);
        }
    }
    std::vector<TileRange> ranges;
    std::size_t total = 0;
    for (const std::uint32_t level : levels) {
        TileRange range = tilesCovering(impl.plan.footprint, level);
        if (options.columns && !range.empty) {
            range.firstX = std::max(range.firstX, options.columns->first);
            range.lastX = std::min(range.lastX, options.columns->second);
            range.empty = range.firstX > range.lastX;
        }
        total += range.count();
        ranges.push_back(range);
    }

    // Where the deepest level's resampling must average: the input is finer than the tiles.
    const double tileDegreesPerPixel = 180.0 / static_cast<double>(std::uint64_t{1} << deepest) / tileSize;
    const GDALResampleAlg resampling =
        tileDegreesPerPixel > 1.5 * impl.plan.degreesPerPixel ? GRA_Average : GRA_Bilinear;
    const int threadCount =
        options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

    if (std::find(levels.begin(), levels.end(), deepest) != levels.end() && !impl.plan.pixels) {
        loadPixels(options.input, _impl->plan);
    }
    TilerSummary summary;
    summary.levelCount = impl.levelCount;
    std::mutex mutex;
    std::size_t done = 0;
    std::string firstError;
    std::atomic<bool> failed{false};

    for (std::size_t l = 0; l < levels.size(); ++l) {
        const std::uint32_t level = levels[l];
        const TileRange range = ranges[l];
        const std::size_t count = range.count();
        const std::uint32_t width = range.empty ? 0 : range.lastX - range.firstX + 1;
        if (level < deepest && options.onlyLevel) {
            const std::filesystem::path below = options.output / std::to_string(level + 1);
            std::error_code error;
            if (!std::filesystem::is_directory(below, error)) {
                throw Error(cutForMessage(below.string()) + " does not exist: level " + std::to_string(level) +
                            " is made from level " + std::to_string(level + 1) + ", cut level " +
                            std::to_string(level + 1) + " first");
            }
        }
        std::atomic<std::size_t> next{0};
        std::size_t levelDone = 0;
        auto work = [&] {
            try {
                std::unique_ptr<TileWarper> warper;
                for (std::size_t index; !failed && (index = next++) < count;) {
                    // North to south, then west to east: the order image files are decoded in.
                    const std::uint32_t row = range.lastY - static_cast<std::uint32_t>(index / width);
                    const std::uint32_t column = range.firstX + static_cast<std::uint32_t>(index % width);
                    const TileKey key{level, column, row};
                    const std::filesystem::path path = impl.tilePath(level, column, row);
                    Image tile;
                    bool hasPixels = false;
                    if (level == deepest) {
                        if (!warper) {
                            warper = std::make_unique<TileWarper>(options.input, impl.plan, tileSize, resampling);
                        }
                        hasPixels = warper->warp(scheme.tileExtent(key), tile, path.string());
                    } else {
                        Image children[4];
                        for (int c = 0; c < 4; ++c) {
                            const TileKey child = key.child(c);
                            const std::filesystem::path childPath = impl.tilePath(child.level, child.x, child.y);
                            if (auto bytes = readFileBytesIfExists(childPath, "tile")) {
                                children[c] = decodeImage(*bytes, childPath.string(), 4);
                                if (children[c].width != tileSize || children[c].height != tileSize) {
                                    throw Error(childPath.string() + ": a tile of " + std::to_string(children[c].width) +
                                                "x" + std::to_string(children[c].height) + " pixels, expected " +
                                                std::to_string(tileSize));
                                }
                            }
                        }
                        tile = downsample(children, tileSize);
                        hasPixels = anyOpaque(tile);
                    }
                    if (hasPixels) {
                        writeFileAtomically(path, encodeImage(forOutput(tile, options.format), options.format, impl.quality));
                    }
                    const std::lock_guard lock(mutex);
                    ++(hasPixels ? summary.tilesWritten : summary.tilesEmpty);
                    ++done;
                    ++levelDone;
                    if (options.progress) {
                        options.progress({level, levelDone, count, done, total,
                                          std::chrono::duration<double>(Clock::now() - start).count()});
                    }
                }
            } catch (const std::exception& error) {
                const std::lock_guard lock(mutex);
                if (!failed.exchange(true)) {
                    firstError = error.what();
                }
            }
        };
        std::vector<std::thread> workers;
        const int levelThreads = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(threadCount), count));
        for (int t = 1; t < levelThreads; ++t) {
            workers.emplace_back(work);
        }
        work();
        for (std::thread& worker : workers) {
            worker.join();
        }
        if (failed) {
            throw Error(firstError);
        }
    }

    TileMapResource resource;
    resource.title = options.title.empty() ? options.input.filename().string() : options.title;
    resource.attribution = options.attribution;
    resource.extent = impl.plan.footprint;
    resource.tileWidth = tileSize;
    resource.tileHeight = tileSize;
    resource.extension = impl.extension;
    resource.mimeType = options.format == ImageFormat::Jpeg ? "image/jpeg" : "image/" + impl.extension;
    for (std::uint32_t level = 0; level < impl.levelCount; ++level) {
        resource.tileSets.push_back({std::to_string(level), level, tileMapUnitsPerPixel(scheme, level, tileSize)});
    }
    writeFileAtomically(options.output / "tilemapresource.xml", formatTileMapResource(resource));
    summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return summary;
}

} // namespace orbis::world
