#include <orbis/scene/CameraControllers.h>

#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <utility>

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
    // An up vector parallel to the view is replaced by a unit one perpendicular to it, so that the
    // view is a rotation that still puts the target 10 m ahead on the axis.
    const Camera straightDown({0, 0, 10}, {0, 0, 0}, {0, 0, 1}, 1.0);
    REQUIRE_THAT(glm::length(straightDown.up()), WithinAbs(1.0, 1e-15));
    REQUIRE_THAT(glm::dot(straightDown.up(), straightDown.direction()), WithinAbs(0.0, 1e-15));
    REQUIRE_THAT(glm::length(straightDown.right()), WithinAbs(1.0, 1e-15));
    REQUIRE_THAT(glm::dot(straightDown.right(), straightDown.direction()), WithinAbs(0.0, 1e-15));
    const glm::dmat4 view = straightDown.viewMatrix();
    const glm::dvec4 ahead = view * glm::dvec4(0, 0, 0, 1);
    REQUIRE(glm::distance(glm::dvec3(ahead), glm::dvec3(0, 0, -10)) < 1e-14);
    const glm::dvec4 aside = view * glm::dvec4(straightDown.right(), 0.0); // right maps to +x
    REQUIRE(glm::distance(glm::dvec3(aside), glm::dvec3(1, 0, 0)) < 1e-15);
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

