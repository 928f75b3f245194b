#include <orbis/core/Ellipsoid.h>
#include <orbis/core/PolygonCleanup.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace orbis;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

using Indices = std::vector<std::size_t>;

std::vector<glm::dvec3> onEarth(const std::vector<glm::dvec2>& degrees)
{
    std::vector<glm::dvec3> positions;
    for (const glm::dvec2& p : degrees) {
        positions.push_back(kEarth.toCartesian(Geodetic2D::fromDegrees(p.x, p.y)));
    }
    return positions;
}

} // namespace

TEST_CASE("cleanRing drops consecutive duplicates, the closing one included", "[polygon][cleanup]")
{
    const std::vector<glm::dvec2> ring = {{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 1}, {0, 1}, {0, 0}};
    REQUIRE(cleanRing(ring) == Indices{0, 1, 3, 4});
    // A run that wraps around the end keeps the first vertex.
    const std::vector<glm::dvec2> wrapped = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {0, 0}};
    REQUIRE(cleanRing(wrapped) == Indices{0, 1, 2});
}

TEST_CASE("cleanRing drops collinear and near-collinear vertices and spikes", "[polygon][cleanup]")
{
    // (1, 0) and (2, 0) lie on the edge from (0, 0) to (3, 0); (3, 1.5) on the next.
    const std::vector<glm::dvec2> collinear = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1.5}, {3, 3}, {0, 3}};
    REQUIRE(cleanRing(collinear) == Indices{0, 3, 5, 6});

    // The tolerance is 1e-12 of the bounding box's diagonal (about 4.2e-12 here): a vertex 1e-12
    // off the line goes, one 1e-9 off stays.
    const std::vector<glm::dvec2> near = {{0, 0}, {1.5, 1e-12}, {3, 0}, {3, 3}, {0, 3}};
    REQUIRE(cleanRing(near) == Indices{0, 2, 3, 4});
    const std::vector<glm::dvec2> notNear = {{0, 0}, {1.5, 1e-9}, {3, 0}, {3, 3}, {0, 3}};
    REQUIRE(cleanRing(notNear) == Indices{0, 1, 2, 3, 4});
    REQUIRE(cleanRing(near, 0.0) == Indices{0, 1, 2, 3, 4});

    // A zero-width spike out to (5, 1) and back.
    const std::vector<glm::dvec2> spike = {{0, 0}, {3, 0}, {3, 1}, {5, 1}, {3, 1}, {3, 3}, {0, 3}};
    REQUIRE(cleanRing(spike) == Indices{0, 1, 5, 6});
}

TEST_CASE("cleanRing leaves fewer than 3 vertices for rings with no area", "[polygon][cleanup]")
{
    REQUIRE(cleanRing(std::vector<glm::dvec2>{}).empty());
    REQUIRE(cleanRing(std::vector<glm::dvec2>{{1, 1}, {1, 1}, {1, 1}, {1, 1}}) == Indices{0});
    REQUIRE(cleanRing(std::vector<glm::dvec2>{{0, 0}, {1, 1}, {2, 2}, {3, 3}, {0, 0}}).size() < 3);
    REQUIRE(cleanRing(std::vector<glm::dvec2>{{0, 0}, {1, 0}}).size() == 2);
}

TEST_CASE("signedArea and winding tell counter-clockwise from clockwise", "[polygon][cleanup]")
{
    const std::vector<glm::dvec2> ccw = {{1e7, 1e7}, {1e7 + 2, 1e7}, {1e7 + 2, 1e7 + 3}, {1e7, 1e7 + 3}};
    REQUIRE(signedArea(ccw) == 6.0); // exact: relative to the first vertex
    REQUIRE(winding(ccw) == Winding::CounterClockwise);
    std::vector<glm::dvec2> cw(ccw.rbegin(), ccw.rend());
    REQUIRE(signedArea(cw) == -6.0);
    REQUIRE(winding(cw) == Winding::Clockwise);
    // A closing duplicate changes nothing.
    cw.push_back(cw.front());
    REQUIRE(signedArea(cw) == -6.0);
    REQUIRE_FALSE(winding(std::vector<glm::dvec2>{{0, 0}, {1, 1}, {2, 2}}));
    REQUIRE_FALSE(winding(std::vector<glm::dvec2>{{0, 0}, {1, 1}}));

    // Fixing: an outer ring counter-clockwise, a hole clockwise.
    std::vector<glm::dvec2> outer = cw;
    REQUIRE(setWinding(outer, Winding::CounterClockwise));
    REQUIRE(winding(outer) == Winding::CounterClockwise);
    REQUIRE(outer.front() == cw.back());
    std::vector<glm::dvec2> hole = ccw;
    REQUIRE(setWinding(hole, Winding::Clockwise));
    REQUIRE(winding(hole) == Winding::Clockwise);
    REQUIRE(setWinding(hole, Winding::Clockwise));
    REQUIRE(winding(hole) == Winding::Clockwise); // already so: unchanged
    std::vector<glm::dvec2> flat = {{0, 0}, {1, 1}, {2, 2}};
    REQUIRE_FALSE(setWinding(flat, Winding::Clockwise));
}

