#include "orbis/core/TilingScheme.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace orbis {

namespace {

/// log2 of the number of columns at `level`: one more than the level for the two geographic roots.
int columnsLog2(TilingProjection projection, std::uint32_t level) noexcept
{
    return static_cast<int>(level) + (projection == TilingProjection::Geographic ? 1 : 0);
}

/// The fraction edge / 2^log2Count mapped onto [-1, 1]. Exact: a dyadic fraction with fewer than
/// 53 bits, so edge 2i at log2Count + 1 gives the same double as edge i at log2Count.
double signedEdgeFraction(std::uint32_t edge, int log2Count) noexcept
{
    return std::ldexp(static_cast<double>(edge), 1 - log2Count) - 1.0;
}

/// Longitude taken into [-pi, pi): pi names the same meridian as -pi, the first column's west edge.
double wrapLongitude(double longitude) noexcept
{
    double wrapped = std::remainder(longitude, kTwoPi); // [-pi, pi]
    if (wrapped >= kPi) {
        wrapped -= kTwoPi;
    }
    return wrapped;
}

} // namespace

std::uint32_t TilingScheme::tilesX(std::uint32_t level) const noexcept
{
    assert(level <= kMaximumTileLevel);
    return std::uint32_t{1} << columnsLog2(_projection, level);
}

std::uint32_t TilingScheme::tilesY(std::uint32_t level) const noexcept
{
    assert(level <= kMaximumTileLevel);
    return std::uint32_t{1} << level;
}

bool TilingScheme::isValid(const TileKey& key) const noexcept
{
    return key.level <= kMaximumTileLevel && key.x < tilesX(key.level) && key.y < tilesY(key.level);
}

GeodeticExtent TilingScheme::coverage() const noexcept
{
    if (_projection == TilingProjection::Geographic) {
        return GeodeticExtent::maximum();
    }
    return {-kPi, edgeLatitude(0, 1), kPi, edgeLatitude(0, 0)};
}

double TilingScheme::edgeLongitude(std::uint32_t level, std::uint32_t edge) const noexcept
{
    assert(edge <= tilesX(level));
    return kPi * signedEdgeFraction(edge, columnsLog2(_projection, level));
}

double TilingScheme::edgeLatitude(std::uint32_t level, std::uint32_t edge) const noexcept
{
    assert(edge <= tilesY(level));
    const double fraction = signedEdgeFraction(edge, static_cast<int>(level));
    if (_projection == TilingProjection::Geographic) {
        return kHalfPi * fraction;
    }
    return mercatorLatitude(-kPi * fraction);
}

GeodeticExtent TilingScheme::tileExtent(const TileKey& key) const noexcept
{
    assert(isValid(key));
    const double west = edgeLongitude(key.level, key.x);
    const double east = edgeLongitude(key.level, key.x + 1);
    if (_projection == TilingProjection::Geographic) {
        return {west, edgeLatitude(key.level, key.y), east, edgeLatitude(key.level, key.y + 1)};
    }
    return {west, edgeLatitude(key.level, key.y + 1), east, edgeLatitude(key.level, key.y)};
}

std::optional<TileKey> TilingScheme::tileAt(const Geodetic2D& g, std::uint32_t level) const noexcept
{
    if (!std::isfinite(g.longitude) || !std::isfinite(g.latitude) || level > kMaximumTileLevel) {
        return std::nullopt;
    }
    const GeodeticExtent limits = coverage();
    if (g.latitude < limits.south || g.latitude > limits.north) {
        return std::nullopt;
    }
    const double longitude = wrapLongitude(g.longitude);
    const std::uint32_t columns = tilesX(level);
    const std::uint32_t rows = tilesY(level);

    // A first guess from the fraction, then corrected against the very edges tileExtent reports,
    // so that a point on an edge lands on the side the comment in the header promises.
    auto guess = [](double fraction, std::uint32_t count) {
        return static_cast<std::uint32_t>(std::clamp(std::floor(fraction * count), 0.0, count - 1.0));
    };
    std::uint32_t x = guess((longitude + kPi) / kTwoPi, columns);
    while (x > 0 && longitude < edgeLongitude(level, x)) {
        --x;
    }
    while (x + 1 < columns && longitude >= edgeLongitude(level, x + 1)) {
        ++x;
    }

    std::uint32_t y = 0;
    if (_projection == TilingProjection::Geographic) {
        y = guess((g.latitude + kHalfPi) / kPi, rows);
        while (y > 0 && g.latitude < edgeLatitude(level, y)) {
            --y;
        }
        while (y + 1 < rows && g.latitude >= edgeLatitude(level, y + 1)) {
            ++y;
        }
    } else {
        // Rows from the north: row y spans [edgeLatitude(y + 1), edgeLatitude(y)).
        y = guess(0.5 - mercatorY(g.latitude) / kTwoPi, rows);
        while (y > 0 && g.latitude >= edgeLatitude(level, y)) {
            --y;
        }
        while (y + 1 < rows && g.latitude < edgeLatitude(level, y + 1)) {
            ++y;
        }
    }
    return TileKey{level, x, y};
}

glm::dvec2 TilingScheme::positionInTile(const TileKey& key, const Geodetic2D& g) const noexcept
{
    const GeodeticExtent extent = tileExtent(key);
    const double centre = 0.5 * (extent.west + extent.east);
    const double longitude = centre + std::remainder(g.longitude - centre, kTwoPi);
    const double u = (longitude - extent.west) / (extent.east - extent.west);
    if (_projection == TilingProjection::Geographic) {
        return {u, (g.latitude - extent.south) / (extent.north - extent.south)};
    }
    const double south = mercatorY(extent.south);
    return {u, (mercatorY(g.latitude) - south) / (mercatorY(extent.north) - south)};
}

double TilingScheme::geometricError(const Ellipsoid& ellipsoid, std::uint32_t level, int samplesAcross) const noexcept
{
    assert(samplesAcross >= 2);
    const double levelZero = ellipsoid.maximumRadius() * kTwoPi * 0.25 / (samplesAcross * static_cast<double>(tilesX(0)));
    return std::ldexp(levelZero, -static_cast<int>(level));
}

double TilingScheme::mercatorY(double latitude) noexcept
{
    return std::atanh(std::sin(latitude));
}

double TilingScheme::mercatorLatitude(double mercatorY) noexcept
{
    return std::atan(std::sinh(mercatorY));
}

} // namespace orbis
