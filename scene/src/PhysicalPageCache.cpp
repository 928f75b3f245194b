#include "orbis/scene/PhysicalPageCache.h"

#include <orbis/core/Error.h>

#include <algorithm>
#include <string>

namespace orbis::scene {

PhysicalPageCache::PhysicalPageCache(int slotsX, int slotsY)
    : _slotsX(slotsX)
    , _slotsY(slotsY)
{
    if (slotsX < 1 || slotsX > 256 || slotsY < 1 || slotsY > 256) {
        throw Error("PhysicalPageCache: a physical texture has 1 to 256 slots a side, not " + std::to_string(slotsX) +
                    " x " + std::to_string(slotsY));
    }
    _occupied.assign(capacity(), 0);
}

std::optional<PhysicalPageCache::Slot> PhysicalPageCache::find(const PageKey& page) const noexcept
{
    const auto found = _pages.find(page);
    if (found == _pages.end()) {
        return std::nullopt;
    }
    return found->second.slot;
}

std::optional<std::uint64_t> PhysicalPageCache::lastUsed(const PageKey& page) const noexcept
{
    const auto found = _pages.find(page);
    if (found == _pages.end()) {
        return std::nullopt;
    }
    return found->second.lastUsed;
}

void PhysicalPageCache::touch(const PageKey& page, std::uint64_t frame) noexcept
{
    const auto found = _pages.find(page);
    if (found != _pages.end()) {
        found->second.lastUsed = std::max(found->second.lastUsed, frame);
    }
}

std::optional<PhysicalPageCache::Placement> PhysicalPageCache::insert(
    const PageKey& page, std::uint64_t frame, const std::function<bool(const PageKey&)>& evictable)
{
    Placement placement;
    const auto freeSlot = std::find(_occupied.begin(), _occupied.end(), std::uint8_t{0});
    if (freeSlot != _occupied.end()) {
        const auto index = static_cast<int>(freeSlot - _occupied.begin());
        placement.slot = {static_cast<std::uint8_t>(index % _slotsX), static_cast<std::uint8_t>(index / _slotsX)};
    } else {
        // The oldest, the deepest of equally old ones, then by key: the same victim every run.
        const std::pair<const PageKey, Held>* victim = nullptr;
        for (const auto& held : _pages) {
            if (held.second.lastUsed >= frame || !evictable(held.first)) {
                continue;
            }
            if (!victim) {
                victim = &held;
                continue;
            }
            const Held& best = victim->second;
            const bool older = held.second.lastUsed < best.lastUsed;
            const bool sameAge = held.second.lastUsed == best.lastUsed;
            const bool deeper = held.first.level > victim->first.level;
            const bool sameLevel = held.first.level == victim->first.level;
            if (older || (sameAge && (deeper || (sameLevel && held.first < victim->first)))) {
                victim = &held;
            }
        }
        if (!victim) {
            return std::nullopt;
        }
        placement.slot = victim->second.slot;
        placement.evicted = victim->first;
        _pages.erase(*placement.evicted);
    }
    _occupied[static_cast<std::size_t>(placement.slot.y) * _slotsX + placement.slot.x] = 1;
    _pages[page] = Held{placement.slot, frame};
    return placement;
}

void PhysicalPageCache::erase(const PageKey& page) noexcept
{
    const auto found = _pages.find(page);
    if (found == _pages.end()) {
        return;
    }
    _occupied[static_cast<std::size_t>(found->second.slot.y) * _slotsX + found->second.slot.x] = 0;
    _pages.erase(found);
}

std::vector<PageKey> PhysicalPageCache::pages() const
{
    std::vector<PageKey> keys;
    keys.reserve(_pages.size());
    for (const auto& held : _pages) {
        keys.push_back(held.first);
    }
    return keys;
}

} // namespace orbis::scene
