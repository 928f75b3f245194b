#include "TessellationChecks.h"

#include <orbis/core/SubdivisionSphereTessellator.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>

using namespace orbis;

TEST_CASE("SubdivisionSphereTessellator has 4*4^n+2 vertices and 8*4^n triangles", "[core][tessellation]")
{
    for (int n = 0; n <= 6; ++n) {
        const std::size_t power = std::size_t{1} << (2 * n);
        const Mesh plain = SubdivisionSphereTessellator::compute(n, 1.0, VertexAttributes::Normal, Deviation::Skip).mesh;
        REQUIRE(plain.positions.size() == 4 * power + 2);
        REQUIRE(plain.normals.size() == plain.positions.size());
        REQUIRE(plain.textureCoordinates.empty());
        REQUIRE(plain.triangleCount() == 8 * power);
        // Texture coordinates add 2^(n+1) - 1 antimeridian copies and 3 copies of each pole.
        const Mesh textured = SubdivisionSphereTessellator::compute(n, 1.0, VertexAttributes::All, Deviation::Skip).mesh;
        REQUIRE(textured.positions.size() == 4 * power + 2 + ((std::size_t{2} << n) - 1) + 6);
        REQUIRE(textured.triangleCount() == 8 * power);
        REQUIRE(test::distinctPositions(textured) == plain.positions.size());
    }
}

TEST_CASE("SubdivisionSphereTessellator is closed, outward, on the sphere, with radial normals", "[core][tessellation]")
{
    const double radius = 6378137.0;
    const Ellipsoid sphere(radius, radius, radius);
    for (int n = 0; n <= 5; ++n) {
        INFO("subdivisions " << n);
        for (const VertexAttributes attributes : {VertexAttributes::Position, VertexAttributes::All}) {
            const Mesh mesh = SubdivisionSphereTessellator::compute(n, radius, attributes, Deviation::Skip).mesh;
            test::requireClosed(mesh);
            // Octahedron subdivision keeps triangle areas within a factor of ~2: 0.3 of the mean is safe.
            test::requireOutwardAndNonDegenerate(mesh, 0.3);
            // 1e-12 relative (6 micrometres here): normalising and scaling round to a few ulps.
            test::requireOnSurface(mesh, sphere, 1e-12);
        }
        const Mesh mesh = SubdivisionSphereTessellator::compute(n, radius, VertexAttributes::All, Deviation::Skip).mesh;
        test::requireGeodeticNormals(mesh, sphere);
        test::requireGeographicTextureCoordinates(mesh, sphere);
    }
}

TEST_CASE("SubdivisionSphereTessellator deviation is the exact sag and falls about fourfold per level",
          "[core][tessellation]")
{
    const double radius = 6378137.0;
    double previous = HUGE_VAL;
    for (int n = 0; n <= 6; ++n) {
        INFO("subdivisions " << n);
        const TessellationResult result = SubdivisionSphereTessellator::compute(n, radius);
        REQUIRE(result.maxDeviationMeters.has_value());
        const double deviation = *result.maxDeviationMeters;
        // 1e-6 relative: the compass search's last step; see the maxDeviationFromEllipsoid tests.
        REQUIRE(deviation == Approx(test::exactSphereDeviation(result.mesh, radius)).epsilon(1e-6));
        // Never less than any edge's chord sag R(1 - cos(theta/2)): edge midpoints are on the mesh.
        double edgeSag = 0.0;
        for (std::size_t t = 0; t < result.mesh.indices.size(); t += 3) {
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3& a = result.mesh.positions[result.mesh.indices[t + k]];
                const glm::dvec3& b = result.mesh.positions[result.mesh.indices[t + (k + 1) % 3]];
                const double theta = std::acos(std::clamp(glm::dot(a, b) / (radius * radius), -1.0, 1.0));
                edgeSag = std::max(edgeSag, radius * (1.0 - std::cos(0.5 * theta)));
            }
        }
        REQUIRE(deviation >= edgeSag * (1.0 - 1e-9));
        REQUIRE(deviation < previous);
        if (n >= 3) {
            // Halving every edge quarters the sag once the triangles are small.
            REQUIRE(previous / deviation == Approx(4.0).margin(0.3));
        }
        previous = deviation;
    }
    // Level 0: the octahedron's faces lie 1/sqrt(3) of the radius from the centre.
    REQUIRE(*SubdivisionSphereTessellator::compute(0, radius).maxDeviationMeters ==
            Approx(radius * (1.0 - 1.0 / std::sqrt(3.0))).epsilon(1e-12));
}

TEST_CASE("SubdivisionSphereTessellator splits the poles and the antimeridian for texture coordinates",
          "[core][tessellation][hard]")
{
    const Mesh mesh = SubdivisionSphereTessellator::compute(3, 1.0, VertexAttributes::All, Deviation::Skip).mesh;
    std::set<float> northU;
    std::size_t seamEast = 0;
    std::size_t seamWest = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3& p = mesh.positions[v];
        if (p == glm::dvec3(0, 0, 1)) {
            REQUIRE(mesh.textureCoordinates[v].y == 1.0f);
            REQUIRE(mesh.normals[v] == glm::vec3(0, 0, 1));
            northU.insert(mesh.textureCoordinates[v].x);
        } else if (p.y == 0.0 && p.x < 0.0) {
            (mesh.textureCoordinates[v].x == 0.0f ? seamWest : seamEast)++;
        }
    }
    // Four triangles meet at the pole, one copy each, u at the middle of each quadrant.
    REQUIRE(northU == std::set<float>{0.125f, 0.375f, 0.625f, 0.875f});
    REQUIRE(seamEast == 15);
    REQUIRE(seamWest == 15);
}
