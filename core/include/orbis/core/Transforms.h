#pragma once

#include "orbis/core/Ellipsoid.h"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

namespace orbis {

/// East, north and up unit vectors (the columns) of the local frame at a position, up being the
/// geodetic surface normal of the point below it (so heights measure along up). At the poles, where east is undefined, east is the limit taken along
/// the prime meridian: +y at both poles.
glm::dmat3 eastNorthUpAxes(const Ellipsoid& ellipsoid, const glm::dvec3& origin) noexcept;

/// Local east-north-up coordinates (metres) at origin to Earth-fixed coordinates.
glm::dmat4 eastNorthUpToFixedFrame(const Ellipsoid& ellipsoid, const glm::dvec3& origin) noexcept;

/// The direction and up vector (Earth-fixed, unit) of a view with the given heading (clockwise
/// from north), pitch (up from the horizontal) and roll (clockwise about the view direction),
/// all radians, at a position.
struct ViewOrientation {
    glm::dvec3 direction;
    glm::dvec3 up;
};
ViewOrientation headingPitchRollToView(const Ellipsoid& ellipsoid, const glm::dvec3& position, double heading,
                                       double pitch, double roll) noexcept;

/// The heading and pitch (radians, as above) of a view direction at a position: the inverse of
/// headingPitchRollToView's direction. Looking straight up or down, the heading is 0.
struct HeadingPitch {
    double heading = 0.0;
    double pitch = 0.0;
};
HeadingPitch viewToHeadingPitch(const Ellipsoid& ellipsoid, const glm::dvec3& position,
                                const glm::dvec3& direction) noexcept;

} // namespace orbis
