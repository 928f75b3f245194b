#pragma once

#include "orbis/core/Geodetic.h"
#include "orbis/core/Math.h"

namespace orbis {

/// A longitude-latitude rectangle in radians: west and east in [-pi, pi], south <= north in
/// [-pi/2, pi/2]. When east < west the extent crosses the antimeridian (it runs east from west
/// through +-180 degrees to east). west == east is a single meridian; the whole globe is
/// west = -pi, east = pi. Longitudes -pi and pi are the same meridian throughout.
struct GeodeticExtent {
    double west = 0.0;
    double south = 0.0;
    double east = 0.0;
    double north = 0.0;

    static constexpr GeodeticExtent fromDegrees(double westDegrees, double southDegrees, double eastDegrees,
                                                double northDegrees) noexcept
    {
        return {toRadians(westDegrees), toRadians(southDegrees), toRadians(eastDegrees), toRadians(northDegrees)};
    }

    /// The whole globe.
    static constexpr GeodeticExtent maximum() noexcept { return {-kPi, -kHalfPi, kPi, kHalfPi}; }

    /// Longitude span in radians, in [0, 2 pi]: east - west, plus 2 pi across the antimeridian.
    double width() const noexcept;
    /// Latitude span in radians: north - south.
    double height() const noexcept { return north - south; }
    /// The middle longitude of width() (in (-pi, pi]) and the middle latitude.
    Geodetic2D centre() const noexcept;
    /// True when g lies inside or on the boundary. g's longitude is taken modulo 2 pi (false when
    /// it is not finite). At a pole every longitude names the same point: a pole is inside an
    /// extent that reaches it, whatever its longitude.
    bool contains(const Geodetic2D& g) const noexcept;
    /// True when the two extents share a point, boundaries included (either may cross the
    /// antimeridian; -pi and pi are one meridian; two extents reaching the same pole meet there).
    bool intersects(const GeodeticExtent& other) const noexcept;

    friend constexpr bool operator==(const GeodeticExtent&, const GeodeticExtent&) = default;
};

} // namespace orbis
