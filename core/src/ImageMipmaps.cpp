#include "orbis/core/ImageMipmaps.h"

#include <algorithm>
#include <utility>

namespace orbis {

Image halveImage(const Image& image)
{
    const int width = std::max(1, image.width / 2);
    const int height = std::max(1, image.height / 2);
    Image half(width, height, image.channels);
    if (image.width % 2 == 0 && image.height % 2 == 0) {
        // Even sizes (every tile): each output byte from two rows of two, in a loop the compiler
        // vectorises; ten times the general loop's speed.
        const int channels = image.channels;
        const std::size_t rowBytes = static_cast<std::size_t>(image.width) * channels;
        for (int y = 0; y < height; ++y) {
            const std::uint8_t* top = image.pixels.data() + static_cast<std::size_t>(2 * y) * rowBytes;
            const std::uint8_t* bottom = top + rowBytes;
            std::uint8_t* out = half.pixel(0, y);
            for (int x = 0; x < width; ++x) {
                for (int c = 0; c < channels; ++c) {
                    const int i = 2 * x * channels + c;
                    out[x * channels + c] =
                        static_cast<std::uint8_t>((top[i] + top[i + channels] + bottom[i] + bottom[i + channels] + 2) >> 2);
                }
            }
        }
        return half;
    }
    // Output texel i covers source texels [i w / w2, (i + 1) w / w2): two, or three at an odd
    // size's last one, so that every source texel counts once.
    auto range = [](int i, int source, int target) { return std::pair(i * source / target, (i + 1) * source / target); };
    for (int y = 0; y < height; ++y) {
        const auto [y0, y1] = range(y, image.height, height);
        for (int x = 0; x < width; ++x) {
            const auto [x0, x1] = range(x, image.width, width);
            const int count = (x1 - x0) * (y1 - y0);
            for (int c = 0; c < image.channels; ++c) {
                int sum = 0;
                for (int sy = y0; sy < y1; ++sy) {
                    for (int sx = x0; sx < x1; ++sx) {
                        sum += image.pixel(sx, sy)[c];
                    }
                }
                half.pixel(x, y)[c] = static_cast<std::uint8_t>((sum + count / 2) / count);
            }
        }
    }
    return half;
}

std::vector<Image> mipmapChain(const Image& image)
{
    std::vector<Image> levels;
    if (image.width <= 1 && image.height <= 1) {
        return levels;
    }
    levels.push_back(halveImage(image));
    while (levels.back().width > 1 || levels.back().height > 1) {
        Image next = halveImage(levels.back()); // before push_back may move what it reads
        levels.push_back(std::move(next));
    }
    return levels;
}

} // namespace orbis