TEST_CASE("cleanRing on the ellipsoid merges the two sides of the antimeridian and the pole's spike", "[polygon][cleanup]")
{
    // Fiji's ring in countries-110m goes from 180 to -180 at the same latitude, and repeats its
    // first vertex: both pairs are one position.
    const std::vector<glm::dvec3> fiji = onEarth({{-180, -16.0668824394954},
                                                  {-179.79479794797948, -16.02118335720543},
                                                  {-179.9171991719917, -16.50187000055172},
                                                  {-180, -16.556031875858352},
                                                  {179.3627936279363, -16.80145287334149},
                                                  {179.41319413194134, -16.37831322250848},
                                                  {180, -16.0668824394954},
                                                  {-180, -16.0668824394954}});
    REQUIRE(cleanRing(fiji) == Indices{0, 1, 2, 3, 4, 5});

    // A ring closed along the south pole as Natural Earth's shapefiles close Antarctica: down the
    // antimeridian to -90, across the pole (one point) and back up: a zero-width spike.
    const std::vector<glm::dvec3> polar = onEarth({{-180, -70}, {-90, -72}, {0, -75}, {90, -71}, {180, -70},
                                                   {180, -90}, {-180, -90}, {-180, -70}});
    REQUIRE(cleanRing(polar) == Indices{0, 1, 2, 3});
}

TEST_CASE("cleanRing on the ellipsoid drops vertices within its tolerance of their neighbours' edge", "[polygon][cleanup]")
{
    const glm::dvec3 a = kEarth.toCartesian(Geodetic2D::fromDegrees(10, 10));
    const glm::dvec3 c = kEarth.toCartesian(Geodetic2D::fromDegrees(20, 30));
    const glm::dvec3 far = kEarth.toCartesian(Geodetic2D::fromDegrees(30, 5));
    // The midpoint of the edge a-c (on the plane through the centre), moved sideways.
    const glm::dvec3 mid = kEarth.scaleToGeocentricSurface(0.5 * (a + c));
    const glm::dvec3 side = glm::normalize(glm::cross(a, c));
    for (const double offset : {0.0, 1e-3, 1.0}) {
        INFO("offset " << offset << " m");
        const std::vector<glm::dvec3> ring = {a, kEarth.scaleToGeocentricSurface(mid + offset * side), c, far};
        // The default tolerance, 1e-9 rad, is about 6 mm on the Earth: 1 mm goes, 1 m stays.
        REQUIRE(cleanRing(ring).size() == (offset < 0.5 ? 3u : 4u));
    }
    // Antipodal neighbours define no edge: the vertex between them stays.
    const std::vector<glm::dvec3> wide = {kEarth.toCartesian(Geodetic2D::fromDegrees(0, 0)),
                                          kEarth.toCartesian(Geodetic2D::fromDegrees(90, 0)),
                                          kEarth.toCartesian(Geodetic2D::fromDegrees(180, 0)),
                                          kEarth.toCartesian(Geodetic2D::fromDegrees(90, 80))};
    REQUIRE(cleanRing(wide).size() == 4);
}

TEST_CASE("leftSolidAngle and winding on the ellipsoid pick the smaller region", "[polygon][cleanup]")
{
    // A ring at latitude 60 north on the unit sphere, eastwards: counter-clockwise around the cap
    // seen from outside.
    std::vector<glm::dvec3> ring;
    for (int i = 0; i < 360; i += 10) {
        ring.push_back(Ellipsoid::geodeticSurfaceNormal(Geodetic2D::fromDegrees(i, 60.0)));
    }
    // The cap bounded by the chords' planes: a little less than the spherical cap 2 pi (1 - sin 60).
    const double cap = kTwoPi * (1.0 - std::sin(toRadians(60.0)));
    const double left = leftSolidAngle(ring);
    REQUIRE(left < cap);
    REQUIRE(left > 0.97 * cap);
    REQUIRE(winding(ring) == Winding::CounterClockwise);
    const std::vector<glm::dvec3> reversed(ring.rbegin(), ring.rend());
    REQUIRE_THAT(leftSolidAngle(reversed), WithinAbs(2.0 * kTwoPi - left, 1e-12));
    REQUIRE(winding(reversed) == Winding::Clockwise);

    // The equator bounds two equal halves: no smaller side.
    std::vector<glm::dvec2> equator;
    for (int i = 0; i < 360; i += 30) {
        equator.emplace_back(i, 0.0);
    }
    REQUIRE_THAT(leftSolidAngle(onEarth(equator)), WithinAbs(kTwoPi, 1e-12));
    REQUIRE_FALSE(winding(onEarth(equator)));
    std::vector<glm::dvec3> fixable = reversed;
    REQUIRE(setWinding(fixable, Winding::CounterClockwise));
    REQUIRE(winding(fixable) == Winding::CounterClockwise);
    std::vector<glm::dvec3> ambiguous = onEarth(equator);
    REQUIRE_FALSE(setWinding(ambiguous, Winding::CounterClockwise));
    REQUIRE(leftSolidAngle(std::vector<glm::dvec3>{}) == 0.0);

    // A small right triangle on the unit sphere (legs of 1.7e-7 rad, as 1 m on the Earth): its area
    // to rounding, 0.1% at that size.
    const std::vector<glm::dvec3> small = {Ellipsoid::geodeticSurfaceNormal(Geodetic2D::fromDegrees(0, 0)),
                                           Ellipsoid::geodeticSurfaceNormal(Geodetic2D::fromDegrees(1e-5, 0)),
                                           Ellipsoid::geodeticSurfaceNormal(Geodetic2D::fromDegrees(0, 1e-5))};
    REQUIRE(winding(small) == Winding::CounterClockwise);
    REQUIRE_THAT(leftSolidAngle(small), WithinRel(0.5 * toRadians(1e-5) * toRadians(1e-5), 1e-3));
}
