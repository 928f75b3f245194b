#include <orbis/core/ImageMipmaps.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/core/VirtualTextureLayout.h>

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace orbis;

TEST_CASE("A virtual texture has two pages at level 0 and four times more at each level below", "[core][virtual]")
{
    const TilingScheme geographic = TilingScheme::geographic();
    std::uint64_t total = 0;
    for (std::uint32_t level = 0; level <= kMaximumVirtualTextureLevel; ++level) {
        CHECK(VirtualTextureLayout::pagesX(level) == geographic.tilesX(level));
        CHECK(VirtualTextureLayout::pagesY(level) == geographic.tilesY(level));
        CHECK(VirtualTextureLayout::pageCount(level) ==
              std::uint64_t{geographic.tilesX(level)} * geographic.tilesY(level));
        CHECK(VirtualTextureLayout::firstIndexOfLevel(level) == total);
        total += VirtualTextureLayout::pageCount(level);
        VirtualTextureLayout layout;
        layout.finestLevel = level;
        CHECK(layout.totalPageCount() == total);
    }
    VirtualTextureLayout blueMarble{256, 4, 4};
    CHECK(blueMarble.totalPageCount() == 2 + 8 + 32 + 128 + 512);
    CHECK(blueMarble.texelsX(4) == 8192);
    CHECK(blueMarble.texelsY(4) == 4096);
    CHECK(blueMarble.slotSize() == 264);
}

TEST_CASE("Page numbers run level by level and map back to their pages", "[core][virtual]")
{
    CHECK(VirtualTextureLayout::linearIndex({0, 0, 0}) == 0);
    CHECK(VirtualTextureLayout::linearIndex({0, 1, 0}) == 1);
    CHECK(VirtualTextureLayout::linearIndex({1, 0, 0}) == 2);
    CHECK(VirtualTextureLayout::linearIndex({1, 3, 1}) == 9);
    CHECK(VirtualTextureLayout::linearIndex({2, 0, 0}) == 10);
    // Every page of levels 0..7 once, in order, and back.
    std::uint64_t expected = 0;
    for (std::uint32_t level = 0; level <= 7; ++level) {
        for (std::uint32_t y = 0; y < VirtualTextureLayout::pagesY(level); ++y) {
            for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(level); ++x) {
                const PageKey page{level, x, y};
                REQUIRE(VirtualTextureLayout::linearIndex(page) == expected);
                REQUIRE(VirtualTextureLayout::pageOfIndex(expected) == page);
                ++expected;
            }
        }
    }
    // The deepest level a feedback sample names, at its far corner.
    const PageKey last{kMaximumVirtualTextureLevel, VirtualTextureLayout::pagesX(kMaximumVirtualTextureLevel) - 1,
                       VirtualTextureLayout::pagesY(kMaximumVirtualTextureLevel) - 1};
    CHECK(VirtualTextureLayout::pageOfIndex(VirtualTextureLayout::linearIndex(last)) == last);
}

TEST_CASE("A page's four children cover it and share its parent", "[core][virtual]")
{
    const std::uint32_t seed = 20261201;
    INFO("seed " << seed);
    std::mt19937 random(seed);
    for (int i = 0; i < 1000; ++i) {
        const std::uint32_t level = std::uniform_int_distribution<std::uint32_t>(0, 11)(random);
        const PageKey page{level,
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesX(level) - 1)(random),
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesY(level) - 1)(random)};
        const double u = (page.x + 0.25) / VirtualTextureLayout::pagesX(level);
        const double v = (page.y + 0.75) / VirtualTextureLayout::pagesY(level);
        REQUIRE(VirtualTextureLayout::pageAt(level, u, v) == page);
        std::set<std::uint64_t> children;
        for (int c = 0; c < 4; ++c) {
            const PageKey child = page.child(c);
            REQUIRE(child.parent() == page);
            REQUIRE(child.ancestor(0) == page.ancestor(0));
            children.insert(VirtualTextureLayout::linearIndex(child));
        }
        REQUIRE(children.size() == 4);
        // The point lies in the child holding it at the next level.
        const PageKey below = VirtualTextureLayout::pageAt(level + 1, u, v);
        REQUIRE(below.parent() == page);
        REQUIRE(below == page.child(2)); // west half, north half
    }
    // The edges: u = 1 and v = 1 are in the last column and row, beyond them clamped.
    CHECK(VirtualTextureLayout::pageAt(3, 1.0, 1.0) == PageKey{3, 15, 7});
    CHECK(VirtualTextureLayout::pageAt(3, -0.5, 2.0) == PageKey{3, 0, 7});
}

TEST_CASE("The page-table texture holds every level once, inside it, no wider than the finest level", "[core][virtual]")
{
    for (std::uint32_t finest = 0; finest <= kMaximumVirtualTextureLevel; ++finest) {
        INFO("finest level " << finest);
        const glm::uvec2 size = VirtualTextureLayout::pageTableSize(finest);
        REQUIRE(size.x == VirtualTextureLayout::pagesX(finest));
        if (finest > 7) {
            continue; // the coverage check below, entry by entry, for the smaller tables
        }
        std::vector<int> owner(std::size_t{size.x} * size.y, -1);
        for (std::uint32_t level = 0; level <= finest; ++level) {
            const glm::uvec2 origin = VirtualTextureLayout::pageTableOrigin(level, finest);
            REQUIRE(origin.x + VirtualTextureLayout::pagesX(level) <= size.x);
            REQUIRE(origin.y + VirtualTextureLayout::pagesY(level) <= size.y);
            for (std::uint32_t y = 0; y < VirtualTextureLayout::pagesY(level); ++y) {
                for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(level); ++x) {
                    int& taken = owner[std::size_t{origin.y + y} * size.x + origin.x + x];
                    REQUIRE(taken == -1);
                    taken = static_cast<int>(level);
                }
            }
        }
    }
}

