#include "orbis/scene/Camera.h"

#include "orbis/core/Math.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

namespace orbis {

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

} // namespace orbis
