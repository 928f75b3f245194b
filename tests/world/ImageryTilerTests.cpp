// The imagery tiler on inputs the tests write themselves: a GeoTIFF in UTM (written with GDAL) and a
// plain whole-globe JPEG. Positions are checked against GeographicLib's UTM, not GDAL's own PROJ.

#include "TempFiles.h"
#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/ImageryTiler.h>
#include <orbis/world/TileMapResource.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

#include <GeographicLib/UTMUPS.hpp>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <chrono>
#include <future>
#include <map>

#include <sys/stat.h>

using namespace orbis;
using namespace orbis::world;
using orbis::test::TempDirectory;
using Catch::Matchers::Contains;

namespace {

struct Marker {
    int column; ///< the 5 x 5 block's centre pixel in the input
    int row;
    std::uint8_t colour[3];
};

const Marker kMarkers[] = {{40, 60, {255, 0, 0}}, {150, 30, {0, 255, 0}}, {100, 170, {0, 0, 255}}};

/// An input image: grey, with the markers as 5 x 5 blocks.
Image markedImage(int width, int height, const Marker* markers, std::size_t count)
{
    Image image(width, height, 3);
    std::fill(image.pixels.begin(), image.pixels.end(), std::uint8_t{100});
    for (std::size_t m = 0; m < count; ++m) {
        for (int y = markers[m].row - 2; y <= markers[m].row + 2; ++y) {
            for (int x = markers[m].column - 2; x <= markers[m].column + 2; ++x) {
                std::copy_n(markers[m].colour, 3, image.pixel(x, y));
            }
        }
    }
    return image;
}

// UTM zone 33 north, 500 m pixels, 200 x 200, the top left corner at E 450 km, N 5,000 km (45 N, 14.4 E).
constexpr double kEasting = 450000.0;
constexpr double kNorthing = 5000000.0;
constexpr double kPixelMeters = 500.0;
constexpr int kUtmSize = 200;

void writeUtmGeoTiff(const std::filesystem::path& path)
{
    GDALAllRegister();
    const Image image = markedImage(kUtmSize, kUtmSize, kMarkers, 3);
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    REQUIRE(driver);
    GDALDatasetH dataset = GDALCreate(driver, path.c_str(), kUtmSize, kUtmSize, 3, GDT_Byte, nullptr);
    REQUIRE(dataset);
    double transform[6] = {kEasting, kPixelMeters, 0.0, kNorthing, 0.0, -kPixelMeters};
    GDALSetGeoTransform(dataset, transform);
    OGRSpatialReferenceH utm = OSRNewSpatialReference(nullptr);
    REQUIRE(OSRImportFromEPSG(utm, 32633) == OGRERR_NONE);
    GDALSetSpatialRef(dataset, utm);
    OSRDestroySpatialReference(utm);
    REQUIRE(GDALDatasetRasterIO(dataset, GF_Write, 0, 0, kUtmSize, kUtmSize, const_cast<std::uint8_t*>(image.pixels.data()),
                                kUtmSize, kUtmSize, GDT_Byte, 3, nullptr, 3, kUtmSize * 3, 1) == CE_None);
    GDALClose(dataset);
}

/// Longitude and latitude (degrees) of a point of the UTM input, by GeographicLib.
std::pair<double, double> utmToDegrees(double column, double row)
{
    double latitude = 0.0;
    double longitude = 0.0;
    GeographicLib::UTMUPS::Reverse(33, true, kEasting + column * kPixelMeters, kNorthing - row * kPixelMeters, latitude,
                                   longitude);
    return {longitude, latitude};
}

/// One level of a pyramid joined into an RGBA image over tile columns x0..x1 and rows y0..y1
/// (rows from the south), north up; missing tiles transparent.
struct Mosaic {
    Image image;
    double west = 0.0;  ///< degrees
    double north = 0.0;
    double degreesPerPixel = 0.0;

