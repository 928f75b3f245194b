#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace orbis;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {
const Ellipsoid kEarth = Ellipsoid::wgs84();

bool near(const glm::dvec3& a, const glm::dvec3& b, double tolerance)
{
    return glm::length(a - b) <= tolerance;
}
} // namespace

TEST_CASE("East-north-up axes are orthonormal and point the right way", "[core][transforms]")
{
    const glm::dmat3 atOrigin = eastNorthUpAxes(kEarth, kEarth.toCartesian(Geodetic2D::fromDegrees(0, 0)));
    REQUIRE(near(atOrigin[0], {0, 1, 0}, 1e-15));
    REQUIRE(near(atOrigin[1], {0, 0, 1}, 1e-15));
    REQUIRE(near(atOrigin[2], {1, 0, 0}, 1e-15));

    for (const double latitude : {-89.0, -45.0, 0.0, 30.0, 89.999999}) {
        for (const double longitude : {-180.0, -90.0, 0.0, 135.0, 180.0}) {
            const glm::dvec3 p = kEarth.toCartesian(Geodetic2D::fromDegrees(longitude, latitude));
            const glm::dmat3 enu = eastNorthUpAxes(kEarth, p);
            // Orthonormal and right-handed to rounding (1e-15 per component).
            REQUIRE_THAT(glm::dot(enu[0], enu[1]), WithinAbs(0.0, 1e-15));
            REQUIRE(glm::length(glm::cross(enu[0], enu[1]) - enu[2]) < 1e-15 * 4);
            // North increases latitude: a 1 cm step north (short of the pole, 11 cm from the last row) moves up.
            const double stepped = kEarth.toGeodetic2D(p + 0.01 * enu[1]).latitude;
            REQUIRE(stepped > toRadians(latitude));
        }
    }
}

TEST_CASE("East-north-up at the poles is finite and follows the prime meridian", "[core][transforms][hard]")
{
    for (const double z : {kEarth.radii().z, -kEarth.radii().z}) {
        const glm::dmat3 enu = eastNorthUpAxes(kEarth, {0.0, 0.0, z});
        REQUIRE(near(enu[0], {0, 1, 0}, 1e-15));
        REQUIRE(near(enu[2], {0, 0, z > 0 ? 1.0 : -1.0}, 1e-15));
        REQUIRE_THAT(glm::length(enu[1]), WithinRel(1.0, 1e-12));
    }
}

TEST_CASE("Heading, pitch and roll give the expected view directions", "[core][transforms]")
{
    const glm::dvec3 p = kEarth.toCartesian(Geodetic2D::fromDegrees(0, 0));
    const ViewOrientation north = headingPitchRollToView(kEarth, p, 0.0, 0.0, 0.0);
    REQUIRE(near(north.direction, {0, 0, 1}, 1e-15));
    REQUIRE(near(north.up, {1, 0, 0}, 1e-15));
    const ViewOrientation east = headingPitchRollToView(kEarth, p, kHalfPi, 0.0, 0.0);
    REQUIRE(near(east.direction, {0, 1, 0}, 1e-15));
    const ViewOrientation down = headingPitchRollToView(kEarth, p, 0.0, -kHalfPi, 0.0);
    REQUIRE(near(down.direction, {-1, 0, 0}, 1e-15));
    REQUIRE(near(down.up, {0, 0, 1}, 1e-15));
    const ViewOrientation rolled = headingPitchRollToView(kEarth, p, 0.0, 0.0, kHalfPi);
    REQUIRE(near(rolled.direction, {0, 0, 1}, 1e-15));
    REQUIRE(near(rolled.up, {0, 1, 0}, 1e-15)); // rolled right: up tips towards east
}

TEST_CASE("East-north-up above the surface uses the geodetic normal of the point below", "[core][transforms]")
{
    // 1,000 km up at 45 degrees, the gradient at the point itself leans by about 0.026 degrees.
    const Geodetic3D high = Geodetic3D::fromDegrees(30, 45, 1e6);
    const glm::dmat3 enu = eastNorthUpAxes(kEarth, kEarth.toCartesian(high));
    REQUIRE(near(enu[2], Ellipsoid::geodeticSurfaceNormal(high), 1e-15 * 4));
}

TEST_CASE("viewToHeadingPitch inverts headingPitchRollToView, and stays finite looking straight down or at the pole", "[core][transforms][hard]")
{
    std::mt19937_64 random(20261123);
    std::uniform_real_distribution<double> longitude(-180.0, 180.0);
    std::uniform_real_distribution<double> latitude(-90.0, 90.0);
    std::uniform_real_distribution<double> height(-1e4, 4e7);
    std::uniform_real_distribution<double> heading(-kPi + 1e-9, kPi);
    std::uniform_real_distribution<double> pitch(-kHalfPi + 1e-6, kHalfPi - 1e-6);
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 p = kEarth.toCartesian(Geodetic3D::fromDegrees(longitude(random), latitude(random), height(random)));
        const double h = heading(random);
        const double t = pitch(random);
        const HeadingPitch back = viewToHeadingPitch(kEarth, p, headingPitchRollToView(kEarth, p, h, t, 0.0).direction);
        // A few ulps of the angles; the heading is as good as cos(pitch) lets it be.
        REQUIRE_THAT(back.pitch, WithinAbs(t, 1e-14));
        REQUIRE_THAT(std::remainder(back.heading - h, kTwoPi), WithinAbs(0.0, 1e-14 / std::cos(t)));
    }
    for (const glm::dvec3 p : {kEarth.toCartesian(Geodetic2D::fromDegrees(0, 90)), glm::dvec3(0.0)}) {
        for (const glm::dvec3 direction : {glm::dvec3(0, 0, -1), glm::dvec3(0, 0, 1), glm::dvec3(0.0)}) {
            const HeadingPitch view = viewToHeadingPitch(kEarth, p, direction);
            REQUIRE(std::isfinite(view.heading));
            REQUIRE(std::isfinite(view.pitch));
        }
    }
    const HeadingPitch down = viewToHeadingPitch(kEarth, kEarth.toCartesian(Geodetic2D::fromDegrees(0, 90)), {0, 0, -1});
    REQUIRE(down.heading == 0.0);
    REQUIRE(down.pitch == -kHalfPi);
}