namespace {

Camera viewFrom(const Geodetic3D& position, const HeadingPitchRoll& orientation)
{
    Camera camera;
    camera.setView(kEarth, position, orientation);
    return camera;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b)
{
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

} // namespace

TEST_CASE("A camera flight starts at the camera, ends at the destination and eases in between", "[scene][camera]")
{
    const Camera start = viewFrom(Geodetic3D::fromDegrees(2.35, 48.85, 5000.0), {0.3, -0.5, 0.1});
    const Geodetic3D destination = Geodetic3D::fromDegrees(-74.0, 40.7, 2000.0);
    const HeadingPitchRoll orientation{toRadians(-100.0), toRadians(-20.0), 0.0};
    const CameraFlight flight(kEarth, start, destination, orientation, 8.0);
    REQUIRE(flight.duration() == 8.0);

    Camera camera = start;
    camera.setFieldOfViewY(0.9);
    flight.apply(0.0, camera);
    CHECK(glm::distance(camera.eye(), start.eye()) < 1e-6);
    CHECK(angleBetween(camera.direction(), start.direction()) < 1e-9);
    CHECK(angleBetween(camera.up(), start.up()) < 1e-9);
    CHECK(camera.fieldOfViewY() == 0.9);

    const Camera arrived = viewFrom(destination, orientation);
    for (const double after : {8.0, 100.0}) {
        flight.apply(after, camera);
        CHECK(camera.eye() == arrived.eye());
        CHECK(angleBetween(camera.direction(), arrived.direction()) < 1e-9);
        CHECK(angleBetween(camera.up(), arrived.up()) < 1e-9);
    }
    // Eased: the first tenth of the time covers a few per cent of the way (2.8 % for smoothstep).
    const double firstTenth = kEarth.toGeodetic3D(start.eye()).longitude - flight.positionAt(0.8).longitude;
    const double wholeLongitude = kEarth.toGeodetic3D(start.eye()).longitude - destination.longitude;
    CHECK(firstTenth > 0.0);
    CHECK(firstTenth < 0.05 * wholeLongitude);

    // 5,800 km from Paris to New York: at least half of that up at mid-flight.
    const double middle = flight.positionAt(4.0).height;
    CHECK(middle > 0.5 * 5.8e6);
    CHECK(middle < 0.5 * 5.9e6);
    for (double t = 0.0; t <= 8.0; t += 0.05) {
        flight.apply(t, camera);
        REQUIRE(isFinite(camera.eye()));
        REQUIRE(isFinite(camera.right()));
        // Never below the lower end.
        REQUIRE(kEarth.toGeodetic3D(camera.eye()).height >= 2000.0 - 1e-6);
    }
}

TEST_CASE("A short camera flight stays low; one from orbit does not climb", "[scene][camera]")
{
    const Camera street = viewFrom(Geodetic3D::fromDegrees(11.575, 48.137, 300.0), {0.0, -0.3, 0.0});
    const CameraFlight hop(kEarth, street, Geodetic3D::fromDegrees(11.585, 48.137, 300.0), {0.0, -0.3, 0.0}, 2.0);
    // 743 m east: at mid-flight half of that up, 72 m above the start's height.
    CHECK_THAT(hop.arcHeight(), WithinAbs(71.6, 0.5));
    CHECK_THAT(hop.positionAt(1.0).height, WithinAbs(371.6, 0.5));

    const Camera orbit = viewFrom(Geodetic3D::fromDegrees(0.0, 0.0, 2e7), {0.0, -kHalfPi, 0.0});
    const CameraFlight descent(kEarth, orbit, Geodetic3D::fromDegrees(30.0, 10.0, 1e4), {0.0, -0.5, 0.0}, 5.0);
    CHECK(descent.arcHeight() == 0.0);
    double previous = 2e7 + 1.0;
    for (double t = 0.0; t <= 5.0; t += 0.1) {
        const double height = descent.positionAt(t).height;
        CHECK(height < previous); // straight down the heights
        previous = height;
    }
}

TEST_CASE("A camera flight crosses the antimeridian and a pole the short way, turning smoothly", "[scene][camera]")
{
    SECTION("antimeridian")
    {
        const Camera start = viewFrom(Geodetic3D::fromDegrees(175.0, -10.0, 1e5), {kHalfPi, -0.4, 0.0});
        const CameraFlight flight(kEarth, start, Geodetic3D::fromDegrees(-175.0, -12.0, 1e5), {kHalfPi, -0.4, 0.0},
                                  3.0);
        for (double t = 0.0; t <= 3.0; t += 0.01) {
            CHECK(std::abs(flight.positionAt(t).longitude) >= toRadians(175.0) - 1e-9); // never via 0
        }
    }
    SECTION("over the north pole, and to the antipode")
    {
        // Looking along the way from 80 N 0 E to 80 N 180 E: over the pole, still looking ahead.
        const Camera start = viewFrom(Geodetic3D::fromDegrees(0.0, 80.0, 1e6), {0.0, -0.3, 0.0});
        const Geodetic3D destination = Geodetic3D::fromDegrees(180.0, 80.0, 1e6);
        const HeadingPitchRoll ahead{kPi, -0.3, 0.0}; // south, on the far side of the pole
        const Geodetic3D antipode = Geodetic3D::fromDegrees(180.0, -80.0, 1e6); // any great circle will do
        for (const Geodetic3D& to : {destination, antipode}) {
            const HeadingPitchRoll orientation = ahead;
            const CameraFlight flight(kEarth, start, to, orientation, 10.0);
            Camera camera = start;
            Camera previous = start;
            double highestLatitude = -kHalfPi;
            constexpr int kSteps = 2000;
            for (int i = 0; i <= kSteps; ++i) {
                flight.apply(10.0 * i / kSteps, camera);
                REQUIRE(isFinite(camera.eye()));
                REQUIRE(isFinite(camera.right()));
                highestLatitude = std::max(highestLatitude, kEarth.toGeodetic3D(camera.eye()).latitude);
                // No spin where the local frame turns round the pole: the view moves a little each step.
                CHECK(angleBetween(camera.direction(), previous.direction()) < 0.01);
                CHECK(angleBetween(camera.up(), previous.up()) < 0.01);
                previous = camera;
            }
            if (to == destination) {
                CHECK(highestLatitude > toRadians(89.99));
            }
            CHECK(angleBetween(camera.direction(), viewFrom(to, orientation).direction()) < 1e-9);
        }
    }
}

TEST_CASE("A camera flight with no time, no distance or NaN time is finite and there at once", "[scene][camera]")
{
    const Geodetic3D here = Geodetic3D::fromDegrees(-180.0, 90.0, 500.0);
    const Camera start = viewFrom(here, {0.0, -kHalfPi, 0.0});
    for (const double seconds : {0.0, -1.0, std::nan("")}) {
        const CameraFlight flight(kEarth, start, Geodetic3D::fromDegrees(10.0, 10.0, 10.0), {}, seconds);
        Camera camera;
        flight.apply(0.0, camera);
        CHECK(glm::distance(camera.eye(), kEarth.toCartesian(Geodetic3D::fromDegrees(10.0, 10.0, 10.0))) < 1e-6);
    }
    const CameraFlight stay(kEarth, start, here, {1.0, -0.2, 0.3}, 4.0);
    CHECK(stay.arcHeight() == 0.0);
    Camera camera;
    for (const double t : {0.0, 1.0, 2.0, std::nan(""), 4.0}) {
        stay.apply(t, camera);
        REQUIRE(isFinite(camera.eye()));
        REQUIRE(isFinite(camera.right()));
        CHECK(glm::distance(camera.eye(), start.eye()) < 1e-6);
    }
}
