#include "orbis/core/SubdivisionSphereTessellator.h"

#include "orbis/core/Ellipsoid.h"

#include "TessellationInternal.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>

namespace orbis {

namespace detail {

Mesh subdividedOctahedron(int subdivisions)
{
    assert(subdivisions >= 0 && subdivisions <= 12);
    subdivisions = std::clamp(subdivisions, 0, 12);

    Mesh mesh;
    const std::size_t finalVertices = 4 * (std::size_t{1} << (2 * subdivisions)) + 2;
    const std::size_t finalTriangles = 8 * (std::size_t{1} << (2 * subdivisions));
    mesh.positions.reserve(finalVertices);
    mesh.positions = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    // Counter-clockwise seen from outside: (+x, +y, +z) has the outward normal (1, 1, 1).
    mesh.indices = {2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 2, 0, 3, 2, 1, 4, 3, 1, 5, 4, 1, 2, 5, 1};

    // Each edge's midpoint is filed under its lower-numbered end: no vertex has more than 6
    // neighbours, so 6 slots per vertex hold them, and a lookup scans one cache line or two.
    constexpr std::uint32_t kEmpty = 0xffffffffu;
    struct Slot {
        std::uint32_t other;
        std::uint32_t midpoint;
    };
    std::vector<std::uint32_t> next;
    std::vector<Slot> midpoints;
    for (int level = 0; level < subdivisions; ++level) {
        const std::size_t triangles = mesh.indices.size() / 3;
        next.clear();
        next.reserve(4 * mesh.indices.size());
        midpoints.assign(6 * mesh.positions.size(), Slot{kEmpty, kEmpty});
        auto midpoint = [&](std::uint32_t i, std::uint32_t j) {
            Slot* slot = &midpoints[6 * std::size_t{std::min(i, j)}];
            const std::uint32_t other = std::max(i, j);
            while (slot->other != other && slot->other != kEmpty) {
                ++slot;
            }
            assert(slot < midpoints.data() + 6 * (std::size_t{std::min(i, j)} + 1));
            if (slot->other == kEmpty) {
                *slot = {other, static_cast<std::uint32_t>(mesh.positions.size())};
                mesh.positions.push_back(glm::normalize(mesh.positions[i] + mesh.positions[j]));
            }
            return slot->midpoint;
        };
        for (std::size_t t = 0; t < triangles; ++t) {
            const std::uint32_t a = mesh.indices[3 * t];
            const std::uint32_t b = mesh.indices[3 * t + 1];
            const std::uint32_t c = mesh.indices[3 * t + 2];
            const std::uint32_t ab = midpoint(a, b);
            const std::uint32_t bc = midpoint(b, c);
            const std::uint32_t ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        }
        mesh.indices.swap(next);
    }
    assert(mesh.positions.size() == finalVertices && mesh.indices.size() == 3 * finalTriangles);
    (void)finalTriangles;
    return mesh;
}

} // namespace detail

TessellationResult SubdivisionSphereTessellator::compute(int subdivisions, double radiusMeters,
                                                         VertexAttributes attributes, Deviation deviation)
{
    assert(radiusMeters > 0.0);
    const Ellipsoid sphere(radiusMeters, radiusMeters, radiusMeters);
    TessellationResult result{detail::subdividedOctahedron(subdivisions), std::nullopt};
    Mesh& mesh = result.mesh;
    if (contains(attributes, VertexAttributes::Normal)) {
        mesh.normals.assign(mesh.positions.begin(), mesh.positions.end());
    }
    for (glm::dvec3& p : mesh.positions) {
        p *= radiusMeters;
    }
    if (contains(attributes, VertexAttributes::TextureCoordinate)) {
        detail::addGeographicTextureCoordinates(mesh, sphere);
    }
    result.maxDeviationMeters = detail::measureDeviation(mesh, sphere, deviation);
    return result;
}

} // namespace orbis
