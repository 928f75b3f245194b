#include <orbis/core/TileMesh.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <cmath>

#include <array>
#include <map>
#include <set>
#include <tuple>
#include <utility>

using orbis::EdgeCoarsening;
using orbis::Ellipsoid;
using orbis::GeodeticExtent;
using orbis::TileKey;
using orbis::TileMesh;
using orbis::TilingScheme;

namespace {

using Point = std::tuple<double, double, double>;
using Segment = std::pair<Point, Point>;

Point point(const glm::dvec3& p)
{
    return {p.x, p.y, p.z};
}

/// The directed edges of the triangles that no other triangle of the same list shares backwards:
/// the mesh's boundary, as positions.
std::set<Segment> boundary(const TileMesh& mesh, const std::vector<std::uint32_t>& indices)
{
    std::map<Segment, int> directed;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        for (int e = 0; e < 3; ++e) {
            const Point a = point(mesh.position(indices[t + e]));
            const Point b = point(mesh.position(indices[t + (e + 1) % 3]));
            ++directed[{a, b}];
        }
    }
    std::set<Segment> open;
    for (const auto& [segment, count] : directed) {
        REQUIRE(count == 1); // no edge twice in one direction: no overlap, no flipped triangle
        if (!directed.contains({segment.second, segment.first})) {
            open.insert(segment);
        }
    }
    return open;
}

} // namespace

TEST_CASE("TileMesh puts each vertex at its longitude, latitude and height, split for the GPU", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey key{9, 520, 300};
    const GeodeticExtent extent = scheme.tileExtent(key);
    std::vector<float> heights(5 * 5);
    for (std::size_t k = 0; k < heights.size(); ++k) {
        heights[k] = static_cast<float>(100.0 * static_cast<double>(k) - 700.0);
    }
    const TileMesh mesh = TileMesh::build(wgs84, scheme, key, 2, heights, 0.0);
    REQUIRE(mesh.size() == 5);
    REQUIRE(mesh.vertexCount() == 25);
    CHECK(mesh.minimumHeight == -700.0);
    CHECK(mesh.maximumHeight == 1700.0);
    for (int j = 0; j < 5; ++j) {
        for (int i = 0; i < 5; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * 5 + i;
            const orbis::Geodetic3D expected(extent.west + extent.width() * i / 4, extent.north - extent.height() * j / 4,
                                             static_cast<double>(heights[index]));
            INFO("i " << i << " j " << j);
            // Two floats keep 48 bits: well under a micrometre.
            CHECK(glm::length(mesh.position(index) - wgs84.toCartesian(expected)) < 1e-6);
            const float* v = &mesh.vertices[index * TileMesh::kFloatsPerVertex];
            CHECK(v[6] == Approx(i / 4.0));
            CHECK(v[7] == Approx(1.0 - j / 4.0));
            CHECK(v[8] == heights[index]);
        }
    }
}

TEST_CASE("TileMesh triangles cover the tile once, counter-clockwise, closed inside, for every edge coarsening",
          "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey key{6, 70, 40};
    for (int samplesLog2 : {1, 2, 4, 6}) {
        const TileMesh mesh = TileMesh::build(wgs84, scheme, key, samplesLog2, {}, 0.0);
        for (int coarse : {0, 1, 2, 3, 7}) {
            const EdgeCoarsening coarsening{coarse, 0, coarse == 0 ? 0 : 1, coarse};
            const std::vector<std::uint32_t> indices = TileMesh::indices(samplesLog2, coarsening, false);
            INFO("samples log2 " << samplesLog2 << ", coarsening " << coarse);
            double area = 0.0;
            for (std::size_t t = 0; t < indices.size(); t += 3) {
                const glm::dvec3 a = mesh.position(indices[t]);
                const glm::dvec3 b = mesh.position(indices[t + 1]);
                const glm::dvec3 c = mesh.position(indices[t + 2]);
                const glm::dvec3 normal = glm::cross(b - a, c - a);
                REQUIRE(glm::dot(normal, wgs84.geodeticSurfaceNormal((a + b + c) / 3.0)) > 0.0);
                area += 0.5 * glm::length(normal);
            }
            // The open edges are the tile's outline: as many segments as edge vertices in use.
            const int size = mesh.size();
            auto segments = [&](int levels) { return (size - 1) / std::min(1 << std::min(levels, 30), size - 1); };
            CHECK(boundary(mesh, indices).size() ==
                  static_cast<std::size_t>(segments(coarsening.north) + segments(coarsening.east) +
                                           segments(coarsening.south) + segments(coarsening.west)));
            // In the tile's (u, v) square the triangles cover the unit square exactly once: no gap,
            // no overlap (their orientations all agree, checked above).
            double uvArea = 0.0;
            for (std::size_t t = 0; t < indices.size(); t += 3) {
                auto uv = [&](std::size_t k) {
                    const float* v = &mesh.vertices[indices[t + k] * TileMesh::kFloatsPerVertex];
                    return glm::dvec2(v[6], v[7]);
                };
                const glm::dvec2 ab = uv(1) - uv(0);
                const glm::dvec2 ac = uv(2) - uv(0);
                uvArea += 0.5 * (ab.x * ac.y - ab.y * ac.x);
            }
            CHECK(uvArea == Approx(1.0).epsilon(1e-12));
            CHECK(area > 0.0);
        }
    }
}

