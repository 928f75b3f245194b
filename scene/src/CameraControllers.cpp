#include "orbis/scene/CameraControllers.h"

#include <orbis/core/Math.h>
#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace orbis::scene {

namespace {
constexpr double kMaximumElevation = kHalfPi - 1.7e-3; // 89.9 degrees
constexpr double kMaximumPitch = kHalfPi - 1.7e-3;
} // namespace

OrbitController::OrbitController(const glm::dvec3& centre, double range, double surfaceRadius) noexcept
    : _centre(centre)
    , _range(std::max(range, surfaceRadius))
    , _surfaceRadius(surfaceRadius)
{
}

void OrbitController::handle(const InputEvent& event) noexcept
{
    switch (event.type) {
    case InputEvent::Type::Drag:
        rotate(-event.pixels.x * radiansPerPixel, event.pixels.y * radiansPerPixel);
        break;
    case InputEvent::Type::Scroll:
        zoom(std::pow(zoomPerWheelStep, event.wheelSteps));
        break;
    case InputEvent::Type::Key:
        break;
    }
}

void OrbitController::rotate(double azimuthRadians, double elevationRadians) noexcept
{
    _azimuth = std::remainder(_azimuth + azimuthRadians, kTwoPi);
    _elevation = std::clamp(_elevation + elevationRadians, -kMaximumElevation, kMaximumElevation);
}

void OrbitController::zoom(double factor) noexcept
{
    if (factor > 0.0 && std::isfinite(factor)) {
        _range = _surfaceRadius + std::max(minimumHeight, (_range - _surfaceRadius) * factor);
    }
}

void OrbitController::apply(Camera& camera) const noexcept
{
    const glm::dvec3 offset(std::cos(_elevation) * std::cos(_azimuth), std::cos(_elevation) * std::sin(_azimuth),
                            std::sin(_elevation));
    camera.lookAt(_centre + _range * offset, _centre, {0.0, 0.0, 1.0});
}

FlyController::FlyController(const Ellipsoid& ellipsoid, const glm::dvec3& position, double heading,
                             double pitch) noexcept
    : _ellipsoid(ellipsoid)
    , _position(position)
    , _heading(heading)
    , _pitch(std::clamp(pitch, -kMaximumPitch, kMaximumPitch))
{
}

double FlyController::speed() const noexcept
{
    return std::max(1.0, std::abs(_ellipsoid.toGeodetic3D(_position).height));
}

void FlyController::handle(const InputEvent& event) noexcept
{
    if (event.type == InputEvent::Type::Drag) {
        _heading = std::remainder(_heading + event.pixels.x * radiansPerPixel, kTwoPi);
        _pitch = std::clamp(_pitch - event.pixels.y * radiansPerPixel, -kMaximumPitch, kMaximumPitch);
        return;
    }
    if (event.type != InputEvent::Type::Key) {
        return;
    }
    const ViewOrientation view = headingPitchRollToView(_ellipsoid, _position, _heading, _pitch, 0.0);
    const glm::dvec3 right = glm::normalize(glm::cross(view.direction, view.up));
    glm::dvec3 direction(0.0);
    switch (event.key) {
    case InputEvent::Key::Forward: direction = view.direction; break;
    case InputEvent::Key::Backward: direction = -view.direction; break;
    case InputEvent::Key::Left: direction = -right; break;
    case InputEvent::Key::Right: direction = right; break;
    case InputEvent::Key::Up: direction = _ellipsoid.geodeticSurfaceNormal(_position); break;
    case InputEvent::Key::Down: direction = -_ellipsoid.geodeticSurfaceNormal(_position); break;
    }
    _position += direction * (speed() * event.seconds);
}

void FlyController::apply(Camera& camera) const noexcept
{
    camera.setView(_ellipsoid, _position, {_heading, _pitch, 0.0});
}

namespace {

OrbitController orbitFrom(const Ellipsoid& ellipsoid, const glm::dvec3& eye) noexcept
{
    const double range = glm::length(eye);
    OrbitController orbit(glm::dvec3(0.0), range, ellipsoid.maximumRadius());
    orbit.rotate(std::atan2(eye.y, eye.x), range > 0.0 ? std::asin(std::clamp(eye.z / range, -1.0, 1.0)) : 0.0);
    return orbit;
}

FlyController flyFrom(const Ellipsoid& ellipsoid, const Camera& camera) noexcept
{
    const HeadingPitchRoll view = camera.headingPitchRoll(ellipsoid);
    return FlyController(ellipsoid, camera.eye(), view.heading, view.pitch);
}

} // namespace

ViewerController::ViewerController(const Ellipsoid& ellipsoid, const Camera& camera) noexcept
    : _ellipsoid(ellipsoid)
    , _orbit(orbitFrom(ellipsoid, camera.eye()))
    , _fly(flyFrom(ellipsoid, camera))
{
}

void ViewerController::setMode(Mode mode, const Camera& camera) noexcept
{
    _mode = mode;
    if (mode == Mode::Orbit) {
        _orbit = orbitFrom(_ellipsoid, camera.eye());
    } else {
        _fly = flyFrom(_ellipsoid, camera);
    }
}

void ViewerController::handle(const InputEvent& event) noexcept
{
    if (_mode == Mode::Orbit) {
        _orbit.handle(event);
    } else {
        _fly.handle(event);
    }
}

void ViewerController::apply(Camera& camera) const noexcept
{
    if (_mode == Mode::Orbit) {
        _orbit.apply(camera);
    } else {
        _fly.apply(camera);
    }
}

