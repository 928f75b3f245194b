#include <orbis/core/AxisAlignedBoundingBox.h>
#include <orbis/core/BoundingSphere.h>
#include <orbis/core/Ellipsoid.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace orbis;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

std::vector<glm::dvec3> randomCloud(std::mt19937_64& random, int shape, std::size_t count)
{
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::vector<glm::dvec3> points;
    const glm::dvec3 offset = glm::dvec3(unit(random), unit(random), unit(random)) * 1e3;
    while (points.size() < count) {
        glm::dvec3 p(unit(random), unit(random), unit(random));
        switch (shape) {
        case 0: // a cube
            break;
        case 1: // a ball
            if (glm::length(p) > 1.0) {
                continue;
            }
            break;
        case 2: // a thin needle
            p *= glm::dvec3(1.0, 1e-3, 1e-3);
            break;
        default: // a sphere's surface
            if (glm::length(p) < 1e-3) {
                continue;
            }
            p = glm::normalize(p);
            break;
        }
        points.push_back(offset + 50.0 * p);
    }
    return points;
}

/// Half the largest distance between two points: no enclosing sphere is smaller.
double halfDiameter(const std::vector<glm::dvec3>& points)
{
    double largest = 0.0;
    for (const glm::dvec3& a : points) {
        for (const glm::dvec3& b : points) {
            largest = std::max(largest, glm::length(a - b));
        }
    }
    return 0.5 * largest;
}

} // namespace

TEST_CASE("BoundingSphere fromPoints contains every point exactly and is near the smallest", "[core][geometry][boundingsphere]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    for (int trial = 0; trial < 200; ++trial) {
        const int shape = trial % 4;
        INFO("trial " << trial << " shape " << shape);
        const std::vector<glm::dvec3> points = randomCloud(random, shape, 10 + 3 * static_cast<std::size_t>(trial));
        const BoundingSphere sphere = BoundingSphere::fromPoints(points);
        // No tolerance: the radius is the largest distance measured exactly as contains() measures.
        for (const glm::dvec3& p : points) {
            REQUIRE(sphere.contains(p));
        }
        const double lowerBound = halfDiameter(points);
        // Jung's theorem: the smallest sphere is at most sqrt(3/2) times half the diameter in 3D;
        // the documented "typically within 20 percent" of it gives 1.2 * 1.225 = 1.47 at worst.
        REQUIRE(sphere.radius >= lowerBound * (1.0 - 1e-15));
        REQUIRE(sphere.radius <= 1.47 * lowerBound);
        if (shape != 0 && points.size() >= 100) {
            // Well-sampled balls, needles and shells have about half their diameter as their
            // smallest radius; 20 percent above it is the typical quality of Ritter's method.
            REQUIRE(sphere.radius <= 1.2 * lowerBound);
        }
    }
}

TEST_CASE("BoundingSphere fromPoints of a cube takes the box-centred sphere", "[core][geometry][boundingsphere]")
{
    std::vector<glm::dvec3> corners;
    for (int i = 0; i < 8; ++i) {
        corners.emplace_back(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0);
    }
    const BoundingSphere sphere = BoundingSphere::fromPoints(corners);
    // The corners lie on the sphere of radius sqrt(3), which is the smallest; rounding only.
    REQUIRE_THAT(sphere.radius, WithinRel(std::sqrt(3.0), 1e-15));
    REQUIRE(glm::length(sphere.centre) <= 1e-15);
}

TEST_CASE("BoundingSphere fromPoints handles no points, one point and two points", "[core][geometry][boundingsphere]")
{
    REQUIRE(BoundingSphere::fromPoints({}) == BoundingSphere{});

    const glm::dvec3 p(6378137.0, -1.5, 3.25);
    const BoundingSphere one = BoundingSphere::fromPoints(std::vector<glm::dvec3>{p});
    REQUIRE(one.centre == p);
    REQUIRE(one.radius == 0.0);
    REQUIRE(one.contains(p));

    const std::vector<glm::dvec3> two{{-3.0, 0.0, 0.0}, {5.0, 0.0, 0.0}};
    const BoundingSphere pair = BoundingSphere::fromPoints(two);
    REQUIRE(pair.centre == glm::dvec3(1.0, 0.0, 0.0)); // exact: small integers
    REQUIRE(pair.radius == 4.0);
}

