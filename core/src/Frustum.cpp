#include "orbis/core/Frustum.h"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <limits>

namespace orbis {

namespace {

glm::dvec4 row(const glm::dmat4& m, int i) noexcept
{
    return {m[0][i], m[1][i], m[2][i], m[3][i]};
}

/// The plane a.x*x + a.y*y + a.z*z + a.w >= 0, normalised.
Plane normalisedPlane(const glm::dvec4& a) noexcept
{
    const glm::dvec3 normal(a);
    const double length = glm::length(normal);
    if (!(length > 0.0) || !std::isfinite(length)) {
        // A plane at infinity: the half-space is everything (w > 0) or nothing.
        constexpr double infinity = std::numeric_limits<double>::infinity();
        return {glm::dvec3(0.0), a.w >= 0.0 ? infinity : -infinity};
    }
    return {normal / length, a.w / length};
}

} // namespace

Frustum Frustum::fromViewProjection(const glm::dmat4& m) noexcept
{
    // A point is inside when -w <= x, y, z <= w for (x, y, z, w) = m * (p, 1): each inequality is
    // a half-space whose coefficients are the sum or difference of two rows of m.
    const glm::dvec4 x = row(m, 0);
    const glm::dvec4 y = row(m, 1);
    const glm::dvec4 z = row(m, 2);
    const glm::dvec4 w = row(m, 3);
    Frustum f;
    f._planes[Left] = normalisedPlane(w + x);
    f._planes[Right] = normalisedPlane(w - x);
    f._planes[Bottom] = normalisedPlane(w + y);
    f._planes[Top] = normalisedPlane(w - y);
    f._planes[Near] = normalisedPlane(w + z);
    f._planes[Far] = normalisedPlane(w - z);
    return f;
}

namespace {

/// Outside one plane is outside; inside all six is inside.
template <typename Volume>
Intersect intersectPlanes(const std::array<Plane, 6>& planes, const Volume& volume) noexcept
{
    bool inside = true;
    for (const Plane& plane : planes) {
        const Intersect result = volume.intersect(plane);
        if (result == Intersect::Outside) {
            return Intersect::Outside;
        }
        inside = inside && result == Intersect::Inside;
    }
    return inside ? Intersect::Inside : Intersect::Intersecting;
}

} // namespace

Intersect Frustum::intersect(const BoundingSphere& sphere) const noexcept
{
    return intersectPlanes(_planes, sphere);
}

Intersect Frustum::intersect(const OrientedBoundingBox& box) const noexcept
{
    return intersectPlanes(_planes, box);
}

bool Frustum::contains(const glm::dvec3& p) const noexcept
{
    for (const Plane& plane : _planes) {
        if (plane.signedDistance(p) < 0.0) {
            return false;
        }
    }
    return true;
}

} // namespace orbis
