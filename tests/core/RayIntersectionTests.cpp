#include <orbis/core/IntersectionTests.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <utility>

using namespace orbis;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

using Extended = long double;

struct ExtendedInterval {
    Extended nearDistance;
    Extended farDistance;
};

/// The same interval in extended precision (x87: 11 more bits), dividing by the radii instead
/// of multiplying by their rounded inverses: the yardstick for the double version.
std::optional<ExtendedInterval> referenceRayEllipsoid(const glm::dvec3& origin, const glm::dvec3& direction,
                                                      const glm::dvec3& radii)
{
    Extended q[3], v[3];
    for (int i = 0; i < 3; ++i) {
        q[i] = Extended(origin[i]) / Extended(radii[i]);
        v[i] = Extended(direction[i]) / Extended(radii[i]);
    }
    auto dot = [](const Extended* a, const Extended* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const Extended a = dot(v, v), h = dot(q, v), c = dot(q, q) - 1;
    Extended l[3];
    for (int i = 0; i < 3; ++i) {
        l[i] = q[i] - (h / a) * v[i];
    }
    const Extended m = 1 - dot(l, l);
    if (m < 0) {
        return std::nullopt;
    }
    const Extended s = std::sqrt(a * m);
    if (c > 0) {
        if (h >= 0) {
            return std::nullopt;
        }
        const Extended k = s - h;
        return ExtendedInterval{std::min(c / k, k / a), std::max(c / k, k / a)};
    }
    return ExtendedInterval{0, h <= 0 ? (s - h) / a : -c / (h + s)};
}

/// The parameter of the ray's closest approach to the centre in scaled space, in extended precision.
double closestApproach(const Ray& ray, const glm::dvec3& radii)
{
    Extended h = 0, a = 0;
    for (int i = 0; i < 3; ++i) {
        const Extended q = Extended(ray.origin[i]) / Extended(radii[i]);
        const Extended v = Extended(ray.direction[i]) / Extended(radii[i]);
        h += q * v;
        a += v * v;
    }
    return static_cast<double>(-h / a);
}

/// A unit vector perpendicular to the unit normal n, towards r (Gram-Schmidt twice, so that it is
/// perpendicular to rounding even when r is nearly parallel to n).
glm::dvec3 tangentDirection(const glm::dvec3& n, const glm::dvec3& r)
{
    glm::dvec3 t = r - glm::dot(r, n) * n;
    if (glm::length(t) < 1e-3) {
        t = anyPerpendicular(n);
    }
    t = glm::normalize(t);
    return glm::normalize(t - glm::dot(t, n) * n);
}

/// Moeller-Trumbore in extended precision: distance and barycentrics of the ray's hit.
RayTriangleHit referenceRayTriangle(const Ray& ray, const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2)
{
    Extended o[3], d[3], e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
        o[k] = Extended(ray.origin[k]) - Extended(p0[k]);
        d[k] = Extended(ray.direction[k]);
        e1[k] = Extended(p1[k]) - Extended(p0[k]);
        e2[k] = Extended(p2[k]) - Extended(p0[k]);
    }
    auto cross = [](const Extended* x, const Extended* y, Extended* r) {
        r[0] = x[1] * y[2] - x[2] * y[1];
        r[1] = x[2] * y[0] - x[0] * y[2];
        r[2] = x[0] * y[1] - x[1] * y[0];
    };
    auto dot = [](const Extended* x, const Extended* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    Extended p[3], q[3];
    cross(d, e2, p);
    cross(o, e1, q);
    const Extended det = dot(e1, p);
    return {static_cast<double>(dot(e2, q) / det), static_cast<double>(dot(o, p) / det),
            static_cast<double>(dot(d, q) / det)};
}

/// How far p is from the surface, in scaled units (|p / radii| - 1).
double scaledHeight(const glm::dvec3& p, const Ellipsoid& ellipsoid)
{
    return glm::length(p * ellipsoid.oneOverRadii()) - 1.0;
}

glm::dvec3 randomUnit(std::mt19937_64& random)
{
    std::normal_distribution<double> normal;
    for (;;) {
        const glm::dvec3 v(normal(random), normal(random), normal(random));
        if (glm::length(v) > 1e-6) {
            return glm::normalize(v);
        }
    }
}

Geodetic2D randomGeodetic(std::mt19937_64& random)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    return {kPi * (2.0 * unit(random) - 1.0), std::asin(2.0 * unit(random) - 1.0)};
}

} // namespace