TEST_CASE("BoundingSphere fromPoints is tight for a small tile at Earth scale", "[core][geometry][boundingsphere]")
{
    // A 100 m x 100 m patch on the WGS84 surface, 11 x 11 points: the smallest sphere has a radius
    // of about 70.7 m (half the diagonal); the coordinates are 6.4e6 m, so this checks that
    // nothing is lost to their size.
    const Ellipsoid earth = Ellipsoid::wgs84();
    std::vector<glm::dvec3> points;
    const double step = 10.0 / 6378137.0;
    for (int i = 0; i <= 10; ++i) {
        for (int j = 0; j <= 10; ++j) {
            points.push_back(earth.toCartesian(Geodetic3D(toRadians(7.0) + i * step, toRadians(46.0) + j * step)));
        }
    }
    const BoundingSphere sphere = BoundingSphere::fromPoints(points);
    for (const glm::dvec3& p : points) {
        REQUIRE(sphere.contains(p));
    }
    // Longitude steps shrink by cos(46 deg): the diagonal is sqrt(100^2 + 69.5^2) = 121.8 m.
    REQUIRE(sphere.radius >= 60.0);
    REQUIRE(sphere.radius <= 1.2 * 0.5 * 121.8);
}

TEST_CASE("BoundingSphere merge contains both spheres", "[core][geometry][boundingsphere]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int trial = 0; trial < 2000; ++trial) {
        const double scale = std::pow(10.0, 8.0 * (0.5 + 0.5 * unit(random)));
        const BoundingSphere a{glm::dvec3(unit(random), unit(random), unit(random)) * scale,
                               scale * (0.5 + 0.5 * unit(random))};
        const BoundingSphere b{a.centre + glm::dvec3(unit(random), unit(random), unit(random)) * scale,
                               scale * (0.5 + 0.5 * unit(random)) * (trial % 3 == 0 ? 1e-3 : 1.0)};
        const BoundingSphere merged = BoundingSphere::merge(a, b);
        INFO("trial " << trial);
        // Extreme points of each sphere along a few directions must be inside, up to 4e-16 of
        // the size (the rounding of the last sums of merge).
        const double slack = 4e-16 * (glm::length(merged.centre) + merged.radius);
        for (const BoundingSphere& s : {a, b}) {
            const glm::dvec3 towards = merged.centre - s.centre;
            const glm::dvec3 away = glm::length(towards) > 0.0 ? -glm::normalize(towards) : glm::dvec3(1, 0, 0);
            for (const glm::dvec3& d : {away, glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)}) {
                REQUIRE(glm::length(s.centre + s.radius * d - merged.centre) <= merged.radius + slack);
            }
        }
        // Never larger than the smallest enclosing sphere, up to the same rounding.
        const double d = glm::length(a.centre - b.centre);
        const double smallest = std::max({a.radius, b.radius, 0.5 * (d + a.radius + b.radius)});
        REQUIRE(merged.radius <= smallest + slack);
    }
}

TEST_CASE("BoundingSphere merge returns the containing sphere when one contains the other", "[core][geometry][boundingsphere]")
{
    const BoundingSphere big{{1.0, 2.0, 3.0}, 10.0};
    const BoundingSphere small{{2.0, 2.0, 3.0}, 1.0};
    REQUIRE(BoundingSphere::merge(big, small) == big);
    REQUIRE(BoundingSphere::merge(small, big) == big);
    REQUIRE(BoundingSphere::merge(big, big) == big);
    // Disjoint, along x: from -1 to 13, so centre 6 and radius 7 (exact in binary).
    const BoundingSphere merged = BoundingSphere::merge({{0.0, 0.0, 0.0}, 1.0}, {{10.0, 0.0, 0.0}, 3.0});
    REQUIRE(merged.centre == glm::dvec3(6.0, 0.0, 0.0));
    REQUIRE(merged.radius == 7.0);
}

