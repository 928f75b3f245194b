#include "orbis/core/Ellipsoid.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace orbis {

namespace {

constexpr double kWgs84A = 6378137.0;
constexpr double kWgs84F = 1.0 / 298.257223563;
// Beyond this distance squares overflow; the ellipsoid is a point and the geocentric answer is exact
// to far below a unit in the last place.
constexpr double kFarAway = 1e100;

/// The closest point on the ellipsoid with the given radii to p, by a safeguarded Newton search
/// on the Lagrange parameter of the distance (after D. Eberly, "Distance from a Point to an
/// Ellipse, an Ellipsoid, or a Hyperellipsoid"). The parameter is shifted by the smallest radius
/// squared so that no step subtracts nearly equal numbers. Robust for every point, the centre
/// and the axes included; slower than the spheroid's Newton step, so used only where that one
/// cannot be (triaxial ellipsoids, and points with several normals near a spheroid's centre).
/// Ties go to the positive side of each axis, so the centre maps to the +z pole of WGS84.
glm::dvec3 closestSurfacePoint(const glm::dvec3& radii, const glm::dvec3& p) noexcept
{
    int m = 0; // the axis of the smallest radius
    for (int i = 1; i < 3; ++i) {
        if (radii[i] < radii[m] || (radii[i] == radii[m] && i == 2)) {
            m = i;
        }
    }
    const glm::dvec3 q = glm::abs(p);
    const glm::dvec3 weighted = radii * q;                                      // r_i |p_i|
    const glm::dvec3 shift = (radii - radii[m]) * (radii + radii[m]);           // r_i^2 - r_m^2 >= 0
    auto foot = [&](double s) { return radii * weighted / (s + shift); };       // x_i = r_i^2 |p_i| / (s + c_i^2)

    glm::dvec3 x;
    double lo = weighted[m];
    if (q[m] == 0.0) {
        // Below the lower bracket the m-term vanishes: the foot may sit where the others alone
        // fall short of the surface, with the m-coordinate making up the rest.
        double partial = 0.0;
        bool singular = false;
        for (int i = 0; i < 3; ++i) {
            if (i == m || q[i] == 0.0) {
                continue;
            }
            if (shift[i] == 0.0) {
                singular = true;
                break;
            }
            const double term = weighted[i] / shift[i];
            partial += term * term;
        }
        if (!singular && partial < 1.0) {
            for (int i = 0; i < 3; ++i) {
                x[i] = (i == m || q[i] == 0.0 || shift[i] == 0.0) ? 0.0 : radii[i] * weighted[i] / shift[i];
            }
            x[m] = radii[m] * std::sqrt(1.0 - partial);
            return glm::dvec3(std::copysign(x.x, p.x), std::copysign(x.y, p.y), std::copysign(x.z, p.z));
        }
        lo = 0.0;
    }
    double hi = glm::length(weighted);
    double s = lo > 0.0 ? lo : 0.5 * hi;
    for (int i = 0; i < 1100; ++i) {
        glm::dvec3 ratio = weighted / (s + shift);
        const double f = glm::dot(ratio, ratio) - 1.0;
        if (f > 0.0) {
            lo = s;
        } else if (f < 0.0) {
            hi = s;
        } else {
            break;
        }
        // F is convex and decreasing in s, so Newton from either side is safe inside the bracket.
        const double df = -2.0 * glm::dot(ratio * ratio, 1.0 / (s + shift));
        double next = s - f / df;
        if (!(next > lo && next < hi)) {
            next = 0.5 * (lo + hi);
        }
        if (next == s || next == lo || next == hi) {
            break;
        }
        s = next;
    }
    x = foot(s);
    return glm::dvec3(std::copysign(x.x, p.x), std::copysign(x.y, p.y), std::copysign(x.z, p.z));
}

// Book section 2.3.3: Newton's method on the scale factor that moves p along its geodetic
// normal onto the surface, to the book's tolerance. Kept as the report's baseline.
glm::dvec3 bookScaleToGeodeticSurface(const glm::dvec3& p, const glm::dvec3& oneOverRadiiSquared) noexcept
{
    const glm::dvec3 q = p * p * oneOverRadiiSquared;
    const double qSum = q.x + q.y + q.z;
    if (qSum == 0.0) {
        return {0.0, 0.0, 1.0 / std::sqrt(oneOverRadiiSquared.z)};
    }
    const double beta = 1.0 / std::sqrt(qSum);
    const double n = glm::length(beta * p * oneOverRadiiSquared);
    double alpha = (1.0 - beta) * (glm::length(p) / n);
    for (int i = 0; i < 100; ++i) {
        const glm::dvec3 d = 1.0 / (1.0 + alpha * oneOverRadiiSquared);
        const glm::dvec3 d2 = d * d;
        const double s = glm::dot(q, d2) - 1.0;
        const double ds = -2.0 * glm::dot(q * d2 * d, oneOverRadiiSquared);
        if (ds == 0.0) {
            break;
        }
        alpha -= s / ds;
        if (std::abs(s) <= 1e-10) {
            break;
        }
    }
    return p / (1.0 + alpha * oneOverRadiiSquared);
}

} // namespace

