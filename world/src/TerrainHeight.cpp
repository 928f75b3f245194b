#include "orbis/world/TerrainHeight.h"

#include "orbis/world/TerrainSampler.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>

#include <algorithm>
#include <cmath>
#include <list>
#include <map>

namespace orbis::world {

namespace {

/// The longitude, a turn away where needed, that lies within west..east; empty when none does.
std::optional<double> longitudeWithin(double longitude, double west, double east) noexcept
{
    for (const double shift : {0.0, kTwoPi, -kTwoPi}) {
        const double shifted = longitude + shift;
        if (shifted >= west && shifted <= east) {
            return shifted;
        }
    }
    return std::nullopt;
}

/// Where a position falls in a tile: u west to east, v south to north, both 0..1; empty outside.
std::optional<std::pair<double, double>> tileCoordinates(const TileKey& key, const Geodetic2D& position) noexcept
{
    const GeodeticExtent extent = TilingScheme::geographic().tileExtent(key);
    const std::optional<double> longitude = longitudeWithin(position.longitude, extent.west, extent.east);
    if (!longitude || !(position.latitude >= extent.south && position.latitude <= extent.north)) {
        return std::nullopt;
    }
    return std::pair((*longitude - extent.west) / (extent.east - extent.west),
                     (position.latitude - extent.south) / (extent.north - extent.south));
}

/// The height of a tile at u, v: bilinear on a grid, on the triangle of a mesh that holds the
/// point; none for a malformed grid or a point in no triangle.
std::optional<double> heightIn(const TerrainSampler& sampler, double u, double v)
{
    const TerrainTileData& tile = sampler.data();
    if (!tile.isMesh() &&
        (tile.size < 2 || tile.heights.size() != static_cast<std::size_t>(tile.size) * static_cast<std::size_t>(tile.size))) {
        return std::nullopt;
    }
    return sampler.heightOnTriangles(u, v);
}

} // namespace

std::optional<double> terrainTileHeight(const TerrainTileData& tile, const Geodetic2D& position)
{
    const auto coordinates = tileCoordinates(tile.key, position);
    if (!coordinates) {
        return std::nullopt;
    }
    // Not owned: the sampler lives for this call only.
    const TerrainSampler sampler(std::shared_ptr<const TerrainTileData>(&tile, [](const TerrainTileData*) {}));
    return heightIn(sampler, coordinates->first, coordinates->second);
}

std::vector<TileKey> terrainTilesAt(std::uint32_t level, const Geodetic2D& position)
{
    const TilingScheme scheme = TilingScheme::geographic();
    std::vector<TileKey> keys;
    if (level > kMaximumTileLevel || !std::isfinite(position.longitude) || !(std::abs(position.latitude) <= kHalfPi)) {
        return keys;
    }
    const double longitude = std::remainder(position.longitude, kTwoPi); // -pi .. pi
    const double span = kPi / static_cast<double>(std::uint64_t{1} << level);
    const auto columns = static_cast<std::int64_t>(scheme.tilesX(level));
    const auto rows = static_cast<std::int64_t>(scheme.tilesY(level));
    const auto column = std::clamp(static_cast<std::int64_t>(std::floor((longitude + kPi) / span)), std::int64_t{0}, columns - 1);
    const auto row = std::clamp(static_cast<std::int64_t>(std::floor((position.latitude + kHalfPi) / span)), std::int64_t{0}, rows - 1);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const std::int64_t y = row + dy;
        if (y < 0 || y >= rows) {
            continue;
        }
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
            const auto x = static_cast<std::uint32_t>((column + dx + columns) % columns);
            const TileKey key{level, x, static_cast<std::uint32_t>(y)};
            if (tileCoordinates(key, {longitude, position.latitude}) && std::find(keys.begin(), keys.end(), key) == keys.end()) {
                keys.push_back(key);
            }
        }
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

struct TerrainHeightQuery::Impl {
    struct Entry {
        std::shared_ptr<const TerrainTileData> tile; ///< null: the source has no such tile
        std::optional<TerrainSampler> sampler;       ///< over the tile (a mesh's triangles indexed)
        std::size_t bytes = 0;
        std::list<TileKey>::iterator position;
    };

    TerrainSource& source;
    std::size_t budget;
    std::size_t bytes = 0;
    std::size_t loaded = 0;
    std::map<TileKey, Entry> entries;
    std::list<TileKey> recent; ///< most recently used first