TEST_CASE("Ray-sphere intersection: through, from inside, from the centre, tangent, missing", "[core][geometry][intersection]")
{
    const BoundingSphere unit{{0.0, 0.0, 0.0}, 1.0};
    // Small integers and halves: all exact.
    auto through = intersectRaySphere({{0.0, 0.0, -5.0}, {0.0, 0.0, 1.0}}, unit);
    REQUIRE(through);
    REQUIRE(through->nearDistance == 4.0);
    REQUIRE(through->farDistance == 6.0);

    auto scaled = intersectRaySphere({{0.0, 0.0, -5.0}, {0.0, 0.0, 2.0}}, unit); // t in units of |direction|
    REQUIRE(scaled);
    REQUIRE(scaled->nearDistance == 2.0);
    REQUIRE(scaled->farDistance == 3.0);

    auto inside = intersectRaySphere({{0.0, 0.0, 0.5}, {0.0, 0.0, -1.0}}, unit);
    REQUIRE(inside);
    REQUIRE(inside->nearDistance == 0.0);
    REQUIRE(inside->farDistance == 1.5);

    auto centre = intersectRaySphere({{3.0, 4.0, 5.0}, {0.0, 1.0, 0.0}}, {{3.0, 4.0, 5.0}, 2.0});
    REQUIRE(centre);
    REQUIRE(centre->nearDistance == 0.0);
    REQUIRE(centre->farDistance == 2.0);

    auto tangent = intersectRaySphere({{1.0, 0.0, -5.0}, {0.0, 0.0, 1.0}}, unit);
    REQUIRE(tangent);
    REQUIRE(tangent->nearDistance == 5.0);
    REQUIRE(tangent->farDistance == 5.0);

    REQUIRE_FALSE(intersectRaySphere({{1.001, 0.0, -5.0}, {0.0, 0.0, 1.0}}, unit));   // passes by
    REQUIRE_FALSE(intersectRaySphere({{0.0, 0.0, -5.0}, {0.0, 0.0, -1.0}}, unit));    // points away
    REQUIRE_FALSE(intersectRaySphere({{0.0, 0.0, -5.0}, {0.0, 0.0, 0.0}}, unit));     // no direction
    REQUIRE_FALSE(intersectRaySphere({{0.0, 0.0, -5.0}, {0.0, 0.0, 1.0}}, {{}, 0.0})); // no radius
}

TEST_CASE("Ray-ellipsoid intersection along the axes is exact to rounding", "[core][geometry][intersection]")
{
    const glm::dvec3 r = kEarth.radii();
    // Tolerance: 4 units in the last place of the distance (scaling by rounded 1 / radius).
    auto x = intersectRayEllipsoid({{1e9, 0.0, 0.0}, {-1.0, 0.0, 0.0}}, kEarth);
    REQUIRE(x);
    REQUIRE_THAT(x->nearDistance, WithinRel(1e9 - r.x, 4 * kEpsilon));
    REQUIRE_THAT(x->farDistance, WithinRel(1e9 + r.x, 4 * kEpsilon));

    auto z = intersectRayEllipsoid({{0.0, 0.0, -2e7}, {0.0, 0.0, 1.0}}, kEarth);
    REQUIRE(z);
    REQUIRE_THAT(z->nearDistance, WithinRel(2e7 - r.z, 4 * kEpsilon));
    REQUIRE_THAT(z->farDistance, WithinRel(2e7 + r.z, 4 * kEpsilon));
}

