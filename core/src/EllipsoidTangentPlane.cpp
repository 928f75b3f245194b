#include "orbis/core/EllipsoidTangentPlane.h"

#include "orbis/core/Math.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace orbis {

namespace {

glm::dvec3 boundingBoxCentre(std::span<const glm::dvec3> positions) noexcept
{
    if (positions.empty()) {
        return glm::dvec3(0.0);
    }
    glm::dvec3 lo = positions[0];
    glm::dvec3 hi = positions[0];
    for (const glm::dvec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return 0.5 * lo + 0.5 * hi;
}

} // namespace

EllipsoidTangentPlane::EllipsoidTangentPlane(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions) noexcept
    : EllipsoidTangentPlane(ellipsoid, boundingBoxCentre(positions))
{
}

EllipsoidTangentPlane::EllipsoidTangentPlane(const Ellipsoid& ellipsoid, const glm::dvec3& point) noexcept
    : _ellipsoid(ellipsoid)
{
    _origin = isFinite(point) ? _ellipsoid.scaleToGeodeticSurface(point) : glm::dvec3(0.0, 0.0, _ellipsoid.radii().z);
    _normal = _ellipsoid.geodeticSurfaceNormal(_origin);
    // East is z x normal; at the poles, where that vanishes, the east of longitude 0 (+y).
    const glm::dvec3 east(-_normal.y, _normal.x, 0.0);
    const double length = glm::length(east);
    _xAxis = length > 1e-15 ? east / length : glm::dvec3(0.0, 1.0, 0.0);
    _yAxis = glm::normalize(glm::cross(_normal, _xAxis));
}

std::optional<glm::dvec2> EllipsoidTangentPlane::projectPointOntoPlane(const glm::dvec3& p) const noexcept
{
    const double along = glm::dot(_normal, p);
    if (!(along > 0.0)) {
        return std::nullopt;
    }
    // The plane is normal . x = normal . origin; the ray t p meets it at t = (normal . origin) / (normal . p).
    const glm::dvec3 onPlane = (glm::dot(_normal, _origin) / along) * p - _origin;
    const glm::dvec2 q(glm::dot(onPlane, _xAxis), glm::dot(onPlane, _yAxis));
    if (!std::isfinite(q.x) || !std::isfinite(q.y)) {
        return std::nullopt;
    }
    return q;
}

std::optional<std::vector<glm::dvec2>> EllipsoidTangentPlane::projectPointsOntoPlane(
    std::span<const glm::dvec3> positions) const
{
    std::vector<glm::dvec2> result;
    result.reserve(positions.size());
    for (const glm::dvec3& p : positions) {
        const std::optional<glm::dvec2> q = projectPointOntoPlane(p);
        if (!q) {
            return std::nullopt;
        }
        result.push_back(*q);
    }
    return result;
}

glm::dvec3 EllipsoidTangentPlane::projectPointOntoEllipsoid(const glm::dvec2& q) const noexcept
{
    return _ellipsoid.scaleToGeocentricSurface(planeToWorld(q));
}

double EllipsoidTangentPlane::cosineFromNormal(const glm::dvec3& p) const noexcept
{
    const double length = glm::length(p);
    return length > 0.0 && std::isfinite(length) ? glm::dot(_normal, p) / length : 0.0;
}

} // namespace orbis
