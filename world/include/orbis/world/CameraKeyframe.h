#pragma once

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Geodetic.h>

#include <optional>

namespace orbis::world {

/// One keyframe of a camera path file (`orbis render --path`, docs/scene-format.md): where the eye
/// is and what it looks at, at a time. The scene's CameraPath flies through them.
struct CameraKeyframe {
    double seconds;    ///< from the start of the path
    Geodetic3D eye;    ///< radians, metres
    Geodetic3D target; ///< radians, metres
};

/// The eye and target a fraction t (0 to 1) of the way from keyframe a to keyframe b: longitude,
/// latitude and height each linear in t, longitude the short way round.
CameraKeyframe interpolateKeyframes(const CameraKeyframe& a, const CameraKeyframe& b, double t) noexcept;

/// The time between keyframes a and b (interpolated as interpolateKeyframes does) at which the eye
/// comes closest to its target, when that is within `tolerance` metres (a camera there would look
/// nowhere); empty when the eye stays farther. Sampled, then refined by golden sections.
std::optional<double> eyeMeetsTarget(const Ellipsoid& ellipsoid, const CameraKeyframe& a, const CameraKeyframe& b,
                                     double tolerance) noexcept;

} // namespace orbis::world