TEST_CASE("Ray-ellipsoid from the centre or from inside returns 0 and the exit", "[core][geometry][intersection]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);

    auto up = intersectRayEllipsoid({{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}}, kEarth);
    REQUIRE(up);
    REQUIRE(up->nearDistance == 0.0);
    REQUIRE_THAT(up->farDistance, WithinRel(kEarth.radii().z, 2 * kEpsilon));

    for (int i = 0; i < 20000; ++i) {
        // From the centre, from deep inside, and from within 1 m below the surface.
        const double depth = i % 3 == 0 ? 1.0 : (i % 3 == 1 ? unit(random) : 1.0 - 1e-7 * unit(random));
        const glm::dvec3 origin = i % 5 == 0 ? glm::dvec3(0.0) : depth * kEarth.toCartesian(randomGeodetic(random));
        const Ray ray{origin, randomUnit(random)};
        INFO("i " << i);
        const auto hit = intersectRayEllipsoid(ray, kEarth);
        REQUIRE(hit);
        REQUIRE(hit->nearDistance == 0.0);
        // The exit lies on the surface: 1e-15 in scaled units is 6 nm, the rounding of the exit
        // point (1 nm) and of evaluating its height (2 eps).
        REQUIRE(std::abs(scaledHeight(ray.pointAt(hit->farDistance), kEarth)) <= 1e-15);
        REQUIRE(hit->farDistance >= 0.0);
        REQUIRE(hit->farDistance <= 2.0 * kEarth.maximumRadius());
    }
}

TEST_CASE("Ray-ellipsoid from a point on the surface", "[core][geometry][intersection]")
{
    const glm::dvec3 p = kEarth.toCartesian(Geodetic3D::fromDegrees(12.0, 34.0));
    const glm::dvec3 n = kEarth.geodeticSurfaceNormal(p);
    // Outwards: the interval is empty but for the origin (counts as inside up to rounding).
    const auto out = intersectRayEllipsoid({p, n}, kEarth);
    if (out) {
        REQUIRE(out->nearDistance == 0.0);
        REQUIRE(out->farDistance <= 1e-8); // rounding of p: 10 nm
    }
    // Inwards: through the Earth, about 2 x 6370 km along the normal.
    const auto in = intersectRayEllipsoid({p, -n}, kEarth);
    REQUIRE(in);
    REQUIRE(in->nearDistance == 0.0);
    REQUIRE(in->farDistance > 1.2e7);
    REQUIRE(std::abs(scaledHeight(p - in->farDistance * n, kEarth)) <= 1e-15); // as above
}

TEST_CASE("Ray-ellipsoid counts a tangent ray as touching at its closest approach", "[core][geometry][intersection][hard]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    for (int i = 0; i < 20000; ++i) {
        const glm::dvec3 p = kEarth.toCartesian(randomGeodetic(random));
        const glm::dvec3 n = kEarth.geodeticSurfaceNormal(p);
        const glm::dvec3 along = tangentDirection(n, randomUnit(random));
        const double distance = std::pow(10.0, 3.0 + 6.0 * (i % 7) / 6.0); // 1 km to 1e9 m
        const Ray ray{p - distance * along, along};
        INFO("i " << i << " distance " << distance);
        const auto hit = intersectRayEllipsoid(ray, kEarth);
        REQUIRE(hit);
        REQUIRE(hit->nearDistance == hit->farDistance);
        // The closest approach is well conditioned: within 8 ulp of the distance plus 8 ulp of
        // the origin's size (its dot product cancels from |q||v|) of the extended-precision value.
        const double tolerance = 8 * kEpsilon * (distance + glm::length(ray.origin));
        REQUIRE(std::abs(hit->nearDistance - closestApproach(ray, kEarth.radii())) <= tolerance);
        // And near p: the ray's construction rounds p and the direction (1e-16 rad of tilt moves
        // the closest approach by R 1e-16 = 1 nm; 1e-7 m allows for 100 times that).
        REQUIRE(glm::length(ray.pointAt(hit->nearDistance) - p) <= 8 * kEpsilon * distance + 1e-7);
    }
    // Just above the surface (1 mm up, from 10,000 km) is a clean miss; 1 mm down a short chord
    // of 2 sqrt(2 rho 1 mm) = 226 m (rho: radius of curvature, 6378 km on the equator).
    const glm::dvec3 p(kEarth.radii().x, 0.0, 0.0);
    REQUIRE_FALSE(intersectRayEllipsoid({p + glm::dvec3(1e-3, -1e7, 0.0), {0.0, 1.0, 0.0}}, kEarth));
    const auto chord = intersectRayEllipsoid({p + glm::dvec3(-1e-3, -1e7, 0.0), {0.0, 1.0, 0.0}}, kEarth);
    REQUIRE(chord);
    // Error bound of the grazing sweep below: 4 eps (|o| + R)(1 + R / L) = 0.15 m here.
    REQUIRE_THAT(chord->farDistance - chord->nearDistance, WithinAbs(2.0 * std::sqrt(2.0 * 6378137.0 * 1e-3), 0.15));
}

