#pragma once

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/TileKey.h>
#include <orbis/core/TilingScheme.h>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace orbis::scene {

/// How an imagery layer's tiles are cut, as far as putting them on the globe needs.
struct ImageryTiling {
    TilingScheme scheme = TilingScheme::geographic();
    std::uint32_t minimumLevel = 0;
    std::uint32_t maximumLevel = 0;
    int tileWidth = 256;  ///< pixels
    int tileHeight = 256;
    GeodeticExtent extent = GeodeticExtent::maximum(); ///< where the source has tiles
};

/// The coarsest level of the tiling whose texels over the surface extent are no coarser than
/// errorMeters (the surface tile's geometric error), clamped to the tiling's levels. Texels are
/// measured along the meridian for geographic tiles, and at the latitude nearest the equator for
/// Web Mercator ones (their texels shrink towards the poles).
std::uint32_t imageryLevelFor(const ImageryTiling& tiling, const Ellipsoid& ellipsoid, const GeodeticExtent& surfaceExtent,
                              double errorMeters) noexcept;

/// The tiles at `level` that overlap the surface extent with some area, west to east and then in
/// row order; none where the extent lies beyond the tiling's extent or coverage (the Mercator
/// limit). An imagery extent crossing the antimeridian is honoured.
std::vector<TileKey> imageryTilesOver(const ImageryTiling& tiling, std::uint32_t level,
                                      const GeodeticExtent& surfaceExtent);

/// Where one imagery texture, laid out linearly in longitude and latitude over imageryExtent (a
/// geographic tile, or a Web Mercator tile once reprojected), lands on a surface tile: texture
/// coordinates are translation + scale * the surface tile's (u, v), and the texture applies only
/// inside tileRectangle (minimum u, minimum v, maximum u, maximum v of the surface tile).
struct ImageryPlacement {
    glm::dvec2 translation{0.0};
    glm::dvec2 scale{1.0};
    glm::dvec4 tileRectangle{0.0, 0.0, 1.0, 1.0};
};

/// The placement of an imagery texture on a surface tile, its rectangle cut down to `clip` (a
/// layer's rectangle, which may cross the antimeridian) when given; empty when they do not
/// overlap with some area. Neither extent may cross the antimeridian (tiles never do).
std::optional<ImageryPlacement> placeImagery(const GeodeticExtent& imageryExtent, const GeodeticExtent& surfaceExtent,
                                             const std::optional<GeodeticExtent>& clip = std::nullopt) noexcept;

/// For reprojecting a Web Mercator tile over `extent` into a texture of `rows` rows linear in
/// latitude (course 3.7): pairs (y, v) from south to north, y where a strip's vertex goes in the
/// output (0..1) and v the Mercator tile's vertical texture coordinate it samples there (0 south,
/// 1 north), computed in doubles. The vertices sit at the output's row centres, where the
/// rasteriser evaluates fragments, so each fragment gets its exact v rather than one
/// interpolated across its row; and at the two edges, so that the strip covers the texture.
std::vector<glm::dvec2> mercatorReprojectionRows(const GeodeticExtent& extent, int rows);

} // namespace orbis::scene
