#include "TessellationChecks.h"

#include <orbis/core/BoxTessellator.h>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;

TEST_CASE("BoxTessellator bounds the ellipsoid with 8 or 24 vertices and 12 outward triangles", "[core][tessellation]")
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    const Mesh corners = BoxTessellator::compute(earth, VertexAttributes::Position, Deviation::Skip).mesh;
    REQUIRE(corners.positions.size() == 8);
    REQUIRE(corners.triangleCount() == 12);
    test::requireClosed(corners);
    // Every triangle is half a face: equal areas on a cube, within the radii's ratio here.
    test::requireOutwardAndNonDegenerate(corners, 0.9);
    for (const glm::dvec3& p : corners.positions) {
        REQUIRE(glm::abs(p) == earth.radii());
    }

    const Mesh faces = BoxTessellator::compute(earth, VertexAttributes::All, Deviation::Skip).mesh;
    REQUIRE(faces.positions.size() == 24);
    REQUIRE(faces.normals.size() == 24);
    REQUIRE(faces.textureCoordinates.size() == 24);
    REQUIRE(faces.triangleCount() == 12);
    test::requireClosed(faces);
    test::requireOutwardAndNonDegenerate(faces, 0.9);
    for (std::size_t t = 0; t < faces.indices.size(); t += 3) {
        const glm::dvec3& a = faces.positions[faces.indices[t]];
        const glm::dvec3 normal =
            glm::normalize(glm::cross(faces.positions[faces.indices[t + 1]] - a, faces.positions[faces.indices[t + 2]] - a));
        for (int k = 0; k < 3; ++k) {
            REQUIRE(glm::length(glm::dvec3(faces.normals[faces.indices[t + k]]) - normal) <= 1e-15); // normalising rounds
            const glm::vec2 st = faces.textureCoordinates[faces.indices[t + k]];
            REQUIRE((st.x == 0.0f || st.x == 1.0f));
            REQUIRE((st.y == 0.0f || st.y == 1.0f));
        }
    }
}

TEST_CASE("BoxTessellator deviation is the corners' distance from the ellipsoid", "[core][tessellation]")
{
    // Unit sphere: the corner (1, 1, 1) is sqrt(3) - 1 from the surface.
    REQUIRE(*BoxTessellator::compute(Ellipsoid::unitSphere()).maxDeviationMeters ==
            Approx(std::sqrt(3.0) - 1.0).epsilon(1e-14));
    const Ellipsoid earth = Ellipsoid::wgs84();
    REQUIRE(*BoxTessellator::compute(earth).maxDeviationMeters ==
            Approx(earth.toGeodetic3D(earth.radii()).height).epsilon(1e-14));
}

TEST_CASE("BoxTessellator::cube has 8 corners around its centre and 12 outward triangles", "[core][tessellation]")
{
    const glm::dvec3 centre(6378137.0, -20.0, 0.5);
    const Mesh cube = BoxTessellator::cube(centre, 2.0);
    REQUIRE(cube.positions.size() == 8);
    REQUIRE(cube.triangleCount() == 12);
    REQUIRE(cube.normals.empty());
    test::requireClosed(cube);
    Mesh atOrigin = cube; // outward is away from the origin for the check
    for (glm::dvec3& p : atOrigin.positions) {
        REQUIRE(glm::abs(p - centre) == glm::dvec3(2.0)); // exact: the offsets are powers of two here
        p -= centre;
    }
    test::requireOutwardAndNonDegenerate(atOrigin, 0.99);
}
