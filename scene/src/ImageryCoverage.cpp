#include "orbis/scene/ImageryCoverage.h"

#include <algorithm>
#include <cmath>

namespace orbis::scene {

namespace {

/// The longitude ranges of an extent as one or two non-wrapping intervals.
std::vector<glm::dvec2> longitudeIntervals(const GeodeticExtent& extent)
{
    if (extent.east >= extent.west) {
        return {{extent.west, extent.east}};
    }
    return {{extent.west, kPi}, {-kPi, extent.east}};
}

/// The overlap of [a] and [b] when it has some length.
std::optional<glm::dvec2> overlap(const glm::dvec2& a, const glm::dvec2& b)
{
    const glm::dvec2 result(std::max(a.x, b.x), std::min(a.y, b.y));
    return result.y > result.x ? std::optional(result) : std::nullopt;
}

/// The part of the surface extent (which never crosses the antimeridian) inside `limit`.
std::optional<GeodeticExtent> intersect(const GeodeticExtent& surface, const GeodeticExtent& limit)
{
    const auto latitudes = overlap({surface.south, surface.north}, {limit.south, limit.north});
    if (!latitudes) {
        return std::nullopt;
    }
    for (const glm::dvec2& interval : longitudeIntervals(limit)) {
        if (const auto longitudes = overlap({surface.west, surface.east}, interval)) {
            return GeodeticExtent{longitudes->x, latitudes->x, longitudes->y, latitudes->y};
        }
    }
    return std::nullopt;
}

} // namespace

std::uint32_t imageryLevelFor(const ImageryTiling& tiling, const Ellipsoid& ellipsoid, const GeodeticExtent& surfaceExtent,
                              double errorMeters) noexcept
{
    const double radius = ellipsoid.maximumRadius();
    // Texel size at level 0; it halves with each level.
    double texelAtLevelZero = 0.0;
    if (tiling.scheme.projection() == TilingProjection::Geographic) {
        texelAtLevelZero = radius * (kPi / tiling.scheme.tilesY(0)) / tiling.tileHeight;
    } else {
        const double nearestEquator =
            surfaceExtent.south > 0.0 ? surfaceExtent.south : (surfaceExtent.north < 0.0 ? -surfaceExtent.north : 0.0);
        const double latitude = std::min(nearestEquator, TilingScheme::kMaximumMercatorLatitude);
        texelAtLevelZero = radius * std::cos(latitude) * kTwoPi / tiling.tileWidth;
    }
    std::uint32_t level = tiling.minimumLevel;
    // A relative tolerance, so that texels equal to the error (the default quadtree) count as fine.
    while (level < tiling.maximumLevel && std::ldexp(texelAtLevelZero, -static_cast<int>(level)) > errorMeters * (1.0 + 1e-9)) {
        ++level;
    }
    return level;
}

std::vector<TileKey> imageryTilesOver(const ImageryTiling& tiling, std::uint32_t level, const GeodeticExtent& surfaceExtent)
{
    std::vector<TileKey> keys;
    const auto withinCoverage = intersect(surfaceExtent, tiling.scheme.coverage());
    if (!withinCoverage) {
        return keys;
    }
    const auto inside = intersect(*withinCoverage, tiling.extent);
    if (!inside) {
        return keys;
    }
    // The tiles holding the corners, taken a hair inside so that a shared edge does not pull in
    // the neighbour.
    const double insetX = 1e-9 * (inside->east - inside->west);
    const double insetY = 1e-9 * (inside->north - inside->south);
    const TilingScheme& scheme = tiling.scheme;
    const auto northWest = scheme.tileAt({inside->west + insetX, inside->north - insetY}, level);
    const auto southEast = scheme.tileAt({inside->east - insetX, inside->south + insetY}, level);
    if (!northWest || !southEast) {
        return keys;
    }
    const std::uint32_t firstRow = std::min(northWest->y, southEast->y);
    const std::uint32_t lastRow = std::max(northWest->y, southEast->y);
    for (std::uint32_t y = firstRow; y <= lastRow; ++y) {
        for (std::uint32_t x = northWest->x; x <= southEast->x; ++x) {
            keys.push_back({level, x, y});
        }
    }
    return keys;
}

std::optional<ImageryPlacement> placeImagery(const GeodeticExtent& imageryExtent, const GeodeticExtent& surfaceExtent,
                                             const std::optional<GeodeticExtent>& clip) noexcept
{
    auto covered = intersect(surfaceExtent, imageryExtent);
    if (covered && clip) {
        covered = intersect(*covered, *clip);
    }
    if (!covered) {
        return std::nullopt;
    }
    const double surfaceWidth = surfaceExtent.east - surfaceExtent.west;
    const double surfaceHeight = surfaceExtent.north - surfaceExtent.south;
    const double imageryWidth = imageryExtent.east - imageryExtent.west;
    const double imageryHeight = imageryExtent.north - imageryExtent.south;
    ImageryPlacement placement;
    placement.scale = {surfaceWidth / imageryWidth, surfaceHeight / imageryHeight};
    placement.translation = {(surfaceExtent.west - imageryExtent.west) / imageryWidth,
                             (surfaceExtent.south - imageryExtent.south) / imageryHeight};
    placement.tileRectangle = {(covered->west - surfaceExtent.west) / surfaceWidth,
                               (covered->south - surfaceExtent.south) / surfaceHeight,
                               (covered->east - surfaceExtent.west) / surfaceWidth,
                               (covered->north - surfaceExtent.south) / surfaceHeight};
    return placement;
}

std::vector<glm::dvec2> mercatorReprojectionRows(const GeodeticExtent& extent, int rows)
{
    const double south = TilingScheme::mercatorY(extent.south);
    const double north = TilingScheme::mercatorY(extent.north);
    auto sample = [&](double y) {
        const double latitude = extent.south + (extent.north - extent.south) * y;
        return glm::dvec2(y, (TilingScheme::mercatorY(latitude) - south) / (north - south));
    };
    std::vector<glm::dvec2> samples;
    samples.reserve(static_cast<std::size_t>(rows) + 2);
    samples.emplace_back(0.0, 0.0);
    for (int k = 0; k < rows; ++k) {
        samples.push_back(sample((k + 0.5) / rows));
    }
    samples.emplace_back(1.0, 1.0);
    return samples;
}

} // namespace orbis::scene
