#include <orbis/core/TileMesh.h>
#include <orbis/core/TilingScheme.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <map>
#include <utility>

using orbis::Ellipsoid;
using orbis::GeodeticExtent;
using orbis::TileMesh;

namespace {

glm::dvec3 vertexPosition(const TileMesh& mesh, std::size_t index)
{
    const float* v = &mesh.vertices[index * TileMesh::kFloatsPerVertex];
    return mesh.centre + glm::dvec3(v[0], v[1], v[2]);
}

} // namespace

TEST_CASE("TileMesh puts each grid vertex at its longitude, latitude and height", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const GeodeticExtent extent = orbis::TilingScheme::geographic().tileExtent({9, 520, 300});
    std::vector<float> heights(5 * 4);
    for (std::size_t k = 0; k < heights.size(); ++k) {
        heights[k] = static_cast<float>(100.0 * static_cast<double>(k) - 700.0);
    }
    const TileMesh mesh = TileMesh::build(wgs84, extent, 5, 4, heights, 0.0);
    REQUIRE(mesh.vertexCount() == 20);
    CHECK(mesh.minimumHeight == -700.0);
    CHECK(mesh.maximumHeight == 1200.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 5; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * 5 + i;
            const orbis::Geodetic3D expected(extent.west + extent.width() * i / 4, extent.north - extent.height() * j / 3,
                                             heights[index]);
            INFO("i " << i << " j " << j);
            // Floats relative to a centre some 30 km away: a few millimetres.
            CHECK(glm::length(vertexPosition(mesh, index) - wgs84.toCartesian(expected)) < 0.004);
            const float* v = &mesh.vertices[index * TileMesh::kFloatsPerVertex];
            CHECK(v[3] == Approx(i / 4.0));
            CHECK(v[4] == Approx(1.0 - j / 3.0));
            CHECK(v[5] == heights[index]);
        }
    }
}

TEST_CASE("TileMesh indices cover the grid once, counter-clockwise from above, skirts facing out", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const GeodeticExtent extent = orbis::TilingScheme::geographic().tileExtent({4, 3, 9});
    const TileMesh mesh = TileMesh::build(wgs84, extent, 9, 7, {}, 500.0);
    const std::vector<std::uint32_t> indices = TileMesh::indices(9, 7, true);
    REQUIRE(mesh.vertexCount() == 9 * 7 + 2 * (9 + 7));
    REQUIRE(indices.size() == 6 * (8 * 6 + 2 * (8 + 6)));
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        const glm::dvec3 a = vertexPosition(mesh, indices[t]);
        const glm::dvec3 b = vertexPosition(mesh, indices[t + 1]);
        const glm::dvec3 c = vertexPosition(mesh, indices[t + 2]);
        const glm::dvec3 normal = glm::cross(b - a, c - a);
        const glm::dvec3 middle = (a + b + c) / 3.0;
        const glm::dvec3 up = wgs84.geodeticSurfaceNormal(middle);
        REQUIRE(glm::length(normal) > 0.0);
        if (t < 6 * 8 * 6) {
            CHECK(glm::dot(normal, up) > 0.0); // the grid faces up
        } else {
            // A skirt wall faces away from the tile's centre and stands vertical.
            const glm::dvec3 outwards = middle - mesh.centre;
            CHECK(glm::dot(normal, outwards - glm::dot(outwards, up) * up) > 0.0);
            CHECK(std::abs(glm::dot(glm::normalize(normal), up)) < 0.05);
        }
        for (int e = 0; e < 3; ++e) {
            ++edges[{indices[t + e], indices[t + (e + 1) % 3]}];
        }
    }
    // Every directed edge once: no triangle repeated or flipped.
    for (const auto& [edge, count] : edges) {
        CHECK(count == 1);
    }
    // The skirt hangs 500 m below the edge (floats some 900 km from the centre: a few centimetres).
    const std::size_t firstSkirt = 9 * 7;
    CHECK(glm::length(vertexPosition(mesh, firstSkirt) - vertexPosition(mesh, 0)) == Approx(500.0).margin(0.05));
}

TEST_CASE("TileMesh at a pole collapses the polar row to one point, with no NaN", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const GeodeticExtent polar = orbis::TilingScheme::geographic().tileExtent({2, 5, 3});
    REQUIRE(polar.north == orbis::kHalfPi);
    const TileMesh mesh = TileMesh::build(wgs84, polar, 17, 17, {}, 1000.0);
    for (float f : mesh.vertices) {
        REQUIRE(std::isfinite(f));
    }
    for (int i = 1; i < 17; ++i) {
        CHECK(glm::length(vertexPosition(mesh, i) - vertexPosition(mesh, 0)) < 0.5);
    }
    CHECK(glm::length(vertexPosition(mesh, 0) - glm::dvec3(0.0, 0.0, wgs84.radii().z)) < 0.5);
}
