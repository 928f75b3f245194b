#include "GoldenImage.h"

#include <orbis/core/Error.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <sstream>

using namespace orbis::world;

namespace orbis::test {

ImageDifference compareImages(const Image& actual, const Image& expected, int perChannel)
{
    ImageDifference difference;
    difference.sameSize = actual.width == expected.width && actual.height == expected.height &&
                          actual.channels == expected.channels;
    if (!difference.sameSize) {
        return difference;
    }
    const long pixels = static_cast<long>(actual.width) * actual.height;
    for (long i = 0; i < pixels; ++i) {
        bool differs = false;
        for (int c = 0; c < actual.channels; ++c) {
            const std::size_t k = static_cast<std::size_t>(i) * actual.channels + c;
            const int d = std::abs(int(actual.pixels[k]) - int(expected.pixels[k]));
            difference.maxChannelDifference = std::max(difference.maxChannelDifference, d);
            differs = differs || d > perChannel;
        }
        difference.differingPixels += differs ? 1 : 0;
    }
    difference.differingFraction = pixels > 0 ? double(difference.differingPixels) / double(pixels) : 0.0;
    return difference;
}

std::filesystem::path defaultGoldenDirectory()
{
    return std::filesystem::path(ORBIS_SOURCE_DIR) / "tests" / "golden";
}

namespace {

Image differenceImage(const Image& actual, const Image& expected)
{
    // Grey copy of the expected image with the differing pixels in red, brighter for larger
    // differences.
    Image diff(actual.width, actual.height, 4);
    for (int y = 0; y < actual.height; ++y) {
        for (int x = 0; x < actual.width; ++x) {
            const std::uint8_t* a = actual.pixel(x, y);
            const std::uint8_t* e = expected.pixel(x, y);
            int d = 0;
            int grey = 0;
            for (int c = 0; c < std::min(actual.channels, 3); ++c) {
                d = std::max(d, std::abs(int(a[c]) - int(e[c])));
                grey += e[c];
            }
            grey /= std::max(1, std::min(actual.channels, 3));
            std::uint8_t* out = diff.pixel(x, y);
            out[0] = d > 0 ? std::uint8_t(std::min(255, 128 + d)) : std::uint8_t(grey / 3);
            out[1] = d > 0 ? 0 : std::uint8_t(grey / 3);
            out[2] = d > 0 ? 0 : std::uint8_t(grey / 3);
            out[3] = 255;
        }
    }
    return diff;
}

std::filesystem::path outputPath(std::string_view name, const char* suffix)
{
    const char* directory = std::getenv("ORBIS_GOLDEN_OUTPUT_DIR");
    const std::filesystem::path base = directory && *directory ? std::filesystem::path(directory)
                                                                : std::filesystem::current_path() / "golden-output";
    std::filesystem::path path = base / (std::string(name) + suffix);
    std::filesystem::create_directories(path.parent_path());
    return path;
}

} // namespace

GoldenResult compareWithGolden(const Image& image, std::string_view name, const GoldenTolerance& tolerance,
                               const std::filesystem::path& goldenDirectory)
{
    GoldenResult result;
    const std::filesystem::path golden = goldenDirectory / (std::string(name) + ".png");
    const char* update = std::getenv("ORBIS_UPDATE_GOLDEN");
    const bool updating = update && std::strcmp(update, "1") == 0;
    if (updating || !std::filesystem::exists(golden)) {
        std::filesystem::create_directories(golden.parent_path());
        writePng(image, golden);
        result.message = std::string(updating ? "ORBIS_UPDATE_GOLDEN=1: wrote " : "no golden image: wrote ") +
                         golden.string() + "; look at it, commit it if it is right, and run the test again";
        return result;
    }
    Image expected;
    try {
        expected = readImage(golden, image.channels);
    } catch (const Error& error) {
        result.message = error.what();
        return result;
    }
    const ImageDifference difference = compareImages(image, expected, tolerance.perChannel);
    std::ostringstream message;
    if (!difference.sameSize) {
        message << name << ": the image is " << image.width << " x " << image.height << ", the golden "
                << expected.width << " x " << expected.height;
    } else {
        message << name << ": " << difference.differingPixels << " pixels ("
                << difference.differingFraction * 100.0 << " %) differ by more than " << tolerance.perChannel
                << " (allowed: " << tolerance.maxDifferingFraction * 100.0
                << " %); largest channel difference " << difference.maxChannelDifference;
    }
    result.passed = difference.sameSize && difference.differingFraction <= tolerance.maxDifferingFraction;
    if (!result.passed) {
        const std::filesystem::path actualPath = outputPath(name, ".actual.png");
        writePng(image, actualPath);
        message << "; actual image: " << actualPath.string();
        if (difference.sameSize) {
            const std::filesystem::path diffPath = outputPath(name, ".diff.png");
            writePng(differenceImage(image, expected), diffPath);
            message << ", difference: " << diffPath.string();
        }
    }
    result.message = message.str();
    return result;
}

} // namespace orbis::test
