#pragma once

// Checks of positions that a loader read from degrees in a file (GeoJSON, CSV) into radians.

#include <orbis/core/Geodetic.h>
#include <orbis/core/Math.h>

#include <catch2/catch.hpp>

namespace orbis::test {

/// Degrees to radians and back is exact to a few ulps; 1e-12 rad is 6 micrometres on the ground.
inline constexpr double kRadianTolerance = 1e-12;

/// Checks a position against the degrees and metres the file gave for it.
inline void checkPosition(const Geodetic3D& p, double longitudeDegrees, double latitudeDegrees,
                          double heightMeters = 0.0)
{
    CHECK_THAT(p.longitude, Catch::Matchers::WithinAbs(toRadians(longitudeDegrees), kRadianTolerance));
    CHECK_THAT(p.latitude, Catch::Matchers::WithinAbs(toRadians(latitudeDegrees), kRadianTolerance));
    CHECK(p.height == heightMeters);
}

} // namespace orbis::test
