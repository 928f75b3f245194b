#pragma once

// Checks shared by the tessellator tests: topology, winding, surface, attributes, and the exact
// deviation of a mesh inscribed in a sphere.

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Mesh.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>

namespace orbis::test {

/// Vertices welded by exact position: the id of the first vertex at each position.
inline std::vector<std::uint32_t> weldedIds(const Mesh& mesh)
{
    std::map<std::tuple<double, double, double>, std::uint32_t> first;
    std::vector<std::uint32_t> ids(mesh.positions.size());
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3& p = mesh.positions[v];
        ids[v] = first.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(first.size())).first->second;
    }
    return ids;
}

/// Number of distinct positions.
inline std::size_t distinctPositions(const Mesh& mesh)
{
    const auto ids = weldedIds(mesh);
    return ids.empty() ? 0 : *std::max_element(ids.begin(), ids.end()) + 1;
}

/// Requires a closed, consistently oriented 2-manifold of genus 0 once copies of a position are
/// welded: every directed edge appears once and its reverse once (so each edge is shared by exactly
/// two triangles, which traverse it in opposite directions), and V - E + F = 2.
inline void requireClosed(const Mesh& mesh)
{
    const auto ids = weldedIds(mesh);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = ids[mesh.indices[t + k]];
            const std::uint32_t b = ids[mesh.indices[t + (k + 1) % 3]];
            REQUIRE(a != b);
            ++directed[{a, b}];
        }
    }
    for (const auto& [edge, count] : directed) {
        INFO("edge " << edge.first << " -> " << edge.second);
        REQUIRE(count == 1);
        REQUIRE(directed.count({edge.second, edge.first}) == 1);
    }
    const auto vertices = static_cast<long>(distinctPositions(mesh));
    const auto edges = static_cast<long>(directed.size() / 2);
    const auto faces = static_cast<long>(mesh.triangleCount());
    REQUIRE(vertices - edges + faces == 2);
}

/// Requires every index in range, every triangle's geometric normal to point away from the centre
/// (dot with the centroid > 0: counter-clockwise seen from outside), and no triangle smaller than
/// minAreaFraction of the mean area (none of zero area).
inline void requireOutwardAndNonDegenerate(const Mesh& mesh, double minAreaFraction)
{
    REQUIRE(mesh.primitiveType == PrimitiveType::Triangles);
    REQUIRE(mesh.indices.size() % 3 == 0);
    double total = 0.0;
    double smallest = HUGE_VAL;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        REQUIRE(mesh.indices[t] < mesh.positions.size());
        REQUIRE(mesh.indices[t + 1] < mesh.positions.size());
        REQUIRE(mesh.indices[t + 2] < mesh.positions.size());
        const glm::dvec3& a = mesh.positions[mesh.indices[t]];
        const glm::dvec3& b = mesh.positions[mesh.indices[t + 1]];
        const glm::dvec3& c = mesh.positions[mesh.indices[t + 2]];
        const glm::dvec3 normal = glm::cross(b - a, c - a);
        INFO("triangle " << t / 3);
        REQUIRE(glm::dot(normal, a + b + c) > 0.0);
        const double area = 0.5 * glm::length(normal);
        total += area;
        smallest = std::min(smallest, area);
    }
    REQUIRE(smallest > minAreaFraction * total / static_cast<double>(mesh.triangleCount()));
}

/// Requires every vertex on the surface: |height| <= relative * the largest radius.
inline void requireOnSurface(const Mesh& mesh, const Ellipsoid& ellipsoid, double relative)
{
    for (const glm::dvec3& p : mesh.positions) {
        INFO("p = " << p.x << ", " << p.y << ", " << p.z);
        REQUIRE(isFinite(p));
        REQUIRE(std::abs(ellipsoid.toGeodetic3D(p).height) <= relative * ellipsoid.maximumRadius());
    }
}

/// Requires one unit normal per vertex equal to the geodetic surface normal. Tolerance 1e-6: the
/// normals are floats (half an ulp is 6e-8 per component).
inline void requireGeodeticNormals(const Mesh& mesh, const Ellipsoid& ellipsoid)
{
    REQUIRE(mesh.normals.size() == mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3 n(mesh.normals[v]);
        REQUIRE(isFinite(n));
        REQUIRE(glm::length(n) == Approx(1.0).margin(1e-6));
        REQUIRE(glm::length(n - ellipsoid.geodeticSurfaceNormal(mesh.positions[v])) <= 1e-6);
    }
}

