// TextureAtlas lives in the renderer (image work, no GL); its tests sit in the scene suite, which
// links the renderer, until a renderer suite exists.

#include <orbis/renderer/TextureAtlas.h>

#include <orbis/core/Error.h>

#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <random>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;

namespace {

/// A pixel value that differs between images and positions, never 0 (so padding, which is 0,
/// cannot pass for image content).
std::uint8_t patternValue(std::size_t image, int x, int y, int channel)
{
    return static_cast<std::uint8_t>(1 + (image * 131 + static_cast<std::size_t>(x) * 17 +
                                          static_cast<std::size_t>(y) * 29 + static_cast<std::size_t>(channel) * 7) %
                                             255);
}

Image patternImage(std::size_t index, int width, int height, int channels)
{
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < channels; ++c) {
                image.pixel(x, y)[c] = patternValue(index, x, y, c);
            }
        }
    }
    return image;
}

/// Every rectangle inside the atlas at least `padding` from its edges, every two at least
/// `padding` apart, every image's pixels where its rectangle says, zeros everywhere else.
void checkAtlas(const TextureAtlas& atlas)
{
    const int padding = atlas.options().padding;
    const Image& image = atlas.image();
    std::vector<std::uint8_t> covered(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
    for (std::size_t i = 0; i < atlas.size(); ++i) {
        const PixelRectangle& r = atlas.rectangle(i);
        INFO("image " << i << " at " << r.x << "," << r.y << " size " << r.width << "x" << r.height << " in "
                      << image.width << "x" << image.height);
        if (r.width == 0 || r.height == 0) {
            continue;
        }
        REQUIRE(r.x >= padding);
        REQUIRE(r.y >= padding);
        REQUIRE(r.x + r.width + padding <= image.width);
        REQUIRE(r.y + r.height + padding <= image.height);
        for (std::size_t j = 0; j < i; ++j) {
            const PixelRectangle& o = atlas.rectangle(j);
            if (o.width == 0 || o.height == 0) {
                continue;
            }
            // Apart by at least `padding` pixels horizontally or vertically.
            const bool apart = r.x >= o.x + o.width + padding || o.x >= r.x + r.width + padding ||
                               r.y >= o.y + o.height + padding || o.y >= r.y + r.height + padding;
            INFO("other image " << j << " at " << o.x << "," << o.y << " size " << o.width << "x" << o.height);
            REQUIRE(apart);
        }
        bool pixelsMatch = true;
        for (int y = 0; y < r.height; ++y) {
            for (int x = 0; x < r.width; ++x) {
                covered[static_cast<std::size_t>(r.y + y) * static_cast<std::size_t>(image.width) +
                        static_cast<std::size_t>(r.x + x)] = 1;
                for (int c = 0; c < image.channels; ++c) {
                    pixelsMatch = pixelsMatch && image.pixel(r.x + x, r.y + y)[c] == patternValue(i, x, y, c);
                }
            }
        }
        REQUIRE(pixelsMatch);
    }
    bool restIsZero = true;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (!covered[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)]) {
                for (int c = 0; c < image.channels; ++c) {
                    restIsZero = restIsZero && image.pixel(x, y)[c] == 0;
                }
            }
        }
    }
    REQUIRE(restIsZero);
}

/// Adds `count` random images, alternately one by one and in batches of up to 20.
void addRandomImages(TextureAtlas& atlas, std::mt19937& random, std::size_t count, int maxSide)
{
    std::uniform_int_distribution<int> side(1, maxSide);
    std::uniform_int_distribution<std::size_t> batch(1, 20);
    while (atlas.size() < count) {
        std::vector<Image> images;
        const std::size_t n = std::min(count - atlas.size(), atlas.size() % 2 ? batch(random) : 1);
        for (std::size_t k = 0; k < n; ++k) {
            images.push_back(patternImage(atlas.size() + k, side(random), side(random), atlas.options().channels));
        }
        const auto result = atlas.add(images);
        REQUIRE(result.first + n == atlas.size());
    }
}

} // namespace

TEST_CASE("TextureAtlas packs random images without overlap, inside the atlas, padded, pixels intact", "[scene][atlas]")
{
    const auto seed = GENERATE(1u, 2u, 3u, 20261123u);
    const int padding = GENERATE(0, 1, 2);
    INFO("seed " << seed << ", padding " << padding);
    std::mt19937 random(seed);
    TextureAtlasOptions options;
    options.padding = padding;
    options.channels = seed % 2 ? 4 : 1;
    TextureAtlas atlas(options);
    addRandomImages(atlas, random, 300, 40);
    CHECK((atlas.width() & (atlas.width() - 1)) == 0);
    CHECK((atlas.height() & (atlas.height() - 1)) == 0);
    checkAtlas(atlas);
}

