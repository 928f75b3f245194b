#include <orbis/scene/Camera.h>

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Math.h>
#include <orbis/world/SceneDescription.h>

#include <glm/geometric.hpp>

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
