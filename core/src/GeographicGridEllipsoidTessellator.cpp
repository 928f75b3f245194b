#include "orbis/core/GeographicGridEllipsoidTessellator.h"

#include "orbis/core/Ellipsoid.h"

#include "TessellationInternal.h"

#include <algorithm>
#include <cassert>

namespace orbis {

TessellationResult GeographicGridEllipsoidTessellator::compute(const Ellipsoid& ellipsoid, int slicePartitions,
                                                               int stackPartitions, VertexAttributes attributes,
                                                               Deviation deviation)
{
    assert(slicePartitions >= 3 && stackPartitions >= 2);
    const auto slices = static_cast<std::uint32_t>(std::max(slicePartitions, 3));
    const auto stacks = static_cast<std::uint32_t>(std::max(stackPartitions, 2));
    const bool normals = contains(attributes, VertexAttributes::Normal);
    const bool textureCoordinates = contains(attributes, VertexAttributes::TextureCoordinate);
    // With texture coordinates each ring repeats its first vertex at u = 1, and each pole has one
    // vertex per fan triangle.
    const std::uint32_t ringSize = textureCoordinates ? slices + 1 : slices;
    const std::uint32_t poleCount = textureCoordinates ? slices : 1;
    const std::uint32_t rings = stacks - 1;

    TessellationResult result;
    Mesh& mesh = result.mesh;
    const std::size_t vertexCount = 2 * std::size_t{poleCount} + std::size_t{ringSize} * rings;
    mesh.positions.reserve(vertexCount);
    if (normals) {
        mesh.normals.reserve(vertexCount);
    }
    if (textureCoordinates) {
        mesh.textureCoordinates.reserve(vertexCount);
    }
    mesh.indices.reserve(6 * std::size_t{slices} * rings);

    auto addPole = [&](double sign) {
        for (std::uint32_t j = 0; j < poleCount; ++j) {
            mesh.positions.emplace_back(0.0, 0.0, sign * ellipsoid.radii().z);
            if (normals) {
                mesh.normals.emplace_back(0.0f, 0.0f, static_cast<float>(sign));
            }
            if (textureCoordinates) {
                mesh.textureCoordinates.emplace_back(static_cast<float>((j + 0.5) / slices), sign > 0.0 ? 1.0f : 0.0f);
            }
        }
    };

    // On the meridians at multiples of 90 degrees sin or cos of the longitude rounds to 1e-16 instead
    // of 0: zero that coordinate, so that the antimeridian has y = 0 exactly, as in the other
    // tessellators, and the prime meridian too.
    auto snapToAxes = [slices](std::uint32_t j, glm::dvec3& v) {
        if ((4 * j) % slices == 0) {
            v[((4 * j) / slices) % 2 == 0 ? 1 : 0] = 0.0;
        }
    };

    addPole(-1.0);
    for (std::uint32_t i = 1; i < stacks; ++i) {
        const double latitude = -kHalfPi + kPi * i / stacks;
        const auto ringStart = mesh.positions.size();
        for (std::uint32_t j = 0; j < ringSize; ++j) {
            const Geodetic2D g{-kPi + kTwoPi * j / slices, latitude};
            // The duplicated antimeridian vertex takes the first one's position bit for bit.
            glm::dvec3 position = ellipsoid.toCartesian(g);
            glm::dvec3 normal = Ellipsoid::geodeticSurfaceNormal(g);
            snapToAxes(j, position);
            snapToAxes(j, normal);
            mesh.positions.push_back(j == slices ? mesh.positions[ringStart] : position);
            if (normals) {
                mesh.normals.emplace_back(j == slices ? mesh.normals[ringStart] : glm::vec3(normal));
            }
            if (textureCoordinates) {
                mesh.textureCoordinates.emplace_back(static_cast<float>(static_cast<double>(j) / slices),
                                                     static_cast<float>(static_cast<double>(i) / stacks));
            }
        }
    }
    addPole(1.0);

    // Vertex (ring r, meridian j); with no duplicated column meridian `slices` wraps to 0.
    auto ring = [&](std::uint32_t r, std::uint32_t j) { return poleCount + r * ringSize + (j % ringSize); };
    const std::uint32_t northPole = poleCount + rings * ringSize;

    // Quad (A west-south, B east-south, C east-north, D west-north): east x north points outward,
    // so (A, B, C) and (A, C, D) are counter-clockwise.
    for (std::uint32_t j = 0; j < slices; ++j) {
        mesh.indices.insert(mesh.indices.end(), {textureCoordinates ? j : 0, ring(0, j + 1), ring(0, j)});
    }
    for (std::uint32_t r = 0; r + 1 < rings; ++r) {
        for (std::uint32_t j = 0; j < slices; ++j) {
            const std::uint32_t a = ring(r, j);
            const std::uint32_t b = ring(r, j + 1);
            const std::uint32_t c = ring(r + 1, j + 1);
            const std::uint32_t d = ring(r + 1, j);
            mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
        }
    }
    for (std::uint32_t j = 0; j < slices; ++j) {
        mesh.indices.insert(mesh.indices.end(),
                            {ring(rings - 1, j), ring(rings - 1, j + 1), northPole + (textureCoordinates ? j : 0)});
    }

    result.maxDeviationMeters = detail::measureDeviation(mesh, ellipsoid, deviation);
    return result;
}

} // namespace orbis
