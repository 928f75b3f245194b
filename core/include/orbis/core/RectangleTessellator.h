#pragma once

#include "orbis/core/Geodetic.h"
#include "orbis/core/Tessellation.h"

#include <glm/vec2.hpp>

namespace orbis {

class Ellipsoid;

/// A flat grid of partitionsX x partitionsY cells, each split into two triangles: in the z = 0
/// plane (a terrain patch, a screen quad), or laid on the plane tangent to an ellipsoid.
///
///     const Mesh plane = RectangleTessellator::computeGrid({-1, -1}, {1, 1}, 8, 8, VertexAttributes::All);
class RectangleTessellator final {
public:
    RectangleTessellator() = delete;

    /// Grid in the z = 0 plane from lowerLeft to upperRight: (partitionsX + 1) * (partitionsY + 1)
    /// vertices, row by row from lowerLeft, and 2 * partitionsX * partitionsY triangles,
    /// counter-clockwise seen from +z. Normals are +z; texture coordinates run from (0, 0) at
    /// lowerLeft to (1, 1) at upperRight. Partitions below 1 are asserted and clamped; upperRight
    /// must exceed lowerLeft in both coordinates (asserted).
    static Mesh computeGrid(const glm::dvec2& lowerLeft, const glm::dvec2& upperRight, int partitionsX,
                            int partitionsY, VertexAttributes attributes = VertexAttributes::Position);

    /// The grid of sizeMeters (east by north) centred on the surface point at centre, in the plane
    /// tangent to ellipsoid there: x along local east, y along local north, the normal is the
    /// geodetic normal at centre (east is well defined at the poles, from centre's longitude).
    /// Texture coordinates as computeGrid's. The deviation grows with the distance from centre,
    /// about d^2 / 2R: it is reached at the corners.
    static TessellationResult compute(const Ellipsoid& ellipsoid, const Geodetic2D& centre,
                                      const glm::dvec2& sizeMeters, int partitionsX, int partitionsY,
                                      VertexAttributes attributes = VertexAttributes::Position,
                                      Deviation deviation = Deviation::Measure);
};

} // namespace orbis