TEST_CASE("TileMesh's index layout finds each quad row of the inner grid and each edge of the ring", "[core][tiles]")
{
    for (int samplesLog2 : {1, 2, 4, 6}) {
        const int size = (1 << samplesLog2) + 1;
        for (int coarse : {0, 1, 3, 7}) {
            for (bool skirt : {false, true}) {
                const EdgeCoarsening coarsening{coarse, 0, coarse == 0 ? 0 : 1, coarse};
                const std::vector<std::uint32_t> indices = TileMesh::indices(samplesLog2, coarsening, skirt);
                const TileMesh::IndexLayout layout = TileMesh::indexLayout(samplesLog2, coarsening, skirt);
                INFO("samples log2 " << samplesLog2 << ", coarsening " << coarse << ", skirt " << skirt);
                const std::size_t rowIndices = TileMesh::IndexLayout::kQuadIndices * layout.innerRowQuads;
                REQUIRE(layout.ringFirst == rowIndices * layout.innerRowQuads);
                REQUIRE(layout.ringFirst + layout.edgeIndices[0] + layout.edgeIndices[1] + layout.edgeIndices[2] +
                            layout.edgeIndices[3] ==
                        indices.size());
                REQUIRE(layout.indexCount() == indices.size());
                // Quad row r lies between vertex rows r and r + 1, inside the ring's columns.
                for (std::size_t r = 1; r <= layout.innerRowQuads; ++r) {
                    for (std::size_t k = (r - 1) * rowIndices; k < r * rowIndices; ++k) {
                        const int i = static_cast<int>(indices[k]) % size, j = static_cast<int>(indices[k]) / size;
                        REQUIRE((j == static_cast<int>(r) || j == static_cast<int>(r) + 1));
                        REQUIRE((i >= 1 && i <= size - 2));
                    }
                }
                // Each of the ring's triangles has a vertex on its own edge (or that edge's skirt),
                // and none beyond the row inside it.
                std::size_t first = layout.ringFirst;
                for (int edge = 0; edge < 4; ++edge) {
                    for (std::size_t t = first; t < first + layout.edgeIndices[edge]; t += 3) {
                        bool onEdge = false;
                        for (std::size_t k = t; k < t + 3; ++k) {
                            const int v = static_cast<int>(indices[k]);
                            if (v >= size * size) { // a skirt vertex: the edges' copies in order
                                onEdge = onEdge || (v - size * size) / size == edge;
                                continue;
                            }
                            const int i = v % size, j = v / size;
                            const int inset = edge == 0 ? j : edge == 1 ? size - 1 - i : edge == 2 ? size - 1 - j : i;
                            REQUIRE(inset <= 1);
                            onEdge = onEdge || inset == 0;
                        }
                        REQUIRE(onEdge);
                    }
                    first += layout.edgeIndices[edge];
                }
            }
        }
    }
}

TEST_CASE("A tile next to a coarser one shares every edge segment with it, position for position", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    // A coarse tile, and on its east the column of tiles two levels finer, also across the
    // antimeridian (x = 7 at level 2 borders x = 0).
    for (const TileKey coarse : {TileKey{4, 10, 5}, TileKey{2, 7, 1}}) {
        const int samplesLog2 = 4;
        const TileMesh coarseMesh = TileMesh::build(wgs84, scheme, coarse, samplesLog2, {}, 0.0);
        auto onEastEdge = [&](const Point& p) {
            const double longitude = wgs84.toGeodetic2D({std::get<0>(p), std::get<1>(p), std::get<2>(p)}).longitude;
            return std::abs(std::remainder(longitude - scheme.tileExtent(coarse).east, orbis::kTwoPi)) < 1e-12;
        };
        std::set<Segment> coarseEast;
        for (const Segment& s : boundary(coarseMesh, TileMesh::indices(samplesLog2, {}, false))) {
            if (onEastEdge(s.first) && onEastEdge(s.second)) {
                coarseEast.insert(s);
            }
        }
        REQUIRE(coarseEast.size() == 16);
        const std::uint32_t eastColumn = (coarse.x + 1) % scheme.tilesX(coarse.level);
        std::set<Segment> fineWest;
        for (std::uint32_t row = 0; row < 4; ++row) {
            const TileKey fine{coarse.level + 2, eastColumn * 4, coarse.y * 4 + row};
            const TileMesh fineMesh = TileMesh::build(wgs84, scheme, fine, samplesLog2, {}, 0.0);
            for (const Segment& s : boundary(fineMesh, TileMesh::indices(samplesLog2, {0, 0, 0, 2}, false))) {
                fineWest.insert({s.second, s.first}); // seen from the coarse side
            }
        }
        for (const Segment& s : coarseEast) {
            INFO("coarse tile level " << coarse.level);
            CHECK(fineWest.contains(s));
        }
    }
}

