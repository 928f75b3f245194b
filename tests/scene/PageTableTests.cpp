#include <orbis/scene/PageTable.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>

using namespace orbis;
using namespace orbis::scene;

namespace {

/// What an entry must say, worked out from scratch: the page's nearest mapped ancestor (itself
/// included) and its slot.
std::optional<std::pair<PageKey, std::pair<int, int>>> expectedEntry(const std::map<PageKey, std::pair<int, int>>& mapped,
                                                                     const PageKey& page)
{
    for (std::uint32_t level = page.level + 1; level-- > 0;) {
        const auto found = mapped.find(page.ancestor(level));
        if (found != mapped.end()) {
            return std::pair(found->first, found->second);
        }
    }
    return std::nullopt;
}

/// Every entry of the table against expectedEntry.
void checkEveryEntry(const PageTable& table, const std::map<PageKey, std::pair<int, int>>& mapped)
{
    for (std::uint32_t level = 0; level <= table.finestLevel(); ++level) {
        for (std::uint32_t y = 0; y < VirtualTextureLayout::pagesY(level); ++y) {
            for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(level); ++x) {
                const PageKey page{level, x, y};
                const PageTableEntry& entry = table.entry(page);
                const auto expected = expectedEntry(mapped, page);
                INFO("page " << level << "/" << x << "/" << y);
                if (!expected) {
                    REQUIRE_FALSE(entry.flags & PageTableEntry::kValid);
                    continue;
                }
                REQUIRE(entry.flags & PageTableEntry::kValid);
                REQUIRE(entry.level == expected->first.level);
                REQUIRE(entry.slotX == expected->second.first);
                REQUIRE(entry.slotY == expected->second.second);
                REQUIRE(table.isMapped(page) == (expected->first == page));
            }
        }
    }
}

} // namespace

TEST_CASE("Mapping a page points the entries below it at its slot until a mapped page", "[scene][virtual]")
{
    PageTable table(3);
    CHECK_FALSE(table.entry({3, 5, 2}).flags & PageTableEntry::kValid);
    table.map({0, 0, 0}, 1, 2);
    table.map({0, 1, 0}, 3, 4);
    std::map<PageKey, std::pair<int, int>> mapped{{{0, 0, 0}, {1, 2}}, {{0, 1, 0}, {3, 4}}};
    checkEveryEntry(table, mapped);
    // Level 0 maps the whole of every level: all of it changed.
    CHECK(table.dirty(3) == PageRectangle{0, 0, 16, 8});
    table.clearDirty();
    CHECK_FALSE(table.dirty(3));

    table.map({2, 3, 1}, 5, 6);
    mapped[{2, 3, 1}] = {5, 6};
    checkEveryEntry(table, mapped);
    // The page's extent at each level below it, and nothing above.
    CHECK_FALSE(table.dirty(1));
    CHECK(table.dirty(2) == PageRectangle{3, 1, 4, 2});
    CHECK(table.dirty(3) == PageRectangle{6, 2, 8, 4});

    // A page mapped under another stops the propagation of a coarser one mapped later.
    table.map({3, 6, 2}, 7, 8);
    table.map({1, 1, 0}, 9, 9);
    mapped[{3, 6, 2}] = {7, 8};
    mapped[{1, 1, 0}] = {9, 9};
    checkEveryEntry(table, mapped);
    CHECK(table.entry({3, 6, 2}).level == 3);
    CHECK(table.entry({3, 7, 2}).level == 2);
    CHECK(table.entry({3, 4, 2}).level == 1);
    CHECK(table.mappedCount() == 5);
}

TEST_CASE("Unmapping a page points its entries at its own fallback, not past a mapped page", "[scene][virtual]")
{
    PageTable table(3);
    std::map<PageKey, std::pair<int, int>> mapped;
    for (const auto& [page, slot] : std::map<PageKey, std::pair<int, int>>{
             {{0, 0, 0}, {0, 0}}, {{1, 1, 0}, {1, 0}}, {{2, 2, 1}, {2, 0}}, {{3, 4, 2}, {3, 0}}, {{3, 5, 3}, {4, 0}}}) {
        table.map(page, static_cast<std::uint8_t>(slot.first), static_cast<std::uint8_t>(slot.second));
        mapped[page] = slot;
    }
    checkEveryEntry(table, mapped);
    table.unmap({2, 2, 1}); // its two mapped children stay; the rest falls back to level 1
    mapped.erase({2, 2, 1});
    checkEveryEntry(table, mapped);
    CHECK(table.entry({3, 5, 2}).level == 1);
    CHECK(table.entry({3, 4, 2}).level == 3);
    table.unmap({1, 1, 0});
    mapped.erase({1, 1, 0});
    checkEveryEntry(table, mapped);
    CHECK(table.entry({2, 2, 1}).level == 0);
    table.unmap({1, 1, 0}); // not mapped: nothing happens
    checkEveryEntry(table, mapped);
    // A root: nothing left to fall back to, except under the mapped pages.
    table.unmap({0, 0, 0});
    mapped.erase({0, 0, 0});
    checkEveryEntry(table, mapped);
    CHECK(table.mappedCount() == 2);
}