/// Requires geographic texture coordinates: finite and in [0, 1]; v from the geodetic latitude and
/// u from the longitude (1e-6: float rounding of numbers below 1), u = 0 or 1 on the antimeridian;
/// no triangle spanning more than half the texture in u (no wrap-around); a pole's u halfway
/// between its triangle's other corners.
inline void requireGeographicTextureCoordinates(const Mesh& mesh, const Ellipsoid& ellipsoid)
{
    REQUIRE(mesh.textureCoordinates.size() == mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::vec2 st = mesh.textureCoordinates[v];
        const glm::dvec3& p = mesh.positions[v];
        INFO("vertex " << v << " at " << p.x << ", " << p.y << ", " << p.z << ": " << st.x << ", " << st.y);
        REQUIRE(std::isfinite(st.x));
        REQUIRE(std::isfinite(st.y));
        REQUIRE(st.x >= 0.0f);
        REQUIRE(st.x <= 1.0f);
        const Geodetic2D g = ellipsoid.toGeodetic2D(p);
        REQUIRE(st.y == Approx((g.latitude + kHalfPi) / kPi).margin(1e-6));
        if (p.x == 0.0 && p.y == 0.0) {
            REQUIRE((st.y == 0.0f || st.y == 1.0f));
        } else if (p.y == 0.0 && p.x < 0.0) {
            REQUIRE((st.x == 0.0f || st.x == 1.0f));
        } else {
            REQUIRE(st.x == Approx((g.longitude + kPi) / kTwoPi).margin(1e-6));
        }
    }
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        float low = 1.0f;
        float high = 0.0f;
        for (int k = 0; k < 3; ++k) {
            low = std::min(low, mesh.textureCoordinates[mesh.indices[t + k]].x);
            high = std::max(high, mesh.textureCoordinates[mesh.indices[t + k]].x);
        }
        INFO("triangle " << t / 3);
        REQUIRE(high - low < 0.5f);
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3& p = mesh.positions[mesh.indices[t + k]];
            if (p.x == 0.0 && p.y == 0.0) {
                const float middle = 0.5f * (mesh.textureCoordinates[mesh.indices[t + (k + 1) % 3]].x +
                                             mesh.textureCoordinates[mesh.indices[t + (k + 2) % 3]].x);
                REQUIRE(mesh.textureCoordinates[mesh.indices[t + k]].x == Approx(middle).margin(1e-6));
            }
        }
    }
}

/// Distance from the origin to the closest point of the triangle (a, b, c): the foot of the origin
/// on the plane when inside the triangle, else the closest point of an edge.
inline double closestDistanceToOrigin(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    auto segment = [](const glm::dvec3& p, const glm::dvec3& q) {
        const glm::dvec3 d = q - p;
        const double t = std::clamp(-glm::dot(p, d) / glm::dot(d, d), 0.0, 1.0);
        return glm::length(p + t * d);
    };
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const glm::dvec3 foot = n * (glm::dot(a, n) / glm::dot(n, n));
    // Inside when the foot is on the inner side of all three edges.
    const bool inside = glm::dot(glm::cross(b - a, foot - a), n) >= 0.0 &&
                        glm::dot(glm::cross(c - b, foot - b), n) >= 0.0 &&
                        glm::dot(glm::cross(a - c, foot - c), n) >= 0.0;
    if (inside) {
        return glm::length(foot);
    }
    return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

/// The exact maximum deviation of a mesh whose vertices lie on the sphere of the given radius: the
/// deepest point of each triangle is its closest point to the centre.
inline double exactSphereDeviation(const Mesh& mesh, double radius)
{
    double worst = 0.0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        worst = std::max(worst, radius - closestDistanceToOrigin(mesh.positions[mesh.indices[t]],
                                                                 mesh.positions[mesh.indices[t + 1]],
                                                                 mesh.positions[mesh.indices[t + 2]]));
    }
    return worst;
}

} // namespace orbis::test
