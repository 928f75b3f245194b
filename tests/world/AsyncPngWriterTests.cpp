#include <orbis/world/AsyncPngWriter.h>

#include <orbis/world/ImageFile.h>

#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <string>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;

namespace {

/// An image that differs in every pixel from the one of another index.
Image numbered(int index)
{
    Image image(17, 9, 4);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = static_cast<std::uint8_t>(i * 7 + static_cast<std::size_t>(index) * 31);
    }
    return image;
}

} // namespace

TEST_CASE("AsyncPngWriter writes every queued image whole, from several threads", "[world][image]")
{
    const test::TempDirectory directory;
    constexpr int kImages = 24;
    {
        AsyncPngWriter writer(3, 2);
        for (int i = 0; i < kImages; ++i) {
            writer.write(numbered(i), directory.path() / ("frame_" + std::to_string(i) + ".png"));
        }
        writer.finish();
        for (int i = 0; i < kImages; ++i) {
            const Image read = readImage(directory.path() / ("frame_" + std::to_string(i) + ".png"));
            INFO("frame " << i);
            REQUIRE(read.width == 17);
            REQUIRE(read.pixels == numbered(i).pixels);
        }
        // Usable again after finish().
        writer.write(numbered(99), directory.path() / "again.png");
    }
    // The destructor waited for the last one.
    REQUIRE(readImage(directory.path() / "again.png").pixels == numbered(99).pixels);
}

TEST_CASE("AsyncPngWriter rethrows the first failure and writes nothing more", "[world][image]")
{
    const test::TempDirectory directory;
    const std::filesystem::path blocker = directory.write("not-a-folder", "x");
    AsyncPngWriter writer(1, 1);
    writer.write(numbered(0), blocker / "first.png"); // its folder is a file
    // The failure comes back from finish() (or from a write() that found it first), naming the path.
    std::string message = "no error";
    try {
        for (int i = 1; i < 50; ++i) {
            writer.write(numbered(i), directory.path() / ("later_" + std::to_string(i) + ".png"));
        }
        writer.finish();
    } catch (const Error& error) {
        message = error.what();
    }
    CHECK_THAT(message, Contains("first.png"));
    CHECK_THROWS_AS(writer.finish(), Error); // it stays failed
    CHECK_THROWS_AS(writer.write(numbered(0), directory.path() / "after.png"), Error);
    // One thread took the failing image first: none after it was written.
    for (int i = 1; i < 50; ++i) {
        CHECK_FALSE(std::filesystem::exists(directory.path() / ("later_" + std::to_string(i) + ".png")));
    }
    CHECK_FALSE(std::filesystem::exists(directory.path() / "after.png"));
}
