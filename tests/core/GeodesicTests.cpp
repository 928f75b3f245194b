#include <orbis/core/Geodesic.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

// Tolerances are absolute (WithinAbs): Catch's Approx adds a relative slack of 1.2e-5 to any
// margin, which on Earth-sized values would hide errors of tens of metres.

#include <algorithm>
#include <cmath>
#include <random>

using namespace orbis;
using Catch::Matchers::WithinAbs;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
// The IUGG mean Earth radius: a sphere of Earth size, where geodesics are great circles.
constexpr double kSphereRadius = 6371008.8;

/// Great-circle distance on a sphere of the given radius, by the atan2 form (accurate at every
/// separation, unlike acos near 0 and pi).
double greatCircleDistance(double radius, const Geodetic2D& a, const Geodetic2D& b)
{
    const glm::dvec3 p = Ellipsoid::geodeticSurfaceNormal(a);
    const glm::dvec3 q = Ellipsoid::geodeticSurfaceNormal(b);
    return radius * std::atan2(glm::length(glm::cross(p, q)), glm::dot(p, q));
}

/// Pole-to-equator length of a meridian ellipse with semi-axes a and b, by Simpson's rule on
/// 2000 intervals (the integrand is smooth: far below 1e-12 relative).
double quarterMeridian(double a, double b)
{
    constexpr int n = 2000;
    auto f = [&](double t) { return std::hypot(a * std::sin(t), b * std::cos(t)); };
    const double h = kHalfPi / n;
    double sum = f(0.0) + f(kHalfPi);
    for (int i = 1; i < n; ++i) {
        sum += (i % 2 ? 4.0 : 2.0) * f(i * h);
    }
    return sum * h / 3.0;
}

double centralAngle(const glm::dvec3& p, const glm::dvec3& q)
{
    return std::atan2(glm::length(glm::cross(p, q)), glm::dot(p, q));
}

Geodetic2D randomPosition(std::mt19937_64& random)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    return {kPi * (2.0 * unit(random) - 1.0), std::asin(2.0 * unit(random) - 1.0)};
}

bool allFinite(const std::vector<glm::dvec3>& points)
{
    return std::all_of(points.begin(), points.end(), [](const glm::dvec3& p) { return isFinite(p); });
}

} // namespace

TEST_CASE("Geodesic distance matches GeographicLib's documented JFK to LHR example", "[core][geodesic]")
{
    const Geodesic geodesic(kEarth);
    const Geodetic2D jfk = Geodetic2D::fromDegrees(-73.8, 40.6);
    const Geodetic2D lhr = Geodetic2D::fromDegrees(-0.5, 51.6);
    // The documentation prints 5551759.400319 m; 1 µm covers its six decimals and our degree to
    // radian round trip (1e-16 relative, under a nanometre).
    REQUIRE_THAT(geodesic.distance(jfk, lhr), WithinAbs(5551759.400319, 1e-6));
    REQUIRE_THAT(geodesic.distance(lhr, jfk), WithinAbs(5551759.400319, 1e-6));
}

TEST_CASE("Geodesic distance on WGS84 is half a meridian for antipodal points, 0 for identical ones",
          "[core][geodesic][hard]")
{
    const Geodesic geodesic(kEarth);
    // Twice the WGS84 quarter meridian, 10001965.729313 m; the shortest path between
    // antipodal points runs over the poles. 1 µm: the value's last printed digit.
    const double halfMeridian = 2.0 * 10001965.729313;
    REQUIRE_THAT(geodesic.distance(Geodetic2D::fromDegrees(0, 0), Geodetic2D::fromDegrees(180, 0)),
                 WithinAbs(halfMeridian, 1e-6));
    REQUIRE_THAT(geodesic.distance(Geodetic2D::fromDegrees(10, 30), Geodetic2D::fromDegrees(-170, -30)),
                 WithinAbs(halfMeridian, 1e-6));
    REQUIRE_THAT(geodesic.distance(Geodetic2D::fromDegrees(0, 90), Geodetic2D::fromDegrees(0, -90)),
                 WithinAbs(halfMeridian, 1e-6));
    // The quarter meridian itself, from pole to equator.
    REQUIRE_THAT(geodesic.distance(Geodetic2D{0.3, kHalfPi}, Geodetic2D{1.0, 0.0}), WithinAbs(10001965.729313, 1e-6));
    // Numerical integration agrees with it, so the helper can be trusted below.
    REQUIRE_THAT(quarterMeridian(kEarth.radii().x, kEarth.radii().z), WithinAbs(10001965.729313, 1e-6));

    const Geodetic2D p = Geodetic2D::fromDegrees(12.5, -33.0);
    REQUIRE(geodesic.distance(p, p) == 0.0);
    REQUIRE_THAT(geodesic.distance(Geodetic2D::fromDegrees(180, 20), Geodetic2D::fromDegrees(-180, 20)),
                 WithinAbs(0.0, 1e-9));
    // Latitudes beyond the poles by rounding are clamped, not turned into NaN.
    REQUIRE(std::isfinite(geodesic.distance(Geodetic2D{0.0, kHalfPi * (1 + 1e-15)}, p)));
}