TEST_CASE("Random mapping and unmapping keeps every entry at its nearest mapped ancestor", "[scene][virtual]")
{
    const std::uint32_t seed = 4242;
    INFO("seed " << seed);
    std::mt19937 random(seed);
    PageTable table(4);
    std::map<PageKey, std::pair<int, int>> mapped;
    for (int step = 0; step < 400; ++step) {
        const std::uint32_t level = std::uniform_int_distribution<std::uint32_t>(0, 4)(random);
        const PageKey page{level, std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesX(level) - 1)(random),
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesY(level) - 1)(random)};
        if (mapped.contains(page) && random() % 2 == 0) {
            table.unmap(page);
            mapped.erase(page);
        } else if (!mapped.contains(page)) {
            const int slot = step % 200;
            table.map(page, static_cast<std::uint8_t>(slot % 16), static_cast<std::uint8_t>(slot / 16));
            mapped[page] = {slot % 16, slot / 16};
        }
        if (step % 50 == 49) {
            checkEveryEntry(table, mapped);
        }
    }
    checkEveryEntry(table, mapped);
    CHECK(table.mappedCount() == mapped.size());
}

TEST_CASE("A missing page marks itself and everything below, keeping their fallback", "[scene][virtual]")
{
    PageTable table(3);
    table.map({0, 0, 0}, 0, 0);
    table.map({1, 0, 0}, 1, 0);
    table.clearDirty();
    table.markMissing({2, 1, 1});
    CHECK(table.isMissing({2, 1, 1}));
    CHECK(table.isMissing({3, 3, 3}));
    CHECK_FALSE(table.isMissing({2, 0, 1}));
    CHECK_FALSE(table.isMissing({1, 0, 0}));
    CHECK(table.entry({3, 3, 3}).level == 1);
    CHECK(table.dirty(3) == PageRectangle{2, 2, 4, 4});
    // Mapping above keeps the mark.
    table.unmap({1, 0, 0});
    CHECK(table.isMissing({3, 2, 2}));
    CHECK(table.entry({3, 2, 2}).level == 0);
}

TEST_CASE("The texels of the dirty rectangles keep a copy of the page table equal to the table, parents' entries included",
          "[scene][virtual]")
{
    // As the GPU's copy is kept: only the rectangles marked dirty are copied after each change.
    // Each texel carries its parent's entry too, which changes when the parent's subtree does.
    const std::uint32_t seed = 9001;
    INFO("seed " << seed);
    std::mt19937 random(seed);
    const std::uint32_t finest = 4;
    PageTable table(finest);
    auto allTexels = [&](std::uint32_t level) {
        std::vector<float> texels;
        table.texels(level, {0, 0, VirtualTextureLayout::pagesX(level), VirtualTextureLayout::pagesY(level)}, texels);
        return texels;
    };
    std::vector<std::vector<float>> copy;
    for (std::uint32_t level = 0; level <= finest; ++level) {
        copy.push_back(allTexels(level));
    }
    table.clearDirty();
    std::vector<float> rectangle;
    for (int step = 0; step < 300; ++step) {
        const std::uint32_t level = std::uniform_int_distribution<std::uint32_t>(0, finest)(random);
        const PageKey page{level, std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesX(level) - 1)(random),
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesY(level) - 1)(random)};
        const int action = static_cast<int>(random() % 8);
        if (action == 0) {
            table.markMissing(page);
        } else if (table.isMapped(page) && action < 4) {
            table.unmap(page);
        } else {
            table.map(page, static_cast<std::uint8_t>(step % 17), static_cast<std::uint8_t>(step % 13));
        }
        for (std::uint32_t l = 0; l <= finest; ++l) {
            const std::optional<PageRectangle>& dirty = table.dirty(l);
            if (!dirty) {
                continue;
            }
            table.texels(l, *dirty, rectangle);
            const std::uint32_t columns = VirtualTextureLayout::pagesX(l);
            std::size_t k = 0;
            for (std::uint32_t y = dirty->y0; y < dirty->y1; ++y) {
                for (std::uint32_t x = dirty->x0; x < dirty->x1; ++x, k += 2) {
                    std::copy_n(rectangle.begin() + static_cast<std::ptrdiff_t>(k), 2,
                                copy[l].begin() + static_cast<std::ptrdiff_t>(2 * (std::size_t{y} * columns + x)));
                }
            }
        }
        table.clearDirty();
        for (std::uint32_t l = 0; l <= finest; ++l) {
            INFO("step " << step << ", level " << l);
            REQUIRE(copy[l] == allTexels(l));
        }
    }
    // A texel spelled out: a page of level 2 under a mapped root shows the root, and so does its
    // parent's entry beside it.
    PageTable fresh(2);
    fresh.map({0, 1, 0}, 3, 5);
    std::vector<float> texel;
    fresh.texels(2, {4, 1, 5, 2}, texel);
    const auto encoded = [](int slotX, int slotY, int level, int flags) {
        return static_cast<float>(slotX + 256 * slotY + 65536 * level + 2097152 * flags);
    };
    const float root = encoded(3, 5, 0, PageTableEntry::kValid);
    CHECK(texel == std::vector<float>{root, root});
    fresh.map({1, 2, 0}, 7, 1);
    fresh.texels(2, {4, 1, 5, 2}, texel);
    // Now both show the level-1 page, which the parent is (mapped) and the page falls back to.
    CHECK(texel == std::vector<float>{encoded(7, 1, 1, PageTableEntry::kValid),
                                      encoded(7, 1, 1, PageTableEntry::kValid | PageTableEntry::kMapped)});
    fresh.markMissing({2, 4, 1});
    fresh.texels(2, {4, 1, 5, 2}, texel);
    CHECK(texel[0] == encoded(7, 1, 1, PageTableEntry::kValid | PageTableEntry::kMissing));
}

