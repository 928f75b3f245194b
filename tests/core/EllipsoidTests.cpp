#include <orbis/core/Ellipsoid.h>

#include <GeographicLib/Geocentric.hpp>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace orbis;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

// The error bound the foundation issue sets for one conversion, against the exact answer (the
// accuracy report measures both directions against it in extended precision): 10 nm near the
// Earth plus 4e-16 of the distance from the centre (two units in the last place far out).
double bound(const glm::dvec3& p)
{
    return 10e-9 + 4e-16 * glm::length(p);
}

bool finite(const Geodetic3D& g)
{
    return std::isfinite(g.longitude) && std::isfinite(g.latitude) && std::isfinite(g.height);
}

void requireRoundTrip(const glm::dvec3& p)
{
    const Geodetic3D g = kEarth.toGeodetic3D(p);
    INFO("p = " << p.x << ", " << p.y << ", " << p.z);
    REQUIRE(finite(g));
    REQUIRE(g.latitude >= -kHalfPi);
    REQUIRE(g.latitude <= kHalfPi);
    REQUIRE(g.longitude >= -kPi);
    REQUIRE(g.longitude <= kPi);
    // A round trip is two conversions, each rounding within the bound: toCartesian(g) lies within
    // bound(p) of the exact position of g, which lies within bound(p) of p. One bound is not enough:
    // far out toCartesian alone errs by up to 3.4e-16 |p| (measured in extended precision), which
    // leaves toGeodetic3D almost no room (seed 526245 went over by 4.5 nm at 79,000 km).
    REQUIRE(glm::length(kEarth.toCartesian(g) - p) <= 2 * bound(p));
}

/// GeographicLib's answer for p, in radians.
Geodetic3D reference(const glm::dvec3& p)
{
    double latitude, longitude, height;
    GeographicLib::Geocentric::WGS84().Reverse(p.x, p.y, p.z, latitude, longitude, height);
    return {toRadians(longitude), toRadians(latitude), height};
}

} // namespace

TEST_CASE("Ellipsoid WGS84 has the defining radii", "[core][ellipsoid]")
{
    REQUIRE(kEarth.radii().x == 6378137.0);
    REQUIRE(kEarth.radii().y == 6378137.0);
    REQUIRE_THAT(kEarth.radii().z, WithinAbs(6356752.314245, 1e-6));
    REQUIRE(Ellipsoid::scaledWgs84().radii().x == 1.0);
    REQUIRE_THAT(Ellipsoid::scaledWgs84().radii().z * 6378137.0, WithinAbs(kEarth.radii().z, 1e-6));
    REQUIRE(Ellipsoid::unitSphere().radii() == glm::dvec3(1.0));
    REQUIRE_THAT(kEarth.oneOverRadiiSquared().z, WithinRel(1.0 / (kEarth.radii().z * kEarth.radii().z), 1e-12));
}

TEST_CASE("Ellipsoid toCartesian matches GeographicLib Forward", "[core][ellipsoid]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 20000; ++i) {
        const Geodetic3D g(kPi * (2 * unit(random) - 1), std::asin(2 * unit(random) - 1),
                           std::pow(10.0, 9.0 * unit(random)) - 1e5);
        glm::dvec3 expected;
        GeographicLib::Geocentric::WGS84().Forward(toDegrees(g.latitude), toDegrees(g.longitude), g.height,
                                                   expected.x, expected.y, expected.z);
        // Both sides round independently: allow twice the bound.
        REQUIRE(glm::length(kEarth.toCartesian(g) - expected) <= 2 * bound(expected));
    }
}

TEST_CASE("Ellipsoid toGeodetic3D round-trips within the bound and agrees with GeographicLib", "[core][ellipsoid]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 50000; ++i) {
        const double height = i % 3 == 0 ? -1e5 * unit(random) : std::pow(10.0, 8.0 * unit(random));
        const Geodetic3D g(kPi * (2 * unit(random) - 1), std::asin(2 * unit(random) - 1), height);
        const glm::dvec3 p = kEarth.toCartesian(g);
        requireRoundTrip(p);

        const Geodetic3D ours = kEarth.toGeodetic3D(p);
        const Geodetic3D theirs = reference(p);
        const double radius = glm::length(p);
        // Angles compared as arc lengths at the point's distance; 20 nm covers both methods' rounding.
        REQUIRE(std::abs(ours.latitude - theirs.latitude) * radius <= 20e-9 + 8e-16 * radius);
        REQUIRE(std::abs(std::remainder(ours.longitude - theirs.longitude, kTwoPi)) * std::hypot(p.x, p.y) <=
                20e-9 + 8e-16 * radius);
        REQUIRE(std::abs(ours.height - theirs.height) <= 20e-9 + 8e-16 * radius);
    }
}

