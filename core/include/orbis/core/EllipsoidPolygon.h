#pragma once

#include "orbis/core/EarClipping.h"
#include "orbis/core/Ellipsoid.h"
#include "orbis/core/Math.h"
#include "orbis/core/Mesh.h"

#include <glm/vec3.hpp>

#include <span>
#include <string_view>
#include <vector>

namespace orbis {

/// The widest angle, seen from the centre, between a vertex and the normal of the tangent plane
/// for a polygon to be clipped in that one plane; beyond it the gnomonic projection stretches
/// lengths more than 1 / cos^2(80 deg) = 33 times, and at 90 degrees it fails.
inline constexpr double kMaximumTangentPlaneAngleRadians = toRadians(80.0);

/// Ear clipping on the ellipsoid (book section 8.2.2). rings[0] is the outer boundary, the others
/// holes; positions are on the surface, and an edge is the curve cut from it by the plane through
/// the centre and the edge's ends (a great circle arc on a sphere). Each ring is cleaned up
/// (cleanRing with the default tolerance: duplicates, (180, y) and (-180, y) included, spikes, and
/// vertices within 1e-9 rad of their neighbours' edge), projected onto the tangent plane at the
/// centre of the outer ring (EllipsoidTangentPlane, gnomonic, so edges stay straight), and clipped
/// by earClip. The polygon is the smaller of the two regions its outer ring bounds: either winding
/// is accepted. Returns indices into the rings concatenated in order, counter-clockwise seen from
/// outside; vertexCount and holeCount count what the clean-up left. An outer ring left with fewer
/// than 3 vertices gives no triangles; holes like it are dropped; twisted spikes are repaired as
/// earClip does.
///
/// Throws orbis::Error naming `name` for what earClip rejects, for a non-finite position, and for
/// a polygon with a vertex farther than kMaximumTangentPlaneAngleRadians from the plane's normal
/// (too large for one plane: triangulatePolygon splits such polygons). With leftOutHoles given,
/// faulty holes are left out and listed there, as earClip does (their indices into `rings`).
PolygonTriangles earClipOnEllipsoid(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                                    std::string_view name = "polygon", std::vector<LeftOutHole>* leftOutHoles = nullptr);

/// A polygon on the ellipsoid as a mesh of triangles no coarser than granularityRadians
/// (subdivideOnEllipsoid after ear clipping), positions on the surface with geodetic normals,
/// triangles counter-clockwise seen from outside. Rings, edges and clean-up are as for
/// earClipOnEllipsoid, input positions are moved to the surface along their geodetic normals.
/// A polygon with no area gives an empty mesh.
///
/// Any polygon smaller than a hemisphere works, whatever it contains or crosses: rings crossing
/// the antimeridian are nothing special in Cartesian coordinates, and a polygon around a pole
/// projects around it. A polygon too large for one tangent plane is split by three orthogonal
/// planes through the centre (turned so that no vertex lies on them) into pieces within one octant
/// each (each piece projected around its octant's centre, at most 55 degrees away), clipped piece
/// by piece, and welded along the cuts, which are computed once for both sides so that the pieces
/// share their vertices.
///
/// Throws orbis::Error naming `name` as earClipOnEllipsoid does (for any polygon size), and when
/// the outer ring divides the ellipsoid into two halves of equal area (which is meant is unknown).
/// leftOutHoles as for earClipOnEllipsoid, for polygons within one tangent plane; a polygon split
/// into pieces still throws for a faulty hole.
Mesh triangulatePolygon(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                        double granularityRadians, std::string_view name = "polygon",
                        std::vector<LeftOutHole>* leftOutHoles = nullptr);

} // namespace orbis
