#include "orbis/core/EllipsoidalOccluder.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis {

EllipsoidalOccluder::EllipsoidalOccluder(const Ellipsoid& ellipsoid, const glm::dvec3& cameraPosition) noexcept
    : _ellipsoid(ellipsoid)
{
    setCameraPosition(cameraPosition);
}

void EllipsoidalOccluder::setCameraPosition(const glm::dvec3& cameraPosition) noexcept
{
    _cameraPosition = cameraPosition;
    _cameraPositionScaled = toScaledSpace(cameraPosition);
    // The squared distance from the camera to the horizon circle (the limb), in scaled space.
    _distanceToLimbSquared = glm::dot(_cameraPositionScaled, _cameraPositionScaled) - 1.0;
}

bool EllipsoidalOccluder::isPointVisible(const glm::dvec3& p) const noexcept
{
    return isScaledSpacePointVisible(toScaledSpace(p));
}

namespace {

/// The horizon test in a scaled space where the occluder is the unit sphere; distanceToLimbSquared
/// is |camera|^2 - 1.
bool isVisibleFrom(const glm::dvec3& camera, double distanceToLimbSquared, const glm::dvec3& scaledPoint) noexcept
{
    if (!(distanceToLimbSquared > 0.0)) {
        return true;
    }
    const glm::dvec3 cameraToPoint = scaledPoint - camera;
    // How far the point lies beyond the camera along the line to the centre; the horizon plane
    // (through the limb) is at distanceToLimbSquared.
    const double depth = -glm::dot(cameraToPoint, camera);
    if (!(depth > distanceToLimbSquared)) {
        return true;
    }
    // depth^2 / |cameraToPoint|^2 = |camera|^2 cos^2 of the angle off the line to the centre; it
    // exceeds |camera|^2 - 1 exactly inside the cone tangent to the sphere. depth > 0 here, so
    // cameraToPoint is not zero.
    return !(depth * depth > distanceToLimbSquared * glm::dot(cameraToPoint, cameraToPoint));
}

} // namespace

bool EllipsoidalOccluder::isScaledSpacePointVisible(const glm::dvec3& scaledPoint) const noexcept
{
    return isVisibleFrom(_cameraPositionScaled, _distanceToLimbSquared, scaledPoint);
}

bool EllipsoidalOccluder::isScaledSpacePointVisible(const glm::dvec3& scaledPoint, double minimumHeight) const noexcept
{
    if (minimumHeight >= 0.0) {
        return isScaledSpacePointVisible(scaledPoint);
    }
    const Ellipsoid occluding = occludingEllipsoid(_ellipsoid, minimumHeight);
    const glm::dvec3 camera = _cameraPosition * occluding.oneOverRadii();
    return isVisibleFrom(camera, glm::dot(camera, camera) - 1.0, scaledPoint);
}

Ellipsoid EllipsoidalOccluder::occludingEllipsoid(const Ellipsoid& ellipsoid, double minimumHeight) noexcept
{
    if (!(minimumHeight < 0.0)) {
        return ellipsoid;
    }
    return Ellipsoid(glm::max(ellipsoid.radii() + minimumHeight, 0.5 * ellipsoid.radii()));
}

std::optional<glm::dvec3> EllipsoidalOccluder::horizonOcclusionPoint(const glm::dvec3& directionToPoint,
                                                                     std::span<const glm::dvec3> positions) const noexcept
{
    const glm::dvec3 scaledDirection = toScaledSpace(directionToPoint);
    const double directionLength = glm::length(scaledDirection);
    if (positions.empty() || !(directionLength > 0.0) || !std::isfinite(directionLength)) {
        return std::nullopt;
    }
    const glm::dvec3 direction = scaledDirection / directionLength;
    // The cosine below is rounded by a few units of epsilon; taking that much off keeps the
    // point on the safe (far) side.
    constexpr double kMargin = 16.0 * std::numeric_limits<double>::epsilon();
    double largest = 0.0;
    for (const glm::dvec3& position : positions) {
        const glm::dvec3 scaled = toScaledSpace(position);
        const double length = glm::length(scaled);
        if (!(length > 0.0) || !std::isfinite(length)) {
            return std::nullopt;
        }
        const glm::dvec3 unit = scaled / length;
        const double magnitude = std::max(length, 1.0);
        // alpha: angle between the position and the direction; beta: angle from the position to
        // its own horizon as seen from the centre. The tangent line at the horizon point meets
        // the direction's line at 1 / cos(alpha + beta) from the centre.
        const double cosAlpha = glm::dot(unit, direction);
        const double sinAlpha = glm::length(glm::cross(unit, direction));
        const double cosBeta = 1.0 / magnitude;
        const double sinBeta = std::sqrt((magnitude - 1.0) * (magnitude + 1.0)) * cosBeta;
        const double cosSum = cosAlpha * cosBeta - sinAlpha * sinBeta - kMargin;
        if (!(cosSum > 0.0)) {
            return std::nullopt;
        }
        largest = std::max(largest, 1.0 / cosSum);
    }
    if (!std::isfinite(largest)) {
        return std::nullopt;
    }
    return direction * largest;
}

} // namespace orbis
