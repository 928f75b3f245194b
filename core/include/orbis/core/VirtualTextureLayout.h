#pragma once

#include "orbis/core/TileKey.h"

#include <glm/vec2.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>

namespace orbis {

/// A page of a virtual texture over the globe: page (level, x, y) covers exactly the extent of the
/// geographic tile (level, x, y) (rows from the south), so the page quadtree is the tile quadtree.
using PageKey = TileKey;

/// The deepest page level a feedback sample can name (packFeedback): 13 bits of column.
inline constexpr std::uint32_t kMaximumVirtualTextureLevel = 12;

/// The shape of a virtual texture over the whole globe in the geographic layout (Mayer 4.1;
/// course 6.1): level l has 2^(l+1) x 2^l pages of pageSize x pageSize texels, level 0 two pages
/// side by side, each level twice as fine as the one above, up to finestLevel. Every page is
/// stored in a slot of slotSize() texels a side: its own texels in the middle and a border of
/// `border` texels on each side copied from its neighbours (the antimeridian wraps; beyond a pole
/// the edge row repeats), so that bilinear, trilinear and anisotropic filtering (within
/// 2 x border texels of footprint) never reach into an unrelated page. The page keeps its
/// power-of-two size and the slot grows by the border (Mayer's "expand the tile size"): the
/// virtual texture is then texel for texel the source's power-of-two pyramid.
struct VirtualTextureLayout {
    int pageSize = 256;           ///< texels a side of a page's own content, a power of two
    int border = 4;               ///< texels copied from the neighbours on each side
    std::uint32_t finestLevel = 0; ///< the deepest level, <= kMaximumVirtualTextureLevel

    int slotSize() const noexcept { return pageSize + 2 * border; }

    static constexpr std::uint32_t pagesX(std::uint32_t level) noexcept { return 2u << level; }
    static constexpr std::uint32_t pagesY(std::uint32_t level) noexcept { return 1u << level; }
    /// Whether a texture down to level `deepest` has the page: its level, and the page inside it.
    static constexpr bool hasPage(std::uint32_t deepest, const PageKey& page) noexcept
    {
        return page.level <= deepest && page.x < pagesX(page.level) && page.y < pagesY(page.level);
    }
    /// Pages at one level: 2 x 4^level.
    static constexpr std::uint64_t pageCount(std::uint32_t level) noexcept
    {
        return std::uint64_t{2} << (2 * level);
    }
    /// Pages at levels 0..finestLevel together: 2 (4^(n+1) - 1) / 3.
    std::uint64_t totalPageCount() const noexcept { return firstIndexOfLevel(finestLevel + 1); }
    /// Texels across and up the whole texture at a level.
    std::uint64_t texelsX(std::uint32_t level) const noexcept
    {
        return static_cast<std::uint64_t>(pagesX(level)) * static_cast<std::uint64_t>(pageSize);
    }
    std::uint64_t texelsY(std::uint32_t level) const noexcept
    {
        return static_cast<std::uint64_t>(pagesY(level)) * static_cast<std::uint64_t>(pageSize);
    }

    /// The mip tail (Mayer 4.1: no page is smaller than a page): level 0's two pages halved t times,
    /// t = 1 .. tailLevels(), down to 1 x 1, each the box filter of the one before (halveImage).
    /// The tail is kept in the physical texture beside the slots, so that a pixel coarser than
    /// level 0 reads it as any other pixel reads a page: in a strip, the levels side by side from
    /// the west, each with a border as a slot has (the antimeridian wraps, beyond a pole the edge
    /// row repeats).
    int tailLevels() const noexcept { return std::bit_width(static_cast<unsigned>(2 * pageSize)) - 1; }
    /// Texels across and up tail level t (1 .. tailLevels()), its border left out.
    glm::ivec2 tailSize(int t) const noexcept { return {std::max((2 * pageSize) >> t, 1), std::max(pageSize >> t, 1)}; }
    /// Where tail level t's region (its border included) starts across the strip: the widths of
    /// levels 1 .. t - 1, 2P - 2P / 2^(t-1) texels, and their borders.
    int tailOffset(int t) const noexcept { return 2 * pageSize - ((2 * pageSize) >> (t - 1)) + 2 * border * (t - 1); }
    /// The strip's width and height: every tail level's region, the first the tallest.
    glm::ivec2 tailStripSize() const noexcept { return {tailOffset(tailLevels() + 1), pageSize / 2 + 2 * border}; }

