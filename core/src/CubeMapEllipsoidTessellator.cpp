#include "orbis/core/CubeMapEllipsoidTessellator.h"

#include "orbis/core/Ellipsoid.h"

#include "TessellationInternal.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <unordered_map>

namespace orbis {

namespace {

/// A cube face: its outward normal and two in-face axes with u x v = normal, all on the axes.
struct Face {
    glm::ivec3 normal;
    glm::ivec3 u;
    glm::ivec3 v;
};

constexpr Face kFaces[6] = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}},
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
};

} // namespace

TessellationResult CubeMapEllipsoidTessellator::compute(const Ellipsoid& ellipsoid, int partitions,
                                                        CubeMapSpacing spacing, EllipsoidProjection projection,
                                                        VertexAttributes attributes, Deviation deviation)
{
    assert(partitions >= 1);
    int n = std::max(partitions, 1);
    const bool textureCoordinates = contains(attributes, VertexAttributes::TextureCoordinate);
    assert(!textureCoordinates || n % 2 == 0);
    if (textureCoordinates && n % 2 != 0) {
        ++n;
    }

    // Face coordinate (2i - n) / n in [-1, 1] for grid line i, warped for equal angles; exact at
    // the centre and the edges so that faces agree on their shared vertices.
    std::vector<double> coordinate(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        const int a = 2 * i - n;
        const double t = static_cast<double>(a) / n;
        coordinate[static_cast<std::size_t>(i)] =
            (spacing == CubeMapSpacing::Uniform || a == 0 || std::abs(a) == n) ? t : std::tan(t * (kPi / 4.0));
    }

    TessellationResult result;
    Mesh& mesh = result.mesh;
    const auto size = static_cast<std::size_t>(n);
    mesh.positions.reserve(6 * size * size + 2);
    mesh.indices.reserve(36 * size * size);

    // Vertices on face borders are shared: they are found by their integer lattice point on the
    // cube n * normal + (2i - n) * u + (2j - n) * v, each coordinate in [-n, n].
    std::unordered_map<std::uint64_t, std::uint32_t> border;
    border.reserve(12 * size + 8);
    const auto span = static_cast<std::uint64_t>(2 * n + 1);
    std::vector<std::uint32_t> faceIndex((size + 1) * (size + 1));
    for (const Face& face : kFaces) {
        for (int j = 0; j <= n; ++j) {
            for (int i = 0; i <= n; ++i) {
                const glm::dvec3 cubePoint = glm::dvec3(face.normal) +
                                             coordinate[static_cast<std::size_t>(i)] * glm::dvec3(face.u) +
                                             coordinate[static_cast<std::size_t>(j)] * glm::dvec3(face.v);
                auto next = static_cast<std::uint32_t>(mesh.positions.size());
                std::uint32_t index = next;
                if (i == 0 || j == 0 || i == n || j == n) {
                    const glm::ivec3 lattice = n * face.normal + (2 * i - n) * face.u + (2 * j - n) * face.v + n;
                    const std::uint64_t key = (static_cast<std::uint64_t>(lattice.x) * span +
                                               static_cast<std::uint64_t>(lattice.y)) * span +
                                              static_cast<std::uint64_t>(lattice.z);
                    index = border.try_emplace(key, next).first->second;
                }
                if (index == next) {
                    mesh.positions.push_back(detail::projectToEllipsoid(ellipsoid, cubePoint, projection));
                }
                faceIndex[static_cast<std::size_t>(j) * (size + 1) + static_cast<std::size_t>(i)] = index;
            }
        }
        for (std::size_t j = 0; j < size; ++j) {
            for (std::size_t i = 0; i < size; ++i) {
                // Cell corners counter-clockwise seen from outside (u x v is the outward normal).
                const std::uint32_t a = faceIndex[j * (size + 1) + i];
                const std::uint32_t b = faceIndex[j * (size + 1) + i + 1];
                const std::uint32_t c = faceIndex[(j + 1) * (size + 1) + i + 1];
                const std::uint32_t d = faceIndex[(j + 1) * (size + 1) + i];
                const double ac = glm::distance(mesh.positions[a], mesh.positions[c]);
                const double bd = glm::distance(mesh.positions[b], mesh.positions[d]);
                if (ac <= bd) {
                    mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
                } else {
                    mesh.indices.insert(mesh.indices.end(), {a, b, d, b, c, d});
                }
            }
        }
    }
    assert(mesh.positions.size() == 6 * size * size + 2);

    if (contains(attributes, VertexAttributes::Normal)) {
        detail::addGeodeticNormals(mesh, ellipsoid);
    }
    if (textureCoordinates) {
        detail::addGeographicTextureCoordinates(mesh, ellipsoid);
    }
    result.maxDeviationMeters = detail::measureDeviation(mesh, ellipsoid, deviation);
    return result;
}

} // namespace orbis
