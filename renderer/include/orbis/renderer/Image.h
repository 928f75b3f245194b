#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace orbis {

/// An 8-bit-per-channel image in memory, rows top to bottom (as PNG stores them).
struct Image {
    int width = 0;
    int height = 0;
    int channels = 4; ///< 1 (grey), 3 (RGB) or 4 (RGBA)
    std::vector<std::uint8_t> pixels;

    Image() = default;
    Image(int width_, int height_, int channels_ = 4);

    std::uint8_t* pixel(int x, int y) { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * channels; }
    const std::uint8_t* pixel(int x, int y) const
    {
        return pixels.data() + (static_cast<std::size_t>(y) * width + x) * channels;
    }
};

/// Reads a PNG or JPEG file. Throws orbis::Error naming the file when it cannot be read or decoded.
Image readImage(const std::filesystem::path& path, int desiredChannels = 4);

/// Writes a PNG. The file appears whole or not at all: it is written to a temporary name and
/// renamed. Throws orbis::Error naming the file on failure.
void writePng(const Image& image, const std::filesystem::path& path);

} // namespace orbis
