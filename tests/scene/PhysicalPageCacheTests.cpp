#include <orbis/core/Error.h>
#include <orbis/scene/PhysicalPageCache.h>

#include <catch2/catch.hpp>

#include <set>

using namespace orbis;
using namespace orbis::scene;

namespace {

const auto kAnyPage = [](const PageKey&) { return true; };

} // namespace

TEST_CASE("Pages fill free slots row by row, then take the least recently used one's", "[scene][virtual]")
{
    PhysicalPageCache cache(3, 2);
    CHECK(cache.capacity() == 6);
    std::set<std::pair<int, int>> slots;
    for (std::uint32_t x = 0; x < 6; ++x) {
        const auto placement = cache.insert({3, x, 0}, 1, kAnyPage);
        REQUIRE(placement);
        CHECK_FALSE(placement->evicted);
        CHECK(placement->slot == PhysicalPageCache::Slot{static_cast<std::uint8_t>(x % 3), static_cast<std::uint8_t>(x / 3)});
        slots.insert({placement->slot.x, placement->slot.y});
    }
    CHECK(slots.size() == 6);
    CHECK(cache.size() == 6);
    // Used again in frame 2, all but page 4: it goes first.
    for (std::uint32_t x = 0; x < 6; ++x) {
        if (x != 4) {
            cache.touch({3, x, 0}, 2);
        }
    }
    auto placement = cache.insert({3, 9, 0}, 3, kAnyPage);
    REQUIRE(placement);
    CHECK(placement->evicted == PageKey{3, 4, 0});
    CHECK(placement->slot == PhysicalPageCache::Slot{1, 1});
    CHECK(cache.find({3, 9, 0}) == PhysicalPageCache::Slot{1, 1});
    CHECK_FALSE(cache.find({3, 4, 0}));
    CHECK(cache.size() == 6);
    CHECK(cache.lastUsed({3, 9, 0}) == 3u);
}

TEST_CASE("At capacity the deepest of equally old pages goes, never one the frame uses", "[scene][virtual]")
{
    PhysicalPageCache cache(2, 2);
    cache.insert({0, 0, 0}, 1, kAnyPage);
    cache.insert({1, 1, 0}, 1, kAnyPage);
    cache.insert({2, 3, 1}, 1, kAnyPage);
    cache.insert({2, 2, 1}, 1, kAnyPage);
    // All as old: the deeper first, and of the two deepest the smaller key (row, then column).
    auto placement = cache.insert({2, 0, 0}, 5, [](const PageKey& page) { return page.level > 0; });
    REQUIRE(placement);
    CHECK(placement->evicted == PageKey{2, 2, 1});
    // What the predicate protects stays whatever its age.
    placement = cache.insert({2, 1, 0}, 5, [](const PageKey& page) { return page.level == 1; });
    REQUIRE(placement);
    CHECK(placement->evicted == PageKey{1, 1, 0});
    // Every page used in this frame: no slot, and nothing is given up.
    for (const PageKey page : cache.pages()) {
        cache.touch(page, 6);
    }
    CHECK_FALSE(cache.insert({2, 7, 3}, 6, kAnyPage));
    CHECK(cache.size() == 4);
    // The next frame they are old again.
    CHECK(cache.insert({2, 7, 3}, 7, kAnyPage));
}

TEST_CASE("A freed slot is the next one given", "[scene][virtual]")
{
    PhysicalPageCache cache(2, 1);
    cache.insert({0, 0, 0}, 1, kAnyPage);
    cache.insert({0, 1, 0}, 1, kAnyPage);
    cache.erase({0, 0, 0});
    cache.erase({5, 5, 5}); // not held: nothing happens
    CHECK(cache.size() == 1);
    const auto placement = cache.insert({1, 2, 1}, 2, kAnyPage);
    REQUIRE(placement);
    CHECK_FALSE(placement->evicted);
    CHECK(placement->slot == PhysicalPageCache::Slot{0, 0});
    CHECK_THROWS_AS(PhysicalPageCache(0, 4), Error);
    CHECK_THROWS_AS(PhysicalPageCache(300, 1), Error);
}
