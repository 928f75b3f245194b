#pragma once

// A geographic tile source made up on the fly, for tests of what is cut and drawn from tiles: each
// texel's colour is a function of its level and of the longitude and latitude of its centre, so a
// test knows what any texel of any level must be; tiles can be made missing or failing.

#include <orbis/core/Image.h>
#include <orbis/world/TileSource.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>

namespace orbis::test {

/// RGBA of a texel from its level and its centre's u (0 at 180 W .. 1 at 180 E) and v (0 south .. 1 north).
using TexelPattern = std::function<std::array<std::uint8_t, 4>(std::uint32_t level, double u, double v)>;

/// The same at every level, unique to each place (a wrong page shows): red a triangle wave of
/// eight periods across, green one of four up, blue u itself.
std::array<std::uint8_t, 4> placePattern(std::uint32_t level, double u, double v);

struct ProceduralTileSourceOptions {
    TexelPattern pattern = placePattern;
    std::uint32_t minimumLevel = 0;
    std::uint32_t maximumLevel = 4;
    int tileSize = 256;
    /// Tiles the source does not have (a 404) and tiles whose fetch fails.
    std::function<bool(const TileKey&)> missing;
    std::function<bool(const TileKey&)> failing;
};

/// Tiles as PNG bytes (lossless: decoded, each texel is exactly the pattern's).
class ProceduralTileSource final : public world::TileSource {
public:
    explicit ProceduralTileSource(ProceduralTileSourceOptions options = {});
    const world::TileSourceInfo& info() const noexcept override { return _info; }
    world::TileFetch fetch(const TileKey& key) override;
    std::string locate(const TileKey& key) const override;

    /// The tile as it decodes: rows from the north.
    Image tileImage(const TileKey& key) const;
    std::uint64_t fetches() const noexcept { return _fetches.load(); }

private:
    ProceduralTileSourceOptions _options;
    world::TileSourceInfo _info;
    std::atomic<std::uint64_t> _fetches{0};
};

} // namespace orbis::test
