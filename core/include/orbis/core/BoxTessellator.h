#pragma once

#include "orbis/core/Tessellation.h"

#include <glm/vec3.hpp>

namespace orbis {

class Ellipsoid;

/// The axis-aligned box that bounds an ellipsoid: the proxy geometry that GPU ray casting of the
/// globe rasterises (book section 4.3).
///
///     const Mesh proxy = BoxTessellator::compute(Ellipsoid::wgs84()).mesh;
class BoxTessellator final {
public:
    BoxTessellator() = delete;

    /// The box from -radii to +radii, 12 triangles counter-clockwise seen from outside. Positions
    /// only: the 8 corners, shared. With normals or texture coordinates: 4 vertices per face (24),
    /// normals the face's outward axis, texture coordinates the face's corners (0, 0) to (1, 1).
    /// The deviation is the distance from a corner to the ellipsoid (the box touches it only at the
    /// six face centres).
    static TessellationResult compute(const Ellipsoid& ellipsoid, VertexAttributes attributes = VertexAttributes::Position,
                                      Deviation deviation = Deviation::Measure);

    /// An axis-aligned cube around `centre`, `halfSize` metres from it to each face (markers,
    /// satellites, test objects): positions only, the 8 corners shared, 12 triangles
    /// counter-clockwise seen from outside.
    static Mesh cube(const glm::dvec3& centre, double halfSize);
};

} // namespace orbis
