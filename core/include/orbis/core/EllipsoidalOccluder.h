#pragma once

#include "orbis/core/Ellipsoid.h"

#include <glm/vec3.hpp>

#include <optional>
#include <span>

namespace orbis {

/// Horizon culling against an ellipsoid seen from a camera (Rendering Massive Virtual Worlds,
/// section 3.6), worked in ellipsoid-scaled space, where the ellipsoid is the unit sphere.
///
/// A point is occluded when it lies behind the horizon plane and inside the cone of lines from
/// the camera tangent to the ellipsoid. For points on or above the surface this is exact: the
/// segment from the camera to an occluded point passes through the ellipsoid. Points below the
/// surface but in front of the horizon plane count as visible (conservative). Points within
/// rounding (about 1e-15 of the camera's distance) of the horizon may go either way.
///
/// A camera on or below the surface culls nothing: every point is visible. Underground the
/// ellipsoid is not the ground the viewer stands on (terrain dips below it, at the Dead Sea or
/// under water), so no part of it can be trusted to hide anything.
///
/// Usage: compute a tile's horizonOcclusionPoint() once when it loads, then each frame test it
/// with isScaledSpacePointVisible(); when it is hidden, every position it was built from is.
class EllipsoidalOccluder final {
public:
    EllipsoidalOccluder(const Ellipsoid& ellipsoid, const glm::dvec3& cameraPosition) noexcept;

    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }
    const glm::dvec3& cameraPosition() const noexcept { return _cameraPosition; }
    /// Moves the camera (world metres); precomputes what each test needs.
    void setCameraPosition(const glm::dvec3& cameraPosition) noexcept;
    /// True when the camera is strictly above the surface, so that the horizon can hide points.
    bool canOcclude() const noexcept { return _distanceToLimbSquared > 0.0; }

    /// p with each coordinate divided by the ellipsoid's radius along that axis.
    glm::dvec3 toScaledSpace(const glm::dvec3& p) const noexcept { return p * _ellipsoid.oneOverRadii(); }

    /// True unless the world point p is hidden by the ellipsoid (see the class comment).
    bool isPointVisible(const glm::dvec3& p) const noexcept;
    /// The same test for a point already in scaled space (a horizon occlusion point).
    bool isScaledSpacePointVisible(const glm::dvec3& scaledPoint) const noexcept;
    /// The test for a point in the scaled space of occludingEllipsoid(ellipsoid(), minimumHeight),
    /// for geometry that reaches below the surface (terrain under the sea): that smaller
    /// ellipsoid is what hides it. The plain test when minimumHeight >= 0.
    bool isScaledSpacePointVisible(const glm::dvec3& scaledPoint, double minimumHeight) const noexcept;

    /// The ellipsoid that may hide geometry reaching down to minimumHeight: the radii shortened by
    /// -minimumHeight when it is negative (to no less than half of each), else the ellipsoid itself.
    static Ellipsoid occludingEllipsoid(const Ellipsoid& ellipsoid, double minimumHeight) noexcept;

    /// The horizon occlusion point of positions (world metres) along directionToPoint (world,
    /// from the centre, usually towards the tile's bounding-sphere centre), in scaled space: the
    /// point of that line closest to the centre which, once hidden, proves every position hidden
    /// from any camera. A position below the surface counts as its projection onto the surface
    /// towards the centre. Empty when no such point exists (a position at or beyond 90 degrees of
    /// the direction once its own horizon is added, e.g. a surface point opposite the direction),
    /// for no positions, a zero direction or a position at the centre. Does not depend on the camera.
    std::optional<glm::dvec3> horizonOcclusionPoint(const glm::dvec3& directionToPoint,
                                                    std::span<const glm::dvec3> positions) const noexcept;

private:
    Ellipsoid _ellipsoid;
    glm::dvec3 _cameraPosition{0.0};
    glm::dvec3 _cameraPositionScaled{0.0};
    double _distanceToLimbSquared = 0.0; ///< scaled-space |camera|^2 - 1
};

} // namespace orbis
