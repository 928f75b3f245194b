#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace orbis {

/// An 8-bit-per-channel image in memory, rows top to bottom (as PNG stores them). Plain pixels:
/// reading and writing image files belongs to the world-data layer, uploading them to the renderer.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 4; ///< 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA)
    std::vector<std::uint8_t> pixels;

    Image() = default;
    /// width x height pixels of `channels` zero bytes each (asserted: sizes >= 0, 1 to 4 channels).
    Image(int width_, int height_, int channels_ = 4)
        : width(width_)
        , height(height_)
        , channels(channels_)
        , pixels(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * static_cast<std::size_t>(channels_))
    {
        assert(width_ >= 0 && height_ >= 0 && channels_ >= 1 && channels_ <= 4);
    }

    std::uint8_t* pixel(int x, int y) { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * channels; }
    const std::uint8_t* pixel(int x, int y) const
    {
        return pixels.data() + (static_cast<std::size_t>(y) * width + x) * channels;
    }
};

} // namespace orbis
