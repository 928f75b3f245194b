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

} // namespace orbis