TEST_CASE("Geodesic distance on a sphere is the great-circle distance", "[core][geodesic]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    const Geodesic unit(Ellipsoid::unitSphere());
    const Geodesic earthSized(Ellipsoid(kSphereRadius, kSphereRadius, kSphereRadius));
    for (int i = 0; i < 2000; ++i) {
        const Geodetic2D a = randomPosition(random);
        const Geodetic2D b = randomPosition(random);
        // GeographicLib states 15 nm on Earth-sized bodies; 100 nm leaves room for both sides'
        // rounding (measured: 6 nm).
        REQUIRE_THAT(earthSized.distance(a, b), WithinAbs(greatCircleDistance(kSphereRadius, a, b), 1e-7));
        REQUIRE_THAT(unit.distance(a, b), WithinAbs(greatCircleDistance(1.0, a, b), 1e-7 / kSphereRadius));
    }
}

TEST_CASE("Geodesic and computeCurve give the same points on a sphere", "[core][geodesic][curve]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    const Ellipsoid sphere(kSphereRadius, kSphereRadius, kSphereRadius);
    const Geodesic geodesic(sphere);
    for (int i = 0; i < 500; ++i) {
        const Geodetic2D a = randomPosition(random);
        const Geodetic2D b = randomPosition(random);
        const double granularity = toRadians(i % 2 ? 1.0 : 0.37);
        const std::vector<glm::dvec3> path = geodesic.computeGeodesic(a, b, granularity);
        const std::vector<glm::dvec3> curve = sphere.computeCurve(sphere.toCartesian(a), sphere.toCartesian(b), granularity);
        // Both split the central angle into equal steps, so even the point counts agree.
        REQUIRE(path.size() == curve.size());
        for (std::size_t k = 0; k < path.size(); ++k) {
            // 1 µm on a 6371 km sphere: GeographicLib's 15 nm plus each side's rounding (about
            // 1e-15 of the radius per operation); measured at most 35 nm.
            REQUIRE(glm::distance(path[k], curve[k]) < 1e-6);
        }
    }
}

TEST_CASE("Geodesic and computeCurve differ on WGS84 by kilometres over 9600 km", "[core][geodesic][curve]")
{
    const Geodesic geodesic(kEarth);
    const Geodetic2D london = Geodetic2D::fromDegrees(-0.1278, 51.5074);
    const Geodetic2D tokyo = Geodetic2D::fromDegrees(139.6917, 35.6895);
    const glm::dvec3 a = kEarth.toCartesian(london);
    const glm::dvec3 b = kEarth.toCartesian(tokyo);
    const std::vector<glm::dvec3> curve = kEarth.computeCurve(a, b, 1e-4);
    const std::vector<glm::dvec3> path = geodesic.computeGeodesic(london, tokyo, 1e-3);

    // The section lies in the plane through the centre and both ends; the geodesic leaves it.
    const glm::dvec3 normal = glm::normalize(glm::cross(a, b));
    double offPlane = 0.0;
    for (const glm::dvec3& p : path) {
        offPlane = std::max(offPlane, std::abs(glm::dot(p, normal)));
    }
    double sectionLength = 0.0;
    for (std::size_t i = 1; i < curve.size(); ++i) {
        sectionLength += glm::distance(curve[i - 1], curve[i]);
    }
    const double geodesicLength = geodesic.distance(london, tokyo);
    // Measured (bench section "curves"): 4.59 km apart at most, the section 4.39 m longer. The
    // ranges (about +-5%) catch a sign or scale error in either curve. The chord sum at 1e-4 rad
    // falls short of the section's length by L g^2 / 24 = 1 cm, well inside the length range.
    CHECK(offPlane > 4.35e3);
    CHECK(offPlane < 4.8e3);
    CHECK(sectionLength - geodesicLength > 4.1);
    CHECK(sectionLength - geodesicLength < 4.6);
    REQUIRE_THAT(geodesicLength, WithinAbs(9582e3, 1e3));
}

