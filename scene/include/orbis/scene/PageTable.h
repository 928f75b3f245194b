#pragma once

#include <orbis/core/VirtualTextureLayout.h>

#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace orbis::scene {

/// One entry of the page table: where the page's texels are in the physical texture. Four bytes,
/// laid out as the RGBA8 page-table texture stores them.
struct PageTableEntry {
    static constexpr std::uint8_t kValid = 1;   ///< points at a mapped page (every entry once a root is mapped)
    static constexpr std::uint8_t kMapped = 2;  ///< the page itself is in the slot, not an ancestor
    static constexpr std::uint8_t kMissing = 4; ///< the source has no such page: what the entry shows is final

    std::uint8_t slotX = 0; ///< the slot's column and row in the physical texture
    std::uint8_t slotY = 0;
    std::uint8_t level = 0; ///< the level of the page in the slot: the page's own, or its ancestor's
    std::uint8_t flags = 0;

    friend bool operator==(const PageTableEntry&, const PageTableEntry&) = default;
};
static_assert(sizeof(PageTableEntry) == 4);

/// A rectangle of page-table entries at one level, [x0, x1) x [y0, y1), rows from the south.
struct PageRectangle {
    std::uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    friend bool operator==(const PageRectangle&, const PageRectangle&) = default;
};

/// The CPU side of a virtual texture's page table (Mayer 4.3.3): one entry per page at every
/// level, each pointing at the slot holding the page, or, while the page is not mapped, its
/// nearest mapped ancestor's (a fallback entry), so the shader finds the best texels there are
/// in one fetch. Mapping a page points the entries below it that fell back further up at it;
/// unmapping points them at the page's own fallback; both stop under a mapped page. What
/// changed is kept as one rectangle per level, for the GPU copy to update only that.
///
/// ```
/// PageTable table(4);
/// table.map({0, 0, 0}, 0, 0);  // every page in the west half now falls back to slot (0, 0)
/// table.entry({4, 3, 2}).level; // 0
/// ```
class PageTable final {
public:
    explicit PageTable(std::uint32_t finestLevel);

    std::uint32_t finestLevel() const noexcept { return _finestLevel; }
    /// Requires page.level <= finestLevel and the page inside its level (asserted).
    const PageTableEntry& entry(const PageKey& page) const noexcept;
    bool isMapped(const PageKey& page) const noexcept { return (entry(page).flags & PageTableEntry::kMapped) != 0; }
    bool isMissing(const PageKey& page) const noexcept { return (entry(page).flags & PageTableEntry::kMissing) != 0; }
    /// The entries of a level, rows from the south, each row from the west.
    std::span<const PageTableEntry> level(std::uint32_t level) const noexcept;
    std::size_t mappedCount() const noexcept { return _mapped; }

    /// The page is now in the slot; entries below it that showed a coarser page show it.
    void map(const PageKey& page, std::uint8_t slotX, std::uint8_t slotY);
    /// The page left its slot; entries that showed it show its nearest mapped ancestor (nothing,
    /// not valid, for a root). No effect on a page that is not mapped.
    void unmap(const PageKey& page);
    /// The source has no such page, nor any below it: they keep showing what they show now, and
    /// the shader counts that as no fallback.
    void markMissing(const PageKey& page);

    /// The page-table texture's texels (RG32F) for a rectangle of a level, rows from the south,
    /// each row from the west: every entry with its parent's beside it, so that the shader finds
    /// the two levels a trilinear lookup blends in one fetch. Red: the entry as the integer
    /// slotX + 2^8 slotY + 2^16 level + 2^21 flags (24 bits: exact in a float); green: the parent
    /// page's entry (at level 0, the entry itself). A parent's entry changes only with its
    /// subtree, which marks the rectangle of its children dirty too.
    void texels(std::uint32_t level, const PageRectangle& rectangle, std::vector<float>& out) const;

    /// What changed at a level since clearDirty(); empty when nothing did.
    const std::optional<PageRectangle>& dirty(std::uint32_t level) const noexcept { return _dirty[level]; }
    void clearDirty() noexcept;

private:
    PageTableEntry& at(std::uint32_t level, std::uint32_t x, std::uint32_t y) noexcept;
    /// Calls f(entry) for every entry of the page and its descendants, level by level, and marks
    /// the rectangles dirty.
    template <class F>
    void forSubtree(const PageKey& page, F&& f);

    std::uint32_t _finestLevel;
    std::vector<std::vector<PageTableEntry>> _levels;
    std::vector<std::optional<PageRectangle>> _dirty;
    std::size_t _mapped = 0;
};

/// The sparse path's LOD clamp (VirtualTextureGlobe, vtSparseLod): for a level of pages, each
/// texel's red the finest level resident there in levels above the finest (0..12), and blue and
/// alpha its eight neighbours' reds packed 4 bits each, so that the shader learns which levels the
/// pages around a point hold from the point's own texel: blue east, west, north, south,
/// north-east, north-west from bit 0; alpha south-east, south-west. Rows from the south; the
/// antimeridian wraps; beyond a pole the row itself (as a sampler clamps). Repacks the texels whose
/// neighbours lie in `changed`, whose reds changed, and returns the rectangle repacked: `changed`
/// grown by a texel, across the whole width where it reaches the antimeridian.
PageRectangle packResidencyNeighbours(std::span<glm::vec4> texels, std::uint32_t width, std::uint32_t height,
                                      const PageRectangle& changed);

} // namespace orbis::scene
