#include "orbis/core/Geodesic.h"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/GeodesicExact.hpp>
#include <GeographicLib/GeodesicLine.hpp>
#include <GeographicLib/GeodesicLineExact.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <variant>

namespace orbis {

namespace {

// GeographicLib's series solution is accurate to round-off for |f| <= 0.02 (its documentation);
// beyond, the elliptic-integral solution is used.
constexpr double kSeriesFlatteningLimit = 0.02;

/// GeographicLib works in degrees, latitude first.
struct EndpointsDegrees {
    double latitude1, longitude1, latitude2, longitude2;
};

EndpointsDegrees toDegrees(const Geodetic2D& a, const Geodetic2D& b) noexcept
{
    // Clamped in degrees: pi/2 converted may round just above 90, which GeographicLib rejects
    // with NaN.
    auto latitude = [](double radians) { return std::clamp(orbis::toDegrees(radians), -90.0, 90.0); };
    return {latitude(a.latitude), orbis::toDegrees(a.longitude), latitude(b.latitude), orbis::toDegrees(b.longitude)};
}

} // namespace

struct Geodesic::Solver {
    using Variant = std::variant<GeographicLib::Geodesic, GeographicLib::GeodesicExact>;
    Variant geodesic;
};

Geodesic::Geodesic(const Ellipsoid& ellipsoid) : _ellipsoid(ellipsoid)
{
    assert(ellipsoid.isSpheroid() && "Geodesic needs an ellipsoid of revolution (x and y radii equal)");
    const double a = ellipsoid.radii().x;
    const double flattening = (a - ellipsoid.radii().z) / a;
    if (std::abs(flattening) <= kSeriesFlatteningLimit) {
        _solver = std::make_unique<const Solver>(
            Solver{Solver::Variant(std::in_place_type<GeographicLib::Geodesic>, a, flattening)});
    } else {
        _solver = std::make_unique<const Solver>(
            Solver{Solver::Variant(std::in_place_type<GeographicLib::GeodesicExact>, a, flattening)});
    }
}

Geodesic::~Geodesic() = default;
Geodesic::Geodesic(const Geodesic& other)
    : _ellipsoid(other._ellipsoid), _solver(std::make_unique<const Solver>(*other._solver))
{
}
Geodesic& Geodesic::operator=(const Geodesic& other)
{
    if (this != &other) {
        _ellipsoid = other._ellipsoid;
        _solver = std::make_unique<const Solver>(*other._solver);
    }
    return *this;
}
// A moved-from Geodesic may only be assigned to or destroyed.
Geodesic::Geodesic(Geodesic&& other) noexcept = default;
Geodesic& Geodesic::operator=(Geodesic&& other) noexcept = default;

double Geodesic::distance(const Geodetic2D& a, const Geodetic2D& b) const noexcept
{
    const EndpointsDegrees e = toDegrees(a, b);
    return std::visit(
        [&](const auto& geodesic) {
            double s12 = 0.0;
            geodesic.Inverse(e.latitude1, e.longitude1, e.latitude2, e.longitude2, s12);
            return s12;
        },
        _solver->geodesic);
}

namespace {

enum class Spacing { Arc, Length };

/// Points along GeographicLib's inverse line from a to b at `segments` equal steps of arc
/// (degrees on the auxiliary sphere) or of length (metres), the ends exact.
template <typename GeodesicType>
std::vector<glm::dvec3> pathPoints(const GeodesicType& geodesic, const Ellipsoid& ellipsoid, const Geodetic2D& a,
                                   const Geodetic2D& b, Spacing spacing, double maxStep)
{
    const EndpointsDegrees e = toDegrees(a, b);
    const auto line = geodesic.InverseLine(e.latitude1, e.longitude1, e.latitude2, e.longitude2,
                                           GeodesicType::LATITUDE | GeodesicType::LONGITUDE |
                                               GeodesicType::DISTANCE_IN);
    const double total = spacing == Spacing::Arc ? line.Arc() : line.Distance();
    const auto segments = static_cast<std::size_t>(std::max(1.0, std::ceil(total / maxStep)));

    std::vector<glm::dvec3> positions;
    positions.reserve(segments + 1);
    positions.push_back(ellipsoid.toCartesian(a));
    for (std::size_t i = 1; i < segments; ++i) {
        const double along = total * static_cast<double>(i) / static_cast<double>(segments);
        double latitude = 0.0;
        double longitude = 0.0;
        if (spacing == Spacing::Arc) {
            line.ArcPosition(along, latitude, longitude);
        } else {
            line.Position(along, latitude, longitude);
        }
        positions.push_back(ellipsoid.toCartesian(Geodetic2D::fromDegrees(longitude, latitude)));
    }
    positions.push_back(ellipsoid.toCartesian(b));
    return positions;
}

} // namespace

std::vector<glm::dvec3> Geodesic::computeGeodesic(const Geodetic2D& a, const Geodetic2D& b,
                                                  double granularityRadians) const
{
    const double stepDegrees = orbis::toDegrees(std::max(granularityRadians, 1e-6));
    return std::visit(
        [&](const auto& geodesic) { return pathPoints(geodesic, _ellipsoid, a, b, Spacing::Arc, stepDegrees); },
        _solver->geodesic);
}

std::vector<glm::dvec3> Geodesic::computeGeodesicBySegmentLength(const Geodetic2D& a, const Geodetic2D& b,
                                                                 double maxSegmentMeters) const
{
    const double step = std::max(maxSegmentMeters, 1e-6 * _ellipsoid.radii().x);
    return std::visit(
        [&](const auto& geodesic) { return pathPoints(geodesic, _ellipsoid, a, b, Spacing::Length, step); },
        _solver->geodesic);
}

} // namespace orbis
