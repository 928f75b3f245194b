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
#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <list>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

namespace orbis::scene::detail {

/// A decoded imagery tile as one RGBA word a texel (its four bytes in memory order), so that a
/// batch of bilinear lookups loads a texel as one word (vector gathers).
struct ImageTexels {
    int width = 0, height = 0;
    std::vector<std::uint32_t> texels; ///< row by row from the north

    explicit ImageTexels(const Image& rgba)
        : width(rgba.width)
        , height(rgba.height)
        , texels(static_cast<std::size_t>(rgba.width) * static_cast<std::size_t>(rgba.height))
    {
        assert(rgba.channels == 4);
        std::memcpy(texels.data(), rgba.pixels.data(), texels.size() * sizeof(std::uint32_t));
    }
};

class ImageryContent final : public world::TileContent {
public:
    explicit ImageryContent(const Image& rgba)
        : image(std::make_shared<const ImageTexels>(rgba))
    {
    }
    std::size_t byteSize() const noexcept override { return image->texels.size() * sizeof(std::uint32_t); }
    std::shared_ptr<const ImageTexels> image;
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

/// The finest tile in a cache over a point, from `level` up, remembering its last few answers and
/// where each holds, so that the posts of a row look a tile up once, and the next row's again
/// not at all. Its answers point into the cache: it lives while nothing is inserted (one frame's
/// writes).
template <typename Value>
class TileFinder {
public:
    TileFinder(TileCache<Value>* cache, TilingScheme scheme, std::uint32_t minimumLevel)
        : _cache(cache)
        , _scheme(scheme)
        , _minimumLevel(minimumLevel)
    {
    }

    /// The finest tile over g from `level` up, and where g lies in it (0..1 west to east, south
    /// to north); null where none is loaded.
    const Value* find(const Geodetic2D& g, std::uint32_t level, glm::dvec2& uv)
    {
        if (!(level == _answer.askedLevel && holds(g))) {
            recall(g, level);
        }
        if (_answer.value) {
            uv = positionInLast(g);
        }
        return _answer.value;
    }

    /// The last tile found's key (find returned non-null).
    const TileKey& lastKey() const noexcept { return _answer.key; }

    /// Whether the last answer holds at g too.
    bool holds(const Geodetic2D& g) const noexcept
    {
        const GeodeticExtent& e = _answer.holds;
        return g.longitude >= e.west && g.longitude <= e.east && g.latitude >= e.south && g.latitude <= e.north;
    }

    /// Where g lies in the last tile found (g inside it).
    glm::dvec2 positionInLast(const Geodetic2D& g) const noexcept
    {
        glm::dvec2 uv;
        positionsInLast(&g, 1, &uv.x, &uv.y);
        return uv;
    }

    /// Where each of `count` points lies in the last tile found (all inside it): u, v.
    void positionsInLast(const Geodetic2D* g, std::size_t count, double* u, double* v) const noexcept
    {
        if (_scheme.projection() == TilingProjection::Geographic) {
            // From the extent found, without the scheme's general arithmetic.
            const GeodeticExtent& e = _answer.extent;
            for (std::size_t k = 0; k < count; ++k) {
                u[k] = (g[k].longitude - e.west) * _answer.perRadian.x;
                v[k] = (g[k].latitude - e.south) * _answer.perRadian.y;
            }
            return;
        }
        for (std::size_t k = 0; k < count; ++k) {
            const glm::dvec2 uv = _scheme.positionInTile(_answer.key, g[k]);
            u[k] = uv.x;
            v[k] = uv.y;
        }
    }

private:
    static constexpr GeodeticExtent kNowhere{0.0, 1.0, 0.0, -1.0}; ///< south above north: holds no point

    struct Answer {
        std::uint32_t askedLevel = ~0u;
        GeodeticExtent holds = kNowhere; ///< where it holds
        const Value* value = nullptr;    ///< null: no tile loaded there
        TileKey key{};
        GeodeticExtent extent{};
        glm::dvec2 perRadian{0.0}; ///< 1 / the tile's width and height: a point's position a multiply
    };

    /// Makes the answer at g current: a recent one that holds there, or a new search.
    void recall(const Geodetic2D& g, std::uint32_t level)
    {
        for (Answer& recent : _recent) {
            std::swap(recent, _answer);
            if (level == _answer.askedLevel && holds(g)) {
                return;
            }
        }
        // None holds: the oldest (now current) gives way to a search.
        _answer = search(g, level);
    }

    Answer search(const Geodetic2D& g, std::uint32_t level)
    {
        // The answer holds over the tile of the level asked for at g: every point of it has the
        // same ancestors, so the same finest loaded one (a coarser tile found holds only there,
        // not over its whole extent, where finer tiles may be loaded).
        Answer answer;
        answer.askedLevel = level;
        bool first = true;
        for (std::int64_t l = level; l >= static_cast<std::int64_t>(_minimumLevel); --l) {
            const std::optional<TileKey> at = _scheme.tileAt(g, static_cast<std::uint32_t>(l));
            if (!at) {
                continue;
            }
            if (first) {
                answer.holds = _scheme.tileExtent(*at);
                first = false;
            }
            if (const Value* value = _cache->find(*at)) {
                answer.value = value;
                answer.key = *at;
                answer.extent = _scheme.tileExtent(*at);
                answer.perRadian = {1.0 / (answer.extent.east - answer.extent.west),
                                    1.0 / (answer.extent.north - answer.extent.south)};
                break;
            }
        }
        return answer;
    }

    TileCache<Value>* _cache;
    TilingScheme _scheme;
    std::uint32_t _minimumLevel;
    Answer _answer;
    /// The answers before it, the most recent first: a row of posts crosses a few tiles, the next
    /// row the same ones.
    std::array<Answer, 7> _recent;
};

} // namespace orbis::scene::detail
