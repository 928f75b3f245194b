#pragma once

// Pieces the tessellators share; not part of the public API.

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/Tessellation.h"

#include <glm/vec3.hpp>

#include <optional>

namespace orbis::detail {

/// A regular octahedron with vertices on the axes, each face split into four n times with the new
/// vertices pushed out to the unit sphere: 4 * 4^n + 2 unit positions, 8 * 4^n counter-clockwise
/// triangles. The poles are vertices 0 (north) and 1 (south); the antimeridian runs along edges.
Mesh subdividedOctahedron(int subdivisions);

/// The surface point of ellipsoid that stands for the unit (or any non-zero) direction.
glm::dvec3 projectToEllipsoid(const Ellipsoid& ellipsoid, const glm::dvec3& direction,
                              EllipsoidProjection projection) noexcept;

/// Fills mesh.normals with the geodetic surface normals of its positions.
void addGeodeticNormals(Mesh& mesh, const Ellipsoid& ellipsoid);

/// Fills mesh.textureCoordinates with (longitude + pi) / 2pi and (latitude + pi/2) / pi of each
/// position's geodetic normal, and splits vertices so that no triangle wraps around: vertices on the
/// antimeridian (y == 0, x < 0) get a copy with u = 0 for the triangles on the western side (u = 1
/// on the eastern one), and a pole vertex (x == y == 0) gets one copy per triangle, its u halfway
/// between the triangle's other corners. Requires every triangle to lie on one side of the
/// antimeridian, which holds when the antimeridian runs along mesh edges. Normals are copied along.
void addGeographicTextureCoordinates(Mesh& mesh, const Ellipsoid& ellipsoid);

/// maxDeviationFromEllipsoid when asked for, else empty.
std::optional<double> measureDeviation(const Mesh& mesh, const Ellipsoid& ellipsoid, Deviation deviation);

} // namespace orbis::detail