    Impl(TerrainSource& s, std::size_t cacheBytes) : source(s), budget(cacheBytes) {}

    const Entry& load(const TileKey& key)
    {
        if (const auto found = entries.find(key); found != entries.end()) {
            recent.splice(recent.begin(), recent, found->second.position);
            return found->second;
        }
        TerrainFetch fetched = source.load(key);
        if (fetched.status == TerrainFetch::Status::Failed) {
            throw Error(fetched.message);
        }
        ++loaded;
        Entry entry;
        if (fetched.status == TerrainFetch::Status::Ok) {
            auto tile = std::make_shared<const TerrainTileData>(std::move(fetched.tile));
            entry.sampler.emplace(tile);
            entry.bytes = entry.sampler->memoryBytes(); // the tile and the sampler's index over it
            entry.tile = std::move(tile);
        }
        entry.bytes += 128;
        recent.push_front(key);
        entry.position = recent.begin();
        bytes += entry.bytes;
        const Entry& kept = entries.emplace(key, std::move(entry)).first->second;
        // The entry just made stays, whatever its size: the caller reads it now.
        while (bytes > budget && recent.size() > 1) {
            const auto oldest = entries.find(recent.back());
            recent.pop_back();
            bytes -= oldest->second.bytes;
            entries.erase(oldest);
        }
        return kept;
    }
};

TerrainHeightQuery::TerrainHeightQuery(TerrainSource& source, std::size_t cacheBytes)
    : _impl(std::make_unique<Impl>(source, cacheBytes))
{
}

TerrainHeightQuery::~TerrainHeightQuery() = default;

std::size_t TerrainHeightQuery::tilesLoaded() const noexcept
{
    return _impl->loaded;
}

std::optional<TerrainHeight> TerrainHeightQuery::at(const Geodetic2D& position)
{
    Impl& impl = *_impl;
    const TerrainSourceInfo& info = impl.source.info();
    // Down the quadtree: at each level the tiles holding the point that the source has, whose
    // parent (loaded a level up) lists them in its child mask.
    std::optional<TerrainHeight> best;
    std::vector<TileKey> present; // the level above's tiles that loaded
    std::vector<std::uint8_t> childMasks;
    for (std::uint32_t level = info.minimumLevel; level <= info.maximumLevel; ++level) {
        std::vector<TileKey> found;
        std::vector<std::uint8_t> masks;
        double sum = 0.0;
        int count = 0;
        for (const TileKey& key : terrainTilesAt(level, position)) {
            if (level > info.minimumLevel) {
                const auto parent = std::find(present.begin(), present.end(), key.ancestor(level - 1));
                const int child = static_cast<int>((key.x & 1u) | ((key.y & 1u) << 1));
                if (parent == present.end() || (childMasks[static_cast<std::size_t>(parent - present.begin())] & (1 << child)) == 0) {
                    continue;
                }
            }
            if (!impl.source.hasTile(key)) {
                continue;
            }
            const Impl::Entry& entry = impl.load(key);
            if (!entry.tile) {
                continue;
            }
            const TerrainTileData& tile = *entry.tile;
            found.push_back(key);
            masks.push_back(tile.childMask);
            const auto coordinates = tileCoordinates(key, position);
            if (const auto height = heightIn(*entry.sampler, coordinates->first, coordinates->second)) {
                if (count == 0) {
                    best = TerrainHeight{0.0, key, tile.geometricError};
                }
                sum += *height;
                ++count;
            }
        }
        if (count > 0) {
            best->height = sum / count;
        }
        if (found.empty()) {
            break;
        }
        present = std::move(found);
        childMasks = std::move(masks);
        if (level == kMaximumTileLevel) {
            break;
        }
    }
    return best;
}

std::future<std::vector<std::optional<TerrainHeight>>> mostDetailedHeights(std::shared_ptr<TerrainSource> source,
                                                                           std::vector<Geodetic2D> positions)
{
    return std::async(std::launch::async, [source = std::move(source), positions = std::move(positions)] {
        TerrainHeightQuery query(*source);
        std::vector<std::optional<TerrainHeight>> heights;
        heights.reserve(positions.size());
        for (const Geodetic2D& position : positions) {
            heights.push_back(query.at(position));
        }
        return heights;
    });
}

} // namespace orbis::world
