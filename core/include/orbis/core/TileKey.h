#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace orbis {

/// The deepest level a tiling scheme addresses: 2^31 columns still fit a 32-bit index.
inline constexpr std::uint32_t kMaximumTileLevel = 30;

/// One tile of a quadtree pyramid: its level (0 at the roots) and its column and row at that
/// level. What the row counts from (the south or the north) belongs to the TilingScheme.
struct TileKey {
    std::uint32_t level = 0;
    std::uint32_t x = 0;
    std::uint32_t y = 0;

    /// The tile one level up that contains this one; a root tile is its own parent.
    constexpr TileKey parent() const noexcept { return level == 0 ? *this : TileKey{level - 1, x / 2, y / 2}; }

    /// Child 0..3 one level down: bit 0 adds one column, bit 1 one row (the same direction as y).
    constexpr TileKey child(int index) const noexcept
    {
        return {level + 1, 2 * x + static_cast<std::uint32_t>(index & 1), 2 * y + static_cast<std::uint32_t>(index >> 1)};
    }

    /// This tile's ancestor at `ancestorLevel` (<= level; the tile itself at its own level).
    constexpr TileKey ancestor(std::uint32_t ancestorLevel) const noexcept
    {
        const std::uint32_t up = level - ancestorLevel;
        return {ancestorLevel, x >> up, y >> up};
    }

    /// Level first, then row, then column.
    friend constexpr auto operator<=>(const TileKey& a, const TileKey& b) noexcept
    {
        if (auto c = a.level <=> b.level; c != 0) {
            return c;
        }
        if (auto c = a.y <=> b.y; c != 0) {
            return c;
        }
        return a.x <=> b.x;
    }
    friend constexpr bool operator==(const TileKey&, const TileKey&) noexcept = default;
};

/// Hash for unordered containers: the three fields packed into 64 bits, then mixed.
struct TileKeyHash {
    std::size_t operator()(const TileKey& key) const noexcept
    {
        std::uint64_t h = (static_cast<std::uint64_t>(key.level) << 58) ^ (static_cast<std::uint64_t>(key.y) << 29) ^ key.x;
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdULL;
        h ^= h >> 33;
        return static_cast<std::size_t>(h);
    }
};

} // namespace orbis
