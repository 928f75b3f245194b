#pragma once

#include "orbis/scene/Camera.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/world/CameraKeyframe.h>

#include <vector>

namespace orbis::scene {

/// A user input, as an interactive window or a scripted test produces it.
struct InputEvent {
    enum class Type { Drag, Scroll, Key };
    enum class Key { Forward, Backward, Left, Right, Up, Down };

    Type type = Type::Drag;
    glm::dvec2 pixels{0.0}; ///< Drag: pointer movement in pixels (x right, y down)
    double wheelSteps = 0.0; ///< Scroll: positive zooms in
    Key key = Key::Forward;   ///< Key: which movement
    double seconds = 0.0;     ///< Key: how long it was held

    static InputEvent drag(double dx, double dy) { return {Type::Drag, {dx, dy}, 0.0, Key::Forward, 0.0}; }
    static InputEvent scroll(double steps) { return {Type::Scroll, {0.0, 0.0}, steps, Key::Forward, 0.0}; }
    static InputEvent keyHeld(Key key, double seconds) { return {Type::Key, {0.0, 0.0}, 0.0, key, seconds}; }
};

/// Orbits a centre point: dragging turns azimuth and elevation, scrolling scales the distance
/// above a surface radius exponentially, so zooming towards a globe slows near the ground and
/// never passes below it.
class OrbitController final {
public:
    /// surfaceRadius: the distance from the centre the camera never reaches (0 for a point).
    OrbitController(const glm::dvec3& centre, double range, double surfaceRadius = 0.0) noexcept;

    void handle(const InputEvent& event) noexcept;
    /// Turns by the given angles; elevation stays within +-89.9 degrees so up stays defined.
    void rotate(double azimuthRadians, double elevationRadians) noexcept;
    /// Multiplies the distance above the surface radius by factor (> 0), keeping at least minimumHeight.
    void zoom(double factor) noexcept;

    double azimuth() const noexcept { return _azimuth; }
    double elevation() const noexcept { return _elevation; }
    double range() const noexcept { return _range; }

    /// Points the camera at the centre from the current azimuth, elevation and range (z up).
    void apply(Camera& camera) const noexcept;

    double radiansPerPixel = 0.005;
    double zoomPerWheelStep = 0.85;
    double minimumHeight = 1.0; ///< metres above the surface radius

private:
    glm::dvec3 _centre;
    double _range;
    double _surfaceRadius;
    double _azimuth = 0.0;
    double _elevation = 0.0;
};

/// Flies over an ellipsoid: dragging turns heading and pitch, keys move along the view, and the
/// speed is the height above the ellipsoid per second (at least 1 m/s), so it suits both a street
/// and orbit.
class FlyController final {
public:
    FlyController(const Ellipsoid& ellipsoid, const glm::dvec3& position, double heading, double pitch) noexcept;

    void handle(const InputEvent& event) noexcept;
    const glm::dvec3& position() const noexcept { return _position; }
    double heading() const noexcept { return _heading; }
    double pitch() const noexcept { return _pitch; }
    /// Current speed in metres per second.
    double speed() const noexcept;

    void apply(Camera& camera) const noexcept;

    double radiansPerPixel = 0.003;

private:
    Ellipsoid _ellipsoid;
    glm::dvec3 _position;
    double _heading;
    double _pitch;
};

/// Orbiting and flying behind one switch, as an interactive viewer offers them. It starts orbiting
/// the ellipsoid's centre from a camera's eye; switching mode starts the other controller from the
/// camera as it is: flying keeps the eye and the view direction; orbiting keeps the eye's
/// direction and distance (raised to clear the equatorial radius, which orbiting never goes below)
/// and turns to the centre.
class ViewerController final {
public:
    enum class Mode { Orbit, Fly };

    ViewerController(const Ellipsoid& ellipsoid, const Camera& camera) noexcept;

    Mode mode() const noexcept { return _mode; }
    void setMode(Mode mode, const Camera& camera) noexcept;
    /// Drags and wheel steps go to the current controller; keys move only when flying.
    void handle(const InputEvent& event) noexcept;
    void apply(Camera& camera) const noexcept;

private:
    Ellipsoid _ellipsoid;
    Mode _mode = Mode::Orbit;
    OrbitController _orbit;
    FlyController _fly;
};

/// A camera's flight to a destination over a duration, as a viewer's "fly to" plays it: the eye
/// follows the great circle between the start and the destination (over a pole or across the
/// antimeridian as the short way goes), eased in and out, and rises on the way to a height that
/// follows the distance covered (a short hop stays low, a flight to the far side of the Earth
/// goes out to see it whole); heading, pitch and roll turn the short way from the start's to the
/// destination's. Sample it with apply() once a frame.
class CameraFlight final {
public:
    /// From `start` to the eye at `destination` looking with `orientation` (Camera::setView),
    /// taking `seconds` (0 or less: there at once).
    CameraFlight(const Ellipsoid& ellipsoid, const Camera& start, const Geodetic3D& destination,
                 const HeadingPitchRoll& orientation, double seconds);

    double duration() const noexcept { return _duration; }
    /// The camera `seconds` after the start, clamped to 0..duration; the field of view is kept.
    void apply(double seconds, Camera& camera) const noexcept;
    /// The eye's position `seconds` after the start.
    Geodetic3D positionAt(double seconds) const noexcept;
    /// The highest the arc goes above the straight interpolation of the two heights, metres.
    double arcHeight() const noexcept { return _arcHeight; }

private:
    /// The eased fraction of the way done after `seconds`.
    double progress(double seconds) const noexcept;

    Ellipsoid _ellipsoid;
    Geodetic3D _destination;
    glm::dvec3 _startNormal;
    glm::dvec3 _axis;  ///< of the turn from the start's surface normal to the destination's
    double _angle;     ///< of that turn, radians, 0..pi
    double _startHeight;
    double _endHeight;
    double _arcHeight;
    HeadingPitchRoll _startOrientation;
    HeadingPitchRoll _endOrientation;
    double _duration;
};

/// A scripted camera flight: keyframes of geodetic eye and target positions at times, sampled
/// with linear interpolation (longitude the short way round the antimeridian). Tests and
/// benchmarks drive the scene with it.
class CameraPath final {
public:
    using Keyframe = world::CameraKeyframe;

    explicit CameraPath(const Ellipsoid& ellipsoid) : _ellipsoid(ellipsoid) {}

    /// Keyframes must be added in increasing time (asserted).
    void add(const Keyframe& keyframe);
    const std::vector<Keyframe>& keyframes() const noexcept { return _keyframes; }
    double duration() const noexcept;

    /// The camera at a time, clamped to the path's extent; the local up of the eye as up. An empty
    /// path leaves the camera unchanged.
    void apply(double seconds, Camera& camera) const;

private:
    Ellipsoid _ellipsoid;
    std::vector<Keyframe> _keyframes;
};

} // namespace orbis::scene
