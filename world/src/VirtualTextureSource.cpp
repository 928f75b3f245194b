#include "orbis/world/VirtualTextureSource.h"

#include "orbis/world/ImageCodec.h"
#include "orbis/world/TileSource.h"

#include <orbis/core/Error.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <map>
#include <vector>

namespace orbis::world {

namespace {

bool isPowerOfTwo(int value) noexcept
{
    return value > 0 && std::has_single_bit(static_cast<unsigned>(value));
}

int log2Of(int powerOfTwo) noexcept
{
    return std::countr_zero(static_cast<unsigned>(powerOfTwo));
}

/// What a missing tile costs in the cache: it is remembered, not stored.
constexpr std::size_t kMissingTileBytes = 64;

} // namespace

VirtualTextureSource::VirtualTextureSource(std::shared_ptr<TileSource> source, const VirtualTextureSourceOptions& options)
    : _source(std::move(source))
    , _options(options)
{
    if (!_source) {
        throw Error("VirtualTextureSource: no tile source");
    }
    const TileSourceInfo& info = _source->info();
    const std::string name = "virtual texture of " + info.name;
    if (info.scheme.projection() != TilingProjection::Geographic) {
        throw Error(name + ": pages are cut from geographic (EPSG:4326) tiles, and this source is Web Mercator");
    }
    if (info.tileWidth != info.tileHeight || !isPowerOfTwo(info.tileWidth)) {
        throw Error(name + ": tiles must be square with a power-of-two size, not " + std::to_string(info.tileWidth) + " x " +
                    std::to_string(info.tileHeight));
    }
    if (!isPowerOfTwo(options.pageSize) || options.pageSize < 16 || options.pageSize > 1024) {
        throw Error(name + ": the page size must be a power of two from 16 to 1024, not " +
                    std::to_string(options.pageSize));
    }
    if (options.border < 0 || options.border > options.pageSize / 4) {
        throw Error(name + ": the border must be 0 to a quarter of the page (" + std::to_string(options.pageSize / 4) +
                    " texels), not " + std::to_string(options.border));
    }
    _tileSize = info.tileWidth;
    _levelShift = log2Of(options.pageSize) - log2Of(_tileSize);
    _firstSourceLevel = info.minimumLevel;
    const int finest = static_cast<int>(info.maximumLevel) - _levelShift;
    if (finest < 0) {
        throw Error(name + ": pages of " + std::to_string(options.pageSize) + " texels need source level " +
                    std::to_string(_levelShift) + " or deeper, and the deepest is " + std::to_string(info.maximumLevel));
    }
    _layout.pageSize = options.pageSize;
    _layout.border = options.border;
    _layout.finestLevel = std::min(static_cast<std::uint32_t>(finest), kMaximumVirtualTextureLevel);
}

VirtualTextureSource::~VirtualTextureSource() = default;

std::string VirtualTextureSource::describe(const PageKey& page) const
{
    return "page " + std::to_string(page.level) + "/" + std::to_string(page.x) + "/" + std::to_string(page.y) + " of " +
           _source->info().name;
}

VirtualTextureSource::CachedTile VirtualTextureSource::tile(const TileKey& key)
{
    {
        std::lock_guard lock(_mutex);
        const auto found = _cache.find(key);
        if (found != _cache.end()) {
            _recency.splice(_recency.begin(), _recency, found->second.position);
            ++_hits;
            return found->second.tile;
        }
    }
    // Fetched and decoded without the lock: workers decode different tiles at once.
    CachedTile decoded;
    const TileFetch fetched = _source->fetch(key);
    if (fetched.status == TileFetch::Status::Failed) {
        throw Error(fetched.message);
    }
    if (fetched.status == TileFetch::Status::Ok) {
        const std::string where = _source->locate(key);
        Image image = decodeImage(fetched.bytes, where, 4);
        if (image.width != _tileSize || image.height != _tileSize) {
            throw Error(where + ": the tile is " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                        " pixels, and the source's tiles are " + std::to_string(_tileSize) + " x " +
                        std::to_string(_tileSize));
        }
        decoded = std::make_shared<const Image>(std::move(image));
        ++_decoded;
    }
    std::lock_guard lock(_mutex);
    if (_cache.contains(key)) {
        return _cache[key].tile; // another worker was quicker
    }
    _recency.push_front(key);
    _cache[key] = Entry{decoded, _recency.begin()};
    _cachedBytes += decoded ? decoded->pixels.size() : kMissingTileBytes;
    while (_cachedBytes > _options.cacheBytes && _recency.size() > 1) {
        const TileKey oldest = _recency.back();
        const auto entry = _cache.find(oldest);
        _cachedBytes -= entry->second.tile ? entry->second.tile->pixels.size() : kMissingTileBytes;
        _cache.erase(entry);
        _recency.pop_back();
    }
    return decoded;
}

std::optional<Image> VirtualTextureSource::cutPage(const PageKey& page)
{
    const int pageSize = _layout.pageSize;
    const int border = _layout.border;
    const int slot = _layout.slotSize();
    // The source level read, and how many of its texels a page texel averages across and up.
    const int wanted = sourceLevelOf(page.level);
    const auto level = static_cast<std::uint32_t>(std::max(wanted, static_cast<int>(_firstSourceLevel)));
    const int factor = 1 << (static_cast<int>(level) - wanted);
    // Page texels across and up the whole level (the antimeridian wraps, the poles clamp).
    const std::int64_t levelWidth = static_cast<std::int64_t>(VirtualTextureLayout::pagesX(page.level)) * pageSize;
    const std::int64_t levelHeight = static_cast<std::int64_t>(VirtualTextureLayout::pagesY(page.level)) * pageSize;
    const std::int64_t left = static_cast<std::int64_t>(page.x) * pageSize - border;
    const std::int64_t bottom = static_cast<std::int64_t>(page.y) * pageSize - border;
    auto columnAt = [&](int i) { return ((left + i) % levelWidth + levelWidth) % levelWidth; };
    auto rowAt = [&](int j) { return std::clamp<std::int64_t>(bottom + j, 0, levelHeight - 1); };

    // The tiles under the slot, fetched once each.
    std::map<std::pair<std::int64_t, std::int64_t>, CachedTile> tiles;
    std::pair<std::int64_t, std::int64_t> lastCell{-1, -1};
    const Image* lastTile = nullptr;
    auto tileAt = [&](std::int64_t sourceX, std::int64_t sourceY) -> const Image* {
        const std::pair<std::int64_t, std::int64_t> cell{sourceX / _tileSize, sourceY / _tileSize};
        if (cell == lastCell) {
            return lastTile;
        }
        auto found = tiles.find(cell);
        if (found == tiles.end()) {
            const TileKey key{level, static_cast<std::uint32_t>(cell.first), static_cast<std::uint32_t>(cell.second)};
            found = tiles.emplace(cell, tile(key)).first;
        }
        lastCell = cell;
        lastTile = found->second.get();
        return lastTile;
    };

    Image result(slot, slot, 4);
    std::vector<std::uint8_t> fromMissing(static_cast<std::size_t>(slot) * slot, 0);
    bool anyOwnTexel = false;
    for (int j = 0; j < slot; ++j) {
        const std::int64_t row = rowAt(j);
        const int imageRow = slot - 1 - j; // rows from the north
        for (int i = 0; i < slot; ++i) {
            const std::int64_t column = columnAt(i);
            unsigned sum[4] = {0, 0, 0, 0};
            int present = 0;
            for (int b = 0; b < factor; ++b) {
                for (int a = 0; a < factor; ++a) {
                    const std::int64_t sourceX = column * factor + a;
                    const std::int64_t sourceY = row * factor + b;
                    const Image* source = tileAt(sourceX, sourceY);
                    if (!source) {
                        continue;
                    }
                    const int x = static_cast<int>(sourceX % _tileSize);
                    const int y = _tileSize - 1 - static_cast<int>(sourceY % _tileSize); // tile rows from the north
                    const std::uint8_t* texel = source->pixel(x, y);
                    for (int c = 0; c < 4; ++c) {
                        sum[c] += texel[c];
                    }
                    ++present;
                }
            }
            std::uint8_t* out = result.pixel(i, imageRow);
            const unsigned count = static_cast<unsigned>(factor * factor);
            for (int c = 0; c < 4; ++c) {
                out[c] = static_cast<std::uint8_t>((sum[c] + count / 2) / count);
            }
            const bool own = i >= border && i < border + pageSize && j >= border && j < border + pageSize;
            anyOwnTexel = anyOwnTexel || (own && present > 0);
            fromMissing[static_cast<std::size_t>(j) * slot + i] = present == 0 ? 1 : 0;
        }
    }
    if (!anyOwnTexel) {
        return std::nullopt;
    }
    // A border over a tile the source lacks repeats the page's own edge, as a clamped texture would.
    for (int j = 0; j < slot; ++j) {
        for (int i = 0; i < slot; ++i) {
            const bool own = i >= border && i < border + pageSize && j >= border && j < border + pageSize;
            if (own || !fromMissing[static_cast<std::size_t>(j) * slot + i]) {
                continue;
            }
            const int ci = std::clamp(i, border, border + pageSize - 1);
            const int cj = std::clamp(j, border, border + pageSize - 1);
            std::memcpy(result.pixel(i, slot - 1 - j), result.pixel(ci, slot - 1 - cj), 4);
        }
    }
    return result;
}

} // namespace orbis::world