TEST_CASE("Ellipsoid converts the poles exactly and within 1e-12 rad without NaN", "[core][ellipsoid][hard]")
{
    for (const double sign : {1.0, -1.0}) {
        for (const double offset : {0.0, 1e-15, 1e-12, 1e-9}) {
            for (const double height : {-1e5, 0.0, 1.0, 1e5, 1e9}) {
                const Geodetic3D g(0.3, sign * (kHalfPi - offset), height);
                const glm::dvec3 p = kEarth.toCartesian(g);
                requireRoundTrip(p);
                const Geodetic3D back = kEarth.toGeodetic3D(p);
                REQUIRE(std::abs(back.latitude - g.latitude) * glm::length(p) <= bound(p));
                REQUIRE_THAT(back.height, WithinAbs(height, bound(p)));
            }
        }
    }
    const Geodetic3D north = kEarth.toGeodetic3D({0.0, 0.0, kEarth.radii().z});
    REQUIRE(north.latitude == kHalfPi);
    REQUIRE(north.longitude == 0.0);
    REQUIRE(north.height == 0.0);
}

TEST_CASE("Ellipsoid keeps both sides of the antimeridian apart", "[core][ellipsoid][hard]")
{
    const double a = kEarth.radii().x;
    REQUIRE(kEarth.toGeodetic2D({-a, 0.0, 0.0}).longitude == kPi);
    REQUIRE_THAT(kEarth.toGeodetic2D({-a, 1e-9, 0.0}).longitude, WithinAbs(kPi, 1e-15));
    REQUIRE_THAT(kEarth.toGeodetic2D({-a, -1e-9, 0.0}).longitude, WithinAbs(-kPi, 1e-15));
    REQUIRE(kEarth.toGeodetic2D({-a, 1e-9, 0.0}).longitude > 0.0);
    REQUIRE(kEarth.toGeodetic2D({-a, -1e-9, 0.0}).longitude < 0.0);
    for (const double longitude : {kPi, -kPi, kPi - 1e-12, -kPi + 1e-12}) {
        requireRoundTrip(kEarth.toCartesian(Geodetic3D(longitude, 0.4, 100.0)));
    }
}

TEST_CASE("Ellipsoid gives the centre GeographicLib's answer: north pole, minus the polar radius", "[core][ellipsoid][hard]")
{
    const Geodetic3D centre = kEarth.toGeodetic3D({0.0, 0.0, 0.0});
    const Geodetic3D expected = reference({0.0, 0.0, 0.0});
    REQUIRE_THAT(centre.latitude, WithinAbs(expected.latitude, 1e-15));
    REQUIRE(centre.latitude == kHalfPi);
    REQUIRE(centre.longitude == 0.0);
    REQUIRE_THAT(centre.height, WithinAbs(expected.height, 1e-9));
    REQUIRE(kEarth.scaleToGeodeticSurface({0.0, 0.0, 0.0}) == glm::dvec3(0.0, 0.0, kEarth.radii().z));
    REQUIRE(kEarth.scaleToGeocentricSurface({0.0, 0.0, 0.0}) == glm::dvec3(0.0, 0.0, kEarth.radii().z));
}

TEST_CASE("Ellipsoid handles points within a metre of the centre and deep inside like GeographicLib", "[core][ellipsoid][hard]")
{
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> symmetric(-1.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        // Within a metre of the centre, then out to 100 km (inside the evolute, where points have
        // several surface normals and the closest foot must be chosen).
        const double scale = i < 1000 ? 1.0 : 1e5;
        glm::dvec3 p(scale * symmetric(random), scale * symmetric(random), scale * symmetric(random));
        if (i % 10 == 0) {
            p.z = 0.0; // on the equatorial plane: two closest feet, the northern one is taken
        }
        INFO("p = " << p.x << ", " << p.y << ", " << p.z);
        requireRoundTrip(p);
        const Geodetic3D ours = kEarth.toGeodetic3D(p);
        const Geodetic3D theirs = reference(p);
        REQUIRE_THAT(ours.height, WithinAbs(theirs.height, 1e-8));
        // Near the cusp of the evolute (rho -> a e^2 on the equatorial plane) the latitude is
        // ill-conditioned: both methods move by ~1e-13 rad for a last-place change of rho.
        REQUIRE_THAT(ours.latitude, WithinAbs(theirs.latitude, 1e-12));
    }
}

