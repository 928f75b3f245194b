#pragma once

#include "orbis/core/Tessellation.h"

namespace orbis {

class Ellipsoid;

/// How the grid lines of a CubeMapEllipsoidTessellator face are spaced.
enum class CubeMapSpacing {
    Uniform,    ///< equal steps on the cube face: cells near the face corners come out smaller
    EqualAngle, ///< equal steps of the angle seen from the centre (tan-warped), nearly uniform cells
};

/// An ellipsoid from a cube whose six faces are cut into partitions x partitions cells, the cube
/// points then projected onto the surface. Cells are split into two triangles along their shorter
/// diagonal. The face centres are the poles and the points where the x and y axes cross the surface.
///
///     const TessellationResult globe = CubeMapEllipsoidTessellator::compute(
///         Ellipsoid::wgs84(), 32, CubeMapSpacing::EqualAngle, EllipsoidProjection::Geocentric);
class CubeMapEllipsoidTessellator final {
public:
    CubeMapEllipsoidTessellator() = delete;

    /// n = partitions cells along each face edge (at least 1, asserted and clamped): 6 n^2 + 2
    /// vertices shared between faces, 12 n^2 triangles, counter-clockwise seen from outside. Normals
    /// are geodetic surface normals. Texture coordinates map geodetic longitude and latitude to
    /// [0, 1]; they need the poles and the antimeridian on grid lines, so an odd n is asserted and
    /// rounded up to even when they are asked for. They add 2n - 1 copies of the antimeridian's
    /// vertices (u = 0 for the western triangles) and, at each pole, one vertex per triangle around it.
    static TessellationResult compute(const Ellipsoid& ellipsoid, int partitions,
                                      CubeMapSpacing spacing = CubeMapSpacing::EqualAngle,
                                      EllipsoidProjection projection = EllipsoidProjection::Geocentric,
                                      VertexAttributes attributes = VertexAttributes::Position,
                                      Deviation deviation = Deviation::Measure);
};

} // namespace orbis
