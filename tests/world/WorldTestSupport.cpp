#include "WorldTestSupport.h"

#include <catch2/catch.hpp>
#include <gdal.h>
#include <ogr_srs_api.h>
#include <sqlite3.h>
#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace orbis::test {

namespace {

void appendBigEndian32(std::vector<std::uint8_t>& bytes, std::uint32_t value)
{
    for (int shift = 24; shift >= 0; shift -= 8) {
        bytes.push_back(static_cast<std::uint8_t>(value >> shift));
    }
}

} // namespace

void appendPngChunk(std::vector<std::uint8_t>& png, const char type[4], const std::vector<std::uint8_t>& data)
{
    appendBigEndian32(png, static_cast<std::uint32_t>(data.size()));
    const std::size_t typeStart = png.size();
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    const auto crc = ::crc32(0L, png.data() + typeStart, static_cast<uInt>(png.size() - typeStart));
    appendBigEndian32(png, static_cast<std::uint32_t>(crc));
}

std::vector<std::uint8_t> handmadePng(std::uint32_t width, std::uint32_t height, std::uint8_t bitDepth,
                                      std::uint8_t colorType, const std::vector<std::uint8_t>& scanlines)
{
    std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<std::uint8_t> header;
    appendBigEndian32(header, width);
    appendBigEndian32(header, height);
    header.insert(header.end(), {bitDepth, colorType, 0, 0, 0});
    appendPngChunk(png, "IHDR", header);
    uLongf compressedSize = ::compressBound(static_cast<uLong>(scanlines.size()));
    std::vector<std::uint8_t> compressed(compressedSize);
    if (::compress2(compressed.data(), &compressedSize, scanlines.data(), static_cast<uLong>(scanlines.size()), 6) != Z_OK) {
        throw std::runtime_error("zlib failed");
    }
    compressed.resize(compressedSize);
    appendPngChunk(png, "IDAT", compressed);
    appendPngChunk(png, "IEND", {});
    return png;
}

Image testPattern(int width, int height, int channels)
{
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            const bool block = ((x / 16) + (y / 16)) % 5 == 0;
            for (int c = 0; c < channels; ++c) {
                const int gradient = c == 0 ? x * 255 / std::max(width - 1, 1)
                                     : c == 1 ? y * 255 / std::max(height - 1, 1)
                                     : c == 2 ? (x + y) * 255 / std::max(width + height - 2, 1)
                                              : 128 + (x % 64);
                p[c] = static_cast<std::uint8_t>(block && c < 3 ? 255 - gradient : gradient);
            }
        }
    }
    return image;
}

void writeBytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes)
{
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
        throw std::runtime_error("cannot write " + path.string());
    }
}

int maximumDifference(const Image& a, const Image& b)
{
    if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
        return 255;
    }
    int largest = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        largest = std::max(largest, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
    }
    return largest;
}

double meanDifference(const Image& a, const Image& b)
{
    if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.pixels.empty()) {
        return 255.0;
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
    }
    return sum / static_cast<double>(a.pixels.size());
}

MBTilesWriter::MBTilesWriter(const std::filesystem::path& path)
{
    REQUIRE(sqlite3_open(path.c_str(), &_database) == SQLITE_OK);
    run("CREATE TABLE metadata (name TEXT, value TEXT)");
    run("CREATE TABLE tiles (zoom_level INTEGER, tile_column INTEGER, tile_row INTEGER, tile_data BLOB)");
}

MBTilesWriter::~MBTilesWriter()
{
    sqlite3_close(_database);
}

void MBTilesWriter::run(const std::string& sql)
{
    REQUIRE(sqlite3_exec(_database, sql.c_str(), nullptr, nullptr, nullptr) == SQLITE_OK);
}

void MBTilesWriter::metadata(const std::string& name, const std::string& value)
{
    sqlite3_stmt* statement = nullptr;
    REQUIRE(sqlite3_prepare_v2(_database, "INSERT INTO metadata VALUES (?, ?)", -1, &statement, nullptr) == SQLITE_OK);
    sqlite3_bind_text(statement, 1, name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(statement, 2, value.c_str(), -1, SQLITE_TRANSIENT);
    REQUIRE(sqlite3_step(statement) == SQLITE_DONE);
    sqlite3_finalize(statement);
}

void MBTilesWriter::tile(int zoom, int column, int row, const std::vector<std::uint8_t>& bytes)
{
    sqlite3_stmt* statement = nullptr;
    REQUIRE(sqlite3_prepare_v2(_database, "INSERT INTO tiles VALUES (?, ?, ?, ?)", -1, &statement, nullptr) == SQLITE_OK);
    sqlite3_bind_int(statement, 1, zoom);
    sqlite3_bind_int(statement, 2, column);
    sqlite3_bind_int(statement, 3, row);
    sqlite3_bind_blob(statement, 4, bytes.data(), int(bytes.size()), SQLITE_TRANSIENT);
    REQUIRE(sqlite3_step(statement) == SQLITE_DONE);
    sqlite3_finalize(statement);
}

void writeDem(const std::filesystem::path& path, int width, int height, const double transform[6], int epsg,
              const std::function<float(int column, int row)>& heightAt, std::optional<double> noData)
{
    GDALAllRegister();
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    REQUIRE(driver);
    GDALDatasetH dataset = GDALCreate(driver, path.c_str(), width, height, 1, GDT_Float32, nullptr);
    REQUIRE(dataset);
    double geotransform[6];
    std::copy_n(transform, 6, geotransform);
    GDALSetGeoTransform(dataset, geotransform);
    OGRSpatialReferenceH reference = OSRNewSpatialReference(nullptr);
    REQUIRE(OSRImportFromEPSG(reference, epsg) == OGRERR_NONE);
    GDALSetSpatialRef(dataset, reference);
    OSRDestroySpatialReference(reference);
    GDALRasterBandH band = GDALGetRasterBand(dataset, 1);
    if (noData) {
        GDALSetRasterNoDataValue(band, *noData);
    }
    std::vector<float> heights(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int row = 0; row < height; ++row) {
        for (int column = 0; column < width; ++column) {
            heights[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(column)] =
                heightAt(column, row);
        }
    }
    REQUIRE(GDALRasterIO(band, GF_Write, 0, 0, width, height, heights.data(), width, height, GDT_Float32, 0, 0) == CE_None);
    GDALClose(dataset);
}

} // namespace orbis::test
