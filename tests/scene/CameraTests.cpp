#include <orbis/scene/Camera.h>

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Math.h>
#include <orbis/world/SceneDescription.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::scene;
using Catch::Matchers::WithinAbs;

namespace {

// Angles go through degrees-to-radians once; a few ulps of pi/180 is all they can be off.
constexpr double kAngleTolerance = 1e-15;

} // namespace

TEST_CASE("makeCamera looks at the target, or along heading and pitch", "[scene][camera]")
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    CameraDescription description;
    description.position = Geodetic3D::fromDegrees(10.0, 50.0, 1e6);
    description.aim = Geodetic3D::fromDegrees(10.0, 50.0, 0.0);
    const Camera down = makeCamera(description, earth);
    const glm::dvec3 normal = earth.geodeticSurfaceNormal(description.position);
    REQUIRE_THAT(glm::dot(down.direction(), -normal), WithinAbs(1.0, 1e-12));
    // Looking straight down, up is north: perpendicular to the view and pointing to the pole.
    REQUIRE_THAT(glm::dot(down.up(), down.direction()), WithinAbs(0.0, 1e-12));
    REQUIRE(down.up().z > 0.5);
    REQUIRE_THAT(down.fieldOfViewY(), WithinAbs(toRadians(45.0), kAngleTolerance));

    description.aim = HeadingPitchRoll{0.0, -kHalfPi, 0.0};
    REQUIRE_THAT(glm::dot(makeCamera(description, earth).direction(), -normal), WithinAbs(1.0, 1e-12));
    description.aim = HeadingPitchRoll{0.0, 0.0, 0.0}; // level, facing north
    const Camera level = makeCamera(description, earth);
    REQUIRE_THAT(glm::dot(level.direction(), normal), WithinAbs(0.0, 1e-12));
    REQUIRE(level.direction().z > 0.5);
}

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

/// Positions that break naive formulas: the poles, the antimeridian from both sides, the equator,
/// the ground and orbit.
std::vector<Geodetic3D> awkwardPositions()
{
    std::vector<Geodetic3D> positions;
    for (const double longitude : {-180.0, -179.999, 0.0, 45.0, 179.999, 180.0}) {
        for (const double latitude : {-90.0, -89.9999, -30.0, 0.0, 60.0, 90.0}) {
            for (const double height : {2.0, 1e6, 3.6e7}) {
                positions.push_back(Geodetic3D::fromDegrees(longitude, latitude, height));
            }
        }
    }
    return positions;
}

bool isFinite(const Camera& camera)
{
    return orbis::isFinite(camera.eye()) && orbis::isFinite(camera.direction()) && orbis::isFinite(camera.right()) &&
           orbis::isFinite(camera.up());
}

} // namespace

TEST_CASE("setView points the camera along heading, pitch and roll in the local frame", "[scene][camera]")
{
    Camera camera;
    // At 0 N 0 E east is +y, north +z and up +x.
    camera.setView(kEarth, Geodetic3D::fromDegrees(0.0, 0.0, 1000.0), {toRadians(90.0), 0.0, 0.0});
    REQUIRE(glm::distance(camera.eye(), glm::dvec3(kEarth.radii().x + 1000.0, 0.0, 0.0)) < 1e-6);
    REQUIRE(glm::distance(camera.direction(), glm::dvec3(0.0, 1.0, 0.0)) < 1e-12);
    REQUIRE(glm::distance(camera.up(), glm::dvec3(1.0, 0.0, 0.0)) < 1e-12);
    camera.setView(kEarth, Geodetic3D::fromDegrees(0.0, 0.0, 1000.0), {0.0, -kHalfPi, 0.0});
    REQUIRE(glm::distance(camera.direction(), glm::dvec3(-1.0, 0.0, 0.0)) < 1e-12);
    REQUIRE(glm::distance(camera.up(), glm::dvec3(0.0, 0.0, 1.0)) < 1e-12); // north at the top
    // Rolled 90 degrees clockwise, looking north: up turns to the east.
    camera.setView(kEarth, Geodetic3D::fromDegrees(0.0, 0.0, 1000.0), {0.0, 0.0, kHalfPi});
    REQUIRE(glm::distance(camera.direction(), glm::dvec3(0.0, 0.0, 1.0)) < 1e-12);
    REQUIRE(glm::distance(camera.up(), glm::dvec3(0.0, 1.0, 0.0)) < 1e-12);
}