TEST_CASE("Geodesic path starts and ends exactly and spaces its points by the granularity", "[core][geodesic]")
{
    const Geodesic geodesic(kEarth);
    std::mt19937_64 random(5);
    for (int i = 0; i < 200; ++i) {
        const Geodetic2D a = randomPosition(random);
        const Geodetic2D b = randomPosition(random);
        const double granularity = toRadians(i % 3 == 0 ? 5.0 : 1.0);
        const std::vector<glm::dvec3> path = geodesic.computeGeodesic(a, b, granularity);
        REQUIRE(path.front() == kEarth.toCartesian(a));
        REQUIRE(path.back() == kEarth.toCartesian(b));
        REQUIRE(path.size() >= 2);
        double longest = 0.0;
        double shortest = kPi;
        for (std::size_t k = 0; k < path.size(); ++k) {
            const glm::dvec3 q = path[k] * kEarth.oneOverRadii();
            REQUIRE_THAT(glm::dot(q, q), WithinAbs(1.0, 1e-15)); // on the surface
            if (k > 0) {
                const double step = centralAngle(path[k - 1], path[k]);
                longest = std::max(longest, step);
                shortest = std::min(shortest, step);
            }
        }
        // Steps are equal on the auxiliary sphere; seen from the centre they differ from it by
        // less than the flattening (1/298), hence 0.4%.
        REQUIRE(longest <= granularity * 1.004);
        REQUIRE(longest <= shortest * 1.008);
        // No more points than needed: the auxiliary arc is at most distance / b (a metre of path
        // never spans more arc than on the polar circle), so ceil(distance / (b g)) segments
        // suffice.
        const double arcBound = geodesic.distance(a, b) / kEarth.minimumRadius();
        REQUIRE(path.size() - 1 <= static_cast<std::size_t>(std::ceil(arcBound / granularity * (1 + 1e-12))));
    }
}

TEST_CASE("Geodesic path by segment length spaces its points evenly along the path", "[core][geodesic]")
{
    const Geodesic geodesic(kEarth);
    const Geodetic2D a = Geodetic2D::fromDegrees(2.3522, 48.8566);
    const Geodetic2D b = Geodetic2D::fromDegrees(-3.7038, 40.4168);
    const double total = geodesic.distance(a, b);
    const std::vector<glm::dvec3> path = geodesic.computeGeodesicBySegmentLength(a, b, 50e3);
    REQUIRE(path.size() == static_cast<std::size_t>(std::ceil(total / 50e3)) + 1);
    REQUIRE(path.front() == kEarth.toCartesian(a));
    REQUIRE(path.back() == kEarth.toCartesian(b));
    const double segment = total / static_cast<double>(path.size() - 1);
    double sum = 0.0;
    for (std::size_t k = 1; k < path.size(); ++k) {
        const double step = geodesic.distance(kEarth.toGeodetic2D(path[k - 1]), kEarth.toGeodetic2D(path[k]));
        // 1 µm: GeographicLib's 15 nm per evaluation plus the Cartesian round trip (nanometres).
        REQUIRE_THAT(step, WithinAbs(segment, 1e-6));
        sum += step;
    }
    REQUIRE_THAT(sum, WithinAbs(total, 1e-5));
    // A segment length below the clamp (6.4 m on WGS84) is raised to it, bounding the count.
    REQUIRE(geodesic.computeGeodesicBySegmentLength(a, b, 0.0).size() ==
            static_cast<std::size_t>(std::ceil(total / (1e-6 * kEarth.radii().x))) + 1);
}