    /// The pixel (x, y, fractional, from the top left corner) of a longitude and latitude.
    std::pair<double, double> pixelOf(double longitude, double latitude) const
    {
        return {(longitude - west) / degreesPerPixel, (north - latitude) / degreesPerPixel};
    }
};

Mosaic readMosaic(const std::filesystem::path& folder, std::uint32_t level, std::uint32_t x0, std::uint32_t x1,
                  std::uint32_t y0, std::uint32_t y1)
{
    const auto source = openTileSource(folder.string());
    const int size = source->info().tileWidth;
    Mosaic mosaic;
    mosaic.image = Image(int(x1 - x0 + 1) * size, int(y1 - y0 + 1) * size, 4);
    mosaic.degreesPerPixel = 180.0 / double(1u << level) / size;
    mosaic.west = -180.0 + x0 * mosaic.degreesPerPixel * size;
    mosaic.north = -90.0 + (y1 + 1) * mosaic.degreesPerPixel * size;
    for (std::uint32_t y = y0; y <= y1; ++y) {
        for (std::uint32_t x = x0; x <= x1; ++x) {
            const TileFetch fetched = source->fetch({level, x, y});
            if (fetched.status != TileFetch::Status::Ok) {
                continue;
            }
            const Image tile = decodeImage(fetched.bytes, source->locate({level, x, y}), 4);
            REQUIRE(tile.width == size);
            for (int row = 0; row < size; ++row) {
                std::copy_n(tile.pixel(0, row), size * 4,
                            mosaic.image.pixel(int(x - x0) * size, int(y1 - y) * size + row));
            }
        }
    }
    return mosaic;
}

/// The centroid (pixel centres, from the top left) of the pixels near `colour`.
std::pair<double, double> centroidOf(const Image& image, const std::uint8_t colour[3])
{
    double sumX = 0.0;
    double sumY = 0.0;
    double weight = 0.0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            int distance = 0;
            for (int c = 0; c < 3; ++c) {
                distance += std::abs(int(p[c]) - int(colour[c]));
            }
            if (p[3] == 255 && distance < 60) {
                sumX += x + 0.5;
                sumY += y + 0.5;
                weight += 1.0;
            }
        }
    }
    REQUIRE(weight > 0.0);
    return {sumX / weight, sumY / weight};
}

/// Every file under `folder`, relative path to bytes.
std::map<std::string, std::vector<std::uint8_t>> filesUnder(const std::filesystem::path& folder)
{
    std::map<std::string, std::vector<std::uint8_t>> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file()) {
            files[std::filesystem::relative(entry.path(), folder).string()] = readFileBytes(entry.path(), "tile");
        }
    }
    return files;
}

/// The relative paths whose bytes differ between two folders, or that only one holds.
std::vector<std::string> differingFiles(const std::filesystem::path& a, const std::filesystem::path& b)
{
    const auto filesA = filesUnder(a);
    const auto filesB = filesUnder(b);
    std::vector<std::string> differing;
    for (const auto& [name, bytes] : filesA) {
        const auto other = filesB.find(name);
        if (other == filesB.end() || other->second != bytes) {
            differing.push_back(name);
        }
    }
    for (const auto& [name, bytes] : filesB) {
        if (!filesA.count(name)) {
            differing.push_back(name);
        }
    }
    return differing;
}

std::string tilerError(const ImageryTilerOptions& options)
{
    try {
        ImageryTiler(options).run();
    } catch (const Error& error) {
        return error.what();
    }
    FAIL("the tiler succeeded");
    return {};
}

} // namespace

