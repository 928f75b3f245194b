#include <orbis/core/EllipsoidTangentPlane.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace orbis;
using Catch::Matchers::WithinAbs;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

void requireOrthonormalFrame(const EllipsoidTangentPlane& plane)
{
    // Unit and orthogonal to 1e-15 (a few units in the last place).
    REQUIRE_THAT(glm::length(plane.xAxis()), WithinAbs(1.0, 1e-15));
    REQUIRE_THAT(glm::length(plane.yAxis()), WithinAbs(1.0, 1e-15));
    REQUIRE_THAT(glm::length(plane.normal()), WithinAbs(1.0, 1e-15));
    REQUIRE_THAT(glm::dot(plane.xAxis(), plane.yAxis()), WithinAbs(0.0, 1e-15));
    REQUIRE_THAT(glm::dot(plane.xAxis(), plane.normal()), WithinAbs(0.0, 1e-15));
    REQUIRE_THAT(glm::length(glm::cross(plane.xAxis(), plane.yAxis()) - plane.normal()), WithinAbs(0.0, 1e-15));
}

} // namespace

TEST_CASE("EllipsoidTangentPlane sits at the centre of the positions with east, north and up axes", "[polygon][tangent-plane]")
{
    const Geodetic2D centre = Geodetic2D::fromDegrees(30.0, 45.0);
    // Positions symmetric about the centre in the plane tangent there: their bounding box is
    // centred on the centre itself.
    const glm::dvec3 c = kEarth.toCartesian(centre);
    const glm::dvec3 n = Ellipsoid::geodeticSurfaceNormal(centre);
    const glm::dvec3 east(-std::sin(centre.longitude), std::cos(centre.longitude), 0.0);
    const glm::dvec3 north = glm::cross(n, east);
    const std::vector<glm::dvec3> positions = {c + 1000.0 * east, c - 1000.0 * east, c + 1000.0 * north,
                                               c - 1000.0 * north};
    const EllipsoidTangentPlane plane(kEarth, positions);
    requireOrthonormalFrame(plane);
    REQUIRE(glm::length(plane.origin() - c) < 1e-6); // the box centre is c to rounding (micrometres)
    REQUIRE(glm::length(plane.normal() - n) < 1e-12);
    REQUIRE(glm::length(plane.xAxis() - east) < 1e-12);
    REQUIRE(glm::length(plane.yAxis() - north) < 1e-12);
    REQUIRE(plane.ellipsoid() == kEarth);
}

TEST_CASE("EllipsoidTangentPlane has a documented frame at the poles and for no positions", "[polygon][tangent-plane]")
{
    const EllipsoidTangentPlane none(kEarth, std::span<const glm::dvec3>());
    REQUIRE(none.origin() == glm::dvec3(0.0, 0.0, kEarth.radii().z));
    requireOrthonormalFrame(none);
    REQUIRE(none.xAxis() == glm::dvec3(0.0, 1.0, 0.0));

    const EllipsoidTangentPlane centre(kEarth, glm::dvec3(0.0));
    REQUIRE(centre.origin() == glm::dvec3(0.0, 0.0, kEarth.radii().z));

    const EllipsoidTangentPlane south(kEarth, glm::dvec3(0.0, 0.0, -7e6));
    requireOrthonormalFrame(south);
    REQUIRE_THAT(south.origin().z, WithinAbs(-kEarth.radii().z, 1e-6));
    REQUIRE(south.normal() == glm::dvec3(0.0, 0.0, -1.0));
    REQUIRE(south.xAxis() == glm::dvec3(0.0, 1.0, 0.0));
}

