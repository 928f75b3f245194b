#include "SceneTestSupport.h"

#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/scene/Globe.h>

#include <catch2/catch.hpp>

#include <filesystem>

#include <unistd.h>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::scene;
using namespace orbis::test;
using Catch::Matchers::Contains;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

/// 256 x 128: green within 10% of the antimeridian and in the top five rows (the cap north of
/// 83 degrees), magenta elsewhere. A seam, or a pole blurred by the converging meridians, shows
/// as the mixture: the coarse mipmap levels are mostly magenta.
std::filesystem::path writeSeamTexture()
{
    Image image(256, 128, 4);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const bool green = x < 26 || x >= 230 || y < 5;
            std::uint8_t* p = image.pixel(x, y);
            p[0] = green ? 0 : 255;
            p[1] = green ? 255 : 0;
            p[2] = green ? 0 : 255;
            p[3] = 255;
        }
    }
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("orbis-seam-" + std::to_string(::getpid()) + ".png");
    writePng(image, path);
    return path;
}

Image renderGlobeFrom(const Geodetic3D& eye, const std::filesystem::path& texture, int size)
{
    GlobeOptions options;
    options.dayTexture = texture;
    Scene scene(kEarth);
    scene.add(std::make_shared<Globe>(kEarth, options));
    scene.camera().lookAt(kEarth.toCartesian(eye), glm::dvec3(0.0), std::abs(eye.latitude) > 1.5 ? glm::dvec3(1, 0, 0)
                                                                                                  : glm::dvec3(0, 0, 1));
    return renderFrame(scene, size, size).image;
}

} // namespace

TEST_CASE("The globe's texture shows no seam at the antimeridian and stays sharp at the pole", "[scene][globe]")
{
    const std::filesystem::path texture = writeSeamTexture();
    const int size = 128;
    // Looking at the antimeridian, stepped by quarter pixels so that some 2x2 pixel quad (where
    // the GPU takes derivatives) straddles it: the centre columns show longitude 180.
    for (const double offsetDegrees : {0.0, 0.3, 0.6, 0.9}) {
        const Image seam = renderGlobeFrom(Geodetic3D::fromDegrees(180 - offsetDegrees, 0, 2e7), texture, size);
        for (int y = size / 2 - 20; y <= size / 2 + 20; ++y) {
            for (int x = size / 2 - 3; x <= size / 2 + 3; ++x) {
                INFO("offset " << offsetDegrees << " pixel " << describePixel(seam, x, y));
                REQUIRE(pixelNear(seam, x, y, {0, 255, 0, 255}, 24));
            }
        }
    }

    // Straight down on the north pole: its surroundings (the green cap) stay green.
    const Image pole = renderGlobeFrom(Geodetic3D::fromDegrees(0, 90, 2e7), texture, size);
    for (int y = size / 2 - 1; y <= size / 2 + 1; ++y) {
        for (int x = size / 2 - 1; x <= size / 2 + 1; ++x) {
            INFO("pixel " << describePixel(pole, x, y));
            REQUIRE(pixelNear(pole, x, y, {0, 255, 0, 255}, 24));
        }
    }
    std::filesystem::remove(texture);
}

