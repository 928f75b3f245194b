#include <orbis/scene/CameraControllers.h>

#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::scene;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {
const Ellipsoid kEarth = Ellipsoid::wgs84();
}

TEST_CASE("Camera builds a right-handed view looking down -z", "[scene][camera]")
{
    const Camera camera({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, toRadians(60.0));
    const glm::dvec4 target = camera.viewMatrix() * glm::dvec4(0, 0, 0, 1);
    REQUIRE_THAT(target.z, WithinRel(-10.0, 1e-12));
    REQUIRE(glm::length(camera.right() - glm::dvec3(1, 0, 0)) < 1e-15);
    // An up vector parallel to the view is replaced, never left to produce NaN.
    const Camera straightDown({0, 0, 10}, {0, 0, 0}, {0, 0, 1}, 1.0);
    REQUIRE(isFinite(straightDown.right()));
    const glm::dmat4 view = straightDown.viewMatrix();
    REQUIRE(std::isfinite(view[0][0]));
}

TEST_CASE("Orbit controller keeps its range, clamps elevation and never zooms below the surface", "[scene][camera]")
{
    const double radius = kEarth.maximumRadius();
    OrbitController orbit({0, 0, 0}, 3 * radius, radius);
    Camera camera;
    orbit.handle(InputEvent::drag(100, 0));
    orbit.apply(camera);
    REQUIRE_THAT(glm::length(camera.eye()), WithinRel(3 * radius, 1e-12));
    REQUIRE_THAT(orbit.azimuth(), WithinRel(-0.5, 1e-12));

    orbit.handle(InputEvent::drag(0, 1e6)); // far past the pole
    REQUIRE(orbit.elevation() < kHalfPi);
    orbit.apply(camera);
    REQUIRE(isFinite(camera.eye()));
    REQUIRE(isFinite(camera.right()));

    for (int i = 0; i < 1000; ++i) {
        orbit.handle(InputEvent::scroll(5));
    }
    REQUIRE_THAT(orbit.range() - radius, WithinRel(orbit.minimumHeight, 1e-12)); // approaches, then stops above
    orbit.handle(InputEvent::scroll(-10));
    REQUIRE(orbit.range() - radius > 2 * orbit.minimumHeight);
}

TEST_CASE("Fly controller speed follows height, so one key press covers more ground from orbit", "[scene][camera]")
{
    const glm::dvec3 low = kEarth.toCartesian(Geodetic3D::fromDegrees(10, 45, 100));
    const glm::dvec3 high = kEarth.toCartesian(Geodetic3D::fromDegrees(10, 45, 1e6));
    FlyController lowFlyer(kEarth, low, 0.0, 0.0);
    FlyController highFlyer(kEarth, high, 0.0, 0.0);
    REQUIRE_THAT(lowFlyer.speed(), WithinAbs(100.0, 1e-6));
    REQUIRE_THAT(highFlyer.speed(), WithinAbs(1e6, 1e-3));

    lowFlyer.handle(InputEvent::keyHeld(InputEvent::Key::Forward, 1.0));
    // Heading 0, pitch 0: due north, 100 m.
    REQUIRE_THAT(glm::length(lowFlyer.position() - low), WithinAbs(100.0, 1e-6));
    REQUIRE(kEarth.toGeodetic2D(lowFlyer.position()).latitude > toRadians(45.0));

    lowFlyer.handle(InputEvent::drag(0, -1e5)); // pitch up past vertical: clamped
    REQUIRE(lowFlyer.pitch() < kHalfPi);
    Camera camera;
    lowFlyer.apply(camera);
    REQUIRE(isFinite(camera.right()));
}

TEST_CASE("Camera path passes through its keyframes and crosses the antimeridian the short way", "[scene][camera]")
{
    CameraPath path(kEarth);
    path.add({0.0, Geodetic3D::fromDegrees(170, 0, 1e6), Geodetic3D::fromDegrees(170, 0, 0)});
    path.add({10.0, Geodetic3D::fromDegrees(-170, 10, 2e6), Geodetic3D::fromDegrees(-170, 10, 0)});
    REQUIRE(path.duration() == 10.0);

    Camera camera;
    path.apply(0.0, camera);
    REQUIRE(glm::length(camera.eye() - kEarth.toCartesian(Geodetic3D::fromDegrees(170, 0, 1e6))) < 1e-6);
    path.apply(5.0, camera);
    const Geodetic3D middle = kEarth.toGeodetic3D(camera.eye());
    REQUIRE_THAT(std::abs(middle.longitude), WithinAbs(kPi, 1e-12)); // 180, not 0
    REQUIRE_THAT(middle.height, WithinAbs(1.5e6, 1e-6));
    path.apply(99.0, camera); // clamped to the end
    REQUIRE(glm::length(camera.eye() - kEarth.toCartesian(Geodetic3D::fromDegrees(-170, 10, 2e6))) < 1e-6);
}

TEST_CASE("Viewer controller orbits from the camera's eye and flies on from the view as it is", "[scene][camera]")
{
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(-40, 30, 4e6));
    // Looking north-east and down, not at the centre.
    const ViewOrientation view = headingPitchRollToView(kEarth, eye, toRadians(45.0), toRadians(-30.0), 0.0);
    Camera camera(eye, eye + view.direction * 1e6, view.up, toRadians(45.0));
    ViewerController controller(kEarth, camera);
    REQUIRE(controller.mode() == ViewerController::Mode::Orbit);

    // Orbit: the same eye, now looking at the centre.
    Camera orbiting = camera;
    controller.apply(orbiting);
    REQUIRE(glm::distance(orbiting.eye(), eye) < 1e-6);
    REQUIRE(glm::length(orbiting.target()) < 1e-6);
    // Dragging right turns the eye west (the globe follows the pointer), at the same range.
    controller.handle(InputEvent::drag(100.0, 0.0));
    controller.apply(orbiting);
    REQUIRE_THAT(glm::length(orbiting.eye()), WithinRel(glm::length(eye), 1e-12));
    REQUIRE(kEarth.toGeodetic3D(orbiting.eye()).longitude < toRadians(-40.0 - 20.0));

    // Fly from the original view: eye and direction kept.
    controller.setMode(ViewerController::Mode::Fly, camera);
    Camera flying = camera;
    controller.apply(flying);
    REQUIRE(glm::distance(flying.eye(), eye) < 1e-6);
    REQUIRE(glm::distance(glm::normalize(flying.target() - flying.eye()), view.direction) < 1e-12);
    // Keys move along the view at the speed of the height (4,000 km a second here); the wheel does nothing.
    controller.handle(InputEvent::scroll(3.0));
    controller.handle(InputEvent::keyHeld(InputEvent::Key::Forward, 0.25));
    controller.apply(flying);
    REQUIRE_THAT(glm::distance(flying.eye(), eye), WithinRel(1e6, 1e-9));
    REQUIRE(glm::distance(glm::normalize(flying.eye() - eye), view.direction) < 1e-12);

    // Back to orbiting from where the flight went: the eye stays, the view turns to the centre.
    controller.setMode(ViewerController::Mode::Orbit, flying);
    Camera back = flying;
    controller.apply(back);
    REQUIRE(glm::distance(back.eye(), flying.eye()) < 1e-6);
    REQUIRE(glm::length(back.target()) < 1e-6);
}
