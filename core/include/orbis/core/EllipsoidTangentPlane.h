#pragma once

#include "orbis/core/Ellipsoid.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>
#include <span>
#include <vector>

namespace orbis {

/// A plane tangent to an ellipsoid, with axes east (x), north (y) and the outward geodetic normal,
/// and the gnomonic projection onto it (book section 8.2.2): a position maps to where the ray from
/// the ellipsoid's centre through it meets the plane. Curves cut from the surface by planes through
/// the centre (the edges the polygon tessellators draw) map to straight lines, and back.
///
/// ```
/// const EllipsoidTangentPlane plane(Ellipsoid::wgs84(), ringPositions);
/// if (const auto p = plane.projectPointOntoPlane(position)) { /* p->x east, p->y north, metres */ }
/// ```
class EllipsoidTangentPlane final {
public:
    /// The plane tangent at the centre of positions' bounding box moved to the geodetic surface.
    /// Empty positions, or a centre at the ellipsoid's centre, give the plane at the north pole.
    EllipsoidTangentPlane(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions) noexcept;
    /// The plane tangent at the foot of point on the geodetic surface (the north pole for the centre).
    EllipsoidTangentPlane(const Ellipsoid& ellipsoid, const glm::dvec3& point) noexcept;

    /// The ellipsoid the plane is tangent to.
    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }
    /// The point of tangency, on the surface.
    const glm::dvec3& origin() const noexcept { return _origin; }
    /// East at the origin (unit); +y at the poles, where east is undefined.
    const glm::dvec3& xAxis() const noexcept { return _xAxis; }
    /// North at the origin (unit): normal x xAxis.
    const glm::dvec3& yAxis() const noexcept { return _yAxis; }
    /// The outward geodetic surface normal at the origin (unit).
    const glm::dvec3& normal() const noexcept { return _normal; }

    /// Plane coordinates (metres along xAxis and yAxis from the origin) of the point where the ray
    /// from the ellipsoid's centre through p meets the plane; nullopt when the ray does not meet it
    /// (p on or beyond the plane's horizon, normal . p <= 0, the centre included) or the point would
    /// overflow.
    std::optional<glm::dvec2> projectPointOntoPlane(const glm::dvec3& p) const noexcept;
    /// projectPointOntoPlane for each position; nullopt when any of them cannot be projected.
    std::optional<std::vector<glm::dvec2>> projectPointsOntoPlane(std::span<const glm::dvec3> positions) const;

    /// The point of the plane with plane coordinates q, in world coordinates.
    glm::dvec3 planeToWorld(const glm::dvec2& q) const noexcept { return _origin + q.x * _xAxis + q.y * _yAxis; }
    /// The inverse projection: where the ray from the centre through the plane point q meets the
    /// ellipsoid. Exact inverse of projectPointOntoPlane for positions on the surface (to rounding).
    glm::dvec3 projectPointOntoEllipsoid(const glm::dvec2& q) const noexcept;

    /// Cosine of the angle, seen from the ellipsoid's centre, between p and the plane's normal:
    /// 1 straight below the origin, 0 on the horizon of the projection, -1 opposite; 0 for the centre.
    double cosineFromNormal(const glm::dvec3& p) const noexcept;

private:
    Ellipsoid _ellipsoid;
    glm::dvec3 _origin;
    glm::dvec3 _xAxis;
    glm::dvec3 _yAxis;
    glm::dvec3 _normal;
};

} // namespace orbis
