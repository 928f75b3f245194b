#include "orbis/scene/CameraControllers.h"

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
    const ViewOrientation view = headingPitchRollToView(_ellipsoid, _position, _heading, _pitch, 0.0);
    // A target as far off as the eye is from the centre, so that target - eye keeps the direction
    // to the last bits (one metre off, it would keep it to 1e-9 rad).
    camera.lookAt(_position, _position + view.direction * std::max(1.0, glm::length(_position)), view.up);
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
    const HeadingPitch view = viewToHeadingPitch(ellipsoid, camera.eye(), camera.target() - camera.eye());
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
