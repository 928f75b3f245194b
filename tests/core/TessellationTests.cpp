#include "TessellationChecks.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Tessellation.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace orbis;

namespace {

Mesh triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    Mesh mesh;
    mesh.positions = {a, b, c};
    mesh.indices = {0, 1, 2};
    return mesh;
}

} // namespace

TEST_CASE("VertexAttributes combine and test as flags", "[core][tessellation]")
{
    constexpr VertexAttributes both = VertexAttributes::Normal | VertexAttributes::TextureCoordinate;
    STATIC_REQUIRE(both == VertexAttributes::All);
    STATIC_REQUIRE(contains(both, VertexAttributes::Normal));
    STATIC_REQUIRE(contains(both, VertexAttributes::Position));
    STATIC_REQUIRE(!contains(VertexAttributes::Normal, VertexAttributes::TextureCoordinate));
    STATIC_REQUIRE(!contains(VertexAttributes::Position, VertexAttributes::Normal));
}

TEST_CASE("maxDeviationFromEllipsoid equals the chord sag R(1 - cos(theta/2)) of an edge on a sphere",
          "[core][tessellation]")
{
    // A triangle obtuse at its third corner: the deepest point is the midpoint of the long edge,
    // theta wide on the equator, so the deviation is that edge's chord sag.
    const double radius = 6378137.0;
    const Ellipsoid sphere(radius, radius, radius);
    for (const double theta : {1e-4, 1e-3, 0.01, 0.1, 0.5, 1.0, 2.0}) {
        const glm::dvec3 a = sphere.toCartesian(Geodetic2D{-0.5 * theta, 0.0});
        const glm::dvec3 b = sphere.toCartesian(Geodetic2D{0.5 * theta, 0.0});
        const glm::dvec3 c = sphere.toCartesian(Geodetic2D{0.0, 0.1 * theta});
        const double sag = radius * (1.0 - std::cos(0.5 * theta));
        INFO("theta " << theta);
        // The midpoint is one of the samples; both sides round the 6.4e6 m distances to about 1 nm,
        // so 10 nm + 1e-12 relative.
        REQUIRE(maxDeviationFromEllipsoid(triangle(a, b, c), sphere) == Approx(sag).epsilon(1e-12).margin(10e-9));
    }
}

TEST_CASE("maxDeviationFromEllipsoid finds the deepest interior point of an octahedron face", "[core][tessellation]")
{
    // Equilateral face (1,0,0), (0,1,0), (0,0,1) of the unit sphere's octahedron: the plane is
    // 1/sqrt(3) from the centre, the sag of the circumscribed circle's diameter.
    const Ellipsoid unit = Ellipsoid::unitSphere();
    REQUIRE(maxDeviationFromEllipsoid(triangle({1, 0, 0}, {0, 1, 0}, {0, 0, 1}), unit) ==
            Approx(1.0 - 1.0 / std::sqrt(3.0)).epsilon(1e-14));
}

TEST_CASE("maxDeviationFromEllipsoid matches the exact depth of random triangles inscribed in a sphere",
          "[core][tessellation]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const double radius = 6378137.0;
    const Ellipsoid sphere(radius, radius, radius);
    for (int i = 0; i < 2000; ++i) {
        // Triangles from nearly a hemisphere down to 100 m, acute and obtuse, both windings.
        const double size = std::pow(10.0, -4.5 * (0.5 * unit(random) + 0.5));
        const glm::dvec3 centre = glm::normalize(glm::dvec3(unit(random), unit(random), unit(random)));
        glm::dvec3 corner[3];
        for (glm::dvec3& p : corner) {
            p = radius * glm::normalize(centre + size * glm::dvec3(unit(random), unit(random), unit(random)));
        }
        const Mesh mesh = triangle(corner[0], corner[1], corner[2]);
        const double exact = test::exactSphereDeviation(mesh, radius);
        INFO("triangle " << i << " size " << size);
        // Compass-search steps of 2^-13 of the edges leave the depth low by about 4 * step^2 = 6e-8
        // relative; 1e-6 relative plus 10 nm (both sides subtract 6.4e6 m lengths, whose ulp is
        // 1 nm) is the stated tolerance.
        const double measured = maxDeviationFromEllipsoid(mesh, sphere);
        REQUIRE(measured == Approx(exact).epsilon(1e-6).margin(1e-8));
        // Never above the exact value beyond rounding: an ulp of 6.4e6 m is 1 nm, so 10 nm.
        REQUIRE(measured <= exact + 1e-8);
    }
}

TEST_CASE("maxDeviationFromEllipsoid on WGS84 agrees with a dense barycentric grid", "[core][tessellation]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Ellipsoid earth = Ellipsoid::wgs84();
    for (int i = 0; i < 20; ++i) {
        // 0.5 to 1e-3 rad across: far from the centre's 43 km disc where points have several normals
        // and the depth has a ridge instead of a smooth maximum.
        const double size = 0.5 * std::pow(10.0, -2.7 * (0.5 * unit(random) + 0.5));
        const glm::dvec3 centre = glm::normalize(glm::dvec3(unit(random), unit(random), unit(random)));
        glm::dvec3 corner[3];
        for (glm::dvec3& p : corner) {
            p = earth.scaleToGeodeticSurface(earth.radii() *
                                             (centre + size * glm::dvec3(unit(random), unit(random), unit(random))));
        }
        // The dense grid (steps of 1/300) is a lower bound, low by about 4 / 300^2 = 5e-5 relative
        // near a smooth maximum: the measure must be at least it and at most 1e-4 above it.
        constexpr int steps = 300;
        double dense = 0.0;
        for (int s = 0; s <= steps; ++s) {
            for (int t = 0; s + t <= steps; ++t) {
                const glm::dvec3 p = corner[0] + (static_cast<double>(s) / steps) * (corner[1] - corner[0]) +
                                     (static_cast<double>(t) / steps) * (corner[2] - corner[0]);
                dense = std::max(dense, std::abs(earth.toGeodetic3D(p).height));
            }
        }
        const double measured = maxDeviationFromEllipsoid(triangle(corner[0], corner[1], corner[2]), earth);
        INFO("triangle " << i << " size " << size << " dense " << dense << " measured " << measured);
        REQUIRE(measured >= dense - 1e-9);
        REQUIRE(measured <= dense * (1.0 + 1e-4) + 1e-9);
    }
}

TEST_CASE("maxDeviationFromEllipsoid is 0 without triangles and finds the corners of an outside triangle",
          "[core][tessellation]")
{
    const Ellipsoid unit = Ellipsoid::unitSphere();
    REQUIRE(maxDeviationFromEllipsoid(Mesh{}, unit) == 0.0);
    Mesh lines = triangle({2, 0, 0}, {0, 2, 0}, {0, 0, 2});
    lines.primitiveType = PrimitiveType::Lines;
    REQUIRE(maxDeviationFromEllipsoid(lines, unit) == 0.0);
    // Tangent plane z = 1: the distance sqrt(1 + d^2) - 1 peaks at the farthest corner, d = 2.
    REQUIRE(maxDeviationFromEllipsoid(triangle({0, 0, 1}, {2, 0, 1}, {0, 1, 1}), unit) ==
            Approx(std::sqrt(5.0) - 1.0).epsilon(1e-14));
}
