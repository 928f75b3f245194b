#include <orbis/core/ImageMipmaps.h>

#include <catch2/catch.hpp>

using orbis::Image;

TEST_CASE("halveImage averages each 2 x 2 block, rounding, and three along an odd edge", "[core][image]")
{
    Image image(5, 2, 1);
    const std::uint8_t values[] = {0, 10, 20, 30, 41, 1, 11, 21, 31, 40};
    std::copy(std::begin(values), std::end(values), image.pixels.begin());
    const Image half = orbis::halveImage(image);
    REQUIRE(half.width == 2);
    REQUIRE(half.height == 1);
    CHECK(half.pixels[0] == 6);  // (0 + 10 + 1 + 11) / 4 = 5.5, rounded
    CHECK(half.pixels[1] == 31); // (20 + 30 + 41 + 21 + 31 + 40) / 6 = 30.5, rounded
}

TEST_CASE("mipmapChain runs down to one texel, every level the mean of the one above", "[core][image]")
{
    Image image(256, 128, 4);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = static_cast<std::uint8_t>((i * 37) % 251);
    }
    const std::vector<Image> chain = orbis::mipmapChain(image);
    REQUIRE(chain.size() == 8); // 128x64 .. 1x1
    CHECK(chain.front().width == 128);
    CHECK(chain.front().height == 64);
    CHECK(chain.back().width == 1);
    CHECK(chain.back().height == 1);
    CHECK(chain[6].width == 2);
    CHECK(chain[6].height == 1);
    // The coarsest texel is the image's mean, within the rounding of each level.
    for (int c = 0; c < 4; ++c) {
        double sum = 0.0;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                sum += image.pixel(x, y)[c];
            }
        }
        CHECK(std::abs(chain.back().pixel(0, 0)[c] - sum / (256.0 * 128.0)) < 4.0);
    }
    CHECK(orbis::mipmapChain(Image(1, 1, 3)).empty());
}
