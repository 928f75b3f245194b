#include "orbis/scene/PageTable.h"

#include <algorithm>
#include <cassert>

namespace orbis::scene {

PageTable::PageTable(std::uint32_t finestLevel)
    : _finestLevel(finestLevel)
    , _levels(finestLevel + 1)
    , _dirty(finestLevel + 1)
{
    assert(finestLevel <= kMaximumVirtualTextureLevel);
    for (std::uint32_t level = 0; level <= finestLevel; ++level) {
        _levels[level].resize(VirtualTextureLayout::pageCount(level));
    }
}

const PageTableEntry& PageTable::entry(const PageKey& page) const noexcept
{
    assert(VirtualTextureLayout::hasPage(_finestLevel, page));
    return _levels[page.level][static_cast<std::size_t>(page.y) * VirtualTextureLayout::pagesX(page.level) + page.x];
}

PageTableEntry& PageTable::at(std::uint32_t level, std::uint32_t x, std::uint32_t y) noexcept
{
    return _levels[level][static_cast<std::size_t>(y) * VirtualTextureLayout::pagesX(level) + x];
}

std::span<const PageTableEntry> PageTable::level(std::uint32_t level) const noexcept
{
    return _levels[level];
}

template <class F>
void PageTable::forSubtree(const PageKey& page, F&& f)
{
    // The descendants at each level are one rectangle: the page's extent at that level.
    for (std::uint32_t level = page.level; level <= _finestLevel; ++level) {
        const std::uint32_t shift = level - page.level;
        const PageRectangle rectangle{page.x << shift, page.y << shift, (page.x + 1) << shift, (page.y + 1) << shift};
        for (std::uint32_t y = rectangle.y0; y < rectangle.y1; ++y) {
            for (std::uint32_t x = rectangle.x0; x < rectangle.x1; ++x) {
                f(at(level, x, y));
            }
        }
        std::optional<PageRectangle>& dirty = _dirty[level];
        if (!dirty) {
            dirty = rectangle;
        } else {
            dirty = PageRectangle{std::min(dirty->x0, rectangle.x0), std::min(dirty->y0, rectangle.y0),
                                  std::max(dirty->x1, rectangle.x1), std::max(dirty->y1, rectangle.y1)};
        }
    }
}

void PageTable::map(const PageKey& page, std::uint8_t slotX, std::uint8_t slotY)
{
    if (isMapped(page)) {
        return;
    }
    const auto level = static_cast<std::uint8_t>(page.level);
    // Entries showing something coarser than this page (or nothing) show it now; those under a
    // mapped descendant show that, which is finer, and stay.
    forSubtree(page, [&](PageTableEntry& entry) {
        if (!(entry.flags & PageTableEntry::kValid) || entry.level < level) {
            entry.slotX = slotX;
            entry.slotY = slotY;
            entry.level = level;
            entry.flags = static_cast<std::uint8_t>((entry.flags & PageTableEntry::kMissing) | PageTableEntry::kValid);
        }
    });
    at(page.level, page.x, page.y).flags |= PageTableEntry::kMapped;
    ++_mapped;
}

void PageTable::unmap(const PageKey& page)
{
    if (!isMapped(page)) {
        return;
    }
    const auto level = static_cast<std::uint8_t>(page.level);
    // The page's own fallback: what its parent's entry shows (the parent or further up).
    std::optional<PageTableEntry> fallback;
    if (page.level > 0) {
        fallback = entry(page.parent());
    }
    at(page.level, page.x, page.y).flags &= static_cast<std::uint8_t>(~PageTableEntry::kMapped);
    forSubtree(page, [&](PageTableEntry& entry) {
        if (!(entry.flags & PageTableEntry::kValid) || entry.level != level) {
            return; // under a mapped descendant
        }
        const std::uint8_t kept = entry.flags & PageTableEntry::kMissing;
        if (fallback && (fallback->flags & PageTableEntry::kValid)) {
            entry.slotX = fallback->slotX;
            entry.slotY = fallback->slotY;
            entry.level = fallback->level;
            entry.flags = static_cast<std::uint8_t>(kept | PageTableEntry::kValid);
        } else {
            entry = PageTableEntry{};
            entry.flags = kept;
        }
    });
    --_mapped;
}

void PageTable::markMissing(const PageKey& page)
{
    forSubtree(page, [](PageTableEntry& entry) { entry.flags |= PageTableEntry::kMissing; });
}

void PageTable::texels(std::uint32_t level, const PageRectangle& rectangle, std::vector<float>& out) const
{
    out.clear();
    static_assert(kMaximumVirtualTextureLevel < 32 && PageTableEntry::kMissing < 8);
    const auto encoded = [](const PageTableEntry& e) {
        return static_cast<float>(e.slotX | e.slotY << 8 | e.level << 16 | e.flags << 21);
    };
    out.reserve(static_cast<std::size_t>(rectangle.x1 - rectangle.x0) * (rectangle.y1 - rectangle.y0) * 2);
    for (std::uint32_t y = rectangle.y0; y < rectangle.y1; ++y) {
        for (std::uint32_t x = rectangle.x0; x < rectangle.x1; ++x) {
            const PageTableEntry& own = entry({level, x, y});
            out.push_back(encoded(own));
            out.push_back(encoded(level > 0 ? entry({level - 1, x / 2, y / 2}) : own));
        }
    }
}

void PageTable::clearDirty() noexcept
{
    std::fill(_dirty.begin(), _dirty.end(), std::nullopt);
}

PageRectangle packResidencyNeighbours(std::span<glm::vec4> texels, std::uint32_t width, std::uint32_t height,
                                      const PageRectangle& changed)
{
    assert(texels.size() == static_cast<std::size_t>(width) * height);
    const bool wraps = changed.x0 == 0 || changed.x1 == width;
    const PageRectangle grown{wraps ? 0 : changed.x0 - 1, changed.y0 > 0 ? changed.y0 - 1 : 0, wraps ? width : changed.x1 + 1,
                              std::min(changed.y1 + 1, height)};
    const auto w = static_cast<int>(width), h = static_cast<int>(height);
    auto resident = [&](std::uint32_t x, std::uint32_t y, int dx, int dy) {
        const int column = (static_cast<int>(x) + dx + w) % w;
        const int row = std::clamp(static_cast<int>(y) + dy, 0, h - 1);
        return static_cast<std::uint32_t>(texels[static_cast<std::size_t>(row) * width + static_cast<std::size_t>(column)].r);
    };
    for (std::uint32_t y = grown.y0; y < grown.y1; ++y) {
        for (std::uint32_t x = grown.x0; x < grown.x1; ++x) {
            // 24 bits a channel at most: integers exact in a float.
            const std::uint32_t sides = resident(x, y, 1, 0) | resident(x, y, -1, 0) << 4 | resident(x, y, 0, 1) << 8 |
                                        resident(x, y, 0, -1) << 12 | resident(x, y, 1, 1) << 16 | resident(x, y, -1, 1) << 20;
            const std::uint32_t corners = resident(x, y, 1, -1) | resident(x, y, -1, -1) << 4;
            glm::vec4& texel = texels[static_cast<std::size_t>(y) * width + x];
            texel.b = static_cast<float>(sides);
            texel.a = static_cast<float>(corners);
        }
    }
    return grown;
}

} // namespace orbis::scene