TEST_CASE("A UTM GeoTIFF lands where its georeferencing says, within half a tile pixel", "[world][tiler]")
{
    const TempDirectory folder;
    writeUtmGeoTiff(folder.path() / "utm.tif");
    ImageryTilerOptions options;
    options.input = folder.path() / "utm.tif";
    options.output = folder.path() / "out";
    options.format = ImageFormat::Png;
    options.threads = 2;
    std::size_t lastDone = 0;
    std::size_t total = 0;
    options.progress = [&](const TilerProgress& progress) {
        lastDone = progress.done;
        total = progress.total;
    };
    ImageryTiler tiler(options);
    // 500 m is 0.0045 degrees north-south: level 8 (0.0027 degrees per pixel) is the first as fine.
    REQUIRE(tiler.levelCount() == 9);
    const auto [west, north] = utmToDegrees(0, 0);
    REQUIRE(toDegrees(tiler.footprint().north) == Approx(north).margin(0.01));
    const TilerSummary summary = tiler.run();
    REQUIRE(summary.tilesWritten > 0);
    REQUIRE(lastDone == total);
    REQUIRE(total == summary.tilesWritten + summary.tilesEmpty);

    const auto source = openTileSource((folder.path() / "out").string());
    REQUIRE(source->info().maximumLevel == 8);
    REQUIRE(source->info().format == "png");
    // The deepest level's tiles around the input, joined.
    const GeodeticExtent& footprint = tiler.footprint();
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey southWest = *scheme.tileAt({footprint.west, footprint.south}, 8);
    const TileKey northEast = *scheme.tileAt({footprint.east, footprint.north}, 8);
    const Mosaic mosaic = readMosaic(folder.path() / "out", 8, southWest.x, northEast.x, southWest.y, northEast.y);
    for (const Marker& marker : kMarkers) {
        INFO("marker at column " << marker.column << ", row " << marker.row);
        // The block's centre: the middle of its centre pixel.
        const auto [longitude, latitude] = utmToDegrees(marker.column + 0.5, marker.row + 0.5);
        const auto [expectedX, expectedY] = mosaic.pixelOf(longitude, latitude);
        const auto [x, y] = centroidOf(mosaic.image, marker.colour);
        CHECK(x == Approx(expectedX).margin(0.5));
        CHECK(y == Approx(expectedY).margin(0.5));
    }
    // Inside the input: its grey, opaque; outside: transparent.
    const auto [insideX, insideY] = mosaic.pixelOf(utmToDegrees(10, 190).first, utmToDegrees(10, 190).second);
    const std::uint8_t* inside = mosaic.image.pixel(int(insideX), int(insideY));
    REQUIRE(int(inside[0]) == 100);
    REQUIRE(int(inside[3]) == 255);
    const auto [outsideX, outsideY] = mosaic.pixelOf(utmToDegrees(-20, 100).first, utmToDegrees(-20, 100).second);
    REQUIRE(int(mosaic.image.pixel(int(outsideX), int(outsideY))[3]) == 0);

    // Each level above is made from the four tiles below it: a 2 x 2 average.
    const TileKey parent = *scheme.tileAt(footprint.centre(), 7);
    const Mosaic children = readMosaic(folder.path() / "out", 8, parent.x * 2, parent.x * 2 + 1, parent.y * 2, parent.y * 2 + 1);
    const Mosaic made = readMosaic(folder.path() / "out", 7, parent.x, parent.x, parent.y, parent.y);
    int largest = 0;
    for (int y = 0; y < 256; ++y) {
        for (int x = 0; x < 256; ++x) {
            const std::uint8_t* p = made.image.pixel(x, y);
            int alpha = 0;
            for (int d = 0; d < 4; ++d) {
                alpha += children.image.pixel(2 * x + d % 2, 2 * y + d / 2)[3];
            }
            largest = std::max(largest, std::abs(int(p[3]) - (alpha + 2) / 4));
            if (alpha == 4 * 255) {
                for (int c = 0; c < 3; ++c) {
                    int sum = 0;
                    for (int d = 0; d < 4; ++d) {
                        sum += children.image.pixel(2 * x + d % 2, 2 * y + d / 2)[c];
                    }
                    largest = std::max(largest, std::abs(int(p[c]) - (sum + 2) / 4));
                }
            }
        }
    }
    REQUIRE(largest <= 1);
}

TEST_CASE("A plain JPEG is the whole globe, and split jobs write what one job writes", "[world][tiler]")
{
    const TempDirectory folder;
    // 16 x 16 blocks on JPEG's 16-pixel grid, so that 4:2:0 chroma does not smear them.
    struct Block {
        int left, top;
        std::uint8_t colour[3];
    };
    const Block blocks[] = {{96, 48, {255, 0, 0}}, {400, 192, {0, 255, 0}}, {16, 128, {0, 0, 255}}};
    Image image(512, 256, 3);
    std::fill(image.pixels.begin(), image.pixels.end(), std::uint8_t{100});
    for (const Block& block : blocks) {
        for (int y = block.top; y < block.top + 16; ++y) {
            for (int x = block.left; x < block.left + 16; ++x) {
                std::copy_n(block.colour, 3, image.pixel(x, y));
            }
        }
    }
    orbis::test::writeBytes(folder.path() / "world.jpg", encodeJpeg(image, 95));

    ImageryTilerOptions options;
    options.input = folder.path() / "world.jpg";
    options.output = folder.path() / "whole";
    options.levels = 2;
    options.threads = 2;
    options.attribution = "made by the test";
    ImageryTiler tiler(options);
    REQUIRE(tiler.footprint() == GeodeticExtent::maximum());
    const TilerSummary summary = tiler.run();
    REQUIRE(summary.tilesWritten == 8 + 2);
    REQUIRE(summary.tilesEmpty == 0);
    const TileMapResource resource = readTileMapResource(folder.path() / "whole");
    REQUIRE(resource.attribution == "made by the test");
    REQUIRE(resource.title == "world.jpg");
    REQUIRE(resource.maximumLevel() == 1);

    // Level 1 is the image at twice its size: the blocks' centres move with it.
    const Mosaic mosaic = readMosaic(folder.path() / "whole", 1, 0, 3, 0, 1);
    for (const Block& block : blocks) {
        INFO("block at column " << block.left);
        const double longitude = -180.0 + (block.left + 8) * 360.0 / 512.0;
        const double latitude = 90.0 - (block.top + 8) * 180.0 / 256.0;
        const auto [expectedX, expectedY] = mosaic.pixelOf(longitude, latitude);
        const auto [x, y] = centroidOf(mosaic.image, block.colour);
        CHECK(x == Approx(expectedX).margin(0.5));
        CHECK(y == Approx(expectedY).margin(0.5));
    }

    // The same pyramid in three jobs (level 1 in two halves, then level 0), with one thread.
    ImageryTilerOptions split = options;
    split.output = folder.path() / "split";
    split.threads = 1;
    split.onlyLevel = 1;
    split.columns = std::pair(0u, 1u);
    REQUIRE(ImageryTiler(split).run().tilesWritten == 4);
    split.columns = std::pair(2u, 3u);
    REQUIRE(ImageryTiler(split).run().tilesWritten == 4);
    split.columns.reset();
    split.onlyLevel = 0;
    REQUIRE(ImageryTiler(split).run().tilesWritten == 2);
    REQUIRE(filesUnder(folder.path() / "whole").size() == 11);
    const std::vector<std::string> differing = differingFiles(folder.path() / "whole", folder.path() / "split");
    INFO("differing: " << ::Catch::Detail::stringify(differing));
    REQUIRE(differing.empty());
}

