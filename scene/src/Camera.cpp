#include "orbis/scene/Camera.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/IntersectionTests.h>
#include <orbis/core/Math.h>
#include <orbis/core/Transforms.h>
#include <orbis/world/SceneDescription.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <variant>

namespace orbis::scene {

namespace {

/// A target this far ahead of the eye keeps the direction's rounding small next to the eye's
/// coordinates (one metre off the Earth's surface, target - eye would keep it to 1e-9 rad).
double targetReach(const glm::dvec3& eye) noexcept
{
    return std::max(1.0, glm::length(eye));
}

} // namespace

Camera::Camera(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fieldOfViewYRadians)
    : _fieldOfViewY(fieldOfViewYRadians)
{
    lookAt(eye, target, up);
}

void Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up)
{
    _eye = eye;
    _target = target;
    // An up vector parallel to the view direction leaves the view undefined: pick any perpendicular.
    const glm::dvec3 forward = target - eye;
    const glm::dvec3 side = glm::cross(forward, up);
    _up = glm::dot(side, side) > 0.0 ? glm::normalize(up) : anyPerpendicular(forward);
}

void Camera::lookAt(const Ellipsoid& ellipsoid, const glm::dvec3& target, double heading, double pitch, double range)
{
    const ViewOrientation view = headingPitchRollToView(ellipsoid, target, heading, pitch, 0.0);
    range = std::max(0.0, range);
    const glm::dvec3 eye = target - range * view.direction;
    // Aimed at a point past the target, so that a range of 0 still has a direction.
    lookAt(eye, eye + std::max(range, targetReach(eye)) * view.direction, view.up);
}

void Camera::setView(const Ellipsoid& ellipsoid, const glm::dvec3& position, const HeadingPitchRoll& orientation)
{
    const ViewOrientation view =
        headingPitchRollToView(ellipsoid, position, orientation.heading, orientation.pitch, orientation.roll);
    lookAt(position, position + targetReach(position) * view.direction, view.up);
}

void Camera::setView(const Ellipsoid& ellipsoid, const Geodetic3D& position, const HeadingPitchRoll& orientation)
{
    setView(ellipsoid, ellipsoid.toCartesian(position), orientation);
}

HeadingPitchRoll Camera::headingPitchRoll(const Ellipsoid& ellipsoid) const noexcept
{
    const Axes axes = this->axes();
    const HeadingPitch aim = viewToHeadingPitch(ellipsoid, _eye, axes.direction);
    // The roll is the turn of the true up from the up the same heading and pitch have unrolled.
    const ViewOrientation unrolled = headingPitchRollToView(ellipsoid, _eye, aim.heading, aim.pitch, 0.0);
    const glm::dvec3 unrolledRight = glm::cross(unrolled.direction, unrolled.up);
    const double roll = std::atan2(glm::dot(axes.up, unrolledRight), glm::dot(axes.up, unrolled.up));
    return {aim.heading, aim.pitch, roll};
}

Ray Camera::pickRay(const glm::dvec2& windowPosition, int width, int height) const noexcept
{
    const Axes axes = this->axes();
    const glm::dvec2 extent = halfExtent(width, height);
    const double x = width > 0 ? 2.0 * windowPosition.x / width - 1.0 : 0.0;
    const double y = height > 0 ? 1.0 - 2.0 * windowPosition.y / height : 0.0;
    const glm::dvec3 direction = axes.direction + (x * extent.x) * axes.right + (y * extent.y) * axes.up;
    return {_eye, glm::normalize(direction)};
}

std::optional<glm::dvec3> Camera::pickEllipsoid(const glm::dvec2& windowPosition, int width, int height,
                                                const Ellipsoid& ellipsoid) const noexcept
{
    const Ray ray = pickRay(windowPosition, width, height);
    const std::optional<RayInterval> inside = intersectRayEllipsoid(ray, ellipsoid);
    if (!inside || inside->nearDistance <= 0.0) {
        return std::nullopt;
    }
    return ray.pointAt(inside->nearDistance);
}

std::optional<glm::dvec2> Camera::worldToWindow(const glm::dvec3& point, int width, int height) const noexcept
{
    const Axes axes = this->axes();
    const glm::dvec3 offset = point - _eye;
    const double depth = glm::dot(offset, axes.direction);
    if (!(depth > 0.0)) {
        return std::nullopt;
    }
    const glm::dvec2 extent = halfExtent(width, height);
    const double x = glm::dot(offset, axes.right) / (depth * extent.x);
    const double y = glm::dot(offset, axes.up) / (depth * extent.y);
    return glm::dvec2((x + 1.0) * 0.5 * width, (1.0 - y) * 0.5 * height);
}

glm::dvec3 Camera::direction() const noexcept
{
    return glm::normalize(_target - _eye);
}

glm::dvec3 Camera::right() const noexcept
{
    return glm::normalize(glm::cross(direction(), _up));
}

Camera::Axes Camera::axes() const noexcept
{
    const glm::dvec3 forward = direction();
    const glm::dvec3 across = right();
    return {forward, across, glm::cross(across, forward)};
}

glm::dvec2 Camera::halfExtent(int width, int height) const noexcept
{
    const double up = std::tan(0.5 * _fieldOfViewY);
    const double aspect = height > 0 ? static_cast<double>(width) / height : 1.0;
    return {up * aspect, up};
}

glm::dmat4 Camera::viewMatrix() const noexcept
{
    return glm::lookAtRH(_eye, _target, _up);
}

glm::dmat4 Camera::projectionMatrix(double aspectRatio, double nearDistance, double farDistance) const noexcept
{
    return glm::perspectiveRH_NO(_fieldOfViewY, aspectRatio, nearDistance, farDistance);
}

Camera makeCamera(const world::CameraDescription& description, const Ellipsoid& ellipsoid)
{
    const glm::dvec3 eye = ellipsoid.toCartesian(description.position);
    if (const auto* orientation = std::get_if<HeadingPitchRoll>(&description.aim)) {
        Camera camera;
        camera.setFieldOfViewY(description.fieldOfViewY);
        camera.setView(ellipsoid, eye, *orientation);
        return camera;
    }
    const glm::dvec3 target = ellipsoid.toCartesian(std::get<Geodetic3D>(description.aim));
    const glm::dmat3 eastNorthUp = eastNorthUpAxes(ellipsoid, eye);
    // The local vertical as up, unless the view runs along it; then north (the top of a map).
    const glm::dvec3 direction = target - eye;
    const glm::dvec3 side = glm::cross(direction, eastNorthUp[2]);
    const bool vertical = glm::dot(side, side) <= 1e-12 * glm::dot(direction, direction);
    return Camera(eye, target, vertical ? eastNorthUp[1] : eastNorthUp[2], description.fieldOfViewY);
}

} // namespace orbis::scene
