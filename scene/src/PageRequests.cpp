#include "orbis/scene/PageRequests.h"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace orbis::scene {

FeedbackSummary reduceFeedback(std::span<const std::uint32_t> samples, std::uint32_t finestLevel)
{
    FeedbackSummary summary;
    summary.pixels = samples.size();
    // Neighbouring pixels mostly ask for the same page: count runs before touching the map.
    std::unordered_map<std::uint32_t, std::uint64_t> counts;
    std::uint32_t run = 0;
    std::uint64_t runLength = 0;
    const std::uint32_t pageBits = ~(1u << 30); // the page and the covered bit, not the fallback
    for (const std::uint32_t sample : samples) {
        if (sample == 0) {
            continue;
        }
        ++summary.covered;
        summary.fallback += (sample >> 30) & 1u;
        const std::uint32_t page = sample & pageBits;
        if (page != run) {
            if (runLength > 0) {
                counts[run] += runLength;
            }
            run = page;
            runLength = 0;
        }
        ++runLength;
    }
    if (runLength > 0) {
        counts[run] += runLength;
    }
    summary.pages.reserve(counts.size());
    for (const auto& [bits, pixels] : counts) {
        const PageKey page = unpackFeedback(bits).page;
        if (!VirtualTextureLayout::hasPage(finestLevel, page)) {
            summary.outside += pixels;
            continue;
        }
        summary.pages.push_back({page, pixels});
    }
    std::sort(summary.pages.begin(), summary.pages.end(),
              [](const PageCount& a, const PageCount& b) { return a.page < b.page; });
    return summary;
}

std::vector<PageCount> withAncestors(const FeedbackSummary& summary)
{
    std::map<PageKey, std::uint64_t> needed;
    for (const PageCount& count : summary.pages) {
        PageKey page = count.page;
        for (;;) {
            needed[page] += count.pixels;
            if (page.level == 0) {
                break;
            }
            page = page.parent();
        }
    }
    std::vector<PageCount> pages;
    pages.reserve(needed.size());
    for (const auto& [page, pixels] : needed) {
        pages.push_back({page, pixels});
    }
    return pages;
}

namespace {

/// A fixed, well-mixed number per page (SplitMix64 of its linear index).
std::uint64_t shuffleKey(const PageKey& page) noexcept
{
    std::uint64_t z = VirtualTextureLayout::linearIndex(page) + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

} // namespace

std::vector<PageCount> sortRequests(std::span<const PageCount> needed, const std::function<bool(const PageKey&)>& wanted,
                                    RequestOrder order)
{
    std::vector<PageCount> requests;
    for (const PageCount& count : needed) {
        if (wanted(count.page)) {
            requests.push_back(count);
        }
    }
    if (order == RequestOrder::PixelCount) {
        // An ancestor counts at least its descendants' pixels and is coarser: it always comes first.
        std::sort(requests.begin(), requests.end(), [](const PageCount& a, const PageCount& b) {
            if (a.pixels != b.pixels) {
                return a.pixels > b.pixels;
            }
            if (a.page.level != b.page.level) {
                return a.page.level < b.page.level;
            }
            return a.page < b.page;
        });
    } else {
        std::sort(requests.begin(), requests.end(),
                  [](const PageCount& a, const PageCount& b) { return shuffleKey(a.page) < shuffleKey(b.page); });
    }
    return requests;
}

} // namespace orbis::scene