TEST_CASE("Ray-ellipsoid grazing rays at Earth scale match extended precision", "[core][geometry][intersection][hard]")
{
    // Chords dipping 1 mm to 10 km below the surface, from origins 10 km to 1e9 m away. The
    // scaled inputs carry a rounding of about eps (|o| + R) metres across the ray, which a chord
    // of half-length L magnifies by R / L; the tolerance is 4 times that (the sweep's worst is
    // 0.8 times), plus 4 ulp of the distance. The textbook discriminant b^2 - 4ac reaches 200
    // times this bound on the same rays (see the report).
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double R = kEarth.maximumRadius();
    int hits = 0;
    for (int i = 0; i < 50000; ++i) {
        const Geodetic2D g = randomGeodetic(random);
        const glm::dvec3 p = kEarth.toCartesian(g);
        const glm::dvec3 n = Ellipsoid::geodeticSurfaceNormal(g);
        const glm::dvec3 along = tangentDirection(n, randomUnit(random));
        const double depth = std::pow(10.0, -3.0 + 7.0 * unit(random));
        const double distance = std::pow(10.0, 4.0 + 5.0 * unit(random));
        const Ray ray{p - depth * n - distance * along, along};
        INFO("i " << i << " depth " << depth << " distance " << distance);
        const auto expected = referenceRayEllipsoid(ray.origin, ray.direction, kEarth.radii());
        const auto hit = intersectRayEllipsoid(ray, kEarth);
        REQUIRE(expected.has_value() == hit.has_value());
        if (!hit) {
            continue;
        }
        ++hits;
        const double halfChord = static_cast<double>(expected->farDistance - expected->nearDistance) / 2.0;
        const double tolerance = 4.0 * kEpsilon * (glm::length(ray.origin) + R) * (1.0 + R / halfChord) +
                                 4.0 * kEpsilon * static_cast<double>(expected->farDistance);
        REQUIRE(std::abs(static_cast<double>(Extended(hit->nearDistance) - expected->nearDistance)) <= tolerance);
        REQUIRE(std::abs(static_cast<double>(Extended(hit->farDistance) - expected->farDistance)) <= tolerance);
    }
    REQUIRE(hits > 45000); // a few origins 10 km away fall inside the Earth
}

