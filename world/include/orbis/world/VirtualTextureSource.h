#pragma once

#include <orbis/core/Image.h>
#include <orbis/core/VirtualTextureLayout.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace orbis::world {

class TileSource;

struct VirtualTextureSourceOptions {
    int pageSize = 256; ///< a power of two, 16 to 1024
    int border = 4;     ///< 0 to pageSize / 4
    /// Decoded source tiles kept for the next pages (each tile feeds its page and the borders of
    /// up to eight neighbours): bytes of RGBA.
    std::size_t cacheBytes = std::size_t{64} << 20;
};

/// The pages of a virtual texture over the globe (orbis::VirtualTextureLayout), cut from a
/// geographic imagery source (a TMS folder, a {z}/{x}/{y} template, MBTiles, HTTP; the tiler's
/// output): each page with its border, the texels of its neighbours, re-cut from the source's
/// tiles where the page and tile sizes differ. Level l of the virtual texture is the source level
/// as fine as it (l + log2(pageSize / tileSize)); levels coarser than the source's first are its
/// first level averaged down, so level 0 is always two pages.
///
/// Safe from several threads at once (the loader's workers): tiles are decoded once and kept in a
/// byte-capped cache shared by the pages that need them.
class VirtualTextureSource final {
public:
    /// Throws orbis::Error naming the source for a non-geographic scheme, tiles that are not square
    /// powers of two, or options out of range.
    VirtualTextureSource(std::shared_ptr<TileSource> source, const VirtualTextureSourceOptions& options = {});
    ~VirtualTextureSource();
    VirtualTextureSource(const VirtualTextureSource&) = delete;
    VirtualTextureSource& operator=(const VirtualTextureSource&) = delete;

    /// Page size, border, and the finest level: the source's deepest, in pages of this size.
    const VirtualTextureLayout& layout() const noexcept { return _layout; }
    const TileSource& tileSource() const noexcept { return *_source; }
    /// The source level whose texels are as large as the page level's (negative: coarser than the
    /// source's level 0).
    int sourceLevelOf(std::uint32_t pageLevel) const noexcept { return static_cast<int>(pageLevel) + _levelShift; }

    /// The page with its border: slotSize x slotSize RGBA texels, rows from the north. Texels of
    /// tiles the source does not have are transparent in the page and repeat the page's edge in
    /// the border; empty when the source has none of the tiles under the page itself. Throws
    /// orbis::Error naming the tile when one cannot be read or decoded.
    std::optional<Image> cutPage(const PageKey& page);

    /// "page 4/3/2 of <source>", for messages.
    std::string describe(const PageKey& page) const;

    /// Source tiles decoded so far, and those served from the cache.
    std::uint64_t tilesDecoded() const noexcept { return _decoded.load(); }
    std::uint64_t cacheHits() const noexcept { return _hits.load(); }

private:
    /// A decoded tile, or none when the source does not have it.
    using CachedTile = std::shared_ptr<const Image>;
    CachedTile tile(const TileKey& key);

    std::shared_ptr<TileSource> _source;
    VirtualTextureSourceOptions _options;
    VirtualTextureLayout _layout;
    int _tileSize = 256;
    int _levelShift = 0;                   ///< source level minus page level
    std::uint32_t _firstSourceLevel = 0;

    std::mutex _mutex;                     ///< guards the cache
    std::list<TileKey> _recency;           ///< most recent first
    struct Entry {
        CachedTile tile;
        std::list<TileKey>::iterator position;
    };
    std::unordered_map<TileKey, Entry, TileKeyHash> _cache;
    std::size_t _cachedBytes = 0;
    std::atomic<std::uint64_t> _decoded{0};
    std::atomic<std::uint64_t> _hits{0};
};

} // namespace orbis::world
