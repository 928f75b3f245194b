#include <orbis/core/GeodeticExtent.h>

#include <catch2/catch.hpp>

using namespace orbis;
using Catch::Matchers::WithinAbs;

namespace {

bool contains(const GeodeticExtent& e, double longitudeDegrees, double latitudeDegrees)
{
    return e.contains(Geodetic2D::fromDegrees(longitudeDegrees, latitudeDegrees));
}

} // namespace

// Angles are compared to 1e-15 rad: the rounding of a degrees-to-radians conversion and a sum.

TEST_CASE("GeodeticExtent width, height, centre and contains for an ordinary extent", "[core][geometry][extent]")
{
    const GeodeticExtent e = GeodeticExtent::fromDegrees(10.0, -20.0, 30.0, 40.0);
    REQUIRE(e.west == toRadians(10.0));
    REQUIRE(e.north == toRadians(40.0));
    REQUIRE_THAT(e.width(), WithinAbs(toRadians(20.0), 1e-15));
    REQUIRE_THAT(e.height(), WithinAbs(toRadians(60.0), 1e-15));
    REQUIRE_THAT(e.centre().longitude, WithinAbs(toRadians(20.0), 1e-15));
    REQUIRE_THAT(e.centre().latitude, WithinAbs(toRadians(10.0), 1e-15));
    REQUIRE(contains(e, 20.0, 0.0));
    REQUIRE(contains(e, 10.0, -20.0)); // corners are inside
    REQUIRE(contains(e, 30.0, 40.0));
    REQUIRE_FALSE(contains(e, 9.0, 0.0));
    REQUIRE_FALSE(contains(e, 31.0, 0.0));
    REQUIRE_FALSE(contains(e, 20.0, 41.0));
    REQUIRE_FALSE(contains(e, 20.0, -21.0));
    REQUIRE(contains(e, 380.0, 0.0)); // longitudes wrap
    REQUIRE(contains(e, -340.0, 0.0));
    REQUIRE_FALSE(contains(e, 200.0, 0.0));
    REQUIRE_FALSE(e.contains({std::numeric_limits<double>::infinity(), 0.0}));
    REQUIRE_FALSE(e.contains({std::numeric_limits<double>::quiet_NaN(), 0.0}));
}

TEST_CASE("GeodeticExtent across the antimeridian (east < west)", "[core][geometry][extent][hard]")
{
    const GeodeticExtent e = GeodeticExtent::fromDegrees(170.0, -10.0, -170.0, 10.0);
    REQUIRE_THAT(e.width(), WithinAbs(toRadians(20.0), 1e-14));
    REQUIRE_THAT(std::abs(e.centre().longitude), WithinAbs(kPi, 1e-14));
    REQUIRE(e.centre().longitude > 0.0); // in (-pi, pi]
    REQUIRE(contains(e, 175.0, 0.0));
    REQUIRE(contains(e, -175.0, 0.0));
    REQUIRE(contains(e, 180.0, 0.0));
    REQUIRE(contains(e, -180.0, 5.0));
    REQUIRE(contains(e, 170.0, 10.0));
    REQUIRE(contains(e, -170.0, -10.0));
    REQUIRE_FALSE(contains(e, 0.0, 0.0));
    REQUIRE_FALSE(contains(e, 169.0, 0.0));
    REQUIRE_FALSE(contains(e, -169.0, 0.0));
    REQUIRE_FALSE(contains(e, 180.0, 11.0));

    // Off-centre: 150 E to 170 W is 40 degrees wide, centred on 170 E.
    const GeodeticExtent f = GeodeticExtent::fromDegrees(150.0, 0.0, -170.0, 1.0);
    REQUIRE_THAT(f.width(), WithinAbs(toRadians(40.0), 1e-14));
    REQUIRE_THAT(f.centre().longitude, WithinAbs(toRadians(170.0), 1e-14));
    // And 170 E to 150 W centres on 170 W.
    const GeodeticExtent g = GeodeticExtent::fromDegrees(170.0, 0.0, -150.0, 1.0);
    REQUIRE_THAT(g.centre().longitude, WithinAbs(toRadians(-170.0), 1e-14));

    // An extent ending on the antimeridian contains both names of it.
    const GeodeticExtent east = GeodeticExtent::fromDegrees(170.0, 0.0, 180.0, 1.0);
    REQUIRE_THAT(east.width(), WithinAbs(toRadians(10.0), 1e-14));
    REQUIRE(contains(east, 180.0, 0.5));
    REQUIRE(contains(east, -180.0, 0.5));
    const GeodeticExtent west = GeodeticExtent::fromDegrees(-180.0, 0.0, -170.0, 1.0);
    REQUIRE(contains(west, 180.0, 0.5));
    REQUIRE_FALSE(contains(west, 179.0, 0.5));
}

