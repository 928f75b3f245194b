#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace orbis {

/// How a Mesh's indices are read. The adjacency types give a geometry shader each segment with
/// the vertex before and after it (four per segment, or a strip where each vertex adds one).
enum class PrimitiveType { Points, Lines, LineStrip, Triangles, TriangleStrip, LinesAdjacency, LineStripAdjacency };

/// Indexed geometry produced by the tessellators: world positions in doubles (metres), with
/// optional unit normals and texture coordinates (one per position when present).
struct Mesh {
    PrimitiveType primitiveType = PrimitiveType::Triangles;
    std::vector<glm::dvec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> textureCoordinates;
    std::vector<std::uint32_t> indices;

    /// Number of triangles when primitiveType is Triangles; 0 otherwise.
    std::size_t triangleCount() const noexcept
    {
        return primitiveType == PrimitiveType::Triangles ? indices.size() / 3 : 0;
    }
};

} // namespace orbis