Ellipsoid::Ellipsoid(const glm::dvec3& radii) noexcept
    : _radii(radii)
    , _radiiSquared(radii * radii)
    , _oneOverRadii(1.0 / radii)
    , _oneOverRadiiSquared(1.0 / (radii * radii))
{
    assert(radii.x > 0.0 && radii.y > 0.0 && radii.z > 0.0);
    assert(std::isfinite(radii.x) && std::isfinite(radii.y) && std::isfinite(radii.z));
}

Ellipsoid Ellipsoid::wgs84() noexcept
{
    return Ellipsoid(kWgs84A, kWgs84A, kWgs84A * (1.0 - kWgs84F));
}

Ellipsoid Ellipsoid::scaledWgs84() noexcept
{
    return Ellipsoid(1.0, 1.0, 1.0 - kWgs84F);
}

Ellipsoid Ellipsoid::unitSphere() noexcept
{
    return Ellipsoid(1.0, 1.0, 1.0);
}

double Ellipsoid::minimumRadius() const noexcept
{
    return std::min({_radii.x, _radii.y, _radii.z});
}

double Ellipsoid::maximumRadius() const noexcept
{
    return std::max({_radii.x, _radii.y, _radii.z});
}

glm::dvec3 Ellipsoid::geocentricSurfaceNormal(const glm::dvec3& p) noexcept
{
    const double length = glm::length(p);
    return length > 0.0 ? p / length : glm::dvec3(0.0, 0.0, 1.0);
}

glm::dvec3 Ellipsoid::geodeticSurfaceNormal(const glm::dvec3& p) const noexcept
{
    const glm::dvec3 gradient = p * _oneOverRadiiSquared;
    const double length = glm::length(gradient);
    return length > 0.0 ? gradient / length : glm::dvec3(0.0, 0.0, 1.0);
}

glm::dvec3 Ellipsoid::geodeticSurfaceNormal(const Geodetic2D& g) noexcept
{
    const double cosLatitude = std::cos(g.latitude);
    return {cosLatitude * std::cos(g.longitude), cosLatitude * std::sin(g.longitude), std::sin(g.latitude)};
}

glm::dvec3 Ellipsoid::geodeticSurfaceNormal(const Geodetic3D& g) noexcept
{
    return geodeticSurfaceNormal(g.toGeodetic2D());
}

glm::dvec3 Ellipsoid::toCartesian(const Geodetic2D& g) const noexcept
{
    return toCartesian(Geodetic3D(g));
}

glm::dvec3 Ellipsoid::toCartesian(const Geodetic3D& g) const noexcept
{
    const glm::dvec3 n = geodeticSurfaceNormal(g);
    const glm::dvec3 k = _radiiSquared * n;
    const double gamma = std::sqrt(k.x * n.x + k.y * n.y + k.z * n.z);
    return k / gamma + g.height * n;
}

Ellipsoid::Foot Ellipsoid::footOfNormal(const glm::dvec3& p) const noexcept
{
    const double largest = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (largest > kFarAway) {
        const glm::dvec3 direction = p / largest;
        const glm::dvec3 normal = glm::normalize(direction);
        return {scaleToGeocentricSurface(direction), normal, largest * glm::length(direction)};
    }
    return isSpheroid() ? footOfNormalSpheroid(p) : footOfNormalTriaxial(p);
}

