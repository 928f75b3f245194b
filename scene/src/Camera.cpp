#include "orbis/scene/Camera.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Math.h>
#include <orbis/core/Transforms.h>
#include <orbis/world/SceneDescription.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <variant>

namespace orbis::scene {

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

glm::dvec3 Camera::direction() const noexcept
{
    return glm::normalize(_target - _eye);
}

glm::dvec3 Camera::right() const noexcept
{
    return glm::normalize(glm::cross(direction(), _up));
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
        const ViewOrientation view =
            headingPitchRollToView(ellipsoid, eye, orientation->heading, orientation->pitch, orientation->roll);
        // A target far ahead keeps the direction's rounding small next to the eye's coordinates.
        const double reach = std::max(1.0, glm::length(eye));
        return Camera(eye, eye + reach * view.direction, view.up, description.fieldOfViewY);
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
