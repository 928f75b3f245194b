#include "TessellationChecks.h"

#include <orbis/core/RectangleTessellator.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;

TEST_CASE("RectangleTessellator grid has (px+1)(py+1) vertices and 2 px py triangles facing +z", "[core][tessellation]")
{
    for (const auto& [px, py] : {std::pair{1, 1}, {3, 2}, {16, 9}}) {
        INFO(px << " x " << py);
        const Mesh mesh = RectangleTessellator::computeGrid({-2.0, 1.0}, {3.0, 4.0}, px, py, VertexAttributes::All);
        REQUIRE(mesh.positions.size() == static_cast<std::size_t>((px + 1) * (py + 1)));
        REQUIRE(mesh.triangleCount() == static_cast<std::size_t>(2 * px * py));
        REQUIRE(mesh.positions.front() == glm::dvec3(-2.0, 1.0, 0.0));
        REQUIRE(mesh.positions.back() == glm::dvec3(3.0, 4.0, 0.0));
        REQUIRE(mesh.textureCoordinates.front() == glm::vec2(0.0f, 0.0f));
        REQUIRE(mesh.textureCoordinates.back() == glm::vec2(1.0f, 1.0f));
        double area = 0.0;
        for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
            const glm::dvec3& a = mesh.positions[mesh.indices[t]];
            const glm::dvec3 n = glm::cross(mesh.positions[mesh.indices[t + 1]] - a, mesh.positions[mesh.indices[t + 2]] - a);
            REQUIRE(n.z > 0.0); // counter-clockwise seen from +z
            area += 0.5 * n.z;
        }
        REQUIRE(area == Approx(15.0).epsilon(1e-14)); // 5 x 3, no overlap, no gap
        for (const glm::vec3& n : mesh.normals) {
            REQUIRE(n == glm::vec3(0.0f, 0.0f, 1.0f));
        }
    }
}

TEST_CASE("RectangleTessellator tangent patch touches the surface at its centre, also at the pole",
          "[core][tessellation][hard]")
{
    const double radius = 6378137.0;
    const Ellipsoid sphere(radius, radius, radius);
    const glm::dvec2 size(200e3, 100e3);
    for (const Geodetic2D centre : {Geodetic2D::fromDegrees(10.0, 45.0), Geodetic2D::fromDegrees(180.0, 90.0),
                                    Geodetic2D::fromDegrees(-30.0, -90.0)}) {
        const TessellationResult result = RectangleTessellator::compute(sphere, centre, size, 4, 2, VertexAttributes::All);
        const Mesh& mesh = result.mesh;
        const glm::dvec3 up = Ellipsoid::geodeticSurfaceNormal(centre);
        // Centre vertex (2, 1) is the surface point; 1 nm of rounding.
        REQUIRE(glm::length(mesh.positions[1 * 5 + 2] - sphere.toCartesian(centre)) <= 1e-9);
        for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
            REQUIRE(isFinite(mesh.positions[v]));
            REQUIRE(glm::length(glm::dvec3(mesh.normals[v]) - up) <= 1e-7); // float rounding
        }
        for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
            const glm::dvec3& a = mesh.positions[mesh.indices[t]];
            const glm::dvec3 n = glm::cross(mesh.positions[mesh.indices[t + 1]] - a, mesh.positions[mesh.indices[t + 2]] - a);
            REQUIRE(glm::dot(n, up) > 0.0);
        }
        // The corners are sqrt(R^2 + d^2) - R from the sphere, d the half diagonal; 1e-9 relative
        // (the difference of two 6.4e6 m lengths loses about 1e-9 of the 1 km answer).
        const double d = 0.5 * glm::length(size);
        REQUIRE(*result.maxDeviationMeters == Approx(std::hypot(radius, d) - radius).epsilon(1e-9));
    }
}
