#include "orbis/core/IntersectionTests.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

/// The interval of the ray q + t v inside the unit sphere. The quadratic is
/// a t^2 + 2 h t + c = 0 with a = v.v, h = q.v, c = q.q - 1. Its discriminant h^2 - a c is taken
/// as a (1 - |l|^2), l being the point of the line closest to the centre: the textbook form
/// subtracts two numbers of size |q|^2 a and loses all its digits for grazing rays from afar.
/// The roots come from c / k and k / a with k = -h + sqrt(disc) (h < 0) so that nothing cancels.
std::optional<RayInterval> intersectUnitSphere(const glm::dvec3& q, const glm::dvec3& v) noexcept
{
    const double a = glm::dot(v, v);
    if (!(a > 0.0) || !std::isfinite(a)) {
        return std::nullopt;
    }
    const double h = glm::dot(q, v);
    const double qq = glm::dot(q, q);
    const double c = qq - 1.0;
    const glm::dvec3 closest = q - (h / a) * v;
    double m = 1.0 - glm::dot(closest, closest); // disc / a
    // The rounding error of |closest|^2 is a few epsilon of |q|: within it the ray is tangent and
    // touches at its closest approach, the one point of a grazing ray that is well conditioned.
    const double tolerance = 8.0 * kEpsilon * (1.0 + std::sqrt(qq));
    if (m < -tolerance) {
        return std::nullopt;
    }
    if (m <= tolerance) {
        m = 0.0;
    }
    const double s = std::sqrt(a * m); // sqrt(disc)

    RayInterval result;
    // c, like m, is rounded by a few epsilon: an origin that close to the surface is on it and
    // counts as inside.
    if (c > 8.0 * kEpsilon) {
        // Outside: both roots have the sign of -h.
        if (h >= 0.0) {
            return std::nullopt;
        }
        if (s == 0.0) {
            result.nearDistance = result.farDistance = -h / a;
        } else {
            const double k = s - h;
            const double t1 = c / k;
            const double t2 = k / a;
            result.nearDistance = std::min(t1, t2);
            result.farDistance = std::max(t1, t2);
        }
    } else {
        // Inside or on the surface: the exit is the larger root (-h + s) / a.
        result.nearDistance = 0.0;
        if (h <= 0.0) {
            result.farDistance = (s - h) / a;
        } else {
            result.farDistance = -c / (h + s); // h + s > 0
        }
        result.farDistance = std::max(result.farDistance, 0.0);
    }
    if (!std::isfinite(result.nearDistance) || !std::isfinite(result.farDistance)) {
        return std::nullopt;
    }
    return result;
}

} // namespace

std::optional<RayInterval> intersectRayEllipsoid(const Ray& ray, const Ellipsoid& ellipsoid) noexcept
{
    // Scaling every axis by 1 / radius maps the ellipsoid onto the unit sphere and keeps t.
    return intersectUnitSphere(ray.origin * ellipsoid.oneOverRadii(), ray.direction * ellipsoid.oneOverRadii());
}

std::optional<RayInterval> intersectRaySphere(const Ray& ray, const BoundingSphere& sphere) noexcept
{
    if (!(sphere.radius > 0.0)) {
        return std::nullopt;
    }
    const double scale = 1.0 / sphere.radius;
    return intersectUnitSphere((ray.origin - sphere.centre) * scale, ray.direction * scale);
}

std::optional<double> intersectRayPlane(const Ray& ray, const Plane& plane) noexcept
{
    const double denominator = glm::dot(plane.normal, ray.direction);
    if (denominator == 0.0) {
        return std::nullopt;
    }
    const double t = -plane.signedDistance(ray.origin) / denominator;
    if (!(t >= 0.0) || !std::isfinite(t)) {
        return std::nullopt;
    }
    return t;
}

std::optional<RayTriangleHit> intersectRayTriangle(const Ray& ray, const glm::dvec3& p0, const glm::dvec3& p1,
                                                   const glm::dvec3& p2) noexcept
{
    const glm::dvec3 edge1 = p1 - p0;
    const glm::dvec3 edge2 = p2 - p0;
    const glm::dvec3 p = glm::cross(ray.direction, edge2);
    const double determinant = glm::dot(edge1, p); // = -dot(direction, cross(edge1, edge2))
    // |determinant| = |direction| |normal| sin(angle between the ray and the plane).
    constexpr double kParallel = 1e-12;
    const double scale = glm::length(ray.direction) * glm::length(glm::cross(edge1, edge2));
    if (!(std::abs(determinant) > kParallel * scale)) {
        return std::nullopt;
    }
    const double inverse = 1.0 / determinant;
    const glm::dvec3 toOrigin = ray.origin - p0;
    const double u = glm::dot(toOrigin, p) * inverse;
    if (!(u >= 0.0 && u <= 1.0)) {
        return std::nullopt;
    }
    const glm::dvec3 q = glm::cross(toOrigin, edge1);
    const double v = glm::dot(ray.direction, q) * inverse;
    if (!(v >= 0.0 && u + v <= 1.0)) {
        return std::nullopt;
    }
    const double t = glm::dot(edge2, q) * inverse;
    if (!(t >= 0.0) || !std::isfinite(t)) {
        return std::nullopt;
    }
    return RayTriangleHit{t, u, v};
}

} // namespace orbis
