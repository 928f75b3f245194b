#pragma once

#include "orbis/core/Intersect.h"
#include "orbis/core/Plane.h"

#include <glm/vec3.hpp>

#include <span>

namespace orbis {

/// A sphere that bounds geometry: centre in metres (world, doubles) and radius in metres (>= 0).
struct BoundingSphere {
    glm::dvec3 centre{0.0};
    double radius = 0.0;

    /// A sphere containing every point (contains() is true for each, exactly, not only up to
    /// rounding): the smaller of Ritter's sphere and the sphere about the bounding box's centre.
    /// Its radius is at most sqrt(3) times the smallest possible, typically within 5 to 20 percent.
    /// No points give radius 0 at the origin. Distances are summed as squares: points farther
    /// apart than about 1e154 m give an infinite radius.
    static BoundingSphere fromPoints(std::span<const glm::dvec3> points) noexcept;

    /// The smallest sphere containing both a and b (a or b itself when one contains the other);
    /// contains every point of both up to a relative 4e-16 of the result's size.
    static BoundingSphere merge(const BoundingSphere& a, const BoundingSphere& b) noexcept;

    /// True when p lies inside or on the sphere.
    bool contains(const glm::dvec3& p) const noexcept;

    /// Distance in metres from p to the sphere's surface; 0 when p is inside.
    double distanceTo(const glm::dvec3& p) const noexcept;

    /// Where the sphere lies relative to the plane (touching counts as Intersecting).
    Intersect intersect(const Plane& plane) const noexcept;

    friend bool operator==(const BoundingSphere&, const BoundingSphere&) = default;
};

} // namespace orbis