TEST_CASE("Ellipsoid converts points on the axis and at 1e9 m", "[core][ellipsoid][hard]")
{
    for (const double z : {-1e9, -7e6, -6356752.314245, -1.0, 1e-3, 1.0, 1e5, 6356752.314245, 1e9}) {
        const glm::dvec3 p(0.0, 0.0, z);
        requireRoundTrip(p);
        const Geodetic3D g = kEarth.toGeodetic3D(p);
        REQUIRE(g.longitude == 0.0);
        REQUIRE(std::abs(g.latitude) == kHalfPi);
    }
    for (const double r : {1e9, 3e9}) {
        requireRoundTrip({r, 0.0, 0.0});
        requireRoundTrip({r * 0.6, -r * 0.48, r * 0.64});
    }
    // Far beyond any use, the answer stays finite.
    const Geodetic3D far = kEarth.toGeodetic3D({1e200, 1e200, 1e200});
    REQUIRE(finite(far));
    REQUIRE_THAT(far.latitude, WithinAbs(std::atan(1.0 / std::sqrt(2.0)), 1e-12));
}

TEST_CASE("Ellipsoid scaleToGeodeticSurface lands on the surface below the point", "[core][ellipsoid]")
{
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> symmetric(-1.0, 1.0);
    for (int i = 0; i < 5000; ++i) {
        const glm::dvec3 p = glm::dvec3(symmetric(random), symmetric(random), symmetric(random)) * 2e7;
        const glm::dvec3 s = kEarth.scaleToGeodeticSurface(p);
        const glm::dvec3 q = s * kEarth.oneOverRadii();
        REQUIRE_THAT(glm::dot(q, q), WithinAbs(1.0, 1e-15)); // a few roundings, each half an ulp of 1
        // p lies on the surface normal through s.
        const glm::dvec3 n = kEarth.geodeticSurfaceNormal(s);
        REQUIRE(glm::length(glm::cross(p - s, n)) <= 1e-8 + 1e-15 * glm::length(p));
        const glm::dvec3 c = kEarth.scaleToGeocentricSurface(p);
        const glm::dvec3 r = c * kEarth.oneOverRadii();
        REQUIRE_THAT(glm::dot(r, r), WithinAbs(1.0, 1e-15)); // five roundings, each half an ulp of 1
        REQUIRE(glm::length(glm::cross(glm::normalize(c), glm::normalize(p))) <= 1e-15);
    }
}

TEST_CASE("Ellipsoid geodetic and geocentric normals agree at the equator and poles only", "[core][ellipsoid]")
{
    const glm::dvec3 equator = kEarth.toCartesian(Geodetic2D::fromDegrees(30, 0));
    REQUIRE(glm::length(kEarth.geodeticSurfaceNormal(equator) - Ellipsoid::geocentricSurfaceNormal(equator)) < 1e-15);
    const glm::dvec3 mid = kEarth.toCartesian(Geodetic2D::fromDegrees(30, 45));
    // The two normals differ by about 0.19 degrees at 45 degrees latitude on WGS84.
    const double angle = std::acos(glm::dot(kEarth.geodeticSurfaceNormal(mid), Ellipsoid::geocentricSurfaceNormal(mid)));
    REQUIRE_THAT(toDegrees(angle), WithinAbs(0.192, 0.001));
    REQUIRE(glm::length(kEarth.geodeticSurfaceNormal(mid) -
                        Ellipsoid::geodeticSurfaceNormal(Geodetic2D::fromDegrees(30, 45))) < 1e-15);
}

