#pragma once

#include "orbis/core/BoundingSphere.h"
#include "orbis/core/OrientedBoundingBox.h"
#include "orbis/core/Intersect.h"
#include "orbis/core/Plane.h"

#include <glm/mat4x4.hpp>

#include <array>

namespace orbis {

/// A view frustum as six planes whose normals point inwards, in the order of Frustum::Side.
///
/// Usage: `Frustum::fromViewProjection(projection * view).intersect(command.boundingSphere)`.
class Frustum final {
public:
    enum Side { Left, Right, Bottom, Top, Near, Far };

    Frustum() noexcept = default;
    explicit Frustum(const std::array<Plane, 6>& planes) noexcept : _planes(planes) {}

    /// The planes of the clip volume -w <= x, y, z <= w (OpenGL conventions) of
    /// viewProjection = projection * view, in world coordinates (Gribb and Hartmann). A plane that
    /// degenerates (the far plane of an infinite projection) gets a zero normal and a distance of
    /// +infinity (everything is inside it) or -infinity (nothing is).
    static Frustum fromViewProjection(const glm::dmat4& viewProjection) noexcept;

    const std::array<Plane, 6>& planes() const noexcept { return _planes; }
    const Plane& plane(Side side) const noexcept { return _planes[side]; }

    /// Where the sphere lies: Outside when wholly outside one plane, Inside when wholly inside
    /// all six, Intersecting otherwise (conservative near edges and corners).
    Intersect intersect(const BoundingSphere& sphere) const noexcept;
    /// The same for an oriented box.
    Intersect intersect(const OrientedBoundingBox& box) const noexcept;

    /// True when p is inside or on every plane.
    bool contains(const glm::dvec3& p) const noexcept;

private:
    std::array<Plane, 6> _planes{};
};

} // namespace orbis
