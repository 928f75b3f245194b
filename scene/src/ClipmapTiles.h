#pragma once

// The tiles a ClipmapTerrain reads its levels from: their decoded forms, the cache that keeps them
// and the search for the finest one over a point. Private to the clipmap (ClipmapTerrain.cpp).

#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/Image.h>
#include <orbis/core/TileKey.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/world/TerrainSampler.h>
#include <orbis/world/TileLoader.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

namespace orbis::scene::detail {

/// A decoded imagery tile, RGBA.
class ImageryContent final : public world::TileContent {
public:
    explicit ImageryContent(Image image_)
        : image(std::move(image_))
    {
    }
    std::size_t byteSize() const noexcept override { return image.pixels.size(); }
    Image image;
};

/// A terrain tile as a 129 x 129 lattice of its surface (world::TerrainSampler: on a mesh's triangles),
/// made on the worker that loaded it, so that a post's height is a bilinear lookup rather than a
/// search for its triangle (a level's write is twice as fast). Twice as fine as the 65 x 65
/// samples quantized-mesh tiles (ETOPO5's among them) are usually made from.
struct TerrainGrid {
    static constexpr int kSamplesLog2 = 7;
    static constexpr int kSize = (1 << kSamplesLog2) + 1;
    std::vector<float> heights; ///< kSize^2, row by row from the north
    /// A mesh tile's own triangles, for the levels finer than the data: its surface at any spacing,
    /// where the lattice's bilinear cells (or the four-point filter of them) would cut across its
    /// creases. Null for grid tiles: below their spacing the four-point filter is as good.
    std::shared_ptr<const world::TerrainSampler> mesh;

    /// Bilinear heights along the lattice at one v (a row of posts of one latitude crosses a tile
    /// at one v): the two lattice rows and their weight found once.
    struct Row {
        const float* north;
        const float* south;
        double weight; ///< of the southern row

        /// u 0 west .. 1 east, clamped.
        double at(double u) const noexcept
        {
            const double column = std::clamp(u, 0.0, 1.0) * (kSize - 1);
            const int c = std::min(static_cast<int>(column), kSize - 2);
            const double fc = column - c;
            return (1.0 - weight) * ((1.0 - fc) * static_cast<double>(north[c]) + fc * static_cast<double>(north[c + 1])) +
                   weight * ((1.0 - fc) * static_cast<double>(south[c]) + fc * static_cast<double>(south[c + 1]));
        }
    };
    /// v 0 south .. 1 north, clamped.
    Row row(double v) const noexcept
    {
        const double row = (1.0 - std::clamp(v, 0.0, 1.0)) * (kSize - 1);
        const int r = std::min(static_cast<int>(row), kSize - 2);
        const float* north = &heights[static_cast<std::size_t>(r) * kSize];
        return {north, north + kSize, row - r};
    }
    /// u 0 west .. 1 east, v 0 south .. 1 north, clamped.
    double height(double u, double v) const noexcept { return row(v).at(u); }
};

class TerrainContent final : public world::TileContent {
public:
    explicit TerrainContent(std::shared_ptr<const TerrainGrid> grid_)
        : grid(std::move(grid_))
    {
    }
    std::size_t byteSize() const noexcept override
    {
        return grid->heights.size() * sizeof(float) + (grid->mesh ? grid->mesh->memoryBytes() : 0);
    }
    std::shared_ptr<const TerrainGrid> grid;
};

std::uint64_t ticketFor(int kind, const TileKey& key) noexcept
{
    return (static_cast<std::uint64_t>(kind) << 62) | (static_cast<std::uint64_t>(key.level) << 56) |
           (static_cast<std::uint64_t>(key.x) << 28) | static_cast<std::uint64_t>(key.y);
}

struct KeyHash {
    std::size_t operator()(const TileKey& key) const noexcept { return static_cast<std::size_t>(ticketFor(0, key)); }
};

/// Loaded tiles of one kind, least recently used last, capped in bytes.
template <typename Value>
class TileCache {
public:
    const Value* find(const TileKey& key)
    {
        const auto found = _entries.find(key);
        if (found == _entries.end()) {
            return nullptr;
        }
        _order.splice(_order.begin(), _order, found->second.position);
        return &found->second.value;
    }
    bool contains(const TileKey& key) const { return _entries.contains(key); }
    void insert(const TileKey& key, Value value, std::size_t bytes, std::size_t capBytes)
    {
        if (_entries.contains(key)) {
            return;
        }
        _order.push_front(key);
        _entries.emplace(key, Entry{std::move(value), bytes, _order.begin()});
        _bytes += bytes;
        while (_bytes > capBytes && _order.size() > 1) {
            const auto last = _entries.find(_order.back());
            _bytes -= last->second.bytes;
            _entries.erase(last);
            _order.pop_back();
        }
    }

private:
    struct Entry {
        Value value;
        std::size_t bytes;
        std::list<TileKey>::iterator position;
    };
    std::unordered_map<TileKey, Entry, KeyHash> _entries;
    std::list<TileKey> _order;
    std::size_t _bytes = 0;
};

/// The finest tile in a cache over a point, from `level` up, remembering the last answer and where
/// it holds, so that a row of posts looks a tile up once.
template <typename Value>
struct TileFinder {
    TileFinder(TileCache<Value>* cache_, TilingScheme scheme_, std::uint32_t minimumLevel_)
        : cache(cache_)
        , scheme(scheme_)
        , minimumLevel(minimumLevel_)
    {
    }

