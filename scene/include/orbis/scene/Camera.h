#pragma once

#include <orbis/core/Geodetic.h>
#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/core/Ray.h>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <optional>

namespace orbis {
class Ellipsoid;
} // namespace orbis

namespace orbis::world {
struct CameraDescription; // orbis/world/SceneDescription.h
} // namespace orbis::world

namespace orbis::scene {

/// A perspective camera in double precision: world positions in metres, angles in radians.
/// The view matrix is built from eye, target and up; the projection from the vertical field of
/// view, the aspect ratio and the near and far distances a frame chooses.
///
/// Window positions (pickRay, pickEllipsoid, worldToWindow) are pixels as a window reports the
/// pointer: x right and y down from the top-left corner of a width x height view, the centre of
/// pixel (i, j) at (i + 0.5, j + 0.5). (clipToWindow below counts y up, as glReadPixels does.)
class Camera final {
public:
    Camera() = default;
    Camera(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fieldOfViewYRadians);

    void lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up);
    /// Looks at `target` (Earth-fixed) from `range` metres away, along the view direction that
    /// `heading` (clockwise from north) and `pitch` (up from the horizontal: negative looks down)
    /// give in the target's east-north-up frame, without roll. Any heading, pitch and range >= 0
    /// give a finite view, straight down or up at a pole included.
    void lookAt(const Ellipsoid& ellipsoid, const glm::dvec3& target, double heading, double pitch, double range);
    /// Puts the eye at `position` (Earth-fixed) looking with heading, pitch and roll in the eye's
    /// east-north-up frame (headingPitchRollToView).
    void setView(const Ellipsoid& ellipsoid, const glm::dvec3& position, const HeadingPitchRoll& orientation);
    void setView(const Ellipsoid& ellipsoid, const Geodetic3D& position, const HeadingPitchRoll& orientation);
    /// The heading, pitch and roll of the view in the eye's east-north-up frame: what setView
    /// takes. Looking straight up or down the heading is 0 and the roll carries the turn.
    HeadingPitchRoll headingPitchRoll(const Ellipsoid& ellipsoid) const noexcept;

    /// The ray from the eye through a window position (see the class comment), unit direction.
    Ray pickRay(const glm::dvec2& windowPosition, int width, int height) const noexcept;
    /// Where that ray first meets the ellipsoid's surface; empty when it misses, and when the eye
    /// is inside the ellipsoid (or on it, within rounding).
    std::optional<glm::dvec3> pickEllipsoid(const glm::dvec2& windowPosition, int width, int height,
                                            const Ellipsoid& ellipsoid) const noexcept;
    /// The window position of a world point; empty for a point in the plane of the eye or behind
    /// it. A point outside the view gives a position outside 0..width, 0..height.
    std::optional<glm::dvec2> worldToWindow(const glm::dvec3& point, int width, int height) const noexcept;

    const glm::dvec3& eye() const noexcept { return _eye; }
    const glm::dvec3& target() const noexcept { return _target; }
    const glm::dvec3& up() const noexcept { return _up; }
    /// Unit vector from eye to target.
    glm::dvec3 direction() const noexcept;
    /// Unit vector to the right of the view direction, perpendicular to up.
    glm::dvec3 right() const noexcept;
    /// The view's unit axes: its direction, right, and the true up (perpendicular to both).
    struct Axes {
        glm::dvec3 direction{0.0};
        glm::dvec3 right{0.0};
        glm::dvec3 up{0.0};
    };
    Axes axes() const noexcept;
    /// Half the view's extent at unit distance, across and up, for a width x height view: the ray
    /// through clip coordinates x, y (-1..1) is direction + x extent.x right + y extent.y up.
    glm::dvec2 halfExtent(int width, int height) const noexcept;

    double fieldOfViewY() const noexcept { return _fieldOfViewY; }
    void setFieldOfViewY(double radians) noexcept { _fieldOfViewY = radians; }

    /// World to eye space, right-handed, looking down -z.
    glm::dmat4 viewMatrix() const noexcept;
    /// OpenGL clip space (depth -1..1) for the given aspect ratio (width / height) and distances.
    glm::dmat4 projectionMatrix(double aspectRatio, double nearDistance, double farDistance) const noexcept;

private:
    glm::dvec3 _eye{0.0, 0.0, 1.0};
    glm::dvec3 _target{0.0, 0.0, 0.0};
    glm::dvec3 _up{0.0, 1.0, 0.0};
    double _fieldOfViewY = 0.7853981633974483; // 45 degrees
};

/// The camera a scene file's description asks for on an ellipsoid: up is the local vertical, or
/// north where the view is vertical; a heading-pitch-roll aim puts the target ahead of the eye, as
/// far as the eye is from the centre.
Camera makeCamera(const world::CameraDescription& description, const Ellipsoid& ellipsoid);

/// Window position (pixels, y up from the bottom edge) of a clip-space position with w > 0, in
/// double.
inline glm::dvec2 clipToWindow(const glm::dvec4& clip, int width, int height) noexcept
{
    return {(clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height};
}

} // namespace orbis::scene
