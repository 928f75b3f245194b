#pragma once

#include "orbis/core/Tessellation.h"

namespace orbis {

class Ellipsoid;

/// The subdivided octahedron of SubdivisionSphereTessellator, its unit-sphere vertices projected
/// onto an ellipsoid. Same vertex and triangle counts, the same seam and pole handling for texture
/// coordinates.
///
///     const TessellationResult globe = SubdivisionEllipsoidTessellator::compute(
///         Ellipsoid::wgs84(), 6, EllipsoidProjection::Geodetic, VertexAttributes::All);
class SubdivisionEllipsoidTessellator final {
public:
    SubdivisionEllipsoidTessellator() = delete;

    /// The octahedron subdivided n = subdivisions times (clamped to [0, 12], asserted) on the unit
    /// sphere, each vertex then moved to ellipsoid's surface as projection says: 4 * 4^n + 2
    /// vertices, 8 * 4^n triangles, counter-clockwise seen from outside. Normals are the geodetic
    /// surface normals; texture coordinates map geodetic longitude and latitude to [0, 1] (see
    /// SubdivisionSphereTessellator for the vertices they add). Deviation against ellipsoid, in metres.
    static TessellationResult compute(const Ellipsoid& ellipsoid, int subdivisions,
                                      EllipsoidProjection projection = EllipsoidProjection::Geocentric,
                                      VertexAttributes attributes = VertexAttributes::Position,
                                      Deviation deviation = Deviation::Measure);
};

} // namespace orbis
