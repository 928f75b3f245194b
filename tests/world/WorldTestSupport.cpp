#include "WorldTestSupport.h"

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

} // namespace orbis::test