TEST_CASE("GeodeticExtent at the poles and for the whole globe", "[core][geometry][extent][hard]")
{
    // A pole is one point: every longitude of it is inside an extent that reaches it.
    const GeodeticExtent cap = GeodeticExtent::fromDegrees(0.0, 80.0, 10.0, 90.0);
    REQUIRE(contains(cap, 5.0, 90.0));
    REQUIRE(contains(cap, 120.0, 90.0));
    REQUIRE(contains(cap, -180.0, 90.0));
    REQUIRE_FALSE(contains(cap, 120.0, 89.0));
    REQUIRE_FALSE(contains(cap, 5.0, -90.0));
    const GeodeticExtent south = GeodeticExtent::fromDegrees(-10.0, -90.0, 10.0, -60.0);
    REQUIRE(contains(south, 100.0, -90.0));
    REQUIRE_THAT(south.height(), WithinAbs(toRadians(30.0), 1e-15));

    const GeodeticExtent globe = GeodeticExtent::maximum();
    REQUIRE(globe.width() == kTwoPi);
    REQUIRE(globe.height() == kPi);
    REQUIRE(globe.centre() == Geodetic2D{0.0, 0.0});
    for (double longitude : {-180.0, -179.999, 0.0, 179.999, 180.0, 540.0}) {
        for (double latitude : {-90.0, -45.0, 0.0, 89.99, 90.0}) {
            REQUIRE(contains(globe, longitude, latitude));
        }
    }
    // A single meridian (west == east) is zero wide and contains only itself.
    const GeodeticExtent meridian = GeodeticExtent::fromDegrees(30.0, -10.0, 30.0, 10.0);
    REQUIRE(meridian.width() == 0.0);
    REQUIRE(contains(meridian, 30.0, 0.0));
    REQUIRE_FALSE(contains(meridian, 30.001, 0.0));
}

TEST_CASE("GeodeticExtent intersects: boundaries, the antimeridian and the poles", "[core][geometry][extent][hard]")
{
    const GeodeticExtent a = GeodeticExtent::fromDegrees(10.0, 20.0, 30.0, 40.0);
    CHECK(a.intersects(a));
    CHECK(a.intersects(GeodeticExtent::fromDegrees(25.0, 35.0, 50.0, 60.0)));
    CHECK(a.intersects(GeodeticExtent::fromDegrees(15.0, 25.0, 20.0, 30.0))); // inside
    CHECK(a.intersects(GeodeticExtent::fromDegrees(0.0, 0.0, 50.0, 60.0)));   // around it
    CHECK(a.intersects(GeodeticExtent::fromDegrees(30.0, 40.0, 31.0, 41.0))); // a shared corner
    CHECK_FALSE(a.intersects(GeodeticExtent::fromDegrees(30.001, 20.0, 40.0, 40.0)));
    CHECK_FALSE(a.intersects(GeodeticExtent::fromDegrees(10.0, 40.001, 30.0, 50.0)));
    CHECK(a.intersects(GeodeticExtent::maximum()));

    // Across the antimeridian, from either side and from both.
    const GeodeticExtent across = GeodeticExtent::fromDegrees(170.0, -10.0, -170.0, 10.0);
    CHECK(across.intersects(GeodeticExtent::fromDegrees(175.0, 0.0, 180.0, 5.0)));
    CHECK(across.intersects(GeodeticExtent::fromDegrees(-180.0, 0.0, -175.0, 5.0)));
    CHECK(across.intersects(GeodeticExtent::fromDegrees(-175.0, -5.0, 175.0, 5.0))); // nearly the whole globe
    CHECK(across.intersects(GeodeticExtent::fromDegrees(179.0, 0.0, -179.0, 1.0)));
    CHECK_FALSE(across.intersects(GeodeticExtent::fromDegrees(-169.0, 0.0, 169.0, 5.0)));
    CHECK_FALSE(across.intersects(a));
    // -180 and 180 are one meridian.
    CHECK(GeodeticExtent::fromDegrees(170.0, 0.0, 180.0, 5.0).intersects(GeodeticExtent::fromDegrees(-180.0, 0.0, -170.0, 5.0)));

    // Two extents reaching a pole share it, whatever their longitudes.
    CHECK(GeodeticExtent::fromDegrees(0.0, 80.0, 10.0, 90.0).intersects(GeodeticExtent::fromDegrees(100.0, 85.0, 110.0, 90.0)));
    CHECK(GeodeticExtent::fromDegrees(0.0, -90.0, 10.0, -80.0).intersects(GeodeticExtent::fromDegrees(-100.0, -90.0, -90.0, -85.0)));
    CHECK_FALSE(GeodeticExtent::fromDegrees(0.0, 80.0, 10.0, 89.0).intersects(GeodeticExtent::fromDegrees(100.0, 85.0, 110.0, 90.0)));
}
