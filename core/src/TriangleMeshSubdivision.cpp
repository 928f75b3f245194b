#include "orbis/core/TriangleMeshSubdivision.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace orbis {

double centralAngle(const glm::dvec3& a, const glm::dvec3& b) noexcept
{
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

Mesh subdivideOnEllipsoid(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions,
                          std::span<const std::uint32_t> indices, double granularityRadians, std::vector<double>* values)
{
    assert(indices.size() % 3 == 0);
    assert(!values || values->size() == positions.size());
    const double granularity = std::max(granularityRadians, 1e-6);
    Mesh mesh;
    mesh.primitiveType = PrimitiveType::Triangles;
    mesh.positions.assign(positions.begin(), positions.end());
    mesh.indices.reserve(indices.size());

    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
        const auto [it, inserted] = midpoints.try_emplace(key, 0u);
        if (inserted) {
            const glm::dvec3& pa = mesh.positions[a];
            const glm::dvec3& pb = mesh.positions[b];
            it->second = static_cast<std::uint32_t>(mesh.positions.size());
            mesh.positions.push_back(ellipsoid.scaleToGeocentricSurface(0.5 * pa + 0.5 * pb));
            if (values) {
                values->push_back(0.5 * ((*values)[a] + (*values)[b]));
            }
        }
        return it->second;
    };

    using Triangle = std::array<std::uint32_t, 3>;
    std::vector<Triangle> work;
    for (std::size_t t = indices.size() / 3; t-- > 0;) {
        const Triangle triangle{indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
        assert(triangle[0] < positions.size() && triangle[1] < positions.size() && triangle[2] < positions.size());
        work.push_back(triangle);
    }
    while (!work.empty()) {
        const Triangle t = work.back();
        work.pop_back();
        // The longest edge, by the angle it subtends; edge k runs from corner k to corner k + 1.
        int longest = 0;
        double longestAngle = -1.0;
        for (int k = 0; k < 3; ++k) {
            const double angle = centralAngle(mesh.positions[t[static_cast<std::size_t>(k)]],
                                              mesh.positions[t[static_cast<std::size_t>((k + 1) % 3)]]);
            if (angle > longestAngle) {
                longestAngle = angle;
                longest = k;
            }
        }
        if (longestAngle <= granularity) {
            mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
            continue;
        }
        const std::uint32_t a = t[static_cast<std::size_t>(longest)];
        const std::uint32_t b = t[static_cast<std::size_t>((longest + 1) % 3)];
        const std::uint32_t c = t[static_cast<std::size_t>((longest + 2) % 3)];
        const std::uint32_t m = midpoint(a, b);
        work.push_back({m, b, c});
        work.push_back({a, m, c});
    }

    mesh.normals.reserve(mesh.positions.size());
    for (const glm::dvec3& p : mesh.positions) {
        mesh.normals.push_back(glm::vec3(ellipsoid.geodeticSurfaceNormal(p)));
    }
    return mesh;
}

} // namespace orbis
