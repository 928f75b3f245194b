#include <orbis/scene/PageTable.h>

#include <catch2/catch.hpp>

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
