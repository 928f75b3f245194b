#pragma once

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/Mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis {

/// Subdivides a triangle mesh lying on the ellipsoid (book section 8.2.3) until no edge subtends
/// more than granularityRadians at the centre: the longest edge of a triangle that is too coarse is
/// split at its midpoint moved to the surface along the ray from the centre (so it stays on the
/// curve that the plane through the centre and the edge cuts), and both halves are examined again.
/// A map from edges to midpoints gives neighbours the same midpoint, so the mesh stays free of
/// cracks; edges within the granularity are never split, so shared edges split on both sides or on
/// neither. Triangles keep their winding.
///
/// Returns the input positions followed by the midpoints, geodetic surface normals for all, and the
/// indices. granularityRadians is clamped to at least 1e-6 (6 m on the Earth) so that the output
/// stays bounded; every index must be less than positions.size() (asserted).
///
/// With `values` (one per input position), a value is carried along: each midpoint gets the mean
/// of its edge's two, so that on return `values` holds one per output position, interpolated
/// linearly over each input triangle.
Mesh subdivideOnEllipsoid(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions,
                          std::span<const std::uint32_t> indices, double granularityRadians,
                          std::vector<double>* values = nullptr);

/// The angle between a and b seen from the centre, in [0, pi]; 0 when either is the centre.
double centralAngle(const glm::dvec3& a, const glm::dvec3& b) noexcept;

} // namespace orbis
