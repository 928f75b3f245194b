#pragma once

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/GeodeticExtent.h"
#include "orbis/core/TileKey.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <optional>

namespace orbis {

/// How a quadtree pyramid cuts the globe into tiles.
enum class TilingProjection {
    /// EPSG:4326 plate carree: two root tiles (west and east hemispheres), rows counted from the
    /// south (TMS), tiles square in degrees.
    Geographic,
    /// EPSG:3857 Web Mercator: one root tile up to +-85.0511 degrees, rows counted from the north
    /// (XYZ, as web maps name them), tiles square in Mercator metres.
    WebMercator,
};

/// The tile rectangles of a quadtree pyramid over the globe. Edges are computed from the level
/// and an integer edge index by one function, so neighbours share their edges bit for bit, and a
/// parent's edges are bit for bit its children's outer edges, at every level up to
/// kMaximumTileLevel. Angles in radians.
///
/// ```
/// const TilingScheme scheme = TilingScheme::geographic();
/// const GeodeticExtent paris = scheme.tileExtent(*scheme.tileAt(Geodetic2D::fromDegrees(2.35, 48.86), 12));
/// ```
class TilingScheme final {
public:
    static TilingScheme geographic() noexcept { return TilingScheme(TilingProjection::Geographic); }
    static TilingScheme webMercator() noexcept { return TilingScheme(TilingProjection::WebMercator); }

    TilingProjection projection() const noexcept { return _projection; }

    /// Columns and rows at a level (level <= kMaximumTileLevel, asserted).
    std::uint32_t tilesX(std::uint32_t level) const noexcept;
    std::uint32_t tilesY(std::uint32_t level) const noexcept;
    /// True when the key's level is at most kMaximumTileLevel and its column and row exist there.
    bool isValid(const TileKey& key) const noexcept;

    /// What the pyramid covers: the whole globe (geographic), or the globe between
    /// +-kMaximumMercatorLatitude (Web Mercator).
    GeodeticExtent coverage() const noexcept;

    /// Longitude of the western edge of column `edge` at `level` (edge in 0..tilesX(level));
    /// -pi at 0 and exactly pi at tilesX(level).
    double edgeLongitude(std::uint32_t level, std::uint32_t edge) const noexcept;
    /// Latitude of the edge between rows edge - 1 and edge at `level` (edge in 0..tilesY(level)),
    /// in the scheme's row direction: -pi/2 at 0 for Geographic (from the south), the
    /// northern limit at 0 for WebMercator (from the north).
    double edgeLatitude(std::uint32_t level, std::uint32_t edge) const noexcept;

    /// The tile's rectangle; its east never wraps (east > west), and the last column's east is pi.
    GeodeticExtent tileExtent(const TileKey& key) const noexcept;

    /// The tile at `level` that contains g (longitude taken modulo 2 pi); a point on an edge
    /// belongs to the tile east (and, for rows, north) of it, except at the last column or row.
    /// Empty when g is not finite or, for WebMercator, beyond the latitude limit.
    std::optional<TileKey> tileAt(const Geodetic2D& g, std::uint32_t level) const noexcept;

    /// Where g lies in the tile, 0..1 west to east and south to north (not clamped), for
    /// texture coordinates; Mercator tiles measure the vertical in Mercator y. g's longitude is
    /// taken within pi of the tile's centre, so tiles at the antimeridian need no special case.
    glm::dvec2 positionInTile(const TileKey& key, const Geodetic2D& g) const noexcept;

    /// The largest geometric error (metres) of a regular grid of samplesAcross x samplesAcross
    /// heights per tile at `level`, on the ellipsoid: a quarter of the equator over the samples
    /// across the root tiles, halved per level (Rendering Massive Virtual Worlds, 3.2). With 65
    /// samples, level 0 of the geographic scheme allows 77 km and level 17 less than a metre.
    double geometricError(const Ellipsoid& ellipsoid, std::uint32_t level, int samplesAcross = 65) const noexcept;

    /// Web Mercator's latitude limit, atan(sinh(pi)): the square world map's edge, 85.0511 degrees.
    static constexpr double kMaximumMercatorLatitude = 1.4844222297453324;

    /// Mercator y (unit sphere) of a latitude, and back: y = atanh(sin(latitude)).
    static double mercatorY(double latitude) noexcept;
    static double mercatorLatitude(double mercatorY) noexcept;

    friend bool operator==(const TilingScheme&, const TilingScheme&) = default;

private:
    explicit TilingScheme(TilingProjection projection) noexcept : _projection(projection) {}

    TilingProjection _projection;
};

} // namespace orbis
