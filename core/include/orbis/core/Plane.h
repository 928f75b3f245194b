#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace orbis {

/// The plane dot(normal, x) + distance = 0 with a unit normal: distance is the signed distance
/// of the origin from the plane, in metres. The normal's side is in front (positive).
struct Plane {
    glm::dvec3 normal{0.0, 0.0, 1.0};
    double distance = 0.0;

    /// The plane through point with the given normal (normalised here; must be non-zero, asserted
    /// in debug; a zero normal gives +z).
    static Plane fromPointNormal(const glm::dvec3& point, const glm::dvec3& normal) noexcept;

    /// Signed distance of p from the plane in metres: positive on the normal's side.
    double signedDistance(const glm::dvec3& p) const noexcept { return glm::dot(normal, p) + distance; }

    /// The point of the plane closest to p.
    glm::dvec3 project(const glm::dvec3& p) const noexcept { return p - signedDistance(p) * normal; }

    friend bool operator==(const Plane&, const Plane&) = default;
};

} // namespace orbis