TEST_CASE("EllipsoidTangentPlane projects to the plane and back to the same position", "[polygon][tangent-plane]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const Geodetic2D at{kPi * (2.0 * unit(random) - 1.0), std::asin(2.0 * unit(random) - 1.0)};
        const EllipsoidTangentPlane plane(kEarth, kEarth.toCartesian(at));
        // A position up to 85 degrees away, in any direction.
        const double distance = toRadians(85.0) * unit(random);
        const double azimuth = kTwoPi * unit(random);
        const glm::dvec3 direction = std::cos(distance) * plane.normal() +
                                     std::sin(distance) * (std::cos(azimuth) * plane.xAxis() + std::sin(azimuth) * plane.yAxis());
        const glm::dvec3 p = kEarth.scaleToGeocentricSurface(direction);
        const std::optional<glm::dvec2> q = plane.projectPointOntoPlane(p);
        REQUIRE(q);
        // The projected point is on the plane and on the ray through p.
        const glm::dvec3 onPlane = plane.planeToWorld(*q);
        REQUIRE(glm::length(glm::cross(glm::normalize(onPlane), glm::normalize(p))) < 1e-14);
        // Round trip within 10 nm: the plane point is up to 11 Earth radii out at 85 degrees, where
        // rounding is a few nanometres.
        REQUIRE(glm::length(plane.projectPointOntoEllipsoid(*q) - p) < 1e-8);
    }
}

TEST_CASE("EllipsoidTangentPlane maps the curves cut by planes through the centre to straight lines", "[polygon][tangent-plane]")
{
    const glm::dvec3 a = kEarth.toCartesian(Geodetic2D::fromDegrees(-20.0, 10.0));
    const glm::dvec3 b = kEarth.toCartesian(Geodetic2D::fromDegrees(40.0, 60.0));
    const std::vector<glm::dvec3> ends = {a, b};
    const EllipsoidTangentPlane plane(kEarth, ends);
    const glm::dvec2 qa = *plane.projectPointOntoPlane(a);
    const glm::dvec2 qb = *plane.projectPointOntoPlane(b);
    const glm::dvec2 along = glm::normalize(qb - qa);
    for (const glm::dvec3& p : kEarth.computeCurve(a, b, toRadians(1.0))) {
        const glm::dvec2 q = *plane.projectPointOntoPlane(p);
        // Distance from the line through qa and qb: rounding only (micrometres over 7000 km).
        const glm::dvec2 d = q - qa;
        REQUIRE(std::abs(d.x * along.y - d.y * along.x) < 1e-6);
    }
}

TEST_CASE("EllipsoidTangentPlane cannot project points on or beyond its horizon", "[polygon][tangent-plane]")
{
    const EllipsoidTangentPlane plane(kEarth, kEarth.toCartesian(Geodetic2D::fromDegrees(10.0, 20.0)));
    REQUIRE_FALSE(plane.projectPointOntoPlane(-plane.origin()));  // the antipode
    REQUIRE_FALSE(plane.projectPointOntoPlane(glm::dvec3(0.0)));  // the centre
    REQUIRE_THAT(plane.cosineFromNormal(plane.origin()), WithinAbs(1.0, 1e-5)); // geodetic vs geocentric
    REQUIRE(plane.cosineFromNormal(glm::dvec3(0.0)) == 0.0);

    // At the north pole the normal is +z exactly, so the horizon can be hit exactly.
    const EllipsoidTangentPlane pole(kEarth, glm::dvec3(0.0, 0.0, 1.0));
    REQUIRE_FALSE(pole.projectPointOntoPlane(glm::dvec3(1e7, 0.0, 0.0)));    // on the horizon
    REQUIRE_FALSE(pole.projectPointOntoPlane(glm::dvec3(1e7, 0.0, -1.0)));   // beyond it
    REQUIRE_FALSE(pole.projectPointOntoPlane(glm::dvec3(1e7, 0.0, 1e-300))); // before it, but out of range
    const std::optional<glm::dvec2> low = pole.projectPointOntoPlane(glm::dvec3(1e7, 0.0, 1e3));
    REQUIRE(low);
    REQUIRE_THAT(low->y, WithinAbs(-1e7 * kEarth.radii().z / 1e3, 1e-3)); // north of the pole is -x

    const std::vector<glm::dvec3> some = {plane.origin(), -plane.origin()};
    REQUIRE_FALSE(plane.projectPointsOntoPlane(some));
    const std::vector<glm::dvec3> near = {plane.origin(), plane.origin() + 1000.0 * plane.xAxis()};
    const auto projected = plane.projectPointsOntoPlane(near);
    REQUIRE(projected);
    REQUIRE(projected->size() == 2);
    REQUIRE(glm::length((*projected)[0]) < 1e-6);
}
