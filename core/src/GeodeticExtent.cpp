#include "orbis/core/GeodeticExtent.h"

#include <cmath>

namespace orbis {

namespace {

/// A finite longitude in [-pi, pi]; values already there are returned unchanged (-pi and pi
/// both stay).
double wrapLongitude(double longitude) noexcept
{
    if (longitude >= -kPi && longitude <= kPi) {
        return longitude;
    }
    return std::remainder(longitude, kTwoPi); // exact, in [-pi, pi]
}

bool containsLongitude(const GeodeticExtent& e, double longitude) noexcept
{
    if (e.west <= e.east) {
        return longitude >= e.west && longitude <= e.east;
    }
    return longitude >= e.west || longitude <= e.east;
}

} // namespace

double GeodeticExtent::width() const noexcept
{
    return east >= west ? east - west : east - west + kTwoPi;
}

Geodetic2D GeodeticExtent::centre() const noexcept
{
    double longitude = west + 0.5 * width();
    if (longitude > kPi) {
        longitude -= kTwoPi;
    }
    return {longitude, 0.5 * (south + north)};
}

bool GeodeticExtent::contains(const Geodetic2D& g) const noexcept
{
    if (!(g.latitude >= south && g.latitude <= north) || !std::isfinite(g.longitude)) {
        return false;
    }
    if ((g.latitude == kHalfPi && north == kHalfPi) || (g.latitude == -kHalfPi && south == -kHalfPi)) {
        return true;
    }
    const double longitude = wrapLongitude(g.longitude);
    // -pi and pi are one meridian: try both names.
    if (std::abs(longitude) == kPi) {
        return containsLongitude(*this, kPi) || containsLongitude(*this, -kPi);
    }
    return containsLongitude(*this, longitude);
}

bool GeodeticExtent::intersects(const GeodeticExtent& other) const noexcept
{
    if (!(south <= other.north && other.south <= north)) {
        return false;
    }
    // A pole is one point, whatever the longitudes.
    if ((north == kHalfPi && other.north == kHalfPi) || (south == -kHalfPi && other.south == -kHalfPi)) {
        return true;
    }
    // On the circle of longitudes one interval meets the other exactly when one's start lies in
    // the other: measured eastwards from each start.
    const auto eastwards = [](double from, double to) {
        const double d = std::remainder(to - from, kTwoPi);
        return d < 0.0 ? d + kTwoPi : d;
    };
    return eastwards(west, other.west) <= width() || eastwards(other.west, west) <= other.width();
}

} // namespace orbis