TEST_CASE("Ray-ellipsoid from 1e9 m away and beyond never returns NaN", "[core][geometry][intersection][hard]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);

    // Head-on from 1e9 m: the entry at 1e9 - a to 2 ulp.
    const glm::dvec3 from = 1e9 * glm::normalize(glm::dvec3(1.0, 2.0, 0.0));
    const auto head = intersectRayEllipsoid({from, -glm::normalize(from)}, kEarth);
    REQUIRE(head);
    REQUIRE_THAT(head->nearDistance, WithinRel(1e9 - kEarth.radii().x, 4 * kEpsilon));

    for (int i = 0; i < 20000; ++i) {
        const double distance = std::pow(10.0, 9.0 + 300.0 * unit(random) * (i % 2));
        const glm::dvec3 origin = distance * randomUnit(random);
        const glm::dvec3 direction = std::pow(10.0, 200.0 * unit(random) - 100.0) * randomUnit(random);
        const auto hit = intersectRayEllipsoid({origin, direction}, kEarth);
        INFO("i " << i);
        if (hit) {
            REQUIRE(std::isfinite(hit->nearDistance));
            REQUIRE(std::isfinite(hit->farDistance));
            REQUIRE(hit->nearDistance <= hit->farDistance);
        }
    }
    // Aimed at the centre from 1e9 m with directions of all sizes: always a hit at the surface.
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 origin = 1e9 * randomUnit(random);
        const double size = std::pow(10.0, 100.0 * unit(random) - 50.0);
        const Ray ray{origin, -size * glm::normalize(origin)};
        const auto hit = intersectRayEllipsoid(ray, kEarth);
        INFO("i " << i << " size " << size);
        REQUIRE(hit);
        // 1e-15 in scaled units is 6 nm; the hit point itself rounds to 1e9 * eps = 0.2 um.
        REQUIRE(std::abs(scaledHeight(ray.pointAt(hit->nearDistance), kEarth)) <= 1e-13);
    }
}

TEST_CASE("Ray-plane intersection, parallel and behind", "[core][geometry][intersection]")
{
    const Plane plane{{0.0, 0.0, 1.0}, -2.0}; // z = 2
    const auto hit = intersectRayPlane({{1.0, 1.0, -2.0}, {0.0, 0.0, 2.0}}, plane);
    REQUIRE(hit);
    REQUIRE(*hit == 2.0);
    REQUIRE(*intersectRayPlane({{5.0, 5.0, 2.0}, {1.0, 0.0, 1.0}}, plane) == 0.0);      // on the plane
    REQUIRE_FALSE(intersectRayPlane({{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}}, plane));        // parallel
    REQUIRE_FALSE(intersectRayPlane({{0.0, 0.0, 2.0}, {1.0, 0.0, 0.0}}, plane));        // lying in it
    REQUIRE_FALSE(intersectRayPlane({{0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}}, plane));       // away
    REQUIRE_FALSE(intersectRayPlane({{0.0, 0.0, 0.0}, {1.0, 0.0, 1e-310}}, plane));     // beyond doubles
}

TEST_CASE("Ray-triangle intersection (Moeller-Trumbore): hits, edges, misses, parallel, degenerate", "[core][geometry][intersection]")
{
    const glm::dvec3 p0(0.0, 0.0, 0.0), p1(4.0, 0.0, 0.0), p2(0.0, 4.0, 0.0);
    const auto hit = intersectRayTriangle({{1.0, 2.0, 5.0}, {0.0, 0.0, -1.0}}, p0, p1, p2);
    REQUIRE(hit);
    REQUIRE(hit->distance == 5.0);
    REQUIRE(hit->u == 0.25);
    REQUIRE(hit->v == 0.5);
    // From behind (both sides count).
    const auto back = intersectRayTriangle({{1.0, 2.0, -5.0}, {0.0, 0.0, 1.0}}, p0, p1, p2);
    REQUIRE(back);
    REQUIRE(back->distance == 5.0);
    // Through a vertex and through an edge: included.
    REQUIRE(intersectRayTriangle({{4.0, 0.0, 1.0}, {0.0, 0.0, -1.0}}, p0, p1, p2));
    REQUIRE(intersectRayTriangle({{2.0, 2.0, 1.0}, {0.0, 0.0, -1.0}}, p0, p1, p2));
    // Misses beyond each edge.
    REQUIRE_FALSE(intersectRayTriangle({{-0.1, 1.0, 1.0}, {0.0, 0.0, -1.0}}, p0, p1, p2));
    REQUIRE_FALSE(intersectRayTriangle({{1.0, -0.1, 1.0}, {0.0, 0.0, -1.0}}, p0, p1, p2));
    REQUIRE_FALSE(intersectRayTriangle({{2.1, 2.0, 1.0}, {0.0, 0.0, -1.0}}, p0, p1, p2));
    // Behind the origin.
    REQUIRE_FALSE(intersectRayTriangle({{1.0, 1.0, 1.0}, {0.0, 0.0, 1.0}}, p0, p1, p2));
    // Parallel, in the plane and beside it; degenerate triangles (a point, collinear points).
    REQUIRE_FALSE(intersectRayTriangle({{-1.0, 1.0, 0.0}, {1.0, 0.0, 0.0}}, p0, p1, p2));
    REQUIRE_FALSE(intersectRayTriangle({{-1.0, 1.0, 1.0}, {1.0, 0.0, 0.0}}, p0, p1, p2));
    REQUIRE_FALSE(intersectRayTriangle({{-1.0, 1.0, 1.0}, {1.0, 0.0, 1e-13}}, p0, p1, p2)); // within 1e-12 rad
    REQUIRE_FALSE(intersectRayTriangle({{0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}}, p0, p0, p0));
    REQUIRE_FALSE(intersectRayTriangle({{1.0, 0.0, 1.0}, {0.0, 0.0, -1.0}}, p0, p1, 2.0 * p1));
    REQUIRE_FALSE(intersectRayTriangle({{1.0, 0.0, 1.0}, {0.0, 0.0, 0.0}}, p0, p1, p2)); // no direction
}