TEST_CASE("The tiler refuses bad inputs and options by name, and leaves no partial file", "[world][tiler][hostile]")
{
    const TempDirectory folder;
    ImageryTilerOptions options;
    options.output = folder.path() / "out";
    options.input = folder.path() / "none.tif";
    REQUIRE_THAT(tilerError(options), Contains("none.tif: cannot open the input image: No such file or directory"));
    REQUIRE(::mkfifo((folder.path() / "pipe.tif").c_str(), 0600) == 0);
    options.input = folder.path() / "pipe.tif";
    auto piped = std::async(std::launch::async, [&] { return tilerError(options); });
    REQUIRE(piped.wait_for(std::chrono::seconds(20)) == std::future_status::ready);
    REQUIRE_THAT(piped.get(), Contains("pipe.tif: the input image is not a regular file"));
    writeFileAtomically(folder.path() / "text.tif", std::string_view("not an image at all"));
    options.input = folder.path() / "text.tif";
    REQUIRE_THAT(tilerError(options), Contains("text.tif: GDAL cannot read the input image"));

    orbis::test::writeBytes(folder.path() / "small.png", encodePng(orbis::test::testPattern(64, 32, 3), 6));
    options.input = folder.path() / "small.png";
    options.levels = 2;
    options.onlyLevel = 2;
    REQUIRE_THAT(tilerError(options), Contains("level 2 is not in the pyramid (0 to 1)"));
    options.onlyLevel = 1;
    options.columns = std::pair(3u, 4u);
    REQUIRE_THAT(tilerError(options), Contains("columns 3:4 are not within 0:3 of level 1"));
    options.columns.reset();
    options.onlyLevel = 0;
    REQUIRE_THAT(tilerError(options), Contains("cut level 1 first"));
    options.onlyLevel.reset();
    options.levels = 31;
    REQUIRE_THAT(tilerError(options), Contains("ask for fewer levels"));

    // A truncated JPEG: GDAL reads its header, then fails inside a tile: an error naming the tile.
    const std::vector<std::uint8_t> jpeg = encodeJpeg(orbis::test::testPattern(1024, 512, 3), 90);
    orbis::test::writeBytes(folder.path() / "cut.jpg", {jpeg.begin(), jpeg.begin() + std::ptrdiff_t(jpeg.size() / 3)});
    options.input = folder.path() / "cut.jpg";
    options.levels = 3;
    const std::string message = tilerError(options);
    REQUIRE_THAT(message, Contains("cut.jpg"));
    if (std::filesystem::exists(folder.path() / "out")) {
        for (const auto& entry : std::filesystem::recursive_directory_iterator(folder.path() / "out")) {
            REQUIRE(entry.path().string().find(".tmp-") == std::string::npos);
        }
    }
    REQUIRE_FALSE(std::filesystem::exists(folder.path() / "out/tilemapresource.xml"));
}

TEST_CASE("The level for a resolution is the first as fine", "[world][tiler]")
{
    REQUIRE(geographicLevelForResolution(360.0 / 8192.0, 256) == 4);
    REQUIRE(geographicLevelForResolution(0.703125, 256) == 0);
    REQUIRE(geographicLevelForResolution(0.7, 256) == 1);
    REQUIRE(geographicLevelForResolution(1e-12, 256) == kMaximumTileLevel);
}
