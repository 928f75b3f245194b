#include "TessellationChecks.h"

#include <orbis/core/CubeMapEllipsoidTessellator.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::size_t poleVertices(const Mesh& mesh)
{
    std::size_t count = 0;
    for (const glm::dvec3& p : mesh.positions) {
        count += p.x == 0.0 && p.y == 0.0 ? 1 : 0;
    }
    return count;
}

std::size_t poleCorners(const Mesh& mesh)
{
    std::size_t count = 0;
    for (const std::uint32_t v : mesh.indices) {
        count += mesh.positions[v].x == 0.0 && mesh.positions[v].y == 0.0 ? 1 : 0;
    }
    return count;
}

} // namespace

TEST_CASE("CubeMapEllipsoidTessellator has 6n^2+2 vertices and 12n^2 triangles", "[core][tessellation]")
{
    for (const CubeMapSpacing spacing : {CubeMapSpacing::Uniform, CubeMapSpacing::EqualAngle}) {
        for (int n = 1; n <= 33; n += (n < 8 ? 1 : 8)) {
            INFO("spacing " << static_cast<int>(spacing) << " partitions " << n);
            const auto size = static_cast<std::size_t>(n);
            const Mesh mesh = CubeMapEllipsoidTessellator::compute(kEarth, n, spacing, EllipsoidProjection::Geocentric,
                                                                   VertexAttributes::Normal, Deviation::Skip).mesh;
            REQUIRE(mesh.positions.size() == 6 * size * size + 2);
            REQUIRE(mesh.triangleCount() == 12 * size * size);
            if (n % 2 == 0) {
                // Texture coordinates add the 2n - 1 antimeridian vertices again, and turn each pole
                // into one vertex per triangle around it.
                const Mesh textured = CubeMapEllipsoidTessellator::compute(
                    kEarth, n, spacing, EllipsoidProjection::Geocentric, VertexAttributes::All, Deviation::Skip).mesh;
                REQUIRE(textured.triangleCount() == 12 * size * size);
                REQUIRE(poleVertices(textured) == poleCorners(textured));
                REQUIRE(textured.positions.size() == 6 * size * size + 2 + (2 * size - 1) + poleCorners(textured) - 2);
                REQUIRE(test::distinctPositions(textured) == mesh.positions.size());
            }
        }
    }
}

TEST_CASE("CubeMapEllipsoidTessellator is closed, outward, on the surface, with finite attributes", "[core][tessellation]")
{
    for (const CubeMapSpacing spacing : {CubeMapSpacing::Uniform, CubeMapSpacing::EqualAngle}) {
        for (const EllipsoidProjection projection : {EllipsoidProjection::Geocentric, EllipsoidProjection::Geodetic}) {
            for (const int n : {1, 2, 3, 8, 32}) {
                INFO("spacing " << static_cast<int>(spacing) << " projection " << static_cast<int>(projection)
                                << " partitions " << n);
                const VertexAttributes attributes = n % 2 == 0 ? VertexAttributes::All : VertexAttributes::Normal;
                const Mesh mesh =
                    CubeMapEllipsoidTessellator::compute(kEarth, n, spacing, projection, attributes, Deviation::Skip).mesh;
                test::requireClosed(mesh);
                // Uniform cells at the face corners have about a fifth of the area of those at the
                // centre; 0.1 of the mean is safe and catches any degenerate triangle.
                test::requireOutwardAndNonDegenerate(mesh, 0.1);
                test::requireOnSurface(mesh, kEarth, 1e-12); // projection rounds to a few ulps
                test::requireGeodeticNormals(mesh, kEarth);
                if (n % 2 == 0) {
                    test::requireGeographicTextureCoordinates(mesh, kEarth);
                }
            }
        }
    }
}

TEST_CASE("CubeMapEllipsoidTessellator puts the poles on face centres and the antimeridian on grid lines",
          "[core][tessellation][hard]")
{
    const int n = 6;
    const Mesh mesh = CubeMapEllipsoidTessellator::compute(kEarth, n, CubeMapSpacing::EqualAngle,
                                                           EllipsoidProjection::Geocentric, VertexAttributes::All,
                                                           Deviation::Skip).mesh;
    std::size_t seamWest = 0;
    std::size_t seamEast = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3& p = mesh.positions[v];
        if (p.x == 0.0 && p.y == 0.0) {
            REQUIRE(std::abs(p.z) == Approx(kEarth.radii().z).epsilon(1e-15));
            REQUIRE(mesh.normals[v] == glm::vec3(0.0f, 0.0f, p.z > 0.0 ? 1.0f : -1.0f));
        } else if (p.y == 0.0 && p.x < 0.0) {
            (mesh.textureCoordinates[v].x == 0.0f ? seamWest : seamEast)++;
        }
    }
    REQUIRE(seamWest == 2 * n - 1);
    REQUIRE(seamEast == 2 * n - 1);
}

TEST_CASE("CubeMapEllipsoidTessellator deviation falls as the faces refine and equal angles do better",
          "[core][tessellation]")
{
    double previousUniform = HUGE_VAL;
    double previousEqualAngle = HUGE_VAL;
    for (int n = 1; n <= 32; n *= 2) {
        INFO("partitions " << n);
        const double uniform = *CubeMapEllipsoidTessellator::compute(kEarth, n, CubeMapSpacing::Uniform).maxDeviationMeters;
        const double equalAngle =
            *CubeMapEllipsoidTessellator::compute(kEarth, n, CubeMapSpacing::EqualAngle).maxDeviationMeters;
        REQUIRE(uniform < previousUniform);
        REQUIRE(equalAngle < previousEqualAngle);
        if (n >= 4) {
            REQUIRE(equalAngle < 0.8 * uniform);
        }
        previousUniform = uniform;
        previousEqualAngle = equalAngle;
    }
}

TEST_CASE("CubeMapEllipsoidTessellator deviation is exact on a sphere", "[core][tessellation]")
{
    const double radius = 6378137.0;
    const Ellipsoid sphere(radius, radius, radius);
    for (const int n : {1, 2, 5, 16}) {
        const TessellationResult result = CubeMapEllipsoidTessellator::compute(sphere, n);
        // 1e-6 relative: the compass search's last step; see the maxDeviationFromEllipsoid tests.
        REQUIRE(*result.maxDeviationMeters == Approx(test::exactSphereDeviation(result.mesh, radius)).epsilon(1e-6));
    }
    // One cell per face: the inscribed cube's faces lie 1/sqrt(3) of the radius from the centre, and
    // the face centre, the deepest point, is the midpoint of the diagonal the two triangles share
    // (a sample, so exact to rounding: 1e-12).
    REQUIRE(*CubeMapEllipsoidTessellator::compute(sphere, 1).maxDeviationMeters ==
            Approx(radius * (1.0 - 1.0 / std::sqrt(3.0))).epsilon(1e-12));
}
