#pragma once

// Golden-image comparison for rendering tests: an Image against a reference PNG in tests/golden/,
// with a per-channel tolerance and a largest fraction of pixels allowed beyond it (edges
// rasterise differently from one GPU to another). A missing golden file, or ORBIS_UPDATE_GOLDEN=1,
// writes the file from the image and FAILS, so that a golden never passes unreviewed.

#include <orbis/world/ImageFile.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace orbis::test {

struct GoldenTolerance {
    int perChannel = 2;                ///< largest difference of one channel (0..255) that still matches
    double maxDifferingFraction = 0.0; ///< pixels allowed beyond perChannel, as a fraction of all
};

struct ImageDifference {
    bool sameSize = false;
    long differingPixels = 0;     ///< pixels with a channel differing by more than the tolerance
    int maxChannelDifference = 0; ///< over all pixels and channels
    double differingFraction = 0.0;
};

/// Compares two images of the same channel count pixel by pixel.
ImageDifference compareImages(const Image& actual, const Image& expected, int perChannel);

struct GoldenResult {
    bool passed = false;
    std::string message; ///< what was compared, the figures, and where the actual image was written
};

/// tests/golden/ of the source tree.
std::filesystem::path defaultGoldenDirectory();

/// Compares `image` with <goldenDirectory>/<name>.png. On a mismatch the image and a difference
/// image are written to $ORBIS_GOLDEN_OUTPUT_DIR, or golden-output/ in the working directory
/// (<name>.actual.png, <name>.diff.png).
GoldenResult compareWithGolden(const Image& image, std::string_view name, const GoldenTolerance& tolerance = {},
                               const std::filesystem::path& goldenDirectory = defaultGoldenDirectory());

} // namespace orbis::test

/// REQUIRE that an image matches its golden file (see compareWithGolden), printing why not.
#define ORBIS_REQUIRE_GOLDEN(image, name, ...)                                                                         \
    do {                                                                                                               \
        const ::orbis::test::GoldenResult orbisGoldenResult_ =                                                         \
            ::orbis::test::compareWithGolden((image), (name) __VA_OPT__(, ) __VA_ARGS__);                              \
        INFO(orbisGoldenResult_.message);                                                                              \
        REQUIRE(orbisGoldenResult_.passed);                                                                            \
    } while (false)
