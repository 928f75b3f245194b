#include "orbis/core/BoxTessellator.h"

#include "orbis/core/Ellipsoid.h"

#include "TessellationInternal.h"

#include <glm/vec3.hpp>

namespace orbis {

namespace {

/// A box face: outward axis and two in-face axes with u x v = normal.
struct Face {
    glm::dvec3 normal;
    glm::dvec3 u;
    glm::dvec3 v;
};

constexpr Face kFaces[6] = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}},
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
};

/// Face corners in counter-clockwise order seen from outside, as (u, v) signs.
constexpr double kCorners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};

} // namespace

TessellationResult BoxTessellator::compute(const Ellipsoid& ellipsoid, VertexAttributes attributes, Deviation deviation)
{
    const bool normals = contains(attributes, VertexAttributes::Normal);
    const bool textureCoordinates = contains(attributes, VertexAttributes::TextureCoordinate);
    const bool perFace = normals || textureCoordinates;
    const glm::dvec3& radii = ellipsoid.radii();

    TessellationResult result;
    Mesh& mesh = result.mesh;
    if (!perFace) {
        // Corner k has the sign of bit 0 in x, bit 1 in y, bit 2 in z.
        for (int k = 0; k < 8; ++k) {
            mesh.positions.emplace_back((k & 1 ? 1 : -1) * radii.x, (k & 2 ? 1 : -1) * radii.y,
                                        (k & 4 ? 1 : -1) * radii.z);
        }
    }
    for (const Face& face : kFaces) {
        std::uint32_t corner[4];
        for (int k = 0; k < 4; ++k) {
            const glm::dvec3 unit = face.normal + kCorners[k][0] * face.u + kCorners[k][1] * face.v;
            if (perFace) {
                corner[k] = static_cast<std::uint32_t>(mesh.positions.size());
                mesh.positions.push_back(unit * radii);
                if (normals) {
                    mesh.normals.emplace_back(face.normal);
                }
                if (textureCoordinates) {
                    mesh.textureCoordinates.emplace_back(0.5 * (kCorners[k][0] + 1.0), 0.5 * (kCorners[k][1] + 1.0));
                }
            } else {
                corner[k] = (unit.x > 0 ? 1u : 0u) | (unit.y > 0 ? 2u : 0u) | (unit.z > 0 ? 4u : 0u);
            }
        }
        mesh.indices.insert(mesh.indices.end(), {corner[0], corner[1], corner[2], corner[0], corner[2], corner[3]});
    }
    result.maxDeviationMeters = detail::measureDeviation(mesh, ellipsoid, deviation);
    return result;
}

Mesh BoxTessellator::cube(const glm::dvec3& centre, double halfSize)
{
    Mesh mesh;
    // Corner i has the sign of bit 0 in x, bit 1 in y, bit 2 in z.
    for (int i = 0; i < 8; ++i) {
        mesh.positions.push_back(centre + halfSize * glm::dvec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    }
    // Counter-clockwise from outside: -x, +x, -y, +y, -z, +z.
    mesh.indices = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                    2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
    return mesh;
}

} // namespace orbis
