#include "orbis/core/RectangleTessellator.h"

#include "orbis/core/Ellipsoid.h"

#include "TessellationInternal.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace orbis {

Mesh RectangleTessellator::computeGrid(const glm::dvec2& lowerLeft, const glm::dvec2& upperRight, int partitionsX,
                                       int partitionsY, VertexAttributes attributes)
{
    assert(partitionsX >= 1 && partitionsY >= 1);
    assert(upperRight.x > lowerLeft.x && upperRight.y > lowerLeft.y);
    const auto columns = static_cast<std::uint32_t>(std::max(partitionsX, 1));
    const auto rows = static_cast<std::uint32_t>(std::max(partitionsY, 1));
    const bool normals = contains(attributes, VertexAttributes::Normal);
    const bool textureCoordinates = contains(attributes, VertexAttributes::TextureCoordinate);

    Mesh mesh;
    const std::size_t vertexCount = std::size_t{columns + 1} * (rows + 1);
    mesh.positions.reserve(vertexCount);
    mesh.indices.reserve(6 * std::size_t{columns} * rows);
    for (std::uint32_t j = 0; j <= rows; ++j) {
        const double t = static_cast<double>(j) / rows;
        // The last row and column land on upperRight exactly.
        const double y = j == rows ? upperRight.y : lowerLeft.y + t * (upperRight.y - lowerLeft.y);
        for (std::uint32_t i = 0; i <= columns; ++i) {
            const double s = static_cast<double>(i) / columns;
            const double x = i == columns ? upperRight.x : lowerLeft.x + s * (upperRight.x - lowerLeft.x);
            mesh.positions.emplace_back(x, y, 0.0);
            if (normals) {
                mesh.normals.emplace_back(0.0f, 0.0f, 1.0f);
            }
            if (textureCoordinates) {
                mesh.textureCoordinates.emplace_back(static_cast<float>(s), static_cast<float>(t));
            }
        }
    }
    for (std::uint32_t j = 0; j < rows; ++j) {
        for (std::uint32_t i = 0; i < columns; ++i) {
            const std::uint32_t a = j * (columns + 1) + i;
            const std::uint32_t b = a + 1;
            const std::uint32_t c = b + columns + 1;
            const std::uint32_t d = a + columns + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
        }
    }
    return mesh;
}

TessellationResult RectangleTessellator::compute(const Ellipsoid& ellipsoid, const Geodetic2D& centre,
                                                 const glm::dvec2& sizeMeters, int partitionsX, int partitionsY,
                                                 VertexAttributes attributes, Deviation deviation)
{
    TessellationResult result{computeGrid(-0.5 * sizeMeters, 0.5 * sizeMeters, partitionsX, partitionsY, attributes),
                              std::nullopt};
    Mesh& mesh = result.mesh;
    const glm::dvec3 origin = ellipsoid.toCartesian(centre);
    const glm::dvec3 up = Ellipsoid::geodeticSurfaceNormal(centre);
    const double sinLongitude = std::sin(centre.longitude);
    const double cosLongitude = std::cos(centre.longitude);
    const double sinLatitude = std::sin(centre.latitude);
    const glm::dvec3 east(-sinLongitude, cosLongitude, 0.0);
    const glm::dvec3 north(-sinLatitude * cosLongitude, -sinLatitude * sinLongitude, std::cos(centre.latitude));
    for (glm::dvec3& p : mesh.positions) {
        p = origin + p.x * east + p.y * north;
    }
    for (glm::vec3& n : mesh.normals) {
        n = glm::vec3(up);
    }
    result.maxDeviationMeters = detail::measureDeviation(mesh, ellipsoid, deviation);
    return result;
}

} // namespace orbis