    TileCache<Value>* cache;
    TilingScheme scheme;
    std::uint32_t minimumLevel;
    TileKey lastKey{};
    GeodeticExtent lastExtent{};
    const Value* last = nullptr;

    /// The finest tile over g from `level` up, and where g lies in it (0..1 west to east, south
    /// to north); null where none is loaded.
    const Value* find(const Geodetic2D& g, std::uint32_t level, glm::dvec2& uv)
    {
        if (!(level == _askedLevel && holds(g))) {
            search(g, level);
        }
        if (last) {
            uv = positionInLast(g);
        }
        return last;
    }

    /// Whether the last answer holds at g too.
    bool holds(const Geodetic2D& g) const noexcept
    {
        return g.longitude >= _holds.west && g.longitude <= _holds.east && g.latitude >= _holds.south &&
               g.latitude <= _holds.north;
    }

    /// Where g lies in the last tile found (g inside it).
    glm::dvec2 positionInLast(const Geodetic2D& g) const noexcept
    {
        if (scheme.projection() == TilingProjection::Geographic) {
            // From the extent found, without the scheme's general arithmetic.
            return {(g.longitude - lastExtent.west) * _perRadian.x, (g.latitude - lastExtent.south) * _perRadian.y};
        }
        return scheme.positionInTile(lastKey, g);
    }

private:
    void search(const Geodetic2D& g, std::uint32_t level)
    {
        // The answer holds over the tile of the level asked for at g: every point of it has the
        // same ancestors, so the same finest loaded one (a coarser tile found holds only there,
        // not over its whole extent, where finer tiles may be loaded).
        _askedLevel = level;
        _holds = kNowhere;
        last = nullptr;
        bool first = true;
        for (std::int64_t l = level; l >= static_cast<std::int64_t>(minimumLevel); --l) {
            const std::optional<TileKey> at = scheme.tileAt(g, static_cast<std::uint32_t>(l));
            if (!at) {
                continue;
            }
            if (first) {
                _holds = scheme.tileExtent(*at);
                first = false;
            }
            if (const Value* value = cache->find(*at)) {
                last = value;
                lastKey = *at;
                lastExtent = scheme.tileExtent(*at);
                _perRadian = {1.0 / (lastExtent.east - lastExtent.west), 1.0 / (lastExtent.north - lastExtent.south)};
                return;
            }
        }
    }

    static constexpr GeodeticExtent kNowhere{0.0, 1.0, 0.0, -1.0}; ///< south above north: holds no point
    std::uint32_t _askedLevel = ~0u;
    GeodeticExtent _holds = kNowhere; ///< where the last search's answer holds
    glm::dvec2 _perRadian{0.0};       ///< 1 / the last tile's width and height: a post's position a multiply
};

} // namespace orbis::scene::detail
