#include "orbis/core/OrientedBoundingBox.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace orbis {

std::array<glm::dvec3, 8> OrientedBoundingBox::corners() const noexcept
{
    std::array<glm::dvec3, 8> result;
    for (int i = 0; i < 8; ++i) {
        result[i] = centre + ((i & 1) ? 1.0 : -1.0) * halfAxes[0] + ((i & 2) ? 1.0 : -1.0) * halfAxes[1] +
                    ((i & 4) ? 1.0 : -1.0) * halfAxes[2];
    }
    return result;
}

Intersect OrientedBoundingBox::intersect(const Plane& plane) const noexcept
{
    // The box's extent along the normal: the sum of its half-axes' projections.
    const double radius = std::abs(glm::dot(plane.normal, halfAxes[0])) + std::abs(glm::dot(plane.normal, halfAxes[1])) +
                          std::abs(glm::dot(plane.normal, halfAxes[2]));
    const double d = plane.signedDistance(centre);
    if (d < -radius) {
        return Intersect::Outside;
    }
    if (d > radius) {
        return Intersect::Inside;
    }
    return Intersect::Intersecting;
}

double OrientedBoundingBox::distanceSquaredTo(const glm::dvec3& p) const noexcept
{
    const glm::dvec3 offset = p - centre;
    double squared = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double length = glm::length(halfAxes[axis]);
        if (!(length > 0.0)) {
            continue; // counted below, with the offset the non-zero axes leave
        }
        const double along = glm::dot(offset, halfAxes[axis]) / length;
        const double outside = std::abs(along) - length;
        if (outside > 0.0) {
            squared += outside * outside;
        }
    }
    // Directions of zero-length axes: what the other axes leave of the offset.
    int flatAxes = 0;
    glm::dvec3 inPlane = offset;
    for (int axis = 0; axis < 3; ++axis) {
        const double length = glm::length(halfAxes[axis]);
        if (length > 0.0) {
            const glm::dvec3 unit = halfAxes[axis] / length;
            inPlane -= glm::dot(offset, unit) * unit;
        } else {
            ++flatAxes;
        }
    }
    if (flatAxes > 0) {
        squared += glm::dot(inPlane, inPlane);
    }
    return squared;
}

bool OrientedBoundingBox::contains(const glm::dvec3& p) const noexcept
{
    const double tolerance = 1e-12 * (glm::length(centre) + boundingSphere().radius);
    return distanceSquaredTo(p) <= tolerance * tolerance;
}

BoundingSphere OrientedBoundingBox::boundingSphere() const noexcept
{
    return {centre, glm::length(halfAxes[0] + halfAxes[1] + halfAxes[2])};
}

} // namespace orbis
