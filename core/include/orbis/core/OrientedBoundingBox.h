#pragma once

#include "orbis/core/BoundingSphere.h"
#include "orbis/core/Intersect.h"
#include "orbis/core/Plane.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <array>

namespace orbis {

/// A box in any orientation: a centre and three half-axes (the columns of halfAxes, mutually
/// perpendicular, any length >= 0), in metres. The box holds centre + a u + b v + c w for a, b, c
/// in [-1, 1], with u, v, w the columns.
struct OrientedBoundingBox {
    glm::dvec3 centre{0.0};
    glm::dmat3 halfAxes{0.0};

    /// The eight corners.
    std::array<glm::dvec3, 8> corners() const noexcept;

    /// Where the box lies relative to the plane (touching counts as Intersecting).
    Intersect intersect(const Plane& plane) const noexcept;

    /// The squared distance in metres from p to the box; 0 inside. Exact for perpendicular axes,
    /// including degenerate (zero-length) ones.
    double distanceSquaredTo(const glm::dvec3& p) const noexcept;

    /// True when p lies inside or on the box, up to 1e-12 of the box's distance from the origin
    /// plus its size (rounding of points computed on the box's faces).
    bool contains(const glm::dvec3& p) const noexcept;

    /// The sphere through the corners: centre and half the diagonal.
    BoundingSphere boundingSphere() const noexcept;

    friend bool operator==(const OrientedBoundingBox&, const OrientedBoundingBox&) = default;
};

} // namespace orbis
