#pragma once

// Helpers for the world-data tests: PNG files built byte by byte, so that the decoders are checked
// against bytes no encoder of ours produced (and headers that lie), and image comparisons.

#include <orbis/core/Image.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

struct sqlite3;

namespace orbis::test {

/// A PNG chunk: length, type, data, CRC (computed, so a header can claim anything and still pass
/// the checksum).
void appendPngChunk(std::vector<std::uint8_t>& png, const char type[4], const std::vector<std::uint8_t>& data);

/// A whole PNG from raw scanlines (each row: filter byte 0, then the samples, big-endian for 16-bit):
/// signature, IHDR claiming width x height, one zlib-compressed IDAT, IEND.
std::vector<std::uint8_t> handmadePng(std::uint32_t width, std::uint32_t height, std::uint8_t bitDepth,
                                      std::uint8_t colorType, const std::vector<std::uint8_t>& scanlines);

/// width x height RGB(A) test pattern: smooth gradients plus a few sharp blocks, reproducible.
Image testPattern(int width, int height, int channels);

void writeBytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes);

/// The largest absolute difference between two images' bytes (same size and channels, else 255).
int maximumDifference(const Image& a, const Image& b);
/// The mean absolute difference per byte.
double meanDifference(const Image& a, const Image& b);

/// A small MBTiles database: metadata rows, then tiles (zoom, column, row from the south, bytes).
class MBTilesWriter {
public:
    explicit MBTilesWriter(const std::filesystem::path& path);
    ~MBTilesWriter();
    MBTilesWriter(const MBTilesWriter&) = delete;
    MBTilesWriter& operator=(const MBTilesWriter&) = delete;
    void run(const std::string& sql);
    void metadata(const std::string& name, const std::string& value);
    void tile(int zoom, int column, int row, const std::vector<std::uint8_t>& bytes);

private:
    sqlite3* _database = nullptr;
};

/// A one-band Float32 GeoTIFF DEM written with GDAL: width x height pixels, the geotransform
/// (pixel corners), the CRS by EPSG code, each pixel's height from height(column, row) at its
/// centre, optionally a nodata value.
void writeDem(const std::filesystem::path& path, int width, int height, const double transform[6], int epsg,
              const std::function<float(int column, int row)>& heightAt, std::optional<double> noData = std::nullopt);

} // namespace orbis::test
