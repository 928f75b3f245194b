#pragma once

#include "orbis/core/Tessellation.h"

namespace orbis {

class Ellipsoid;

/// An ellipsoid cut along meridians (slices) and parallels (stacks) at equal steps of geodetic
/// longitude and latitude, the way a globe's graticule is drawn. Each pole is closed by a fan of
/// triangles around a single vertex, so no triangle has zero area. Triangles crowd towards the
/// poles, where they are long and thin.
///
///     const TessellationResult grid = GeographicGridEllipsoidTessellator::compute(
///         Ellipsoid::wgs84(), 64, 32, VertexAttributes::All);
class GeographicGridEllipsoidTessellator final {
public:
    GeographicGridEllipsoidTessellator() = delete;

    /// slicePartitions meridians (at least 3) starting at the antimeridian, longitude -pi, and
    /// stackPartitions bands of latitude (at least 2); smaller counts are asserted and clamped.
    /// Vertices: the south pole, the rings of latitude from south to north, the north pole:
    /// 2 + slices * (stacks - 1) of them, and 2 * slices * (stacks - 1) triangles, counter-clockwise
    /// seen from outside. Positions come from Ellipsoid::toCartesian, with the coordinate that
    /// vanishes on the meridians at multiples of 90 degrees set to 0 exactly (the antimeridian has
    /// y = 0); normals are geodetic surface normals, (0, 0, +-1) at the poles. Texture coordinates are u = j / slices, v = i / stacks for
    /// meridian j and parallel i; asking for them duplicates the antimeridian column (u = 0 and u = 1,
    /// at the same position) and gives each pole one vertex per fan triangle, u at the triangle's
    /// middle, so that there are (slices + 1) * (stacks - 1) + 2 * slices vertices.
    static TessellationResult compute(const Ellipsoid& ellipsoid, int slicePartitions, int stackPartitions,
                                      VertexAttributes attributes = VertexAttributes::Position,
                                      Deviation deviation = Deviation::Measure);
};

} // namespace orbis
