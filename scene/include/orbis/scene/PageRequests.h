#pragma once

#include <orbis/core/VirtualTextureLayout.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace orbis::scene {

/// A page and the feedback pixels that ask for it (or, with its descendants counted, for the
/// pages below it).
struct PageCount {
    PageKey page;
    std::uint64_t pixels = 0;
    friend bool operator==(const PageCount&, const PageCount&) = default;
};

/// A feedback buffer reduced to its pages (Mayer 4.2.1): each page asked for, once, with its pixel
/// count, in key order, and how many pixels there were, covered, and drawn from a coarser page.
struct FeedbackSummary {
    std::vector<PageCount> pages;
    std::size_t pixels = 0;   ///< every sample, covered or not
    std::size_t covered = 0;  ///< samples on the virtually textured surface
    std::size_t fallback = 0; ///< covered samples that showed a coarser page than they asked for
    std::size_t outside = 0;  ///< covered samples naming no page of the texture (left out)
    /// fallback / pixels: the share of the picture drawn from a coarser page than it asked for;
    /// 0 for an empty buffer.
    double fallbackFraction() const noexcept
    {
        return pixels == 0 ? 0.0 : static_cast<double>(fallback) / static_cast<double>(pixels);
    }
};

/// Reduces packed feedback samples (orbis::packFeedback) of a texture `finestLevel` deep to their
/// pages; a sample naming a page beyond that (a corrupted read-back) counts as `outside` only.
FeedbackSummary reduceFeedback(std::span<const std::uint32_t> samples, std::uint32_t finestLevel);

/// Each page asked for and every ancestor of it, each counting the pixels of all the asked-for
/// pages at or below it: what the view needs resident, since a page is only drawn once its
/// ancestors are (they are its fallbacks, and the coarser level of its trilinear blend). Key
/// order.
std::vector<PageCount> withAncestors(const FeedbackSummary& summary);

/// How the pages to load are ordered.
enum class RequestOrder {
    /// Most pixels first, then the coarser, then by key (Mayer's priorities).
    PixelCount,
    /// A fixed shuffle by key, whatever the pixels: what a reduction that loses the counts
    /// gives (Mayer's OpenCL reduction), for comparison.
    Unsorted,
};

/// The pages of `needed` (withAncestors' output) that `wanted` says to load, best first.
std::vector<PageCount> sortRequests(std::span<const PageCount> needed, const std::function<bool(const PageKey&)>& wanted,
                                    RequestOrder order);

} // namespace orbis::scene
