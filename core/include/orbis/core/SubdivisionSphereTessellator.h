#pragma once

#include "orbis/core/Tessellation.h"

namespace orbis {

/// A sphere from a regular octahedron whose faces are split into four, subdivisions times, each
/// new vertex pushed out to the sphere. Triangles are nearly equal in size (within a factor of about
/// 2 in area); the poles and the points where the axes cross the surface are vertices, and the
/// antimeridian runs along edges, so texture coordinates need no triangle to wrap around.
///
///     const TessellationResult sphere = SubdivisionSphereTessellator::compute(4, 1.0, VertexAttributes::Normal);
class SubdivisionSphereTessellator final {
public:
    SubdivisionSphereTessellator() = delete;

    /// A sphere of radius radiusMeters centred at the origin: 4 * 4^n + 2 vertices and 8 * 4^n
    /// triangles, counter-clockwise seen from outside, for n = subdivisions (clamped to [0, 12],
    /// asserted). Normals are p / radius. Texture coordinates are longitude and latitude mapped to
    /// [0, 1]; asking for them adds 2^(n+1) - 1 copies of the vertices on the antimeridian (u = 0 for
    /// the western triangles) and 3 copies of each pole (one per pole triangle, u halfway across it).
    /// The deviation is measured against the sphere. radiusMeters must be positive (asserted).
    static TessellationResult compute(int subdivisions, double radiusMeters = 1.0,
                                      VertexAttributes attributes = VertexAttributes::Position,
                                      Deviation deviation = Deviation::Measure);
};

} // namespace orbis