namespace {

/// `v` turned by `angle` about the unit `axis`, which is perpendicular to it.
glm::dvec3 turn(const glm::dvec3& v, const glm::dvec3& axis, double angle) noexcept
{
    return std::cos(angle) * v + std::sin(angle) * glm::cross(axis, v);
}

/// 0 to 1 with zero speed at both ends.
double ease(double t) noexcept
{
    return t * t * (3.0 - 2.0 * t);
}

/// The direction of travel at a point of the flight, as a heading there.
double travelHeading(const Ellipsoid& ellipsoid, const glm::dvec3& position, const glm::dvec3& axis,
                     const glm::dvec3& normal) noexcept
{
    return viewToHeadingPitch(ellipsoid, position, glm::cross(axis, normal)).heading;
}

} // namespace

CameraFlight::CameraFlight(const Ellipsoid& ellipsoid, const Camera& start, const Geodetic3D& destination,
                           const HeadingPitchRoll& orientation, double seconds)
    : _ellipsoid(ellipsoid)
    , _destination(destination)
    , _duration(std::isfinite(seconds) ? std::max(0.0, seconds) : 0.0)
{
    const Geodetic3D from = ellipsoid.toGeodetic3D(start.eye());
    _startNormal = Ellipsoid::geodeticSurfaceNormal(from);
    const glm::dvec3 endNormal = Ellipsoid::geodeticSurfaceNormal(destination);
    const glm::dvec3 across = glm::cross(_startNormal, endNormal);
    const double acrossLength = glm::length(across);
    _angle = std::atan2(acrossLength, glm::dot(_startNormal, endNormal));
    // Staying put or going to the antipode, any great circle through the start serves.
    _axis = acrossLength > 1e-15 ? across / acrossLength : anyPerpendicular(_startNormal);
    _startHeight = from.height;
    _endHeight = destination.height;
    // At mid-flight at least half the distance covered above the ground.
    const double distance = _angle * ellipsoid.maximumRadius();
    _arcHeight = std::max(0.0, 0.5 * distance - 0.5 * (_startHeight + _endHeight));

    // Headings are kept relative to the direction of travel, which turns smoothly over a pole
    // where the east-north-up frame spins.
    _startOrientation = start.headingPitchRoll(ellipsoid);
    _startOrientation.heading -= travelHeading(ellipsoid, start.eye(), _axis, _startNormal);
    _endOrientation = orientation;
    _endOrientation.heading -= travelHeading(ellipsoid, ellipsoid.toCartesian(destination), _axis, endNormal);
}

double CameraFlight::progress(double seconds) const noexcept
{
    // NaN seconds count as the end, where the camera is well defined.
    const double t = _duration > 0.0 && seconds == seconds ? std::clamp(seconds / _duration, 0.0, 1.0) : 1.0;
    return ease(t);
}

Geodetic3D CameraFlight::positionAt(double seconds) const noexcept
{
    const double s = progress(seconds);
    if (s == 1.0) {
        return _destination; // exactly, not to the rounding of the turn
    }
    const glm::dvec3 normal = turn(_startNormal, _axis, s * _angle);
    const double height = _startHeight + s * (_endHeight - _startHeight) + 4.0 * s * (1.0 - s) * _arcHeight;
    return {std::atan2(normal.y, normal.x), std::atan2(normal.z, std::hypot(normal.x, normal.y)), height};
}

void CameraFlight::apply(double seconds, Camera& camera) const noexcept
{
    const double s = progress(seconds);
    const Geodetic3D geodetic = positionAt(seconds);
    const glm::dvec3 position = _ellipsoid.toCartesian(geodetic);
    const glm::dvec3 normal = Ellipsoid::geodeticSurfaceNormal(geodetic);
    auto between = [s](double from, double to) { return from + s * std::remainder(to - from, kTwoPi); };
    const HeadingPitchRoll orientation{
        travelHeading(_ellipsoid, position, _axis, normal) +
            between(_startOrientation.heading, _endOrientation.heading),
        _startOrientation.pitch + s * (_endOrientation.pitch - _startOrientation.pitch),
        between(_startOrientation.roll, _endOrientation.roll)};
    camera.setView(_ellipsoid, position, orientation);
}

void CameraPath::add(const Keyframe& keyframe)
{
    assert(_keyframes.empty() || keyframe.seconds > _keyframes.back().seconds);
    _keyframes.push_back(keyframe);
}

double CameraPath::duration() const noexcept
{
    return _keyframes.empty() ? 0.0 : _keyframes.back().seconds - _keyframes.front().seconds;
}

void CameraPath::apply(double seconds, Camera& camera) const
{
    if (_keyframes.empty()) {
        return;
    }
    const auto after = std::upper_bound(_keyframes.begin(), _keyframes.end(), seconds,
                                        [](double s, const Keyframe& k) { return s < k.seconds; });
    Geodetic3D eye;
    Geodetic3D target;
    if (after == _keyframes.begin()) {
        eye = after->eye;
        target = after->target;
    } else if (after == _keyframes.end()) {
        eye = _keyframes.back().eye;
        target = _keyframes.back().target;
    } else {
        const Keyframe& a = *(after - 1);
        const Keyframe& b = *after;
        const Keyframe between = world::interpolateKeyframes(a, b, (seconds - a.seconds) / (b.seconds - a.seconds));
        eye = between.eye;
        target = between.target;
    }
    const glm::dvec3 eyePosition = _ellipsoid.toCartesian(eye);
    camera.lookAt(eyePosition, _ellipsoid.toCartesian(target), _ellipsoid.geodeticSurfaceNormal(eyePosition));
}

} // namespace orbis::scene
