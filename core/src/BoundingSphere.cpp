#include "orbis/core/BoundingSphere.h"

#include "orbis/core/AxisAlignedBoundingBox.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>

namespace orbis {

namespace {

// contains() and the final pass of fromPoints() measure with this one function, so that a radius
// taken as the largest of these distances contains every point exactly.
double distanceBetween(const glm::dvec3& a, const glm::dvec3& b) noexcept
{
    return glm::length(a - b);
}

double largestDistance(const glm::dvec3& centre, std::span<const glm::dvec3> points) noexcept
{
    double radius = 0.0;
    for (const glm::dvec3& p : points) {
        radius = std::max(radius, distanceBetween(centre, p));
    }
    return radius;
}

/// Ritter's centre: start from the widest of the three pairs of axis-extreme points, then grow
/// the sphere just enough to take in each point outside it.
glm::dvec3 ritterCentre(std::span<const glm::dvec3> points) noexcept
{
    std::size_t lowest[3] = {0, 0, 0};
    std::size_t highest[3] = {0, 0, 0};
    for (std::size_t i = 1; i < points.size(); ++i) {
        for (int axis = 0; axis < 3; ++axis) {
            if (points[i][axis] < points[lowest[axis]][axis]) {
                lowest[axis] = i;
            }
            if (points[i][axis] > points[highest[axis]][axis]) {
                highest[axis] = i;
            }
        }
    }
    int widest = 0;
    double widestSpan = -1.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double span = distanceBetween(points[lowest[axis]], points[highest[axis]]);
        if (span > widestSpan) {
            widestSpan = span;
            widest = axis;
        }
    }
    glm::dvec3 centre = 0.5 * points[lowest[widest]] + 0.5 * points[highest[widest]];
    double radius = 0.5 * widestSpan;
    for (const glm::dvec3& p : points) {
        const double d = distanceBetween(centre, p);
        if (d > radius) {
            // The new sphere touches p and the point diametrically opposite p on the old one.
            const double grown = 0.5 * (radius + d);
            centre += ((grown - radius) / d) * (p - centre);
            radius = grown;
        }
    }
    return centre;
}

} // namespace

BoundingSphere BoundingSphere::fromPoints(std::span<const glm::dvec3> points) noexcept
{
    if (points.empty()) {
        return {};
    }
    const glm::dvec3 ritter = ritterCentre(points);
    const glm::dvec3 boxCentre = AxisAlignedBoundingBox::fromPoints(points).centre();
    const double ritterRadius = largestDistance(ritter, points);
    const double boxRadius = largestDistance(boxCentre, points);
    return ritterRadius <= boxRadius ? BoundingSphere{ritter, ritterRadius} : BoundingSphere{boxCentre, boxRadius};
}

BoundingSphere BoundingSphere::merge(const BoundingSphere& a, const BoundingSphere& b) noexcept
{
    const double d = distanceBetween(a.centre, b.centre);
    if (d + b.radius <= a.radius) {
        return a;
    }
    if (d + a.radius <= b.radius) {
        return b;
    }
    // Here d > |a.radius - b.radius| >= 0. The result spans from a's far side to b's far side.
    const double radius = 0.5 * (d + a.radius + b.radius);
    const glm::dvec3 centre = a.centre + ((radius - a.radius) / d) * (b.centre - a.centre);
    // Re-measured from the rounded centre, so that both spheres stay inside up to the last sums.
    return {centre, std::max({radius, distanceBetween(centre, a.centre) + a.radius,
                              distanceBetween(centre, b.centre) + b.radius})};
}

bool BoundingSphere::contains(const glm::dvec3& p) const noexcept
{
    return distanceBetween(centre, p) <= radius;
}

double BoundingSphere::distanceTo(const glm::dvec3& p) const noexcept
{
    return std::max(0.0, distanceBetween(centre, p) - radius);
}

Intersect BoundingSphere::intersect(const Plane& plane) const noexcept
{
    assert(radius >= 0.0);
    const double d = plane.signedDistance(centre);
    if (d < -radius) {
        return Intersect::Outside;
    }
    if (d > radius) {
        return Intersect::Inside;
    }
    return Intersect::Intersecting;
}

} // namespace orbis