// Works in the meridian plane of p, in the first quadrant (rho, |z|). The foot's parametric
// latitude beta solves a*rho*sin(b) - b*|z|*cos(b) - (a^2 - b^2)*sin(b)*cos(b) = 0, which Newton's
// method solves from Bowring's starting value (exact on the surface) in two or three steps,
// carrying (cos beta, sin beta) as a vector so no trigonometry is needed. Within a*e^2 of the
// centre (43 km for WGS84) points can have several normals, and near there Newton's method may
// stall: those points take the robust search, which finds the closest foot.
Ellipsoid::MeridianFoot Ellipsoid::footInMeridianPlane(double rho, double zAbs) const noexcept
{
    const double a = _radii.x;
    const double b = _radii.z;
    const double c2 = (a - b) * (a + b);
    const double aRho = a * rho;
    const double bZ = b * zAbs;

    auto newton = [&](glm::dvec2& foot) {
        double cosBeta = bZ == 0.0 && aRho == 0.0 ? 0.0 : b * rho;
        double sinBeta = bZ == 0.0 && aRho == 0.0 ? 1.0 : a * zAbs;
        double inverseLength = 1.0 / std::sqrt(cosBeta * cosBeta + sinBeta * sinBeta);
        cosBeta *= inverseLength;
        sinBeta *= inverseLength;
        for (int i = 0; i < 8; ++i) {
            const double f = aRho * sinBeta - bZ * cosBeta - c2 * sinBeta * cosBeta;
            const double df = aRho * cosBeta + bZ * sinBeta - c2 * (cosBeta - sinBeta) * (cosBeta + sinBeta);
            if (!(df > 0.0)) {
                return false;
            }
            const double step = -f / df;
            const double c = cosBeta - step * sinBeta;
            const double s = sinBeta + step * cosBeta;
            inverseLength = 1.0 / std::sqrt(c * c + s * s);
            cosBeta = c * inverseLength;
            sinBeta = s * inverseLength;
            if (std::abs(step) < 1e-8) { // quadratic convergence: what remains is below 1e-16
                foot = {a * cosBeta, b * sinBeta};
                return cosBeta >= 0.0 && sinBeta >= 0.0;
            }
        }
        return false;
    };

    glm::dvec2 foot;
    const double evoluteScale = std::abs(c2);
    const bool nearCentre = aRho < evoluteScale && bZ < evoluteScale;
    if (nearCentre || !newton(foot)) {
        const glm::dvec3 x = closestSurfacePoint(_radii, glm::dvec3(rho, 0.0, zAbs));
        foot = {x.x, x.z};
    }

    // Normal of the meridian ellipse at the foot: the gradient (x/a^2, z/b^2), scaled by a^2 b^2
    // to keep it well away from underflow.
    glm::dvec2 normal(foot.x * b * b, foot.y * a * a);
    normal *= 1.0 / std::sqrt(normal.x * normal.x + normal.y * normal.y);
    // The height is the length of p - foot (parallel to the normal), signed by the side of p: a
    // dot product with the rounded unit normal would add the normal's length error, up to 4 units
    // in the last place of the height far out, where the round trip must stay within its bound.
    const glm::dvec2 offset(rho - foot.x, zAbs - foot.y);
    const double distance = std::hypot(offset.x, offset.y);
    const double height = offset.x * normal.x + offset.y * normal.y < 0.0 ? -distance : distance;
    return {foot, normal, height};
}

Ellipsoid::Foot Ellipsoid::footOfNormalSpheroid(const glm::dvec3& p) const noexcept
{
    const double rho = std::sqrt(p.x * p.x + p.y * p.y);
    const MeridianFoot m = footInMeridianPlane(rho, std::abs(p.z));
    const double zSign = std::signbit(p.z) ? -1.0 : 1.0;
    const double cosLongitude = rho > 0.0 ? p.x / rho : 1.0;
    const double sinLongitude = rho > 0.0 ? p.y / rho : 0.0;
    return {{m.foot.x * cosLongitude, m.foot.x * sinLongitude, zSign * m.foot.y},
            {m.normal.x * cosLongitude, m.normal.x * sinLongitude, zSign * m.normal.y},
            m.height};
}

