#pragma once

#include "orbis/core/Math.h"

namespace orbis {

/// A position on the ellipsoid's surface: longitude and latitude in radians.
struct Geodetic2D {
    double longitude = 0.0;
    double latitude = 0.0;

    static constexpr Geodetic2D fromDegrees(double longitudeDegrees, double latitudeDegrees) noexcept
    {
        return {toRadians(longitudeDegrees), toRadians(latitudeDegrees)};
    }

    friend constexpr bool operator==(const Geodetic2D&, const Geodetic2D&) = default;
};

/// A position relative to the ellipsoid: longitude and latitude in radians, height in metres
/// along the geodetic surface normal.
struct Geodetic3D {
    double longitude = 0.0;
    double latitude = 0.0;
    double height = 0.0;

    constexpr Geodetic3D() noexcept = default;
    constexpr Geodetic3D(double longitude_, double latitude_, double height_ = 0.0) noexcept
        : longitude(longitude_), latitude(latitude_), height(height_)
    {
    }
    constexpr explicit Geodetic3D(const Geodetic2D& g, double height_ = 0.0) noexcept
        : longitude(g.longitude), latitude(g.latitude), height(height_)
    {
    }

    static constexpr Geodetic3D fromDegrees(double longitudeDegrees, double latitudeDegrees,
                                            double heightMeters = 0.0) noexcept
    {
        return {toRadians(longitudeDegrees), toRadians(latitudeDegrees), heightMeters};
    }

    constexpr Geodetic2D toGeodetic2D() const noexcept { return {longitude, latitude}; }

    friend constexpr bool operator==(const Geodetic3D&, const Geodetic3D&) = default;
};

} // namespace orbis