TEST_CASE("BoundingSphere classifies itself against a plane, touching as intersecting", "[core][geometry][boundingsphere]")
{
    const Plane plane{{0.0, 0.0, 1.0}, -2.0}; // z = 2, normal up
    REQUIRE(BoundingSphere{{0.0, 0.0, 5.0}, 1.0}.intersect(plane) == Intersect::Inside);
    REQUIRE(BoundingSphere{{0.0, 0.0, -5.0}, 1.0}.intersect(plane) == Intersect::Outside);
    REQUIRE(BoundingSphere{{0.0, 0.0, 2.5}, 1.0}.intersect(plane) == Intersect::Intersecting);
    REQUIRE(BoundingSphere{{0.0, 0.0, 3.0}, 1.0}.intersect(plane) == Intersect::Intersecting); // touches
    REQUIRE(BoundingSphere{{0.0, 0.0, 1.0}, 1.0}.intersect(plane) == Intersect::Intersecting); // touches
    REQUIRE(BoundingSphere{{7.0, -3.0, 2.0}, 0.0}.intersect(plane) == Intersect::Intersecting);
}

TEST_CASE("BoundingSphere contains and distanceTo measure from the surface", "[core][geometry][boundingsphere]")
{
    const BoundingSphere sphere{{1.0, 0.0, 0.0}, 2.0};
    REQUIRE(sphere.contains({3.0, 0.0, 0.0}));
    REQUIRE_FALSE(sphere.contains({3.5, 0.0, 0.0}));
    REQUIRE(sphere.distanceTo({1.0, 0.0, 0.0}) == 0.0);
    REQUIRE(sphere.distanceTo({1.0, 5.0, 0.0}) == 3.0);
}

TEST_CASE("AxisAlignedBoundingBox fromPoints, centre and contains", "[core][geometry][aabb]")
{
    REQUIRE(AxisAlignedBoundingBox::fromPoints({}) == AxisAlignedBoundingBox{});
    const std::vector<glm::dvec3> points{{1.0, -2.0, 3.0}, {-4.0, 5.0, 0.5}, {2.0, 0.0, -6.0}};
    const AxisAlignedBoundingBox box = AxisAlignedBoundingBox::fromPoints(points);
    REQUIRE(box.minimum == glm::dvec3(-4.0, -2.0, -6.0));
    REQUIRE(box.maximum == glm::dvec3(2.0, 5.0, 3.0));
    REQUIRE(box.centre() == glm::dvec3(-1.0, 1.5, -1.5));
    REQUIRE(box.size() == glm::dvec3(6.0, 7.0, 9.0));
    for (const glm::dvec3& p : points) {
        REQUIRE(box.contains(p));
    }
    REQUIRE(box.contains(box.minimum));
    REQUIRE(box.contains(box.maximum));
    REQUIRE_FALSE(box.contains({2.0 + 1e-12, 0.0, 0.0}));
    REQUIRE_FALSE(box.contains({0.0, 0.0, -7.0}));
    // The centre of corners near the largest double does not overflow.
    const AxisAlignedBoundingBox huge{glm::dvec3(1e308), glm::dvec3(1.7e308)};
    REQUIRE_THAT(huge.centre().x, WithinRel(1.35e308, 1e-15));
}

TEST_CASE("Plane fromPointNormal normalises and measures signed distance", "[core][geometry][plane]")
{
    const Plane plane = Plane::fromPointNormal({0.0, 0.0, 6378137.0}, {0.0, 0.0, 2.0});
    REQUIRE(plane.normal == glm::dvec3(0.0, 0.0, 1.0));
    REQUIRE(plane.distance == -6378137.0);
    REQUIRE(plane.signedDistance({5.0, 5.0, 6378140.0}) == 3.0);
    REQUIRE(plane.signedDistance({5.0, 5.0, 0.0}) == -6378137.0);
    REQUIRE(plane.project({5.0, 6.0, 0.0}) == glm::dvec3(5.0, 6.0, 6378137.0));
    const Plane tilted = Plane::fromPointNormal({1.0, 1.0, 1.0}, {1.0, 1.0, 1.0});
    REQUIRE_THAT(glm::length(tilted.normal), WithinRel(1.0, 1e-15));
    REQUIRE_THAT(tilted.signedDistance({1.0, 1.0, 1.0}), WithinAbs(0.0, 1e-15)); // rounding of 1/sqrt(3)
}
