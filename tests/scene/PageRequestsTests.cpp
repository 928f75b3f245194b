#include <orbis/scene/PageRequests.h>

#include <catch2/catch.hpp>

#include <algorithm>

using namespace orbis;
using namespace orbis::scene;

namespace {

std::uint32_t sample(const PageKey& page, bool fallback = false)
{
    return packFeedback({true, fallback, page});
}

} // namespace

TEST_CASE("A feedback buffer reduces to each page once with its pixel count", "[scene][virtual]")
{
    std::vector<std::uint32_t> samples;
    for (int i = 0; i < 7; ++i) {
        samples.push_back(sample({4, 10, 5}));
    }
    samples.push_back(0);
    samples.push_back(0);
    samples.push_back(sample({3, 2, 1}, true));
    samples.push_back(sample({4, 10, 5}, true)); // the same page, shown coarser
    samples.push_back(sample({3, 2, 1}));
    const FeedbackSummary summary = reduceFeedback(samples, 4);
    CHECK(summary.pixels == 12);
    CHECK(summary.covered == 10);
    CHECK(summary.fallback == 2);
    CHECK(summary.fallbackFraction() == Approx(2.0 / 12.0));
    REQUIRE(summary.pages.size() == 2);
    CHECK(summary.pages[0] == PageCount{{3, 2, 1}, 2});
    CHECK(summary.pages[1] == PageCount{{4, 10, 5}, 8});
    CHECK(summary.outside == 0);
    CHECK(reduceFeedback({}, 4).fallbackFraction() == 0.0);
    // Pages beyond the texture (a read-back gone wrong) are counted, not asked for.
    samples.push_back(sample({5, 0, 0}));
    samples.push_back(sample({3, 16, 0}));
    samples.push_back(sample({3, 0, 8}));
    const FeedbackSummary corrupted = reduceFeedback(samples, 4);
    CHECK(corrupted.outside == 3);
    CHECK(corrupted.covered == 13);
    CHECK(corrupted.pages == summary.pages);
}

TEST_CASE("Pages needed include every ancestor, counting the pixels below it", "[scene][virtual]")
{
    FeedbackSummary summary;
    summary.pages = {{{2, 3, 1}, 5}, {{2, 2, 1}, 1}, {{1, 0, 0}, 4}};
    const std::vector<PageCount> needed = withAncestors(summary);
    const std::vector<PageCount> expected = {{{0, 0, 0}, 10}, {{1, 0, 0}, 4}, {{1, 1, 0}, 6}, {{2, 2, 1}, 1},
                                             {{2, 3, 1}, 5}};
    CHECK(needed == expected);
}

TEST_CASE("Requests go most pixels first, then coarse before fine, and only those wanted", "[scene][virtual]")
{
    const std::vector<PageCount> needed = {{{0, 0, 0}, 50}, {{1, 0, 0}, 20}, {{1, 1, 0}, 30}, {{2, 0, 0}, 20},
                                           {{2, 3, 1}, 20}, {{3, 1, 1}, 2}};
    const auto notRoot = [](const PageKey& page) { return page.level > 0; };
    const std::vector<PageCount> sorted = sortRequests(needed, notRoot, RequestOrder::PixelCount);
    const std::vector<PageCount> expected = {{{1, 1, 0}, 30}, {{1, 0, 0}, 20}, {{2, 0, 0}, 20}, {{2, 3, 1}, 20},
                                             {{3, 1, 1}, 2}};
    CHECK(sorted == expected);
    // Unsorted: the same pages in an order that has nothing to do with the counts, and always the same.
    const std::vector<PageCount> shuffled = sortRequests(needed, notRoot, RequestOrder::Unsorted);
    CHECK(shuffled.size() == 5);
    CHECK(std::is_permutation(shuffled.begin(), shuffled.end(), expected.begin(), expected.end()));
    CHECK(shuffled != expected);
    CHECK(shuffled == sortRequests(needed, notRoot, RequestOrder::Unsorted));
}