Ellipsoid::Foot Ellipsoid::footOfNormalTriaxial(const glm::dvec3& p) const noexcept
{
    const glm::dvec3 surface = closestSurfacePoint(_radii, p);
    const glm::dvec3 normal = geodeticSurfaceNormal(surface);
    return {surface, normal, glm::dot(p - surface, normal)};
}

Geodetic3D Ellipsoid::toGeodetic3D(const glm::dvec3& p) const noexcept
{
    const double largest = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (isSpheroid() && largest <= kFarAway) {
        // The common case, kept in the meridian plane: no 3D foot is needed.
        const double rho = std::sqrt(p.x * p.x + p.y * p.y);
        const MeridianFoot m = footInMeridianPlane(rho, std::abs(p.z));
        const double latitude = std::atan2(m.normal.y, m.normal.x);
        return {rho > 0.0 ? std::atan2(p.y, p.x) : 0.0, std::signbit(p.z) ? -latitude : latitude, m.height};
    }
    const Foot foot = footOfNormal(p);
    // From the normal, not from p: they differ on a triaxial ellipsoid.
    const double longitude =
        (foot.normal.x == 0.0 && foot.normal.y == 0.0) ? 0.0 : std::atan2(foot.normal.y, foot.normal.x);
    const double horizontal = std::sqrt(foot.normal.x * foot.normal.x + foot.normal.y * foot.normal.y);
    return {longitude, std::atan2(foot.normal.z, horizontal), foot.height};
}

Geodetic3D Ellipsoid::toGeodetic3DBook(const glm::dvec3& p) const noexcept
{
    const glm::dvec3 surface = bookScaleToGeodeticSurface(p, _oneOverRadiiSquared);
    const glm::dvec3 normal = geodeticSurfaceNormal(surface);
    const glm::dvec3 offset = p - surface;
    const double height = (glm::dot(offset, p) < 0.0 ? -1.0 : 1.0) * glm::length(offset);
    return {std::atan2(normal.y, normal.x), std::asin(normal.z), height};
}

Geodetic2D Ellipsoid::toGeodetic2D(const glm::dvec3& p) const noexcept
{
    return toGeodetic3D(p).toGeodetic2D();
}

glm::dvec3 Ellipsoid::scaleToGeodeticSurface(const glm::dvec3& p) const noexcept
{
    return footOfNormal(p).surface;
}

glm::dvec3 Ellipsoid::scaleToGeocentricSurface(const glm::dvec3& p) const noexcept
{
    const double largest = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (largest == 0.0) {
        return {0.0, 0.0, _radii.z};
    }
    // Dividing by the largest component first keeps the squares from overflowing or underflowing.
    const glm::dvec3 direction = p / largest;
    const glm::dvec3 q = direction * direction * _oneOverRadiiSquared;
    return direction / std::sqrt(q.x + q.y + q.z);
}

std::vector<glm::dvec3> Ellipsoid::computeCurve(const glm::dvec3& start, const glm::dvec3& stop,
                                                double granularityRadians) const
{
    const glm::dvec3 from = geocentricSurfaceNormal(start);
    const glm::dvec3 to = geocentricSurfaceNormal(stop);
    glm::dvec3 axis = glm::cross(from, to);
    const double sinTheta = glm::length(axis);
    const double theta = std::atan2(sinTheta, glm::dot(from, to));

    // Nearly antipodal points leave the plane undefined by the cross product: take the one
    // through the z axis, or the x axis for points on the z axis.
    if (sinTheta < 1e-12) {
        const glm::dvec3 reference = (std::abs(from.z) > 1.0 - 1e-12) ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
        axis = glm::cross(from, reference);
    }
    axis = glm::normalize(axis);
    const glm::dvec3 tangent = glm::cross(axis, from);

    const double granularity = std::max(granularityRadians, 1e-6);
    const auto segments = static_cast<std::size_t>(std::max(1.0, std::ceil(theta / granularity)));
    std::vector<glm::dvec3> positions;
    positions.reserve(segments + 1);
    positions.push_back(start);
    for (std::size_t i = 1; i < segments; ++i) {
        const double angle = theta * static_cast<double>(i) / static_cast<double>(segments);
        positions.push_back(scaleToGeocentricSurface(std::cos(angle) * from + std::sin(angle) * tangent));
    }
    positions.push_back(stop);
    return positions;
}

} // namespace orbis