TEST_CASE("Ellipsoid works for the unit sphere, scaled WGS84 and a triaxial ellipsoid", "[core][ellipsoid]")
{
    const Ellipsoid sphere = Ellipsoid::unitSphere();
    const Geodetic3D g = sphere.toGeodetic3D({0.0, 2.0, 0.0});
    REQUIRE_THAT(g.longitude, WithinRel(kHalfPi, 1e-12));
    REQUIRE_THAT(g.latitude, WithinAbs(0.0, 1e-15));
    REQUIRE_THAT(g.height, WithinRel(1.0, 1e-12));
    REQUIRE(sphere.toGeodetic3D({0.0, 0.0, 0.0}).height == -1.0);

    const Ellipsoid scaled = Ellipsoid::scaledWgs84();
    const Geodetic3D s = Geodetic3D::fromDegrees(-120, 33, 0.01);
    const glm::dvec3 ps = scaled.toCartesian(s);
    const Geodetic3D sb = scaled.toGeodetic3D(ps);
    REQUIRE_THAT(sb.latitude, WithinAbs(s.latitude, 1e-15));
    REQUIRE_THAT(sb.height, WithinAbs(0.01, 1e-15));
    REQUIRE(glm::length(kEarth.toCartesian(Geodetic3D::fromDegrees(-120, 33, 63781.37)) / 6378137.0 - ps) < 1e-15);

    const Ellipsoid triaxial(3.0, 2.0, 1.0);
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const Geodetic3D t(kPi * (2 * unit(random) - 1), std::asin(2 * unit(random) - 1), 0.5 * unit(random));
        const glm::dvec3 p = triaxial.toCartesian(t);
        const Geodetic3D back = triaxial.toGeodetic3D(p);
        REQUIRE(glm::length(triaxial.toCartesian(back) - p) <= 1e-12);
    }
}

TEST_CASE("computeCurve spaces points by the granularity on the plane of the endpoints", "[core][curve]")
{
    const glm::dvec3 start = kEarth.toCartesian(Geodetic2D::fromDegrees(-100, 40));
    const glm::dvec3 stop = kEarth.toCartesian(Geodetic2D::fromDegrees(20, -10));
    const double granularity = toRadians(1.0);
    const std::vector<glm::dvec3> curve = kEarth.computeCurve(start, stop, granularity);
    REQUIRE(curve.front() == start);
    REQUIRE(curve.back() == stop);
    const double theta = std::acos(glm::dot(glm::normalize(start), glm::normalize(stop)));
    REQUIRE(curve.size() == static_cast<std::size_t>(std::ceil(theta / granularity)) + 1);
    const glm::dvec3 planeNormal = glm::normalize(glm::cross(start, stop));
    for (std::size_t i = 0; i < curve.size(); ++i) {
        const glm::dvec3 q = curve[i] * kEarth.oneOverRadii();
        REQUIRE_THAT(glm::dot(q, q), WithinAbs(1.0, 1e-15));
        REQUIRE(std::abs(glm::dot(curve[i], planeNormal)) < 1e-6);
        if (i > 0) {
            const double step = std::acos(std::min(1.0, glm::dot(glm::normalize(curve[i - 1]), glm::normalize(curve[i]))));
            REQUIRE(step <= granularity * (1 + 1e-9));
        }
    }
}

TEST_CASE("computeCurve between identical and antipodal points stays finite", "[core][curve][hard]")
{
    const glm::dvec3 p = kEarth.toCartesian(Geodetic2D::fromDegrees(10, 20));
    const std::vector<glm::dvec3> same = kEarth.computeCurve(p, p, 0.01);
    REQUIRE(same.size() == 2);
    REQUIRE(same[0] == p);
    REQUIRE(same[1] == p);

    for (const Geodetic2D& g : {Geodetic2D::fromDegrees(10, 20), Geodetic2D::fromDegrees(0, 90)}) {
        const glm::dvec3 a = kEarth.toCartesian(g);
        const glm::dvec3 b = kEarth.toCartesian(Geodetic2D{g.longitude + kPi, -g.latitude});
        const std::vector<glm::dvec3> curve = kEarth.computeCurve(a, b, toRadians(5.0));
        REQUIRE(curve.size() == 37);
        for (const glm::dvec3& q : curve) {
            REQUIRE(isFinite(q));
            REQUIRE(glm::length(q) > 6.3e6);
        }
    }
    // A non-positive granularity is clamped rather than looping forever.
    REQUIRE(kEarth.computeCurve(p, -p, 0.0).size() < 4'000'000);
}
