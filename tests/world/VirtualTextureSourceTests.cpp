#include "ProceduralTileSource.h"

#include <orbis/core/Error.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TileSource.h>
#include <orbis/world/VirtualTextureSource.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <memory>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;

namespace {

/// What texel (i, j) of a page's slot must be (j from the slot's south edge): the pattern at that
/// texel of the page's level, the columns wrapping at the antimeridian and the rows clamped at the
/// poles, averaged over the source texels under it when the level is coarser than the source's.
std::array<int, 4> expectedTexel(const test::ProceduralTileSource& source, const VirtualTextureLayout& layout,
                                 int sourceLevelShift, const PageKey& page, int i, int j)
{
    const std::int64_t across = static_cast<std::int64_t>(VirtualTextureLayout::pagesX(page.level)) * layout.pageSize;
    const std::int64_t up = static_cast<std::int64_t>(VirtualTextureLayout::pagesY(page.level)) * layout.pageSize;
    const std::int64_t column = ((static_cast<std::int64_t>(page.x) * layout.pageSize - layout.border + i) % across + across) % across;
    const std::int64_t row = std::clamp<std::int64_t>(static_cast<std::int64_t>(page.y) * layout.pageSize - layout.border + j, 0, up - 1);
    const int wanted = static_cast<int>(page.level) + sourceLevelShift;
    const int level = std::max(wanted, static_cast<int>(source.info().minimumLevel));
    const int factor = 1 << (level - wanted);
    std::array<int, 4> sum{};
    for (int b = 0; b < factor; ++b) {
        for (int a = 0; a < factor; ++a) {
            const double u = (static_cast<double>(column * factor + a) + 0.5) / static_cast<double>(across * factor);
            const double v = (static_cast<double>(row * factor + b) + 0.5) / static_cast<double>(up * factor);
            const auto texel = test::placePattern(static_cast<std::uint32_t>(level), u, v);
            for (int c = 0; c < 4; ++c) {
                sum[c] += texel[c];
            }
        }
    }
    const int count = factor * factor;
    for (int& channel : sum) {
        channel = (channel + count / 2) / count;
    }
    return sum;
}

/// Checks every texel of a cut page against expectedTexel; returns how many differ.
int differingTexels(const test::ProceduralTileSource& tiles, VirtualTextureSource& pages, const PageKey& page)
{
    const std::optional<Image> image = pages.cutPage(page);
    REQUIRE(image);
    const VirtualTextureLayout& layout = pages.layout();
    REQUIRE(image->width == layout.slotSize());
    REQUIRE(image->height == layout.slotSize());
    const int shift = pages.sourceLevelOf(0);
    int differing = 0;
    for (int j = 0; j < layout.slotSize(); ++j) {
        for (int i = 0; i < layout.slotSize(); ++i) {
            const std::uint8_t* actual = image->pixel(i, layout.slotSize() - 1 - j);
            const std::array<int, 4> expected = expectedTexel(tiles, layout, shift, page, i, j);
            for (int c = 0; c < 4; ++c) {
                if (actual[c] != expected[c]) {
                    ++differing;
                    break;
                }
            }
        }
    }
    return differing;
}

/// 64-texel tiles (quick tests) at levels first..last.
std::shared_ptr<test::ProceduralTileSource> procedural(std::uint32_t first, std::uint32_t last,
                                                       test::ProceduralTileSourceOptions options = {})
{
    options.minimumLevel = first;
    options.maximumLevel = last;
    options.tileSize = 64;
    return std::make_shared<test::ProceduralTileSource>(std::move(options));
}

} // namespace

TEST_CASE("Pages of the tiles' size are the tiles, bordered by their neighbours' texels", "[world][virtual]")
{
    const auto tiles = procedural(0, 3);
    VirtualTextureSource pages(tiles, {.pageSize = 64, .border = 4});
    CHECK(pages.layout().finestLevel == 3);
    CHECK(pages.layout().slotSize() == 72);
    // Inside, at the antimeridian (the border wraps), at both poles (the edge rows repeat), level 0.
    for (const PageKey page : {PageKey{3, 5, 2}, PageKey{3, 0, 3}, PageKey{3, 15, 7}, PageKey{3, 7, 0}, PageKey{0, 1, 0}}) {
        INFO("page " << page.level << "/" << page.x << "/" << page.y);
        CHECK(differingTexels(*tiles, pages, page) == 0);
    }
    // The west border of the first column is the last column's east edge, one level's texels.
    const Image west = *pages.cutPage({3, 0, 3});
    const Image east = *pages.cutPage({3, 15, 3});
    for (int row = 0; row < 72; ++row) {
        REQUIRE(std::memcmp(west.pixel(3, row), east.pixel(67, row), 4) == 0); // 67: the last own column
    }
}

TEST_CASE("Pages smaller or larger than the tiles are re-cut from them", "[world][virtual]")
{
    const auto tiles = procedural(0, 3);
    SECTION("half the tile: one level deeper")
    {
        VirtualTextureSource pages(tiles, {.pageSize = 32, .border = 2});
        CHECK(pages.layout().finestLevel == 4);
        CHECK(pages.sourceLevelOf(4) == 3);
        for (const PageKey page : {PageKey{4, 11, 5}, PageKey{4, 31, 15}, PageKey{1, 2, 1}}) {
            CHECK(differingTexels(*tiles, pages, page) == 0);
        }
    }
    SECTION("twice the tile: one level shallower, four tiles a page")
    {
        VirtualTextureSource pages(tiles, {.pageSize = 128, .border = 4});
        CHECK(pages.layout().finestLevel == 2);
        CHECK(pages.sourceLevelOf(2) == 3);
        for (const PageKey page : {PageKey{2, 3, 1}, PageKey{2, 0, 0}, PageKey{0, 0, 0}}) {
            CHECK(differingTexels(*tiles, pages, page) == 0);
        }
    }
}