TEST_CASE("TileMesh skirts hang below the edges in use, walls facing out", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey key{4, 3, 9};
    const TileMesh mesh = TileMesh::build(wgs84, scheme, key, 3, {}, 500.0);
    REQUIRE(mesh.vertexCount() == 81 + 4 * 9);
    const std::vector<std::uint32_t> indices = TileMesh::indices(3, {1, 0, 0, 0}, true);
    const glm::dvec3 centre = wgs84.toCartesian(scheme.tileExtent(key).centre());
    std::size_t walls = 0;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        if (indices[t + 1] < 81 && indices[t + 2] < 81 && indices[t] < 81) {
            continue;
        }
        ++walls;
        const glm::dvec3 a = mesh.position(indices[t]);
        const glm::dvec3 b = mesh.position(indices[t + 1]);
        const glm::dvec3 c = mesh.position(indices[t + 2]);
        const glm::dvec3 middle = (a + b + c) / 3.0;
        const glm::dvec3 up = wgs84.geodeticSurfaceNormal(middle);
        const glm::dvec3 normal = glm::cross(b - a, c - a);
        const glm::dvec3 outwards = middle - centre;
        CHECK(glm::dot(normal, outwards - glm::dot(outwards, up) * up) > 0.0);
        CHECK(std::abs(glm::dot(glm::normalize(normal), up)) < 0.05);
    }
    CHECK(walls == 2 * (4 + 8 + 8 + 8)); // the north edge uses every other vertex
    CHECK(glm::length(mesh.position(81) - mesh.position(0)) == Approx(500.0).epsilon(1e-9));
}

TEST_CASE("TileMesh skirts hang from the edges as moved, the floats of a mesh built with those heights", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey key{6, 40, 21};
    std::vector<float> before(17 * 17), after(17 * 17);
    for (std::size_t v = 0; v < before.size(); ++v) {
        before[v] = static_cast<float>(100.0 + 3.0 * static_cast<double>(v % 17));
        after[v] = before[v];
    }
    // Every edge vertex moved (a neighbour's edge taken, a morph's step): up on two edges, down on two.
    TileMesh moved = TileMesh::build(wgs84, scheme, key, 4, before, 250.0);
    for (int k = 0; k < 17; ++k) {
        for (const auto& [i, j, shift] : {std::tuple{k, 0, 40.0}, std::tuple{16, k, -30.0}, std::tuple{k, 16, 75.0},
                                          std::tuple{0, k, -12.5}}) {
            const std::size_t v = static_cast<std::size_t>(j * 17 + i);
            after[v] = static_cast<float>(static_cast<double>(after[v]) + shift);
            moved.setVertexHeight(wgs84, scheme, i, j, static_cast<double>(after[v]));
        }
    }
    const TileMesh stale = moved;
    moved.hangSkirt(wgs84, scheme);
    const TileMesh built = TileMesh::build(wgs84, scheme, key, 4, after, 250.0);
    CHECK(moved.vertices == built.vertices);
    CHECK(stale.vertices != built.vertices); // the skirt did hang from the old edges
    TileMesh flat = TileMesh::build(wgs84, scheme, key, 4, before, 0.0);
    const std::vector<float> unchanged = flat.vertices;
    flat.hangSkirt(wgs84, scheme); // no skirt: nothing to do
    CHECK(flat.vertices == unchanged);
}

TEST_CASE("TileMesh at a pole collapses the polar row to one point, with no NaN", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    const TileKey polar{2, 5, 3};
    REQUIRE(scheme.tileExtent(polar).north == orbis::kHalfPi);
    const TileMesh mesh = TileMesh::build(wgs84, scheme, polar, 4, {}, 1000.0);
    for (float f : mesh.vertices) {
        REQUIRE(std::isfinite(f));
    }
    for (int i = 1; i < 17; ++i) {
        CHECK(glm::length(mesh.position(static_cast<std::size_t>(i)) - mesh.position(0)) < 1e-6);
    }
    CHECK(glm::length(mesh.position(0) - glm::dvec3(0.0, 0.0, wgs84.radii().z)) < 1e-6);
}