TEST_CASE("Ray-triangle intersection at Earth scale matches extended precision and finds the aimed-at point", "[core][geometry][intersection]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 20000; ++i) {
        // A 10 m triangle on the surface, aimed at from 100 m to 1e7 m away.
        const Geodetic2D g = randomGeodetic(random);
        const glm::dvec3 p0 = kEarth.toCartesian(g);
        const glm::dvec3 n = Ellipsoid::geodeticSurfaceNormal(g);
        const glm::dvec3 e = anyPerpendicular(n);
        const glm::dvec3 f = glm::cross(n, e);
        const glm::dvec3 p1 = p0 + 10.0 * e, p2 = p0 + 10.0 * f;
        double u = unit(random), v = unit(random);
        if (u + v > 1.0) {
            u = 1.0 - u;
            v = 1.0 - v;
        }
        const glm::dvec3 target = (1.0 - u - v) * p0 + u * p1 + v * p2;
        const double distance = std::pow(10.0, 2.0 + 5.0 * unit(random));
        glm::dvec3 direction = randomUnit(random);
        if (glm::dot(direction, n) > -0.1) {
            direction = glm::normalize(direction - (glm::dot(direction, n) + 0.5) * n);
        }
        const Ray ray{target - distance * direction, direction};
        INFO("i " << i << " u " << u << " v " << v << " distance " << distance);
        // The rounded ray's own barycentrics, in extended precision: the construction above rounds
        // by 1e-9 m at this scale, more than the algorithm's error.
        const RayTriangleHit expected = referenceRayTriangle(ray, p0, p1, p2);
        const auto hit = intersectRayTriangle(ray, p0, p1, p2);
        // Tolerance 2e-9 of the 10 m edges (2e-8 m): the edges are differences of 6.4e6 m
        // coordinates, each rounded to 5e-10 m; the sweep's worst is 4.4e-10.
        const bool nearEdge = expected.u < 2e-9 || expected.v < 2e-9 || expected.u + expected.v > 1.0 - 2e-9;
        if (!hit) {
            REQUIRE(nearEdge);
            continue;
        }
        REQUIRE_THAT(hit->u, WithinAbs(expected.u, 2e-9));
        REQUIRE_THAT(hit->v, WithinAbs(expected.v, 2e-9));
        // 8 ulp of the distance plus 2e-8 m across the plane (the ray meets it at least 0.1 rad off).
        REQUIRE_THAT(hit->distance, WithinAbs(expected.distance, 8 * kEpsilon * distance + 2e-7));
        // And the aimed-at point, up to the construction's rounding (1.5e-8 m in the sweep).
        REQUIRE(glm::length(ray.pointAt(hit->distance) - target) <= 8 * kEpsilon * distance + 1e-7);
    }
}
