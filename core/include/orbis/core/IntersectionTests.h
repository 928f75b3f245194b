#pragma once

#include "orbis/core/BoundingSphere.h"
#include "orbis/core/Ellipsoid.h"
#include "orbis/core/Plane.h"
#include "orbis/core/Ray.h"

#include <glm/vec3.hpp>

#include <optional>

namespace orbis {

/// The part of a ray inside a closed surface, as distances along the ray (see Ray):
/// 0 <= nearDistance <= farDistance. A ray starting inside has nearDistance 0 and farDistance
/// at its exit; a tangent ray has nearDistance == farDistance.
struct RayInterval {
    double nearDistance = 0.0;
    double farDistance = 0.0;
};

/// Where a ray meets a triangle: the distance along the ray and the barycentric weights of the
/// second and third vertices (the point is (1 - u - v) p0 + u p1 + v p2).
struct RayTriangleHit {
    double distance = 0.0;
    double u = 0.0;
    double v = 0.0;
};

/// The interval of the ray inside the ellipsoid; empty when the ray misses it, points away from
/// it, or has a zero direction, or when squares of the scaled input overflow (beyond ~1e150 m).
/// Solved on the unit sphere of ellipsoid-scaled space with the discriminant taken from the
/// ray's closest approach to the centre and the roots in the cancellation-free form. A ray whose
/// closest approach is within the rounding error of its own inputs of the surface (1e-15 of
/// the distance from the centre: under a micrometre for a ray from 1e9 m grazing the Earth)
/// counts as tangent and touches there (nearDistance == farDistance). An origin within rounding
/// of the surface (about 6 nm on the Earth) counts as inside: nearDistance is 0.
std::optional<RayInterval> intersectRayEllipsoid(const Ray& ray, const Ellipsoid& ellipsoid) noexcept;

/// The interval of the ray inside the sphere, with the same rules as intersectRayEllipsoid;
/// empty also for a radius <= 0.
std::optional<RayInterval> intersectRaySphere(const Ray& ray, const BoundingSphere& sphere) noexcept;

/// Distance along the ray to the plane; 0 when the origin lies on it. Empty when the ray is
/// parallel to the plane (dot(normal, direction) == 0, even when it lies in the plane), points
/// away from it, or meets it too far away to represent.
std::optional<double> intersectRayPlane(const Ray& ray, const Plane& plane) noexcept;

/// Where the ray meets the triangle p0 p1 p2, from either side (Moeller and Trumbore), edges and
/// vertices included. Empty when it misses, when the hit is behind the origin, when the triangle
/// is degenerate (zero area) and when the ray is parallel to the triangle's plane to within
/// 1e-12 radians (a ray lying in the plane misses). Not watertight: a ray through an edge shared
/// by two triangles may, by rounding, hit both or neither.
std::optional<RayTriangleHit> intersectRayTriangle(const Ray& ray, const glm::dvec3& p0, const glm::dvec3& p1,
                                                   const glm::dvec3& p2) noexcept;

} // namespace orbis