TEST_CASE("headingPitchRoll reads back what setView set, at the poles and the antimeridian too", "[scene][camera]")
{
    const HeadingPitchRoll orientations[] = {{0.0, 0.0, 0.0},
                                             {toRadians(135.0), toRadians(-30.0), toRadians(10.0)},
                                             {toRadians(-170.0), toRadians(80.0), toRadians(-175.0)},
                                             {toRadians(30.0), -kHalfPi, 0.0},
                                             {toRadians(-60.0), kHalfPi, toRadians(20.0)}};
    for (const Geodetic3D& position : awkwardPositions()) {
        for (const HeadingPitchRoll& orientation : orientations) {
            Camera camera;
            camera.setView(kEarth, position, orientation);
            REQUIRE(isFinite(camera));
            const HeadingPitchRoll back = camera.headingPitchRoll(kEarth);
            const bool vertical = std::abs(orientation.pitch) == kHalfPi;
            if (!vertical) {
                CHECK_THAT(std::remainder(back.heading - orientation.heading, kTwoPi), WithinAbs(0.0, 1e-9));
                CHECK_THAT(back.pitch, WithinAbs(orientation.pitch, 1e-9));
                CHECK_THAT(std::remainder(back.roll - orientation.roll, kTwoPi), WithinAbs(0.0, 1e-9));
            } else {
                CHECK(back.heading == 0.0); // the roll carries the turn instead
            }
            // Either way, what it reads back is the same view.
            Camera again;
            again.setView(kEarth, position, back);
            CHECK(glm::distance(again.direction(), camera.direction()) < 1e-9);
            CHECK(glm::distance(again.up(), camera.up()) < 1e-9);
        }
    }
}

TEST_CASE("lookAt with heading, pitch and range puts the target that far ahead", "[scene][camera]")
{
    const glm::dvec3 target = kEarth.toCartesian(Geodetic3D::fromDegrees(0.0, 0.0, 0.0));
    Camera camera;
    camera.lookAt(kEarth, target, 0.0, toRadians(-45.0), 1000.0);
    REQUIRE_THAT(glm::distance(camera.eye(), target), WithinAbs(1000.0, 1e-6));
    REQUIRE_THAT(glm::dot(glm::normalize(target - camera.eye()), camera.direction()), WithinAbs(1.0, 1e-12));
    // Looking north and down at 45 degrees: the eye is south of the target, 707 m up.
    const Geodetic3D eye = kEarth.toGeodetic3D(camera.eye());
    REQUIRE(eye.latitude < 0.0);
    REQUIRE_THAT(eye.height, WithinAbs(1000.0 / std::sqrt(2.0), 0.1));
    REQUIRE_THAT(camera.headingPitchRoll(kEarth).roll, WithinAbs(0.0, 1e-9));

    for (const Geodetic3D& position : awkwardPositions()) {
        const glm::dvec3 point = kEarth.toCartesian(position);
        for (const double range : {0.0, 1.0, 5e6}) {
            for (const double pitch : {-kHalfPi, toRadians(-20.0), 0.0, kHalfPi}) {
                camera.lookAt(kEarth, point, toRadians(100.0), pitch, range);
                REQUIRE(isFinite(camera));
                CHECK_THAT(glm::distance(camera.eye(), point), WithinAbs(range, 1e-6));
                if (range > 0.0) {
                    CHECK_THAT(glm::dot(glm::normalize(point - camera.eye()), camera.direction()),
                               WithinAbs(1.0, 1e-12));
                }
            }
        }
    }
}