TEST_CASE("TextureAtlas is deterministic", "[scene][atlas]")
{
    TextureAtlas first;
    TextureAtlas second;
    std::mt19937 randomFirst(7);
    std::mt19937 randomSecond(7);
    addRandomImages(first, randomFirst, 200, 30);
    addRandomImages(second, randomSecond, 200, 30);
    REQUIRE(first.size() == second.size());
    for (std::size_t i = 0; i < first.size(); ++i) {
        CHECK(first.rectangle(i) == second.rectangle(i));
    }
    CHECK(first.image().pixels == second.image().pixels);
}

TEST_CASE("TextureAtlas grows by powers of two, keeping placed images where they were", "[scene][atlas]")
{
    TextureAtlas atlas; // 64x64, 1 px padding
    const auto small = atlas.add(patternImage(0, 10, 10, 4));
    CHECK_FALSE(small.resized);
    CHECK_FALSE(small.repacked);
    CHECK(small.changed == atlas.rectangle(0));
    const PixelRectangle before = atlas.rectangle(0);
    const std::uint64_t version = atlas.version();

    const auto wide = atlas.add(patternImage(1, 100, 10, 4));
    CHECK(wide.first == 1);
    CHECK(wide.resized);
    CHECK_FALSE(wide.repacked);
    CHECK(wide.changed == PixelRectangle{0, 0, 128, 64});
    CHECK(atlas.width() == 128);
    CHECK(atlas.height() == 64);
    CHECK(atlas.rectangle(0) == before);
    CHECK(atlas.version() > version);
    checkAtlas(atlas);

    // Texture coordinates are the rectangle over the atlas size, v growing with the row.
    const PixelRectangle r = atlas.rectangle(1);
    const TextureRectangle uv = atlas.textureCoordinates(1);
    // Exact in float: multiples of 1/128 and 1/64.
    CHECK_THAT(uv.u0, WithinAbs(r.x / 128.0, 1e-7));
    CHECK_THAT(uv.v0, WithinAbs(r.y / 64.0, 1e-7));
    CHECK_THAT(uv.u1, WithinAbs((r.x + 100) / 128.0, 1e-7));
    CHECK_THAT(uv.v1, WithinAbs((r.y + 10) / 64.0, 1e-7));
}

TEST_CASE("TextureAtlas packs everything again when the atlas cannot grow and that makes room", "[scene][atlas]")
{
    TextureAtlasOptions options;
    options.padding = 0;
    options.initialSize = 64;
    options.maxSize = 64;
    TextureAtlas atlas(options);
    // Three 20x10 images one by one go side by side along the top, leaving no column free from
    // top to bottom for a 44x64 image; packed again tallest first, they stack beside it.
    for (std::size_t i = 0; i < 3; ++i) {
        const auto result = atlas.add(patternImage(i, 20, 10, 4));
        CHECK(atlas.rectangle(i) == PixelRectangle{20 * static_cast<int>(i), 0, 20, 10});
        CHECK_FALSE(result.repacked);
    }
    const auto result = atlas.add(patternImage(3, 44, 64, 4));
    CHECK(result.repacked);
    CHECK_FALSE(result.resized);
    CHECK(result.changed == PixelRectangle{0, 0, 64, 64});
    CHECK(atlas.rectangle(3) == PixelRectangle{0, 0, 44, 64});
    CHECK(atlas.rectangle(0) == PixelRectangle{44, 0, 20, 10});
    checkAtlas(atlas);
}

TEST_CASE("TextureAtlas refuses images beyond its maximum size and stays unchanged", "[scene][atlas]")
{
    TextureAtlasOptions options;
    options.maxSize = 128;
    TextureAtlas atlas(options);
    atlas.add(patternImage(0, 60, 60, 4));
    const PixelRectangle before = atlas.rectangle(0);
    const std::uint64_t version = atlas.version();

    CHECK_THAT(test::errorMessage([&] { atlas.add(patternImage(1, 127, 10, 4)); }),
               Contains("texture atlas: image 1 (127x10) cannot fit in the maximum atlas size 128x128 with 1 px "
                        "padding"));
    std::vector<Image> many;
    for (int i = 0; i < 5; ++i) {
        many.push_back(patternImage(1 + static_cast<std::size_t>(i), 60, 60, 4));
    }
    CHECK_THAT(test::errorMessage([&] { atlas.add(many); }),
               Contains("texture atlas: 5 more image(s) do not fit beside the 1 already packed within the maximum "
                        "size 128x128"));
    CHECK_THAT(test::errorMessage([&] { atlas.add(patternImage(1, 4, 4, 3)); }),
               Contains("texture atlas: image 1 has 3 channels, the atlas 4"));
    CHECK(atlas.size() == 1);
    CHECK(atlas.rectangle(0) == before);
    CHECK(atlas.version() == version);
    CHECK(atlas.width() == 64);
    checkAtlas(atlas);

    // Three more 60x60 images do fit in 128x128.
    many.resize(3);
    atlas.add(many);
    CHECK(atlas.width() == 128);
    CHECK(atlas.height() == 128);
    checkAtlas(atlas);
}