TEST_CASE("Each page's neighbours' resident levels are packed beside its own, kept true as reds change",
          "[scene][virtual]")
{
    const std::uint32_t width = 16, height = 8;
    std::mt19937 random(7);
    std::uniform_int_distribution<int> level(0, 12);
    std::vector<glm::vec4> texels(width * height);
    for (glm::vec4& texel : texels) {
        texel.r = static_cast<float>(level(random));
    }
    CHECK(packResidencyNeighbours(texels, width, height, {0, 0, width, height}) == PageRectangle{0, 0, width, height});
    // Page (x, y)'s neighbour dx, dy from scratch: the antimeridian wraps, a pole repeats the row.
    auto red = [&](int x, int y) {
        const int column = (x + static_cast<int>(width)) % static_cast<int>(width);
        const int row = std::clamp(y, 0, static_cast<int>(height) - 1);
        return static_cast<std::uint32_t>(texels[static_cast<std::size_t>(row) * width + column].r);
    };
    auto checkAll = [&]() {
        for (int y = 0; y < static_cast<int>(height); ++y) {
            for (int x = 0; x < static_cast<int>(width); ++x) {
                const glm::vec4& texel = texels[static_cast<std::size_t>(y) * width + x];
                const auto sides = static_cast<std::uint32_t>(texel.b);
                const auto corners = static_cast<std::uint32_t>(texel.a);
                INFO("page " << x << ", " << y);
                REQUIRE((sides & 15) == red(x + 1, y));
                REQUIRE(((sides >> 4) & 15) == red(x - 1, y));
                REQUIRE(((sides >> 8) & 15) == red(x, y + 1));
                REQUIRE(((sides >> 12) & 15) == red(x, y - 1));
                REQUIRE(((sides >> 16) & 15) == red(x + 1, y + 1));
                REQUIRE(((sides >> 20) & 15) == red(x - 1, y + 1));
                REQUIRE((corners & 15) == red(x + 1, y - 1));
                REQUIRE(((corners >> 4) & 15) == red(x - 1, y - 1));
            }
        }
    };
    checkAll();
    // Reds changed in a rectangle, and only its repacking asked for: every page stays true.
    std::uniform_int_distribution<std::uint32_t> column(0, width - 1), row(0, height - 1);
    for (int round = 0; round < 200; ++round) {
        std::uint32_t x0 = column(random), x1 = column(random), y0 = row(random), y1 = row(random);
        const PageRectangle changed{std::min(x0, x1), std::min(y0, y1), std::max(x0, x1) + 1, std::max(y0, y1) + 1};
        for (std::uint32_t y = changed.y0; y < changed.y1; ++y) {
            for (std::uint32_t x = changed.x0; x < changed.x1; ++x) {
                texels[y * width + x].r = static_cast<float>(level(random));
            }
        }
        const PageRectangle repacked = packResidencyNeighbours(texels, width, height, changed);
        INFO("round " << round);
        CHECK(repacked.x0 <= changed.x0);
        CHECK(repacked.x1 >= changed.x1);
        checkAll();
    }
}
