#pragma once

#include <glm/vec3.hpp>

#include <span>

namespace orbis {

/// A box aligned with the coordinate axes, from minimum to maximum corner (metres).
struct AxisAlignedBoundingBox {
    glm::dvec3 minimum{0.0};
    glm::dvec3 maximum{0.0};

    /// The smallest box containing every point; no points give the empty box at the origin
    /// (minimum == maximum == 0).
    static AxisAlignedBoundingBox fromPoints(std::span<const glm::dvec3> points) noexcept;

    /// The box's centre (exact halfway, no overflow for finite corners).
    glm::dvec3 centre() const noexcept;

    /// maximum - minimum along each axis.
    glm::dvec3 size() const noexcept { return maximum - minimum; }

    /// True when p lies inside or on the box.
    bool contains(const glm::dvec3& p) const noexcept;

    friend bool operator==(const AxisAlignedBoundingBox&, const AxisAlignedBoundingBox&) = default;
};

} // namespace orbis
