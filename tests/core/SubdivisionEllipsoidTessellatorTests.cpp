#include "TessellationChecks.h"

#include <orbis/core/SubdivisionEllipsoidTessellator.h>
#include <orbis/core/SubdivisionSphereTessellator.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

} // namespace

TEST_CASE("SubdivisionEllipsoidTessellator is closed, outward and on WGS84 for both projections", "[core][tessellation]")
{
    for (const EllipsoidProjection projection : {EllipsoidProjection::Geocentric, EllipsoidProjection::Geodetic}) {
        for (int n = 0; n <= 5; ++n) {
            INFO("projection " << static_cast<int>(projection) << " subdivisions " << n);
            const std::size_t power = std::size_t{1} << (2 * n);
            const Mesh plain = SubdivisionEllipsoidTessellator::compute(kEarth, n, projection, VertexAttributes::Position,
                                                                        Deviation::Skip).mesh;
            REQUIRE(plain.positions.size() == 4 * power + 2);
            REQUIRE(plain.triangleCount() == 8 * power);
            test::requireClosed(plain);
            test::requireOutwardAndNonDegenerate(plain, 0.3);
            // 1e-12 relative (6 micrometres): projection rounds to a few ulps, and the yardstick is exact.
            test::requireOnSurface(plain, kEarth, 1e-12);

            const Mesh mesh =
                SubdivisionEllipsoidTessellator::compute(kEarth, n, projection, VertexAttributes::All, Deviation::Skip).mesh;
            REQUIRE(mesh.positions.size() == 4 * power + 2 + ((std::size_t{2} << n) - 1) + 6);
            test::requireClosed(mesh);
            test::requireOutwardAndNonDegenerate(mesh, 0.3);
            test::requireGeodeticNormals(mesh, kEarth);
            test::requireGeographicTextureCoordinates(mesh, kEarth);
        }
    }
}

TEST_CASE("SubdivisionEllipsoidTessellator projects the sphere's vertices as asked", "[core][tessellation]")
{
    const Mesh sphere = SubdivisionSphereTessellator::compute(4, 1.0, VertexAttributes::Position, Deviation::Skip).mesh;
    const Mesh geocentric = SubdivisionEllipsoidTessellator::compute(kEarth, 4, EllipsoidProjection::Geocentric,
                                                                      VertexAttributes::Position, Deviation::Skip).mesh;
    const Mesh geodetic = SubdivisionEllipsoidTessellator::compute(kEarth, 4, EllipsoidProjection::Geodetic,
                                                                   VertexAttributes::Position, Deviation::Skip).mesh;
    REQUIRE(geocentric.indices == sphere.indices);
    REQUIRE(geodetic.indices == sphere.indices);
    for (std::size_t v = 0; v < sphere.positions.size(); ++v) {
        // Directions agree to rounding: 1e-15 for unit vectors.
        REQUIRE(glm::length(glm::normalize(geocentric.positions[v]) - sphere.positions[v]) <= 1e-15);
        REQUIRE(glm::length(kEarth.geodeticSurfaceNormal(geodetic.positions[v]) - sphere.positions[v]) <= 1e-15);
    }
}

TEST_CASE("SubdivisionEllipsoidTessellator keeps the poles exact and finite", "[core][tessellation][hard]")
{
    const Mesh mesh = SubdivisionEllipsoidTessellator::compute(kEarth, 4, EllipsoidProjection::Geodetic,
                                                               VertexAttributes::All, Deviation::Skip).mesh;
    int poles = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3& p = mesh.positions[v];
        if (p.x == 0.0 && p.y == 0.0) {
            ++poles;
            REQUIRE(std::abs(p.z) == Approx(kEarth.radii().z).epsilon(1e-15));
            REQUIRE(mesh.normals[v] == glm::vec3(0.0f, 0.0f, p.z > 0.0 ? 1.0f : -1.0f));
        }
    }
    REQUIRE(poles == 8); // four triangles meet at each pole, one copy each
}

TEST_CASE("SubdivisionEllipsoidTessellator deviation falls with every level", "[core][tessellation]")
{
    for (const EllipsoidProjection projection : {EllipsoidProjection::Geocentric, EllipsoidProjection::Geodetic}) {
        double previous = HUGE_VAL;
        for (int n = 0; n <= 6; ++n) {
            INFO("projection " << static_cast<int>(projection) << " subdivisions " << n);
            const double deviation = *SubdivisionEllipsoidTessellator::compute(kEarth, n, projection).maxDeviationMeters;
            REQUIRE(deviation < previous);
            if (n >= 3) {
                REQUIRE(previous / deviation == Approx(4.0).margin(0.3));
            }
            previous = deviation;
        }
        // At 6 levels (32768 triangles) the globe is within 1.6 km of WGS84.
        REQUIRE(previous < 1600.0);
    }
}

TEST_CASE("SubdivisionEllipsoidTessellator works on a triaxial ellipsoid", "[core][tessellation]")
{
    const Ellipsoid triaxial(3.0, 2.0, 1.0);
    const TessellationResult result =
        SubdivisionEllipsoidTessellator::compute(triaxial, 3, EllipsoidProjection::Geodetic, VertexAttributes::All);
    test::requireClosed(result.mesh);
    test::requireOutwardAndNonDegenerate(result.mesh, 0.05);
    test::requireOnSurface(result.mesh, triaxial, 1e-12);
    test::requireGeodeticNormals(result.mesh, triaxial);
    REQUIRE(*result.maxDeviationMeters > 0.0);
    REQUIRE(*result.maxDeviationMeters < 0.1);
}
