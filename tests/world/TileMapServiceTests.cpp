#include "TempFiles.h"

#include <orbis/core/Error.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TileMapResource.h>
#include <orbis/world/TileMapService.h>

#include <catch2/catch.hpp>

#include <array>

using namespace orbis;
using namespace orbis::world;
using orbis::test::TempDirectory;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kImagery = std::filesystem::path(ORBIS_SOURCE_DIR) / "data/imagery";

/// The RGB of the mosaic's pixel at a longitude and latitude (degrees).
std::array<int, 3> at(const Image& mosaic, double longitudeDegrees, double latitudeDegrees)
{
    const int x = static_cast<int>((longitudeDegrees + 180.0) / 360.0 * mosaic.width);
    const int y = static_cast<int>((90.0 - latitudeDegrees) / 180.0 * mosaic.height);
    return {mosaic.pixel(x, y)[0], mosaic.pixel(x, y)[1], mosaic.pixel(x, y)[2]};
}

} // namespace

TEST_CASE("The Natural Earth and Blue Marble pyramids join into north-up equirectangular images", "[world][tms]")
{
    for (const char* name : {"NaturalEarthII", "BlueMarble"}) {
        INFO(name);
        const Image mosaic = readTileMapMosaic(kImagery / name);
        const int expectedWidth = std::string(name) == "BlueMarble" ? 8192 : 2048;
        REQUIRE(mosaic.width == expectedWidth);
        REQUIRE(mosaic.height == expectedWidth / 2);
        const auto sahara = at(mosaic, 10, 23);
        const auto pacific = at(mosaic, -150, 0);
        const auto antarctica = at(mosaic, 40, -80);
        INFO("sahara " << sahara[0] << "," << sahara[1] << "," << sahara[2] << " pacific " << pacific[0] << ","
                       << pacific[1] << "," << pacific[2]);
        REQUIRE(sahara[0] > sahara[2] + 20);   // pale sand: red over blue
        REQUIRE(pacific[2] > pacific[0] + 10); // ocean: blue over red
        REQUIRE(antarctica[0] > 180);          // ice, at the bottom: the rows are not upside down
        REQUIRE(readTileMapMosaic(kImagery / name, 0).width == 512);
    }
}

TEST_CASE("A bad TMS folder is reported with the file and the problem, before anything is allocated", "[world][tms][hostile]")
{
    REQUIRE_THROWS_WITH(readTileMapMosaic("/nonexistent/pyramid"), Contains("/nonexistent/pyramid: no such file or folder"));
    REQUIRE_THROWS_WITH(readTileMapMosaic(kImagery / "NaturalEarthII", 7), Contains("level 7 is not in the pyramid (0..2)"));

    // A valid description of 4096-pixel tiles down to level 12: the mosaic would be 2^25 pixels wide.
    const TempDirectory folder;
    TileMapResource resource;
    resource.tileWidth = resource.tileHeight = 4096;
    for (std::uint32_t level = 0; level <= 12; ++level) {
        resource.tileSets.push_back({std::to_string(level), level, tileMapUnitsPerPixel(resource.scheme, level, 4096)});
    }
    writeFileAtomically(folder.path() / "huge/tilemapresource.xml", formatTileMapResource(resource));
    REQUIRE_THROWS_WITH(readTileMapMosaic(folder.path() / "huge"),
                        Contains("level 12 joins into 33554432x16777216 pixels, more than the 16384 a side allowed"));

    // A pyramid with a tile missing, and one with a tile of the wrong size.
    resource.tileWidth = resource.tileHeight = 16;
    resource.tileSets = {{"0", 0, tileMapUnitsPerPixel(resource.scheme, 0, 16)}};
    writeFileAtomically(folder.path() / "holes/tilemapresource.xml", formatTileMapResource(resource));
    Image tile(16, 16, 3);
    writeFileAtomically(folder.path() / "holes/0/0/0.jpg", encodeJpeg(tile, 90));
    REQUIRE_THROWS_WITH(readTileMapMosaic(folder.path() / "holes"), Contains("holes/0/1/0.jpg: no such tile"));
    writeFileAtomically(folder.path() / "holes/0/1/0.jpg", encodeJpeg(Image(8, 16, 3), 90));
    REQUIRE_THROWS_WITH(readTileMapMosaic(folder.path() / "holes"), Contains("holes/0/1/0.jpg: a 8x16 tile, expected 16x16"));
    writeFileAtomically(folder.path() / "holes/0/1/0.jpg", std::string_view("<html>"));
    REQUIRE_THROWS_WITH(readTileMapMosaic(folder.path() / "holes"), Contains("holes/0/1/0.jpg: not a JPEG, PNG or WebP image"));
}
