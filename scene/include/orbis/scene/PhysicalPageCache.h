#pragma once

#include <orbis/core/VirtualTextureLayout.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_map>
#include <vector>

namespace orbis::scene {

/// Which page each slot of a physical page texture holds, and which to give up when a new page
/// needs a slot and none is free (Mayer 4.3.2): the least recently used, the deepest first among
/// equally old ones, never one used in the current frame. A fixed number of slots: the memory of
/// a virtual texture is that of its physical texture, whatever the view asks for.
///
/// ```
/// PhysicalPageCache cache(2, 1);
/// cache.insert(page, frame, [](const PageKey&) { return true; }); // a free slot
/// cache.touch(page, frame + 1);                                    // used again
/// ```
class PhysicalPageCache final {
public:
    struct Slot {
        std::uint8_t x = 0;
        std::uint8_t y = 0;
        friend bool operator==(const Slot&, const Slot&) = default;
    };
    /// Where a new page goes, and the page that was there (to unmap).
    struct Placement {
        Slot slot;
        std::optional<PageKey> evicted;
    };

    /// slotsX, slotsY in 1..256.
    PhysicalPageCache(int slotsX, int slotsY);

    int slotsX() const noexcept { return _slotsX; }
    int slotsY() const noexcept { return _slotsY; }
    std::size_t capacity() const noexcept { return static_cast<std::size_t>(_slotsX) * _slotsY; }
    std::size_t size() const noexcept { return _pages.size(); }

    std::optional<Slot> find(const PageKey& page) const noexcept;
    /// The frame the page was last used in (inserted or touched); empty for a page not held.
    std::optional<std::uint64_t> lastUsed(const PageKey& page) const noexcept;
    /// The page is used in `frame`; no effect for a page not held.
    void touch(const PageKey& page, std::uint64_t frame) noexcept;

    /// A slot for a page not held yet, used from `frame` on: the first free slot (row by row),
    /// else the slot of the least recently used page that `evictable` allows giving up and that
    /// was not used in `frame`. Empty when there is no such page: the slots hold what the frame
    /// needs.
    std::optional<Placement> insert(const PageKey& page, std::uint64_t frame,
                                    const std::function<bool(const PageKey&)>& evictable);
    /// Frees the page's slot; no effect for a page not held.
    void erase(const PageKey& page) noexcept;

    /// Every page held, in no particular order.
    std::vector<PageKey> pages() const;

private:
    struct Held {
        Slot slot;
        std::uint64_t lastUsed = 0;
    };

    int _slotsX;
    int _slotsY;
    std::unordered_map<PageKey, Held, TileKeyHash> _pages;
    /// By slot index y * slotsX + x; bytes, not vector<bool>, whose bit references GCC 12 -O3
    /// warns about falsely (-Wnull-dereference).
    std::vector<std::uint8_t> _occupied;
};

} // namespace orbis::scene
