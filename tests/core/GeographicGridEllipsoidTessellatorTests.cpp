#include "TessellationChecks.h"

#include <orbis/core/GeographicGridEllipsoidTessellator.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

} // namespace

TEST_CASE("GeographicGridEllipsoidTessellator has the formula's vertex and triangle counts", "[core][tessellation]")
{
    for (const auto& [slices, stacks] : {std::pair{3, 2}, {4, 3}, {8, 4}, {36, 18}, {7, 5}}) {
        INFO(slices << " x " << stacks);
        const auto s = static_cast<std::size_t>(slices);
        const auto t = static_cast<std::size_t>(stacks);
        const Mesh plain =
            GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, VertexAttributes::Normal, Deviation::Skip).mesh;
        REQUIRE(plain.positions.size() == 2 + s * (t - 1));
        REQUIRE(plain.triangleCount() == 2 * s * (t - 1));
        const Mesh textured =
            GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, VertexAttributes::All, Deviation::Skip).mesh;
        REQUIRE(textured.positions.size() == (s + 1) * (t - 1) + 2 * s);
        REQUIRE(textured.triangleCount() == 2 * s * (t - 1));
        REQUIRE(test::distinctPositions(textured) == plain.positions.size());
    }
}

TEST_CASE("GeographicGridEllipsoidTessellator is closed, outward, on the surface, with finite attributes",
          "[core][tessellation]")
{
    for (const auto& [slices, stacks] : {std::pair{3, 2}, {8, 4}, {64, 32}, {9, 7}, {256, 128}}) {
        INFO(slices << " x " << stacks);
        for (const VertexAttributes attributes : {VertexAttributes::Position, VertexAttributes::All}) {
            const Mesh mesh =
                GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, attributes, Deviation::Skip).mesh;
            test::requireClosed(mesh);
            // The pole fans are the smallest triangles, about pi/2 * (pi / stacks) of the mean area
            // (0.04 at 128 stacks): 1e-3 of the mean catches any zero-area or collapsed triangle.
            test::requireOutwardAndNonDegenerate(mesh, 1e-3);
            // toCartesian is exact to a few nanometres: 1e-15 relative.
            test::requireOnSurface(mesh, kEarth, 1e-15);
        }
        const Mesh mesh =
            GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, VertexAttributes::All, Deviation::Skip).mesh;
        test::requireGeodeticNormals(mesh, kEarth);
        test::requireGeographicTextureCoordinates(mesh, kEarth);
    }
}

TEST_CASE("GeographicGridEllipsoidTessellator poles are single vertices or fans without NaN", "[core][tessellation][hard]")
{
    const int slices = 16;
    const int stacks = 8;
    const Mesh plain =
        GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, VertexAttributes::Normal, Deviation::Skip).mesh;
    REQUIRE(plain.positions.front() == glm::dvec3(0.0, 0.0, -kEarth.radii().z));
    REQUIRE(plain.positions.back() == glm::dvec3(0.0, 0.0, kEarth.radii().z));
    REQUIRE(plain.normals.front() == glm::vec3(0, 0, -1));
    REQUIRE(plain.normals.back() == glm::vec3(0, 0, 1));
    std::size_t northFan = 0;
    for (std::size_t i = 0; i < plain.indices.size(); ++i) {
        northFan += plain.indices[i] == plain.positions.size() - 1 ? 1 : 0;
    }
    REQUIRE(northFan == slices);

    const Mesh textured =
        GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, VertexAttributes::All, Deviation::Skip).mesh;
    for (int j = 0; j < slices; ++j) {
        // One south and one north pole vertex per fan triangle, u at the middle of its slice.
        const glm::vec2 south = textured.textureCoordinates[static_cast<std::size_t>(j)];
        const glm::vec2 north = textured.textureCoordinates[textured.positions.size() - slices + static_cast<std::size_t>(j)];
        REQUIRE(south == glm::vec2(static_cast<float>((j + 0.5) / slices), 0.0f));
        REQUIRE(north == glm::vec2(static_cast<float>((j + 0.5) / slices), 1.0f));
    }
}

TEST_CASE("GeographicGridEllipsoidTessellator duplicates the antimeridian column", "[core][tessellation][hard]")
{
    const int slices = 12;
    const int stacks = 6;
    const Mesh mesh =
        GeographicGridEllipsoidTessellator::compute(kEarth, slices, stacks, VertexAttributes::All, Deviation::Skip).mesh;
    const std::size_t ringSize = slices + 1;
    for (std::size_t r = 0; r + 1 < stacks; ++r) {
        const std::size_t first = slices + r * ringSize;
        const std::size_t last = first + slices;
        REQUIRE(mesh.positions[first] == mesh.positions[last]);
        REQUIRE(mesh.normals[first] == mesh.normals[last]);
        REQUIRE(mesh.textureCoordinates[first].x == 0.0f);
        REQUIRE(mesh.textureCoordinates[last].x == 1.0f);
        REQUIRE(mesh.textureCoordinates[first].y == mesh.textureCoordinates[last].y);
        // Exactly on the antimeridian: y is 0, not sin(pi) * 6.4e6 m = 8e-10 m.
        REQUIRE(mesh.positions[first].x < 0.0);
        REQUIRE(mesh.positions[first].y == 0.0);
        REQUIRE(mesh.normals[first].y == 0.0f);
        REQUIRE(kEarth.toGeodetic2D(mesh.positions[first]).longitude == kPi);
    }
}

TEST_CASE("GeographicGridEllipsoidTessellator deviation falls as the grid refines and is exact on a sphere",
          "[core][tessellation]")
{
    double previous = HUGE_VAL;
    for (int stacks = 4; stacks <= 64; stacks *= 2) {
        INFO("stacks " << stacks);
        const double deviation = *GeographicGridEllipsoidTessellator::compute(kEarth, 2 * stacks, stacks).maxDeviationMeters;
        REQUIRE(deviation < previous);
        previous = deviation;
    }
    const double radius = 6378137.0;
    const Ellipsoid sphere(radius, radius, radius);
    for (const auto& [slices, stacks] : {std::pair{3, 2}, {8, 4}, {32, 16}, {20, 3}}) {
        INFO(slices << " x " << stacks);
        const TessellationResult result = GeographicGridEllipsoidTessellator::compute(sphere, slices, stacks);
        // 1e-6 relative: the compass search's last step; see the maxDeviationFromEllipsoid tests.
        REQUIRE(*result.maxDeviationMeters == Approx(test::exactSphereDeviation(result.mesh, radius)).epsilon(1e-6));
    }
}