    /// Where a level's page-table entries start in the page-table texture, which holds every level
    /// in one image (the shader then reads the texture's level 0 only: a fetch at a mipmap level
    /// that varies from pixel to pixel costs llvmpipe more): the finest level n at the origin,
    /// 2^(n+1) x 2^n entries, and the coarser ones in a row above it, the next coarser to the right.
    static constexpr glm::uvec2 pageTableOrigin(std::uint32_t level, std::uint32_t finestLevel) noexcept
    {
        return level == finestLevel ? glm::uvec2(0) : glm::uvec2((2u << finestLevel) - (4u << level), 1u << finestLevel);
    }
    /// The page-table texture's size: 2^(n+1) by 2^n + 2^(n-1) entries, no wider than the finest level.
    static constexpr glm::uvec2 pageTableSize(std::uint32_t finestLevel) noexcept
    {
        return {2u << finestLevel, (1u << finestLevel) + (1u << finestLevel) / 2};
    }

    /// The index of the first page of a level when pages are numbered level by level from level
    /// 0, each level row by row from the south, each row from the west (the quadtree's linear
    /// order): the pages of levels 0..level-1 together.
    static constexpr std::uint64_t firstIndexOfLevel(std::uint32_t level) noexcept
    {
        return ((std::uint64_t{1} << (2 * level)) - 1) / 3 * 2;
    }
    /// A page's number in that order; 0 for page (0, 0, 0).
    static constexpr std::uint64_t linearIndex(const PageKey& page) noexcept
    {
        return firstIndexOfLevel(page.level) + static_cast<std::uint64_t>(page.y) * pagesX(page.level) + page.x;
    }
    /// The page with that number (inverse of linearIndex).
    static PageKey pageOfIndex(std::uint64_t index) noexcept;

    /// The page of a level holding the point at u (0 at 180 degrees west .. 1 at 180 east) and v
    /// (0 at the south pole .. 1 at the north pole); points on or beyond an edge go to the page
    /// inside it.
    static PageKey pageAt(std::uint32_t level, double u, double v) noexcept;
    /// Where in its page the point lies, 0..1 from the page's south-west corner.
    static glm::dvec2 positionInPage(const PageKey& page, double u, double v) noexcept;

    /// Border contraction (Mayer 4.5.2): a position in a page (0..1 from its south-west corner) as
    /// a position in its slot (0..1): border + position x pageSize texels from the slot's corner.
    glm::dvec2 contractToSlot(const glm::dvec2& positionInPage) const noexcept;
    /// The inverse: a position in a slot as a position in its page (outside 0..1 in the border).
    glm::dvec2 expandFromSlot(const glm::dvec2& positionInSlot) const noexcept;
};

/// One pixel of the feedback pass: the page its texels ask for, and whether what it showed came
/// from a coarser page than that (a fallback).
struct FeedbackSample {
    bool covered = false;  ///< false where no virtually textured surface was drawn
    bool fallback = false;
    PageKey page;          ///< level <= kMaximumVirtualTextureLevel, x < 8192, y < 8192

    friend bool operator==(const FeedbackSample&, const FeedbackSample&) = default;
};

/// The 32 bits of a feedback pixel (red the lowest byte, alpha the highest, as an RGBA8 target
/// stores them and the shader writes them): column in bits 0-12, row in 13-25, level in 26-29,
/// fallback in bit 30, covered in bit 31. 0 is an uncovered pixel.
constexpr std::uint32_t packFeedback(const FeedbackSample& sample) noexcept
{
    if (!sample.covered) {
        return 0;
    }
    return (sample.page.x & 0x1FFFu) | ((sample.page.y & 0x1FFFu) << 13) | ((sample.page.level & 0xFu) << 26) |
           (sample.fallback ? 1u << 30 : 0u) | (1u << 31);
}

constexpr FeedbackSample unpackFeedback(std::uint32_t bits) noexcept
{
    FeedbackSample sample;
    sample.covered = (bits >> 31) != 0;
    if (!sample.covered) {
        return sample;
    }
    sample.fallback = ((bits >> 30) & 1u) != 0;
    sample.page = {(bits >> 26) & 0xFu, bits & 0x1FFFu, (bits >> 13) & 0x1FFFu};
    return sample;
}

} // namespace orbis
