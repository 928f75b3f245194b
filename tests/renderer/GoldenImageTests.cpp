#include "GoldenImage.h"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;

namespace {

Image gradient(int width, int height)
{
    Image image(width, height, 4);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            p[0] = static_cast<std::uint8_t>(x * 16);
            p[1] = static_cast<std::uint8_t>(y * 16);
            p[2] = 128;
            p[3] = 255;
        }
    }
    return image;
}

// One per test process and test: CTest runs tests in parallel, and other checkouts may too. It
// holds the golden files and the failure images, and is removed afterwards.
struct TemporaryDirectory {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("orbis-golden-test-" + std::to_string(getpid()) + "-" +
                                  Catch::getResultCapture().getCurrentTestName().substr(0, 12));
    TemporaryDirectory()
    {
        std::filesystem::remove_all(path);
        setenv("ORBIS_GOLDEN_OUTPUT_DIR", (path / "output").c_str(), 1);
    }
    ~TemporaryDirectory()
    {
        unsetenv("ORBIS_GOLDEN_OUTPUT_DIR");
        std::filesystem::remove_all(path);
    }
};

} // namespace

TEST_CASE("A missing golden image is written and the comparison fails", "[renderer][golden]")
{
    unsetenv("ORBIS_UPDATE_GOLDEN");
    TemporaryDirectory directory;
    const Image image = gradient(8, 8);
    test::GoldenResult result = test::compareWithGolden(image, "sub/picture", {}, directory.path);
    CHECK_FALSE(result.passed);
    CHECK_THAT(result.message, Contains("no golden image: wrote"));
    REQUIRE(std::filesystem::exists(directory.path / "sub" / "picture.png"));
    // The second time, it matches.
    result = test::compareWithGolden(image, "sub/picture", {}, directory.path);
    INFO(result.message);
    CHECK(result.passed);
}

TEST_CASE("ORBIS_UPDATE_GOLDEN=1 rewrites the golden image and fails", "[renderer][golden]")
{
    TemporaryDirectory directory;
    test::compareWithGolden(gradient(8, 8), "picture", {}, directory.path);
    setenv("ORBIS_UPDATE_GOLDEN", "1", 1);
    const test::GoldenResult result = test::compareWithGolden(gradient(4, 4), "picture", {}, directory.path);
    unsetenv("ORBIS_UPDATE_GOLDEN");
    CHECK_FALSE(result.passed);
    CHECK_THAT(result.message, Contains("ORBIS_UPDATE_GOLDEN=1"));
    CHECK(readImage(directory.path / "picture.png").width == 4);
}

TEST_CASE("The golden comparison allows the stated tolerance and no more", "[renderer][golden]")
{
    unsetenv("ORBIS_UPDATE_GOLDEN");
    TemporaryDirectory directory;
    const Image golden = gradient(10, 10);
    test::compareWithGolden(golden, "tolerance", {}, directory.path);

    Image slightly = golden;
    slightly.pixel(3, 3)[0] += 2; // within 2
    CHECK(test::compareWithGolden(slightly, "tolerance", {2, 0.0}, directory.path).passed);

    Image changed = golden;
    changed.pixel(1, 1)[1] += 40; // one pixel of 100 beyond the tolerance
    CHECK_FALSE(test::compareWithGolden(changed, "tolerance", {2, 0.0}, directory.path).passed);
    CHECK(test::compareWithGolden(changed, "tolerance", {2, 0.01}, directory.path).passed);
    // The fraction is a bound: one pixel of 100 is 1 %, refused just below it, and counted.
    const test::GoldenResult failed = test::compareWithGolden(changed, "tolerance", {2, 0.0099}, directory.path);
    CHECK_FALSE(failed.passed);
    CHECK_THAT(failed.message, Contains(": 1 pixels (1 %) differ by more than 2") && Contains("largest channel difference 40"));
    // A channel tolerance above the change lets the pixel match.
    CHECK(test::compareWithGolden(changed, "tolerance", {40, 0.0}, directory.path).passed);
    CHECK_FALSE(test::compareWithGolden(changed, "tolerance", {39, 0.0}, directory.path).passed);

    const test::GoldenResult sizes = test::compareWithGolden(gradient(9, 10), "tolerance", {}, directory.path);
    CHECK_FALSE(sizes.passed);
    CHECK_THAT(sizes.message, Contains("9 x 10") && Contains("10 x 10") && Contains("actual image"));
    CHECK(std::filesystem::exists(directory.path / "output" / "tolerance.actual.png"));

    const test::ImageDifference difference = test::compareImages(changed, golden, 2);
    CHECK(difference.sameSize);
    CHECK(difference.differingPixels == 1);
    CHECK(difference.maxChannelDifference == 40);
    CHECK(difference.differingFraction == Approx(0.01));
}