TEST_CASE("Border contraction keeps positions in a page inside its slot's border", "[core][virtual]")
{
    const VirtualTextureLayout layout{128, 4, 6};
    CHECK(layout.slotSize() == 136);
    const glm::dvec2 corner = layout.contractToSlot({0.0, 0.0});
    CHECK(corner.x == Approx(4.0 / 136.0).margin(1e-15));
    const glm::dvec2 far = layout.contractToSlot({1.0, 1.0});
    CHECK(far.y == Approx(132.0 / 136.0).margin(1e-15));
    // A texel centre in the page is a texel centre in the slot, 4 texels in.
    const glm::dvec2 first = layout.contractToSlot({0.5 / 128.0, 127.5 / 128.0}) * 136.0;
    CHECK(first.x == Approx(4.5).margin(1e-12));
    CHECK(first.y == Approx(131.5).margin(1e-12));
    // A bilinear footprint one texel either side of the page's edge stays in the slot.
    for (const int border : {1, 2, 4}) {
        const VirtualTextureLayout bordered{256, border, 4};
        const double outside = -static_cast<double>(border) / 256.0; // border texels beyond the page's edge
        CHECK(bordered.contractToSlot({outside, 0.0}).x == Approx(0.0).margin(1e-15));
        CHECK(bordered.contractToSlot({1.0 - outside, 0.0}).x == Approx(1.0).margin(1e-15));
    }
    // And back.
    const glm::dvec2 position{0.3, 0.9};
    const glm::dvec2 round = layout.expandFromSlot(layout.contractToSlot(position));
    CHECK(round.x == Approx(position.x).margin(1e-15));
    CHECK(round.y == Approx(position.y).margin(1e-15));
}

TEST_CASE("Feedback samples pack into 32 bits and unpack to the same page", "[core][virtual]")
{
    CHECK(packFeedback({}) == 0u);
    CHECK_FALSE(unpackFeedback(0u).covered);
    const FeedbackSample sample{true, true, {4, 31, 15}};
    const std::uint32_t bits = packFeedback(sample);
    CHECK(bits == (31u | (15u << 13) | (4u << 26) | (1u << 30) | (1u << 31)));
    CHECK(unpackFeedback(bits) == sample);
    // Every level to the deepest, its far corner, with and without a fallback.
    for (std::uint32_t level = 0; level <= kMaximumVirtualTextureLevel; ++level) {
        for (const bool fallback : {false, true}) {
            const FeedbackSample corner{true, fallback,
                                        {level, VirtualTextureLayout::pagesX(level) - 1, VirtualTextureLayout::pagesY(level) - 1}};
            REQUIRE(unpackFeedback(packFeedback(corner)) == corner);
            const FeedbackSample origin{true, fallback, {level, 0, 0}};
            REQUIRE(unpackFeedback(packFeedback(origin)) == origin);
            REQUIRE(packFeedback(origin) != 0u);
        }
    }
    // As bytes in an RGBA8 pixel: red the lowest byte.
    const std::uint8_t rgba[4] = {static_cast<std::uint8_t>(bits), static_cast<std::uint8_t>(bits >> 8),
                                  static_cast<std::uint8_t>(bits >> 16), static_cast<std::uint8_t>(bits >> 24)};
    const std::uint32_t fromBytes = rgba[0] | (rgba[1] << 8) | (rgba[2] << 16) | (static_cast<std::uint32_t>(rgba[3]) << 24);
    CHECK(unpackFeedback(fromBytes) == sample);
}

TEST_CASE("The mip tail's levels are level 0's mipmaps, side by side in a strip without overlapping", "[core][virtual]")
{
    for (const int pageSize : {16, 64, 128, 256}) {
        for (const int border : {0, 1, 4}) {
            INFO("page size " << pageSize << ", border " << border);
            const VirtualTextureLayout layout{pageSize, border, 3};
            // The sizes mipmapChain makes of level 0 (two pages side by side), down to 1 x 1.
            Image level0(2 * pageSize, pageSize, 4);
            const std::vector<Image> chain = mipmapChain(level0);
            REQUIRE(layout.tailLevels() == static_cast<int>(chain.size()));
            int end = 0; // where the regions so far end across the strip
            for (int t = 1; t <= layout.tailLevels(); ++t) {
                const glm::ivec2 size = layout.tailSize(t);
                CHECK(size.x == chain[static_cast<std::size_t>(t) - 1].width);
                CHECK(size.y == chain[static_cast<std::size_t>(t) - 1].height);
                CHECK(layout.tailOffset(t) == end); // next to the one before, no gap, no overlap
                end += size.x + 2 * border;
                CHECK(size.y + 2 * border <= layout.tailStripSize().y);
            }
            CHECK(layout.tailSize(layout.tailLevels()) == glm::ivec2(1, 1));
            CHECK(layout.tailStripSize().x == end);
        }
    }
}