TEST_CASE("Geodesic paths between identical and antipodal points stay finite", "[core][geodesic][hard]")
{
    const Geodesic geodesic(kEarth);
    const Geodetic2D p = Geodetic2D::fromDegrees(10, 20);
    const std::vector<glm::dvec3> same = geodesic.computeGeodesic(p, p, 0.01);
    REQUIRE(same.size() == 2);
    REQUIRE(same[0] == kEarth.toCartesian(p));
    REQUIRE(same[1] == kEarth.toCartesian(p));
    REQUIRE(geodesic.computeGeodesicBySegmentLength(p, p, 1000.0).size() == 2);

    const Geodetic2D near{p.longitude + 1e-12, p.latitude};
    REQUIRE(allFinite(geodesic.computeGeodesic(p, near, 0.01)));

    for (const Geodetic2D& g : {Geodetic2D::fromDegrees(0, 0), Geodetic2D::fromDegrees(10, 20),
                                Geodetic2D::fromDegrees(-120, -75), Geodetic2D::fromDegrees(0, 90)}) {
        const Geodetic2D antipode{g.longitude + kPi, -g.latitude};
        const std::vector<glm::dvec3> path = geodesic.computeGeodesic(g, antipode, toRadians(5.0));
        INFO("from " << toDegrees(g.longitude) << ", " << toDegrees(g.latitude));
        REQUIRE(allFinite(path));
        REQUIRE(path.size() == 37); // 180 degrees of arc in 5-degree steps
        // GeographicLib's choice: the meridian plane, over the pole of the start's hemisphere
        // (the north pole from the equator; pole to pole along the start's meridian).
        const bool pole = std::abs(g.latitude) > kHalfPi - 1e-9;
        const glm::dvec3 meridianNormal =
            glm::normalize(glm::cross(glm::dvec3(0, 0, 1), Ellipsoid::geodeticSurfaceNormal(g)));
        double highest = -1e300;
        double lowest = 1e300;
        for (const glm::dvec3& q : path) {
            highest = std::max(highest, q.z);
            lowest = std::min(lowest, q.z);
            if (!pole) {
                REQUIRE(std::abs(glm::dot(q, meridianNormal)) < 1e-6); // 1 µm: on the meridian
            }
        }
        // Over the pole: some sample lies within half a step (2.5 degrees) of it.
        const double nearPole = kEarth.radii().z * std::cos(toRadians(2.5));
        if (g.latitude >= 0.0) {
            REQUIRE(highest > nearPole);
        } else {
            REQUIRE(lowest < -nearPole);
        }
        // computeCurve takes the same meridian plane (heading north whatever the start).
        if (!pole) {
            for (const glm::dvec3& q : kEarth.computeCurve(path.front(), path.back(), toRadians(5.0))) {
                REQUIRE(std::abs(glm::dot(q, meridianNormal)) < 1e-6);
            }
        }
    }
}

TEST_CASE("Geodesic on eccentric spheroids uses the exact solution", "[core][geodesic]")
{
    // |f| > 1/50: GeographicLib's series would lose accuracy; the elliptic-integral solution is
    // exact to round-off (1e-12 on unit radii leaves room for the integration helper's error).
    for (const double polar : {0.5, 1.5}) {
        const Ellipsoid spheroid(1.0, 1.0, polar);
        const Geodesic geodesic(spheroid);
        INFO("polar radius " << polar);
        REQUIRE_THAT(geodesic.distance(Geodetic2D{0.2, kHalfPi}, Geodetic2D{0.2, 0.0}),
                     WithinAbs(quarterMeridian(1.0, polar), 1e-12));
        // Along the equator, short of the conjugate point, the geodesic is the equator.
        REQUIRE_THAT(geodesic.distance(Geodetic2D{0.0, 0.0}, Geodetic2D{kPi / 6, 0.0}), WithinAbs(kPi / 6, 1e-12));
        const std::vector<glm::dvec3> path =
            geodesic.computeGeodesic(Geodetic2D::fromDegrees(-40, 10), Geodetic2D::fromDegrees(70, 50), 0.05);
        REQUIRE(allFinite(path));
        for (const glm::dvec3& q : path) {
            const glm::dvec3 s = q * spheroid.oneOverRadii();
            REQUIRE_THAT(glm::dot(s, s), WithinAbs(1.0, 1e-14));
        }
    }
}

TEST_CASE("Geodesic copies and moves keep their solver", "[core][geodesic]")
{
    const Geodesic original(Ellipsoid(1.0, 1.0, 0.5));
    Geodesic copy = original;
    const Geodetic2D a{0.0, 0.0};
    const Geodetic2D b{1.0, 0.5};
    REQUIRE(copy.distance(a, b) == original.distance(a, b));
    Geodesic assigned(kEarth);
    assigned = copy;
    REQUIRE(assigned.ellipsoid() == Ellipsoid(1.0, 1.0, 0.5));
    REQUIRE(assigned.distance(a, b) == original.distance(a, b));
    Geodesic moved = std::move(copy);
    REQUIRE(moved.distance(a, b) == original.distance(a, b));
}
