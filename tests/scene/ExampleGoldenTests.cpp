// Each chapter example and `orbis render`, run as a user runs them (small, for speed), against a
// golden image. Built only with the examples (ORBIS_EXAMPLE_DIR).
#ifdef ORBIS_EXAMPLE_DIR

#include "GoldenImage.h"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

using namespace orbis;
using namespace orbis::world;

namespace {

Image runExample(const std::string& command, const std::string& name)
{
    const std::filesystem::path output = std::filesystem::temp_directory_path() /
                                         ("orbis-" + name + "-" + std::to_string(::getpid()) + ".png");
    const std::string line = std::string(ORBIS_EXAMPLE_DIR) + "/" + command + " --out " + output.string() +
                             " --width 160 --height 120 > /dev/null";
    INFO(line);
    REQUIRE(std::system(line.c_str()) == 0);
    Image image = readImage(output);
    std::filesystem::remove(output);
    return image;
}

// llvmpipe renders the same pixels every run; a GPU may differ at edges and in filtering.
const test::GoldenTolerance kTolerance{4, 0.01};

} // namespace

TEST_CASE("The chapter 4 examples render their golden images", "[scene][golden][examples]")
{
    for (const char* example :
         {"ch04_subdivision_sphere", "ch04_globe_ray_casting", "ch04_night_lights", "ch04_latitude_longitude_grid"}) {
        INFO(example);
        ORBIS_REQUIRE_GOLDEN(runExample(example, example), std::string("scene/") + example, kTolerance);
    }
}

TEST_CASE("The chapter 5 and 6 examples render their golden images", "[scene][golden][examples]")
{
    // Six tiles of 160 x 120 each: every vertex transform, every depth strategy.
    for (const char* example : {"ch05_jitter", "ch06_depth_buffer_precision"}) {
        INFO(example);
        ORBIS_REQUIRE_GOLDEN(runExample(example, example), std::string("scene/") + example, kTolerance);
    }
}

TEST_CASE("The chapter 7 and 8 examples render their golden images", "[scene][golden][examples]")
{
    for (const char* example : {"ch07_vector_data", "ch08_polygons"}) {
        INFO(example);
        ORBIS_REQUIRE_GOLDEN(runExample(example, example), std::string("scene/") + example, kTolerance);
    }
}

TEST_CASE("The chapter 9 example renders its golden image", "[scene][golden][examples]")
{
    ORBIS_REQUIRE_GOLDEN(runExample("ch09_billboards", "ch09_billboards"), "scene/ch09_billboards", kTolerance);
}

TEST_CASE("The chapter 11 example renders its golden image: an 80 m DEM lit, coloured by height and slope, hillshaded",
          "[scene][golden][examples][terrain]")
{
    ORBIS_REQUIRE_GOLDEN(runExample("ch11_terrain_shading", "ch11_terrain_shading"), "scene/ch11_terrain_shading",
                         kTolerance);
}

TEST_CASE("The chapter 13 example renders its golden image: clipmap levels coloured, shaded, and from near the North Pole",
          "[scene][golden][examples][terrain][clipmap]")
{
    ORBIS_REQUIRE_GOLDEN(runExample("ch13_clipmap", "ch13_clipmap"), "scene/ch13_clipmap", kTolerance);
}

TEST_CASE("The chapter 12 example renders its golden image: a view's tiles by level, then their boxes and the frustum "
          "from outside",
          "[scene][golden][examples][terrain]")
{
    ORBIS_REQUIRE_GOLDEN(runExample("ch12_levels_and_culling", "ch12_levels_and_culling"), "scene/ch12_levels_and_culling",
                         kTolerance);
}

TEST_CASE("The chapter 14 example renders its golden image: tiles by level over ETOPO5, then imagery at two errors",
          "[scene][golden][examples][terrain]")
{
    ORBIS_REQUIRE_GOLDEN(runExample("ch14_chunked_lod", "ch14_chunked_lod"), "scene/ch14_chunked_lod", kTolerance);
}

TEST_CASE("The virtual texturing example renders its golden image and the three pictures of its machinery",
          "[scene][golden][examples]")
{
    const std::filesystem::path folder = std::filesystem::temp_directory_path() /
                                         ("orbis-ch_virtual_texturing-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    const std::string line = std::string(ORBIS_EXAMPLE_DIR) + "/ch_virtual_texturing --out " +
                             (folder / "vt.png").string() + " --width 160 --height 120 > /dev/null";
    INFO(line);
    REQUIRE(std::system(line.c_str()) == 0);
    ORBIS_REQUIRE_GOLDEN(readImage(folder / "vt.png"), "scene/ch_virtual_texturing", kTolerance);
    // 64 slots of 256 + 2 x 4 texels, 8 a side, and the mip tail's strip (128 + 2 x 4 texels
    // high) above them; the page table's 32 x 16 pages at 16 pixels each; the quarter-resolution
    // feedback (40 x 30) enlarged back to the view.
    const Image physical = readImage(folder / "vt-physical.png");
    CHECK((physical.width == 8 * 264 && physical.height == 8 * 264 + 136));
    const Image pageTable = readImage(folder / "vt-page-table.png");
    CHECK((pageTable.width == 32 * 16 && pageTable.height == 16 * 16));
    const Image feedback = readImage(folder / "vt-feedback.png");
    CHECK((feedback.width == 160 && feedback.height == 120));
    std::filesystem::remove_all(folder);
}

TEST_CASE("orbis render draws the default Earth as its golden image", "[scene][golden][examples]")
{
    ORBIS_REQUIRE_GOLDEN(runExample("orbis render", "render-default"), "scene/orbis_render_default", kTolerance);
}

TEST_CASE("orbis render draws a GeoJSON layer draped over the Cumberland DEM as its golden image",
          "[scene][golden][examples][terrain]")
{
    // data/scenes/draped.json: a translucent fill on the hillshaded ridges, its outline and a line clamped to them.
    ORBIS_REQUIRE_GOLDEN(runExample("orbis render draped", "render-draped"), "scene/orbis_render_draped", kTolerance);
}

#endif