TEST_CASE("pickRay and worldToWindow invert each other and agree with the projection matrix", "[scene][camera]")
{
    constexpr int kWidth = 800;
    constexpr int kHeight = 500;
    Camera camera;
    camera.setFieldOfViewY(toRadians(50.0));
    camera.setView(kEarth, Geodetic3D::fromDegrees(179.99, 89.5, 30000.0), {toRadians(20.0), toRadians(-35.0), 0.2});
    // The centre of the window is the view direction.
    REQUIRE(glm::distance(camera.pickRay({kWidth / 2.0, kHeight / 2.0}, kWidth, kHeight).direction,
                          camera.direction()) < 1e-15);
    // The top edge's centre is half the field of view up.
    const Ray top = camera.pickRay({kWidth / 2.0, 0.0}, kWidth, kHeight);
    REQUIRE_THAT(std::acos(glm::dot(top.direction, camera.direction())), WithinAbs(toRadians(25.0), 1e-12));
    REQUIRE(glm::dot(top.direction, camera.up()) > 0.0);

    const glm::dmat4 viewProjection = camera.projectionMatrix(double(kWidth) / kHeight, 1.0, 1e7) * camera.viewMatrix();
    for (const glm::dvec2 pixel : {glm::dvec2(0.5, 0.5), glm::dvec2(799.5, 0.5), glm::dvec2(12.25, 480.0),
                                   glm::dvec2(400.0, 250.0), glm::dvec2(-100.0, 900.0)}) {
        const Ray ray = camera.pickRay(pixel, kWidth, kHeight);
        REQUIRE_THAT(glm::length(ray.direction), WithinAbs(1.0, 1e-15));
        REQUIRE(ray.origin == camera.eye());
        const glm::dvec3 point = ray.pointAt(20000.0);
        const std::optional<glm::dvec2> back = camera.worldToWindow(point, kWidth, kHeight);
        REQUIRE(back);
        CHECK(glm::distance(*back, pixel) < 1e-6);
        // The GL projection counts y up from the bottom.
        const glm::dvec2 gl = clipToWindow(viewProjection * glm::dvec4(point, 1.0), kWidth, kHeight);
        CHECK(glm::distance(glm::dvec2(gl.x, kHeight - gl.y), pixel) < 1e-6);
    }
    // Behind the eye, and in its plane, there is no window position.
    CHECK_FALSE(camera.worldToWindow(camera.eye() - camera.direction() * 10.0, kWidth, kHeight));
    CHECK_FALSE(camera.worldToWindow(camera.eye() + camera.right() * 10.0, kWidth, kHeight));
}

TEST_CASE("pickEllipsoid finds the ground under a pixel, and nothing in the sky", "[scene][camera]")
{
    constexpr int kSize = 600;
    const glm::dvec2 centre(kSize / 2.0, kSize / 2.0);
    Camera camera;
    for (const Geodetic3D& position : awkwardPositions()) {
        camera.setView(kEarth, position, {0.3, -kHalfPi, 0.0}); // straight down
        const std::optional<glm::dvec3> ground = camera.pickEllipsoid(centre, kSize, kSize, kEarth);
        REQUIRE(ground);
        // Straight down along the normal meets the surface at the point below.
        const Geodetic3D below{position.longitude, position.latitude, 0.0};
        CHECK(glm::distance(*ground, kEarth.toCartesian(below)) < 1e-6);
        // Off-centre pixels: the point lies on the surface and shows at that pixel.
        for (const glm::dvec2 pixel : {glm::dvec2(10.5, 20.5), glm::dvec2(590.0, 300.0)}) {
            if (const std::optional<glm::dvec3> hit = camera.pickEllipsoid(pixel, kSize, kSize, kEarth)) {
                CHECK_THAT(kEarth.toGeodetic3D(*hit).height, WithinAbs(0.0, 1e-6));
                const std::optional<glm::dvec2> shown = camera.worldToWindow(*hit, kSize, kSize);
                REQUIRE(shown);
                CHECK(glm::distance(*shown, pixel) < 1e-6);
            } else {
                CHECK(position.height > 1e7); // only orbit sees past the Earth's edge with a 45-degree view
            }
        }
    }
    // Looking level from 2 m, the top half of the window is sky.
    camera.setView(kEarth, Geodetic3D::fromDegrees(10.0, 20.0, 2.0), {0.0, 0.0, 0.0});
    CHECK_FALSE(camera.pickEllipsoid({300.0, 100.0}, kSize, kSize, kEarth));
    const std::optional<glm::dvec3> road = camera.pickEllipsoid({300.0, 500.0}, kSize, kSize, kEarth);
    REQUIRE(road);
    CHECK(glm::distance(*road, camera.eye()) < 100.0);
    // From inside the Earth nothing is picked.
    camera.setView(kEarth, Geodetic3D::fromDegrees(10.0, 20.0, -100.0), {0.0, -kHalfPi, 0.0});
    CHECK_FALSE(camera.pickEllipsoid(centre, kSize, kSize, kEarth));
}