TEST_CASE("Levels coarser than the source's first are its first level averaged", "[world][virtual]")
{
    // 16-texel pages of 64-texel tiles: page level 0 is source level -2, four by four texels of
    // level 0 averaged; a source starting at level 1 averages deeper.
    for (const std::uint32_t first : {0u, 1u}) {
        const auto tiles = procedural(first, 3);
        VirtualTextureSource pages(tiles, {.pageSize = 16, .border = 1});
        CHECK(pages.layout().finestLevel == 5);
        for (const PageKey page : {PageKey{0, 0, 0}, PageKey{0, 1, 0}, PageKey{1, 3, 1}, PageKey{2, 4, 2}}) {
            INFO("first level " << first << ", page " << page.level << "/" << page.x << "/" << page.y);
            CHECK(differingTexels(*tiles, pages, page) == 0);
        }
    }
}

TEST_CASE("Tiles the source lacks leave a page empty, transparent or with its edge repeated", "[world][virtual]")
{
    test::ProceduralTileSourceOptions options;
    options.missing = [](const TileKey& key) { return key.level == 3 && key.x == 6 && key.y == 2; };
    const auto tiles = procedural(0, 3, options);
    SECTION("a page over a missing tile is empty")
    {
        VirtualTextureSource pages(tiles, {.pageSize = 64, .border = 4});
        CHECK_FALSE(pages.cutPage({3, 6, 2}));
        // Its neighbour's east border repeats the neighbour's own east edge.
        const Image page = *pages.cutPage({3, 5, 2});
        for (int row = 4; row < 68; ++row) {
            for (int column = 68; column < 72; ++column) {
                REQUIRE(std::memcmp(page.pixel(column, row), page.pixel(67, row), 4) == 0);
            }
        }
    }
    SECTION("a page over it and a tile the source has is transparent over the missing one")
    {
        VirtualTextureSource pages(tiles, {.pageSize = 128, .border = 4});
        const Image page = *pages.cutPage({2, 3, 1}); // tiles (3, 6..7, 2..3): (3, 6, 2) is the south-west one
        CHECK(page.pixel(10, 120)[3] == 0);           // south-west quarter
        CHECK(page.pixel(100, 120)[3] == 255);        // south-east
        CHECK(page.pixel(10, 10)[3] == 255);          // north-west
    }
}

TEST_CASE("A page over a failing tile throws, naming the tile", "[world][virtual]")
{
    test::ProceduralTileSourceOptions options;
    options.failing = [](const TileKey& key) { return key == TileKey{2, 1, 1}; };
    VirtualTextureSource pages(procedural(0, 2, options), {.pageSize = 64, .border = 2});
    CHECK_THROWS_WITH(pages.cutPage({2, 1, 1}), Contains("procedural/2/1/1.png"));
    CHECK_THROWS_WITH(pages.cutPage({2, 2, 1}), Contains("procedural/2/1/1.png")); // in its border
    CHECK(pages.cutPage({2, 5, 1}));
}

TEST_CASE("Neighbouring pages decode each tile once", "[world][virtual]")
{
    const auto tiles = procedural(0, 3);
    VirtualTextureSource pages(tiles, {.pageSize = 64, .border = 4});
    for (std::uint32_t y = 2; y <= 4; ++y) {
        for (std::uint32_t x = 5; x <= 7; ++x) {
            REQUIRE(pages.cutPage({3, x, y}));
        }
    }
    // Nine pages and their borders: the 5 x 5 tiles around them, each fetched and decoded once.
    CHECK(pages.tilesDecoded() == 25);
    CHECK(tiles->fetches() == 25);
    CHECK(pages.cacheHits() > 0);
}

TEST_CASE("A virtual texture refuses what it cannot cut pages from", "[world][virtual]")
{
    const auto tiles = procedural(0, 2);
    CHECK_THROWS_WITH(VirtualTextureSource(tiles, {.pageSize = 100}), Contains("power of two"));
    CHECK_THROWS_WITH(VirtualTextureSource(tiles, {.pageSize = 64, .border = 17}), Contains("border"));
    CHECK_THROWS_WITH(VirtualTextureSource(tiles, {.pageSize = 512}), Contains("source level 3"));
    CHECK_THROWS_WITH(VirtualTextureSource(nullptr), Contains("no tile source"));
    TileSourceOptions mercator;
    mercator.scheme = TilingScheme::webMercator();
    const std::shared_ptr<TileSource> xyz =
        openTileSource(std::string(ORBIS_SOURCE_DIR) + "/data/imagery/BlueMarble/{z}/{x}/{reverseY}.jpg", mercator);
    CHECK_THROWS_WITH(VirtualTextureSource(xyz), Contains("Web Mercator"));
}

TEST_CASE("Blue Marble pages are its tiles texel for texel", "[world][virtual]")
{
    const std::string folder = std::string(ORBIS_SOURCE_DIR) + "/data/imagery/BlueMarble";
    const std::shared_ptr<TileSource> source = openTileSource(folder);
    VirtualTextureSource pages(source, {.pageSize = 256, .border = 4});
    REQUIRE(pages.layout().finestLevel == 4);
    const Image page = *pages.cutPage({4, 17, 11});
    const TileFetch fetched = source->fetch({4, 17, 11});
    REQUIRE(fetched.status == TileFetch::Status::Ok);
    const Image tile = decodeImage(fetched.bytes, "4/17/11", 4);
    for (int row = 0; row < 256; ++row) {
        REQUIRE(std::memcmp(page.pixel(4, row + 4), tile.pixel(0, row), 256 * 4) == 0);
    }
}
